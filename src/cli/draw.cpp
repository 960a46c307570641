// `qex draw`: pictures, as SVG written here (no dependency), optionally converted to PNG by
// rsvg-convert. The map in UV space (triangles, fold-overs in red, degenerate triangles marked,
// the integer grid, singularities with their valence, fold regions labelled), or the quad mesh
// in three orthographic views (flat-shaded, back faces culled) with every defect of a report and
// every violation of the checker circled and numbered.
#include "cli.h"
#include "draw.h"
#include "map_info.h"
#include "progress.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <queue>
#include <tuple>
#include <unordered_map>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace qex::cli {
namespace {

using Vec2 = std::array<double, 2>;
using Vec3 = std::array<double, 3>;

constexpr std::size_t kWholeMapTriangles = 30000; ///< larger maps are drawn in outline
constexpr double kMapSize = 1000.0;               ///< the map picture's larger side, in pixels
constexpr double kPanel = 520.0;                  ///< one view of the mesh, in pixels
constexpr std::size_t kListed = 40;               ///< defects listed under the mesh picture
constexpr std::size_t kMeshViewFaces = 30000;     ///< larger meshes are not drawn in 3D by `qex check --svg`

// === SVG text

std::string num(double x) {
    char b[32];
    std::snprintf(b, sizeof b, "%.1f", x);
    return b;
}

std::string escape(const std::string& s) {
    std::string out;
    for (char c : s) {
        if (c == '<')
            out += "&lt;";
        else if (c == '>')
            out += "&gt;";
        else if (c == '&')
            out += "&amp;";
        else if (c == '"')
            out += "&quot;";
        else
            out += c;
    }
    return out;
}

std::string polygon(const std::vector<Vec2>& p, const std::string& style) {
    std::string s = "<polygon points=\"";
    for (const Vec2& q : p) s += num(q[0]) + "," + num(q[1]) + " ";
    return s + "\" " + style + "/>\n";
}

std::string text(double x, double y, const std::string& t, const std::string& style = "") {
    return "<text x=\"" + num(x) + "\" y=\"" + num(y) + "\" " + style + ">" + escape(t) + "</text>\n";
}

std::string circle(double x, double y, double r, const std::string& style) {
    return "<circle cx=\"" + num(x) + "\" cy=\"" + num(y) + "\" r=\"" + num(r) + "\" " + style + "/>\n";
}

std::string svg_document(double w, double h, const std::string& body) {
    return "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + num(w) +
           "\" height=\"" + num(h) + "\" viewBox=\"0 0 " + num(w) + " " + num(h) +
           "\" font-family=\"sans-serif\" font-size=\"13\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n" +
           body + "</svg>\n";
}

// === the map in UV space

/// The triangles to draw around triangle `t`: those reached from it across edges whose ends
/// keep their UVs (one chart), within `radius` grid units of its centroid.
/// Directed edge (a, b), packed, -> 3 * triangle + corner of a.
std::unordered_map<std::int64_t, int> half_edges(const Input& in) {
    std::unordered_map<std::int64_t, int> he;
    he.reserve(3 * in.triangles.size());
    for (std::size_t f = 0; f < in.triangles.size(); ++f)
        for (int k = 0; k < 3; ++k)
            he.emplace(static_cast<std::int64_t>(in.triangles[f][k]) << 32 |
                           static_cast<std::uint32_t>(in.triangles[f][(k + 1) % 3]),
                       static_cast<int>(3 * f + k));
    return he;
}

/// Whether two UVs are the same point up to solver noise.
bool same_uv(const Vec2& a, const Vec2& b) {
    return std::abs(a[0] - b[0]) <= 1e-6 * (1 + std::abs(a[0])) && std::abs(a[1] - b[1]) <= 1e-6 * (1 + std::abs(a[1]));
}

std::vector<int> around(const Input& in, int t, double radius) {
    const auto he = half_edges(in);
    const auto centroid = [&](int f) {
        Vec2 c{0, 0};
        for (int k = 0; k < 3; ++k) c[0] += in.uvs[3 * f + k][0] / 3, c[1] += in.uvs[3 * f + k][1] / 3;
        return c;
    };
    const Vec2 c0 = centroid(t);
    std::vector<char> in_set(in.triangles.size(), 0);
    std::vector<int> out{t};
    in_set[t] = 1;
    std::queue<int> todo;
    todo.push(t);
    while (!todo.empty()) {
        const int f = todo.front();
        todo.pop();
        for (int k = 0; k < 3; ++k) {
            const int a = in.triangles[f][k], b = in.triangles[f][(k + 1) % 3];
            const auto twin = he.find(static_cast<std::int64_t>(b) << 32 | static_cast<std::uint32_t>(a));
            if (twin == he.end()) continue;
            const int g = twin->second / 3, kg = twin->second % 3;
            if (in_set[g] || !same_uv(in.uvs[3 * f + k], in.uvs[3 * g + (kg + 1) % 3]) ||
                !same_uv(in.uvs[3 * f + (k + 1) % 3], in.uvs[3 * g + kg]))
                continue;
            const Vec2 c = centroid(g);
            if (std::max(std::abs(c[0] - c0[0]), std::abs(c[1] - c0[1])) > radius) continue;
            in_set[g] = 1;
            out.push_back(g);
            todo.push(g);
        }
    }
    return out;
}

/// A violation's place on the map, in the chart of `triangle`: a grid cell (lower-left `at`), a
/// grid point, or the triangle itself (`at` its UV centroid).
struct MapMark {
    enum class Shape { Cell, Point, Triangle } shape = Shape::Point;
    Vec2 at{0, 0};
    int triangle = -1;
    std::string label; ///< the violation's number (on its first mark only)
};

/// The map's picture: every triangle of `tris`, or with `outline` (large maps) only its
/// boundary and seam edges, its flipped and degenerate triangles and its singularities; and the
/// violations' marks, each a group of class "violation-mark".
std::string draw_map(const Input& in, const MapInfo& info, const std::vector<int>& tris, bool outline,
                     const std::string& title, double& width, double& height, const std::vector<MapMark>& marks = {}) {
    Vec2 lo{INFINITY, INFINITY}, hi{-INFINITY, -INFINITY};
    for (int t : tris)
        for (int k = 0; k < 3; ++k)
            for (int c = 0; c < 2; ++c)
                lo[c] = std::min(lo[c], in.uvs[3 * t + k][c]), hi[c] = std::max(hi[c], in.uvs[3 * t + k][c]);
    const double span = std::max({hi[0] - lo[0], hi[1] - lo[1], 1e-9});
    const double scale = kMapSize / span, margin = 30.0, top = 60.0;
    width = std::max((hi[0] - lo[0]) * scale + 2 * margin, 900.0); // room for the title lines
    height = (hi[1] - lo[1]) * scale + top + margin;
    const auto at = [&](const Vec2& p) { return Vec2{margin + (p[0] - lo[0]) * scale, top + (hi[1] - p[1]) * scale}; };
    std::string s;
    // Triangles: regular ones light, flipped red, degenerate ones outlined in orange.
    std::string regular, folded;
    for (int t : tris) {
        const std::vector<Vec2> p = {at(in.uvs[3 * t]), at(in.uvs[3 * t + 1]), at(in.uvs[3 * t + 2])};
        const int o = info.orientation[t];
        if (o > 0) {
            if (!outline) regular += polygon(p, "");
        } else if (o < 0)
            folded += polygon(p, "fill=\"#e02020\" fill-opacity=\"0.8\" stroke=\"#900\" stroke-width=\"1\"");
        else
            folded += polygon(p, "fill=\"none\" stroke=\"#f08000\" stroke-width=\"3\"");
    }
    s += "<g fill=\"#dde6f3\" stroke=\"#8090a8\" stroke-width=\"0.5\">\n" + regular + "</g>\n";
    if (outline) { // boundary edges, and seams (an edge whose two sides have different UVs)
        const auto he = half_edges(in);
        s += "<g stroke=\"#40608a\" stroke-width=\"1\">\n";
        for (int t : tris)
            for (int k = 0; k < 3; ++k) {
                const int a = in.triangles[t][k], b = in.triangles[t][(k + 1) % 3];
                const auto twin = he.find(static_cast<std::int64_t>(b) << 32 | static_cast<std::uint32_t>(a));
                const Vec2& p = in.uvs[3 * t + k];
                const Vec2& q = in.uvs[3 * t + (k + 1) % 3];
                if (twin != he.end() && same_uv(p, in.uvs[3 * (twin->second / 3) + (twin->second % 3 + 1) % 3]) &&
                    same_uv(q, in.uvs[twin->second]))
                    continue;
                const Vec2 x = at(p), y = at(q);
                s += "<line x1=\"" + num(x[0]) + "\" y1=\"" + num(x[1]) + "\" x2=\"" + num(y[0]) + "\" y2=\"" +
                     num(y[1]) + "\"/>\n";
            }
        s += "</g>\n";
    }
    // The integer grid (every line while there are few, else every k-th).
    const std::int64_t step = std::max<std::int64_t>(1, static_cast<std::int64_t>(span / 200) + 1);
    s += "<g stroke=\"#303030\" stroke-width=\"0.8\" stroke-opacity=\"0.6\">\n";
    for (int c = 0; c < 2; ++c)
        for (std::int64_t g = static_cast<std::int64_t>(std::ceil(lo[c] / step)) * step; g <= hi[c]; g += step) {
            const Vec2 a = c == 0 ? at({double(g), lo[1]}) : at({lo[0], double(g)});
            const Vec2 b = c == 0 ? at({double(g), hi[1]}) : at({hi[0], double(g)});
            s += "<line x1=\"" + num(a[0]) + "\" y1=\"" + num(a[1]) + "\" x2=\"" + num(b[0]) + "\" y2=\"" + num(b[1]) +
                 "\"/>\n";
        }
    s += "</g>\n" + folded;
    // Fold regions: a label at the first drawn triangle of each.
    std::vector<char> drawn(in.triangles.size(), 0);
    for (int t : tris) drawn[t] = 1;
    for (std::size_t r = 0; r < info.fold_regions.size(); ++r)
        for (int t : info.fold_regions[r].triangles)
            if (drawn[t]) {
                const Vec2 p = at(in.uvs[3 * t]);
                s += text(
                    p[0] + 6, p[1] - 6, "R" + std::to_string(r + 1),
                    "fill=\"#900\" font-weight=\"bold\" stroke=\"white\" stroke-width=\"3\" paint-order=\"stroke\"");
                break;
            }
    // Singularities: a dot and the valence, at the vertex's corner in each drawn triangle's chart once.
    for (const Singularity& sg : info.singularities)
        for (int t : tris) {
            const auto& tri = in.triangles[t];
            const int k = tri[0] == sg.vertex ? 0 : tri[1] == sg.vertex ? 1 : tri[2] == sg.vertex ? 2 : -1;
            if (k < 0) continue;
            const Vec2 p = at(in.uvs[3 * t + k]);
            const char* color = sg.valence < 4 ? "#1060d0" : "#20a020";
            s += circle(p[0], p[1], 6, std::string("fill=\"") + color + "\" stroke=\"white\"");
            s += text(p[0] + 8, p[1] + 14, std::to_string(sg.valence),
                      std::string("fill=\"") + color +
                          "\" font-weight=\"bold\" stroke=\"white\" stroke-width=\"3\" paint-order=\"stroke\"");
            break;
        }
    // The violations: cells and triangles outlined, points circled, each with its number.
    const std::string red = "fill=\"#e00000\" fill-opacity=\"0.25\" stroke=\"#e00000\" stroke-width=\"2.5\"";
    for (const MapMark& m : marks) {
        std::string g;
        Vec2 label_at = at(m.at);
        if (m.shape == MapMark::Shape::Cell) {
            g += polygon(
                {at(m.at), at({m.at[0] + 1, m.at[1]}), at({m.at[0] + 1, m.at[1] + 1}), at({m.at[0], m.at[1] + 1})},
                red);
            label_at = at({m.at[0] + 1, m.at[1] + 1});
        } else if (m.shape == MapMark::Shape::Triangle && m.triangle >= 0) {
            g += polygon({at(in.uvs[3 * m.triangle]), at(in.uvs[3 * m.triangle + 1]), at(in.uvs[3 * m.triangle + 2])},
                         red);
        }
        const Vec2 c = m.shape == MapMark::Shape::Cell ? at({m.at[0] + 0.5, m.at[1] + 0.5}) : at(m.at);
        g += circle(c[0], c[1], 9, "fill=\"none\" stroke=\"#e00000\" stroke-width=\"2.5\"");
        if (!m.label.empty())
            g += text(
                label_at[0] + 8, label_at[1] - 8, m.label,
                "fill=\"#c00000\" font-weight=\"bold\" stroke=\"white\" stroke-width=\"3\" paint-order=\"stroke\"");
        s += "<g class=\"violation-mark\">\n" + g + "</g>\n";
    }
    s += text(margin, 22, title, "font-size=\"16\" font-weight=\"bold\"");
    s += text(margin, 44,
              std::to_string(info.flipped) + " flipped (red), " + std::to_string(info.degenerate) +
                  " degenerate (orange), " + std::to_string(info.fold_regions.size()) + " fold regions (R1..), " +
                  std::to_string(info.singularities.size()) + " singularities (valence; blue < 4 < green)");
    return s;
}

// === the quad mesh in three views

struct Mark {
    Vec3 at;
    std::string label;
};

Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/// A view: screen right, screen up and towards the viewer.
struct View {
    const char* name;
    Vec3 right, up, toward;
};

std::string draw_view(const QuadMesh& mesh, const std::vector<Mark>& marks, const View& v, double x0, double y0,
                      const Vec3& lo, const Vec3& hi) {
    const Vec3 mid = {(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2};
    const double extent = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2], 1e-12});
    const double scale = (kPanel - 40) / extent;
    const auto at = [&](const Vec3& p) {
        const Vec3 d = sub(p, mid);
        return Vec2{x0 + kPanel / 2 + dot(d, v.right) * scale, y0 + kPanel / 2 - dot(d, v.up) * scale};
    };
    struct Drawn {
        double depth;
        std::string svg;
    };
    std::vector<Drawn> faces;
    const Vec3 light = {0.3 * v.right[0] + 0.5 * v.up[0] + v.toward[0], 0.3 * v.right[1] + 0.5 * v.up[1] + v.toward[1],
                        0.3 * v.right[2] + 0.5 * v.up[2] + v.toward[2]};
    const double light_norm = std::sqrt(dot(light, light));
    for (const auto& f : mesh.faces) {
        if (f.size() < 3) continue;
        Vec3 n{0, 0, 0}, c{0, 0, 0};
        bool bad = false;
        for (std::size_t k = 0; k < f.size(); ++k) {
            if (f[k] < 0 || static_cast<std::size_t>(f[k]) >= mesh.positions.size()) bad = true;
        }
        if (bad) continue;
        for (std::size_t k = 0; k < f.size(); ++k) { // Newell's normal
            const Vec3& p = mesh.positions[f[k]];
            const Vec3& q = mesh.positions[f[(k + 1) % f.size()]];
            n[0] += (p[1] - q[1]) * (p[2] + q[2]), n[1] += (p[2] - q[2]) * (p[0] + q[0]);
            n[2] += (p[0] - q[0]) * (p[1] + q[1]);
            for (int i = 0; i < 3; ++i) c[i] += p[i] / f.size();
        }
        const double len = std::sqrt(dot(n, n));
        if (len == 0 || dot(n, v.toward) <= 0) continue; // back face (or no area)
        const double shade = 0.25 + 0.75 * std::max(0.0, dot(n, light) / (len * light_norm));
        std::vector<Vec2> p;
        for (int i : f) p.push_back(at(mesh.positions[i]));
        const int g = static_cast<int>(255 * shade);
        char fill[64];
        if (f.size() == 4)
            std::snprintf(fill, sizeof fill, "fill=\"rgb(%d,%d,%d)\"", g * 7 / 10, g * 8 / 10, g);
        else
            std::snprintf(fill, sizeof fill, "fill=\"rgb(%d,%d,%d)\"", g, g * 6 / 10, g / 5); // not a quad: orange
        faces.push_back({dot(c, v.toward), polygon(p, fill)});
    }
    std::sort(faces.begin(), faces.end(), [](const Drawn& a, const Drawn& b) { return a.depth < b.depth; });
    std::string s = "<g stroke=\"#203040\" stroke-width=\"0.4\" stroke-linejoin=\"round\">\n";
    for (const Drawn& d : faces) s += d.svg;
    s += "</g>\n";
    for (const Mark& m : marks) {
        const Vec2 p = at(m.at);
        s += circle(p[0], p[1], 11, "fill=\"none\" stroke=\"#e00000\" stroke-width=\"2.5\"");
        s += text(p[0] + 12, p[1] - 8, m.label,
                  "fill=\"#c00000\" font-weight=\"bold\" stroke=\"white\" stroke-width=\"3\" paint-order=\"stroke\"");
    }
    s += text(x0 + 8, y0 + 18, v.name, "font-weight=\"bold\"");
    s += "<rect x=\"" + num(x0) + "\" y=\"" + num(y0) + "\" width=\"" + num(kPanel) + "\" height=\"" + num(kPanel) +
         "\" fill=\"none\" stroke=\"#999\"/>\n";
    return s;
}

Vec3 face_centroid(const QuadMesh& mesh, std::int64_t f) {
    Vec3 c{0, 0, 0};
    const auto& face = mesh.faces[static_cast<std::size_t>(f)];
    for (int v : face)
        if (v >= 0 && static_cast<std::size_t>(v) < mesh.positions.size())
            for (int i = 0; i < 3; ++i) c[i] += mesh.positions[v][i] / face.size();
    return c;
}

Vec3 triangle_centroid(const Input& in, std::int64_t t) {
    Vec3 c{0, 0, 0};
    for (int v : in.triangles[static_cast<std::size_t>(t)])
        for (int i = 0; i < 3; ++i) c[i] += in.positions[v][i] / 3;
    return c;
}

/// Where a defect or violation is, if it names a place this picture can show.
bool place_of(const Input& in, const QuadMesh& mesh, ViolationElement kind, std::int64_t e, Vec3& at) {
    if (e < 0) return false;
    const auto n = [](const auto& v) { return static_cast<std::int64_t>(v.size()); };
    switch (kind) {
        case ViolationElement::OutputFace:
            if (e >= n(mesh.faces)) return false;
            at = face_centroid(mesh, e);
            return true;
        case ViolationElement::OutputVertex:
            if (e >= n(mesh.positions)) return false;
            at = mesh.positions[e];
            return true;
        case ViolationElement::InputVertex:
            if (e >= n(in.positions)) return false;
            at = in.positions[e];
            return true;
        case ViolationElement::InputTriangle:
            if (e >= n(in.triangles)) return false;
            at = triangle_centroid(in, e);
            return true;
        case ViolationElement::None: return false;
    }
    return false;
}

/// The point of triangle t whose UV in t's chart is (u, v) (barycentric; outside t when (u, v) is).
Vec3 surface_point(const Input& in, std::int64_t t, double u, double v) {
    const auto T = static_cast<std::size_t>(t);
    const Vec2 &a = in.uvs[3 * T], &b = in.uvs[3 * T + 1], &c = in.uvs[3 * T + 2];
    const double den = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    if (den == 0) return triangle_centroid(in, t);
    const double l1 = ((u - a[0]) * (c[1] - a[1]) - (v - a[1]) * (c[0] - a[0])) / den;
    const double l2 = ((b[0] - a[0]) * (v - a[1]) - (b[1] - a[1]) * (u - a[0])) / den;
    Vec3 x{0, 0, 0};
    for (int i = 0; i < 3; ++i)
        x[i] = (1 - l1 - l2) * in.positions[in.triangles[T][0]][i] + l1 * in.positions[in.triangles[T][1]][i] +
               l2 * in.positions[in.triangles[T][2]][i];
    return x;
}

/// Where a violation is in 3D: the element it names, else its first place this picture can show
/// (a grid cell's centre or a grid point on the surface through its chart's triangle).
bool violation_at(const Input& in, const QuadMesh& mesh, const Violation& x, Vec3& at) {
    if (place_of(in, mesh, element_kind(x.kind), x.element, at)) return true;
    for (const Place& p : x.places) {
        if (p.indices.empty()) continue;
        const std::int64_t e = p.indices[0];
        if (p.kind == PlaceKind::GridCell || p.kind == PlaceKind::GridPoint) {
            if (p.indices.size() >= 3 && e >= 0 && e < static_cast<std::int64_t>(in.triangles.size())) {
                const double half = p.kind == PlaceKind::GridCell ? 0.5 : 0.0;
                at = surface_point(in, e, static_cast<double>(p.indices[1]) + half,
                                   static_cast<double>(p.indices[2]) + half);
                return true;
            }
            continue;
        }
        // Vertices, edges and loops are drawn at their first vertex.
        const ViolationElement kind = p.kind == PlaceKind::Face            ? ViolationElement::OutputFace
                                      : p.kind == PlaceKind::InputVertex   ? ViolationElement::InputVertex
                                      : p.kind == PlaceKind::InputTriangle ? ViolationElement::InputTriangle
                                                                           : ViolationElement::OutputVertex;
        if (place_of(in, mesh, kind, e, at)) return true;
    }
    return false;
}

/// Where a violation is on the map: its grid cells and grid points (up to four of each), else the
/// input triangle it names or lies on, else an input vertex (in its first triangle's chart). The
/// first mark carries `label`; none where the violation has no place on the map.
std::vector<MapMark> map_marks(const Input& in, const Violation& x, const std::string& label) {
    std::vector<MapMark> out;
    const auto nt = static_cast<std::int64_t>(in.triangles.size());
    for (const Place& p : x.places) {
        if (p.kind != PlaceKind::GridCell && p.kind != PlaceKind::GridPoint) continue;
        for (std::size_t i = 0; i + 2 < p.indices.size() && i < 12; i += 3)
            if (p.indices[i] >= 0 && p.indices[i] < nt)
                out.push_back({p.kind == PlaceKind::GridCell ? MapMark::Shape::Cell : MapMark::Shape::Point,
                               {static_cast<double>(p.indices[i + 1]), static_cast<double>(p.indices[i + 2])},
                               static_cast<int>(p.indices[i]),
                               ""});
    }
    std::int64_t triangle = element_kind(x.kind) == ViolationElement::InputTriangle ? x.element : -1;
    for (const Place& p : x.places)
        if (triangle < 0 && p.kind == PlaceKind::InputTriangle && !p.indices.empty()) triangle = p.indices[0];
    if (out.empty() && triangle >= 0 && triangle < nt) {
        const auto t = static_cast<std::size_t>(triangle);
        const Vec2 c{(in.uvs[3 * t][0] + in.uvs[3 * t + 1][0] + in.uvs[3 * t + 2][0]) / 3,
                     (in.uvs[3 * t][1] + in.uvs[3 * t + 1][1] + in.uvs[3 * t + 2][1]) / 3};
        out.push_back({MapMark::Shape::Triangle, c, static_cast<int>(triangle), ""});
    }
    std::int64_t vertex = element_kind(x.kind) == ViolationElement::InputVertex ? x.element : -1;
    for (const Place& p : x.places)
        if (vertex < 0 && p.kind == PlaceKind::InputVertex && !p.indices.empty()) vertex = p.indices[0];
    if (out.empty() && vertex >= 0)
        for (std::size_t c = 0; c < 3 * in.triangles.size(); ++c)
            if (in.triangles[c / 3][c % 3] == vertex) {
                out.push_back({MapMark::Shape::Point, in.uvs[c], static_cast<int>(c / 3), ""});
                break;
            }
    if (!out.empty()) out.front().label = label;
    return out;
}

/// The marks (and the listing under the picture): the report's defects, then the checker's violations.
std::vector<Mark> collect_marks(const Input& in, const QuadMesh& mesh, const nlohmann::json& report,
                                const VerifyResult& check, std::vector<std::string>& listing) {
    std::vector<Mark> marks;
    const auto add = [&](bool placed, const Vec3& at, const std::string& what) {
        const std::string label = std::to_string(listing.size() + 1);
        listing.push_back(label + ": " + what + (placed ? "" : " (no place)"));
        if (placed) marks.push_back({at, label});
    };
    if (report.is_object() && report.contains("defects"))
        for (const auto& d : report["defects"]) {
            Vec3 at{};
            const std::int64_t face = d.value("output_face", std::int64_t{-1});
            const std::int64_t tri = d.value("input_element", std::int64_t{-1});
            const bool placed = place_of(in, mesh, ViolationElement::OutputFace, face, at) ||
                                place_of(in, mesh, ViolationElement::InputTriangle, tri, at);
            add(placed, at, "defect " + d.value("kind", std::string("?")) + ": " + d.value("message", std::string()));
        }
    for (const Violation& x : check.violations) {
        Vec3 at{};
        const bool placed = violation_at(in, mesh, x, at);
        add(placed, at, std::string("check ") + to_string(x.kind) + ": " + x.message);
    }
    return marks;
}

std::string draw_mesh(const Input& in, const QuadMesh& mesh, const std::vector<Mark>& marks,
                      const std::vector<std::string>& listing, const std::string& title, double& width,
                      double& height) {
    Vec3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
    for (const Vec3& p : mesh.positions.empty() ? in.positions : mesh.positions)
        for (int i = 0; i < 3; ++i) lo[i] = std::min(lo[i], p[i]), hi[i] = std::max(hi[i], p[i]);
    const View views[3] = {{"front (x right, y up)", {1, 0, 0}, {0, 1, 0}, {0, 0, 1}},
                           {"side (-z right, y up)", {0, 0, -1}, {0, 1, 0}, {1, 0, 0}},
                           {"top (x right, -z up)", {1, 0, 0}, {0, 0, -1}, {0, 1, 0}}};
    const double margin = 20, top = 60;
    std::string s;
    for (int i = 0; i < 3; ++i) s += draw_view(mesh, marks, views[i], margin + i * (kPanel + margin), top, lo, hi);
    s += text(margin, 24, title, "font-size=\"16\" font-weight=\"bold\"");
    s += text(margin, 46,
              std::to_string(mesh.faces.size()) + " faces, " + std::to_string(mesh.positions.size()) + " vertices; " +
                  std::to_string(listing.size()) + " defects and violations (circled where they have a place)");
    double y = top + kPanel + 24;
    for (std::size_t i = 0; i < listing.size() && i < kListed; ++i, y += 17) {
        std::string line = listing[i];
        if (line.size() > 200) line = line.substr(0, 197) + "...";
        s += text(margin, y, line, "fill=\"#900\"");
    }
    if (listing.size() > kListed)
        s += text(margin, y, "... and " + std::to_string(listing.size() - kListed) + " more"), y += 17;
    width = 3 * kPanel + 4 * margin;
    height = y + 10;
    return s;
}

// === PNG

/// The path of `program` on PATH, or empty.
std::string on_path(const std::string& program) {
    const char* path = std::getenv("PATH");
    for (std::string dirs = path ? path : ""; !dirs.empty();) {
        const std::size_t colon = dirs.find(':');
        const std::string dir = dirs.substr(0, colon);
        dirs = colon == std::string::npos ? "" : dirs.substr(colon + 1);
        const std::string candidate = (dir.empty() ? "." : dir) + "/" + program;
        if (access(candidate.c_str(), X_OK) == 0) return candidate;
    }
    return {};
}

int to_png(const std::string& svg, const std::string& png) {
    const std::string tool = on_path("rsvg-convert");
    if (tool.empty()) {
        std::cerr << "qex: --png needs rsvg-convert (Debian package librsvg2-bin); the SVG is " << svg << "\n";
        return kIo;
    }
    const std::string tmp = png + ".tmp";
    std::vector<std::string> args = {tool, "-f", "png", "-o", tmp, svg};
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    pid_t pid;
    int status = 0;
    if (posix_spawn(&pid, tool.c_str(), nullptr, nullptr, argv.data(), environ) != 0 || waitpid(pid, &status, 0) < 0 ||
        !WIFEXITED(status) || WEXITSTATUS(status) != 0 || std::rename(tmp.c_str(), png.c_str()) != 0) {
        std::remove(tmp.c_str());
        std::cerr << "qex: rsvg-convert could not convert " << svg << " to " << png << "\n";
        return kIo;
    }
    return kOk;
}

} // namespace

std::string verdict_svg(const Input& input, const QuadMesh& mesh, const VerifyResult& verdict, int grid_scale,
                        const std::string& title) {
    // The map as the checker judged it (its UVs times the grid scale, a power of two: exact).
    Input in = input;
    if (grid_scale != 1)
        for (auto& uv : in.uvs) uv = {uv[0] * grid_scale, uv[1] * grid_scale};
    // Marks at one place are drawn once, with the numbers of all violations there.
    std::vector<MapMark> on_map;
    std::map<std::tuple<int, int, double, double>, std::size_t> map_mark_at;
    std::vector<Mark> in_3d;
    std::map<Vec3, std::size_t> mark_at;
    std::vector<std::string> listing;
    for (std::size_t i = 0; i < verdict.violations.size(); ++i) {
        const Violation& x = verdict.violations[i];
        const std::string label = std::to_string(i + 1);
        const std::vector<MapMark> m = map_marks(in, x, label);
        for (const MapMark& mark : m) {
            const auto key = std::make_tuple(static_cast<int>(mark.shape), mark.triangle, mark.at[0], mark.at[1]);
            const auto [it, added] = map_mark_at.emplace(key, on_map.size());
            if (added)
                on_map.push_back(mark);
            else if (!mark.label.empty())
                on_map[it->second].label += (on_map[it->second].label.empty() ? "" : ", ") + mark.label;
        }
        Vec3 at{};
        if (violation_at(in, mesh, x, at)) {
            const auto [it, added] = mark_at.emplace(at, in_3d.size());
            if (added)
                in_3d.push_back({at, label});
            else
                in_3d[it->second].label += ", " + label;
        }
        listing.push_back(label + ": " + to_string(x.kind) + ": " + x.message + (m.empty() ? " (not on the map)" : ""));
    }
    std::vector<int> tris(in.triangles.size());
    for (std::size_t t = 0; t < tris.size(); ++t) tris[t] = static_cast<int>(t);
    const bool outline = tris.size() > kWholeMapTriangles;
    double map_width = 0, map_height = 0, mesh_width = 0, mesh_height = 0;
    const std::string verdict_line = std::string(verdict.valid ? "VALID" : "INVALID") + ", " +
                                     std::to_string(verdict.violations.size()) + " violations (numbered)";
    std::string body = draw_map(in, analyse_map(in), tris, outline,
                                title + ": " + verdict_line + "; the map" +
                                    (grid_scale != 1 ? " at grid scale " + std::to_string(grid_scale) : "") +
                                    (outline ? " in outline" : ""),
                                map_width, map_height, on_map);
    if (mesh.faces.size() <= kMeshViewFaces) {
        body += "<g transform=\"translate(0," + num(map_height) + ")\">\n" +
                draw_mesh(in, mesh, in_3d, listing, title + ": the mesh", mesh_width, mesh_height) + "</g>\n";
    } else { // the listing alone
        double y = map_height + 20;
        for (std::size_t i = 0; i < listing.size() && i < kListed; ++i, y += 17)
            body +=
                text(20, y, listing[i].size() > 200 ? listing[i].substr(0, 197) + "..." : listing[i], "fill=\"#900\"");
        if (listing.size() > kListed)
            body += text(20, y, "... and " + std::to_string(listing.size() - kListed) + " more");
        mesh_height = y - map_height + 20;
    }
    return svg_document(std::max(map_width, mesh_width), map_height + mesh_height, body);
}

CLI::App* add_draw(CLI::App& app, DrawArgs& a) {
    auto* draw = app.add_subcommand("draw", "Draw a map in UV space, or a quad mesh in 3 views with its defects (SVG)");
    draw->add_option("map", a.map_path, "the map: OBJ or PLY with per-corner UVs")->required();
    draw->add_option("-o,--output", a.out_path, "the SVG to write")->required();
    draw->add_option("--quads", a.quads_path, "draw this quad mesh (OBJ or PLY) instead of the map");
    draw->add_option("--report", a.report_path, "with --quads: circle the defects of this `qex extract --report`");
    draw->add_option("--around", a.around, "draw the map around this triangle only")->check(CLI::NonNegativeNumber);
    draw->add_option("--radius", a.radius, "with --around: how far, in grid units (default 6)")
        ->check(CLI::PositiveNumber);
    draw->add_flag("--png", a.png, "also write a PNG beside the SVG (needs rsvg-convert)");
    return draw;
}

int run_draw(const DrawArgs& a) {
    Progress progress(true, 2);
    progress.step("reading " + a.map_path);
    Input in;
    if (const int code = read_map(a.map_path, in); code != kOk) return code;
    progress.step("drawing");
    if (const Error e = validate(in); e.code != ErrorCode::None) {
        progress.stop();
        std::cerr << "qex: " << a.map_path << ": invalid input (" << to_string(e.code) << "): " << e.message << "\n";
        return kBadInput;
    }
    double width = 0, height = 0;
    std::string body;
    const std::string name = std::filesystem::path(a.map_path).filename().string();
    if (a.quads_path.empty()) {
        const MapInfo info = analyse_map(in);
        std::vector<int> tris;
        std::string title = name + ": the map in UV space";
        if (a.around >= static_cast<long long>(in.triangles.size())) {
            stop_progress();
            std::cerr << "qex: --around " << a.around << ": the map has " << in.triangles.size() << " triangles\n";
            return kUsage;
        }
        const bool outline = a.around < 0 && in.triangles.size() > kWholeMapTriangles;
        if (a.around >= 0) {
            tris = around(in, static_cast<int>(a.around), a.radius);
            title += " around triangle " + std::to_string(a.around);
        } else {
            tris.resize(in.triangles.size());
            for (std::size_t t = 0; t < tris.size(); ++t) tris[t] = static_cast<int>(t);
            if (outline) title += " (outline: " + std::to_string(tris.size()) + " triangles; --around T for detail)";
        }
        body = draw_map(in, info, tris, outline, title, width, height);
    } else {
        QuadMesh mesh;
        if (const int code = read_quads(a.quads_path, mesh); code != kOk) return code;
        nlohmann::json report;
        if (!a.report_path.empty()) {
            std::ifstream f(a.report_path);
            if (!f) {
                stop_progress();
                std::cerr << "qex: cannot open report '" << a.report_path << "'\n";
                return kIo;
            }
            report = nlohmann::json::parse(f, nullptr, false);
            if (report.is_discarded() || !report.is_object()) {
                stop_progress();
                std::cerr << "qex: " << a.report_path << ": not a JSON report\n";
                return kParse;
            }
        }
        const VerifyResult check = verify(in, mesh);
        std::vector<std::string> listing;
        const std::vector<Mark> marks = collect_marks(in, mesh, report, check, listing);
        const std::string title = std::filesystem::path(a.quads_path).filename().string() + " on " + name + ": " +
                                  (check.valid ? "VALID" : "INVALID") + " (qex check)";
        body = draw_mesh(in, mesh, marks, listing, title, width, height);
    }
    progress.stop();
    if (!write_text(a.out_path, svg_document(width, height, body))) {
        std::cerr << "qex: cannot write '" << a.out_path << "'\n";
        return kIo;
    }
    if (a.png) return to_png(a.out_path, std::filesystem::path(a.out_path).replace_extension(".png").string());
    return kOk;
}

} // namespace qex::cli

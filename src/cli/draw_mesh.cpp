// The quad mesh in three orthographic views (flat-shaded, back faces culled), for `qex draw --quads`
// and `qex check --svg` (draw_parts.h), with every defect of a report and every violation of the
// checker circled and numbered where it has a place in 3D.
#include "draw_parts.h"
#include "svg.h"

#include "io/checked_int.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace qex::cli {
namespace {

using svg::circle;
using svg::num;
using svg::polygon;
using svg::text;

constexpr double kPanel = 520.0; ///< one view of the mesh, in pixels

/// a - b.
Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
/// The dot product of a and b.
double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/// A view: screen right, screen up and towards the viewer.
struct View {
    const char* name;
    Vec3 right, up, toward;
};

/// One view of the mesh in the panel at (x0, y0): its front faces flat-shaded, farthest first,
/// and the marks circled; `lo` and `hi` bound the mesh (every view has the same scale).
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
        const int g = io_detail::clamped_int<int>(255 * shade); // shade lies in [0.25, 1]
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

/// The centroid of output face f (of its corners that name a vertex).
Vec3 face_centroid(const QuadMesh& mesh, std::int64_t f) {
    Vec3 c{0, 0, 0};
    const auto& face = mesh.faces[static_cast<std::size_t>(f)];
    for (int v : face)
        if (v >= 0 && static_cast<std::size_t>(v) < mesh.positions.size())
            for (int i = 0; i < 3; ++i) c[i] += mesh.positions[v][i] / face.size();
    return c;
}

/// The centroid of input triangle t.
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

/// A defect's index `key` into `out` (-1 where it is absent or null); false where it is not an
/// integer of 64 bits. A JSON float is converted by checked_int(), never cast.
bool defect_index(const nlohmann::json& d, const char* key, std::int64_t& out) {
    out = -1;
    const auto it = d.find(key);
    if (it == d.end() || it->is_null()) return true;
    if (it->is_number_unsigned()) return io_detail::checked_int(it->get<std::uint64_t>(), out);
    if (it->is_number_integer()) return io_detail::checked_int(it->get<std::int64_t>(), out);
    if (it->is_number_float()) return io_detail::checked_int(it->get<double>(), out);
    return false;
}

/// A defect's text `key`, or `fallback` where it is absent.
std::string defect_text(const nlohmann::json& d, const char* key, const char* fallback) {
    const auto it = d.find(key);
    return it != d.end() && it->is_string() ? it->get<std::string>() : fallback;
}

} // namespace

std::string report_problem(const nlohmann::json& report) {
    if (!report.is_object() || !report.contains("defects")) return "";
    const nlohmann::json& defects = report["defects"];
    if (!defects.is_array()) return "\"defects\" is not a list";
    for (std::size_t i = 0; i < defects.size(); ++i) {
        const nlohmann::json& d = defects[i];
        const std::string where = "defect " + std::to_string(i) + ": ";
        if (!d.is_object()) return where + "not an object";
        std::int64_t x;
        for (const char* key : {"output_face", "input_element"})
            if (!defect_index(d, key, x)) return where + key + " " + d[key].dump() + " is not an index";
        for (const char* key : {"kind", "message"})
            if (d.contains(key) && !d[key].is_string()) return where + key + " is not a string";
    }
    return "";
}

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
            std::int64_t face = -1, tri = -1;
            const bool placed = (defect_index(d, "output_face", face) &&
                                 place_of(in, mesh, ViolationElement::OutputFace, face, at)) ||
                                (defect_index(d, "input_element", tri) &&
                                 place_of(in, mesh, ViolationElement::InputTriangle, tri, at));
            add(placed, at, "defect " + defect_text(d, "kind", "?") + ": " + defect_text(d, "message", ""));
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

} // namespace qex::cli

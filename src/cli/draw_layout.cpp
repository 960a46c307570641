// `qex draw MAP --quads QUADS --layout`: the quad layout in three views (draw_parts.h): each patch
// in its own colour, flat-shaded, the separatrices as dark lines and the special vertices as dots.
#include "draw_parts.h"
#include "svg.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

namespace qex::cli {
namespace {

using namespace svg;

constexpr double kPanel = 520.0; ///< one view, in pixels

double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

struct LayoutView {
    const char* name;
    Vec3 right, up, toward;
};

/// A patch's colour: hues a golden angle apart, so neighbours by number differ.
std::array<double, 3> patch_colour(int p) {
    const double h = std::fmod(p * 0.381966, 1.0) * 6, s = p % 3 == 0 ? 0.55 : 0.4, v = 1.0;
    const int i = static_cast<int>(h);
    const double f = h - i, a = v * (1 - s), b = v * (1 - s * f), c = v * (1 - s * (1 - f));
    const std::array<std::array<double, 3>, 6> rgb = {
        {{v, c, a}, {b, v, a}, {a, v, c}, {a, b, v}, {c, a, v}, {v, a, b}}};
    return rgb[i % 6];
}

/// What a view draws, farthest first: front faces, and separatrix edges beside a front face.
struct Drawn {
    double depth;
    std::string svg;
};

/// One view in the panel at (x0, y0); `lo`, `hi` bound the mesh, `edge_faces` are each
/// separatrix edge's faces.
std::string layout_view(const QuadMesh& mesh, const Layout& layout, const std::vector<std::array<int, 4>>& sep_edges,
                        const LayoutView& v, double x0, double y0, const Vec3& lo, const Vec3& hi) {
    const Vec3 mid = {(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2};
    const double extent = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2], 1e-12}),
                 scale = (kPanel - 40) / extent;
    const auto at = [&](int i) {
        const Vec3& p = mesh.positions[i];
        const Vec3 d = {p[0] - mid[0], p[1] - mid[1], p[2] - mid[2]};
        return Vec2{x0 + kPanel / 2 + dot(d, v.right) * scale, y0 + kPanel / 2 - dot(d, v.up) * scale};
    };
    std::vector<double> depth(mesh.faces.size(), -1e300); // -1e300: a back face
    std::vector<Drawn> items;
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
        const auto& q = mesh.faces[f];
        Vec3 n{0, 0, 0}, c{0, 0, 0};
        for (std::size_t k = 0; k < q.size(); ++k) { // Newell's normal
            const Vec3 &p = mesh.positions[q[k]], &r = mesh.positions[q[(k + 1) % q.size()]];
            n[0] += (p[1] - r[1]) * (p[2] + r[2]), n[1] += (p[2] - r[2]) * (p[0] + r[0]);
            n[2] += (p[0] - r[0]) * (p[1] + r[1]);
            for (int i = 0; i < 3; ++i) c[i] += p[i] / q.size();
        }
        const double len = std::sqrt(dot(n, n));
        if (len == 0 || dot(n, v.toward) <= 0) continue;
        depth[f] = dot(c, v.toward);
        const double shade = 0.45 + 0.55 * dot(n, v.toward) / len;
        const auto rgb = patch_colour(layout.face_patch[f]);
        char fill[64];
        std::snprintf(fill, sizeof fill, "fill=\"rgb(%d,%d,%d)\"", int(255 * shade * rgb[0]), int(255 * shade * rgb[1]),
                      int(255 * shade * rgb[2]));
        std::vector<Vec2> p;
        for (const int i : q) p.push_back(at(i));
        items.push_back({depth[f], polygon(p, fill)});
    }
    for (const auto& e : sep_edges) { // a, b, and the faces on either side (-1: none)
        const double d = std::max(e[2] >= 0 ? depth[e[2]] : -1e300, e[3] >= 0 ? depth[e[3]] : -1e300);
        if (d == -1e300) continue;
        const Vec2 a = at(e[0]), b = at(e[1]);
        items.push_back({d + 1e-9 * extent, "<line x1=\"" + num(a[0]) + "\" y1=\"" + num(a[1]) + "\" x2=\"" +
                                                num(b[0]) + "\" y2=\"" + num(b[1]) +
                                                "\" stroke=\"#101010\" stroke-width=\"2.2\"/>\n"});
    }
    std::stable_sort(items.begin(), items.end(), [](const Drawn& a, const Drawn& b) { return a.depth < b.depth; });
    std::string s = "<g stroke=\"#506070\" stroke-width=\"0.3\" stroke-linejoin=\"round\" stroke-linecap=\"round\">\n";
    for (const Drawn& d : items) s += d.svg;
    s += "</g>\n" + text(x0 + 8, y0 + 18, v.name, "font-weight=\"bold\"");
    s += "<rect x=\"" + num(x0) + "\" y=\"" + num(y0) + "\" width=\"" + num(kPanel) + "\" height=\"" + num(kPanel) +
         "\" fill=\"none\" stroke=\"#999\"/>\n";
    return s;
}

/// Each separatrix edge with its faces: {a, b, face, face}.
std::vector<std::array<int, 4>> separatrix_edges(const QuadMesh& mesh, const Layout& layout) {
    std::map<std::pair<int, int>, std::array<int, 4>> edges;
    for (const Separatrix& s : layout.separatrices)
        for (std::size_t i = 0; i + 1 < s.vertices.size(); ++i) {
            const int a = s.vertices[i], b = s.vertices[i + 1];
            edges[std::minmax(a, b)] = {a, b, -1, -1};
        }
    for (std::size_t f = 0; f < mesh.faces.size(); ++f)
        for (std::size_t k = 0; k < mesh.faces[f].size(); ++k) {
            const auto it = edges.find(std::minmax(mesh.faces[f][k], mesh.faces[f][(k + 1) % mesh.faces[f].size()]));
            if (it != edges.end()) it->second[it->second[2] < 0 ? 2 : 3] = static_cast<int>(f);
        }
    std::vector<std::array<int, 4>> out;
    for (const auto& [key, e] : edges) out.push_back(e);
    return out;
}

} // namespace

std::string draw_layout(const QuadMesh& mesh, const Layout& layout, const std::string& title, double& width,
                        double& height) {
    Vec3 lo = mesh.positions.empty() ? Vec3{0, 0, 0} : mesh.positions[0], hi = lo;
    for (const Vec3& p : mesh.positions)
        for (int i = 0; i < 3; ++i) lo[i] = std::min(lo[i], p[i]), hi[i] = std::max(hi[i], p[i]);
    const LayoutView views[3] = {{"front (x right, y up)", {1, 0, 0}, {0, 1, 0}, {0, 0, 1}},
                                 {"back (-x right, y up)", {-1, 0, 0}, {0, 1, 0}, {0, 0, -1}},
                                 {"side (-z right, y up)", {0, 0, -1}, {0, 1, 0}, {1, 0, 0}}};
    const double margin = 20, top = 40;
    const auto edges = separatrix_edges(mesh, layout);
    std::string s = text(margin, 26, title, "font-size=\"16\" font-weight=\"bold\"");
    for (int i = 0; i < 3; ++i)
        s += layout_view(mesh, layout, edges, views[i], margin + i * (kPanel + margin), top, lo, hi);
    width = 3 * kPanel + 4 * margin;
    height = top + kPanel + margin;
    return s;
}

} // namespace qex::cli

// The map in UV space, for `qex draw` and `qex check --svg` (draw_parts.h): its triangles
// (fold-overs in red, degenerate triangles marked) or, for large maps, its outline; the integer
// grid, the singularities with their valences, the fold regions labelled, and the violations'
// places numbered.
#include "draw_parts.h"
#include "svg.h"

#include "io/checked_int.h"

#include <algorithm>
#include <cmath>
#include <queue>
#include <unordered_map>

namespace qex::cli {
namespace {

using svg::circle;
using svg::num;
using svg::polygon;
using svg::text;

constexpr double kMapSize = 1000.0; ///< the map picture's larger side, in pixels

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

/// Where the map's UVs go in the picture: the box around the drawn triangles' UVs, scaled so
/// that its larger side takes kMapSize pixels, below the title lines (v up).
struct MapFrame {
    Vec2 lo{INFINITY, INFINITY}, hi{-INFINITY, -INFINITY};
    double span = 0, scale = 0;
    static constexpr double margin = 30.0, top = 60.0;

    MapFrame(const Input& in, const std::vector<int>& tris) {
        for (int t : tris)
            for (int k = 0; k < 3; ++k)
                for (int c = 0; c < 2; ++c)
                    lo[c] = std::min(lo[c], in.uvs[3 * t + k][c]), hi[c] = std::max(hi[c], in.uvs[3 * t + k][c]);
        span = std::max({hi[0] - lo[0], hi[1] - lo[1], 1e-9});
        scale = kMapSize / span;
    }
    /// The picture's point of UV p.
    Vec2 at(const Vec2& p) const { return Vec2{margin + (p[0] - lo[0]) * scale, top + (hi[1] - p[1]) * scale}; }
    double width() const { return std::max((hi[0] - lo[0]) * scale + 2 * margin, 900.0); } // room for the title lines
    double height() const { return (hi[1] - lo[1]) * scale + top + margin; }
};

/// A line from a to b (picture points).
std::string line(const Vec2& a, const Vec2& b) {
    return "<line x1=\"" + num(a[0]) + "\" y1=\"" + num(a[1]) + "\" x2=\"" + num(b[0]) + "\" y2=\"" + num(b[1]) +
           "\"/>\n";
}

/// The triangles: regular ones light (left out in `outline`), flipped red, degenerate ones
/// outlined in orange. The flipped and degenerate ones go to `folded`, to be drawn over the grid.
std::string triangles_svg(const Input& in, const MapInfo& info, const std::vector<int>& tris, bool outline,
                          const MapFrame& f, std::string& folded) {
    std::string regular;
    for (int t : tris) {
        const std::vector<Vec2> p = {f.at(in.uvs[3 * t]), f.at(in.uvs[3 * t + 1]), f.at(in.uvs[3 * t + 2])};
        const int o = info.orientation[t];
        if (o > 0) {
            if (!outline) regular += polygon(p, "");
        } else if (o < 0)
            folded += polygon(p, "fill=\"#e02020\" fill-opacity=\"0.8\" stroke=\"#900\" stroke-width=\"1\"");
        else
            folded += polygon(p, "fill=\"none\" stroke=\"#f08000\" stroke-width=\"3\"");
    }
    return "<g fill=\"#dde6f3\" stroke=\"#8090a8\" stroke-width=\"0.5\">\n" + regular + "</g>\n";
}

/// The outline of the triangles: boundary edges, and seams (an edge whose two sides have different UVs).
std::string seams_svg(const Input& in, const std::vector<int>& tris, const MapFrame& f) {
    const auto he = half_edges(in);
    std::string s = "<g stroke=\"#40608a\" stroke-width=\"1\">\n";
    for (int t : tris)
        for (int k = 0; k < 3; ++k) {
            const int a = in.triangles[t][k], b = in.triangles[t][(k + 1) % 3];
            const auto twin = he.find(static_cast<std::int64_t>(b) << 32 | static_cast<std::uint32_t>(a));
            const Vec2& p = in.uvs[3 * t + k];
            const Vec2& q = in.uvs[3 * t + (k + 1) % 3];
            if (twin != he.end() && same_uv(p, in.uvs[3 * (twin->second / 3) + (twin->second % 3 + 1) % 3]) &&
                same_uv(q, in.uvs[twin->second]))
                continue;
            s += line(f.at(p), f.at(q));
        }
    return s + "</g>\n";
}

/// The integer grid (every line while there are few, else every k-th).
std::string grid_svg(const MapFrame& f) {
    const Vec2 &lo = f.lo, &hi = f.hi;
    // The UVs of a drawn map are validated (below 2^52, times the grid scale): the clamps never bite.
    const std::int64_t step = std::max<std::int64_t>(1, io_detail::clamped_int<std::int64_t>(f.span / 200) + 1);
    std::string s = "<g stroke=\"#303030\" stroke-width=\"0.8\" stroke-opacity=\"0.6\">\n";
    for (int c = 0; c < 2; ++c)
        for (std::int64_t g = io_detail::clamped_int<std::int64_t>(std::ceil(lo[c] / step)) * step; g <= hi[c];
             g += step) {
            const Vec2 a = c == 0 ? f.at({double(g), lo[1]}) : f.at({lo[0], double(g)});
            const Vec2 b = c == 0 ? f.at({double(g), hi[1]}) : f.at({hi[0], double(g)});
            s += line(a, b);
        }
    return s + "</g>\n";
}

/// Fold regions: a label at the first drawn triangle of each.
std::string fold_labels_svg(const Input& in, const MapInfo& info, const std::vector<int>& tris, const MapFrame& f) {
    std::string s;
    std::vector<char> drawn(in.triangles.size(), 0);
    for (int t : tris) drawn[t] = 1;
    for (std::size_t r = 0; r < info.fold_regions.size(); ++r)
        for (int t : info.fold_regions[r].triangles)
            if (drawn[t]) {
                const Vec2 p = f.at(in.uvs[3 * t]);
                s += text(
                    p[0] + 6, p[1] - 6, "R" + std::to_string(r + 1),
                    "fill=\"#900\" font-weight=\"bold\" stroke=\"white\" stroke-width=\"3\" paint-order=\"stroke\"");
                break;
            }
    return s;
}

/// Singularities: a dot and the valence, at the vertex's corner in each drawn triangle's chart once.
std::string singularities_svg(const Input& in, const MapInfo& info, const std::vector<int>& tris, const MapFrame& f) {
    std::string s;
    for (const Singularity& sg : info.singularities)
        for (int t : tris) {
            const auto& tri = in.triangles[t];
            const int k = tri[0] == sg.vertex ? 0 : tri[1] == sg.vertex ? 1 : tri[2] == sg.vertex ? 2 : -1;
            if (k < 0) continue;
            const Vec2 p = f.at(in.uvs[3 * t + k]);
            const char* color = sg.valence < 4 ? "#1060d0" : "#20a020";
            s += circle(p[0], p[1], 6, std::string("fill=\"") + color + "\" stroke=\"white\"");
            s += text(p[0] + 8, p[1] + 14, std::to_string(sg.valence),
                      std::string("fill=\"") + color +
                          "\" font-weight=\"bold\" stroke=\"white\" stroke-width=\"3\" paint-order=\"stroke\"");
            break;
        }
    return s;
}

/// The violations: cells and triangles outlined, points circled, each with its number.
std::string violations_svg(const Input& in, const std::vector<MapMark>& marks, const MapFrame& f) {
    std::string s;
    const std::string red = "fill=\"#e00000\" fill-opacity=\"0.25\" stroke=\"#e00000\" stroke-width=\"2.5\"";
    for (const MapMark& m : marks) {
        std::string g;
        Vec2 label_at = f.at(m.at);
        if (m.shape == MapMark::Shape::Cell) {
            g += polygon({f.at(m.at), f.at({m.at[0] + 1, m.at[1]}), f.at({m.at[0] + 1, m.at[1] + 1}),
                          f.at({m.at[0], m.at[1] + 1})},
                         red);
            label_at = f.at({m.at[0] + 1, m.at[1] + 1});
        } else if (m.shape == MapMark::Shape::Triangle && m.triangle >= 0) {
            g += polygon(
                {f.at(in.uvs[3 * m.triangle]), f.at(in.uvs[3 * m.triangle + 1]), f.at(in.uvs[3 * m.triangle + 2])},
                red);
        }
        const Vec2 c = m.shape == MapMark::Shape::Cell ? f.at({m.at[0] + 0.5, m.at[1] + 0.5}) : f.at(m.at);
        g += circle(c[0], c[1], 9, "fill=\"none\" stroke=\"#e00000\" stroke-width=\"2.5\"");
        if (!m.label.empty())
            g += text(
                label_at[0] + 8, label_at[1] - 8, m.label,
                "fill=\"#c00000\" font-weight=\"bold\" stroke=\"white\" stroke-width=\"3\" paint-order=\"stroke\"");
        s += "<g class=\"violation-mark\">\n" + g + "</g>\n";
    }
    return s;
}

} // namespace

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

std::string draw_map(const Input& in, const MapInfo& info, const std::vector<int>& tris, bool outline,
                     const std::string& title, double& width, double& height, const std::vector<MapMark>& marks) {
    const MapFrame f(in, tris);
    width = f.width();
    height = f.height();
    std::string folded;
    std::string s = triangles_svg(in, info, tris, outline, f, folded);
    if (outline) s += seams_svg(in, tris, f);
    s += grid_svg(f) + folded;
    s += fold_labels_svg(in, info, tris, f);
    s += singularities_svg(in, info, tris, f);
    s += violations_svg(in, marks, f);
    s += text(MapFrame::margin, 22, title, "font-size=\"16\" font-weight=\"bold\"");
    s += text(MapFrame::margin, 44,
              std::to_string(info.flipped) + " flipped (red), " + std::to_string(info.degenerate) +
                  " degenerate (orange), " + std::to_string(info.fold_regions.size()) + " fold regions (R1..), " +
                  std::to_string(info.singularities.size()) + " singularities (valence; blue < 4 < green)");
    return s;
}

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

} // namespace qex::cli

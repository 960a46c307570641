// Where a rejected mesh is wrong: every checker violation becomes a defect that keeps the
// violation's kind and names what its element says (element_kind): for an output face or
// vertex, the face and the input triangle and grid point of the vertex's provenance; for an
// input vertex or triangle, an input triangle.
// A global violation (Euler characteristic, boundary loops, components) names where faces were
// removed and the input vertex farthest from the output, where a lost handle or a hole shows.
// And a defect's place on the working mesh, in vertices that do not depend on the input's order
// (place_vertices).
#include "pipeline.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace qex::detail {
namespace {

double distance(const std::array<double, 3>& p, const std::array<double, 3>& q) {
    return std::sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]));
}

/// The median length of the mesh's face sides; 0 for a mesh without faces or positions.
double median_edge_length(const QuadMesh& mesh) {
    std::vector<double> lengths;
    for (const auto& f : mesh.faces)
        for (std::size_t i = 0; i < f.size(); ++i)
            lengths.push_back(distance(mesh.positions[static_cast<std::size_t>(f[i])],
                                       mesh.positions[static_cast<std::size_t>(f[(i + 1) % f.size()])]));
    if (lengths.empty() || mesh.positions.empty()) return 0.0;
    std::nth_element(lengths.begin(), lengths.begin() + static_cast<std::ptrdiff_t>(lengths.size() / 2), lengths.end());
    return lengths[lengths.size() / 2];
}

/// Points bucketed in a uniform grid of cubes `cell` wide (a sorted list of cube keys).
class CellGrid {
public:
    using Key = std::array<std::int64_t, 3>;
    CellGrid(const std::vector<std::array<double, 3>>& points, double cell) : points_(points), cell_(cell) {
        entries_.reserve(points.size());
        for (std::size_t i = 0; i < points.size(); ++i)
            entries_.push_back({key(points[i], 0, 0, 0), static_cast<int>(i)});
        std::sort(entries_.begin(), entries_.end());
    }
    /// The cube of p, shifted by (dx, dy, dz) cubes.
    Key key(const std::array<double, 3>& p, int dx, int dy, int dz) const {
        const auto c = [&](double x, int d) { return static_cast<std::int64_t>(std::floor(x / cell_)) + d; };
        return {c(p[0], dx), c(p[1], dy), c(p[2], dz)};
    }
    /// The distance from p to the nearest point within `rings` cubes of p's cube (HUGE_VAL if none).
    /// The cubes are searched shell by shell (the cubes r from p's): a point in shell r or beyond
    /// lies more than r - 1 cube widths from p, so once a point nearer than that is found (with
    /// a margin for the rounding of the cube keys), the shells left cannot hold a nearer one.
    double nearest(const std::array<double, 3>& p, int rings) const {
        double best = HUGE_VAL;
        for (int r = 0; r <= rings && !(best < (r - 1) * cell_ * (1 - 1e-9)); ++r)
            for (int dx = -r; dx <= r; ++dx)
                for (int dy = -r; dy <= r; ++dy)
                    for (int dz = -r; dz <= r; ++dz) {
                        if (std::max({std::abs(dx), std::abs(dy), std::abs(dz)}) != r) continue; // an inner shell's
                        const Key k = key(p, dx, dy, dz);
                        auto it = std::lower_bound(entries_.begin(), entries_.end(), std::make_pair(k, -1));
                        for (; it != entries_.end() && it->first == k; ++it)
                            best = std::min(best, distance(p, points_[static_cast<std::size_t>(it->second)]));
                    }
        return best;
    }

private:
    const std::vector<std::array<double, 3>>& points_;
    double cell_;
    std::vector<std::pair<Key, int>> entries_;
};

/// Where the output leaves the input surface bare: the input vertex farthest from every output
/// vertex, and that distance in median output edge lengths. A lost handle or a hole shows up as
/// a bare region. A uniform grid of cells one median edge wide holds the output vertices, and
/// each input vertex searches up to 4 rings of cells around its own.
std::pair<int, double> barest_input_vertex(const Input& input, const QuadMesh& mesh) {
    const double cell = median_edge_length(mesh);
    if (!(cell > 0) || !std::isfinite(cell)) return {-1, 0.0};
    const CellGrid grid(mesh.positions, cell);
    const int rings = 4;
    int worst = -1;
    double worst_d = -1;
    for (std::size_t v = 0; v < input.positions.size(); ++v) {
        const double best = std::min(grid.nearest(input.positions[v], rings), (rings + 1) * cell); // beyond the rings
        if (best > worst_d) worst_d = best, worst = static_cast<int>(v);
    }
    return {worst, worst_d / cell};
}

/// A global defect has no single place; the places where faces were removed are where the
/// topology can have changed, and the barest input vertex is where the output is missing.
void describe_global(const Input& input, const Result& result, Defect& d) {
    // The explanations that removed faces: how many, and the first.
    const Defect* first = nullptr;
    std::size_t removed = 0;
    for (const Defect& e : result.report.explanations)
        if (e.kind == DefectKind::FaceCollapsed || e.kind == DefectKind::GhostFacesCancelled ||
            e.kind == DefectKind::BoundaryFaceDiscarded)
            first = first ? first : &e, ++removed;
    if (first) {
        d.message += " (faces were removed at " + std::to_string(removed) +
                     " places, listed in explanations; the first is near grid point (" + std::to_string(first->grid[0]) +
                     ", " + std::to_string(first->grid[1]) + ") of input triangle " +
                     std::to_string(first->input_element) + ")";
        d.input_element = first->input_element;
        d.grid = first->grid;
    }
    const auto [bare, distance] = barest_input_vertex(input, result.mesh);
    if (bare >= 0) {
        char figure[32];
        std::snprintf(figure, sizeof figure, "%.1f", distance);
        d.message += "; the input surface farthest from the output is at input vertex " + std::to_string(bare) + ", " +
                     figure + " median edge lengths from every output vertex";
    }
}

/// The first vertex of face `f` that has a provenance, or -1.
int vertex_of_face(const QuadMesh& mesh, std::int64_t f) {
    if (f < 0 || f >= static_cast<std::int64_t>(mesh.faces.size())) return -1;
    for (int v : mesh.faces[static_cast<std::size_t>(f)])
        if (v >= 0 && v < static_cast<int>(mesh.provenance.size())) return v;
    return -1;
}

/// Per input vertex, the first input triangle that has it (-1 for none).
std::vector<std::int64_t> first_triangles(const Input& input) {
    std::vector<std::int64_t> first(input.positions.size(), -1);
    for (std::size_t t = input.triangles.size(); t-- > 0;)
        for (int w : input.triangles[t])
            if (w >= 0 && static_cast<std::size_t>(w) < first.size())
                first[static_cast<std::size_t>(w)] = static_cast<std::int64_t>(t);
    return first;
}

/// Names the place of a violation of one output vertex: its provenance's triangle and grid point.
void place_at_vertex(const QuadMesh& mesh, int vertex, Defect& d) {
    if (vertex < 0 || vertex >= static_cast<int>(mesh.provenance.size())) return;
    const Provenance& p = mesh.provenance[static_cast<std::size_t>(vertex)];
    d.input_element = p.chart_triangle;
    d.grid = p.grid;
    d.message += " (near grid point (" + std::to_string(p.grid[0]) + ", " + std::to_string(p.grid[1]) +
                 ") of input triangle " + std::to_string(p.chart_triangle) + ")";
}

/// The defect for one violation, placed by what its element indexes (`first_triangle`: per
/// input vertex, a triangle that has it).
Defect locate(const Input& input, const Result& result, const std::vector<std::int64_t>& first_triangle,
              const Violation& v) {
    const QuadMesh& mesh = result.mesh;
    Defect d{DefectKind::CheckerViolation, v.message, -1, -1, {0, 0}, v.kind};
    switch (element_kind(v.kind)) {
        case ViolationElement::OutputFace:
            if (v.element >= 0 && v.element < static_cast<std::int64_t>(mesh.faces.size())) {
                d.output_face = v.element;
                place_at_vertex(mesh, vertex_of_face(mesh, v.element), d);
            }
            break;
        case ViolationElement::OutputVertex:
            if (v.element >= 0 && v.element < static_cast<std::int64_t>(mesh.positions.size()))
                place_at_vertex(mesh, static_cast<int>(v.element), d);
            break;
        case ViolationElement::InputVertex:
            if (v.element >= 0 && v.element < static_cast<std::int64_t>(first_triangle.size()))
                d.input_element = first_triangle[static_cast<std::size_t>(v.element)];
            break;
        case ViolationElement::InputTriangle:
            if (v.element >= 0 && v.element < static_cast<std::int64_t>(input.triangles.size()))
                d.input_element = v.element;
            break;
        case ViolationElement::None:
            if (v.kind == ViolationKind::EulerMismatch || v.kind == ViolationKind::BoundaryMismatch ||
                v.kind == ViolationKind::ComponentMismatch)
                describe_global(input, result, d);
            break;
    }
    return d;
}

} // namespace

void locate_violations(const Input& input, Result& result) {
    std::vector<std::int64_t> first_triangle;
    for (const Violation& v : result.check.violations)
        if (element_kind(v.kind) == ViolationElement::InputVertex && first_triangle.empty())
            first_triangle = first_triangles(input);
    for (const Violation& v : result.check.violations)
        result.report.defects.push_back(locate(input, result, first_triangle, v));
}

/// The vertices of every triangle round the element of triangle f that grid point g (in f's
/// chart) lies on: a corner's fan (every corner on g: a zero-length edge can survive the
/// collapse), an edge's two triangles (every edge through g when f is degenerate), else f.
/// Whichever triangle round a place an explanation names (that depends on the input's order),
/// the vertices are the same, and they hold the named triangle's.
void place_vertices(const TriMesh& m, int f, const std::array<std::int64_t, 2>& g, std::vector<int>& out) {
    const Point2 p{static_cast<double>(g[0]), static_cast<double>(g[1])};
    const auto triangle = [&](int t) {
        for (const int v : m.tri[t]) out.push_back(v);
    };
    bool on_corner = false;
    for (int k = 0; k < 3; ++k)
        if (m.uv[3 * f + k] == p) {
            const int v = m.tri[f][k];
            for (int h = m.fan_start[v], n = 0; h >= 0 && n < m.fan_size[v]; h = m.cw(h), ++n) triangle(TriMesh::face(h));
            on_corner = true;
        }
    if (!on_corner) {
        const bool degenerate = orient2d(m.uv[3 * f], m.uv[3 * f + 1], m.uv[3 * f + 2]) == Orientation::Collinear;
        for (int k = 0; k < 3; ++k)
            if (on_segment(p, m.uv[3 * f + k], m.uv[3 * f + (k + 1) % 3])) {
                if (const int o = m.opp[3 * f + k]; o >= 0) triangle(TriMesh::face(o));
                if (!degenerate) break;
            }
    }
    triangle(f);
}

} // namespace qex::detail

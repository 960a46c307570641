// The quality figures of a quad mesh (qex/quality.h): the scaled Jacobians of its quads, its
// irregular vertices, and the distances between it and the input. The checker's second use of
// CGAL's AABB tree (surface.cpp has the first); its CGAL stays in this file. Nothing here reads the
// checker's verdict: the figures are measured, not judged.
#include "parallel.h"
#include "qex/quality.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <tuple>
#include <vector>

namespace qex {
namespace {

using K = CGAL::Simple_cartesian<double>;
using Point = K::Point_3;
using Vector = K::Vector_3;
using Triangles = std::vector<K::Triangle_3>;
using Primitive = CGAL::AABB_triangle_primitive<K, Triangles::const_iterator>;
using AabbTree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;
using Positions = std::vector<std::array<double, 3>>;

/// The 5th percentile is the value at rank ceil(n / kPercentileDivisor), counted from 1.
constexpr std::size_t kPercentileDivisor = 20;
/// Fewer closest-point queries than this stay serial. A query takes microseconds, so threads pay
/// off far sooner than in the checker's cheap loops (verify_detail::kParallelMinElements).
constexpr std::int64_t kParallelMinQueries = std::int64_t{1} << 12;
/// Coordinates beyond this magnitude are not measured: squared distances between them would
/// overflow, and CGAL's boxes and predicates are not meant for infinities.
constexpr double kMaxCoordinate = 1e150;

// ============================================================================ the elements

Point at(const Positions& x, int v) {
    const auto& p = x[static_cast<std::size_t>(v)];
    return Point(p[0], p[1], p[2]);
}

/// Whether every index of the faces names a position, and every coordinate they use is within
/// kMaxCoordinate (so finite). CGAL's tree is built on these points: a NaN would break its boxes.
template <class Faces>
bool usable(const Positions& x, const Faces& faces) {
    for (const auto& f : faces)
        for (const int v : f) {
            if (v < 0 || static_cast<std::size_t>(v) >= x.size()) return false;
            for (const double c : x[static_cast<std::size_t>(v)])
                if (!(std::abs(c) <= kMaxCoordinate)) return false;
        }
    return true;
}

/// The mean of the face's corners. Each coordinate is summed in ascending order, so the bits do
/// not depend on which corner the face starts at.
template <class Face>
Point centroid(const Positions& x, const Face& f) {
    std::vector<double> c(f.size());
    double mean[3];
    for (int d = 0; d < 3; ++d) {
        for (std::size_t k = 0; k < f.size(); ++k) c[k] = x[static_cast<std::size_t>(f[k])][d];
        std::sort(c.begin(), c.end());
        double sum = 0;
        for (const double v : c) sum += v;
        mean[d] = sum / static_cast<double>(c.size());
    }
    return Point(mean[0], mean[1], mean[2]);
}

/// Marks the positions the faces use.
template <class Faces>
std::vector<char> used_positions(const Positions& x, const Faces& faces) {
    std::vector<char> used(x.size(), 0);
    for (const auto& f : faces)
        for (const int v : f) used[static_cast<std::size_t>(v)] = 1;
    return used;
}

// ============================================================================ shape of the quads

/// The scaled Jacobian of quad `f` (qex/quality.h): the smallest over its corners. A corner
/// whose value is not finite (a safeguard: within kMaxCoordinate none should be) counts 0, as a
/// degenerate one does.
double scaled_jacobian(const Positions& x, const std::vector<int>& f) {
    const Point p[4] = {at(x, f[0]), at(x, f[1]), at(x, f[2]), at(x, f[3])};
    const Vector n = CGAL::cross_product(p[2] - p[0], p[3] - p[1]);
    const double n_length = std::sqrt(n.squared_length());
    if (!(n_length > 0)) return 0.0;    // parallel diagonals: no side to sign the corners by
    const Vector normal = n / n_length; // before the products, which would overflow sooner
    double worst = 1.0;
    for (int k = 0; k < 4; ++k) {
        const Vector e1 = p[(k + 1) % 4] - p[k], e2 = p[(k + 3) % 4] - p[k];
        const double lengths = std::sqrt(e1.squared_length()) * std::sqrt(e2.squared_length());
        double j = lengths > 0 ? (CGAL::cross_product(e1, e2) * normal) / lengths : 0.0;
        if (!std::isfinite(j)) j = 0.0;
        worst = std::min(worst, std::clamp(j, -1.0, 1.0)); // rounding may step just past +-1
    }
    return worst;
}

void shape_figures(const QuadMesh& mesh, MeshQuality& q) {
    std::vector<double> values;
    values.reserve(mesh.faces.size());
    for (const auto& f : mesh.faces) {
        if (f.size() == 4)
            values.push_back(scaled_jacobian(mesh.positions, f));
        else
            ++q.other_faces;
    }
    q.quads = static_cast<std::int64_t>(values.size());
    if (values.empty()) return;
    // Sorted, the values are the same sequence for any face order: the mean's sum too.
    std::sort(values.begin(), values.end());
    q.min_scaled_jacobian = values.front();
    q.p5_scaled_jacobian = values[(values.size() + kPercentileDivisor - 1) / kPercentileDivisor - 1];
    double sum = 0;
    for (const double v : values) sum += v;
    q.mean_scaled_jacobian = sum / static_cast<double>(values.size());
}

// ============================================================================ irregular vertices

void vertex_figures(const QuadMesh& mesh, MeshQuality& q) {
    const std::size_t nv = mesh.positions.size();
    std::vector<std::int64_t> faces_at(nv, 0);
    // Each face side as its two vertices, the smaller first: sorted, a side that occurs once is
    // on the boundary.
    std::vector<std::uint64_t> sides;
    for (const auto& f : mesh.faces)
        for (std::size_t k = 0; k < f.size(); ++k) {
            const auto a = static_cast<std::uint32_t>(f[k]), b = static_cast<std::uint32_t>(f[(k + 1) % f.size()]);
            ++faces_at[a];
            sides.push_back(std::uint64_t{std::min(a, b)} << 32 | std::max(a, b));
        }
    std::sort(sides.begin(), sides.end());
    std::vector<char> boundary(nv, 0);
    for (std::size_t i = 0, j = 0; i < sides.size(); i = j) {
        while (j < sides.size() && sides[j] == sides[i]) ++j;
        if (j - i == 1) boundary[sides[i] >> 32] = boundary[sides[i] & 0xffffffffu] = 1;
    }
    for (std::size_t v = 0; v < nv; ++v) {
        if (faces_at[v] == 0) continue;
        ++q.vertices;
        q.irregular_vertices += faces_at[v] != (boundary[v] ? 2 : 4);
    }
    if (q.vertices > 0)
        q.irregular_vertex_share = static_cast<double>(q.irregular_vertices) / static_cast<double>(q.vertices);
}

// ============================================================================ distances

bool lexicographically_less(const Point& a, const Point& b) {
    return std::make_tuple(a.x(), a.y(), a.z()) < std::make_tuple(b.x(), b.y(), b.z());
}

bool lexicographically_less(const K::Triangle_3& s, const K::Triangle_3& t) {
    for (int k = 0; k < 3; ++k) {
        if (lexicographically_less(s[k], t[k])) return true;
        if (lexicographically_less(t[k], s[k])) return false;
    }
    return false;
}

/// Triangles of positive area, and the tree over them. Heap-held by the caller: the tree's
/// primitives point into `triangles`.
struct Surface {
    Triangles triangles;
    std::unique_ptr<AabbTree> tree;

    /// Each triangle starts at its smallest corner (the orientation kept). With the sort in
    /// build(), the tree is the same for any order of the faces and their corners, and so is
    /// every rounding of its queries, ties between triangles included.
    void add(const Point& a, const Point& b, const Point& c) {
        const Point p[3] = {a, b, c};
        int k = 0;
        if (lexicographically_less(p[1], p[k])) k = 1;
        if (lexicographically_less(p[2], p[k])) k = 2;
        const K::Triangle_3 t(p[k], p[(k + 1) % 3], p[(k + 2) % 3]);
        if (!t.is_degenerate()) triangles.push_back(t); // no closest point of its own
    }
    /// Builds the tree and its search structure now, so that the queries only read them (from
    /// several threads). Returns false for a surface without a triangle.
    bool build() {
        if (triangles.empty()) return false;
        std::sort(triangles.begin(), triangles.end(),
                  [](const K::Triangle_3& s, const K::Triangle_3& t) { return lexicographically_less(s, t); });
        tree = std::make_unique<AabbTree>(triangles.cbegin(), triangles.cend());
        tree->build();
        tree->accelerate_distance_queries();
        return true;
    }
};

/// The input's triangles; `diagonal` gets the bounding-box diagonal of the vertices they use.
bool input_surface(const Input& map, Surface& s, double& diagonal) {
    double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    s.triangles.reserve(map.triangles.size());
    for (const auto& t : map.triangles) {
        for (const int v : t)
            for (int d = 0; d < 3; ++d) {
                lo[d] = std::min(lo[d], map.positions[static_cast<std::size_t>(v)][d]);
                hi[d] = std::max(hi[d], map.positions[static_cast<std::size_t>(v)][d]);
            }
        s.add(at(map.positions, t[0]), at(map.positions, t[1]), at(map.positions, t[2]));
    }
    if (!s.build()) return false;
    diagonal = std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                         (hi[2] - lo[2]) * (hi[2] - lo[2]));
    return std::isfinite(diagonal) && diagonal > 0;
}

/// The mesh's faces, each split into triangles joining its sides to its centroid (faces of fewer
/// than 3 vertices have no area).
bool mesh_surface(const QuadMesh& mesh, Surface& s) {
    s.triangles.reserve(4 * mesh.faces.size());
    for (const auto& f : mesh.faces) {
        if (f.size() < 3) continue;
        const Point c = centroid(mesh.positions, f);
        for (std::size_t k = 0; k < f.size(); ++k)
            s.add(at(mesh.positions, f[k]), at(mesh.positions, f[(k + 1) % f.size()]), c);
    }
    return s.build();
}

/// The points measured from one side: the vertices its faces use and each face's centroid.
template <class Faces>
std::vector<Point> sample_points(const Positions& x, const Faces& faces) {
    std::vector<Point> points;
    const std::vector<char> used = used_positions(x, faces);
    for (std::size_t v = 0; v < x.size(); ++v)
        if (used[v]) points.push_back(at(x, static_cast<int>(v)));
    for (const auto& f : faces)
        if (f.size() >= 3) points.push_back(centroid(x, f));
    return points;
}

/// The largest distance from the points to the tree's triangles. Each point's distance is its
/// own, and a maximum does not round: the same bits for any order of the points and any split
/// over the threads.
double farthest(const AabbTree& tree, const std::vector<Point>& points) {
    const auto n = static_cast<std::int64_t>(points.size());
    const int threads = verify_detail::thread_count(0);
    const int workers = threads > 1 && n >= kParallelMinQueries ? threads : 1;
    std::vector<double> worst(static_cast<std::size_t>(workers), 0.0);
    verify_detail::share_chunks(workers, n, (n + workers - 1) / workers, [&](std::size_t t, const auto& next) {
        for (std::int64_t from = 0, to = 0; next(from, to);)
            for (std::int64_t i = from; i < to; ++i) {
                const Point& p = points[static_cast<std::size_t>(i)];
                worst[t] = std::max(worst[t], CGAL::squared_distance(p, tree.closest_point(p)));
            }
    });
    return std::sqrt(*std::max_element(worst.begin(), worst.end()));
}

} // namespace

MeshQuality mesh_quality(const Input& map, const QuadMesh& mesh) {
    if (!usable(map.positions, map.triangles) || !usable(mesh.positions, mesh.faces)) return {};
    MeshQuality q;
    Surface input, quads;
    if (!input_surface(map, input, q.diagonal) || !mesh_surface(mesh, quads)) return {};
    shape_figures(mesh, q);
    vertex_figures(mesh, q);
    q.distance_input_to_mesh = farthest(*quads.tree, sample_points(map.positions, map.triangles)) / q.diagonal;
    q.distance_mesh_to_input = farthest(*input.tree, sample_points(mesh.positions, mesh.faces)) / q.diagonal;
    q.computed = true;
    return q;
}

} // namespace qex

// The located mode's geometry on CGAL (its only translation unit that includes CGAL): the input
// surface as an AABB tree for locating points, the exact orientation of the map's triangles,
// and the distances between neighbouring triangles' centroids that its searches walk.
#include "checker.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Simple_cartesian.h>

#include <algorithm>
#include <cmath>

namespace qex::verify_detail {
namespace {

using K = CGAL::Simple_cartesian<double>;
using Triangles = std::vector<K::Triangle_3>;
using Primitive = CGAL::AABB_triangle_primitive<K, Triangles::const_iterator>;
using AabbTree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;

/// The centroid of input triangle t.
K::Point_3 centroid(const Input& in, std::size_t t) {
    const auto &a = in.positions[static_cast<std::size_t>(in.triangles[t][0])],
               &b = in.positions[static_cast<std::size_t>(in.triangles[t][1])],
               &c = in.positions[static_cast<std::size_t>(in.triangles[t][2])];
    return K::Point_3((a[0] + b[0] + c[0]) / 3, (a[1] + b[1] + c[1]) / 3, (a[2] + b[2] + c[2]) / 3);
}

} // namespace

/// The tree over the triangles that are not degenerate in 3D (`index`: their input triangles),
/// and the tolerances. Heap-allocated once: the tree's primitives point into `tris`.
struct Surface::Tree {
    const Input& in;
    Triangles tris;
    std::vector<std::uint32_t> index;
    double diag = 0, max_dist = 0;
    std::unique_ptr<AabbTree> aabb;
    explicit Tree(const Input& input) : in(input) {}
};

Surface::Surface(std::unique_ptr<Tree> tree) : tree_(std::move(tree)) {}
Surface::~Surface() = default;
double Surface::diagonal() const { return tree_->diag; }
double Surface::max_distance() const { return tree_->max_dist; }

std::unique_ptr<Surface> Surface::build(const Input& in, double distance_tolerance) {
    // Surface triangles (3D-degenerate ones cannot be closest to anything their neighbours miss).
    auto s = std::make_unique<Tree>(in);
    const std::size_t nt = in.triangles.size();
    s->tris.reserve(nt);
    s->index.reserve(nt);
    double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    for (std::size_t t = 0; t < nt; ++t) {
        K::Point_3 p[3];
        bool finite = true;
        for (int k = 0; k < 3; ++k) {
            const auto& x = in.positions[static_cast<std::size_t>(in.triangles[t][k])];
            for (int d = 0; d < 3; ++d) {
                finite = finite && std::isfinite(x[d]) && std::isfinite(in.uvs[3 * t + k][d % 2]);
                lo[d] = std::min(lo[d], x[d]);
                hi[d] = std::max(hi[d], x[d]);
            }
            p[k] = K::Point_3(x[0], x[1], x[2]);
        }
        if (!finite) return nullptr; // not a map this mode can judge (validation names the problem)
        const K::Triangle_3 tri(p[0], p[1], p[2]);
        if (tri.is_degenerate()) continue;
        s->tris.push_back(tri);
        s->index.push_back(static_cast<std::uint32_t>(t));
    }
    if (s->tris.empty()) return nullptr;
    s->diag = std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                        (hi[2] - lo[2]) * (hi[2] - lo[2]));
    s->max_dist = distance_tolerance * s->diag;
    s->aabb = std::make_unique<AabbTree>(s->tris.cbegin(), s->tris.cend());
    s->aabb->accelerate_distance_queries();
    return std::unique_ptr<Surface>(new Surface(std::move(s)));
}

SurfacePoint Surface::locate(const std::array<double, 3>& x, double snap) const {
    const Tree& s = *tree_;
    const K::Point_3 p(x[0], x[1], x[2]);
    const auto hit = s.aabb->closest_point_and_primitive(p);
    const std::size_t k = static_cast<std::size_t>(hit.second - s.tris.cbegin());
    SurfacePoint out;
    out.triangle = s.index[k];
    out.distance = std::sqrt(CGAL::squared_distance(p, hit.first));
    // Barycentric coordinates of the closest point (in the triangle's plane).
    const K::Triangle_3& tri = s.tris[k];
    const K::Vector_3 e0 = tri[1] - tri[0], e1 = tri[2] - tri[0], w = hit.first - tri[0];
    const double d00 = e0 * e0, d01 = e0 * e1, d11 = e1 * e1, d20 = w * e0, d21 = w * e1;
    const double den = d00 * d11 - d01 * d01;
    const double b1 = den != 0 ? (d11 * d20 - d01 * d21) / den : 0.0;
    const double b2 = den != 0 ? (d00 * d21 - d01 * d20) / den : 0.0;
    const double b0 = 1.0 - b1 - b2;
    for (int q = 0; q < 3 && out.corner < 0; ++q)
        if (std::sqrt(CGAL::squared_distance(hit.first, tri[q])) <= (snap < 0 ? s.max_dist : snap)) out.corner = q;
    const std::uint32_t t = out.triangle;
    const auto &u0 = s.in.uvs[3 * t], &u1 = s.in.uvs[3 * t + 1], &u2 = s.in.uvs[3 * t + 2];
    out.uv = {b0 * u0[0] + b1 * u1[0] + b2 * u2[0], b0 * u0[1] + b1 * u1[1] + b2 * u2[1]};
    return out;
}

std::vector<char> fold_overs(const Input& in, VerifyResult& r) {
    using P = CGAL::Epick::Point_2;
    std::vector<char> fold_over(in.triangles.size(), 0);
    for (std::size_t t = 0; t < in.triangles.size(); ++t) {
        const auto &a = in.uvs[3 * t], &b = in.uvs[3 * t + 1], &c = in.uvs[3 * t + 2];
        const auto o = CGAL::orientation(P(a[0], a[1]), P(b[0], b[1]), P(c[0], c[1]));
        fold_over[t] = o != CGAL::POSITIVE;
        r.map_flipped_triangles += o == CGAL::NEGATIVE;
    }
    return fold_over;
}

std::vector<double> centroid_steps(const Input& in, const InputEdges& edges) {
    const std::size_t nt = in.triangles.size();
    std::vector<K::Point_3> centre(nt);
    for (std::size_t t = 0; t < nt; ++t) centre[t] = centroid(in, t);
    std::vector<double> step(edges.opposite.size(), 0.0);
    for (std::size_t c = 0; c < step.size(); ++c) {
        const std::int64_t o = edges.opposite[c];
        if (o >= 0) step[c] = std::sqrt(CGAL::squared_distance(centre[c / 3], centre[static_cast<std::size_t>(o / 3)]));
    }
    return step;
}

} // namespace qex::verify_detail

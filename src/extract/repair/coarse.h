// The repair on the map's coarsest triangulation (inside the subsystem only; its door is
// repair.h). A vertex whose star is flat in space and on which the map is affine adds nothing to
// the map: a subdivided map is the same map with more such vertices. The repair counts its rings,
// its dipoles' reach and its untangler's unknowns in vertices, so it runs on the triangulation
// without them (coarse_triangulation.cpp, coarse_mesh.cpp), and its result is written back onto
// the given one (coarse_transfer.cpp, coarse_outcome.cpp).
#pragma once

#include "extract/repair/regions.h"
#include "extract/repair/repair.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <vector>

namespace qex::detail::repair_impl {

using Vec3 = std::array<double, 3>;

/// Relative tolerance of "flat in space": far above the rounding of a midpoint, (a + b) / 2 in
/// doubles, and far below what a curved surface leaves (of the 50 shared maps, only fandisk's
/// planes and 6 vertices elsewhere pass, and none of them is affine in the map too).
inline constexpr double kFlat = 1e-9;

inline Vec3 minus(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/// The barycentric coordinates of p, projected onto the plane of (a, b, c). False if degenerate.
inline bool barycentric3(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& p, std::array<double, 3>& l) {
    const Vec3 e1 = minus(b, a), e2 = minus(c, a), d = minus(p, a);
    const double a11 = dot(e1, e1), a12 = dot(e1, e2), a22 = dot(e2, e2), det = a11 * a22 - a12 * a12;
    if (!(det > 0.0)) return false;
    const double b1 = dot(d, e1), b2 = dot(d, e2);
    l[1] = (b1 * a22 - b2 * a12) / det;
    l[2] = (b2 * a11 - b1 * a12) / det;
    l[0] = 1.0 - l[1] - l[2];
    return true;
}

/// Whether p lies in the plane of triangle q: a vertex on a piece's rim projects into the piece
/// beside it too, where it is not. Looser than kFlat: p's distance adds up over the collapses.
inline bool in_plane(const std::array<Vec3, 3>& q, const Vec3& p) {
    const Vec3 n = cross(minus(q[1], q[0]), minus(q[2], q[0]));
    double l = 0.0;
    for (int k = 0; k < 3; ++k) {
        const Vec3 e = minus(q[(k + 1) % 3], q[k]);
        l = std::max(l, std::sqrt(dot(e, e)));
    }
    return std::abs(dot(n, minus(p, q[0]))) <= 1e3 * kFlat * l * std::sqrt(dot(n, n));
}

/// A vertex's fan in the given mesh, and the maps between its corners' charts.
struct Fan {
    std::vector<int> corners;
    std::vector<GridAutomorphism> to_c;
    GridAutomorphism between(int from, int to) const {
        const auto at = [&](int c) { return std::find(corners.begin(), corners.end(), c) - corners.begin(); };
        return to_c[static_cast<std::size_t>(at(to))].after(to_c[static_cast<std::size_t>(at(from))].inverse());
    }
};

/// What the collapses leave: per coarse triangle and corner, its vertex, a corner of that vertex
/// in the given mesh and the map from that corner's chart to the triangle's; per vertex, the one
/// it was collapsed onto (-1 if kept).
struct Collapses {
    std::vector<std::array<int, 3>> v, ref;
    std::vector<std::array<GridAutomorphism, 3>> to_face;
    std::vector<int> onto;
};

/// The coarsest triangulation found, with the given mesh's vertex numbering (a vertex it does
/// without has no fan there), and its map state the given one's. Per coarse corner: a corner of
/// the same vertex in the given mesh and the map from that corner's chart to the coarse
/// triangle's.
struct CoarseMap {
    TriMesh mesh;
    std::vector<int> host; ///< per vertex: the coarse triangle that holds it, -1 if kept
    std::vector<int> ref;
    std::vector<GridAutomorphism> to_face;
};

/// The coarsest triangulation of m's map, by collapses that keep it (free vertices only: `pinned`
/// as pinned_vertices gives it). False when no vertex can go, or when the result does not carry
/// m's map exactly (then nothing is to be gained or trusted).
bool coarsen(const TriMesh& m, const std::vector<char>& pinned, CoarseMap& out);

/// The collapses' triangles as a mesh with m's vertex numbering and map state, and the coarse
/// triangle holding each vertex it does without; false if they are not a mesh, their transitions
/// do not carry their UVs exactly, a fan closes otherwise than in m, or a vertex lies in none
/// (coarse_mesh.cpp).
bool build_coarse(const TriMesh& m, const Collapses& collapses, CoarseMap& out);

/// The coarse repair's outcome named on m, its UVs written back (`sanitized`: m's UVs before):
/// the triangles whose UVs changed and their groups, the fold-overs left (grouped on m, each
/// with the reason of the coarse fold-over that holds it) and the proofs, with the triangles of m
/// their coarse triangles hold; updates face_sign (coarse_outcome.cpp).
RepairOutcome fine_outcome(TriMesh& m, const std::vector<Point2>& sanitized, const CoarseMap& cm,
                           const RepairOutcome& coarse);

/// The vertices of m in `near` as coarse ones: one the coarse triangulation does without by the
/// corners of the triangle that holds it.
std::vector<int> coarse_near(const CoarseMap& cm, const std::vector<int>& near);

/// The repair at one triangulation: repair() without the coarse triangulation (repair.cpp).
using RepairAt = std::function<RepairOutcome(TriMesh&, Report&, const LookBeforeLastRing&)>;

/// The repair run on the coarse triangulation of m's map and written back onto m: the UVs of the
/// vertices it moved (the others interpolated in their coarse triangles), the transitions of the
/// dipole merges that stand, and valences. False, with m as it was, where no vertex can go or the
/// result does not hold on m (a triangle of m not positive, or a vertex winding otherwise); the
/// caller then repairs m itself.
bool repair_coarse(TriMesh& m, const std::vector<char>& pinned, const RepairAt& repair_at, Report& report,
                   const LookBeforeLastRing& look, RepairOutcome& out);

} // namespace qex::detail::repair_impl

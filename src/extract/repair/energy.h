// The repair's energy (inside the subsystem only; its door is repair.h): the rest shapes of a
// region's triangles, the region as an optimisation problem over its free vertices' UVs, and
// the foldover-free energy of Garanzha et al. 2021 over it (energy.cpp).
#pragma once

#include "extract/repair/regions.h"

#include <array>
#include <cmath>
#include <cstdint>
#include <atomic>
#include <vector>

namespace qex::detail::repair_impl {

/// A triangle's rest shape: the inverse of its reference edge matrix (columns r1 - r0, r2 - r0)
/// and its reference area; corners in the order base, next, prev.
struct RestShape {
    double g00, g01, g10, g11;
    double area;
    int base; ///< corner the triangle's Jacobian starts at (canonical: smallest 3D position)
};

/// chi(D, eps) = (D + r) / 2 with r = sqrt(eps^2 + D^2) given, without cancellation for D < 0.
inline double chi_with(double d, double eps, double r) { return d >= 0 ? 0.5 * (d + r) : 0.5 * eps * eps / (r - d); }

/// chi(D, eps) = (D + sqrt(eps^2 + D^2)) / 2, without cancellation for D < 0. Inline: the
/// energy evaluates it for every triangle of a region at every step.
inline double chi(double d, double eps) { return chi_with(d, eps, std::sqrt(eps * eps + d * d)); }

/// The free vertices' UVs in their first charts (the unknowns), and their mean edge length.
std::vector<double> region_point(const TriMesh& m, const Region& r, double& length);

/// Rest shapes of the region's triangles (in its order), scaled so that their total area is the region's
/// signed UV area (which the repair keeps). False when that area is not positive: no
/// orientation-preserving embedding with this boundary exists.
bool rest_shapes(const TriMesh& m, const Region& r, std::vector<RestShape>& rest);

/// The region as an optimisation problem over its free vertices' UVs, each in the chart of its
/// fan's first corner: per triangle and rest-shape corner, the free vertex (-1: fixed, with
/// its UV) and the transition into the triangle's chart; per triangle its rest shape, in the
/// region's order and in separate arrays (structure of arrays), so that the energy's arithmetic,
/// triangle by triangle independent, runs in vector lanes.
struct Problem {
    /// Per corner (corner k of triangle t at k n + t, k from its rest shape's base on), how its UV
    /// is read from the point X (the free vertices' UVs, then the fixed corners' UVs), with no
    /// branch: the rotation as a pick and a sign (-1.0 * v is -v, 1.0 * v is v), the translation
    /// added (-0.0 for a fixed corner: v + -0.0 is v, zeros' signs included).
    struct Corners {
        std::vector<std::int32_t> ix, iy; ///< u = (sx X[ix] + tx, sy X[iy] + ty)
        std::vector<double> sx, sy, tx, ty;
    };
    Corners corners;
    /// The gradient as gathered per unknown: unknown j sums sign * out[from] over its terms, in
    /// the order of the triangles and their corners (so its bits depend on nothing else); `from`
    /// names a row of `out` and a triangle. A fixed corner's gradient goes nowhere. The unknowns
    /// go in blocks of four, summed side by side in vector lanes: block b's terms are from
    /// first[b] to first[b + 1], four at a time (one per unknown), each unknown's padded to the
    /// block's longest with +1 * the zero after out's rows (a sum from +0.0 is never -0.0, so
    /// adding +0.0 keeps its bits).
    struct Gather {
        std::vector<std::int32_t> first, from;
        std::vector<double> sign;
    };
    Gather gather;
    std::size_t triangles = 0;
    std::size_t unknowns = 0; ///< 2 per free vertex
    /// Where set, the minimisation ends at its next iteration (Workspace::stop).
    const std::atomic<bool>* stop = nullptr;
    mutable std::vector<double> point; ///< X
    /// The triangles (places in the region's order, ascending) kept positive by a pure barrier (no
    /// regularisation), so the opened fan of a cone keeps its winding.
    std::vector<int> barrier_triangles;
    /// The energy's rows, n = triangles long each: what goes in per triangle (its edge vectors
    /// u1 - u0 and u2 - u0 in its chart, the regularisation, its rest shape's inverse edge matrix
    /// and area), and what comes out (its energy and gradient with respect to u1 (da), u2 (db)
    /// and u0 (dc = -(da + db))).
    enum In : std::size_t { a0, a1, b0, b1, eps, g00, g01, g10, g11, area, in_rows };
    enum Out : std::size_t { energy, da0, da1, db0, db1, dc0, dc1, out_rows };
    mutable std::vector<double> in, out; ///< row by row (structure of arrays); out ends in a zero
    std::vector<double> gdet;            ///< per triangle: the inverse edge matrix's determinant
};

/// Twice triangle t's signed UV area at the point whose edge vectors p.in holds (the one the
/// energy evaluated last): positive where the triangle is not inverted, in the solver's doubles.
inline double twice_area(const Problem& p, std::size_t t) {
    const std::size_t n = p.triangles;
    const double* in = p.in.data();
    return in[Problem::a0 * n + t] * in[Problem::b1 * n + t] - in[Problem::a1 * n + t] * in[Problem::b0 * n + t];
}

/// The region's problem (the corners of each triangle from its rest shape's base on; `rest` as
/// rest_shapes left it); `corner_slot` is per-corner scratch (all -1 before and after), and
/// `barrier` (sorted) names the triangles kept positive by a pure barrier.
Problem make_problem(const TriMesh& m, const Region& r, const std::vector<RestShape>& rest,
                     std::vector<int>& corner_slot, const std::vector<int>& barrier);

/// The region's energy at x, and with `grad` its gradient; `lowest`: the smallest Jacobian
/// determinant.
double region_energy(const Problem& p, const std::vector<double>& x, double eps, std::vector<double>* grad,
                     double* lowest = nullptr);

} // namespace qex::detail::repair_impl

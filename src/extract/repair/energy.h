// The repair's energy (inside the subsystem only; its door is repair.h): the rest shapes of a
// region's triangles, the region as an optimisation problem over its free vertices' UVs, and
// the foldover-free energy of Garanzha et al. 2021 over it (energy.cpp).
#pragma once

#include "extract/repair/regions.h"

#include <array>
#include <cmath>
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

/// Rest shapes of the region's triangles, scaled so that their total area is the region's
/// signed UV area (which the repair keeps). False when that area is not positive: no
/// orientation-preserving embedding with this boundary exists.
bool rest_shapes(const TriMesh& m, const Region& r, std::vector<RestShape>& rest);

/// The region as an optimisation problem over its free vertices' UVs, each in the chart of its
/// fan's first corner: per triangle and rest-shape corner, the free vertex (-1: fixed, with
/// its UV) and the transition into the triangle's chart.
struct Problem {
    struct Corner {
        int slot = -1;
        GridAutomorphism to;
        Vec2 fixed{0.0, 0.0};
    };
    std::vector<std::array<Corner, 3>> corners; ///< per triangle of the region, in its order
    std::size_t unknowns = 0;                   ///< 2 per free vertex
    /// Per triangle: kept positive by a pure barrier (no regularisation), so the opened fan of a
    /// cone keeps its winding.
    std::vector<char> barrier;
};

/// The region's problem (the corners of each triangle from its rest shape's base on);
/// `corner_slot` and `corner_to` are per-corner scratch (corner_slot is all -1 before and after),
/// and `barrier` (sorted) names the triangles kept positive by a pure barrier.
Problem make_problem(const TriMesh& m, const Region& r, const std::vector<RestShape>& rest,
                     std::vector<int>& corner_slot, std::vector<GridAutomorphism>& corner_to,
                     const std::vector<int>& barrier);

/// The region's energy at x, and with `grad` its gradient; `lowest`: the smallest Jacobian
/// determinant.
double region_energy(const Problem& p, const Region& r, const std::vector<RestShape>& rest,
                     const std::vector<double>& x, double eps, std::vector<double>* grad, double* lowest = nullptr);

} // namespace qex::detail::repair_impl

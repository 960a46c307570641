// The repair's Newton solver (inside the subsystem only; its door is repair.h): the final
// relaxation of a repaired region, to the minimum of its energy with no regularisation
// (newton.cpp).
#pragma once

#include "extract/repair/energy.h"

#include <Eigen/Core>

#include <memory>
#include <vector>

namespace qex::detail::repair_impl {

/// What Newton's method needs of a region before any point: the Hessian's pattern over the free
/// unknowns and the sparse Cholesky's ordering and symbolic factorisation. It reads only the
/// problem's corners (never its rows), so it can be made beside the L-BFGS iterations that come
/// before Newton's (polish_region): the same system, and the same bits, either way.
class NewtonSystem {
public:
    explicit NewtonSystem(const Problem& p);
    ~NewtonSystem();
    NewtonSystem(const NewtonSystem&) = delete;
    NewtonSystem& operator=(const NewtonSystem&) = delete;
    struct Parts; ///< newton.cpp's
    Parts& parts() { return *parts_; }

private:
    std::unique_ptr<Parts> parts_;
};

/// Minimises the region's energy at eps = 0 (a pure barrier: no triangle can invert) from x, which
/// must have every triangle positive, by Newton's method: each triangle's Hessian projected onto
/// the positive semi-definite matrices, the sum solved by a sparse Cholesky factorisation
/// (Eigen's), and a backtracking line search. It stops after a whole step from a decrement below
/// 1e-4 of the energy (the vertices are then as near the minimum as positions need), when the
/// decrement is below 1e-13, or after `iterations`. Returns the iterations taken; x is left at the last accepted
/// point (unchanged when none was).
int minimise_newton(const Problem& p, std::vector<double>& x, int iterations);
/// The same, with the system made before (from the same problem).
int minimise_newton(const Problem& p, std::vector<double>& x, int iterations, NewtonSystem& system);

/// The Hessian of one triangle's energy at eps = 0, f(J) = w |J|^2 / det J + q det J + q / det J
/// (det J > 0, the weights as in energy.cpp), in the entries (j00, j01, j10, j11) of its Jacobian;
/// with `project`, projected onto the positive semi-definite matrices (negative eigenvalues set
/// to zero). Here for its test.
Eigen::Matrix4d energy_hessian(double j00, double j01, double j10, double j11, bool project);

} // namespace qex::detail::repair_impl

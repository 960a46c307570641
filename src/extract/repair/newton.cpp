// The repair's Newton solver: the energy's Hessian per triangle, projected and assembled over a
// region's free vertices, and Newton steps to the minimum (newton.h). L-BFGS needs thousands of
// iterations to settle this barrier energy; Newton needs a few. It stops near enough the minimum
// that a translated or re-charted map's relaxed vertices stay within the owner's bound (1% of
// the median edge length), not at the minimum to rounding.
#include "extract/repair/newton.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>

#include <algorithm>
#include <cmath>

namespace qex::detail::repair_impl {
namespace {

/// The energy's weight on area against shape, as in energy.cpp.
constexpr double kAreaWeight = 0.5;
/// The decrement, relative to the energy, below which a step would change nothing that matters.
constexpr double kDecrement = 1e-13;
/// The decrement, relative to the energy, after whose whole step the relaxation stops. Near the
/// minimum a whole step about squares it (duck_miq_8's largest region: 2.1e-4, 3.6e-6, 1.3e-8),
/// so the point is then far nearer the minimum than positions need. The transform tests hold up
/// to 1e-3 and fail at 1e-2; over the 50 shared maps the quality figures are those of the exact
/// minimum to 2%. On the paper's ducks it saves two or three factorisations per large region.
constexpr double kSettled = 1e-4;

using Matrix4 = Eigen::Matrix4d;
using Triplets = std::vector<Eigen::Triplet<double>>;

} // namespace

Eigen::Matrix4d energy_hessian(double j00, double j01, double j10, double j11, bool project) {
    constexpr double q = kAreaWeight, w = 1 - kAreaWeight;
    const double x[4] = {j00, j01, j10, j11}, c[4] = {j11, -j10, -j01, j00}; // c: the gradient of d
    const double d = j00 * j11 - j01 * j10, F = j00 * j00 + j01 * j01 + j10 * j10 + j11 * j11;
    // The Hessians of |J|^2 / d, d and 1 / d combined: identity, x c^T + c x^T, c c^T, and the
    // constant Hessian of d (1 at (0, 3), -1 at (1, 2), symmetric).
    const double k_id = 2 * w / d, k_xc = -2 * w / (d * d), k_cc = 2 * (w * F + q) / (d * d * d),
                 k_hd = q - (w * F + q) / (d * d);
    Matrix4 h;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
            h(i, j) = (i == j ? k_id : 0.0) + k_xc * (x[i] * c[j] + c[i] * x[j]) + k_cc * c[i] * c[j];
    h(0, 3) += k_hd, h(3, 0) += k_hd, h(1, 2) -= k_hd, h(2, 1) -= k_hd;
    if (!project) return h;
    // Most triangles' Hessians are positive definite already: a Cholesky factorisation tells,
    // at a fraction of the eigen-decomposition's cost.
    if (Eigen::LLT<Matrix4>(h).info() == Eigen::Success) return h;
    const Eigen::SelfAdjointEigenSolver<Matrix4> eigen(h);
    const Eigen::Vector4d clamped = eigen.eigenvalues().cwiseMax(0.0);
    return eigen.eigenvectors() * clamped.asDiagonal() * eigen.eigenvectors().transpose();
}

namespace {

/// Triangle t's corners as unknowns: per corner component, its unknown (>= p.unknowns: fixed)
/// and the sign it is read with.
struct CornerUnknowns {
    int index[6];
    double sign[6];
};

CornerUnknowns corner_unknowns(const Problem& p, std::size_t t) {
    CornerUnknowns u;
    for (std::size_t k = 0; k < 3; ++k) {
        const std::size_t c = k * p.triangles + t;
        u.index[2 * k] = p.corners.ix[c], u.sign[2 * k] = p.corners.sx[c];
        u.index[2 * k + 1] = p.corners.iy[c], u.sign[2 * k + 1] = p.corners.sy[c];
    }
    return u;
}

/// Triangle t's Hessian (projected with `project`) in its corners' UVs (u0, u1, u2 in its chart),
/// from the edge vectors that region_energy left in p.in.
Eigen::Matrix<double, 6, 6> triangle_hessian(const Problem& p, std::size_t t, bool project) {
    const std::size_t n = p.triangles;
    const auto in = [&](std::size_t row) { return p.in[row * n + t]; };
    const double a0 = in(Problem::a0), a1 = in(Problem::a1), b0 = in(Problem::b0), b1 = in(Problem::b1);
    const double g00 = in(Problem::g00), g01 = in(Problem::g01), g10 = in(Problem::g10), g11 = in(Problem::g11);
    const Matrix4 h =
        energy_hessian(a0 * g00 + b0 * g10, a0 * g01 + b0 * g11, a1 * g00 + b1 * g10, a1 * g01 + b1 * g11, project);
    // J = [a b] G with a = u1 - u0, b = u2 - u0: entry (r, col) of J is component r of the
    // corners weighted by coef[col] (u0, u1, u2), so each block of h over (r, r') maps to one
    // 3 x 3 block over the corners.
    const double coef[2][3] = {{-(g00 + g10), g00, g10}, {-(g01 + g11), g01, g11}};
    const double area = in(Problem::area);
    Eigen::Matrix<double, 6, 6> out;
    for (int r = 0; r < 2; ++r)
        for (int r2 = 0; r2 < 2; ++r2)
            for (int k = 0; k < 3; ++k)
                for (int k2 = 0; k2 < 3; ++k2) {
                    double sum = 0.0;
                    for (int col = 0; col < 2; ++col)
                        for (int col2 = 0; col2 < 2; ++col2)
                            sum += coef[col][k] * coef[col2][k2] * h(2 * r + col, 2 * r2 + col2);
                    out(2 * k + r, 2 * k2 + r2) = area * sum;
                }
    return out;
}

/// The region's Hessian: its pattern (the lower triangle, over the free unknowns) made once, and
/// per triangle where each of its 36 entries goes among the matrix's values (-1: nowhere).
class Hessian {
public:
    explicit Hessian(const Problem& p)
        : p_(p), matrix_(static_cast<Eigen::Index>(p.unknowns), static_cast<Eigen::Index>(p.unknowns)) {
        std::vector<Eigen::Triplet<double>> pattern;
        const auto free = static_cast<int>(p.unknowns);
        for (std::size_t t = 0; t < p.triangles; ++t) {
            const CornerUnknowns u = corner_unknowns(p, t);
            for (int i = 0; i < 6; ++i)
                for (int j = 0; j < 6; ++j)
                    if (u.index[i] < free && u.index[j] < free && u.index[i] >= u.index[j])
                        pattern.emplace_back(u.index[i], u.index[j], 0.0);
        }
        matrix_.setFromTriplets(pattern.begin(), pattern.end());
        matrix_.makeCompressed();
        slot_.assign(36 * p.triangles, -1);
        for (std::size_t t = 0; t < p.triangles; ++t) {
            const CornerUnknowns u = corner_unknowns(p, t);
            for (int i = 0; i < 6; ++i)
                for (int j = 0; j < 6; ++j)
                    if (u.index[i] < free && u.index[j] < free && u.index[i] >= u.index[j])
                        slot_[36 * t + 6 * i + j] = slot_of(u.index[i], u.index[j]);
        }
    }

    /// The matrix with the pattern only (every value zero), for the symbolic analysis.
    const Eigen::SparseMatrix<double>& pattern() const { return matrix_; }

    /// The matrix at the point region_energy last evaluated.
    const Eigen::SparseMatrix<double>& at(bool project) {
        double* values = matrix_.valuePtr();
        std::fill(values, values + matrix_.nonZeros(), 0.0);
        for (std::size_t t = 0; t < p_.triangles; ++t) {
            const Eigen::Matrix<double, 6, 6> h = triangle_hessian(p_, t, project);
            const CornerUnknowns u = corner_unknowns(p_, t);
            for (int i = 0; i < 6; ++i)
                for (int j = 0; j < 6; ++j)
                    if (const int s = slot_[36 * t + 6 * i + j]; s >= 0) values[s] += u.sign[i] * u.sign[j] * h(i, j);
        }
        return matrix_;
    }

private:
    int slot_of(int row, int col) const {
        const int* inner = matrix_.innerIndexPtr();
        const int* begin = inner + matrix_.outerIndexPtr()[col];
        const int* end = inner + matrix_.outerIndexPtr()[col + 1];
        return static_cast<int>(std::lower_bound(begin, end, row) - inner);
    }

    const Problem& p_;
    Eigen::SparseMatrix<double> matrix_; ///< column-major: column col holds rows >= col
    std::vector<int> slot_;
};

} // namespace

struct NewtonSystem::Parts {
    explicit Parts(const Problem& p) : hessian(p) {
        // The region's pattern, the same at every step: the analysis reads no value.
        if (p.unknowns > 0) solver.analyzePattern(hessian.pattern());
    }
    Hessian hessian;
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower> solver;
};

NewtonSystem::NewtonSystem(const Problem& p) : parts_(std::make_unique<Parts>(p)) {}
NewtonSystem::~NewtonSystem() = default;

int minimise_newton(const Problem& p, std::vector<double>& x, int iterations) {
    if (p.unknowns == 0) return 0;
    NewtonSystem system(p);
    return minimise_newton(p, x, iterations, system);
}

int minimise_newton(const Problem& p, std::vector<double>& x, int iterations, NewtonSystem& system) {
    const auto n = static_cast<Eigen::Index>(p.unknowns);
    if (n == 0) return 0;
    std::vector<double> g, g_new, x_new(x.size());
    double f = region_energy(p, x, 0.0, &g);
    if (!std::isfinite(f)) return 0;
    Hessian& hessian = system.parts().hessian;
    auto& solver = system.parts().solver;
    bool full_step = true;                    // the last step was Newton's whole step
    int it = 0;
    for (; it < iterations; ++it) {
        // The true Hessian where the sum is positive definite (near the minimum: quadratic
        // convergence), else each triangle's projected (a descent direction anywhere).
        bool factorized = false;
        for (const bool project : {false, true}) {
            if (!project && !full_step) continue; // far from the minimum: the true one fails
            solver.factorize(hessian.at(project));
            factorized = solver.info() == Eigen::Success && (solver.vectorD().array() > 0.0).all();
            if (factorized) break;
        }
        if (!factorized) break;
        const Eigen::Map<const Eigen::VectorXd> grad(g.data(), n);
        const Eigen::VectorXd d = -solver.solve(grad);
        const double slope = grad.dot(d);
        if (!(slope < 0) || -slope <= kDecrement * std::abs(f)) break;
        bool accepted = false;
        for (double step = 1.0; step > 1e-12 && !accepted; step *= 0.5) {
            for (Eigen::Index i = 0; i < n; ++i) x_new[i] = x[i] + step * d[i];
            const double f_new = region_energy(p, x_new, 0.0, &g_new);
            if (std::isfinite(f_new) && f_new <= f + 1e-4 * step * slope) {
                accepted = true;
                full_step = step == 1.0;
                f = f_new;
            }
        }
        // The last evaluation was at the accepted point: p.in holds its edge vectors.
        if (!accepted) break;
        x.swap(x_new), g.swap(g_new);
        // Near the minimum a whole step squares the decrement: after one from below kSettled,
        // the next steps would move the vertices by far less than positions need.
        if (full_step && -slope <= kSettled * std::abs(f)) break;
    }
    return it;
}

} // namespace qex::detail::repair_impl

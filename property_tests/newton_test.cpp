// The repair's Newton solver: one triangle's Hessian against finite differences of its energy
// (written here on its own), and the projection onto the positive semi-definite matrices.
#include "extract/repair/newton.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include <array>
#include <cmath>
#include <random>

namespace qex::detail::repair_impl {
namespace {

/// f(J) = w |J|^2 / d + q d + q / d, with w = q = 1/2 (the repair's weights).
double energy(const std::array<double, 4>& j) {
    const double d = j[0] * j[3] - j[1] * j[2];
    const double frob = j[0] * j[0] + j[1] * j[1] + j[2] * j[2] + j[3] * j[3];
    return 0.5 * frob / d + 0.5 * d + 0.5 / d;
}

/// The Hessian by central differences of the energy.
Eigen::Matrix4d numeric_hessian(const std::array<double, 4>& j, double h) {
    Eigen::Matrix4d out;
    for (int a = 0; a < 4; ++a)
        for (int b = 0; b < 4; ++b) {
            auto at = [&](double da, double db) {
                std::array<double, 4> x = j;
                x[a] += da, x[b] += db;
                return energy(x);
            };
            out(a, b) = (at(h, h) - at(h, -h) - at(-h, h) + at(-h, -h)) / (4 * h * h);
        }
    return out;
}

/// Jacobians with a positive determinant, some near the identity, some far from it.
std::vector<std::array<double, 4>> jacobians() {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-2.0, 2.0);
    std::vector<std::array<double, 4>> out{{1, 0, 0, 1}, {2, 0.3, -0.1, 0.5}, {0.2, 1.5, -1.1, 0.4}};
    while (out.size() < 40) {
        const std::array<double, 4> j{u(rng), u(rng), u(rng), u(rng)};
        if (j[0] * j[3] - j[1] * j[2] > 0.05) out.push_back(j);
    }
    return out;
}

TEST(NewtonSolver, HessianMatchesFiniteDifferences) {
    for (const auto& j : jacobians()) {
        const Eigen::Matrix4d exact = energy_hessian(j[0], j[1], j[2], j[3], false);
        const Eigen::Matrix4d numeric = numeric_hessian(j, 1e-4);
        EXPECT_LT((exact - numeric).norm(), 1e-4 * (1.0 + exact.norm()))
            << "J = (" << j[0] << ", " << j[1] << ", " << j[2] << ", " << j[3] << ")\n"
            << exact << "\nagainst\n"
            << numeric;
    }
}

TEST(NewtonSolver, ProjectionIsPositiveSemiDefiniteAndKeepsADefiniteHessian) {
    int indefinite = 0;
    for (const auto& j : jacobians()) {
        const Eigen::Matrix4d h = energy_hessian(j[0], j[1], j[2], j[3], false);
        const Eigen::Matrix4d p = energy_hessian(j[0], j[1], j[2], j[3], true);
        const Eigen::Vector4d before = Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d>(h).eigenvalues();
        const Eigen::Vector4d after = Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d>(p).eigenvalues();
        EXPECT_GE(after.minCoeff(), -1e-9 * (1.0 + h.norm()));
        if (before.minCoeff() > 0) {
            EXPECT_LT((p - h).norm(), 1e-12 * h.norm()); // nothing to project
        } else {
            ++indefinite;
            EXPECT_GT((p - h).norm(), 0.0);
        }
    }
    EXPECT_GT(indefinite, 0) << "the sample should hold Jacobians whose Hessian is indefinite";
}

} // namespace
} // namespace qex::detail::repair_impl

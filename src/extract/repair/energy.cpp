// The repair's energy: rest shapes, the problem over a region's free vertices, and the energy
// that penalises inverted triangles through a regularised determinant (energy.h).
#include "extract/repair/energy.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace qex::detail::repair_impl {
namespace {

/// The energy's weight on area (det^2 + 1) against shape (|J|^2), both over the regularised det.
constexpr double kAreaWeight = 0.5;

/// The energy of one triangle with corner UVs u0, u1, u2 (corners base, next, prev, in the
/// triangle's chart); with `grad`, adds its gradient with respect to the three corners.
double triangle_energy(const Vec2& u0, const Vec2& u1, const Vec2& u2, const RestShape& s, double eps,
                       std::array<Vec2, 3>* grad) {
    const double a0 = u1[0] - u0[0], a1 = u1[1] - u0[1], b0 = u2[0] - u0[0], b1 = u2[1] - u0[1];
    const double j00 = a0 * s.g00 + b0 * s.g10, j01 = a0 * s.g01 + b0 * s.g11;
    const double j10 = a1 * s.g00 + b1 * s.g10, j11 = a1 * s.g01 + b1 * s.g11;
    const double det = j00 * j11 - j01 * j10;
    const double frob = j00 * j00 + j01 * j01 + j10 * j10 + j11 * j11;
    const double r = std::sqrt(eps * eps + det * det);
    const double c = chi_with(det, eps, r);
    constexpr double theta = kAreaWeight;
    const double num = (1 - theta) * frob + theta * (det * det + 1.0);
    const double energy = s.area * num / c;
    if (grad) {
        const double dchi = 0.5 * (1.0 + det / r);
        // dE/dJ = (2 J + 2 det cof J) / chi - num chi' / chi^2 cof J, cof J = [[j11, -j10], [-j01, j00]].
        const double k = num * dchi / (c * c);
        const double w = 1 - theta, q = theta;
        const double d00 = (2 * w * j00 + 2 * q * det * j11) / c - k * j11,
                     d01 = (2 * w * j01 - 2 * q * det * j10) / c + k * j10;
        const double d10 = (2 * w * j10 - 2 * q * det * j01) / c + k * j01,
                     d11 = (2 * w * j11 + 2 * q * det * j00) / c - k * j00;
        // dE/d[a b] = area * dE/dJ * G^T.
        const Vec2 da{s.area * (d00 * s.g00 + d01 * s.g01), s.area * (d10 * s.g00 + d11 * s.g01)};
        const Vec2 db{s.area * (d00 * s.g10 + d01 * s.g11), s.area * (d10 * s.g10 + d11 * s.g11)};
        (*grad)[0][0] -= da[0] + db[0];
        (*grad)[0][1] -= da[1] + db[1];
        (*grad)[1][0] += da[0];
        (*grad)[1][1] += da[1];
        (*grad)[2][0] += db[0];
        (*grad)[2][1] += db[1];
    }
    return energy;
}

/// The corner a triangle's rest shape starts at: its smallest 3D position (then UV), so that
/// the input's corner order does not matter.
int canonical_base(const TriMesh& m, int f) {
    int base = 3 * f;
    for (int c = 3 * f + 1; c < 3 * f + 3; ++c)
        if (m.pos(c) != m.pos(base) ? m.pos(c) < m.pos(base) : m.uv[c] < m.uv[base]) base = c;
    return base;
}

} // namespace

std::vector<double> region_point(const TriMesh& m, const Region& r, double& length) {
    std::vector<double> x(2 * r.fans.size());
    length = 0.0;
    for (std::size_t i = 0; i < r.fans.size(); ++i) {
        x[2 * i] = m.uv[r.fans[i].corners[0]][0];
        x[2 * i + 1] = m.uv[r.fans[i].corners[0]][1];
        length += r.fans[i].length;
    }
    length /= static_cast<double>(r.fans.size());
    return x;
}

bool rest_shapes(const TriMesh& m, const Region& r, std::vector<RestShape>& rest) {
    double uv_area = 0.0, area3 = 0.0;
    std::vector<std::array<double, 4>> shape(r.faces.size()); // r1x, r2x, r2y, 3D area
    for (std::size_t i = 0; i < r.faces.size(); ++i) {
        const int f = r.faces[i];
        const int base = canonical_base(m, f);
        rest[static_cast<std::size_t>(f)].base = base;
        const auto &p0 = m.pos(base), &p1 = m.pos(TriMesh::next(base)), &p2 = m.pos(TriMesh::prev(base));
        const std::array<double, 3> e1{p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]};
        const std::array<double, 3> e2{p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]};
        const std::array<double, 3> cr{e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                                       e1[0] * e2[1] - e1[1] * e2[0]};
        const double l1 = std::sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
        const double twice = std::sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]);
        const double l2sq = e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2];
        if (l1 > 0 && twice > 1e-6 * (l1 * l1 + l2sq))
            shape[i] = {l1, (e1[0] * e2[0] + e1[1] * e2[1] + e1[2] * e2[2]) / l1, twice / l1, 0.5 * twice};
        else
            shape[i] = {0, 0, 0, 0}; // degenerate in 3D: an equilateral rest shape below
        area3 += shape[i][3];
        // From the canonical base too: the rounding must not depend on the input's corner order.
        const Vec2 &a = m.uv[base], &b = m.uv[TriMesh::next(base)], &c = m.uv[TriMesh::prev(base)];
        uv_area += 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
    }
    if (!(uv_area > 0)) return false;
    const double mean_uv = uv_area / static_cast<double>(r.faces.size());
    const double scale = area3 > 0 ? std::sqrt(uv_area / area3) : 1.0;
    for (std::size_t i = 0; i < r.faces.size(); ++i) {
        auto s = shape[i];
        if (s[3] > 0) {
            s = {s[0] * scale, s[1] * scale, s[2] * scale, s[3] * scale * scale};
        } else {
            const double side = std::sqrt(4.0 * mean_uv / std::sqrt(3.0));
            s = {side, 0.5 * side, 0.5 * std::sqrt(3.0) * side, mean_uv};
        }
        // Reference edge matrix [[r1x, r2x], [0, r2y]] and its inverse.
        RestShape& rs = rest[static_cast<std::size_t>(r.faces[i])];
        rs.g00 = 1.0 / s[0];
        rs.g01 = -s[1] / (s[0] * s[2]);
        rs.g10 = 0.0;
        rs.g11 = 1.0 / s[2];
        rs.area = s[3];
    }
    return true;
}

Problem make_problem(const TriMesh& m, const Region& r, const std::vector<RestShape>& rest,
                     std::vector<int>& corner_slot, std::vector<GridAutomorphism>& corner_to,
                     const std::vector<int>& barrier) {
    Problem p;
    for (std::size_t i = 0; i < r.fans.size(); ++i)
        for (std::size_t k = 0; k < r.fans[i].corners.size(); ++k) {
            corner_slot[r.fans[i].corners[k]] = static_cast<int>(i);
            corner_to[r.fans[i].corners[k]] = r.fans[i].to_c[k];
        }
    p.corners.resize(r.faces.size());
    for (std::size_t t = 0; t < r.faces.size(); ++t) {
        const int b = rest[static_cast<std::size_t>(r.faces[t])].base;
        const int order[3] = {b, TriMesh::next(b), TriMesh::prev(b)};
        for (int k = 0; k < 3; ++k) {
            Problem::Corner& c = p.corners[t][k];
            c.slot = corner_slot[order[k]];
            if (c.slot >= 0) c.to = corner_to[order[k]];
            c.fixed = m.uv[order[k]];
        }
    }
    for (const FreeFan& fan : r.fans)
        for (const int c : fan.corners) corner_slot[c] = -1;
    p.unknowns = 2 * r.fans.size();
    p.barrier.assign(r.faces.size(), 0);
    for (std::size_t t = 0; t < r.faces.size() && !barrier.empty(); ++t)
        p.barrier[t] = std::binary_search(barrier.begin(), barrier.end(), r.faces[t]);
    return p;
}

double region_energy(const Problem& p, const Region& r, const std::vector<RestShape>& rest,
                     const std::vector<double>& x, double eps, std::vector<double>* grad, double* lowest) {
    if (grad) grad->assign(p.unknowns, 0.0);
    double energy = 0.0;
    if (lowest) *lowest = std::numeric_limits<double>::infinity();
    for (std::size_t t = 0; t < p.corners.size(); ++t) {
        const RestShape& s = rest[static_cast<std::size_t>(r.faces[t])];
        std::array<Vec2, 3> u;
        for (int k = 0; k < 3; ++k) {
            const Problem::Corner& c = p.corners[t][k];
            u[k] = c.slot < 0 ? c.fixed : c.to(Vec2{x[2 * c.slot], x[2 * c.slot + 1]});
        }
        if (lowest) {
            const double d = ((u[1][0] - u[0][0]) * (u[2][1] - u[0][1]) - (u[1][1] - u[0][1]) * (u[2][0] - u[0][0])) *
                             (s.g00 * s.g11 - s.g01 * s.g10);
            *lowest = std::min(*lowest, d);
        }
        double e = eps;
        if (p.barrier[t]) {
            // Never inverted at a start (the caller's), and not to be inverted by a step.
            const double twice = (u[1][0] - u[0][0]) * (u[2][1] - u[0][1]) - (u[1][1] - u[0][1]) * (u[2][0] - u[0][0]);
            if (!(twice > 0.0)) return std::numeric_limits<double>::infinity();
            e = 0.0;
        }
        if (!grad) {
            energy += triangle_energy(u[0], u[1], u[2], s, e, nullptr);
            continue;
        }
        std::array<Vec2, 3> g{};
        energy += triangle_energy(u[0], u[1], u[2], s, e, &g);
        for (int k = 0; k < 3; ++k) {
            const Problem::Corner& c = p.corners[t][k];
            if (c.slot < 0) continue;
            const Vec2 back = GridAutomorphism::rotate(g[k], (4 - c.to.r) & 3);
            (*grad)[2 * c.slot] += back[0];
            (*grad)[2 * c.slot + 1] += back[1];
        }
    }
    return energy;
}

} // namespace qex::detail::repair_impl

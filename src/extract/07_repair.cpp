// Stage repair: certified re-embedding of fold-over regions (not in the paper, whose handling of
// fold-overs is local and assumes a fold covers a small part of a cell).
//
// A region is a connected set of free vertices (interior, regular, off the features) near
// flipped or degenerate triangles; its triangles are those around its free vertices, and its
// other vertices (singular, boundary, feature, or outside) stay fixed. The free vertices move to
// minimise an energy that penalises inverted triangles through a regularised determinant, the
// regularisation shrinking as the triangles untangle (the foldover-free energy of Garanzha et
// al. 2021, minimised here with L-BFGS over the region's free vertices). Each vertex lives in the
// chart of one of its corners and is written to the others through the exact transitions after
// truncation (as sanitize does), so transitions and singularities are untouched. A region is
// attempted only when its fixed vertices leave room for an embedding (their angles,
// Gauss-Bonnet), and counts as repaired only when every one of its triangles is positively
// oriented by the exact predicate and every vertex winds as it must (positive triangles can
// still wind twice round a vertex while a singularity beside it is a turn short); otherwise its
// UVs are restored bit for bit, it grows, and it is tried again, up to a budget. What the
// untangler leaves inverted is moved vertex by vertex into the kernel of its link where it has
// one. Where the untangler wound a region wrongly round its singularities, the region is tried
// once more from its given UVs, with the fans of the singularities that wind short there opened
// (laid out over their angles) and kept open by a barrier.
//
// The one change to transitions and singularities: before the regions are grown, co-located
// dipoles (two singularities of opposite index on one grid point, which no fold-free map allows)
// are merged into regular vertices, each merge named in the report and undone unless the repair
// re-embeds it.
#include "pipeline.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>
#include <unordered_map>

namespace qex::detail {
namespace {

// ============================================================================ budget

/// Ring radii around the fold-overs, one attempt each.
constexpr int kRingRadii[] = {1, 2, 4, 8};
/// Regularisation steps per attempt, and L-BFGS iterations per step.
constexpr int kOuterIterations = 60;
constexpr int kInnerIterations = 80;
/// The first regularisation, relative to the most negative Jacobian determinant.
constexpr double kInitialRegularisation = 0.1;
/// The energy's weight on area (det^2 + 1) against shape (|J|^2), both over the regularised det.
constexpr double kAreaWeight = 0.5;
/// An attempt stops once this many regularisation steps in a row leave more triangles inverted
/// than its best step did.
constexpr int kStagnation = 8;
/// Larger regions are not attempted (their repair would cost more than the extraction).
constexpr std::size_t kMaxRegionVertices = std::size_t{1} << 17;

// ============================================================================ the energy

/// A triangle's rest shape: the inverse of its reference edge matrix (columns r1 - r0, r2 - r0)
/// and its reference area; corners in the order base, next, prev.
struct RestShape {
    double g00, g01, g10, g11;
    double area;
    int base; ///< corner the triangle's Jacobian starts at (canonical: smallest 3D position)
};

using Vec2 = std::array<double, 2>;

/// chi(D, eps) = (D + sqrt(eps^2 + D^2)) / 2, without cancellation for D < 0.
double chi(double d, double eps) {
    const double r = std::sqrt(eps * eps + d * d);
    return d >= 0 ? 0.5 * (d + r) : 0.5 * eps * eps / (r - d);
}

/// The energy of one triangle with corner UVs u0, u1, u2 (corners base, next, prev, in the
/// triangle's chart); with `grad`, adds its gradient with respect to the three corners.
double triangle_energy(const Vec2& u0, const Vec2& u1, const Vec2& u2, const RestShape& s, double eps,
                       std::array<Vec2, 3>* grad) {
    const double a0 = u1[0] - u0[0], a1 = u1[1] - u0[1], b0 = u2[0] - u0[0], b1 = u2[1] - u0[1];
    const double j00 = a0 * s.g00 + b0 * s.g10, j01 = a0 * s.g01 + b0 * s.g11;
    const double j10 = a1 * s.g00 + b1 * s.g10, j11 = a1 * s.g01 + b1 * s.g11;
    const double det = j00 * j11 - j01 * j10;
    const double frob = j00 * j00 + j01 * j01 + j10 * j10 + j11 * j11;
    const double c = chi(det, eps);
    constexpr double theta = kAreaWeight;
    const double num = (1 - theta) * frob + theta * (det * det + 1.0);
    const double energy = s.area * num / c;
    if (grad) {
        const double r = std::sqrt(eps * eps + det * det);
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

bool positive(const TriMesh& m, int f) { return sign(orient2d(m.uv[3 * f], m.uv[3 * f + 1], m.uv[3 * f + 2])) > 0; }

// ============================================================================ a free vertex

/// A free vertex's fan, starting at a canonical corner (so the sums below do not depend on the
/// input's order), with the transitions from the first corner's chart to each corner's.
struct FreeFan {
    int vertex = -1;
    std::vector<int> corners;
    std::vector<GridAutomorphism> to_c;
    double length = 1.0; ///< mean UV edge length around the vertex, the scale of its steps
};

FreeFan free_fan(const TriMesh& m, int v) {
    FreeFan fan;
    fan.vertex = v;
    // Started at the canonical corner sanitize starts the fan at too (the vertex is interior).
    walk_fan_corners(m, v, true, fan.corners, fan.to_c);
    const std::vector<int>& walk = fan.corners;
    const std::size_t n = walk.size();
    double sum = 0.0;
    for (const int c : walk) {
        const Vec2 &p = m.uv[c], &q = m.uv[TriMesh::next(c)];
        sum += std::hypot(q[0] - p[0], q[1] - p[1]);
    }
    fan.length = sum / static_cast<double>(n);
    return fan;
}

/// The corners of interior vertex v's fan, clockwise from the one whose next and previous
/// corners have the smallest 3D positions: an order that depends neither on the input's order
/// nor on its charts.
std::vector<int> fan_in_3d_order(const TriMesh& m, int v) {
    std::vector<int> fan;
    for (int h = m.fan_start[v], n = 0; h >= 0 && n < m.fan_size[v]; h = m.cw(h), ++n) fan.push_back(h);
    const auto first = std::min_element(fan.begin(), fan.end(), [&](int a, int b) {
        if (m.pos(TriMesh::next(a)) != m.pos(TriMesh::next(b)))
            return m.pos(TriMesh::next(a)) < m.pos(TriMesh::next(b));
        return m.pos(TriMesh::prev(a)) < m.pos(TriMesh::prev(b));
    });
    std::rotate(fan.begin(), first, fan.end());
    return fan;
}

/// Writes x (in the fan's first chart), truncated so that it propagates exactly, to every corner;
/// with a unit of headroom, so that the map times a power of two k, plus an integer point below
/// k, stays exact too (coarsening splits its mesh back onto that map).
void place(TriMesh& m, const FreeFan& fan, const Vec2& x) {
    const Vec2 t = truncated_for_fan(m, fan.corners, fan.to_c, x, 1.0);
    for (std::size_t i = 0; i < fan.corners.size(); ++i) m.uv[fan.corners[i]] = fan.to_c[i](t);
}

// ============================================================================ a region

struct Region {
    std::vector<FreeFan> fans; ///< canonical order
    std::vector<int> faces;    ///< canonical order (sort_canonically)
};

std::vector<Point2> region_uvs(const TriMesh& m, const Region& r) {
    std::vector<Point2> uvs;
    for (const FreeFan& fan : r.fans)
        for (const int c : fan.corners) uvs.push_back(m.uv[c]);
    return uvs;
}

void restore_region_uvs(TriMesh& m, const Region& r, const std::vector<Point2>& uvs) {
    std::size_t i = 0;
    for (const FreeFan& fan : r.fans)
        for (const int c : fan.corners) m.uv[c] = uvs[i++];
}

/// The free vertices' UVs in their first charts (the unknowns), and their mean edge length.
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

/// The corner a triangle's rest shape starts at: its smallest 3D position (then UV), so that
/// the input's corner order does not matter.
int canonical_base(const TriMesh& m, int f) {
    int base = 3 * f;
    for (int c = 3 * f + 1; c < 3 * f + 3; ++c)
        if (m.pos(c) != m.pos(base) ? m.pos(c) < m.pos(base) : m.uv[c] < m.uv[base]) base = c;
    return base;
}

/// Triangles in an order that does not depend on the input's: by their corners' 3D positions
/// from the canonical base on.
void sort_canonically(const TriMesh& m, std::vector<int>& faces) {
    std::vector<std::pair<TriangleKey, int>> keyed;
    keyed.reserve(faces.size());
    for (const int f : faces) keyed.push_back({triangle_key(m, f), f});
    std::sort(keyed.begin(), keyed.end());
    for (std::size_t i = 0; i < faces.size(); ++i) faces[i] = keyed[i].second;
}

/// Rest shapes of the region's triangles, scaled so that their total area is the region's
/// signed UV area (which the repair keeps). False when that area is not positive: no
/// orientation-preserving embedding with this boundary exists.
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

/// The signed angle at u in the triangle (u, p, w), from the edge to p to the edge to w: in
/// (0, pi) when the triangle is positive. A flat corner (u inside the opposite side) is half a
/// turn in every chart: atan2 would give -pi or pi by the sign of a zero.
double signed_angle(const Vec2& u, const Vec2& p, const Vec2& w) {
    const double ax = p[0] - u[0], ay = p[1] - u[1], bx = w[0] - u[0], by = w[1] - u[1];
    const double cross = ax * by - ay * bx, dot = ax * bx + ay * by;
    if (cross == 0.0) return dot < 0.0 ? M_PI : 0.0;
    return std::atan2(cross, dot);
}

/// The region's energy at x, and with `grad` its gradient; `lowest`: the smallest Jacobian
/// determinant.
double region_energy(const Problem& p, const Region& r, const std::vector<RestShape>& rest,
                     const std::vector<double>& x, double eps, std::vector<double>* grad, double* lowest = nullptr) {
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

double dot(const std::vector<double>& a, const std::vector<double>& b) {
    double s = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) s += a[i] * b[i];
    return s;
}

/// Minimises the region's energy for a fixed eps from x (L-BFGS, Armijo backtracking).
void minimise(const Problem& p, const Region& r, const std::vector<RestShape>& rest, std::vector<double>& x, double eps,
              double length, int iterations, double stall = 1e-12) {
    constexpr std::size_t kHistory = 8;
    std::vector<std::vector<double>> ss, ys;
    std::vector<double> rho;
    std::vector<double> g, g_new, d(x.size()), x_new(x.size());
    double f = region_energy(p, r, rest, x, eps, &g);
    for (int it = 0; it < iterations && std::isfinite(f); ++it) {
        // Two-loop recursion: d = -H g.
        for (std::size_t i = 0; i < x.size(); ++i) d[i] = -g[i];
        std::vector<double> alpha(ss.size());
        for (std::size_t j = ss.size(); j-- > 0;) {
            alpha[j] = rho[j] * dot(ss[j], d);
            for (std::size_t i = 0; i < d.size(); ++i) d[i] -= alpha[j] * ys[j][i];
        }
        if (!ss.empty()) {
            const double gamma = dot(ss.back(), ys.back()) / dot(ys.back(), ys.back());
            for (double& v : d) v *= gamma;
        } else {
            const double norm = std::sqrt(dot(d, d));
            if (!(norm > 0)) return;
            for (double& v : d) v *= 0.1 * length / norm;
        }
        for (std::size_t j = 0; j < ss.size(); ++j) {
            const double beta = rho[j] * dot(ys[j], d);
            for (std::size_t i = 0; i < d.size(); ++i) d[i] += (alpha[j] - beta) * ss[j][i];
        }
        double slope = dot(g, d);
        if (!(slope < 0)) { // not a descent direction: restart from the gradient
            ss.clear(), ys.clear(), rho.clear();
            const double norm = std::sqrt(dot(g, g));
            if (!(norm > 0)) return;
            for (std::size_t i = 0; i < d.size(); ++i) d[i] = -g[i] * 0.1 * length / norm;
            slope = dot(g, d);
        }
        double step = 1.0, f_new = f;
        bool accepted = false;
        for (int ls = 0; ls < 40; ++ls, step *= 0.5) {
            for (std::size_t i = 0; i < x.size(); ++i) x_new[i] = x[i] + step * d[i];
            f_new = region_energy(p, r, rest, x_new, eps, &g_new);
            if (std::isfinite(f_new) && f_new <= f + 1e-4 * step * slope) {
                accepted = true;
                break;
            }
        }
        if (!accepted) return;
        std::vector<double> s_k(x.size()), y_k(x.size());
        for (std::size_t i = 0; i < x.size(); ++i) s_k[i] = x_new[i] - x[i], y_k[i] = g_new[i] - g[i];
        const double sy = dot(s_k, y_k);
        if (sy > 1e-300) {
            if (ss.size() == kHistory) ss.erase(ss.begin()), ys.erase(ys.begin()), rho.erase(rho.begin());
            ss.push_back(std::move(s_k)), ys.push_back(std::move(y_k)), rho.push_back(1.0 / sy);
        }
        const bool stalled = f - f_new <= stall * std::abs(f);
        x.swap(x_new), g.swap(g_new), f = f_new;
        if (stalled) return;
    }
}

/// Moves a free vertex into the kernel of its link (where every triangle round it is positive),
/// at the kernel's centroid, in its first chart: the half-planes left of each opposite edge,
/// clipped from a box round the link. True when it moved and the exact predicate finds its fan
/// positive; otherwise its UVs are as before.
bool place_in_kernel(TriMesh& m, const FreeFan& fan) {
    std::vector<std::array<Vec2, 2>> edges;
    double lo0 = std::numeric_limits<double>::infinity(), lo1 = lo0, hi0 = -lo0, hi1 = -lo0;
    for (std::size_t k = 0; k < fan.corners.size(); ++k) {
        const GridAutomorphism back = fan.to_c[k].inverse();
        const int c = fan.corners[k];
        const Vec2 a = back(m.uv[TriMesh::next(c)]), b = back(m.uv[TriMesh::prev(c)]);
        edges.push_back({a, b});
        for (const Vec2& q : {a, b})
            lo0 = std::min(lo0, q[0]), hi0 = std::max(hi0, q[0]), lo1 = std::min(lo1, q[1]), hi1 = std::max(hi1, q[1]);
    }
    if (!(hi0 >= lo0 && hi1 >= lo1)) return false;
    std::vector<Vec2> poly{{lo0, lo1}, {hi0, lo1}, {hi0, hi1}, {lo0, hi1}}, next;
    for (const auto& edge : edges) {
        const Vec2 &a = edge[0], &b = edge[1]; // named, not bound: clang 14 cannot capture bindings
        const auto side = [&](const Vec2& q) { return (b[0] - a[0]) * (q[1] - a[1]) - (b[1] - a[1]) * (q[0] - a[0]); };
        next.clear();
        for (std::size_t i = 0; i < poly.size(); ++i) {
            const Vec2 &u = poly[i], &w = poly[(i + 1) % poly.size()];
            const double su = side(u), sw = side(w);
            if (su >= 0) next.push_back(u);
            if ((su >= 0) != (sw >= 0)) {
                const double t = su / (su - sw);
                next.push_back({u[0] + t * (w[0] - u[0]), u[1] + t * (w[1] - u[1])});
            }
        }
        poly.swap(next);
        if (poly.size() < 3) return false;
    }
    double area = 0.0, cx = 0.0, cy = 0.0;
    for (std::size_t i = 0; i < poly.size(); ++i) {
        const Vec2 &u = poly[i], &w = poly[(i + 1) % poly.size()];
        const double cross = u[0] * w[1] - w[0] * u[1];
        area += cross, cx += (u[0] + w[0]) * cross, cy += (u[1] + w[1]) * cross;
    }
    if (!(area > 0.0)) return false;
    std::vector<Point2> before;
    for (const int c : fan.corners) before.push_back(m.uv[c]);
    place(m, fan, {cx / (3.0 * area), cy / (3.0 * area)});
    bool all = true;
    for (const int c : fan.corners) all = all && positive(m, TriMesh::face(c));
    if (all) return true;
    for (std::size_t k = 0; k < fan.corners.size(); ++k) m.uv[fan.corners[k]] = before[k];
    return false;
}

/// What the untangler left inverted, vertex by vertex: each free vertex of an inverted triangle
/// is moved into the kernel of its link where it has one, for a few sweeps (in the region's
/// canonical order). True when the region is then positive.
bool kernel_sweeps(TriMesh& m, const Region& r) {
    for (int sweep = 0; sweep < 4; ++sweep) {
        bool any = false, moved = false;
        for (const FreeFan& fan : r.fans) {
            bool bad = false;
            for (const int c : fan.corners) bad = bad || !positive(m, TriMesh::face(c));
            if (!bad) continue;
            any = true;
            moved = place_in_kernel(m, fan) || moved;
        }
        if (!any) return true;
        if (!moved) return false;
    }
    for (const int f : r.faces)
        if (!positive(m, f)) return false;
    return true;
}

/// Untangles the region in place; true when every triangle of it is positively oriented.
bool untangle_region(TriMesh& m, const Region& r, std::vector<RestShape>& rest, std::vector<int>& corner_slot,
                     std::vector<GridAutomorphism>& corner_to, const std::vector<int>& barrier = {}) {
    if (!rest_shapes(m, r, rest)) return false;
    const Problem p = make_problem(m, r, rest, corner_slot, corner_to, barrier);
    double length = 0.0;
    std::vector<double> x = region_point(m, r, length);
    double lowest = 0.0;
    region_energy(p, r, rest, x, 1.0, nullptr, &lowest);
    double eps = std::max(1e-3, kInitialRegularisation * std::abs(lowest));
    std::size_t best = SIZE_MAX;
    for (int outer = 0, since_best = 0; outer < kOuterIterations && since_best < kStagnation; ++outer) {
        const double before = region_energy(p, r, rest, x, eps, nullptr);
        minimise(p, r, rest, x, eps, length, kInnerIterations);
        // Place (truncated, propagated exactly) and judge exactly.
        for (std::size_t i = 0; i < r.fans.size(); ++i) {
            place(m, r.fans[i], {x[2 * i], x[2 * i + 1]});
            x[2 * i] = m.uv[r.fans[i].corners[0]][0];
            x[2 * i + 1] = m.uv[r.fans[i].corners[0]][1];
        }
        std::size_t inverted = 0;
        for (const int f : r.faces) inverted += !positive(m, f);
        if (inverted == 0) return true;
        if (inverted < best)
            best = inverted, since_best = 0;
        else
            ++since_best;
        const double after = region_energy(p, r, rest, x, eps, nullptr, &lowest);
        const double sigma = std::max(1.0 - after / before, 0.1);
        const double mu = (1.0 - sigma) * chi(lowest, eps);
        eps = lowest < mu ? std::max(2.0 * std::sqrt(mu * (mu - lowest)), 1e-13) : 1e-13;
    }
    return kernel_sweeps(m, r);
}

/// The canonical key of a vertex: its smallest corner position in 3D, then its input index.
struct VertexKey {
    std::array<double, 3> pos;
    int input;
    bool operator<(const VertexKey& o) const { return pos != o.pos ? pos < o.pos : input < o.input; }
};

VertexKey vertex_key(const TriMesh& m, int v) {
    VertexKey k{m.pos(m.fan_start[v]), m.input_vertex[v]};
    for (int h = m.fan_start[v], n = 0; h >= 0 && n < m.fan_size[v]; h = m.cw(h), ++n)
        if (m.pos(h) < k.pos) k.pos = m.pos(h);
    return k;
}

// ============================================================================ the winding certificate

/// The signed angle at corner h of its triangle (from the edge to its next corner to the edge to
/// its previous one): in (0, pi) when the triangle is positive.
double corner_angle(const TriMesh& m, int h) {
    return signed_angle(m.uv[h], m.uv[TriMesh::next(h)], m.uv[TriMesh::prev(h)]);
}

/// The angle an interior vertex's fan sums to in an embedding of the map: a full turn, or a
/// singularity's valence in quarter turns.
double target_angle(const TriMesh& m, int v) {
    return m.map.singular[v] ? m.map.valence[v] * (0.5 * M_PI) : 2.0 * M_PI;
}

/// What the certificate needs of a region: its triangles and free vertices marked, and its
/// fixed vertices (sorted).
struct RegionMarks {
    std::vector<char> face;   ///< per triangle
    std::vector<char> vertex; ///< per vertex: 1 free in the region, 2 fixed in it
    std::vector<int> fixed;
    /// A singularity whose angle Gauss-Bonnet fixes otherwise than Algorithm 8 counted it (the
    /// fold took whole turns from its fan without flipping any), and that angle.
    int cone = -1;
    double cone_angle = 0.0;
    /// Set when the rim winds round the region's one singularity otherwise than its angle
    /// (admits_embedding): that singularity, and the angle the rim turns about it.
    int rim_cone = -1;
    double rim_angle = 0.0;

    /// What v's angles sum to in an embedding of the region's map.
    double target(const TriMesh& m, int v) const { return v == cone ? cone_angle : target_angle(m, v); }

    void mark(const TriMesh& m, const Region& r) {
        for (const int f : r.faces) face[f] = 1;
        for (const FreeFan& fan : r.fans) vertex[fan.vertex] = 1;
        for (const int f : r.faces)
            for (const int v : m.tri[f])
                if (!vertex[v]) vertex[v] = 2, fixed.push_back(v);
        std::sort(fixed.begin(), fixed.end());
    }
    void clear(const Region& r) {
        for (const int f : r.faces) face[f] = 0;
        for (const FreeFan& fan : r.fans) vertex[fan.vertex] = 0;
        for (const int v : fixed) vertex[v] = 0;
        fixed.clear();
        cone = rim_cone = -1;
    }
};

/// Sums the signed angles at v's corners, inside the region and outside it.
void fan_angles(const TriMesh& m, int v, const RegionMarks& marks, double& inside, double& outside, int& corners) {
    inside = outside = 0.0;
    corners = 0;
    for (int h = m.fan_start[v], n = 0; h >= 0 && n < m.fan_size[v]; h = m.cw(h), ++n) {
        if (marks.face[TriMesh::face(h)])
            inside += corner_angle(m, h), ++corners;
        else
            outside += corner_angle(m, h);
    }
}

/// The angle the rim of region r turns about `cone`, the one singular vertex inside it: the sum,
/// over the rim's edges, of the angle each subtends at the cone's grid point, in the chart of the
/// edge's triangle (the grid point carried there through the region's transitions, which turn
/// about it and fix it). False where the sum would prove nothing: the region is not a disk
/// (Euler characteristic 1), or a rim edge passes through the grid point or nearly so.
bool rim_angle_about(const TriMesh& m, const Region& r, const RegionMarks& marks, int cone, double& angle) {
    std::unordered_map<int, std::size_t> local; // region triangle -> index into `at`
    for (std::size_t t = 0; t < r.faces.size(); ++t) local[r.faces[t]] = t;
    const auto in_region = [&](int h) { return h >= 0 && marks.face[TriMesh::face(h)] != 0; };
    // The grid point in each triangle's chart, breadth-first from a triangle of the cone's fan.
    std::vector<Point2> at(r.faces.size());
    std::vector<char> seen(r.faces.size(), 0);
    const int start = m.fan_start[cone];
    if (!in_region(start)) return false;
    std::vector<int> queue{TriMesh::face(start)};
    at[local[queue[0]]] = m.uv[start];
    seen[local[queue[0]]] = 1;
    std::size_t rim = 0;
    for (std::size_t i = 0; i < queue.size(); ++i) {
        const int f = queue[i];
        for (int k = 0; k < 3; ++k) {
            const int h = 3 * f + k, o = m.opp[h];
            if (!in_region(o)) {
                ++rim;
                continue;
            }
            const std::size_t j = local[TriMesh::face(o)];
            if (seen[j]) continue;
            seen[j] = 1;
            at[j] = m.map.transition[h](at[local[f]]);
            queue.push_back(TriMesh::face(o));
        }
    }
    const auto faces = static_cast<std::int64_t>(r.faces.size());
    const auto vertices = static_cast<std::int64_t>(r.fans.size() + marks.fixed.size());
    const auto edges = (3 * faces + static_cast<std::int64_t>(rim)) / 2;
    if (queue.size() != r.faces.size() || vertices - edges + faces != 1) return false;
    angle = 0.0;
    for (const int f : r.faces)
        for (int k = 0; k < 3; ++k) {
            const int h = 3 * f + k;
            if (in_region(m.opp[h])) continue;
            const Point2& p = at[local[f]];
            const double ax = m.uv[h][0] - p[0], ay = m.uv[h][1] - p[1];
            const double bx = m.uv[TriMesh::next(h)][0] - p[0], by = m.uv[TriMesh::next(h)][1] - p[1];
            // On the grid point, or so near it that rounding could turn the edge's angle by a turn.
            const double near = 0x1p-30 * std::max({1.0, std::abs(p[0]), std::abs(p[1])});
            if (std::hypot(ax, ay) < near || std::hypot(bx, by) < near) return false;
            const double turn = std::atan2(ax * by - ay * bx, ax * bx + ay * by);
            if (!(std::abs(turn) < M_PI - 1e-3)) return false;
            angle += turn;
        }
    return true;
}

/// Whether the rim of a region that is a disk leaves room for its one singularity (of valence 3,
/// or 5 and more; `marks.rim_cone` is set when it does not). In an orientation-preserving map
/// that keeps every winding, the singularity is the only point of the region at its grid point
/// (any other would be the centre of a full turn, which the cone's angle does not divide), so the
/// rim turns about it by exactly its angle. A solver that rounded a singularity onto a grid point
/// the map round it does not wind about leaves the rim a whole turn short, on every ring out to
/// where other singularities take part: no re-embedding of such a region exists, and the
/// untangler is not run on it.
bool rim_leaves_room(const TriMesh& m, const Region& r, RegionMarks& marks) {
    int cone = -1;
    for (const int v : marks.fixed) {
        if (!m.map.singular[v]) continue;
        double inside = 0.0, outside = 0.0;
        int corners = 0;
        fan_angles(m, v, marks, inside, outside, corners);
        if (corners < m.fan_size[v]) continue; // on the rim
        if (cone >= 0) return true;            // two inside: no such proof
        cone = v;
    }
    if (cone < 0) return true;
    const double target = marks.target(m, cone);
    if (!(target > 1.25 * M_PI) || std::abs(target - 2.0 * M_PI) < 0.25 * M_PI) return true;
    double angle = 0.0;
    if (!rim_angle_about(m, r, marks, cone, angle)) return true;
    // The transitions round the rim turn by the singularity's angle, so the rim's angle differs
    // from it by whole turns; a sum that does not proves nothing.
    const double turns = std::nearbyint((angle - target) / (2.0 * M_PI));
    if (turns == 0.0 || !(std::abs(angle - target - 2.0 * M_PI * turns) < 0.25)) return true;
    marks.rim_cone = cone;
    marks.rim_angle = angle;
    return false;
}

/// Whether the region's fixed data leave room for an orientation-preserving re-embedding. In one,
/// every interior vertex's angles sum to its target (a full turn, or a singularity's), so a fixed
/// vertex leaves the region its target less its fixed triangles' angles, which must lie between
/// 0 and pi per region corner; and the angles of the region's triangles sum to pi each. Where
/// these fail, no motion of the free vertices helps: the fold reaches past the region's
/// boundary (its boundary winds wrongly), and the region must grow. A region that touches the
/// mesh's boundary is judged by the first test only. When the sum misses whole turns, they are
/// those of singularities inside the region: Algorithm 8 counts a turn only for a flipped run of
/// a fan, and a fold can take one without flipping any (Figure 2 (d), the fan squeezed). With one
/// singularity inside, the turns are its own, and the region is admitted with its angle
/// corrected.
bool admits_embedding(const TriMesh& m, const Region& r, bool valences_given, RegionMarks& marks) {
    double sum = 2.0 * M_PI * static_cast<double>(r.fans.size());
    bool open = false;
    for (const int v : marks.fixed) {
        if (m.on_boundary[v]) {
            open = true;
            continue;
        }
        double inside = 0.0, outside = 0.0;
        int corners = 0;
        fan_angles(m, v, marks, inside, outside, corners);
        const double left = marks.target(m, v) - outside;
        if (!(left > 0.0 && left < M_PI * corners)) return false;
        sum += left;
    }
    const double missing = M_PI * static_cast<double>(r.faces.size()) - sum;
    if (open) return true;
    if (std::abs(missing) < 1.0) return rim_leaves_room(m, r, marks);
    if (valences_given) return false; // the user's valences stand
    // Whole turns missing: they belong to singularities inside the region (Algorithm 8 finds no
    // flipped run in a fan squeezed by the fold, Figure 2 (d)).
    std::vector<int> inner;
    for (const int v : marks.fixed) {
        double inside = 0.0, outside = 0.0;
        int corners = 0;
        fan_angles(m, v, marks, inside, outside, corners);
        // Only singularities whose transitions turn: a branch point's turns are its own business.
        if (corners == m.fan_size[v] && m.map.singular[v] && ((m.map.winding_valence[v] % 4) + 4) % 4 != 0)
            inner.push_back(v);
    }
    const double turns = std::nearbyint(missing / (2.0 * M_PI));
    if (std::abs(missing - 2.0 * M_PI * turns) >= 1.0) return false;
    // One singularity inside: the turns are its own. With several, which of them lack the turns
    // is not known (giving one each to those counted below valence 3 admitted regions of up to
    // 3,400 free vertices that did not untangle, and cost fertility_miq_5 8 s).
    if (inner.size() != 1) return false;
    const double angle = target_angle(m, inner[0]) + 2.0 * M_PI * turns;
    if (!(angle > 1.0 && angle < M_PI * m.fan_size[inner[0]])) return false;
    marks.cone = inner[0];
    marks.cone_angle = angle;
    return rim_leaves_room(m, r, marks);
}

/// Whether every interior vertex of the region (all its triangles positive) winds by its
/// target: positive triangles alone can still wind twice round a vertex (a branch point the
/// map does not have) or leave a singularity a turn short.
bool windings_kept(const TriMesh& m, const Region& r, const RegionMarks& marks) {
    auto kept = [&](int v) {
        if (m.on_boundary[v]) return true;
        double inside = 0.0, outside = 0.0;
        int corners = 0;
        fan_angles(m, v, marks, inside, outside, corners);
        return std::abs(inside + outside - marks.target(m, v)) < 1.0;
    };
    for (const FreeFan& fan : r.fans)
        if (!kept(fan.vertex)) return false;
    for (const int v : marks.fixed)
        if (!kept(v)) return false;
    return true;
}

/// Iterations of the final minimisation of a repaired region.
constexpr int kPolishIterations = 2000;
/// It stops when an iteration lowers the energy by less than this fraction of it.
constexpr double kPolishStall = 1e-15;

/// A repaired region (every triangle positive) relaxed to the minimum of its energy with no
/// regularisation: a pure barrier, so no triangle can invert and no vertex's winding change.
/// Where the untangler stops (the first iterate with nothing inverted) depends on rounding, so
/// an integer translation or a re-charting of the map would move the result; the minimum does
/// not. Kept only if the exact predicate still finds every triangle positive after placement,
/// and every vertex still winds as it must.
void polish_region(TriMesh& m, const Region& r, std::vector<RestShape>& rest, std::vector<int>& corner_slot,
                   std::vector<GridAutomorphism>& corner_to, const RegionMarks& marks) {
    if (!rest_shapes(m, r, rest)) return;
    const Problem p = make_problem(m, r, rest, corner_slot, corner_to, {});
    const std::vector<Point2> before = region_uvs(m, r);
    double length = 0.0;
    std::vector<double> x = region_point(m, r, length);
    minimise(p, r, rest, x, 0.0, length, kPolishIterations, kPolishStall);
    for (std::size_t i = 0; i < r.fans.size(); ++i) place(m, r.fans[i], {x[2 * i], x[2 * i + 1]});
    bool all = true;
    for (const int f : r.faces) all = all && positive(m, f);
    // A line-search step is discrete: a triangle could pass through zero and back within one.
    if (!(all && windings_kept(m, r, marks))) restore_region_uvs(m, r, before);
}

// ============================================================================ opening a cone's fan

/// By how many whole turns v's fan winds past its target (0 for a boundary vertex).
int winding_excess(const TriMesh& m, int v, const RegionMarks& marks) {
    if (m.on_boundary[v]) return 0;
    double inside = 0.0, outside = 0.0;
    int corners = 0;
    fan_angles(m, v, marks, inside, outside, corners);
    const double turns = (inside + outside - marks.target(m, v)) / (2.0 * M_PI);
    return std::isfinite(turns) ? static_cast<int>(std::lround(turns)) : 0;
}

/// A singularity whose fan a fold closed: one run of flipped or degenerate triangles (or none, the
/// fan squeezed), which the untangler tends to open by winding a neighbour twice instead (the
/// cone then a turn short). Lays the run's inner rim vertices (all free; the run grown by
/// positive triangles beside it) out evenly, clockwise from the run's first rim vertex, over the
/// angle that the cone's target leaves the run, each at its distance from the cone. The cone's
/// fan is then positive and winds by its target, and its triangles are added to `barrier` (the
/// untangler keeps them positive, so the cone keeps its winding). False for a fan with several
/// runs, a fixed inner rim vertex, or no room for the run (its angle not between 0 and pi per
/// triangle), with nothing moved; or, after moving, when the cone still does not wind by its
/// target (the caller restores the UVs it had before).
bool open_cone_fan(TriMesh& m, const Region& r, const RegionMarks& marks,
                   const std::unordered_map<int, std::size_t>& slot, int cone, std::vector<int>& barrier) {
    // From a canonical corner: the sums and the choices below depend neither on the input's
    // order nor on its charts.
    std::vector<int> fan = fan_in_3d_order(m, cone);
    const std::size_t n = fan.size();
    std::size_t start = n;
    for (std::size_t i = 0; i < n && start == n; ++i)
        if (positive(m, TriMesh::face(fan[i]))) start = i;
    if (start == n) return false;
    std::rotate(fan.begin(), fan.begin() + static_cast<std::ptrdiff_t>(start), fan.end());
    std::size_t first = n, length = 0;
    int runs = 0;
    double kept = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        const bool bad = !positive(m, TriMesh::face(fan[i]));
        if (!bad) {
            kept += corner_angle(m, fan[i]);
            continue;
        }
        if (i == 0 || positive(m, TriMesh::face(fan[i - 1]))) ++runs, first = i;
        ++length;
    }
    if (runs > 1) return false;
    if (runs == 0) { // a squeezed fan, all positive (Figure 2 (d)): all but its first triangle open
        first = 1;
        length = n - 1;
        kept = corner_angle(m, fan[0]);
    }
    // The run takes in positive triangles beside it, alternately after and before it, until it
    // has at most a quarter turn per triangle (a run of one cannot open by more than half a
    // turn, and near-flat triangles are a poor start).
    double span = marks.target(m, cone) - kept;
    for (bool after = true; span > 0.5 * M_PI * static_cast<double>(length) && length + 1 < n; after = !after) {
        if (after && first + length < n) {
            span += corner_angle(m, fan[first + length]);
        } else if (first > 0) {
            span += corner_angle(m, fan[--first]);
        } else {
            span += corner_angle(m, fan[first + length]);
        }
        ++length;
    }
    if (length < 2 || !(span > 0.0 && span < M_PI * static_cast<double>(length))) return false;
    // In the chart of the run's first triangle: the cone, and the direction of its first rim vertex.
    int h = fan[first];
    const Vec2 c = m.uv[h], p = m.uv[TriMesh::prev(h)];
    const double phi = std::atan2(p[1] - c[1], p[0] - c[0]);
    GridAutomorphism to_h; // the first triangle's chart -> h's
    std::vector<std::pair<std::size_t, Vec2>> moves;
    for (std::size_t i = 1; i < length; ++i) {
        const int rim = TriMesh::next(h);
        const auto it = slot.find(m.origin(rim));
        if (it == slot.end()) return false;
        const double radius = std::hypot(m.uv[rim][0] - m.uv[h][0], m.uv[rim][1] - m.uv[h][1]);
        const double angle = phi - span * static_cast<double>(i) / static_cast<double>(length);
        const Vec2 at = to_h(Vec2{c[0] + radius * std::cos(angle), c[1] + radius * std::sin(angle)});
        const FreeFan& f = r.fans[it->second];
        const auto k = static_cast<std::size_t>(std::find(f.corners.begin(), f.corners.end(), rim) - f.corners.begin());
        moves.push_back({it->second, f.to_c[k].inverse()(at)});
        to_h = m.map.transition[h].after(to_h);
        h = m.cw(h);
    }
    for (const auto& [i, x] : moves) place(m, r.fans[i], x);
    if (winding_excess(m, cone, marks) != 0) return false;
    for (const int c : fan) barrier.push_back(TriMesh::face(c));
    return true;
}

/// After an untangling that failed: the region again from its given UVs (`before`), with the fans
/// of its singularities that wind short of their targets there (a run of flipped triangles, or a
/// squeezed fan) opened and kept open. True when that is certified.
bool untangle_with_open_cones(TriMesh& m, const Region& r, const RegionMarks& marks, const std::vector<Point2>& before,
                              std::vector<RestShape>& rest, std::vector<int>& corner_slot,
                              std::vector<GridAutomorphism>& corner_to) {
    restore_region_uvs(m, r, before);
    std::vector<int> short_cones;
    for (const int v : marks.fixed)
        if (m.map.singular[v] && !m.on_boundary[v] && winding_excess(m, v, marks) < 0) short_cones.push_back(v);
    if (short_cones.empty()) return false;
    // Neighbouring cones may share rim vertices: opened in an order that does not depend on the input's.
    std::sort(short_cones.begin(), short_cones.end(),
              [&](int a, int b) { return vertex_key(m, a) < vertex_key(m, b); });
    std::unordered_map<int, std::size_t> slot;
    for (std::size_t k = 0; k < r.fans.size(); ++k) slot[r.fans[k].vertex] = k;
    // Each cone is opened on top of the ones before it, and kept only if every barrier triangle
    // so far is still positive and every cone opened so far still winds by its target (cones
    // can share rim vertices): the barrier must start positive.
    std::vector<int> barrier, opened;
    for (const int cone : short_cones) {
        const std::vector<Point2> snapshot = region_uvs(m, r);
        const std::size_t kept = barrier.size();
        bool ok = open_cone_fan(m, r, marks, slot, cone, barrier);
        for (std::size_t k = 0; ok && k < barrier.size(); ++k) ok = positive(m, barrier[k]);
        for (std::size_t k = 0; ok && k < opened.size(); ++k) ok = winding_excess(m, opened[k], marks) == 0;
        if (ok) {
            opened.push_back(cone);
            continue;
        }
        barrier.resize(kept);
        restore_region_uvs(m, r, snapshot);
    }
    std::sort(barrier.begin(), barrier.end());
    barrier.erase(std::unique(barrier.begin(), barrier.end()), barrier.end());
    return !barrier.empty() && untangle_region(m, r, rest, corner_slot, corner_to, barrier) &&
           windings_kept(m, r, marks);
}

// ============================================================================ why a region failed

/// What the last attempt at a region found, for the report of the fold-overs it leaves.
struct RegionFailure {
    enum class Why : std::uint8_t { TooLarge, AreaNotPositive, NoRoom, RimShort, Inverted, Winding };
    Why why = Why::NoRoom;
    int radius = 0;
    std::size_t free_vertices = 0, triangles = 0;
    int singularities = 0; ///< fixed singular vertices whose whole fan is in the region
    int inverted = 0;      ///< Inverted: triangles left inverted, the first (by input index) of them
    int triangle = -1;
    int vertex = -1; ///< Winding: the input vertex that winds wrongly, its winding and target
    int winds = 0, target = 0;
    bool singular = false;

    std::string text() const {
        const std::string where = "within " + std::to_string(radius) + " rings (a region of " +
                                  std::to_string(free_vertices) + " free vertices, " + std::to_string(triangles) +
                                  " triangles, " + std::to_string(singularities) + " singularities inside):";
        switch (why) {
            case Why::TooLarge: return where + " the region is larger than the repair attempts";
            case Why::AreaNotPositive:
                return where +
                       " the region's signed UV area is not positive: no orientation-preserving map of it "
                       "exists";
            case Why::NoRoom:
                return where +
                       " the angles its fixed vertices leave the region admit no embedding (Gauss-Bonnet, or "
                       "whole turns missing among several singularities)";
            case Why::RimShort:
                return where + " its rim turns " + std::to_string(winds) +
                       " quarter turns about the grid point of input vertex " + std::to_string(vertex) +
                       " (a singularity of valence " + std::to_string(target) +
                       ", which needs as many): with the singularity at its grid point, no fold-free map of "
                       "the region exists";
            case Why::Inverted:
                return where + " the untangler left " + std::to_string(inverted) +
                       " of its triangles inverted (the first: input triangle " + std::to_string(triangle) + ")";
            case Why::Winding:
                if (vertex < 0)
                    return where + " every triangle was made positive, but a vertex winds otherwise than it must";
                return where + " every triangle was made positive, but input vertex " + std::to_string(vertex) +
                       (singular ? " (a singularity of valence " + std::to_string(target) + ")"
                                 : " (a regular vertex, 4 quarter turns)") +
                       " winds " + std::to_string(winds) + " quarter turns";
        }
        return where;
    }
};

/// Why an attempt at region r failed (`admitted`: it passed admits_embedding), from its UVs as
/// the attempt left them (the first one: the open-cone retry starts again from the given UVs).
RegionFailure describe_failure(const TriMesh& m, const Region& r, const RegionMarks& marks, bool admitted, int radius) {
    RegionFailure f;
    f.radius = radius;
    f.free_vertices = r.fans.size();
    f.triangles = r.faces.size();
    for (const int v : marks.fixed) {
        double inside = 0.0, outside = 0.0;
        int corners = 0;
        fan_angles(m, v, marks, inside, outside, corners);
        f.singularities += m.map.singular[v] && !m.on_boundary[v] && corners == m.fan_size[v];
    }
    double area2 = 0.0;
    for (const int t : r.faces) {
        const Vec2 &a = m.uv[3 * t], &b = m.uv[3 * t + 1], &c = m.uv[3 * t + 2];
        area2 += (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        if (!positive(m, t)) {
            ++f.inverted;
            if (f.triangle < 0 || m.input_triangle[t] < f.triangle) f.triangle = m.input_triangle[t];
        }
    }
    if (!(area2 > 0.0)) {
        f.why = RegionFailure::Why::AreaNotPositive;
    } else if (!admitted && marks.rim_cone >= 0) {
        f.why = RegionFailure::Why::RimShort;
        f.vertex = m.input_vertex[marks.rim_cone];
        f.singular = true;
        f.winds = static_cast<int>(std::lround(marks.rim_angle / (0.5 * M_PI)));
        f.target = static_cast<int>(std::lround(marks.target(m, marks.rim_cone) / (0.5 * M_PI)));
    } else if (!admitted) {
        f.why = RegionFailure::Why::NoRoom;
    } else if (f.inverted > 0) {
        f.why = RegionFailure::Why::Inverted;
    } else {
        f.why = RegionFailure::Why::Winding;
        // The first vertex (free ones in the region's canonical order, then fixed ones) that
        // winds otherwise than it must.
        std::vector<int> order;
        for (const FreeFan& fan : r.fans) order.push_back(fan.vertex);
        order.insert(order.end(), marks.fixed.begin(), marks.fixed.end());
        for (const int v : order) {
            if (m.on_boundary[v] || winding_excess(m, v, marks) == 0) continue;
            double inside = 0.0, outside = 0.0;
            int corners = 0;
            fan_angles(m, v, marks, inside, outside, corners);
            f.vertex = m.input_vertex[v];
            f.singular = m.map.singular[v] != 0;
            f.winds = static_cast<int>(std::lround((inside + outside) / (0.5 * M_PI)));
            f.target = static_cast<int>(std::lround(marks.target(m, v) / (0.5 * M_PI)));
            break;
        }
    }
    return f;
}

// ============================================================================ regions

/// Vertices that never move: boundary, singular, on a feature edge, or without a fan.
std::vector<char> pinned_vertices(const TriMesh& m, const std::vector<std::array<int, 2>>& feature_edges) {
    std::vector<char> pinned(static_cast<std::size_t>(m.num_vertices), 0);
    for (int v = 0; v < m.num_vertices; ++v) pinned[v] = m.fan_start[v] < 0 || m.on_boundary[v] || m.map.singular[v];
    if (!feature_edges.empty()) {
        std::vector<char> on_feature;
        for (const auto& fe : feature_edges)
            for (const int x : fe)
                if (x >= 0) {
                    if (static_cast<std::size_t>(x) >= on_feature.size()) on_feature.resize(x + 1, 0);
                    on_feature[static_cast<std::size_t>(x)] = 1;
                }
        for (int v = 0; v < m.num_vertices; ++v) {
            const auto iv = static_cast<std::size_t>(m.input_vertex[v]);
            if (iv < on_feature.size() && on_feature[iv]) pinned[v] = 1;
        }
    }
    return pinned;
}

/// The vertices within `radius` edges of the seeds (breadth first over the fans).
std::vector<int> ring_neighbourhood(const TriMesh& m, const std::vector<int>& seeds, int radius,
                                    std::vector<int>& distance) {
    std::vector<int> reached;
    for (const int v : seeds)
        if (distance[v] < 0) distance[v] = 0, reached.push_back(v);
    for (std::size_t i = 0; i < reached.size(); ++i) {
        const int v = reached[i];
        if (distance[v] >= radius) continue;
        for (int h = m.fan_start[v], n = 0; h >= 0 && n < m.fan_size[v]; ++n) {
            for (const int w : {m.target(h), m.origin(TriMesh::prev(h))})
                if (distance[w] < 0) distance[w] = distance[v] + 1, reached.push_back(w);
            h = m.cw(h);
        }
    }
    for (const int v : reached) distance[v] = -1;
    return reached;
}

/// Splits the free vertices into regions: connected through shared triangles.
std::vector<Region> split_regions(const TriMesh& m, const std::vector<int>& free, std::vector<int>& label) {
    std::vector<Region> regions;
    for (const int v : free) label[v] = -2; // free, unassigned
    for (const int start : free) {
        if (label[start] != -2) continue;
        const int id = static_cast<int>(regions.size());
        regions.emplace_back();
        std::vector<int> stack{start}, members;
        label[start] = id;
        while (!stack.empty()) {
            const int v = stack.back();
            stack.pop_back();
            members.push_back(v);
            for (int h = m.fan_start[v], n = 0; h >= 0 && n < m.fan_size[v]; h = m.cw(h), ++n)
                for (const int w : {m.target(h), m.origin(TriMesh::prev(h))})
                    if (label[w] == -2) label[w] = id, stack.push_back(w);
        }
        std::vector<std::pair<VertexKey, int>> keyed;
        for (const int v : members) keyed.push_back({vertex_key(m, v), v});
        std::sort(keyed.begin(), keyed.end());
        Region& r = regions.back();
        for (const auto& kv : keyed) {
            r.fans.push_back(free_fan(m, kv.second));
            for (const int c : r.fans.back().corners) r.faces.push_back(TriMesh::face(c));
        }
        std::sort(r.faces.begin(), r.faces.end());
        r.faces.erase(std::unique(r.faces.begin(), r.faces.end()), r.faces.end());
        sort_canonically(m, r.faces);
    }
    for (const int v : free) label[v] = -1;
    return regions;
}

// ============================================================================ co-located dipoles

/// Most edges between the two singularities of a co-located dipole.
constexpr int kDipoleReach = 8;

/// A pair of singularities merged into regular vertices: the path of half-edges between them
/// (each from a vertex to the next) and their transitions before the merge.
struct DipoleMerge {
    int a = -1, b = -1;
    std::vector<int> path;
    std::vector<GridAutomorphism> old;
    std::array<int, 2> valences{0, 0}, winding_valences{0, 0};
};

/// The composition of v's fan transitions, walked clockwise from corner `start` round to it:
/// maps start's chart to itself.
GridAutomorphism fan_holonomy(const TriMesh& m, int start) {
    GridAutomorphism g;
    int h = start;
    for (int n = 0; n < m.fan_size[m.origin(start)]; ++n) {
        g = m.map.transition[h].after(g);
        h = m.cw(h);
        if (h < 0) break;
    }
    return g;
}

/// Whether v is an interior singularity next to a flipped or degenerate triangle.
bool folded_singularity(const TriMesh& m, int v) {
    if (!m.map.singular[v] || m.on_boundary[v] || m.fan_start[v] < 0) return false;
    for (int h = m.fan_start[v], n = 0; h >= 0 && n < m.fan_size[v]; h = m.cw(h), ++n)
        if (!positive(m, TriMesh::face(h))) return true;
    return false;
}

/// Two singularities of opposite turns whose valences sum to two regular vertices' (5 and 3, 6
/// and 2), on one grid point when charted along a short path of regular vertices between them:
/// no injective map keeps both, as the path would have zero length. Solver rounding makes
/// them, snapping a dipole's two cones onto one grid point with a fold between them. The paper
/// lets fold-overs spanning singularities merge them (Section 7, Figure 6); here the merge is
/// explicit: the path's transitions are changed so that both become regular (each vertex on
/// the path keeps its fan closed), and the repair then re-embeds the region as a disk. Found
/// breadth first from `a` over `pinned`-free vertices; true with the path in `merge`.
bool find_colocated_dipole(const TriMesh& m, int a, const std::vector<char>& pinned, DipoleMerge& merge) {
    const int ta = fan_turn(m, a);
    if (ta <= 0) return false;
    // From a canonical corner of a's fan, so that the path found depends neither on the input's
    // order nor on its charts: every other vertex's fan is walked from the corner it is reached by.
    const int first = fan_in_3d_order(m, a)[0];
    const Point2 ua = m.uv[first];
    // Per reached vertex: the half-edge from its parent and its depth; per queued vertex, the
    // corner it was reached by and the map from a's chart to that corner's.
    std::unordered_map<int, std::pair<int, int>> parent;
    std::vector<std::pair<int, GridAutomorphism>> queue{{first, GridAutomorphism{}}};
    parent[a] = {-1, 0};
    for (std::size_t q = 0; q < queue.size(); ++q) {
        const int start = queue[q].first;
        const int w = m.origin(start);
        const int depth = parent[w].second;
        if (depth >= kDipoleReach) continue;
        GridAutomorphism g = queue[q].second;
        for (int h = start, n = 0; h >= 0 && n < m.fan_size[w]; ++n) {
            const int c = TriMesh::next(h), x = m.origin(c);
            if (!parent.count(x)) {
                parent[x] = {h, depth + 1};
                if (m.map.singular[x] && !m.on_boundary[x] && x != a) {
                    const int tx = fan_turn(m, x);
                    if (tx > 0 && ((ta + tx) & 3) == 0 && m.map.valence[a] + m.map.valence[x] == 8 &&
                        g.inverse()(m.uv[c]) == ua) {
                        merge.a = a, merge.b = x;
                        merge.valences = {m.map.valence[a], m.map.valence[x]};
                        merge.winding_valences = {m.map.winding_valence[a], m.map.winding_valence[x]};
                        for (int y = x; y != a; y = m.origin(parent[y].first)) merge.path.push_back(parent[y].first);
                        std::reverse(merge.path.begin(), merge.path.end());
                        return true;
                    }
                } else if (!pinned[x]) {
                    queue.push_back({c, g});
                }
            }
            g = m.map.transition[h].after(g);
            h = m.cw(h);
        }
    }
    return false;
}

/// The path's transitions as they were before merge_dipole (its edges are distinct: any order).
void restore_path_transitions(TriMesh& m, const DipoleMerge& merge) {
    for (std::size_t i = 0; i < merge.old.size(); ++i) {
        m.map.transition.set(static_cast<std::size_t>(merge.path[i]), merge.old[i]);
        m.map.transition.set(static_cast<std::size_t>(m.opp[merge.path[i]]), merge.old[i].inverse());
    }
}

/// Changes the path's transitions so that every fan along it closes: a's, each regular vertex's
/// on the way, and (the pair being a dipole on one grid point) b's. False, with nothing changed,
/// when b's does not.
bool merge_dipole(TriMesh& m, DipoleMerge& merge) {
    for (const int e : merge.path) {
        merge.old.push_back(m.map.transition[e]);
        const GridAutomorphism fixed = fan_holonomy(m, m.cw(e)).inverse().after(m.map.transition[e]);
        m.map.transition.set(static_cast<std::size_t>(e), fixed);
        m.map.transition.set(static_cast<std::size_t>(m.opp[e]), fixed.inverse());
    }
    bool closed = true;
    for (const int e : merge.path) closed = closed && fan_holonomy(m, e).is_identity();
    closed = closed && fan_holonomy(m, m.opp[merge.path.back()]).is_identity();
    if (!closed) {
        restore_path_transitions(m, merge);
        return false;
    }
    for (const int v : {merge.a, merge.b}) {
        m.map.singular[v] = 0;
        m.map.valence[v] = m.map.winding_valence[v] = 4;
    }
    return true;
}

/// Whether the re-embedding made the path's UVs agree with its new transitions (every fan along
/// it was re-embedded); otherwise the merge is undone.
bool dipole_embedded(const TriMesh& m, const DipoleMerge& merge) {
    for (const int e : merge.path) {
        const GridAutomorphism& g = m.map.transition[e];
        const int o = m.opp[e];
        if (g(m.uv[e]) != m.uv[TriMesh::next(o)] || g(m.uv[TriMesh::next(e)]) != m.uv[o]) return false;
    }
    return true;
}

void unmerge_dipole(TriMesh& m, const DipoleMerge& merge) {
    restore_path_transitions(m, merge);
    m.map.singular[merge.a] = m.map.singular[merge.b] = 1;
    m.map.valence[merge.a] = merge.valences[0];
    m.map.valence[merge.b] = merge.valences[1];
    m.map.winding_valence[merge.a] = merge.winding_valences[0];
    m.map.winding_valence[merge.b] = merge.winding_valences[1];
}

/// The flipped or degenerate triangles, split into those with a free vertex (seeds of the
/// repair) and those whose corners are all pinned (no repair can change them).
void bad_triangles(const TriMesh& m, const std::vector<char>& pinned, std::vector<int>& repairable,
                   std::vector<int>& stuck) {
    repairable.clear();
    stuck.clear();
    for (int f = 0; f < m.num_faces(); ++f)
        if (!positive(m, f)) {
            const auto& t = m.tri[f];
            (pinned[t[0]] && pinned[t[1]] && pinned[t[2]] ? stuck : repairable).push_back(f);
        }
}

/// Connected groups (through shared vertices) of the given triangles, for the report.
std::vector<std::vector<int>> triangle_groups(const TriMesh& m, const std::vector<int>& faces) {
    std::vector<int> parent(faces.size());
    std::iota(parent.begin(), parent.end(), 0);
    auto find = [&](int x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    };
    std::vector<int> owner(static_cast<std::size_t>(m.num_vertices), -1);
    for (std::size_t i = 0; i < faces.size(); ++i)
        for (const int v : m.tri[faces[i]]) {
            if (owner[v] >= 0) parent[find(static_cast<int>(i))] = find(owner[v]);
            owner[v] = static_cast<int>(i);
        }
    std::vector<std::vector<int>> groups;
    std::vector<int> group_of(faces.size(), -1);
    for (std::size_t i = 0; i < faces.size(); ++i) {
        const int root = find(static_cast<int>(i));
        if (group_of[root] < 0) group_of[root] = static_cast<int>(groups.size()), groups.emplace_back();
        groups[group_of[root]].push_back(faces[i]);
    }
    return groups;
}

} // namespace

void explain_unrepaired(const TriMesh& m, const RepairOutcome& outcome, Report& report) {
    for (const RepairOutcome::Unrepaired& u : outcome.unrepaired) {
        int first = m.input_triangle[u.triangles[0]];
        double area = 0.0;
        for (const int f : u.triangles) {
            first = std::min(first, m.input_triangle[f]);
            const Vec2 &a = m.uv[3 * f], &b = m.uv[3 * f + 1], &c = m.uv[3 * f + 2];
            area += 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
        }
        report.explanations.push_back({DefectKind::FoldOverNotRepaired,
                                       "a fold-over of " + std::to_string(u.triangles.size()) +
                                           " flipped or degenerate triangles (UV area " + std::to_string(area) +
                                           ", from input triangle " + std::to_string(first) +
                                           ") stays as the map gives it: " + u.why,
                                       first,
                                       -1,
                                       {0, 0},
                                       std::nullopt});
    }
}

RepairOutcome repair(TriMesh& m, const std::vector<std::array<int, 2>>& feature_edges, bool valences_given,
                     Report& report) {
    RepairOutcome out;
    std::vector<int> seeds_faces, stuck;
    std::vector<char> pinned = pinned_vertices(m, feature_edges);
    bad_triangles(m, pinned, seeds_faces, stuck);
    if (seeds_faces.empty() && stuck.empty()) return out;
    // Co-located dipoles next to the fold-overs are merged first (their vertices become free),
    // in an order that does not depend on the input's; not against the user's valences.
    std::vector<DipoleMerge> merges;
    if (!valences_given) {
        std::vector<std::pair<VertexKey, int>> cones;
        for (int v = 0; v < m.num_vertices; ++v)
            if (folded_singularity(m, v)) cones.push_back({vertex_key(m, v), v});
        std::sort(cones.begin(), cones.end());
        for (const auto& kv : cones) {
            DipoleMerge d;
            if (m.map.singular[kv.second] && find_colocated_dipole(m, kv.second, pinned, d) && merge_dipole(m, d))
                merges.push_back(std::move(d));
        }
    }
    if (!merges.empty()) { // merged vertices are free now
        pinned = pinned_vertices(m, feature_edges);
        bad_triangles(m, pinned, seeds_faces, stuck);
    }
    // A merge stands only if every vertex of its path was re-embedded by a certified region.
    std::vector<char> reembedded(static_cast<std::size_t>(m.num_vertices), 0);
    const auto merge_reembedded = [&](const DipoleMerge& d) {
        bool all = reembedded[d.b] != 0;
        for (const int e : d.path) all = all && reembedded[m.origin(e)];
        return all && dipole_embedded(m, d);
    };
    const std::vector<Point2> sanitized = m.uv;
    std::vector<RestShape> rest(static_cast<std::size_t>(m.num_faces()));
    std::vector<int> distance(static_cast<std::size_t>(m.num_vertices), -1), label(distance.size(), -1);
    std::vector<int> corner_slot(3 * static_cast<std::size_t>(m.num_faces()), -1);
    std::vector<GridAutomorphism> corner_to(corner_slot.size());
    // Per free vertex, the last failed attempt at a region that held it (an index into failures).
    std::vector<RegionFailure> failures;
    std::vector<int> failure_of(static_cast<std::size_t>(m.num_vertices), -1);
    // Per free vertex, the last region that held it and was proved to have no re-embedding (a
    // rim short of its singularity's angle): a larger region's failure does not undo the proof.
    std::vector<int> proof_of(failure_of.size(), -1);
    RegionMarks marks; // its members by name: an aggregate list would silently fill `cone`
    marks.face.assign(static_cast<std::size_t>(m.num_faces()), 0);
    marks.vertex.assign(static_cast<std::size_t>(m.num_vertices), 0);
    for (const int radius : kRingRadii) {
        if (seeds_faces.empty()) break;
        for (const DipoleMerge& d : merges)
            if (!merge_reembedded(d))
                for (const int e : d.path) seeds_faces.push_back(TriMesh::face(e));
        if (seeds_faces.empty()) break;
        std::vector<int> seeds;
        for (const int f : seeds_faces)
            for (const int v : m.tri[f]) seeds.push_back(v);
        std::vector<int> free;
        for (const int v : ring_neighbourhood(m, seeds, radius, distance))
            if (!pinned[v]) free.push_back(v);
        std::sort(free.begin(), free.end());
        // Regions share fixed vertices, whose windings the certificate reads: they are taken in
        // an order that does not depend on the input's (their smallest vertex key first).
        std::vector<Region> regions = split_regions(m, free, label);
        std::sort(regions.begin(), regions.end(), [&](const Region& a, const Region& b) {
            return vertex_key(m, a.fans[0].vertex) < vertex_key(m, b.fans[0].vertex);
        });
        for (const Region& r : regions) {
            const auto record = [&](const RegionFailure& f) {
                for (const FreeFan& fan : r.fans) {
                    failure_of[fan.vertex] = static_cast<int>(failures.size());
                    if (f.why == RegionFailure::Why::RimShort) proof_of[fan.vertex] = static_cast<int>(failures.size());
                }
                failures.push_back(f);
            };
            if (r.fans.size() > kMaxRegionVertices) {
                RegionFailure f;
                f.why = RegionFailure::Why::TooLarge;
                f.radius = radius;
                f.free_vertices = r.fans.size();
                f.triangles = r.faces.size();
                record(f);
                continue;
            }
            const std::vector<Point2> before = region_uvs(m, r);
            marks.mark(m, r);
            bool repaired = false;
            const bool admitted = admits_embedding(m, r, valences_given, marks);
            RegionFailure failure; // what the first attempt left, if it failed (the retry starts over)
            if (admitted) {
                const bool untangled = untangle_region(m, r, rest, corner_slot, corner_to);
                repaired = untangled && windings_kept(m, r, marks);
                if (!repaired) failure = describe_failure(m, r, marks, true, radius);
                // Once more with cone fans opened, where that is what failed: the untangler wound
                // the region wrongly round its singularities, or Gauss-Bonnet corrected some.
                if (!repaired && (untangled || marks.cone >= 0))
                    repaired = untangle_with_open_cones(m, r, marks, before, rest, corner_slot, corner_to);
            } else {
                failure = describe_failure(m, r, marks, false, radius);
            }
            if (repaired) {
                polish_region(m, r, rest, corner_slot, corner_to, marks);
                for (const FreeFan& fan : r.fans) reembedded[fan.vertex] = 1;
            }
            // A corrected singularity winds by the angle Gauss-Bonnet gave it: that is its valence.
            if (repaired && marks.cone >= 0)
                m.map.valence[marks.cone] = m.map.winding_valence[marks.cone] =
                    static_cast<int>(std::lround(marks.cone_angle / (0.5 * M_PI)));
            if (!repaired) record(failure);
            marks.clear(r);
            if (!repaired) restore_region_uvs(m, r, before);
        }
        bad_triangles(m, pinned, seeds_faces, stuck);
    }
    // Undone in reverse order (a later path may run along an earlier one's edges).
    for (std::size_t k = merges.size(); k-- > 0;)
        if (!merge_reembedded(merges[k])) unmerge_dipole(m, merges[k]);
    for (const DipoleMerge& d : merges) {
        if (m.map.singular[d.a]) continue; // undone
        report.explanations.push_back(
            {DefectKind::SingularitiesMerged,
             "the singularities at input vertices " + std::to_string(m.input_vertex[d.a]) + " (valence " +
                 std::to_string(d.valences[0]) + ") and " + std::to_string(m.input_vertex[d.b]) + " (valence " +
                 std::to_string(d.valences[1]) + ") lie on one grid point with " + std::to_string(d.path.size() - 1) +
                 " vertices between them, which no fold-free map allows: they were merged into regular vertices "
                 "(the transitions of the " +
                 std::to_string(d.path.size()) + " edges between them changed) and the fold re-embedded",
             m.input_triangle[TriMesh::face(m.fan_start[d.a])],
             -1,
             {0, 0},
             std::nullopt});
    }
    // The certificate's region: every triangle whose UVs differ from the sanitized map.
    for (int f = 0; f < m.num_faces(); ++f) {
        bool changed = false;
        for (int k = 0; k < 3; ++k) changed = changed || m.uv[3 * f + k] != sanitized[3 * f + k];
        if (changed) out.repaired_faces.push_back(f);
        m.map.face_sign[f] = static_cast<signed char>(sign(orient2d(m.uv[3 * f], m.uv[3 * f + 1], m.uv[3 * f + 2])));
    }
    out.regions_repaired = static_cast<std::int64_t>(triangle_groups(m, out.repaired_faces).size());
    for (auto& group : triangle_groups(m, stuck))
        out.unrepaired.push_back(
            {std::move(group), "all its corners are singular, boundary or feature vertices, which stay fixed"});
    for (const auto& group : triangle_groups(m, seeds_faces)) {
        // The latest attempt at a region that held one of its vertices (the largest radius).
        int last = -1, proof = -1;
        for (const int f : group)
            for (const int v : m.tri[f]) last = std::max(last, failure_of[v]), proof = std::max(proof, proof_of[v]);
        std::string why =
            "no orientation-preserving re-embedding that keeps every vertex's winding (once round a regular "
            "vertex, a singularity's valence round it) was found: " +
            (last >= 0 ? failures[static_cast<std::size_t>(last)].text() : std::string("no region held it"));
        if (proof >= 0 && proof != last) why += "; and before, " + failures[static_cast<std::size_t>(proof)].text();
        out.unrepaired.push_back({group, std::move(why)});
    }
    return out;
}

} // namespace qex::detail

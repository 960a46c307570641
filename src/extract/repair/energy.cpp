// The repair's energy: rest shapes, the problem over a region's free vertices, and the energy
// that penalises inverted triangles through a regularised determinant (energy.h).
#include "extract/repair/energy.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace qex::detail::repair_impl {
namespace {

/// The energy's weight on area (det^2 + 1) against shape (|J|^2), both over the regularised det.
constexpr double kAreaWeight = 0.5;

/// The energy of the region's n triangles from their edge vectors in the scratch (a = u1 - u0,
/// b = u2 - u0, rest-shape corners base, next, prev), into the scratch: each triangle's energy and
/// its gradient with respect to u1 (da) and u2 (db); that with respect to u0 is -(da + db). No
/// branch and nothing shared between triangles, so the loop runs in vector lanes; both sides of
/// chi are computed and one is picked (the other may divide by zero, which is harmless here).
inline __attribute__((always_inline)) void triangle_energies_in_lanes(const double* __restrict in,
                                                                     double* __restrict out, std::size_t n) {
    using In = Problem::In;
    using Out = Problem::Out;
    constexpr double theta = kAreaWeight, w = 1 - theta, q = theta;
    for (std::size_t t = 0; t < n; ++t) {
        const double a0 = in[In::a0 * n + t], a1 = in[In::a1 * n + t], b0 = in[In::b0 * n + t],
                     b1 = in[In::b1 * n + t], eps = in[In::eps * n + t];
        const double g00 = in[In::g00 * n + t], g01 = in[In::g01 * n + t], g10 = in[In::g10 * n + t],
                     g11 = in[In::g11 * n + t], area = in[In::area * n + t];
        const double j00 = a0 * g00 + b0 * g10, j01 = a0 * g01 + b0 * g11;
        const double j10 = a1 * g00 + b1 * g10, j11 = a1 * g01 + b1 * g11;
        const double det = j00 * j11 - j01 * j10;
        const double frob = j00 * j00 + j01 * j01 + j10 * j10 + j11 * j11;
        const double r = std::sqrt(eps * eps + det * det);
        // chi_with(det, eps, r), both sides computed.
        const double chi_up = 0.5 * (det + r), chi_down = 0.5 * eps * eps / (r - det);
        const double c = det >= 0 ? chi_up : chi_down;
        const double num = (1 - theta) * frob + theta * (det * det + 1.0);
        // Three divisions, not eight: they bound the loop's throughput.
        const double inv_c = 1.0 / c;
        out[Out::energy * n + t] = area * num * inv_c;
        const double dchi = 0.5 * (1.0 + det / r);
        // dE/dJ = (2 J + 2 det cof J) / chi - num chi' / chi^2 cof J, cof J = [[j11, -j10], [-j01, j00]].
        const double k = num * dchi * inv_c * inv_c;
        const double d00 = (2 * w * j00 + 2 * q * det * j11) * inv_c - k * j11,
                     d01 = (2 * w * j01 - 2 * q * det * j10) * inv_c + k * j10;
        const double d10 = (2 * w * j10 - 2 * q * det * j01) * inv_c + k * j01,
                     d11 = (2 * w * j11 + 2 * q * det * j00) * inv_c - k * j00;
        // dE/d[a b] = area * dE/dJ * G^T.
        out[Out::da0 * n + t] = area * (d00 * g00 + d01 * g01);
        out[Out::da1 * n + t] = area * (d10 * g00 + d11 * g01);
        out[Out::db0 * n + t] = area * (d00 * g10 + d01 * g11);
        out[Out::db1 * n + t] = area * (d10 * g10 + d11 * g11);
    }
}

// On x86-64 the loop is built twice, for AVX2 (four lanes) and for the baseline (two), and the
// first call picks the one the processor runs, at run time (a check, not an ifunc: an ifunc's
// resolver runs before a sanitizer's runtime is up). Not FMA: the values are the same bits either
// way.
#if defined(__x86_64__) && defined(__GNUC__)
#define QEX_REPAIR_AVX2 1
__attribute__((target("avx2"))) void triangle_energies_avx2(const double* __restrict in, double* __restrict out,
                                                            std::size_t n) {
    triangle_energies_in_lanes(in, out, n);
}
#endif

void triangle_energies(const double* in, double* out, std::size_t n) {
#if defined(QEX_REPAIR_AVX2)
    static const bool avx2 = __builtin_cpu_supports("avx2");
    if (avx2) return triangle_energies_avx2(in, out, n);
#endif
    triangle_energies_in_lanes(in, out, n);
}

/// The triangles' edge vectors a = u1 - u0 and b = u2 - u0 in their charts, from the point X,
/// into the scratch's rows. No branch and nothing shared between triangles: the loop runs in
/// vector lanes (the corners' reads gathered), with the scalar loop's arithmetic.
inline __attribute__((always_inline)) void edge_vectors_in_lanes(const Problem::Corners& pc, const double* __restrict X,
                                                                double* __restrict in, std::size_t n) {
    const std::int32_t *__restrict ix = pc.ix.data(), *__restrict iy = pc.iy.data();
    const double *__restrict sx = pc.sx.data(), *__restrict sy = pc.sy.data();
    const double *__restrict tx = pc.tx.data(), *__restrict ty = pc.ty.data();
    // Corner k of triangle t is entry k n + t: each corner's reads are contiguous, one gather.
    const std::size_t c1 = n, c2 = 2 * n;
    for (std::size_t t = 0; t < n; ++t) {
        const double u0x = sx[t] * X[ix[t]] + tx[t], u0y = sy[t] * X[iy[t]] + ty[t];
        const double u1x = sx[c1 + t] * X[ix[c1 + t]] + tx[c1 + t], u1y = sy[c1 + t] * X[iy[c1 + t]] + ty[c1 + t];
        const double u2x = sx[c2 + t] * X[ix[c2 + t]] + tx[c2 + t], u2y = sy[c2 + t] * X[iy[c2 + t]] + ty[c2 + t];
        in[Problem::a0 * n + t] = u1x - u0x, in[Problem::a1 * n + t] = u1y - u0y;
        in[Problem::b0 * n + t] = u2x - u0x, in[Problem::b1 * n + t] = u2y - u0y;
    }
}

/// The gradient per unknown, gathered from the triangles' rows in their order (Problem::Gather),
/// four unknowns side by side: each lane sums its unknown's terms as a scalar loop would, so the
/// same bits as the scatter into a zero gradient made (a zero's sign aside, which no sum from
/// +0.0 keeps). No branch inside a block, whose terms all unknowns share in count.
inline __attribute__((always_inline)) void gather_in_lanes(const Problem::Gather& pg, const double* __restrict out,
                                                           double* __restrict g, std::size_t unknowns) {
    typedef double Lanes __attribute__((vector_size(32)));
    const std::int32_t *__restrict first = pg.first.data(), *__restrict from = pg.from.data();
    const double* __restrict sign = pg.sign.data();
    const std::size_t blocks = pg.first.size() - 1;
    for (std::size_t b = 0; b < blocks; ++b) {
        Lanes sum = {0.0, 0.0, 0.0, 0.0};
        for (std::int32_t k = first[b]; k < first[b + 1]; k += 4) {
            const Lanes term = {out[from[k]], out[from[k + 1]], out[from[k + 2]], out[from[k + 3]]};
            Lanes s;
            std::memcpy(&s, sign + k, sizeof s);
            sum += s * term;
        }
        const std::size_t j = 4 * b, lanes = std::min<std::size_t>(4, unknowns - j);
        for (std::size_t l = 0; l < lanes; ++l) g[j + l] = sum[l];
    }
}

#if defined(QEX_REPAIR_AVX2)
__attribute__((target("avx2"))) void gather_avx2(const Problem::Gather& pg, const double* out, double* g,
                                                 std::size_t unknowns) {
    gather_in_lanes(pg, out, g, unknowns);
}
#endif

void gather_gradient(const Problem::Gather& pg, const double* out, double* g, std::size_t unknowns) {
#if defined(QEX_REPAIR_AVX2)
    static const bool avx2 = __builtin_cpu_supports("avx2");
    if (avx2) return gather_avx2(pg, out, g, unknowns);
#endif
    gather_in_lanes(pg, out, g, unknowns);
}

#if defined(QEX_REPAIR_AVX2)
__attribute__((target("avx2"))) void edge_vectors_avx2(const Problem::Corners& pc, const double* X, double* in,
                                                       std::size_t n) {
    edge_vectors_in_lanes(pc, X, in, n);
}
#endif

void edge_vectors(const Problem::Corners& pc, const double* X, double* in, std::size_t n) {
#if defined(QEX_REPAIR_AVX2)
    static const bool avx2 = __builtin_cpu_supports("avx2");
    if (avx2) return edge_vectors_avx2(pc, X, in, n);
#endif
    edge_vectors_in_lanes(pc, X, in, n);
}

/// One term of the gradient: unknown += sign * out[from].
struct GradientTerm {
    std::int32_t unknown, from;
    double sign;
};

/// The terms by unknown, each unknown's in their order, in blocks of four unknowns padded to the
/// block's longest (Problem::Gather); `zero` is the place of the zero after out's rows.
Problem::Gather by_unknown(const std::vector<GradientTerm>& terms, std::size_t unknowns, std::int32_t zero) {
    std::vector<std::int32_t> count(unknowns + 1, 0), at(unknowns + 1, 0);
    for (const GradientTerm& term : terms) ++count[static_cast<std::size_t>(term.unknown)];
    const std::size_t blocks = (unknowns + 3) / 4;
    Problem::Gather pg;
    pg.first.assign(blocks + 1, 0);
    for (std::size_t b = 0; b < blocks; ++b) {
        std::int32_t width = 0;
        for (std::size_t j = 4 * b; j < std::min(4 * b + 4, unknowns); ++j) width = std::max(width, count[j]);
        pg.first[b + 1] = pg.first[b] + 4 * width;
    }
    pg.from.assign(static_cast<std::size_t>(pg.first[blocks]), zero);
    pg.sign.assign(pg.from.size(), 1.0);
    // Unknown j's k-th term at first[j / 4] + 4 k + j % 4.
    for (std::size_t j = 0; j < unknowns; ++j) at[j] = pg.first[j / 4] + static_cast<std::int32_t>(j % 4);
    for (const GradientTerm& term : terms) {
        auto& k = at[static_cast<std::size_t>(term.unknown)];
        pg.from[static_cast<std::size_t>(k)] = term.from, pg.sign[static_cast<std::size_t>(k)] = term.sign;
        k += 4;
    }
    return pg;
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
    rest.resize(r.faces.size());
    std::vector<std::array<double, 4>> shape(r.faces.size()); // r1x, r2x, r2y, 3D area
    for (std::size_t i = 0; i < r.faces.size(); ++i) {
        const int f = r.faces[i];
        const int base = canonical_base(m, f);
        rest[i].base = base;
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
        RestShape& rs = rest[i];
        rs.g00 = 1.0 / s[0];
        rs.g01 = -s[1] / (s[0] * s[2]);
        rs.g10 = 0.0;
        rs.g11 = 1.0 / s[2];
        rs.area = s[3];
    }
    return true;
}

Problem make_problem(const TriMesh& m, const Region& r, const std::vector<RestShape>& rest,
                     std::vector<int>& corner_slot, const std::vector<int>& barrier) {
    Problem p;
    // corner_slot: the free corners' places in `owner` (fan, corner of the fan).
    std::vector<std::array<int, 2>> owner;
    for (std::size_t i = 0; i < r.fans.size(); ++i)
        for (std::size_t k = 0; k < r.fans[i].corners.size(); ++k) {
            corner_slot[r.fans[i].corners[k]] = static_cast<int>(owner.size());
            owner.push_back({static_cast<int>(i), static_cast<int>(k)});
        }
    const std::size_t n = r.faces.size();
    p.triangles = n;
    p.unknowns = 2 * r.fans.size();
    Problem::Corners& pc = p.corners;
    for (auto* v : {&pc.ix, &pc.iy}) v->resize(3 * n);
    for (auto* v : {&pc.sx, &pc.sy, &pc.tx, &pc.ty}) v->resize(3 * n);
    // The gradient's terms in the order of the triangles and their corners.
    std::vector<GradientTerm> terms;
    terms.reserve(6 * n);
    constexpr std::size_t kRowX[3] = {Problem::dc0, Problem::da0, Problem::db0};
    constexpr std::size_t kRowY[3] = {Problem::dc1, Problem::da1, Problem::db1};
    std::vector<double> fixed;
    for (std::size_t t = 0; t < n; ++t) {
        const int b = rest[t].base;
        const int order[3] = {b, TriMesh::next(b), TriMesh::prev(b)};
        for (std::size_t k = 0; k < 3; ++k) {
            const std::size_t c = k * n + t;
            const int e = corner_slot[order[k]];
            if (e < 0) { // read as is: (1 X + -0.0); its gradient goes to the slots nobody reads
                pc.ix[c] = static_cast<std::int32_t>(p.unknowns + fixed.size());
                pc.iy[c] = pc.ix[c] + 1;
                fixed.push_back(m.uv[order[k]][0]), fixed.push_back(m.uv[order[k]][1]);
                pc.sx[c] = pc.sy[c] = 1.0;
                pc.tx[c] = pc.ty[c] = -0.0;
                continue;
            }
            // GridAutomorphism::rotate by r: (x, y), (-y, x), (-x, -y), (y, -x); then + t.
            const int slot = owner[static_cast<std::size_t>(e)][0];
            const GridAutomorphism& to = r.fans[static_cast<std::size_t>(slot)].to_c[static_cast<std::size_t>(owner[static_cast<std::size_t>(e)][1])];
            const int rot = to.r & 3, odd = rot & 1;
            pc.ix[c] = 2 * slot + odd, pc.iy[c] = 2 * slot + 1 - odd;
            pc.sx[c] = rot == 1 || rot == 2 ? -1.0 : 1.0;
            pc.sy[c] = rot == 2 || rot == 3 ? -1.0 : 1.0;
            pc.tx[c] = static_cast<double>(to.tx), pc.ty[c] = static_cast<double>(to.ty);
            // The gradient back into the vertex's chart, by (4 - r) & 3: x from the row of
            // component `swap`, y from the other, each with its sign.
            const int back = (4 - rot) & 3;
            const bool swap = (back & 1) != 0;
            const auto row = [&](bool y) {
                return static_cast<std::int32_t>((y ? kRowY[k] : kRowX[k]) * n + t);
            };
            terms.push_back({2 * slot, row(swap), back == 1 || back == 2 ? -1.0 : 1.0});
            terms.push_back({2 * slot + 1, row(!swap), back == 2 || back == 3 ? -1.0 : 1.0});
        }
    }
    p.point.resize(p.unknowns + fixed.size());
    std::copy(fixed.begin(), fixed.end(), p.point.begin() + static_cast<std::ptrdiff_t>(p.unknowns));
    p.gather = by_unknown(terms, p.unknowns, static_cast<std::int32_t>(Problem::out_rows * n));
    for (const FreeFan& fan : r.fans)
        for (const int c : fan.corners) corner_slot[c] = -1;
    p.in.resize(Problem::in_rows * n);
    p.out.assign(Problem::out_rows * n + 1, 0.0); // the last: the zero that padding terms read
    p.gdet.resize(n);
    for (std::size_t t = 0; t < n; ++t) {
        const RestShape& s = rest[t];
        p.in[Problem::g00 * n + t] = s.g00, p.in[Problem::g01 * n + t] = s.g01;
        p.in[Problem::g10 * n + t] = s.g10, p.in[Problem::g11 * n + t] = s.g11;
        p.in[Problem::area * n + t] = s.area;
        p.gdet[t] = s.g00 * s.g11 - s.g01 * s.g10;
    }
    for (std::size_t t = 0; t < r.faces.size() && !barrier.empty(); ++t)
        if (std::binary_search(barrier.begin(), barrier.end(), r.faces[t]))
            p.barrier_triangles.push_back(static_cast<int>(t));
    return p;
}

double region_energy(const Problem& p, const std::vector<double>& x, double eps, std::vector<double>* grad,
                     double* lowest) {
    if (grad) grad->resize(p.unknowns);
    const std::size_t n = p.triangles;
    double* in = p.in.data();
    std::copy(x.begin(), x.end(), p.point.begin());
    const double* X = p.point.data();
    edge_vectors(p.corners, X, in, n);
    std::fill(in + Problem::eps * n, in + (Problem::eps + 1) * n, eps);
    // A barrier triangle is never inverted at a start (the caller's), and not to be by a step.
    for (const int t : p.barrier_triangles) {
        if (!(twice_area(p, static_cast<std::size_t>(t)) > 0.0))
            return std::numeric_limits<double>::infinity();
        in[Problem::eps * n + t] = 0.0;
    }
    if (lowest) {
        *lowest = std::numeric_limits<double>::infinity();
        for (std::size_t t = 0; t < n; ++t) *lowest = std::min(*lowest, twice_area(p, t) * p.gdet[t]);
    }
    const double* out = p.out.data();
    triangle_energies(in, p.out.data(), n);
    // Summed and scattered in the triangles' order, so the result depends on nothing else.
    double energy = 0.0;
    for (std::size_t t = 0; t < n; ++t) energy += out[Problem::energy * n + t];
    if (!grad) return energy;
    // The gradient with respect to u0, in a loop of its own (in the energy's loop it kept that
    // loop out of vector lanes).
    double* dc = p.out.data();
    for (std::size_t t = 0; t < n; ++t) {
        dc[Problem::dc0 * n + t] = -(out[Problem::da0 * n + t] + out[Problem::db0 * n + t]);
        dc[Problem::dc1 * n + t] = -(out[Problem::da1 * n + t] + out[Problem::db1 * n + t]);
    }
    gather_gradient(p.gather, out, grad->data(), p.unknowns);
    return energy;
}

} // namespace qex::detail::repair_impl

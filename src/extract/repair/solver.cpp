// The repair's solver: L-BFGS over a region's free vertices, regularisation steps judged by the
// exact predicate, kernel sweeps, and the final relaxation (solver.h).
#include "extract/repair/solver.h"
#include "extract/repair/newton.h"
#include "extract/parallel.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <exception>
#include <limits>
#include <optional>
#include <utility>

namespace qex::detail::repair_impl {
namespace {

// ============================================================================ budget

/// Regularisation steps per attempt, and L-BFGS iterations per step: a step stops earlier, at the
/// first iteration after its gradient step that lowers the energy by less than kInnerStall of it.
/// The regularisation changes after each step, so its minimum need not be reached: 744 of 766
/// steps on the paper's maps ran all 80 iterations, gaining less than 1e-6 per iteration from the
/// 40th on average. Quad counts and exit codes of the shared maps are the same from 1e-4 to 1e-7;
/// where the untangler stops moves the repaired vertices, and with them which minimum of the
/// relaxation a translated or re-charted map lands in (the transform tests; bench/RESULTS.md,
/// issue 30 round 6).
constexpr int kOuterIterations = 60;
constexpr int kInnerIterations = 80;
constexpr double kInnerStall = 1e-5;
/// A region with more than this share of its triangles inverted after its second step, and more
/// than kHopelessFloor of them, is given up: a larger region at the next ring, or the paper's
/// handling, takes them. Over the 50 shared maps, of 960 untangler runs, 619 succeeded (the
/// kernel sweeps included); 3 of those had more than this after their second step (the kernel
/// sweeps mended the 1, 3 and 5 triangles they ended with), and their maps keep their quad
/// counts and quality without them (bench/RESULTS.md). The runs given up so were a third of the
/// failing runs' steps. The floor spares small regions, where one triangle is a large share.
constexpr double kHopelessShare = 0.015;
constexpr std::size_t kHopelessFloor = 2;
/// After its first step the bound is a tenth, and 5 triangles: no success had more inverted at
/// that point (the most: 10 of 116 triangles, 9 of 98), and the failing runs that had spent a
/// tenth of all failing runs' time after it.
constexpr double kHopelessShareFirst = 0.1;
constexpr std::size_t kHopelessFloorFirst = 5;
/// After this many L-BFGS iterations of a step, a region with more than kGiveUpShareFirst of its
/// triangles inverted (and more than kHopelessFloorFirst) in its first step, or more than
/// kGiveUpShare (and more than kLocalMost, which a local mend could still take) in a later one, is
/// given up there. A failing first step mostly ends worse than it is there (duck_miq_16's region
/// of 1,338 triangles: 210 inverted after 20 iterations, 147 after 80). Over the 50 shared maps no
/// success had more than 11% inverted there in its first step (5 of 47 triangles; the largest
/// region, 85 of 963), nor more than 1.4% with more than 6 in a later one (13 of 963). With a
/// margin over those, the bounds leave every run's outcome and mesh on those maps as it was, and
/// spare about a tenth of the failing runs' untangling (duck_miq_16's repair 17.7 -> 15.3 ms).
constexpr int kGiveUpIteration = 20;
constexpr double kGiveUpShareFirst = 0.15;
constexpr double kGiveUpShare = 0.02;
/// The first regularisation, relative to the most negative Jacobian determinant.
constexpr double kInitialRegularisation = 0.1;
/// A step that is the first since the attempt's last best not to leave fewer triangles inverted,
/// with at most this many inverted, tries to mend them locally: the free vertices within
/// kLocalRings triangles of them untangled alone for one step (and its kernel sweeps), the rest
/// of the region held. Without it a stalled attempt spends its patience's steps on a few
/// triangles (duck_miq_8's large region: 6 inverted from its fourth step to its eighth, then
/// mended by the kernel sweeps). Over the 50 shared maps 17 of 60 such mends succeed; with up to
/// 16 inverted, 1 of 29 more did, and the failures cost 37 ms more in all.
constexpr std::size_t kLocalMost = 6;
constexpr int kLocalRings = 2;
/// The final minimisation of a repaired region: L-BFGS iterations, then Newton steps. L-BFGS
/// alone took 2,000 iterations to settle the pure barrier (most of the repair's time on the
/// paper's maps); 50 bring Newton near enough that it ends in a few steps (at most 7 over the
/// regions of duck_miq_8, against 31 from the untangler's point).
constexpr int kPolishIterations = 50;
/// L-BFGS stops when an iteration lowers the energy by less than this fraction of it.
constexpr double kPolishStall = 1e-15;
constexpr int kNewtonIterations = 50;
/// From this many unknowns Newton's system (its pattern and symbolic factorisation, about as
/// long as the L-BFGS iterations before it) is made on a helper thread beside those iterations.
/// Below, the two take less than handing the work over.
constexpr std::size_t kNewtonBesideMinUnknowns = 256;

/// The dot product of a and b, summed in four interleaved lanes (one chain of dependent
/// additions would bound the L-BFGS's two-loop recursion by the adder's latency): lane j sums
/// the products i = j mod 4 in order, the tail goes to lane 0, and the lanes are added as
/// (0 + 1) + (2 + 3). The order is fixed, so the result depends on nothing but a and b, and the
/// lanes are one vector register where the processor has four (the same bits either way).
inline __attribute__((always_inline)) double dot(const std::vector<double>& a, const std::vector<double>& b) {
    typedef double Lanes __attribute__((vector_size(32)));
    Lanes s = {0.0, 0.0, 0.0, 0.0};
    std::size_t i = 0;
    for (; i + 4 <= a.size(); i += 4) {
        Lanes x, y;
        std::memcpy(&x, a.data() + i, sizeof x);
        std::memcpy(&y, b.data() + i, sizeof y);
        s += x * y;
    }
    double s0 = s[0];
    for (; i < a.size(); ++i) s0 += a[i] * b[i];
    return (s0 + s[1]) + (s[2] + s[3]);
}

/// Triangles inverted at the point the energy last evaluated: the solver's own view, in doubles,
/// of how far it is.
std::size_t inverted_at_last_point(const Problem& p) {
    std::size_t inverted = 0;
    for (std::size_t t = 0; t < p.triangles; ++t) inverted += !(twice_area(p, t) > 0);
    return inverted;
}

/// Minimises the region's energy for a fixed eps from x (L-BFGS, Armijo backtracking). Inline:
/// built for the baseline and for AVX2 below, the same arithmetic in wider lanes. Returns false
/// where it gave up: after kGiveUpIteration iterations more than `give_up_above` triangles were
/// inverted (x is then that iterate).
inline __attribute__((always_inline)) bool minimise_lanes(const Problem& p, std::vector<double>& x, double eps,
                                                          double length, int iterations, double stall,
                                                          std::size_t give_up_above) {
    constexpr std::size_t kHistory = 8;
    std::vector<std::vector<double>> ss, ys;
    std::vector<double> rho;
    std::vector<double> g, g_new, d(x.size()), x_new(x.size()), spare_s, spare_y, alpha;
    double f = region_energy(p, x, eps, &g);
    for (int it = 0; it < iterations && std::isfinite(f); ++it) {
        if (p.stop && p.stop->load(std::memory_order_relaxed)) return true;
        // Two-loop recursion: d = -H g.
        for (std::size_t i = 0; i < x.size(); ++i) d[i] = -g[i];
        alpha.assign(ss.size(), 0.0);
        for (std::size_t j = ss.size(); j-- > 0;) {
            alpha[j] = rho[j] * dot(ss[j], d);
            for (std::size_t i = 0; i < d.size(); ++i) d[i] -= alpha[j] * ys[j][i];
        }
        if (!ss.empty()) {
            const double gamma = dot(ss.back(), ys.back()) / dot(ys.back(), ys.back());
            for (double& v : d) v *= gamma;
        } else {
            const double norm = std::sqrt(dot(d, d));
            if (!(norm > 0)) return true;
            for (double& v : d) v *= 0.1 * length / norm;
        }
        for (std::size_t j = 0; j < ss.size(); ++j) {
            const double beta = rho[j] * dot(ys[j], d);
            for (std::size_t i = 0; i < d.size(); ++i) d[i] += (alpha[j] - beta) * ss[j][i];
        }
        double slope = dot(g, d);
        bool gradient_step = ss.empty();
        if (!(slope < 0)) { // not a descent direction: restart from the gradient
            gradient_step = true;
            ss.clear(), ys.clear(), rho.clear();
            const double norm = std::sqrt(dot(g, g));
            if (!(norm > 0)) return true;
            for (std::size_t i = 0; i < d.size(); ++i) d[i] = -g[i] * 0.1 * length / norm;
            slope = dot(g, d);
        }
        double step = 1.0, f_new = f;
        bool accepted = false;
        for (int ls = 0; ls < 40; ++ls, step *= 0.5) {
            for (std::size_t i = 0; i < x.size(); ++i) x_new[i] = x[i] + step * d[i];
            f_new = region_energy(p, x_new, eps, &g_new);
            if (std::isfinite(f_new) && f_new <= f + 1e-4 * step * slope) {
                accepted = true;
                break;
            }
        }
        if (!accepted) return true;
        // The pair goes into the oldest pair's storage once the history is full (no allocation).
        if (spare_s.size() != x.size()) spare_s.resize(x.size()), spare_y.resize(x.size());
        for (std::size_t i = 0; i < x.size(); ++i) spare_s[i] = x_new[i] - x[i], spare_y[i] = g_new[i] - g[i];
        const double sy = dot(spare_s, spare_y);
        if (sy > 1e-300) {
            if (ss.size() == kHistory) {
                std::rotate(ss.begin(), ss.begin() + 1, ss.end()), std::rotate(ys.begin(), ys.begin() + 1, ys.end());
                rho.erase(rho.begin());
                ss.back().swap(spare_s), ys.back().swap(spare_y);
            } else {
                ss.push_back(std::move(spare_s)), ys.push_back(std::move(spare_y));
                spare_s.clear(), spare_y.clear();
            }
            rho.push_back(1.0 / sy);
        }
        // A gradient step (the first, or after a restart) does not end the minimisation: near a
        // barrier it can gain little where the steps after it, with a history, gain much.
        const bool stalled = gradient_step ? false : f - f_new <= stall * std::abs(f);
        x.swap(x_new), g.swap(g_new), f = f_new;
        if (it + 1 == kGiveUpIteration && give_up_above != SIZE_MAX && inverted_at_last_point(p) > give_up_above)
            return false;
        if (stalled) return true;
    }
    return true;
}

// On x86-64 the L-BFGS (its dot products and vector updates) is built twice, for AVX2 and for
// the baseline, and the first call picks the one the processor runs (a check, not an ifunc, as
// for the energy: energy.cpp). Not FMA: the values are the same bits either way.
#if defined(__x86_64__) && defined(__GNUC__)
#define QEX_SOLVER_AVX2 1
__attribute__((target("avx2"))) bool minimise_avx2(const Problem& p, std::vector<double>& x, double eps, double length,
                                                   int iterations, double stall, std::size_t give_up_above) {
    return minimise_lanes(p, x, eps, length, iterations, stall, give_up_above);
}
#endif

/// minimise_lanes on the processor's widest lanes; `give_up_above` SIZE_MAX: never gives up.
bool minimise(const Problem& p, std::vector<double>& x, double eps, double length, int iterations,
              double stall = 1e-12, std::size_t give_up_above = SIZE_MAX) {
#if defined(QEX_SOLVER_AVX2)
    static const bool avx2 = __builtin_cpu_supports("avx2");
    if (avx2) return minimise_avx2(p, x, eps, length, iterations, stall, give_up_above);
#endif
    return minimise_lanes(p, x, eps, length, iterations, stall, give_up_above);
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

} // namespace

Workspace::Workspace(const TriMesh& m) : corner_slot(3 * static_cast<std::size_t>(m.num_faces()), -1) {}

namespace {

bool untangle(TriMesh& m, const Region& r, Workspace& work, int patience, const std::vector<int>& barrier,
              int steps, bool mend);

/// Untangles the free vertices round what r has inverted (around_inverted) for one step and its
/// kernel sweeps, the rest of r held, where the barrier keeps its triangles. True when r is then
/// positive; else its UVs are as before. It leaves the sub-region's rest shapes in work.rest.
bool mend_locally(TriMesh& m, const Region& r, Workspace& work, const std::vector<int>& barrier) {
    const Region sub = around_inverted(m, r, kLocalRings);
    std::vector<int> kept;
    for (const int f : sub.faces)
        if (std::binary_search(barrier.begin(), barrier.end(), f)) kept.push_back(f);
    std::sort(kept.begin(), kept.end());
    const std::vector<Point2> held = region_uvs(m, r);
    bool all = untangle(m, sub, work, 1, kept, 1, false);
    for (const int f : r.faces) all = all && positive(m, f);
    if (!all) restore_region_uvs(m, r, held);
    return all;
}

/// How many triangles of a region of `faces` may be inverted after kGiveUpIteration iterations
/// of step `outer` for the step to go on.
std::size_t give_up_bound(int outer, std::size_t faces) {
    const double share = outer == 0 ? kGiveUpShareFirst : kGiveUpShare;
    const auto most = static_cast<std::size_t>(share * static_cast<double>(faces));
    return std::max(outer == 0 ? kHopelessFloorFirst : kLocalMost, most);
}

bool untangle(TriMesh& m, const Region& r, Workspace& work, int patience, const std::vector<int>& barrier,
              int steps, bool mend) {
    if (!rest_shapes(m, r, work.rest)) return false;
    // The problem holds what it needs of the rest shapes: a local mend may reuse work.rest.
    Problem p = make_problem(m, r, work.rest, work.corner_slot, barrier);
    p.stop = work.stop;
    double length = 0.0;
    std::vector<double> x = region_point(m, r, length);
    double lowest = 0.0;
    region_energy(p, x, 1.0, nullptr, &lowest);
    double eps = std::max(1e-3, kInitialRegularisation * std::abs(lowest));
    std::size_t best = SIZE_MAX;
    const auto stopped = [&] { return work.stop && work.stop->load(std::memory_order_relaxed); };
    for (int outer = 0, since_best = 0; outer < steps && since_best < patience; ++outer) {
        if (stopped()) return false;
        const double before = region_energy(p, x, eps, nullptr);
        const std::size_t give_up_above = mend && work.give_up_early ? give_up_bound(outer, r.faces.size()) : SIZE_MAX;
        const bool went_on = minimise(p, x, eps, length, kInnerIterations, kInnerStall, give_up_above);
        // Place (truncated, propagated exactly) and judge exactly.
        for (std::size_t i = 0; i < r.fans.size(); ++i) {
            place(m, r.fans[i], {x[2 * i], x[2 * i + 1]});
            x[2 * i] = m.uv[r.fans[i].corners[0]][0];
            x[2 * i + 1] = m.uv[r.fans[i].corners[0]][1];
        }
        if (!went_on) return false; // placed, so the failure reads what the untangler left
        std::size_t inverted = 0;
        for (const int f : r.faces) inverted += !positive(m, f);
        if (inverted == 0) return true;
        const double share = outer == 0 ? kHopelessShareFirst : kHopelessShare;
        if (inverted > (outer == 0 ? kHopelessFloorFirst : kHopelessFloor) &&
            static_cast<double>(inverted) > share * static_cast<double>(r.faces.size()))
            return false;
        if (inverted < best)
            best = inverted, since_best = 0;
        else if (++since_best == 1 && mend && inverted <= kLocalMost && mend_locally(m, r, work, barrier))
            return true; // x is stale now, and not read again
        const double after = region_energy(p, x, eps, nullptr, &lowest);
        const double sigma = std::max(1.0 - after / before, 0.1);
        const double mu = (1.0 - sigma) * chi(lowest, eps);
        eps = lowest < mu ? std::max(2.0 * std::sqrt(mu * (mu - lowest)), 1e-13) : 1e-13;
    }
    return !stopped() && kernel_sweeps(m, r);
}

} // namespace

bool untangle_region(TriMesh& m, const Region& r, Workspace& work, int patience, const std::vector<int>& barrier) {
    return untangle(m, r, work, patience, barrier, kOuterIterations, true);
}

namespace {

/// Runs `lbfgs` and makes `system` for p: with `beside` and a large region, side by side (the
/// system reads only p's corners, which the L-BFGS iterations never write), else one after the
/// other.
template <class Work>
void newton_system_beside(bool beside, const Problem& p, std::optional<NewtonSystem>& system, const Work& lbfgs) {
    if (!beside || p.unknowns < kNewtonBesideMinUnknowns) {
        lbfgs();
        system.emplace(p);
        return;
    }
    std::vector<std::exception_ptr> thrown(2);
    run_workers(2, [&](std::size_t t) {
        try {
            if (t == 0)
                lbfgs();
            else
                system.emplace(p);
        } catch (...) { thrown[t] = std::current_exception(); }
    }, thrown);
}

} // namespace

void polish_region(TriMesh& m, const Region& r, Workspace& work, const RegionMarks& marks) {
    if (!rest_shapes(m, r, work.rest)) return;
    const std::vector<RestShape>& rest = work.rest;
    const Problem p = make_problem(m, r, rest, work.corner_slot, {});
    const std::vector<Point2> before = region_uvs(m, r);
    double length = 0.0;
    std::vector<double> x = region_point(m, r, length);
    // L-BFGS's first iterations gain most; Newton's steps then end near the minimum.
    std::optional<NewtonSystem> system;
    newton_system_beside(work.beside, p, system, [&] { minimise(p, x, 0.0, length, kPolishIterations, kPolishStall); });
    minimise_newton(p, x, kNewtonIterations, *system);
    for (std::size_t i = 0; i < r.fans.size(); ++i) place(m, r.fans[i], {x[2 * i], x[2 * i + 1]});
    bool all = true;
    for (const int f : r.faces) all = all && positive(m, f);
    // A line-search step is discrete: a triangle could pass through zero and back within one.
    if (!(all && windings_kept(m, r, marks))) restore_region_uvs(m, r, before);
}

} // namespace qex::detail::repair_impl

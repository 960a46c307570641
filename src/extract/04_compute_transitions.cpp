// Transition functions between adjacent charts (Section 3.1): the rotation that best maps one
// chart's copy of the shared edge onto the other's, then the rounded integer translation.
//
// An edge whose two copies differ by about as much as the edge is long (solver noise on an edge
// that is nearly degenerate in the parameter domain) does not determine its rotation. Such an
// edge takes the rotation that closes the fan of one of its ends with the other edges'
// transitions: noise never creates a singularity. Only when neither end has a closed fan of
// determined edges does the nearest rotation stand.
#include "pipeline.h"

#include <algorithm>
#include <cmath>
#include <vector>
#if defined(_OPENMP)
#include <omp.h>
#endif

namespace qex::detail {
namespace {

double norm_inf(const Point2& p) { return std::max(std::abs(p[0]), std::abs(p[1])); }

/// The rotation (quarter turns) that closes the fan round the origin of corner `start` when the
/// edge of half-edge `skip` is crossed last; -1 if the fan is open or crosses an undetermined edge.
/// The walk goes from face(opp[skip]) round the shared vertex to face(skip).
int closing_rotation(const TriMesh& m, const std::vector<char>& determined, int skip, int start) {
    int turns = 0;
    int c = start;
    for (int guard = 0; guard < 1 << 16; ++guard) {
        if (c == skip) return (4 - (turns & 3)) & 3;
        const int o = m.opp[c];
        if (o < 0 || !determined[c]) return -1;
        turns += m.map.transition[c].r;
        c = TriMesh::next(o);
    }
    return -1;
}

} // namespace

void compute_transitions(TriMesh& m) {
    const int nh = 3 * m.num_faces();
    m.map.transition.allocate(static_cast<std::size_t>(nh));
    std::vector<char> determined(nh, 1);
    auto len = [&](int c) {
        const Point2 &p = m.uv[c], &q = m.uv[TriMesh::next(c)];
        return norm_inf({q[0] - p[0], q[1] - p[1]});
    };
    auto set = [&](int h, int r) {
        const int o = m.opp[h];
        // In face(h) the edge runs a -> b; in face(o) it runs b -> a.
        const Point2& a = m.uv[h];
        const Point2& b = m.uv[TriMesh::next(h)];
        const Point2& a2 = m.uv[TriMesh::next(o)];
        const Point2& b2 = m.uv[o];
        const Point2 ra = GridAutomorphism::rotate(a, r), rb = GridAutomorphism::rotate(b, r);
        GridAutomorphism g;
        g.r = r;
        g.tx = static_cast<std::int64_t>(std::llround(0.5 * ((a2[0] - ra[0]) + (b2[0] - rb[0]))));
        g.ty = static_cast<std::int64_t>(std::llround(0.5 * ((a2[1] - ra[1]) + (b2[1] - rb[1]))));
        m.map.transition.set(static_cast<std::size_t>(h), g);
        m.map.transition.set(static_cast<std::size_t>(o), g.inverse());
    };
    // Per triangle: its longest edge (for the dipole pass below).
    std::vector<double> longest(static_cast<std::size_t>(m.num_faces()));
#if defined(_OPENMP)
#pragma omp parallel for schedule(static) num_threads(m.threads) if (m.parallel(nh))
#endif
    for (int f = 0; f < m.num_faces(); ++f) longest[static_cast<std::size_t>(f)] = std::max({len(3 * f), len(3 * f + 1), len(3 * f + 2)});
    // Each interior edge is set from its smaller half-edge, writing only its own two entries;
    // a boundary half-edge gets the identity (it is never read). Each thread lists, in index
    // order, its range's undetermined edges and edges much shorter than their triangles (an
    // eighth of their longest edge); with the static schedule the threads' ranges are in
    // thread order, so the joined lists are in index order, as a serial pass makes them.
    std::vector<int> undetermined;
    std::vector<std::pair<double, int>> short_edges;
#if defined(_OPENMP)
#pragma omp parallel num_threads(m.threads) if (m.parallel(nh))
#endif
    {
        std::vector<int> my_undetermined;
        std::vector<std::pair<double, int>> my_short;
#if defined(_OPENMP)
#pragma omp for schedule(static) nowait
#endif
        for (int h = 0; h < nh; ++h) {
            const int o = m.opp[h];
            if (o < 0) {
                m.map.transition.set(static_cast<std::size_t>(h), GridAutomorphism{});
                continue;
            }
            if (o < h) continue; // set as the inverse of o
            const Point2& a = m.uv[h];
            const Point2& b = m.uv[TriMesh::next(h)];
            const Point2& a2 = m.uv[TriMesh::next(o)];
            const Point2& b2 = m.uv[o];
            const Point2 e{b[0] - a[0], b[1] - a[1]};
            const Point2 e2{b2[0] - a2[0], b2[1] - a2[1]};
            if (!std::isfinite(e[0] + e[1] + e2[0] + e2[1] + a[0] + a[1] + a2[0] + a2[1])) {
                // A collapsed triangle's missing UVs: no transition.
                m.map.transition.set(static_cast<std::size_t>(h), GridAutomorphism{});
                m.map.transition.set(static_cast<std::size_t>(o), GridAutomorphism{});
                determined[h] = determined[o] = 0;
                continue;
            }
            // Rotation: the multiple of 90 degrees closest to the angle from e to e2 (largest dot product).
            int best = 0;
            double best_dot = -HUGE_VAL;
            for (int r = 0; r < 4; ++r) {
                const Point2 re = GridAutomorphism::rotate(e, r);
                const double dot = re[0] * e2[0] + re[1] * e2[1];
                if (dot > best_dot) { best_dot = dot; best = r; }
            }
            set(h, best);
            const Point2 re = GridAutomorphism::rotate(e, best);
            if (!(2 * norm_inf({re[0] - e2[0], re[1] - e2[1]}) < std::min(norm_inf(e), norm_inf(e2)))) {
                determined[h] = determined[o] = 0;
                my_undetermined.push_back(h);
            }
            const double l = std::max(norm_inf(e), norm_inf(e2));
            if (8 * l < std::max(longest[static_cast<std::size_t>(TriMesh::face(h))], longest[static_cast<std::size_t>(TriMesh::face(o))]))
                my_short.push_back({l, h});
        }
#if defined(_OPENMP)
#pragma omp for ordered schedule(static, 1)
        for (int t = 0; t < omp_get_num_threads(); ++t)
#pragma omp ordered
#endif
        {
            undetermined.insert(undetermined.end(), my_undetermined.begin(), my_undetermined.end());
            short_edges.insert(short_edges.end(), my_short.begin(), my_short.end());
        }
    }
    // Undetermined edges in index order (edges with a missing UV stay without a transition).
    for (const int h : undetermined) {
        const int o = m.opp[h];
        // Round the edge's start (a: corner h in face(h), corner next(o) in face(o)), else its end.
        int r = closing_rotation(m, determined, h, TriMesh::next(o));
        if (r < 0) {
            const int rb = closing_rotation(m, determined, o, TriMesh::next(h)); // o's rotation
            if (rb >= 0) r = (4 - rb) & 3;
        }
        if (r >= 0) set(h, r);
    }

    // Dipoles: noise can still turn a short edge by a quarter, which puts singularities of
    // opposite index on its two ends. An edge much shorter than its triangles (an eighth of their
    // longest edge) whose ends turn by opposite amounts takes the rotation that makes both
    // regular. Shortest edges first, so the outcome does not depend on the input's order.
    if (short_edges.empty()) return;
    // The turn of each short edge's ends (fans of interior vertices only; -1: open fan).
    std::vector<int> turns(static_cast<std::size_t>(m.num_vertices), -2); // -2: not yet walked
    auto turn = [&](int v) -> int& {
        int& t = turns[static_cast<std::size_t>(v)];
        if (t != -2) return t;
        t = -1;
        if (m.fan_start[v] < 0 || m.on_boundary[v]) return t;
        int c = m.fan_start[v], sum = 0, n = 0;
        do {
            sum += m.map.transition[c].r;
            c = m.cw(c);
        } while (c >= 0 && c != m.fan_start[v] && ++n <= m.fan_size[v]);
        if (c == m.fan_start[v]) t = sum & 3;
        return t;
    };
    std::sort(short_edges.begin(), short_edges.end());
    for (const auto& [l, h] : short_edges) {
        int &ta = turn(m.origin(h)), &tb = turn(m.target(h));
        if (ta <= 0 || tb <= 0 || ((ta + tb) & 3) != 0) continue; // regular, open, or not opposite
        const int delta = (4 - ta) & 3; // a's walk crosses h, b's walk crosses opp(h)
        set(h, (m.map.transition[h].r + delta) & 3);
        ta = 0;
        tb = 0;
    }
}

} // namespace qex::detail

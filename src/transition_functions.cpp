// Transition functions between adjacent charts (Section 3.1): the rotation that best maps one
// chart's copy of the shared edge onto the other's, then the rounded integer translation.
//
// An edge whose two copies differ by about as much as the edge is long (solver noise on an edge
// that is nearly degenerate in the parameter domain) does not determine its rotation. Such an
// edge takes the rotation that closes the fan of one of its ends with the other edges'
// transitions: noise never creates a singularity. Only when neither end has a closed fan of
// determined edges does the nearest rotation stand.
#include "pipeline.h"

#include <cmath>

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
        turns += m.transition[c].r;
        c = TriMesh::next(o);
    }
    return -1;
}

} // namespace

void compute_transitions(TriMesh& m) {
    const int nh = 3 * m.num_faces();
    m.transition.assign(nh, GridAutomorphism{});
    std::vector<char> determined(nh, 1);
    std::vector<int> undetermined;
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
        m.transition[h] = g;
        m.transition[o] = g.inverse();
    };
    for (int h = 0; h < nh; ++h) {
        const int o = m.opp[h];
        if (o < h) continue; // boundary, or already set as the inverse of o
        const Point2& a = m.uv[h];
        const Point2& b = m.uv[TriMesh::next(h)];
        const Point2& a2 = m.uv[TriMesh::next(o)];
        const Point2& b2 = m.uv[o];
        const Point2 e{b[0] - a[0], b[1] - a[1]};
        const Point2 e2{b2[0] - a2[0], b2[1] - a2[1]};
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
            undetermined.push_back(h);
        }
    }
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
}

} // namespace qex::detail

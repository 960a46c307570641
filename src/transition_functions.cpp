// Transition functions between adjacent charts (Section 3.1): the rotation that best maps one
// chart's copy of the shared edge onto the other's, then the rounded integer translation.
#include "pipeline.h"

#include <cmath>

namespace qex::detail {

void compute_transitions(TriMesh& m) {
    const int nh = 3 * m.num_faces();
    m.transition.assign(nh, GridAutomorphism{});
    for (int h = 0; h < nh; ++h) {
        const int o = m.opp[h];
        if (o < h) continue; // boundary, or already set as the inverse of o
        // In face(h) the edge runs a -> b; in face(o) it runs b -> a.
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
        const Point2 ra = GridAutomorphism::rotate(a, best), rb = GridAutomorphism::rotate(b, best);
        GridAutomorphism g;
        g.r = best;
        g.tx = static_cast<std::int64_t>(std::llround(0.5 * ((a2[0] - ra[0]) + (b2[0] - rb[0]))));
        g.ty = static_cast<std::int64_t>(std::llround(0.5 * ((a2[1] - ra[1]) + (b2[1] - rb[1]))));
        m.transition[h] = g;
        m.transition[o] = g.inverse();
    }
}

} // namespace qex::detail

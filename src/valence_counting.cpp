// Valence counting (Algorithm 8): the fan is split into runs of equal orientation and every
// flipped run counts 2*pi plus its (negative) angle sum, which recovers the valence of a
// singularity whose fan lost a full turn to a fold-over (Figure 2 (d)). Beside it the plain signed
// angle sum ("winding valence") is kept: a fold-over next to a regular vertex makes Algorithm 8
// count 8 where the winding valence correctly says 4, so branch points (r = 0 singularities) are
// decided by the winding valence.
#include "pipeline.h"

#include <cmath>
#include <vector>

namespace qex::detail {

void count_valences(TriMesh& m, bool singular_only) {
    const int nv = m.num_vertices;
    m.valence.assign(nv, 4);
    m.winding_valence.assign(nv, 4);
    const auto count = static_cast<std::int64_t>(m.vertex_order.size());
#if defined(_OPENMP)
#pragma omp parallel num_threads(m.threads) if (m.parallel(3 * m.num_faces()))
#endif
    {
    std::vector<std::pair<int, double>> fan; // (orientation sign, signed inner angle)
#if defined(_OPENMP)
#pragma omp for schedule(static)
#endif
    for (std::int64_t i = 0; i < count; ++i) {
        const int v = m.vertex_order[static_cast<std::size_t>(i)];
        if (m.fan_start[v] < 0 || m.on_boundary[v]) continue;
        if (singular_only && !m.singular[v]) continue;
        fan.clear();
        double winding = 0.0;
        int h = m.fan_start[v];
        do {
            const Point2& u = m.uv[h];
            const Point2& p = m.uv[TriMesh::next(h)];
            const Point2& w = m.uv[TriMesh::prev(h)];
            const int s = sign(orient2d(u, p, w));
            const double ax = p[0] - u[0], ay = p[1] - u[1], bx = w[0] - u[0], by = w[1] - u[1];
            const double angle = std::atan2(std::abs(ax * by - ay * bx), ax * bx + ay * by);
            fan.emplace_back(s, angle);
            winding += s < 0 ? -angle : angle;
            h = m.cw(h);
        } while (h != m.fan_start[v] && h >= 0);
        // Degenerate corners join the orientation of the run before them (cyclically).
        int last = 0;
        for (const auto& c : fan) if (c.first != 0) last = c.first;
        if (last == 0) continue; // every triangle degenerate: no valence
        for (auto& c : fan) {
            if (c.first == 0) c.first = last;
            last = c.first;
        }
        // Rotate so the fan starts at a run boundary, then sum run by run.
        std::size_t start = 0;
        while (start < fan.size() && fan[start].first == fan[(start + fan.size() - 1) % fan.size()].first) ++start;
        m.winding_valence[v] = static_cast<int>(std::lround(2.0 * winding / M_PI));
        if (start == fan.size()) { // a single run: the whole fan has one orientation
            m.valence[v] = std::abs(m.winding_valence[v]);
            continue;
        }
        double total = 0.0, run = 0.0;
        int run_sign = fan[start].first;
        for (std::size_t i = 0; i < fan.size(); ++i) {
            const auto& c = fan[(start + i) % fan.size()];
            if (c.first != run_sign) {
                total += run_sign < 0 ? 2.0 * M_PI - run : run;
                run = 0.0;
                run_sign = c.first;
            }
            run += c.second;
        }
        total += run_sign < 0 ? 2.0 * M_PI - run : run;
        m.valence[v] = static_cast<int>(std::lround(2.0 * total / M_PI));
    }
    } // parallel region
}

} // namespace qex::detail

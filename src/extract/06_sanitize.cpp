// Sanitization of the map (Algorithms 1 and 2, Section 3.2): per vertex, the precision of one
// corner's UV is truncated so that every chart of the fan can represent it exactly, singular
// vertices are snapped to the fixed point of their accumulated transition, feature vertices onto
// their integer iso-line, and the result is propagated around the fan with exact transitions.
#include "pipeline.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace qex::detail {
namespace {

/// A feature constraint: in the chart of `corner`, coordinate `axis` must equal `value`.
struct FeatureConstraint {
    int corner, axis;
    double value;
};

/// Truncates x to the precision that magnitude delta (a power of two) leaves: (x + d) - d.
double truncate(double x, double delta) {
    const double s = x < 0 ? -delta : delta;
    volatile double y = x + s; // volatile: keep the rounding of the addition
    return y - s;
}

/// Fixed point of g (Algorithm 2); for r = 0 the caller rounds instead.
Point2 fixed_point(const GridAutomorphism& g) {
    const double t1 = static_cast<double>(g.tx), t2 = static_cast<double>(g.ty);
    switch (g.r) {
        case 1: return {0.5 * (t1 - t2), 0.5 * (t2 + t1)};
        case 2: return {0.5 * t1, 0.5 * t2};
        case 3: return {0.5 * (t1 + t2), 0.5 * (t2 - t1)};
        default: return {0.0, 0.0};
    }
}

std::vector<std::vector<FeatureConstraint>> feature_constraints(
    const TriMesh& m, const std::vector<std::array<int, 2>>& features, Error& error) {
    std::vector<std::vector<FeatureConstraint>> per_vertex;
    if (features.empty()) return per_vertex;
    per_vertex.resize(m.num_vertices);
    // Map input vertex -> working vertex (collapses may have merged some).
    std::vector<int> work_of_input;
    for (int v = 0; v < m.num_vertices; ++v) {
        if (m.input_vertex[v] >= static_cast<int>(work_of_input.size())) work_of_input.resize(m.input_vertex[v] + 1, -1);
        work_of_input[m.input_vertex[v]] = v;
    }
    for (std::size_t i = 0; i < features.size(); ++i) {
        const auto& fe = features[i];
        auto lookup = [&](int x) { return x < static_cast<int>(work_of_input.size()) ? work_of_input[x] : -1; };
        const int a = lookup(fe[0]), b = lookup(fe[1]);
        if (a < 0 || b < 0 || a == b) continue; // merged away by a collapse
        int found = -1;
        for (int h = m.fan_start[a], n = 0; h >= 0 && n < m.fan_size[a]; h = m.cw(h), ++n) {
            if (m.target(h) == b) { found = h; break; }
        }
        if (found < 0)
            for (int h = m.fan_start[b], n = 0; h >= 0 && n < m.fan_size[b]; h = m.cw(h), ++n)
                if (m.target(h) == a) { found = h; break; }
        if (found < 0) {
            error = {ErrorCode::BadFeatureEdge,
                     "feature edge " + std::to_string(i) + " (" + std::to_string(fe[0]) + ", " +
                         std::to_string(fe[1]) + ") is not an edge of the mesh",
                     static_cast<std::int64_t>(i)};
            return {};
        }
        const Point2& p = m.uv[found];
        const Point2& q = m.uv[TriMesh::next(found)];
        // The edge follows the iso-line of the coordinate that changes least along it.
        const int axis = std::abs(q[0] - p[0]) <= std::abs(q[1] - p[1]) ? 0 : 1;
        const double value = std::nearbyint(0.5 * (p[axis] + q[axis]));
        per_vertex[m.origin(found)].push_back({found, axis, value});
        per_vertex[m.target(found)].push_back({TriMesh::next(found), axis, value});
    }
    return per_vertex;
}

} // namespace

Error sanitize(TriMesh& m, const std::vector<int>& given_valences,
               const std::vector<std::array<int, 2>>& feature_edges, Report& report, bool branch_points,
               std::int64_t* deferred) {
    if (deferred) *deferred = 0;
    Error error;
    const auto features = feature_constraints(m, feature_edges, error);
    if (error.code != ErrorCode::None) return error;

    const int nv = m.num_vertices;
    m.map.singular.assign(nv, 0);
    double max_disp = 0.0, sum_disp = 0.0;
    std::int64_t singularities = 0, deferred_count = 0;
    // The first vertex (in vertex_order) whose transitions compose to a pure translation.
    std::int64_t bad = -1;
    GridAutomorphism bad_loop;

    // Fans in corner order (TriMesh::vertex_order). Each vertex reads and writes only its own
    // corners, so neither the order nor the parallel loop changes the result.
    const auto count = static_cast<std::int64_t>(m.vertex_order.size());
#if defined(_OPENMP)
#pragma omp parallel num_threads(m.threads) if (m.parallel(3 * m.num_faces())) reduction(max : max_disp) reduction(+ : sum_disp, singularities, deferred_count)
#endif
    {
    std::vector<int> fan;                 // corners clockwise
    std::vector<GridAutomorphism> to_c;   // chart of fan[0] -> chart of fan[i]
#if defined(_OPENMP)
#pragma omp for schedule(static)
#endif
    for (std::int64_t index = 0; index < count; ++index) {
        const int v = m.vertex_order[static_cast<std::size_t>(index)];
        if (m.fan_start[v] < 0) continue;
        fan.clear();
        for (int h = m.fan_start[v], n = 0; h >= 0 && n < m.fan_size[v]; h = m.cw(h), ++n) fan.push_back(h);
        const bool closed = !m.on_boundary[v];
        // Start at the corner with the smallest UV, so the result does not depend on input order.
        if (closed) {
            const auto first = std::min_element(fan.begin(), fan.end(),
                                                [&](int a, int b) { return m.uv[a] < m.uv[b]; });
            std::rotate(fan.begin(), first, fan.end());
        }
        const std::size_t n = fan.size();
        to_c.assign(n, GridAutomorphism{});
        for (std::size_t i = 1; i < n; ++i) to_c[i] = m.map.transition[fan[i - 1]].after(to_c[i - 1]);
        const GridAutomorphism loop = closed ? m.map.transition[fan[n - 1]].after(to_c[n - 1]) : GridAutomorphism{};

        // With r = 0 only a branch point (valence 8, 12, ...) is singular; without given valences
        // the winding valence decides, since fold-overs inflate Algorithm 8's count (see there).
        const int val = !given_valences.empty() ? given_valences[m.input_vertex[v]] : std::abs(m.map.winding_valence[v]);
        const bool branch = closed && loop.r == 0 && val >= 8;
        if (branch && !branch_points) ++deferred_count;
        const bool singular = closed && (loop.r != 0 || (branch && branch_points));
        if (closed && loop.r == 0 && (loop.tx != 0 || loop.ty != 0)) {
#if defined(_OPENMP)
#pragma omp critical(qex_sanitize_error)
#endif
            if (bad < 0 || index < bad) bad = index, bad_loop = loop;
            continue;
        }

        Point2 u0 = m.uv[fan[0]];
        if (singular) {
            m.map.singular[v] = 1;
            ++singularities;
            u0 = loop.r == 0 ? Point2{std::nearbyint(u0[0]), std::nearbyint(u0[1])} : fixed_point(loop);
        } else {
            if (!features.empty())
                for (const auto& fc : features[v]) {
                    // Express u0 in the constraint's chart, set the coordinate, map back.
                    std::size_t i = std::find(fan.begin(), fan.end(), fc.corner) - fan.begin();
                    Point2 w = to_c[i](u0);
                    w[fc.axis] = fc.value;
                    u0 = to_c[i].inverse()(w);
                }
            // delta: a power of two at least as large as every coordinate of the fan, before and
            // after propagation (translations may dominate tiny coordinates). Truncated to it, u0
            // propagates exactly; the loop only guards against rounding at the boundary.
            double scale = 0.0;
            for (std::size_t i = 0; i < n; ++i) {
                const Point2 p = to_c[i](u0);
                scale = std::max({scale, std::abs(m.uv[fan[i]][0]), std::abs(m.uv[fan[i]][1]), std::abs(p[0]), std::abs(p[1])});
            }
            if (scale > 0.0) {
                int e = 0;
                std::frexp(scale, &e);
                for (int attempt = 0; attempt < 64; ++attempt, ++e) {
                    const double delta = std::ldexp(1.0, e);
                    const Point2 t{truncate(u0[0], delta), truncate(u0[1], delta)};
                    double reach = 0.0;
                    for (std::size_t i = 0; i < n; ++i) {
                        const Point2 p = to_c[i](t);
                        reach = std::max({reach, std::abs(p[0]), std::abs(p[1])});
                    }
                    if (reach <= delta) { u0 = t; break; }
                }
            }
        }
        for (std::size_t i = 0; i < n; ++i) {
            const Point2 p = to_c[i](u0);
            const double d = std::max(std::abs(p[0] - m.uv[fan[i]][0]), std::abs(p[1] - m.uv[fan[i]][1]));
            max_disp = std::max(max_disp, d);
            sum_disp += d;
            m.uv[fan[i]] = p;
        }
    }
    } // parallel region
    if (bad >= 0) {
        const int v = m.vertex_order[static_cast<std::size_t>(bad)];
        return {ErrorCode::InconsistentMap,
                "the transitions around vertex " + std::to_string(m.input_vertex[v]) + " compose to a pure translation by (" +
                    std::to_string(bad_loop.tx) + ", " + std::to_string(bad_loop.ty) +
                    "): the map is not an integer-grid map there",
                m.input_vertex[v]};
    }
    if (deferred) *deferred = deferred_count;
    report.max_sanitization_displacement = std::max(report.max_sanitization_displacement, max_disp);
    report.sum_sanitization_displacement += sum_disp;
    report.singularities = singularities;

    m.map.face_sign.resize(m.num_faces());
#if defined(_OPENMP)
#pragma omp parallel for schedule(static) num_threads(m.threads) if (m.parallel(3 * m.num_faces()))
#endif
    for (int f = 0; f < m.num_faces(); ++f)
        m.map.face_sign[f] = static_cast<signed char>(sign(orient2d(m.uv[3 * f], m.uv[3 * f + 1], m.uv[3 * f + 2])));
    return {};
}

} // namespace qex::detail

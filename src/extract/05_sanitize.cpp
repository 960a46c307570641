// Sanitization of the map (Algorithms 1 and 2, Section 3.2): per vertex, the precision of one
// corner's UV is truncated so that every chart of the fan can represent it exactly, singular
// vertices are snapped to the fixed point of their accumulated transition (branch points to the
// nearest grid point), feature vertices onto their integer iso-line, and the result is
// propagated around the fan with exact transitions.
#include "pipeline.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace qex::detail {
namespace {

// ============================================================================ feature constraints

/// A feature constraint: in the chart of `corner`, coordinate `axis` must equal `value`.
struct FeatureConstraint {
    int corner, axis;
    double value;
};

/// Per vertex: its feature constraints (empty when there are no feature edges).
using FeatureConstraints = std::vector<std::vector<FeatureConstraint>>;

/// Per input vertex: the working vertex that represents it, -1 if none (collapses may have
/// merged some); only as long as the largest represented input vertex needs.
std::vector<int> working_vertex_of_input(const TriMesh& m) {
    std::vector<int> work_of_input;
    for (int v = 0; v < m.num_vertices; ++v) {
        if (m.input_vertex[v] >= static_cast<int>(work_of_input.size()))
            work_of_input.resize(m.input_vertex[v] + 1, -1);
        work_of_input[m.input_vertex[v]] = v;
    }
    return work_of_input;
}

/// A half-edge of the edge between a and b: from a's fan to b if there is one, else from b's
/// fan to a; -1 if a and b share no edge.
int find_half_edge(const TriMesh& m, int a, int b) {
    for (int h = m.fan_start[a], n = 0; h >= 0 && n < m.fan_size[a]; h = m.cw(h), ++n)
        if (m.target(h) == b) return h;
    for (int h = m.fan_start[b], n = 0; h >= 0 && n < m.fan_size[b]; h = m.cw(h), ++n)
        if (m.target(h) == a) return h;
    return -1;
}

/// The constraints of the feature edges (input vertex pairs) on both their ends. Fails, setting
/// `error`, when a feature edge whose ends survived the collapses is not an edge of the mesh.
FeatureConstraints feature_constraints(const TriMesh& m, const std::vector<std::array<int, 2>>& features,
                                       Error& error) {
    FeatureConstraints per_vertex;
    if (features.empty()) return per_vertex;
    per_vertex.resize(m.num_vertices);
    const std::vector<int> work_of_input = working_vertex_of_input(m);
    auto lookup = [&](int x) { return x < static_cast<int>(work_of_input.size()) ? work_of_input[x] : -1; };
    for (std::size_t i = 0; i < features.size(); ++i) {
        const auto& fe = features[i];
        const int a = lookup(fe[0]), b = lookup(fe[1]);
        if (a < 0 || b < 0 || a == b) continue; // merged away by a collapse
        const int found = find_half_edge(m, a, b);
        if (found < 0) {
            error = {ErrorCode::BadFeatureEdge,
                     "feature edge " + std::to_string(i) + " (" + std::to_string(fe[0]) + ", " + std::to_string(fe[1]) +
                         ") is not an edge of the mesh",
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

// ============================================================================ one fan

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

/// The order in which a closed fan's corners compete to start it (walk_fan_corners).
bool fan_corner_less(const TriMesh& m, int a, int b) {
    if (m.uv[a] != m.uv[b]) return m.uv[a] < m.uv[b];
    const int na = TriMesh::next(a), nb = TriMesh::next(b), pa = TriMesh::prev(a), pb = TriMesh::prev(b);
    if (m.pos(na) != m.pos(nb)) return m.pos(na) < m.pos(nb);
    if (m.pos(pa) != m.pos(pb)) return m.pos(pa) < m.pos(pb);
    if (m.uv[na] != m.uv[nb]) return m.uv[na] < m.uv[nb];
    return m.uv[pa] < m.uv[pb];
}

/// A vertex's fan and the transitions between its charts.
struct Fan {
    std::vector<int> corners;           ///< clockwise; a closed fan starts at its canonical corner
    std::vector<GridAutomorphism> to_c; ///< chart of corners[0] -> chart of corners[i]
    GridAutomorphism loop;              ///< once round a closed fan; the identity for an open one
    bool closed = false;                ///< interior vertex
};

/// Walks the fan of vertex v (fan_start[v] >= 0) into `fan`.
void walk_fan(const TriMesh& m, int v, Fan& fan) {
    fan.closed = !m.on_boundary[v];
    // Start at the canonical corner, so the result does not depend on input order: the truncated
    // or snapped UV is computed in the start's chart, and corners in different charts can carry
    // one UV (charts turned about a point within noise of the vertex), so the smallest UV alone
    // does not decide.
    walk_fan_corners(m, v, fan.closed, fan.corners, fan.to_c);
    const std::size_t n = fan.corners.size();
    fan.loop = fan.closed ? m.map.transition[fan.corners[n - 1]].after(fan.to_c[n - 1]) : GridAutomorphism{};
}

/// u0 (in the chart of the fan's first corner) moved onto the iso-lines of the constraints.
Point2 snapped_to_features(Point2 u0, const std::vector<FeatureConstraint>& constraints, const Fan& fan) {
    for (const auto& fc : constraints) {
        // Express u0 in the constraint's chart, set the coordinate, map back.
        std::size_t i = std::find(fan.corners.begin(), fan.corners.end(), fc.corner) - fan.corners.begin();
        Point2 w = fan.to_c[i](u0);
        w[fc.axis] = fc.value;
        u0 = fan.to_c[i].inverse()(w);
    }
    return u0;
}

/// Writes u0 to every corner of the fan through the transitions, accumulating each corner's
/// displacement (maximum norm) into `max_disp` and `sum_disp`.
void propagate(TriMesh& m, const Fan& fan, const Point2& u0, double& max_disp, double& sum_disp) {
    for (std::size_t i = 0; i < fan.corners.size(); ++i) {
        const Point2 p = fan.to_c[i](u0);
        Point2& c = m.uv[fan.corners[i]];
        const double d = std::max(std::abs(p[0] - c[0]), std::abs(p[1] - c[1]));
        max_disp = std::max(max_disp, d);
        sum_disp += d;
        c = p;
    }
}

// ============================================================================ every fan

/// Whether u lies on a grid point up to solver noise (solver_noise_bound, `noise_scale` times).
bool near_grid_point(const Point2& u, double noise_scale) {
    const double off = std::max(std::abs(u[0] - std::nearbyint(u[0])), std::abs(u[1] - std::nearbyint(u[1])));
    return off <= solver_noise_bound(std::max(std::abs(u[0]), std::abs(u[1])), noise_scale);
}

/// What a sanitize call is told besides the mesh.
struct Rules {
    const std::vector<int>& given_valences;
    const FeatureConstraints& features;
    bool branch_points;
};

/// What sanitizing every fan found.
struct Totals {
    double max_disp = 0.0, sum_disp = 0.0;
    std::int64_t singularities = 0, deferred = 0;
    /// The first vertex (index in vertex_order) whose transitions compose to a nonzero pure
    /// translation, -1 if none, and that translation.
    std::int64_t bad = -1;
    GridAutomorphism bad_loop;
};

/// The sanitized UV of the fan's first corner: a singular vertex's snapped position, else u0
/// snapped onto its feature iso-lines and truncated.
Point2 sanitized_start(const TriMesh& m, int v, const Fan& fan, bool singular, const Rules& rules) {
    const Point2 u0 = m.uv[fan.corners[0]];
    if (singular) return fan.loop.r == 0 ? Point2{std::nearbyint(u0[0]), std::nearbyint(u0[1])} : fixed_point(fan.loop);
    return truncated_for_fan(m, fan.corners, fan.to_c,
                             rules.features.empty() ? u0 : snapped_to_features(u0, rules.features[v], fan));
}

/// Sanitizes the fan of vertex_order[index] (unless its loop is a nonzero pure translation),
/// adding to the totals `t`.
void sanitize_one(TriMesh& m, const Rules& rules, std::int64_t index, Fan& fan, Totals& t) {
    const int v = m.vertex_order[static_cast<std::size_t>(index)];
    if (m.fan_start[v] < 0) return;
    walk_fan(m, v, fan);
    const GridAutomorphism& loop = fan.loop;
    // With r = 0 only a branch point (valence 8, 12, ...) is singular; without given valences
    // the winding valence decides, since fold-overs inflate Algorithm 8's count (see there).
    // A fold can wind a fan twice too, with or without a flipped triangle: without given
    // valences, a vertex off every grid point by more than solver noise is read as such a
    // fold, not snapped (a solver puts its branch points on grid points; snapping would
    // move an exact map by up to half a cell). It stays a regular vertex: the repair
    // unfolds its flipped triangles, if it has any; the paper's handling takes the rest.
    const bool given = !rules.given_valences.empty();
    const int val = given ? rules.given_valences[m.input_vertex[v]] : std::abs(m.map.winding_valence[v]);
    const bool branch =
        fan.closed && loop.r == 0 && val >= 8 && (given || near_grid_point(m.uv[fan.corners[0]], m.noise_scale));
    if (branch && !rules.branch_points) ++t.deferred;
    const bool singular = fan.closed && (loop.r != 0 || (branch && rules.branch_points));
    if (fan.closed && loop.r == 0 && (loop.tx != 0 || loop.ty != 0)) {
        if (t.bad < 0) t.bad = index, t.bad_loop = loop;
        return;
    }
    if (singular) {
        m.map.singular[v] = 1;
        ++t.singularities;
    }
    propagate(m, fan, sanitized_start(m, v, fan, singular, rules), t.max_disp, t.sum_disp);
}

/// Vertices per block of sanitize_fans' totals.
constexpr std::int64_t kTotalsBlock = std::int64_t{1} << 12;

/// Sanitizes every fan, in corner order (TriMesh::vertex_order). Each vertex reads and writes
/// only its own corners, so neither the order nor the parallel loop changes the result. The
/// totals are kept per fixed block of vertices and joined in block order: the same bits for any
/// thread count. A fan whose loop is a nonzero pure translation stays as it is.
Totals sanitize_fans(TriMesh& m, const Rules& rules) {
    const auto count = static_cast<std::int64_t>(m.vertex_order.size());
    const std::int64_t blocks = (count + kTotalsBlock - 1) / kTotalsBlock;
    std::vector<Totals> of_block(static_cast<std::size_t>(blocks));
    const int parts =
        static_cast<int>(std::min<std::int64_t>(m.parts(3 * m.num_faces()), std::max<std::int64_t>(blocks, 1)));
    for_parts(parts, parts, blocks, [&](int, std::int64_t first, std::int64_t last) {
        Fan fan;
        for (std::int64_t b = first; b < last; ++b)
            for (std::int64_t i = b * kTotalsBlock; i < std::min(count, (b + 1) * kTotalsBlock); ++i)
                sanitize_one(m, rules, i, fan, of_block[static_cast<std::size_t>(b)]);
    });
    Totals all; // the blocks in order: the first bad vertex is the serial pass's
    for (const Totals& t : of_block) {
        all.max_disp = std::max(all.max_disp, t.max_disp);
        all.sum_disp += t.sum_disp;
        all.singularities += t.singularities;
        all.deferred += t.deferred;
        if (all.bad < 0 && t.bad >= 0) all.bad = t.bad, all.bad_loop = t.bad_loop;
    }
    return all;
}

/// The error for the vertex at vertex_order[bad], whose transitions compose to the pure
/// translation `loop`.
Error pure_translation_error(const TriMesh& m, std::int64_t bad, const GridAutomorphism& loop) {
    const int v = m.vertex_order[static_cast<std::size_t>(bad)];
    return {ErrorCode::InconsistentMap,
            "the transitions around vertex " + std::to_string(m.input_vertex[v]) +
                " compose to a pure translation by (" + std::to_string(loop.tx) + ", " + std::to_string(loop.ty) +
                "): the map is not an integer-grid map there",
            m.input_vertex[v]};
}

/// MapState::face_sign of every triangle, from the sanitized UVs.
void set_face_signs(TriMesh& m) { m.map.face_sign = triangle_signs(m); }

} // namespace

void walk_fan_corners(const TriMesh& m, int v, bool canonical_start, std::vector<int>& corners,
                      std::vector<GridAutomorphism>& to_c) {
    corners.clear();
    corners.reserve(static_cast<std::size_t>(std::max(m.fan_size[v], 0)));
    for (int h = m.fan_start[v], n = 0; h >= 0 && n < m.fan_size[v]; h = m.cw(h), ++n) corners.push_back(h);
    if (canonical_start)
        std::rotate(
            corners.begin(),
            std::min_element(corners.begin(), corners.end(), [&](int a, int b) { return fan_corner_less(m, a, b); }),
            corners.end());
    to_c.assign(corners.size(), GridAutomorphism{});
    for (std::size_t i = 1; i < corners.size(); ++i) to_c[i] = m.map.transition[corners[i - 1]].after(to_c[i - 1]);
}

Point2 truncated_for_fan(const TriMesh& m, const std::vector<int>& corners, const std::vector<GridAutomorphism>& to_c,
                         Point2 u0, double headroom) {
    const std::size_t n = corners.size();
    double scale = headroom;
    for (std::size_t i = 0; i < n; ++i) {
        const Point2 p = to_c[i](u0);
        const Point2& c = m.uv[corners[i]];
        scale = std::max({scale, std::abs(c[0]), std::abs(c[1]), std::abs(p[0]), std::abs(p[1])});
    }
    if (!(scale > 0.0)) return u0;
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
        if (reach + headroom <= delta) return t;
    }
    return u0;
}

Error sanitize(TriMesh& m, const std::vector<int>& given_valences, const std::vector<std::array<int, 2>>& feature_edges,
               Report& report, bool branch_points, std::int64_t* deferred) {
    if (deferred) *deferred = 0;
    Error error;
    const FeatureConstraints features = feature_constraints(m, feature_edges, error);
    if (error.code != ErrorCode::None) return error;

    m.map.singular.assign(m.num_vertices, 0);
    const Totals totals = sanitize_fans(m, Rules{given_valences, features, branch_points});
    if (totals.bad >= 0) return pure_translation_error(m, totals.bad, totals.bad_loop);
    if (deferred) *deferred = totals.deferred;
    report.max_sanitization_displacement = std::max(report.max_sanitization_displacement, totals.max_disp);
    report.sum_sanitization_displacement += totals.sum_disp;
    report.singularities = totals.singularities;
    set_face_signs(m);
    return {};
}

} // namespace qex::detail

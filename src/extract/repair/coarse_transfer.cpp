// The repair on the coarse triangulation, written back onto the given one: the dipole merges'
// transitions along the fine edges of their paths, the moved vertices' UVs, the others
// interpolated in their coarse triangles, each checked on the given triangles (coarse.h).
#include "extract/repair/coarse.h"

#include "extract/repair/certificates.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace qex::detail::repair_impl {
namespace {

/// Most fine edges along one coarse edge (a guard: a subdivision level doubles them).
constexpr int kMaxChain = 1 << 12;

/// The coarse map as the repair found it: what it changed is what differs.
struct Start {
    std::vector<Point2> uv;
    std::vector<GridAutomorphism> transition;
};

/// What the transfer changes in the given mesh, to put it back.
struct Saved {
    std::vector<Point2> uv;
    std::vector<std::pair<int, GridAutomorphism>> transitions; ///< half-edges, in the order changed
    std::vector<int> valence, winding_valence;
    std::vector<char> singular;
    std::vector<signed char> face_sign;
};

Saved save(const TriMesh& m) {
    return {m.uv, {}, m.map.valence, m.map.winding_valence, m.map.singular, m.map.face_sign};
}

void restore(TriMesh& m, Saved& s) {
    m.uv = s.uv;
    for (std::size_t i = s.transitions.size(); i-- > 0;)
        m.map.transition.set(static_cast<std::size_t>(s.transitions[i].first), s.transitions[i].second);
    s.transitions.clear();
    m.map.valence = s.valence;
    m.map.winding_valence = s.winding_valence;
    m.map.singular = s.singular;
    m.map.face_sign = s.face_sign;
}

/// Where p lies along a -> b, from 0 to 1 (3D).
double along(const Vec3& a, const Vec3& b, const Vec3& p) {
    const Vec3 d{b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    return ((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1] + (p[2] - a[2]) * d[2]) /
           (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
}

/// The fine half-edges along coarse half-edge h, from its origin to its target (through vertices
/// the coarse triangulation does without, on the segment). False if there is no such path.
bool fine_chain(const TriMesh& m, const CoarseMap& cm, int h, std::vector<int>& chain) {
    const TriMesh& c = cm.mesh;
    const int a = c.origin(h), b = c.target(h);
    const Vec3 &pa = c.pos(h), &pb = c.pos(TriMesh::next(h));
    chain.clear();
    double at = 0.0;
    for (int v = a; v != b && static_cast<int>(chain.size()) < kMaxChain;) {
        int step = -1;
        double reach = 1.0 + 1e-9;
        for (int e = m.fan_start[v], n = 0; e >= 0 && n < m.fan_size[v]; e = m.cw(e), ++n) {
            const int x = m.target(e);
            if (x != b && cm.host[x] < 0) continue;
            const double t = x == b ? 1.0 : along(pa, pb, m.pos(TriMesh::next(e)));
            // On the segment: its distance from the line well below the edge's length.
            const Vec3& p = m.pos(TriMesh::next(e));
            Vec3 off{};
            for (int d = 0; d < 3; ++d) off[d] = p[d] - (pa[d] + t * (pb[d] - pa[d]));
            const double l2 = (pb[0] - pa[0]) * (pb[0] - pa[0]) + (pb[1] - pa[1]) * (pb[1] - pa[1]) +
                              (pb[2] - pa[2]) * (pb[2] - pa[2]);
            if (off[0] * off[0] + off[1] * off[1] + off[2] * off[2] > 1e-12 * l2) continue;
            if (t > at + 1e-12 && t < reach) reach = t, step = e;
        }
        if (step < 0) return false;
        chain.push_back(step);
        at = reach;
        v = m.target(step);
    }
    return !chain.empty() && m.target(chain.back()) == b;
}

/// How far a fitted chart map may miss: the coarse map is the fine one only up to what
/// sanitization moved (singularities and seams onto exact values, well below 1e-5 cells), and a
/// wrong rotation misses by about the edge's length.
double fit_tolerance(const Point2& p, const Point2& q) {
    return std::min(1e-4, 0.1 * std::max(std::abs(q[0] - p[0]), std::abs(q[1] - p[1])));
}

/// The grid automorphism taking p -> pc and q -> qc (p != q), up to that; false if none does.
bool fit(const Point2& p, const Point2& q, const Point2& pc, const Point2& qc, GridAutomorphism& g) {
    double best = 1e300;
    for (int r = 0; r < 4; ++r) {
        const Point2 d = GridAutomorphism::rotate(Point2{q[0] - p[0], q[1] - p[1]}, r);
        const double miss = std::max(std::abs(d[0] - (qc[0] - pc[0])), std::abs(d[1] - (qc[1] - pc[1])));
        if (miss < best) best = miss, g.r = r;
    }
    const Point2 rp = GridAutomorphism::rotate(p, g.r);
    g.tx = std::llround(pc[0] - rp[0]);
    g.ty = std::llround(pc[1] - rp[1]);
    const Point2 gp = g(p), gq = g(q);
    return std::max({std::abs(gp[0] - pc[0]), std::abs(gp[1] - pc[1]), std::abs(gq[0] - qc[0]),
                     std::abs(gq[1] - qc[1])}) <= fit_tolerance(p, q);
}

/// The dipole merges' transitions on the fine edges along the coarse edges whose transitions the
/// repair changed: per fine edge, its triangles' charts fitted to the coarse triangles' along the
/// edge, the coarse change carried through them. Their vertices go in `touched`.
bool move_transitions(TriMesh& m, const CoarseMap& cm, const Start& start, Saved& saved, std::vector<int>& touched) {
    const TriMesh& c = cm.mesh;
    std::vector<int> chain;
    for (int h = 0; h < 3 * c.num_faces(); ++h) {
        const int o = c.opp[h];
        if (o < h || c.map.transition[h] == start.transition[h]) continue;
        if (!fine_chain(m, cm, h, chain)) return false;
        const Point2 &ua = start.uv[h], &ub = start.uv[TriMesh::next(h)];
        const Point2 &va = start.uv[TriMesh::next(o)], &vb = start.uv[o];
        const Vec3 &pa = c.pos(h), &pb = c.pos(TriMesh::next(h));
        for (const int e : chain) {
            const double s = along(pa, pb, m.pos(e)), t = along(pa, pb, m.pos(TriMesh::next(e)));
            const auto lerp = [](const Point2& x, const Point2& y, double w) {
                return Point2{x[0] + w * (y[0] - x[0]), x[1] + w * (y[1] - x[1])};
            };
            const int eo = m.opp[e];
            GridAutomorphism k1, k2; // the fine triangles' charts -> the coarse ones'
            if (eo < 0 || !fit(m.uv[e], m.uv[TriMesh::next(e)], lerp(ua, ub, s), lerp(ua, ub, t), k1) ||
                !fit(m.uv[TriMesh::next(eo)], m.uv[eo], lerp(va, vb, s), lerp(va, vb, t), k2))
                return false;
            if (!(start.transition[h].after(k1) == k2.after(m.map.transition[e]))) return false;
            const GridAutomorphism now = k2.inverse().after(c.map.transition[h].after(k1));
            saved.transitions.push_back({e, m.map.transition[e]});
            saved.transitions.push_back({eo, m.map.transition[eo]});
            m.map.transition.set(static_cast<std::size_t>(e), now);
            m.map.transition.set(static_cast<std::size_t>(eo), now.inverse());
            touched.push_back(m.origin(e)), touched.push_back(m.target(e));
        }
    }
    return true;
}

/// Writes x (in the chart of v's corner `corner`) to every corner of v, truncated to propagate.
void write_vertex(TriMesh& m, int v, int corner, const Point2& x) {
    const FreeFan fan = free_fan(m, v);
    const auto k =
        static_cast<std::size_t>(std::find(fan.corners.begin(), fan.corners.end(), corner) - fan.corners.begin());
    place(m, fan, fan.to_c[k].inverse()(x));
}

/// The vertices whose UVs the coarse repair changed: free coarse vertices it moved, the
/// vertices their triangles hold, and the ends of the fine edges whose transitions changed.
std::vector<int> changed_vertices(const CoarseMap& cm, const Start& start, std::vector<int> touched) {
    const TriMesh& c = cm.mesh;
    std::vector<char> moved(static_cast<std::size_t>(c.num_faces()), 0);
    for (int h = 0; h < 3 * c.num_faces(); ++h)
        if (c.uv[h] != start.uv[h]) moved[TriMesh::face(h)] = 1, touched.push_back(c.origin(h));
    for (int v = 0; v < c.num_vertices; ++v)
        if (cm.host[v] >= 0 && moved[cm.host[v]]) touched.push_back(v);
    std::sort(touched.begin(), touched.end());
    touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
    return touched;
}

/// Where p lies in coarse triangle t: its 3D barycentric coordinates; false if degenerate.
bool coordinates(const TriMesh& c, int t, const Vec3& p, std::array<double, 3>& l) {
    return barycentric3(c.pos(3 * t), c.pos(3 * t + 1), c.pos(3 * t + 2), p, l);
}

/// Coarse triangle t's map (its UVs in `uv`, coarse corner by corner) at coordinates l.
Point2 coarse_at(const std::vector<Point2>& uv, int t, const std::array<double, 3>& l) {
    Point2 x{0.0, 0.0};
    for (int k = 0; k < 3; ++k)
        for (int d = 0; d < 2; ++d) x[d] += l[k] * uv[3 * t + k][d];
    return x;
}

/// The map from fine triangle f's chart to coarse triangle t's, fitted to their UVs before the
/// repair (`given`, and the coarse `start`): the chart relation the fans would give, but without
/// walking round a cone (whose way round matters) or across a seam a merge glued anew.
bool chart_to(const TriMesh& m, const CoarseMap& cm, const Start& start, const std::vector<Point2>& given, int f, int t,
              GridAutomorphism& g) {
    std::array<Point2, 3> x;
    for (int k = 0; k < 3; ++k) {
        std::array<double, 3> l{};
        if (!coordinates(cm.mesh, t, m.pos(3 * f + k), l)) return false;
        x[k] = coarse_at(start.uv, t, l);
    }
    if (!fit(given[3 * f], given[3 * f + 1], x[0], x[1], g)) return false;
    const Point2 third = g(given[3 * f + 2]);
    return std::max(std::abs(third[0] - x[2][0]), std::abs(third[1] - x[2][1])) <=
           fit_tolerance(given[3 * f], given[3 * f + 1]);
}

/// Where v lies in coarse triangle t: its corner there, or its coordinates in t (those below
/// rounding set to 0, so that a vertex on an edge depends on that edge's ends alone).
std::array<double, 3> weights(const TriMesh& m, const TriMesh& c, int v, int t, int corner) {
    std::array<double, 3> l{0.0, 0.0, 0.0};
    for (int k = 0; k < 3; ++k)
        if (c.tri[t][k] == v) {
            l[k] = 1.0;
            return l;
        }
    if (!coordinates(c, t, m.pos(corner), l)) return {-1.0, -1.0, -1.0};
    double sum = 0.0;
    for (double& x : l) sum += x = std::abs(x) < 1e-9 ? 0.0 : x;
    for (double& x : l) x /= sum;
    return l;
}

/// v's UV as the coarse map now gives it, written to its corners (through the chart of a fine
/// triangle round v that lies in the coarse one): its own in a coarse triangle round it if kept,
/// else interpolated in the one that holds it. Nothing is written where that depends only on
/// coarse vertices the repair left (an edge's vertices stay as they were, bit for bit), unless
/// `glued`: v's fan crosses an edge whose transition changed, so all its corners are written anew.
bool write_from_coarse(TriMesh& m, const CoarseMap& cm, const Start& start, const std::vector<Point2>& given, int v,
                       bool glued) {
    const TriMesh& c = cm.mesh;
    if (cm.host[v] < 0 && (c.on_boundary[v] || m.map.singular[v])) return true; // fixed
    std::vector<int> near{cm.host[v]};
    if (cm.host[v] < 0) {
        near.clear();
        for (int h = c.fan_start[v], n = 0; h >= 0 && n < c.fan_size[v]; h = c.cw(h), ++n)
            near.push_back(TriMesh::face(h));
    }
    for (int h = m.fan_start[v], n = 0; h >= 0 && n < m.fan_size[v]; h = m.cw(h), ++n)
        for (const int t : near) {
            GridAutomorphism g;
            if (!chart_to(m, cm, start, given, TriMesh::face(h), t, g)) continue;
            const std::array<double, 3> l = weights(m, c, v, t, h);
            if (l[0] < 0.0) continue;
            bool changed = false;
            for (int k = 0; k < 3; ++k) changed = changed || (l[k] != 0.0 && c.uv[3 * t + k] != start.uv[3 * t + k]);
            if (changed || glued) write_vertex(m, v, h, g.inverse()(coarse_at(c.uv, t, l)));
            return true;
        }
    return false;
}

/// Whether m keeps what the coarse repair certified round the written vertices: every triangle
/// whose UVs changed is positive (the certificate says so of each), and a written vertex with a
/// positive fan winds by its target.
bool still_holds(const TriMesh& m, const std::vector<Point2>& given, const std::vector<int>& written) {
    for (const int v : written) {
        bool all = true;
        double sum = 0.0;
        for (int h = m.fan_start[v], n = 0; h >= 0 && n < m.fan_size[v]; h = m.cw(h), ++n) {
            const int f = TriMesh::face(h);
            const bool ok = positive(m, f);
            bool changed = false;
            for (int k = 0; k < 3; ++k) changed = changed || m.uv[3 * f + k] != given[3 * f + k];
            if (!ok && changed) return false;
            all = all && ok;
            sum += corner_angle(m, h);
        }
        if (all && !m.on_boundary[v] && std::abs(sum - target_angle(m, v)) > 1.0) return false;
    }
    return true;
}

/// The coarse map written back onto m: transitions, valences, the UVs of the vertices it changed;
/// false if m does not keep what the coarse repair certified.
bool transfer(TriMesh& m, const CoarseMap& cm, const Start& start, Saved& saved) {
    const TriMesh& c = cm.mesh;
    std::vector<int> touched;
    if (!move_transitions(m, cm, start, saved, touched)) return false;
    for (int v = 0; v < m.num_vertices; ++v)
        if (c.fan_start[v] >= 0) {
            m.map.valence[v] = c.map.valence[v];
            m.map.winding_valence[v] = c.map.winding_valence[v];
            m.map.singular[v] = c.map.singular[v];
        }
    std::vector<char> glued(static_cast<std::size_t>(m.num_vertices), 0);
    for (const int v : touched) glued[v] = 1;
    const std::vector<int> written = changed_vertices(cm, start, std::move(touched));
    for (const int v : written)
        if (!write_from_coarse(m, cm, start, saved.uv, v, glued[v] != 0)) return false;
    return still_holds(m, saved.uv, written);
}

} // namespace

bool repair_coarse(TriMesh& m, const std::vector<char>& pinned, const RepairAt& repair_at, Report& report,
                   const LookBeforeLastRing& look, RepairOutcome& out) {
    CoarseMap cm;
    if (!coarsen(m, pinned, cm)) return false;
    Start start{cm.mesh.uv, {}};
    for (int h = 0; h < 3 * cm.mesh.num_faces(); ++h) start.transition.push_back(cm.mesh.map.transition[h]);
    LookBeforeLastRing coarse_look;
    if (look)
        coarse_look = [&](const TriMesh&, const RepairOutcome& so_far) {
            // The look is at m as the coarse map written back would leave it; m is put back after.
            Saved saved = save(m);
            RepairLook seen;
            if (transfer(m, cm, start, saved)) seen = look(m, fine_outcome(m, saved.uv, cm, so_far));
            restore(m, saved);
            seen.near = coarse_near(cm, seen.near);
            return seen;
        };
    Report scratch;
    const RepairOutcome coarse = repair_at(cm.mesh, scratch, coarse_look);
    Saved saved = save(m);
    if (!transfer(m, cm, start, saved)) {
        restore(m, saved);
        return false;
    }
    report.explanations.insert(report.explanations.end(), scratch.explanations.begin(), scratch.explanations.end());
    out = fine_outcome(m, saved.uv, cm, coarse);
    return true;
}

} // namespace qex::detail::repair_impl

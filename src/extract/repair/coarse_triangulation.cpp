// The repair's coarse triangulation: the vertices the map does not need, removed by collapses that
// keep the map, in an order that depends neither on the input's nor on its charts (coarse.h).
#include "extract/repair/coarse.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>

namespace qex::detail::repair_impl {
namespace {

/// Relative tolerance of "affine in the map": above what sanitization moves a subdivided map's
/// singularities and seams by (up to 3e-7 cells on edges of 0.05 on the twice-subdivided duck),
/// and only ever asked where the star is flat in space (fandisk's 1,810 flat vertices miss it).
constexpr double kAffine = 1e-5;
/// Two unit normals this close are one plane (a candidate's precheck; the collapse checks again).
constexpr double kSamePlane = 1e-6;
/// A triangle a collapse makes must keep this much of the squared longest edge of the star as
/// twice its area: no slivers.
constexpr double kMinArea = 1e-6;
/// Passes over the candidates: a guard, as each pass tries only the vertices whose stars changed.
constexpr int kMaxPasses = 16;

/// A triangle of the coarsening: per corner its vertex, a corner of that vertex in the given mesh,
/// and the map from that corner's chart to this triangle's.
struct Tri {
    std::array<int, 3> v, ref;
    std::array<GridAutomorphism, 3> g;
    bool alive = true;
};

/// The collapses' state: the triangles, per vertex the triangles round it (dead ones dropped when
/// met) and the vertex it went onto, and each collapse's scratch.
struct State {
    const TriMesh& m;
    std::vector<Tri> tris;
    std::vector<std::vector<int>> around;
    std::vector<int> onto;      ///< per vertex: the vertex it was collapsed onto, -1 if kept
    std::vector<VertexKey> key; ///< per vertex, once asked for (keyed)
    std::vector<char> keyed;
    std::vector<char> dirty; ///< per vertex: its star changed since it was last tried
    std::vector<char> seam;  ///< per vertex: a transition in its fan is not the identity

    Point2 uv(int t, int k) const { return tris[t].g[k](m.uv[tris[t].ref[k]]); }
    const Vec3& pos(int t, int k) const { return m.pos(tris[t].ref[k]); }
    int corner_of(int t, int v) const {
        const auto& a = tris[t].v;
        return static_cast<int>(std::find(a.begin(), a.end(), v) - a.begin());
    }
    const std::vector<int>& star(int v) {
        std::vector<int>& a = around[v];
        a.erase(std::remove_if(a.begin(), a.end(), [&](int t) { return !tris[t].alive; }), a.end());
        return a;
    }
    const VertexKey& key_of(int v) {
        if (!keyed[v]) key[v] = vertex_key(m, v), keyed[v] = 1;
        return key[v];
    }
    void neighbours(int v, std::vector<int>& n) {
        n.clear();
        for (const int t : star(v))
            for (const int x : tris[t].v)
                if (x != v) n.push_back(x);
        std::sort(n.begin(), n.end());
        n.erase(std::unique(n.begin(), n.end()), n.end());
    }

    // Scratch of one collapse (kept across them: no allocation per vertex): v's star, its
    // neighbours, the targets, the star triangles' charts to the first's, its longest edge in
    // space and in the map.
    std::vector<int> star_of_v, nv, to, both, opposite, plane_of;
    std::vector<char> mark; ///< per vertex, 0 between uses
    double l3 = 0.0, luv = 0.0;
    std::vector<GridAutomorphism> a;
    std::vector<Vec3> planes;
    Fan fan;
};

/// What a collapse of v onto w takes: w's corner, and the map from its chart to the first star
/// triangle's.
struct Plan {
    int ref_w = -1;
    GridAutomorphism g_w;
};

/// Whether collapsing v onto w keeps the map: an interior edge whose link is its two opposite
/// vertices, and every triangle of v's star not at w, with v replaced by w, still in the plane of
/// that triangle, positive there, and with w where its affine map puts w (s.a maps each star
/// triangle's chart to the first's; s.l3 and s.luv are the star's scales). The triangles left
/// then cover v's star as before, each in one plane with one affine map.
bool plan_collapse(State& s, int v, int w, Plan& plan) {
    const std::vector<int>& star = s.star_of_v;
    const std::vector<GridAutomorphism>& a = s.a;
    std::vector<int>&both = s.both, &opposite = s.opposite;
    both.clear(), opposite.clear();
    for (std::size_t i = 0; i < star.size(); ++i) {
        const int k = s.corner_of(star[i], w);
        if (k == 3) continue;
        both.push_back(static_cast<int>(i));
        for (const int x : s.tris[star[i]].v)
            if (x != v && x != w) opposite.push_back(x);
    }
    if (both.size() != 2) return false;
    // The link condition: v and w share no neighbour but the two opposite vertices.
    for (const int x : s.nv) s.mark[x] = 1;
    int shared = 0;
    for (const int t : s.star(w))
        for (const int x : s.tris[t].v)
            if (s.mark[x] == 1 && x != v && x != w) s.mark[x] = 2, ++shared;
    bool link = shared == 2;
    for (const int x : opposite) link = link && s.mark[x] == 2;
    for (const int x : s.nv) s.mark[x] = 0;
    if (!link) return false;
    const int u = star[static_cast<std::size_t>(both[0])], kw = s.corner_of(u, w);
    plan.ref_w = s.tris[u].ref[kw];
    plan.g_w = a[static_cast<std::size_t>(both[0])].after(s.tris[u].g[kw]);
    const Point2 uw = plan.g_w(s.m.uv[plan.ref_w]);
    const Vec3& pw = s.m.pos(plan.ref_w);
    const double l3 = s.l3, luv = s.luv;
    for (std::size_t i = 0; i < star.size(); ++i) {
        const int t = star[i], kv = s.corner_of(t, v);
        if (s.corner_of(t, w) != 3) continue;
        const int kx = (kv + 1) % 3, ky = (kv + 2) % 3;
        const Vec3 &px = s.pos(t, kx), &py = s.pos(t, ky), &pv = s.pos(t, kv);
        const Vec3 n = cross(minus(px, pv), minus(py, pv));
        const double nn = std::sqrt(dot(n, n));
        if (!(nn > 0.0) || std::abs(dot(n, minus(pw, pv))) > kFlat * l3 * nn) return false;
        if (!(dot(cross(minus(px, pw), minus(py, pw)), n) > kMinArea * l3 * l3 * nn)) return false;
        std::array<double, 3> l{};
        if (!barycentric3(pv, px, py, pw, l)) return false;
        const Point2 uv_v = a[i](s.uv(t, kv)), uv_x = a[i](s.uv(t, kx)), uv_y = a[i](s.uv(t, ky));
        for (int d = 0; d < 2; ++d)
            if (std::abs(l[0] * uv_v[d] + l[1] * uv_x[d] + l[2] * uv_y[d] - uw[d]) > kAffine * luv) return false;
    }
    return true;
}

/// The neighbours of v a collapse may take it to: all of them where its star is one plane, those
/// on the line where its two planes meet, none where it has more (most vertices of a real map).
void targets(State& s) {
    const std::vector<int>& star = s.star_of_v;
    std::vector<Vec3>& planes = s.planes;
    std::vector<int>&plane_of = s.plane_of, &out = s.to;
    planes.clear(), plane_of.clear(), out.clear();
    for (const int t : star) {
        const Vec3 n = cross(minus(s.pos(t, 1), s.pos(t, 0)), minus(s.pos(t, 2), s.pos(t, 0)));
        const double l = std::sqrt(dot(n, n));
        if (!(l > 0.0)) return;
        const Vec3 u{n[0] / l, n[1] / l, n[2] / l};
        std::size_t i = 0;
        while (i < planes.size() && std::sqrt(dot(minus(planes[i], u), minus(planes[i], u))) > kSamePlane) ++i;
        if (i == planes.size()) planes.push_back(u);
        if (planes.size() > 2) return;
        plane_of.push_back(static_cast<int>(i));
    }
    for (std::size_t j = 0; j < star.size(); ++j)
        for (const int x : s.tris[star[j]].v) s.mark[x] |= static_cast<char>(1 << plane_of[j]);
    for (const int w : s.nv)
        if (planes.size() == 1 || s.mark[w] == 3) out.push_back(w);
    for (const int t : star)
        for (const int x : s.tris[t].v) s.mark[x] = 0;
    for (const int w : out) s.key_of(w);
    std::sort(out.begin(), out.end(), [&](int x, int y) { return s.key[x] < s.key[y]; });
}

/// Collapses v onto the first of its neighbours (in vertex-key order) that keeps the map.
bool collapse(State& s, int v) {
    s.star_of_v = s.star(v);
    const std::vector<int>& star = s.star_of_v;
    if (star.size() < 3) return false;
    s.neighbours(v, s.nv);
    targets(s);
    if (s.to.empty()) return false;
    // Each star triangle's chart to the first's, through v's corners (one chart where no seam
    // crosses v's fan, as for most vertices a subdivision added).
    const bool seam = s.seam[v] != 0;
    if (seam) walk_fan_corners(s.m, v, false, s.fan.corners, s.fan.to_c);
    std::vector<GridAutomorphism>& a = s.a;
    a.clear();
    const int k0 = s.corner_of(star[0], v);
    for (const int t : star) {
        const int k = s.corner_of(t, v);
        const GridAutomorphism through =
            seam ? s.fan.between(s.tris[t].ref[k], s.tris[star[0]].ref[k0]) : GridAutomorphism{};
        a.push_back(s.tris[star[0]].g[k0].after(through.after(s.tris[t].g[k].inverse())));
    }
    s.l3 = s.luv = 0.0;
    for (std::size_t i = 0; i < star.size(); ++i)
        for (int k = 0; k < 3; ++k) {
            const Vec3 e = minus(s.pos(star[i], k), s.pos(star[i], (k + 1) % 3));
            s.l3 = std::max(s.l3, std::sqrt(dot(e, e)));
            const Point2 p = a[i](s.uv(star[i], k)), q = a[i](s.uv(star[i], (k + 1) % 3));
            s.luv = std::max({s.luv, std::abs(p[0] - q[0]), std::abs(p[1] - q[1])});
        }
    for (const int w : s.to) {
        Plan plan;
        if (!plan_collapse(s, v, w, plan)) continue;
        for (const int x : s.nv) s.dirty[x] = 1;
        for (std::size_t i = 0; i < star.size(); ++i) {
            Tri& t = s.tris[star[i]];
            const int k = s.corner_of(star[i], w);
            if (k != 3) {
                t.alive = false;
                continue;
            }
            const int kv = s.corner_of(star[i], v);
            t.v[kv] = w, t.ref[kv] = plan.ref_w, t.g[kv] = a[i].inverse().after(plan.g_w);
            s.around[w].push_back(star[i]);
        }
        s.onto[v] = w;
        return true;
    }
    return false;
}

/// Whether v may go: free, its fan closed, all its corners at one point in space, and its
/// triangles in at most two planes (a collapse keeps the part of the surface a star covers, so a
/// vertex whose star is not flat now never is: most vertices of a real map stop here).
bool candidate(const TriMesh& m, const std::vector<char>& pinned, int v) {
    if (pinned[v] || m.fan_start[v] < 0 || m.on_boundary[v]) return false;
    std::array<Vec3, 2> planes{};
    int found = 0;
    for (int h = m.fan_start[v], n = 0; h >= 0 && n < m.fan_size[v]; h = m.cw(h), ++n) {
        if (m.pos(h) != m.pos(m.fan_start[v])) return false;
        const Vec3 c = cross(minus(m.pos(TriMesh::next(h)), m.pos(h)), minus(m.pos(TriMesh::prev(h)), m.pos(h)));
        const double l = std::sqrt(dot(c, c));
        if (!(l > 0.0)) return false;
        const Vec3 u{c[0] / l, c[1] / l, c[2] / l};
        int i = 0;
        while (i < found && std::sqrt(dot(minus(planes[i], u), minus(planes[i], u))) > kSamePlane) ++i;
        if (i == 2) return false;
        if (i == found) planes[found++] = u;
    }
    return true;
}

/// The candidates along a space-filling (Morton) curve through their positions, then by vertex
/// key: an order that depends neither on the input's nor on its charts, in which consecutive
/// collapses lie near each other on the surface.
void in_space_order(const TriMesh& m, std::vector<int>& order) {
    Vec3 lo = m.vertex_pos(order[0]), hi = lo;
    for (const int v : order)
        for (int d = 0; d < 3; ++d)
            lo[d] = std::min(lo[d], m.vertex_pos(v)[d]), hi[d] = std::max(hi[d], m.vertex_pos(v)[d]);
    std::vector<std::pair<std::uint64_t, int>> coded;
    for (const int v : order) {
        std::uint64_t code = 0;
        for (int d = 0; d < 3; ++d) {
            const double span = hi[d] > lo[d] ? hi[d] - lo[d] : 1.0;
            const auto q = static_cast<std::uint64_t>((m.vertex_pos(v)[d] - lo[d]) / span * 2097151.0);
            for (int b = 0; b < 21; ++b) code |= ((q >> b) & 1u) << (3 * b + d);
        }
        coded.push_back({code, v});
    }
    std::sort(coded.begin(), coded.end(), [&](const auto& a, const auto& b) {
        return a.first != b.first ? a.first < b.first : vertex_key(m, a.second) < vertex_key(m, b.second);
    });
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = coded[i].second;
}

} // namespace

bool coarsen(const TriMesh& m, const std::vector<char>& pinned, CoarseMap& out) {
    std::vector<int> order;
    for (int v = 0; v < m.num_vertices; ++v)
        if (candidate(m, pinned, v)) order.push_back(v);
    if (order.empty()) return false;
    in_space_order(m, order);
    State s{m, {}, std::vector<std::vector<int>>(static_cast<std::size_t>(m.num_vertices)), {}, {}, {}};
    s.key.resize(static_cast<std::size_t>(m.num_vertices));
    s.keyed.assign(static_cast<std::size_t>(m.num_vertices), 0);
    s.mark.assign(static_cast<std::size_t>(m.num_vertices), 0);
    s.dirty.assign(static_cast<std::size_t>(m.num_vertices), 1);
    s.seam.assign(static_cast<std::size_t>(m.num_vertices), 0);
    for (const int v : order)
        for (int h = m.fan_start[v], n = 0; h >= 0 && n < m.fan_size[v]; h = m.cw(h), ++n)
            if (!m.map.transition[h].is_identity()) s.seam[v] = 1;
    s.tris.resize(static_cast<std::size_t>(m.num_faces()));
    s.onto.assign(static_cast<std::size_t>(m.num_vertices), -1);
    for (int v = 0; v < m.num_vertices; ++v)
        if (m.fan_start[v] >= 0) s.around[v].reserve(static_cast<std::size_t>(m.fan_size[v]) + 4);
    for (int f = 0; f < m.num_faces(); ++f) {
        s.tris[f].v = m.tri[f];
        s.tris[f].ref = {3 * f, 3 * f + 1, 3 * f + 2};
        for (const int v : m.tri[f]) s.around[v].push_back(f);
    }
    std::vector<char> gone(static_cast<std::size_t>(m.num_vertices), 0);
    std::size_t removed = 0;
    for (int pass = 0; pass < kMaxPasses; ++pass) {
        const std::size_t before = removed;
        // A vertex is tried again only once its star changed.
        for (const int v : order) {
            if (gone[v] || !s.dirty[v]) continue;
            s.dirty[v] = 0;
            if (collapse(s, v)) gone[v] = 1, ++removed;
        }
        if (removed == before) break;
    }
    if (removed == 0) return false;
    Collapses done;
    done.onto = std::move(s.onto);
    for (const Tri& t : s.tris)
        if (t.alive) done.v.push_back(t.v), done.ref.push_back(t.ref), done.to_face.push_back(t.g);
    return build_coarse(m, done, out);
}

} // namespace qex::detail::repair_impl

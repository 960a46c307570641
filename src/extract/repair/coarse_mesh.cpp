// The repair's coarse triangulation as a mesh: its triangles with the given mesh's vertex
// numbering, transitions that carry its UVs exactly, and the coarse triangle that holds each
// vertex it does without (coarse.h).
#include "extract/repair/coarse.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace qex::detail::repair_impl {
namespace {

/// The transition across coarse half-edge h, if one carries its ends' UVs exactly onto the
/// opposite triangle's: the rotation and translation that do, or, where the edge has no length in
/// the map, the one through the fine fan of an end that closes (at a singularity the way round
/// would matter).
bool edge_transition(const TriMesh& m, const CoarseMap& out, int h, Fan& fan, GridAutomorphism& g) {
    const TriMesh& c = out.mesh;
    const int o = c.opp[h], there = TriMesh::next(o);
    const Point2 &p = c.uv[h], &q = c.uv[TriMesh::next(h)], &p2 = c.uv[there], &q2 = c.uv[o];
    const auto carries = [&](const GridAutomorphism& t) { return t(p) == p2 && t(q) == q2; };
    if (p != q) {
        for (int r = 0; r < 4; ++r) {
            const Point2 rp = GridAutomorphism::rotate(p, r);
            g = {r, std::llround(p2[0] - rp[0]), std::llround(p2[1] - rp[1])};
            if (carries(g)) return true;
        }
        return false;
    }
    for (const std::array<int, 2> ends : {std::array<int, 2>{h, there}, std::array<int, 2>{TriMesh::next(h), o}}) {
        const int v = c.origin(ends[0]);
        if (m.map.singular[v] || m.on_boundary[v]) continue;
        walk_fan_corners(m, v, false, fan.corners, fan.to_c);
        g = out.to_face[ends[1]].after(
            fan.between(out.ref[ends[0]], out.ref[ends[1]]).after(out.to_face[ends[0]].inverse()));
        if (carries(g)) return true;
    }
    return false;
}

/// The coarse triangle holding p best among `near` (in its plane, largest smallest coordinate),
/// and that coordinate.
std::pair<int, double> holding(const TriMesh& c, const std::vector<int>& near, const Vec3& p) {
    std::pair<int, double> best{-1, -1e300};
    for (const int t : near) {
        const std::array<Vec3, 3> q{c.pos(3 * t), c.pos(3 * t + 1), c.pos(3 * t + 2)};
        std::array<double, 3> l{};
        if (!barycentric3(q[0], q[1], q[2], p, l)) continue;
        const double low = std::min({l[0], l[1], l[2]});
        if (low > best.second && in_plane(q, p)) best = {t, low};
    }
    return best;
}

/// The coarse triangles round v (in `out`), and with `rings` 2 those round its neighbours too.
void triangles_near(const TriMesh& c, int v, int rings, std::vector<int>& out) {
    out.clear();
    std::vector<int> ends{v};
    if (rings > 1)
        for (int h = c.fan_start[v], n = 0; h >= 0 && n < c.fan_size[v]; h = c.cw(h), ++n) ends.push_back(c.target(h));
    for (const int u : ends)
        for (int h = c.fan_start[u], n = 0; h >= 0 && n < c.fan_size[u]; h = c.cw(h), ++n)
            out.push_back(TriMesh::face(h));
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
}

/// Per removed vertex, the coarse triangle that holds it: near the kept vertex its collapses
/// ended on (a ring, or two where it lies farther). False if none does.
bool locate(const TriMesh& m, const Collapses& s, CoarseMap& out) {
    const TriMesh& c = out.mesh;
    const auto kept = [&](int v) {
        while (s.onto[v] >= 0) v = s.onto[v];
        return v;
    };
    out.host.assign(static_cast<std::size_t>(m.num_vertices), -1);
    std::vector<int> near;
    for (int v = 0; v < m.num_vertices; ++v) {
        if (s.onto[v] < 0) continue;
        const Vec3& p = m.pos(m.fan_start[v]);
        const int a = kept(v);
        triangles_near(c, a, 1, near);
        std::pair<int, double> best = holding(c, near, p);
        if (best.second < -1e-9) triangles_near(c, a, 2, near), best = holding(c, near, p);
        if (best.first < 0 || best.second < -1e-6) return false;
        out.host[v] = best.first;
    }
    return true;
}

} // namespace

bool build_coarse(const TriMesh& m, const Collapses& s, CoarseMap& out) {
    TriMesh& c = out.mesh;
    c.num_vertices = m.num_vertices;
    c.positions = m.positions;
    c.input_vertex = m.input_vertex;
    c.threads = m.threads;
    c.noise_scale = m.noise_scale;
    for (std::size_t t = 0; t < s.v.size(); ++t) {
        c.tri.push_back(s.v[t]);
        c.input_triangle.push_back(m.input_triangle[TriMesh::face(s.ref[t][0])]);
        for (int k = 0; k < 3; ++k) {
            c.uv.push_back(s.to_face[t][k](m.uv[s.ref[t][k]]));
            c.corner_vertex.push_back(m.corner_vertex[s.ref[t][k]]);
            out.ref.push_back(s.ref[t][k]);
            out.to_face.push_back(s.to_face[t][k]);
        }
    }
    if (build_topology(c, "the coarse triangulation of the map").code != ErrorCode::None) return false;
    const int nh = 3 * c.num_faces();
    c.map.transition.allocate(static_cast<std::size_t>(nh));
    Fan fan;
    for (int h = 0; h < nh; ++h) {
        const int o = c.opp[h];
        if (o < 0) {
            c.map.transition.set(static_cast<std::size_t>(h), GridAutomorphism{});
            continue;
        }
        GridAutomorphism g;
        if (!edge_transition(m, out, h, fan, g)) return false;
        c.map.transition.set(static_cast<std::size_t>(h), g);
    }
    c.map.valence = m.map.valence;
    c.map.winding_valence = m.map.winding_valence;
    c.map.singular = m.map.singular;
    c.map.face_sign = triangle_signs(c);
    for (int v = 0; v < c.num_vertices; ++v)
        if (c.fan_start[v] >= 0 && !c.on_boundary[v] && fan_turn(c, v) != fan_turn(m, v)) return false;
    return locate(m, s, out);
}

} // namespace qex::detail::repair_impl

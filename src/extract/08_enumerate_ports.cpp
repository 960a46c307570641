// Q-port enumeration (Algorithm 4): the outgoing integer iso-lines of every q-vertex, listed in
// clockwise order on the surface. In a regular triangle clockwise on the surface is clockwise in
// the chart; in a flipped one it is counter-clockwise. Each iso-line along a mesh edge belongs to
// the corner for which that edge is the clockwise bound ("v-edge"). Where no corner claims it
// that way (the neighbour across it is missing, or degenerate and not carrying the ray on to one
// that claims it), the corner on the other side takes it as its counter-clockwise bound ("w-edge").
#include "pipeline.h"

namespace qex::detail {
namespace {

/// Where a direction from a corner points: into the corner, along one of its edges, or out of it.
enum class Where { Outside, Inside, AlongV, AlongW };

/// Where direction d from u points relative to the corner at u with edges to v and w (orientation s).
Where classify(const Point2& u, const Point2& v, const Point2& w, int s, int d) {
    const IPoint e = unit_dir(d);
    const Point2 x{u[0] + static_cast<double>(e[0]), u[1] + static_cast<double>(e[1])};
    const int ov = sign(orient2d(u, v, x)), ow = sign(orient2d(u, x, w));
    if (ov == s && ow == s) return Where::Inside;
    if (ov == 0 && (v[0] - u[0]) * e[0] + (v[1] - u[1]) * e[1] > 0) return Where::AlongV;
    if (ow == 0 && (w[0] - u[0]) * e[0] + (w[1] - u[1]) * e[1] > 0) return Where::AlongW;
    return Where::Outside;
}

/// Appends the ports of one corner at grid point `grid` (edges to v and w, orientation s), from the
/// w-side to the v-side; the iso-line along the w-edge only if `take_w`.
void corner_ports(std::vector<Port>& ports, int qv, int corner, const IPoint& grid, const Point2& v, const Point2& w,
                  int s, bool take_w) {
    if (s == 0) return;
    const Point2 u = to_point(grid);
    Where where[4];
    int outside = -1;
    for (int d = 0; d < 4; ++d) {
        where[d] = classify(u, v, w, s, d);
        if (where[d] == Where::Outside && outside < 0) outside = d;
    }
    if (outside < 0) return; // impossible for a non-degenerate corner (its angle is at most 180 degrees)
    for (int i = 1; i < 4; ++i) {
        const int d = (outside - s * i + 8) & 3; // clockwise on the surface
        if (where[d] == Where::Inside || where[d] == Where::AlongV || (take_w && where[d] == Where::AlongW))
            ports.push_back({qv, corner, d, grid});
    }
}

/// Whether the ray of corner c's w-edge is claimed counter-clockwise of c: degenerate corners of
/// angle 0 carry the ray on unchanged, and the first non-degenerate corner claims it as its v-edge.
bool w_ray_claimed(const TriMesh& m, int c) {
    int cur = m.ccw(c);
    for (int guard = 0; cur >= 0 && m.map.face_sign[TriMesh::face(cur)] == 0; ++guard) {
        const Point2& u = m.uv[cur];
        const Point2& v = m.uv[TriMesh::next(cur)];
        const Point2& w = m.uv[TriMesh::prev(cur)];
        // Angle pi, or a zero-length edge: the ray ends here.
        if ((v[0] - u[0]) * (w[0] - u[0]) + (v[1] - u[1]) * (w[1] - u[1]) <= 0) return false;
        if (guard > m.fan_size[m.origin(c)]) return false;
        cur = m.ccw(cur);
    }
    return cur >= 0;
}

/// Appends the ports of vertex-q-vertex i (on mesh vertex v), corner by corner clockwise around v.
void vertex_ports(const TriMesh& m, int i, const QVertex& qv, std::vector<Port>& ports) {
    const int v = qv.element;
    IPoint grid = qv.grid; // in the chart of the fan's first corner, propagated clockwise
    for (int c = m.fan_start[v], n = 0; c >= 0 && n < m.fan_size[v]; ++n) {
        const bool take_w = m.ccw(c) < 0 || !w_ray_claimed(m, c);
        corner_ports(ports, i, c, grid, m.uv[TriMesh::next(c)], m.uv[TriMesh::prev(c)],
                     m.map.face_sign[TriMesh::face(c)], take_w);
        grid = m.map.transition[c](grid);
        c = m.cw(c);
        if (c == m.fan_start[v]) break;
    }
}

/// Appends the ports of edge-q-vertex i: those in the triangle of its half-edge, then the other side's.
void edge_ports(const TriMesh& m, int i, const QVertex& qv, std::vector<Port>& ports) {
    const int h = qv.element, o = m.opp[h];
    const int sh = m.map.face_sign[TriMesh::face(h)];
    const int so = o >= 0 ? m.map.face_sign[TriMesh::face(o)] : 0;
    // In face(h) the edge runs a -> b: v-edge towards b, w-edge towards a.
    corner_ports(ports, i, h, qv.grid, m.uv[TriMesh::next(h)], m.uv[h], sh, o < 0 || so == 0);
    if (o >= 0) corner_ports(ports, i, o, m.map.transition[h](qv.grid), m.uv[TriMesh::next(o)], m.uv[o], so, sh == 0);
}

} // namespace

void enumerate_ports(const TriMesh& m, QState& q) {
    q.ports.clear();
    // Reserved at a bound (a q-vertex on a vertex gives at most 3 ports per corner of its fan, one
    // on an edge at most 3 in each of its two triangles, one in a face 4): capacity left
    // untouched costs no memory, where growing by doubling touched up to twice the ports' size.
    std::size_t bound = 0;
    for (const QVertex& qv : q.qvertices)
        bound += qv.kind == QVertexKind::Face   ? 4
                 : qv.kind == QVertexKind::Edge ? 6
                                                : 3 * static_cast<std::size_t>(m.fan_size[qv.element]);
    q.ports.reserve(bound);
    for (int i = 0; i < static_cast<int>(q.qvertices.size()); ++i) {
        QVertex& qv = q.qvertices[i];
        qv.first_port = static_cast<int>(q.ports.size());
        switch (qv.kind) {
            case QVertexKind::Vertex: vertex_ports(m, i, qv, q.ports); break;
            case QVertexKind::Edge: edge_ports(m, i, qv, q.ports); break;
            case QVertexKind::Face: {
                // Directions 3, 2, 1, 0 are clockwise in a regular triangle's chart.
                const int f = qv.element, s = m.map.face_sign[f];
                for (int k = 0; k < 4; ++k) q.ports.push_back({i, 3 * f, s > 0 ? 3 - k : k, qv.grid});
                break;
            }
        }
        qv.num_ports = static_cast<int>(q.ports.size()) - qv.first_port;
    }
}

} // namespace qex::detail

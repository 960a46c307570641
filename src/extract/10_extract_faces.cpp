// Face extraction (Algorithm 6): follow a connection, turn left by taking the next port clockwise,
// repeat until the walk closes; local UVs accumulate the transitions along the way.
#include "pipeline.h"

#include <algorithm>
#include <string>

namespace qex::detail {

GridAutomorphism fan_transition_cw(const TriMesh& m, const QState& q, int a, int b, bool& ok) {
    ok = true;
    const Port &pa = q.ports[a], &pb = q.ports[b];
    const QVertex& v = q.qvertices[pa.qvertex];
    if (v.kind == QVertexKind::Face) return {};
    if (pa.corner == pb.corner && b > a) return {};
    // Step clockwise corner by corner (for an edge-q-vertex the two corners alternate).
    GridAutomorphism g;
    int c = pa.corner;
    const int limit = v.kind == QVertexKind::Vertex ? m.fan_size[v.element] : 2;
    for (int step = 0; step < limit; ++step) {
        const int next = v.kind == QVertexKind::Vertex ? m.cw(c) : m.opp[c];
        if (next < 0) {
            ok = false;
            return g;
        }
        g = m.map.transition[c].after(g);
        c = next;
        if (c == pb.corner) return g;
    }
    ok = false;
    return g;
}

bool qvertex_less(const QState& q, int a, int b) {
    const QVertex &x = q.qvertices[static_cast<std::size_t>(a)], &y = q.qvertices[static_cast<std::size_t>(b)];
    if (x.position != y.position) return x.position < y.position;
    if (x.kind != y.kind) return x.kind < y.kind;
    return a < b;
}

std::size_t canonical_start(const QState& q, const int* qv, std::size_t n) {
    // Q-vertices on input vertices first (then on edges, then in faces), then qvertex_less: a walk
    // around a singularity starts there, so its local UVs jump at the singularity, where the
    // recovery of lost edges looks for corners that share them.
    auto less = [&](int a, int b) {
        const QVertexKind ka = q.qvertices[static_cast<std::size_t>(a)].kind,
                          kb = q.qvertices[static_cast<std::size_t>(b)].kind;
        return ka != kb ? ka < kb : qvertex_less(q, a, b);
    };
    std::size_t best = 0;
    for (std::size_t start = 1; start < n; ++start)
        for (std::size_t k = 0; k < n; ++k) {
            const int a = qv[(start + k) % n], b = qv[(best + k) % n];
            if (a != b) {
                if (less(a, b)) best = start;
                break;
            }
        }
    return best;
}

namespace {

/// One face walk: its ports, their q-vertices and local UVs, and how it ended.
struct Walk {
    std::vector<int> ports;
    std::vector<int> qv;
    std::vector<IPoint> uv; ///< in the chart of the start port's triangle
    bool closed = false;    ///< came back to the start port
    bool boundary = false;  ///< ran into the boundary between grid points
    bool open = false;      ///< ran into an unconnected port or into another walk
};

/// Walks the face to the left of the connection of port `start`: follow the connection, take the
/// next port clockwise, repeat. Marks the ports visited (1); `visited` is 2 on ports of earlier
/// walks that ran into the boundary.
void walk_face(const TriMesh& m, const QState& q, int start, std::vector<char>& visited, Walk& w) {
    const int np = static_cast<int>(q.ports.size());
    w.ports.clear();
    w.qv.clear();
    w.uv.clear();
    w.closed = w.boundary = w.open = false;
    GridAutomorphism gbar; // chart of the start port -> chart of the current port
    int cur = start;
    for (int guard = 0; guard < 4 * np + 8; ++guard) {
        visited[cur] = 1;
        w.ports.push_back(cur);
        const Port& port = q.ports[cur];
        w.qv.push_back(port.qvertex);
        w.uv.push_back(gbar.inverse()(port.grid));
        const Connection& c = q.connections[cur];
        const int arrive = c.to;
        const QVertex& v = q.qvertices[q.ports[arrive].qvertex];
        const int next = v.first_port + (arrive - v.first_port + 1) % v.num_ports;
        bool ok = true;
        const GridAutomorphism fan = fan_transition_cw(m, q, arrive, next, ok);
        if (!ok) {
            w.boundary = true;
            break;
        }
        gbar = fan.after(c.g.after(gbar));
        if (q.connections[next].to < 0) {
            (q.into_boundary[next] ? w.boundary : w.open) = true;
            break;
        }
        cur = next;
        if (cur == start) {
            w.closed = true;
            break;
        }
        if (visited[cur]) {
            (visited[cur] == 2 ? w.boundary : w.open) = true;
            break;
        }
    }
}

/// Reports a walk that did not close: a boundary face discarded (an explanation) or an open walk
/// (a defect); `chart` is the start port's triangle.
/// Whether a closed walk is a plain quad: four corners at four distinct q-vertices.
bool plain_quad(const Walk& w) {
    if (w.qv.size() != 4) return false;
    for (std::size_t i = 0; i < 4; ++i)
        for (std::size_t j = i + 1; j < 4; ++j)
            if (w.qv[i] == w.qv[j]) return false;
    return true;
}

/// Restarts a closed walk at its canonical corner, with local UVs accumulated from there.
void start_canonically(const TriMesh& m, const QState& q, Walk& w) {
    const std::size_t n = w.ports.size(), s = canonical_start(q, w.qv.data(), n);
    if (s == 0) return;
    std::rotate(w.ports.begin(), w.ports.begin() + static_cast<std::ptrdiff_t>(s), w.ports.end());
    std::rotate(w.qv.begin(), w.qv.begin() + static_cast<std::ptrdiff_t>(s), w.qv.end());
    GridAutomorphism gbar; // as in walk_face, along the same ports
    for (std::size_t i = 0; i < n; ++i) {
        const int cur = w.ports[i];
        w.uv[i] = gbar.inverse()(q.ports[cur].grid);
        const Connection& c = q.connections[cur];
        bool ok = true;
        gbar = fan_transition_cw(m, q, c.to, w.ports[(i + 1) % n], ok).after(c.g.after(gbar));
    }
}

void report_unclosed(const TriMesh& m, const QState& q, const Walk& w, int chart, Report& report) {
    if (w.boundary) {
        // The walk reached the boundary between grid points: the boundary is not on an integer
        // iso-line here, and the face intersecting it is discarded (Section 5.1).
        ++report.boundary_faces_discarded;
        const QVertex& v = q.qvertices[w.qv[0]];
        report.explanations.push_back({DefectKind::BoundaryFaceDiscarded,
                                       "a face walk from grid point (" + std::to_string(v.grid[0]) + ", " +
                                           std::to_string(v.grid[1]) + ") of input triangle " +
                                           std::to_string(m.input_triangle[v.chart]) +
                                           " ran into the boundary between grid points; the face is left out",
                                       m.input_triangle[v.chart],
                                       -1,
                                       {v.grid[0], v.grid[1]},
                                       std::nullopt});
    } else {
        ++report.open_face_walks;
        report.defects.push_back({DefectKind::OpenFaceWalk,
                                  "a face walk starting at grid point (" + std::to_string(w.uv[0][0]) + ", " +
                                      std::to_string(w.uv[0][1]) + ") did not close",
                                  m.input_triangle[chart],
                                  -1,
                                  {w.uv[0][0], w.uv[0][1]},
                                  std::nullopt});
    }
}

} // namespace

FaceWalks extract_faces(const TriMesh& m, const QState& q, Report& report) {
    const int np = static_cast<int>(q.ports.size());
    // Per port: 0 unvisited, 1 on the walk under way, a closed face or an open walk, 2 on a walk
    // that ran into the boundary (a later walk joining it ends at the boundary too).
    std::vector<char> visited(np, 0);
    FaceWalks faces;
    // Every port is on one walk at most: reserved at that bound, whose untouched rest costs no
    // memory (growing by doubling touched up to twice the walks' size, and copied them).
    faces.first.reserve(static_cast<std::size_t>(np) + 1);
    faces.qv.reserve(static_cast<std::size_t>(np));
    faces.uv.reserve(static_cast<std::size_t>(np));
    Walk w;
    // Closed walks are cycles of the port graph: found from any of their ports. A walk that does
    // not close ends where it meets another walk or the boundary, so what it holds depends on
    // where it started: those walks are undone and walked again afterwards, from their starts in
    // canonical port order.
    std::vector<int> later;
    auto take = [&](int start) {
        ++report.faces_traced;
        if (w.closed) {
            if (!plain_quad(w)) start_canonically(m, q, w);
            faces.qv.insert(faces.qv.end(), w.qv.begin(), w.qv.end());
            faces.uv.insert(faces.uv.end(), w.uv.begin(), w.uv.end());
            faces.first.push_back(faces.qv.size());
        } else {
            report_unclosed(m, q, w, TriMesh::face(q.ports[start].corner), report);
        }
    };
    for (int start = 0; start < np; ++start) {
        if (visited[start] || q.connections[start].to < 0) continue;
        walk_face(m, q, start, visited, w);
        if (!w.closed) {
            for (const int p : w.ports) visited[p] = 0;
            later.push_back(start);
            continue;
        }
        take(start);
    }
    std::sort(later.begin(), later.end(), [&](int a, int b) { return port_less(m, q, a, b); });
    for (const int start : later) {
        if (visited[start]) continue;
        walk_face(m, q, start, visited, w);
        if (w.boundary)
            for (const int p : w.ports) visited[p] = 2;
        take(start);
    }
    return faces;
}

} // namespace qex::detail

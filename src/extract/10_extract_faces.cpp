// Face extraction (Algorithm 6): follow a connection, turn left by taking the next port clockwise,
// repeat until the walk closes; local UVs accumulate the transitions along the way.
#include "pipeline.h"

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
        if (next < 0) { ok = false; return g; }
        g = m.map.transition[c].after(g);
        c = next;
        if (c == pb.corner) return g;
    }
    ok = false;
    return g;
}

FaceWalks extract_faces(const TriMesh& m, const QState& q, Report& report) {
    const int np = static_cast<int>(q.ports.size());
    // Per port: 0 unvisited, 1 on the walk under way or a closed face, 2 on a walk that ran into
    // the boundary (a later walk joining it ends at the boundary too).
    std::vector<char> visited(np, 0);
    std::vector<int> walk;
    FaceWalks faces;
    std::vector<int> face_qv; // the walk under way
    std::vector<IPoint> face_uv;
    for (int start = 0; start < np; ++start) {
        if (visited[start] || q.connections[start].to < 0) continue;
        face_qv.clear();
        face_uv.clear();
        const int chart = TriMesh::face(q.ports[start].corner); // the local UVs' chart
        GridAutomorphism gbar; // chart of the start port -> chart of the current port
        int cur = start;
        bool closed = false, boundary = false, open = false;
        walk.clear();
        for (int guard = 0; guard < 4 * np + 8; ++guard) {
            visited[cur] = 1;
            walk.push_back(cur);
            const Port& port = q.ports[cur];
            face_qv.push_back(port.qvertex);
            face_uv.push_back(gbar.inverse()(port.grid));
            const Connection& c = q.connections[cur];
            const int arrive = c.to;
            const QVertex& v = q.qvertices[q.ports[arrive].qvertex];
            const int next = v.first_port + (arrive - v.first_port + 1) % v.num_ports;
            bool ok = true;
            const GridAutomorphism fan = fan_transition_cw(m, q, arrive, next, ok);
            if (!ok) { boundary = true; break; }
            gbar = fan.after(c.g.after(gbar));
            if (q.connections[next].to < 0) {
                (q.dangling[next] ? boundary : open) = true;
                break;
            }
            cur = next;
            if (cur == start) { closed = true; break; }
            if (visited[cur]) { (visited[cur] == 2 ? boundary : open) = true; break; }
        }
        if (boundary)
            for (int p : walk) visited[p] = 2;
        ++report.faces_traced;
        if (closed) {
            faces.qv.insert(faces.qv.end(), face_qv.begin(), face_qv.end());
            faces.uv.insert(faces.uv.end(), face_uv.begin(), face_uv.end());
            faces.first.push_back(faces.qv.size());
        } else if (boundary) {
            // The walk reached the boundary between grid points: the boundary is not on an integer
            // iso-line here, and the face intersecting it is discarded (Section 5.1).
            ++report.boundary_faces_discarded;
            const QVertex& v = q.qvertices[face_qv[0]];
            report.explanations.push_back({DefectKind::BoundaryFaceDiscarded,
                                           "a face walk from grid point (" + std::to_string(v.grid[0]) + ", " +
                                               std::to_string(v.grid[1]) + ") of input triangle " +
                                               std::to_string(m.input_triangle[v.chart]) +
                                               " ran into the boundary between grid points; the face is left out",
                                           m.input_triangle[v.chart], -1, {v.grid[0], v.grid[1]}, std::nullopt});
        } else {
            ++report.open_face_walks;
            report.defects.push_back({DefectKind::OpenFaceWalk,
                                      "a face walk starting at grid point (" + std::to_string(face_uv[0][0]) + ", " +
                                          std::to_string(face_uv[0][1]) + ") did not close",
                                      m.input_triangle[chart], -1, {face_uv[0][0], face_uv[0][1]}, std::nullopt});
        }
    }
    return faces;
}

} // namespace qex::detail

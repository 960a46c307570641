// A rung's stages from its map to its mesh: generate_qvertices and enumerate_ports (the
// geometry, Section 4), then trace_ports, extract_faces and merge_vertices (the connectivity,
// Section 5). Each rung runs them once (ladder.cpp), and the repair's look before its last ring
// runs them on the map so far.
#include "ladder.h"

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace qex::detail {
namespace {

/// Why a q-vertex found no q-port, from the triangles it lies on: on a vertex, its fan and how
/// many of them are flipped or degenerate; on an edge or in a triangle, whether they are all
/// degenerate.
std::string portless_why(const TriMesh& m, const QVertex& v) {
    const auto sign = [&](int f) { return m.map.face_sign[static_cast<std::size_t>(f)]; };
    if (v.kind == QVertexKind::Vertex) {
        int triangles = 0, flipped = 0, degenerate = 0;
        for (int h = m.fan_start[v.element], k = 0; h >= 0 && k < m.fan_size[v.element]; h = m.cw(h), ++k) {
            ++triangles;
            flipped += sign(TriMesh::face(h)) < 0;
            degenerate += sign(TriMesh::face(h)) == 0;
        }
        return "on input vertex " + std::to_string(m.input_vertex[v.element]) + ", whose fan of " +
               std::to_string(triangles) + " triangles (" + std::to_string(flipped) + " flipped, " +
               std::to_string(degenerate) + " degenerate) starts no iso-line";
    }
    const int f = v.kind == QVertexKind::Edge ? TriMesh::face(v.element) : v.element;
    const int o = v.kind == QVertexKind::Edge ? m.opp[v.element] : -1;
    const bool degenerate = sign(f) == 0 && (o < 0 || sign(TriMesh::face(o)) == 0);
    return std::string(v.kind == QVertexKind::Edge ? "on an edge" : "inside a triangle") +
           (degenerate ? " of degenerate triangles only" : " whose triangles start no iso-line");
}

/// Geometry extraction (Section 4): stages generate_qvertices and enumerate_ports.
Error extract_geometry(const TriMesh& m, const Options& options, QState& q, Report& report, StageTimer& timer) {
    if (Error e = generate_qvertices(m, options, q); e.code != ErrorCode::None) return e;
    for (const auto& v : q.qvertices) {
        report.qvertices_on_vertices += v.kind == QVertexKind::Vertex;
        report.qvertices_on_edges += v.kind == QVertexKind::Edge;
        report.qvertices_in_faces += v.kind == QVertexKind::Face;
    }
    timer.done(Stage::generate_qvertices);
    enumerate_ports(m, q);
    report.ports = static_cast<std::int64_t>(q.ports.size());
    for (const QVertex& v : q.qvertices)
        if (v.num_ports == 0)
            report.defects.push_back({DefectKind::PortlessQVertex,
                                      "the q-vertex at grid point (" + std::to_string(v.grid[0]) + ", " +
                                          std::to_string(v.grid[1]) + ") has no q-port: " + portless_why(m, v),
                                      m.input_triangle[v.chart],
                                      -1,
                                      {v.grid[0], v.grid[1]},
                                      std::nullopt});
    timer.done(Stage::enumerate_ports);
    return {};
}

/// Connectivity extraction (Section 5): stages trace_ports, extract_faces and merge_vertices.
/// Returns the output faces, flat (merge_vertices).
FaceWalks extract_connectivity(const TriMesh& m, const Options& options, QState& q, QuadMesh& mesh, Report& report,
                               StageTimer& timer) {
    trace_ports(m, options, q, report);
    timer.done(Stage::trace_ports);
    FaceWalks faces = extract_faces(m, q, report);
    timer.done(Stage::extract_faces);
    // Merging needs the q-vertices only: the ports and traces (two thirds of the q-state on
    // maps with many quads) are released first.
    std::vector<Port>().swap(q.ports);
    std::vector<Connection>().swap(q.connections);
    std::vector<char>().swap(q.into_boundary);
    std::vector<int>().swap(q.edge_first);
    std::vector<int>().swap(q.face_first);
    FaceWalks out = merge_vertices(m, q, std::move(faces), options, mesh, report);
    timer.done(Stage::merge_vertices);
    return out;
}

} // namespace

Error extract_mesh(const TriMesh& m, const Options& options, Result& result, StageTimer& timer, FaceWalks& faces) {
    QState q;
    if (Error e = extract_geometry(m, options, q, result.report, timer); e.code != ErrorCode::None) return e;
    faces = extract_connectivity(m, options, q, result.mesh, result.report, timer);
    return {};
}

} // namespace qex::detail

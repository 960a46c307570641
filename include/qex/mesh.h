// The data both sides of qex share: the input (a triangle mesh carrying an integer-grid map) and
// the output (a quad mesh, with where each of its vertices lies on the input). The extractor
// (qex/extract.h) writes these structs and the checker (qex/verify.h) reads them; neither side
// sees the other's code.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace qex {

/// A triangle mesh carrying a (relaxed) integer-grid map.
struct Input {
    /// #V positions in R^3.
    std::vector<std::array<double, 3>> positions;
    /// #F triangles, vertex indices into `positions`, counter-clockwise on the surface.
    std::vector<std::array<int, 3>> triangles;
    /// 3·#F parameter coordinates, one per triangle corner: corner k of triangle f is uvs[3f+k].
    std::vector<std::array<double, 2>> uvs;
    /// Optional: per-vertex valence of the cross field (4 = regular). Empty: computed (Algorithm 8).
    std::vector<int> valences;
    /// Optional: feature edges (vertex pairs) to snap onto their closest integer iso-line (Section 3.2).
    std::vector<std::array<int, 2>> feature_edges;
};

/// Which kind of input element an output vertex was generated on (Section 4).
enum class QVertexKind : std::uint8_t { Vertex, Edge, Face };

/// Where an output vertex lies on the input surface.
struct Provenance {
    QVertexKind kind = QVertexKind::Face;
    /// Input vertex (Vertex), input triangle of the edge's half-edge (Edge), or input triangle (Face).
    int element = -1;
    /// For Edge: local edge index 0..2 of the half-edge (corner k to corner k+1) in triangle `element`.
    int local_edge = -1;
    /// Barycentric coordinates in triangle `element` (Edge, Face). For Vertex, in triangle
    /// `chart_triangle`: 1 at the vertex's corner of that triangle, 0 at the other two.
    std::array<double, 3> barycentric{1.0, 0.0, 0.0};
    /// Integer grid point of the vertex in the chart of triangle `element`
    /// (for Vertex: in the chart of the vertex's first corner triangle, `chart_triangle`).
    std::array<std::int64_t, 2> grid{0, 0};
    int chart_triangle = -1;
    /// Number of q-vertices merged into this output vertex (1 unless a fold-over produced clones).
    int merged = 1;
};

struct QuadMesh {
    std::vector<std::array<double, 3>> positions;
    /// Faces as vertex index lists (4 each when extraction succeeded), counter-clockwise.
    std::vector<std::vector<int>> faces;
    /// Per face corner: integer local UV (a unit square per quad, counter-clockwise).
    std::vector<std::vector<std::array<std::int64_t, 2>>> face_uvs;
    /// Per vertex (qex's own output; empty for meshes from elsewhere).
    std::vector<Provenance> provenance;
    /// The sanitized (and repaired) map the mesh was extracted from: 3 UVs per input triangle,
    /// NaN for triangles removed by collapsing UV-degenerate edges. Empty for meshes from
    /// elsewhere. The checker verifies it is an exact integer-grid map and that every vertex's
    /// provenance names a grid point on the element it claims.
    std::vector<std::array<double, 2>> map_uvs;
    /// The repair's certificate: the input triangles (sorted) whose UVs the repair of fold-overs
    /// changed. The checker verifies that each is positively oriented in `map_uvs`, exactly;
    /// every other triangle keeps its sanitized UVs.
    std::vector<std::int32_t> map_repaired;
    /// The factor the input map's UVs were multiplied by before extraction (1, or a power of two
    /// when the map was too coarse at its own scale; Options::max_refinement). The checker judges
    /// the mesh against the input map scaled by it; for meshes from elsewhere, set it to judge a
    /// mesh against a refined map (`qex check --grid-scale K`).
    int grid_scale = 1;
};

} // namespace qex

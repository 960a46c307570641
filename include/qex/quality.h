// Quality figures of a quad mesh on its input surface: the shape of its quads, its irregular
// vertices, and how far the two surfaces lie apart. They judge nothing (a valid mesh may have
// poor quads); they are measured by the checker's library (qex::verify) from the mesh's positions
// and faces and the input's positions and triangles alone, so they mean the same for any
// extractor's mesh. `qex extract --report` writes them under "quality", `qex check` prints them.
#pragma once

#include "qex/mesh.h"

#include <cstdint>

namespace qex {

/// The figures of mesh_quality. Every figure is a function of the geometry alone: the same bits
/// for any order of the faces (and of the input's triangles), any numbering of the vertices, and
/// any corner a face (or triangle) starts at.
struct MeshQuality {
    /// False when no figure could be computed: a face or triangle names a vertex that does not
    /// exist, a coordinate either side uses is not finite or beyond 1e150 in magnitude (where
    /// squared distances overflow), or either surface has no triangle of positive area. Every
    /// figure below is 0 then.
    bool computed = false;

    // ---- shape of the quads
    /// Faces with 4 vertices: the population of the scaled Jacobians below.
    std::int64_t quads = 0;
    /// Faces with other than 4 vertices: skipped by the scaled Jacobians; they count in the
    /// vertex figures and in the distances.
    std::int64_t other_faces = 0;
    /// Scaled Jacobian of a quad (dimensionless, in [-1, 1]): the smallest over its 4 corners v of
    /// dot(cross(e1, e2), n) / (|e1| |e2|), with e1 = next - v, e2 = prev - v and n the unit
    /// normal of the quad's diagonals, cross(v2 - v0, v3 - v1). In a planar quad it is the sine
    /// of the corner's angle, signed by the quad's side: 1 for a rectangle, 0 or below for a
    /// folded (reflex) or degenerate corner. A corner with a zero-length edge, and every corner of
    /// a quad whose diagonals are parallel (no normal), count 0 (not -1: degenerate, not turned
    /// over). This field: the smallest over the quads; 0 without quads.
    double min_scaled_jacobian = 0;
    /// The 5th percentile by nearest rank: the value at rank ceil(0.05 · quads) in ascending order.
    double p5_scaled_jacobian = 0;
    /// The mean over the quads, summed in ascending order of the values.
    double mean_scaled_jacobian = 0;

    // ---- irregular vertices
    /// Vertices that at least one face uses (the population of the share below).
    std::int64_t vertices = 0;
    /// Interior vertices with other than 4 faces, and boundary vertices (on an edge of one face)
    /// with other than 2 faces. A boundary corner (1 face, or 3 at a concave corner) counts as
    /// irregular too, whether the input's boundary has a corner there or not.
    std::int64_t irregular_vertices = 0;
    /// irregular_vertices / vertices (0 to 1; 0 without vertices).
    double irregular_vertex_share = 0;

    // ---- distances between the surfaces, as fractions of the input's bounding-box diagonal
    /// The input's bounding-box diagonal (model units): over the vertices its triangles use.
    double diagonal = 0;
    /// The largest distance from an input vertex, or an input triangle's centroid, to the mesh's
    /// surface, as a fraction of `diagonal`. That surface splits each face (of 3 or more vertices) into triangles joining each
    /// side to the face's centroid (the mean of its corners): 4 per quad, no diagonal to choose.
    double distance_input_to_mesh = 0;
    /// The largest distance from a mesh vertex, or a face's centroid, to the input's triangles,
    /// as a fraction of `diagonal`.
    double distance_mesh_to_input = 0;
};

/// The quality figures of `mesh` on `map` (its positions and triangles; its UVs are not read).
/// Triangles of zero area on either side are left out of the surfaces. Never throws (std::bad_alloc
/// aside), never prints.
MeshQuality mesh_quality(const Input& map, const QuadMesh& mesh);

} // namespace qex

// The independent checker: judges a quad mesh against the input map with its own code and exact
// arithmetic. It is its own library (qex::verify) and sees nothing of the extractor; every test,
// fuzz target and the `qex check` command use it as their oracle.
#pragma once

#include "qex/mesh.h"

#include <cstdint>
#include <string>
#include <vector>

namespace qex {

enum class ViolationKind {
    NotQuad,
    BadIndex,
    RepeatedVertex,
    NonManifoldEdge,
    InconsistentOrientation,
    NonManifoldVertex,
    UnreferencedVertex,
    NonFinitePosition,
    BoundaryMismatch,
    EulerMismatch,
    ComponentMismatch,
    LocalUvNotUnitSquare,
    EmptyMesh,
    MapNotIntegerGrid,  ///< map_uvs: across an edge the charts differ by more than a grid automorphism
    NotOnGridPoint,     ///< provenance: the vertex's grid point is not on the element it names
    SingularityOffGrid, ///< map_uvs: a singular vertex is not on an integer grid point
    /// map_repaired: a listed triangle is not positively oriented in map_uvs (exactly), or the
    /// list is not sorted, unique and within the map's live triangles
    RepairNotCertified,
    // Located mode (meshes without provenance, e.g. from other extractors):
    OffSurface,       ///< a vertex farther from the input surface than the distance tolerance
    FaceNotGridCell,  ///< a face's corners, carried into one chart, are not a ccw unit grid cell
    CoverageMismatch, ///< the faces do not cover the map once (map without flipped triangles)
    TooLarge,         ///< more face corners (mesh or input) than the checker's 32-bit tables hold
};
const char* to_string(ViolationKind kind);

/// What Violation::element indexes, for each kind of violation.
enum class ViolationElement {
    None,          ///< nothing: a violation of the whole mesh (topology counts, coverage, size)
    OutputFace,    ///< a face of the judged mesh
    OutputVertex,  ///< a vertex of the judged mesh
    InputVertex,   ///< a vertex of the input (SingularityOffGrid)
    InputTriangle, ///< a triangle of the input (MapNotIntegerGrid, RepairNotCertified)
};
/// What a violation of kind `kind` names in Violation::element.
ViolationElement element_kind(ViolationKind kind);

struct Violation {
    ViolationKind kind;
    std::string message;
    /// The element at fault, of the kind element_kind(kind) says; -1 when the violation has no
    /// single place (always for ViolationElement::None).
    std::int64_t element = -1;
};

struct VerifyResult {
    bool valid = false;
    std::vector<Violation> violations;
    std::int64_t faces = 0, vertices = 0, edges = 0, boundary_loops = 0, components = 0;
    std::int64_t euler = 0;
    std::int64_t input_euler = 0, input_boundary_loops = 0, input_components = 0;
    /// Largest and summed |map_uvs - input uvs| (inf-norm per corner; 0 without a map) over the
    /// triangles the repair left alone (sanitization's displacement), and the largest over those
    /// it repaired (QuadMesh::map_repaired).
    double max_map_displacement = 0.0, sum_map_displacement = 0.0;
    double max_repair_displacement = 0.0;
    /// The repair's certificate: triangles listed in QuadMesh::map_repaired, and their signed UV
    /// area in map_uvs (a double sum).
    std::int64_t repaired_triangles = 0;
    double repaired_uv_area = 0.0;
    /// Interior vertices of the map whose fan composes to a non-trivial rotation.
    std::int64_t map_singularities = 0;
    /// Located mode (the mesh has no provenance): vertices were located on the input surface.
    bool located = false;
    double max_grid_distance = 0.0;    ///< largest UV distance (inf-norm) of a vertex to its grid point
    double max_surface_distance = 0.0; ///< largest distance to the surface / bounding-box diagonal
    /// Located mode: input triangles of negative UV area (exact; degenerate ones not counted).
    /// Any of them lifts the coverage check (CoverageMismatch).
    std::int64_t map_flipped_triangles = 0;
    std::int64_t coverage_difference = 0; ///< faces - input_signed_uv_area_rounded
    /// Located mode: checks that could not be decided because the map folds over there (a
    /// face's corners carried across flipped or degenerate triangles, or next to them) or
    /// through the fan of a singular vertex; not violations, listed for review.
    std::vector<Violation> undecided;
    /// Signed UV area of the input map for display, printed with six decimals: the double sum,
    /// or the exact area rounded to a double where the sum's error bound left the rounding open.
    std::string input_signed_uv_area;
    /// The exact signed UV area rounded to the nearest integer, halves upwards; decided with
    /// exact rationals wherever the double sum's error bound does not decide it.
    std::int64_t input_signed_uv_area_rounded = 0;
};

struct VerifyOptions {
    /// Meshes without provenance are located on the input surface (see below); off: topology only.
    bool locate = true;
    /// Located mode: a vertex must map within this UV distance (inf-norm) of an integer grid point
    /// (the map is the raw input, with its solver noise; qex's own output is within 1e-6).
    double uv_tolerance = 1e-3;
    /// Located mode: and lie within this fraction of the bounding-box diagonal of the surface.
    double distance_tolerance = 1e-6;
    /// Threads for the checker's parallel loops (0: every core, 1: serial). The verdict and the
    /// violations do not depend on it.
    int threads = 0;
};

/// Judges `mesh` against `input` with its own code (no extraction code is shared) and exact
/// arithmetic: all-quad, manifold, oriented, boundary and Euler characteristic and components as
/// the input's, local UVs unit squares (when given). With `mesh.map_uvs` and provenance (qex's
/// own output): the sanitized map is an exact integer-grid map and every vertex is on its grid
/// point, exactly. Without provenance (any other extractor's mesh, or an OBJ read back), the
/// vertices are located on the surface: each must be the image of an integer grid point, each
/// face's corners one counter-clockwise grid cell, and the faces must cover the map.
/// Does not throw on malformed meshes.
VerifyResult verify(const Input& input, const QuadMesh& mesh, const VerifyOptions& options = {});

} // namespace qex

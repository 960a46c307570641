// qex — robust quad mesh extraction from relaxed integer-grid maps (QEx, Ebke et al. 2013).
//
// One entry point, plain structs:
//   qex::Input in = ...;                       // positions, triangles, per-corner UVs
//   qex::Result r = qex::extract(in);          // never throws, never aborts, never prints
//   if (!r.ok()) { r.error.message ... }       // bad input: what and where
//   r.mesh  (quads, local UVs, provenance)     // r.report: counts, defects, timings
//   qex::VerifyResult v = qex::verify(in, r.mesh);   // independent exact checker
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace qex {

// ============================================================================ input

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

// ============================================================================ errors

/// Why an input was rejected. Every code is distinct and maps to a distinct CLI exit code family.
enum class ErrorCode {
    None = 0,
    EmptyMesh,              ///< no triangles
    IndexOutOfRange,        ///< a triangle refers to a vertex that does not exist
    UvCountMismatch,        ///< uvs.size() != 3 * triangles.size()
    NonFiniteValue,         ///< NaN or Inf in a position or UV
    CoordinateTooLarge,     ///< |coordinate| >= 2^52: integer transitions cannot be exact
    DegenerateTriangle,     ///< a triangle uses the same vertex twice
    NonManifoldEdge,        ///< an edge has more than two incident triangles
    InconsistentOrientation,///< two triangles traverse an edge in the same direction
    NonManifoldVertex,      ///< the triangles around a vertex do not form one fan
    IsolatedVertex,         ///< a vertex used by no triangle
    ValenceCountMismatch,   ///< valences.size() != positions.size()
    BadFeatureEdge,         ///< a feature edge is not an edge of the mesh
    InconsistentMap,        ///< transitions around a vertex do not compose to a grid automorphism with a fixed point
    MapTooLarge,            ///< the map would need more q-vertices than Options::max_qvertices
    CollapseFailed,         ///< collapsing UV-degenerate edges would make the mesh non-manifold
};

struct Error {
    ErrorCode code = ErrorCode::None;
    std::string message;     ///< human readable, names the element
    std::int64_t element = -1; ///< index of the offending element (vertex, triangle, ...), -1 if none
};

const char* to_string(ErrorCode code);

// ============================================================================ options

struct Options {
    /// Upper bound on generated q-vertices (about the output's vertex count); protects callers
    /// from absurdly scaled maps (each q-vertex costs some 300 bytes during extraction).
    std::int64_t max_qvertices = 10'000'000;
    /// Upper bound on triangles crossed by one trace before it is declared failed.
    std::int64_t max_trace_steps = 100'000;
    /// Recover q-edges lost at singularities inside fold-overs (Section 5.5).
    bool recover_lost_edges = true;
    /// Merge q-vertex clones created by fold-overs (Algorithm 7).
    bool merge_vertices = true;
    /// Sort output vertices and faces canonically, so any input order gives the same output.
    bool canonical_order = true;
    /// Treat every boundary edge as a feature edge: snap it to its closest integer iso-line.
    /// For maps whose boundaries are meant to be aligned but carry solver noise.
    bool snap_boundary = false;
    /// When the checker rejects the output of the paper's method, retry on a map whose fold-over
    /// regions are relaxed (keeping transitions and singularities); see Report::rung.
    bool fallback_ladder = true;
    /// Threads for the parallel loops (built with QEX_OPENMP): 0 uses every core, 1 runs
    /// serially. The output is identical for every value.
    int threads = 0;
};

// ============================================================================ output

enum class QVertexKind : std::uint8_t { Vertex, Edge, Face };

/// Where an output vertex lies on the input surface.
struct Provenance {
    QVertexKind kind = QVertexKind::Face;
    /// Input vertex (Vertex), input triangle of the edge's half-edge (Edge), or input triangle (Face).
    int element = -1;
    /// For Edge: local edge index 0..2 of the half-edge (corner k to corner k+1) in triangle `element`.
    int local_edge = -1;
    /// Barycentric coordinates in triangle `element` (Edge/Face); (1,0,0) for Vertex.
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
    std::vector<Provenance> provenance;
    /// The sanitized map the mesh was extracted from: 3 UVs per input triangle, NaN for
    /// triangles removed by collapsing UV-degenerate edges. Empty for meshes from elsewhere.
    /// The checker verifies it is an exact integer-grid map and that every vertex's provenance
    /// names a grid point on the element it claims.
    std::vector<std::array<double, 2>> map_uvs;
};

/// A defect of the output that the input made unavoidable, with where it is.
enum class DefectKind {
    NonQuadFace,        ///< a face with other than 4 vertices survived simplification
    TraceFailed,        ///< an iso-line trace exceeded Options::max_trace_steps
    UnmatchedPort,      ///< a trace arrived at a grid point without a matching q-port
    PortConflict,       ///< two traces claimed the same q-port
    OpenFaceWalk,       ///< a face walk ran into an unconnected port in the interior
    PortlessQVertex,    ///< a q-vertex has no q-port (it lies only on degenerate triangles)
    CheckerViolation,   ///< the checker rejected the returned mesh here (no rung produced a valid one)
    // Explanations (Report::explanations): why the quad count differs from the UV area.
    FaceCollapsed,      ///< a face walk collapsed to a 2-gon or 1-gon after merging fold-over clones
    GhostFacesCancelled,///< a face and its reverse (a fold-over's double cover) were removed together
    BoundaryFaceDiscarded, ///< a face walk ran into a boundary that is not on an integer iso-line
};
const char* to_string(DefectKind kind);

struct Defect {
    DefectKind kind;
    std::string message;
    /// Input triangle (or vertex for PortlessQVertex of kind Vertex) near which it happened.
    std::int64_t input_element = -1;
    /// Output face index for NonQuadFace, -1 otherwise.
    std::int64_t output_face = -1;
    std::array<std::int64_t, 2> grid{0, 0};
};

struct Report {
    // input
    std::int64_t input_vertices = 0, input_triangles = 0;
    std::int64_t flipped_triangles = 0, degenerate_triangles = 0; ///< after sanitization
    std::int64_t collapsed_edges = 0;     ///< UV-degenerate edges collapsed (before and after sanitization)
    std::int64_t singularities = 0;       ///< interior vertices with non-identity or valence != 4
    double max_sanitization_displacement = 0.0; ///< largest |sanitized uv - input uv| (inf-norm)
    double sum_sanitization_displacement = 0.0;
    // geometry extraction
    std::int64_t qvertices_on_vertices = 0, qvertices_on_edges = 0, qvertices_in_faces = 0;
    std::int64_t ports = 0;
    // tracing
    std::int64_t traces = 0, traces_connected = 0, traces_into_boundary = 0, traces_failed = 0;
    std::int64_t orientation_flips_crossed = 0;
    // connectivity
    std::int64_t faces_traced = 0, boundary_faces_discarded = 0, open_face_walks = 0;
    std::int64_t recovered_edges = 0, merged_qvertices = 0, collapsed_faces = 0;
    std::int64_t ghost_faces_cancelled = 0; ///< faces removed in pairs with their reverse (Figure 2 (c))
    std::int64_t non_quad_faces = 0;
    /// Rounded signed UV area of the input (the expected quad count for fold-over-free closed maps).
    double signed_uv_area = 0.0;
    std::vector<Defect> defects;
    /// Where fold-overs removed quads (collapsed faces, cancelled ghost pairs), with locations:
    /// together they explain a quad count below the signed UV area.
    std::vector<Defect> explanations;
    /// Which rung of the fallback ladder produced the mesh ("as-given", "untangled-1", ...),
    /// how many were tried, and how many violations the checker found in the returned mesh.
    std::string rung;
    std::int64_t rungs_tried = 0;
    std::int64_t check_violations = 0;
    /// Triangles still flipped after untangling (rungs past the first).
    std::int64_t flipped_after_untangling = 0;
    /// Rungs past the first: output vertices that found no preimage of their grid point in the
    /// given map (they stay where the relaxed map put them, and the checker rejects them).
    std::int64_t unplaced_vertices = 0;
    /// Wall time per stage, in the order the stages ran.
    std::vector<std::pair<std::string, double>> stage_seconds;
};


// ============================================================================ verification

enum class ViolationKind {
    NotQuad, BadIndex, RepeatedVertex, NonManifoldEdge, InconsistentOrientation, NonManifoldVertex,
    UnreferencedVertex, NonFinitePosition, BoundaryMismatch, EulerMismatch, ComponentMismatch,
    LocalUvNotUnitSquare, EmptyMesh,
    MapNotIntegerGrid,   ///< map_uvs: across an edge the charts differ by more than a grid automorphism
    NotOnGridPoint,      ///< provenance: the vertex's grid point is not on the element it names
    SingularityOffGrid,  ///< map_uvs: a singular vertex is not on an integer grid point
    // Located mode (meshes without provenance, e.g. from other extractors):
    OffSurface,          ///< a vertex farther from the input surface than the distance tolerance
    FaceNotGridCell,     ///< a face's corners, carried into one chart, are not a ccw unit grid cell
    CoverageMismatch,    ///< the faces do not cover the map once (map without fold-overs)
    TooLarge,            ///< more face corners (mesh or input) than the checker's 32-bit tables hold
};
const char* to_string(ViolationKind kind);

struct Violation {
    ViolationKind kind;
    std::string message;
    std::int64_t element = -1; ///< output face, vertex or edge (see message)
};

struct VerifyResult {
    bool valid = false;
    std::vector<Violation> violations;
    std::int64_t faces = 0, vertices = 0, edges = 0, boundary_loops = 0, components = 0;
    std::int64_t euler = 0;
    std::int64_t input_euler = 0, input_boundary_loops = 0, input_components = 0;
    /// Largest and summed |map_uvs - input uvs| (inf-norm per corner; 0 without a map).
    double max_map_displacement = 0.0, sum_map_displacement = 0.0;
    /// Interior vertices of the map whose fan composes to a non-trivial rotation.
    std::int64_t map_singularities = 0;
    /// Located mode (the mesh has no provenance): vertices were located on the input surface.
    bool located = false;
    double max_grid_distance = 0.0;    ///< largest UV distance (inf-norm) of a vertex to its grid point
    double max_surface_distance = 0.0; ///< largest distance to the surface / bounding-box diagonal
    std::int64_t map_flipped_triangles = 0;
    std::int64_t coverage_difference = 0; ///< faces - rounded signed UV area
    /// Located mode: checks that could not be decided because the map folds over there (a
    /// face's corners carried across flipped triangles); not violations, listed for review.
    std::vector<Violation> undecided;
    /// Exact (rational) signed UV area of the input map, as a decimal string, and rounded.
    std::string input_signed_uv_area;
    std::int64_t input_signed_uv_area_rounded = 0;
};

struct Result {
    Error error;   ///< code None on success
    QuadMesh mesh;
    Report report;
    /// The checker's verdict on `mesh` (extract() consults the checker to choose a fallback rung).
    VerifyResult check;
    bool ok() const { return error.code == ErrorCode::None; }
};

/// Extracts the quad mesh induced by the integer-grid map of `input`.
/// Never throws (std::bad_alloc aside), never aborts, never prints.
Result extract(const Input& input, const Options& options = {});

/// Validates `input` as extract() would; returns an Error with code None when it is acceptable.
Error validate(const Input& input);

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

// ============================================================================ files

struct IoError {
    enum class Code { None, CannotOpen, CannotWrite, Syntax, MissingUv, NonTriangle, IndexOutOfRange,
                      NonFinite, VvalSyntax };
    Code code = Code::None;
    std::string message;
    std::int64_t line = 0; ///< 1-based line number, 0 if not applicable
    bool ok() const { return code == Code::None; }
};

/// Parses an OBJ with `v`, `vt` and `f a/ta b/tb c/tc` records (one UV per face corner).
/// `threads` parse large inputs in pieces (0: every core, 1: serial); the result, and the first
/// problem reported with its line, are those of a serial read. On a problem `out` is left empty.
IoError parse_obj(const char* data, std::size_t size, Input& out, int threads = 0);
IoError read_obj(const std::string& path, Input& out, int threads = 0);
/// Reads a VVAL valence file: `{"file_format":"VVAL","version":1}`, vertex count, one integer each.
IoError read_vval(const std::string& path, std::vector<int>& valences);
IoError parse_vval(const char* data, std::size_t size, std::vector<int>& valences);
/// Writes the quad mesh as OBJ (local UVs as `vt`), through a temporary file renamed into place.
IoError write_obj(const std::string& path, const QuadMesh& mesh);
/// Reads a polygon OBJ (v and f records; vt ignored) as a QuadMesh without UVs or provenance.
IoError read_polygon_obj(const std::string& path, QuadMesh& out);

} // namespace qex

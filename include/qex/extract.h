// The extractor: turns a triangle mesh carrying an integer-grid map into a quad mesh (QEx,
// Ebke et al. 2013, with the robustness extensions the README lists). Never throws (std::bad_alloc
// aside), never aborts, never prints: bad input comes back as an Error, defects in the Report.
#pragma once

#include "qex/mesh.h"
#include "qex/verify.h"

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace qex {

/// Why an input was rejected. Every code is distinct and maps to a distinct CLI exit code family.
enum class ErrorCode {
    None = 0,
    EmptyMesh,               ///< no triangles
    IndexOutOfRange,         ///< a triangle refers to a vertex that does not exist
    UvCountMismatch,         ///< uvs.size() != 3 * triangles.size()
    NonFiniteValue,          ///< NaN or Inf in a position or UV
    CoordinateTooLarge,      ///< |coordinate| >= 2^52: integer transitions cannot be exact
    DegenerateTriangle,      ///< a triangle uses the same vertex twice
    NonManifoldEdge,         ///< an edge has more than two incident triangles
    InconsistentOrientation, ///< two triangles traverse an edge in the same direction
    NonManifoldVertex,       ///< the triangles around a vertex do not form one fan
    IsolatedVertex,          ///< a vertex used by no triangle
    ValenceCountMismatch,    ///< valences.size() != positions.size()
    BadFeatureEdge,          ///< a feature edge is not an edge of the mesh
    InconsistentMap,         ///< transitions around a vertex do not compose to a grid automorphism with a fixed point
    MapTooLarge,             ///< the map would need more q-vertices than Options::max_qvertices
    CollapseFailed,          ///< collapsing UV-degenerate edges would make the mesh non-manifold
};

struct Error {
    ErrorCode code = ErrorCode::None;
    std::string message;       ///< human readable, names the element
    std::int64_t element = -1; ///< index of the offending element (vertex, triangle, ...), -1 if none
};

const char* to_string(ErrorCode code);

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
    /// For maps whose boundaries are meant to be aligned but lie off the iso-lines. Without it,
    /// a boundary loop whose every edge lies within solver noise (1/1024 of a cell, or a few
    /// ulps) of an iso-line is still snapped onto them, as a seam within noise of a grid
    /// transition is rounded to it.
    bool snap_boundary = false;
    /// Re-embed the regions of flipped and degenerate triangles before extraction (stage repair),
    /// keeping transitions, singularities, boundaries and everything outside them; the mesh
    /// carries the repaired map and which triangles changed (QuadMesh::map_repaired). The one
    /// exception: two singularities of opposite index that a fold put on one grid point are
    /// merged into regular vertices (the transitions of a short path between them change), each
    /// merge named in the report (DefectKind::SingularitiesMerged).
    bool repair_fold_overs = true;
    /// A seam whose two UV copies no grid transition relates (more than 1/1024 of a cell apart
    /// after the nearest one) is an input error (ErrorCode::InconsistentMap, naming the seam).
    /// With this set, such seams are instead rounded to the nearest transition, as the paper's
    /// sanitization does with noise, and each is reported (DefectKind::SeamRounded): the map
    /// moves by up to half a cell there.
    bool round_inconsistent_seams = false;
    /// When the checker rejects the mesh of the repaired map, retry on the map as given with the
    /// paper's local handling of fold-overs alone, then (last resorts, uncertified) on maps whose
    /// folded regions are relaxed, with the mesh moved back onto the given map; see Report::rung.
    bool fallback_ladder = true;
    /// When no rung gives a valid mesh at the map's own scale, retry with the map's UVs
    /// multiplied by 2, then 4, ... up to this factor (a power of two; 1 disables). Maps too
    /// coarse for their surface (a handle or neck less than a quad or two around, clusters of
    /// singularities within a quad, boundary holes a fraction of a quad across) induce no valid
    /// quad mesh at their own scale, but they do
    /// once every quad is split into K x K. The mesh then carries QuadMesh::grid_scale = K, the
    /// report says so (Report::grid_scale, and an explanation naming what failed at scale 1), and
    /// the checker judges it against the map scaled by K. Needs fallback_ladder. Not tried past
    /// 200,000 quads (the map's signed UV area times K^2): a map that large is not too coarse;
    /// nor past as many quads as the input has triangles, where a cell is smaller than a
    /// triangle on average and a finer grid resolves nothing more.
    int max_refinement = 16;
    /// When the map gives no valid mesh at its own scale (fold-overs that cover many cells, as on
    /// a map whose UVs were multiplied to make the quads smaller), and the map is twice an
    /// integer-grid map laid from some grid point o (u = 2 u' + o: every singularity, and every
    /// boundary or feature edge on an iso-line, on the coarse grid, every transition one of its
    /// automorphisms), the ladder runs on that map, then on the map divided by 4, ... up to this
    /// factor K (a power of two; 1 disables). Its sanitized map must be the given map's, moved
    /// and divided, to within sanitizing's truncation (outside the triangles its repair
    /// changed). The first valid mesh there has each quad split into
    /// K x K on the given map, every new vertex on a preimage of its grid point, and is judged
    /// against the map it carries (the coarse map times K) like any other, and also without its
    /// provenance against the given map (as `qex check --param` judges): the report says so
    /// (Report::coarsening, and an explanation naming what failed at scale 1). Tried before
    /// refinement. Needs fallback_ladder.
    int max_coarsening = 16;
    /// When no attempt gives a valid mesh (the map would end with exit code 5), return the
    /// attempt closest to valid instead of the one at the map's own scale: the one with the
    /// fewest checker violations among the map's own scale and its refinements (ties to the
    /// smallest grid scale), every violation located in the report (Report::defects), and a
    /// BestEffortMesh explanation naming the choice. The result stays invalid (Result::check).
    /// Refinement then runs even where a collapsed handle (DefectKind::MapCollapsesHandle) proves
    /// that none can give a valid mesh, and stops at the first attempt whose only violations are
    /// the topology that handle loses. Without it, nothing changes.
    bool best_effort = false;
    /// The last resort, when no attempt at any scale gives a valid mesh: holes that no cells of the
    /// grid close (their rims lay out in none, or round grid points with no vertex; rims of up to
    /// 24 vertices) are filled with quads joining their rim vertices, in the mesh each scale gave
    /// or in the first rung's there that lost only its topology, its sheets joined at an edge
    /// separated first where they are (DefectKind::SheetsSeparated); at the smallest scale where
    /// the checker then accepts the mesh (DefectKind::HoleFilled: those quads follow no cells of
    /// the map; the checker rejects them where the map requires cells, and judges them by topology
    /// and footprint where it judges a fold-over on the surface only, as round a fold between
    /// pinned singularities). Off: such a map ends invalid. Needs fallback_ladder.
    bool fill_holes = true;
    /// Called on the calling thread each time a pipeline stage finishes, with the stage's name
    /// (the README's stage table) and the refinement factor being tried (1 at the map's own
    /// scale). For progress display; it must not throw. Empty: not called.
    std::function<void(const char* stage, int grid_scale)> on_stage;
    /// Threads for the parallel loops and the repair's independent fold-over regions (built with
    /// QEX_OPENMP): 0 uses every core, 1 runs serially. The output is identical for every value.
    int threads = 0;
};

/// A defect of the output that the input made unavoidable, with where it is.
enum class DefectKind {
    NonQuadFace, ///< a face with other than 4 vertices survived simplification
    /// An iso-line trace found no edge to leave a triangle by, or crossed
    /// Options::max_trace_steps triangles.
    TraceFailed,
    UnmatchedPort,    ///< a trace arrived at a grid point without a matching q-port
    PortConflict,     ///< two traces claimed the same q-port
    OpenFaceWalk,     ///< a face walk ran into an unconnected port in the interior
    PortlessQVertex,  ///< a q-vertex has no q-port (it lies only on degenerate triangles)
    CheckerViolation, ///< the checker rejected the returned mesh here (no rung produced a valid one)
    // Explanations (Report::explanations): why the quad count differs from the UV area.
    FaceCollapsed,         ///< a face walk collapsed to a 2-gon or 1-gon after merging fold-over clones
    GhostFacesCancelled,   ///< a face and its reverse (a fold-over's double cover) were removed together
    BoundaryFaceDiscarded, ///< a face walk ran into a boundary that is not on an integer iso-line
    FoldOverNotRepaired,   ///< stage repair left a fold-over as the map gives it (the paper's handling applies)
    /// No valid mesh at the map's own scale: the mesh is extracted on the map with its UVs
    /// multiplied by Report::grid_scale (Options::max_refinement); names the first failure at scale 1.
    MapRefined,
    /// A seam no grid transition relates was rounded to the nearest one
    /// (Options::round_inconsistent_seams); names the seam and how far off it was.
    SeamRounded,
    /// Two singularities of opposite index on one grid point, with a fold between them (solver
    /// rounding), were merged into regular vertices before the fold was re-embedded; names both.
    SingularitiesMerged,
    /// No valid mesh at the map's own scale, but the map with its UVs divided by
    /// Report::coarsening is an integer-grid map too and gives one: each of its quads is split
    /// into that many by that many (Options::max_coarsening); names the first failure at scale 1.
    MapCoarsened,
    /// A hole that face walks left open (next to a fold-over, a trace lost to a port conflict) was
    /// closed by the unit cells its rim encloses in the grid, and the checker accepted the mesh
    /// with them; names the rim's output vertices and how many cells.
    HoleClosed,
    /// Sheets of a fold-over were joined at an edge of more than two face sides (merging clones
    /// took a vertex of each sheet for one on both its ends). Its ends were split into a vertex per
    /// fan, each moved onto the preimage of its grid point nearest its fan, and the checker
    /// accepted the mesh so (holes closed too, if HoleClosed follows); names the edge, the
    /// vertices split and the grid point.
    SheetsSeparated,
    /// No valid mesh at the map's own scale, and none on the map with its UVs multiplied by a
    /// refinement factor either (Options::max_refinement): one per factor tried, naming the first
    /// of that attempt's checker violations, located (its grid point is in the refined map, so
    /// `grid` is left (0, 0); `input_element` is -1 for a violation of the whole mesh that names
    /// no place). Only in a report whose mesh is invalid.
    RefinementFailed,
    /// The map collapses a handle of the surface: a region of triangles whose UV areas are far
    /// below a cell (each at most 1/64 of one, with the map multiplied by the largest refinement,
    /// 16), folded onto itself (at most half its absolute UV area is left signed) and net below
    /// one cell at that refinement, and that holds a cycle no disk of the surface bounds. No
    /// mesh that follows the map keeps that handle, at any scale up to that refinement, so
    /// refinement is not tried (unless Options::best_effort). First among the defects of an
    /// invalid result, before the symptoms that follow from it; names the input vertex its
    /// region is round, its triangles and UV areas (Report::collapsed_handles has them all).
    MapCollapsesHandle,
    /// Options::best_effort: the mesh returned is the attempt closest to valid (the fewest
    /// checker violations, ties to the smallest grid scale); names it and its violation count.
    BestEffortMesh,
    // Proofs (Report::explanations, before the FoldOverNotRepaired they back), with singularities
    // held at their grid points.
    /// The rim of a fold-over's region turns about the grid point of its one singularity by fewer
    /// quarter turns than the singularity's angle (stage repair's room certificate; in a fold-free
    /// map it turns by the angle, and a full turn more for each other preimage of the point): no
    /// fold-free map of that region, its rim as the map gives it, keeps the singularity at its grid
    /// point. (A larger region moves the rim; the repair tried those it could.) Names the
    /// singularity (input vertex, the quarter turns it needs and its rim turns, `grid` its grid
    /// point in the chart of `input_element`, a triangle of its fan) and the region (rings,
    /// triangles).
    RimShortOfSingularity,
    /// A flipped triangle (UV area < 0) whose three corners are singularities: none of them moves,
    /// so no fold-free map keeps them at their grid points. Names the triangle (`input_element`),
    /// its UV area and its corners (input vertices, `grid` the first one's grid point).
    FoldPinnedBySingularities,
    /// Stage repair's room certificate proves a fold-over's region has no fold-free map that keeps
    /// every vertex's winding, its rim and singularities as the map gives them: a fixed vertex
    /// whose triangles outside the region leave it an angle positive triangles cannot fill (at
    /// most 0, or at least half a turn per corner), or angles that sum, over the fixed vertices,
    /// other than half a turn per triangle (Gauss-Bonnet; where whole turns are missing among
    /// several singularities, with their valences as the map counts them). Names the region
    /// (rings, triangles, singularities; `input_element` its triangle of smallest input index,
    /// `grid` near that triangle's first corner), the vertex and the quarter turns.
    AnglesLeaveNoRoom,
    /// A fold-over's region whose signed UV area is not positive: moving its free vertices keeps
    /// the sum, so no map of it with its rim and singularities as given is fold-free. Names the
    /// region as AnglesLeaveNoRoom does, and its area.
    RegionAreaNotPositive,
    /// The last resort, once no attempt at any scale gave a valid mesh: a hole that face walks
    /// left and no cells of the grid close (HoleClosed could not: its rim lays out in no grid, as
    /// where its vertices' fans wind round a fold between pinned singularities, or round a grid
    /// point with no vertex) was filled with quads joining its rim vertices (no new vertex), and
    /// the checker accepted the mesh so, against the map it carries and the given map. These quads
    /// follow no cells of the map; names the rim's output vertices and how many quads. The mesh is
    /// at the smallest scale (but coarsened ones) where this made it valid.
    HoleFilled,
};
const char* to_string(DefectKind kind);

struct Defect {
    DefectKind kind;
    std::string message;
    /// Input triangle near which it happened (for a q-vertex or an output vertex: the triangle
    /// whose chart `grid` is in); -1 for a defect of the whole mesh that names no place.
    std::int64_t input_element = -1;
    /// Output face at fault (NonQuadFace, and a CheckerViolation of one face); -1 otherwise.
    std::int64_t output_face = -1;
    /// Integer grid point in the chart of triangle `input_element`; (0, 0) for a defect that
    /// names no grid point (a checker violation of an input vertex or triangle, or of the
    /// whole mesh).
    std::array<std::int64_t, 2> grid{0, 0};
    /// For CheckerViolation: the kind of the checker's violation.
    std::optional<ViolationKind> violation;
};

/// A handle of the surface that the map collapses (DefectKind::MapCollapsesHandle).
struct CollapsedHandle {
    /// The input vertex the region is round: the one with the most of its triangles.
    std::int64_t vertex = -1;
    /// The region's input triangles, in increasing order: each has a UV area far below a cell.
    std::vector<std::int64_t> triangles;
    /// Their UV area, signed (what they cover net) and absolute, in cells of the map as given.
    double signed_uv_area = 0.0, absolute_uv_area = 0.0;
    /// The region with the disks of the surface it encloses: its genus and its rims (boundary
    /// loops across which the rest of the surface lies; the input's own boundary loops are
    /// not counted). Not a disk: genus > 0 or more than one rim.
    int genus = 0, rims = 0;
};

struct Report {
    // input
    std::int64_t input_vertices = 0, input_triangles = 0;
    /// Triangles of the sanitized map with UV area < 0 (flipped) and == 0 (degenerate), exactly.
    std::int64_t flipped_triangles = 0, degenerate_triangles = 0;
    std::int64_t collapsed_edges = 0;           ///< UV-degenerate edges collapsed (before and after sanitization)
    std::int64_t singularities = 0;             ///< interior vertices with non-identity or valence != 4
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
    /// Of those, faces removed in near pairs (a face walked clockwise over a fold and a face with
    /// its other three corners reversed, their fourth corners merged). A mesh with any must also
    /// pass the oracle without provenance (as `qex check --param` judges it) to be accepted.
    std::int64_t near_ghost_faces_cancelled = 0;
    std::int64_t non_quad_faces = 0;
    /// Signed UV area of the map the mesh was extracted from (sanitized and repaired), a double
    /// sum: the expected quad count for fold-over-free closed maps. A repair keeps it.
    double signed_uv_area = 0.0;
    std::vector<Defect> defects;
    /// Where fold-overs removed quads (collapsed faces, cancelled ghost pairs), with locations:
    /// together they explain a quad count below the signed UV area.
    std::vector<Defect> explanations;
    /// Which rung of the fallback ladder produced the mesh ("repaired", "as-given", "untangled-1",
    /// "untangled-3"), how many were tried, and how many violations the checker found in the
    /// returned mesh.
    std::string rung;
    std::int64_t rungs_tried = 0;
    std::int64_t check_violations = 0;
    /// Stage repair: fold-over regions re-embedded, the triangles whose UVs it changed, the
    /// regions it left as given (each named in `explanations`), and the triangles still flipped
    /// or degenerate (UV area <= 0) after it.
    std::int64_t repaired_regions = 0, repaired_triangles = 0, unrepaired_regions = 0;
    std::int64_t flipped_after_repair = 0;
    /// Of the explanations that removed faces (FaceCollapsed, GhostFacesCancelled,
    /// BoundaryFaceDiscarded) on a rung that repairs: those next to a fold-over the repair left
    /// with a proof that no fold-free map of its region exists (a proof among the explanations
    /// backs it), and the others (next to a fold-over the repair failed on, or to none). Each such
    /// explanation's message says which, and names the fold-over.
    std::int64_t losses_proved = 0, losses_not_proved = 0;
    /// Last-resort rungs: output vertices that found no preimage of their grid point in the
    /// given map (they stay where the relaxed map put them, and the checker rejects them).
    std::int64_t unplaced_vertices = 0;
    /// 1, or the factor K the map's UVs were multiplied by to give a valid mesh (each quad of the
    /// map's own scale is then K x K quads of the mesh; Options::max_refinement). The rest of the
    /// report describes the extraction at that scale; `explanations` names what failed at scale 1.
    int grid_scale = 1;
    /// Refinement factors tried after scale 1 failed (0 when scale 1 succeeded or refinement is off).
    std::int64_t refinements_tried = 0;
    /// 1, or the factor K the map's UVs were divided by to give a valid mesh, whose quads were
    /// then split into K x K (Options::max_coarsening). The rest of the report describes the
    /// extraction at that scale, but for signed_uv_area (the given map's, as the mesh's quads
    /// are); `explanations` names what failed at scale 1.
    int coarsening = 1;
    /// Handles of the surface the map collapses (DefectKind::MapCollapsesHandle), looked for
    /// when no attempt at the map's own scale gives a valid mesh.
    std::vector<CollapsedHandle> collapsed_handles;
    /// Wall time per pipeline stage, under the stage's name (its file, function and benchmark
    /// name; see the README's pipeline table), summed over every run of the stage in this
    /// extraction (sanitize rounds, and every rung tried), in first-run order.
    std::vector<std::pair<std::string, double>> stage_seconds;
};

struct Result {
    Error error; ///< code None on success
    QuadMesh mesh;
    Report report;
    /// The checker's verdict on `mesh` (extract() consults the checker to choose a fallback rung).
    VerifyResult check;
    bool ok() const { return error.code == ErrorCode::None; }
};

/// Extracts the quad mesh induced by the integer-grid map of `input`.
/// Never throws (std::bad_alloc aside), never aborts, never prints.
Result extract(const Input& input, const Options& options = {});

/// The first checks extract() makes: values, indices and the mesh's topology (manifold,
/// oriented, no isolated vertex). Code None means extract() gets past them; the map itself can
/// still be rejected there (InconsistentMap, MapTooLarge, CollapseFailed).
Error validate(const Input& input);

/// The exact orientation of each triangle in the map as given (its three corner UVs): +1,
/// 0 (degenerate) or -1 (flipped), by the core's exact predicate. Input::uvs must hold three
/// UVs per triangle.
std::vector<std::int8_t> uv_orientations(const Input& input);

} // namespace qex

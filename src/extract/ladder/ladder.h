// The fallback ladder: what extract() tries, in this order, until the checker accepts a mesh.
//
//   the map at its own scale:  rung repaired -> as-given -> untangled-1 -> untangled-3   kLadder, ladder.cpp
//   no rung's mesh is valid:   the ladder on the map / 2, / 4, ... (while it is an       coarsen.cpp
//                              integer-grid map), the first valid mesh split back onto it
//   still none:                the ladder on the map x 2, x 4, ... x 16                   refine.cpp
//   valid, but more quads than the signed UV area: the coarsened mesh, if closer to it   (extract.cpp)
//
// Every rung runs the pipeline's stages (pipeline.h) on the validated, collapsed mesh, in the
// order of the stage table. The steps only some rungs take are here: untangle and
// place_on_given_map (the relaxed rungs), separate_sheets and close_holes (a mesh the checker
// rejected), map_divisible_by and split_onto_map (coarsening).
#pragma once

#include "../pipeline.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <future>
#include <iterator>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

namespace qex::detail {

// ============================================================================ the rungs' steps

/// Last resort: relaxes regular vertices within `rings` of a flipped or degenerate triangle (UV
/// area <= 0) towards the average of their neighbours, through exact transitions. Returns the
/// number of triangles still flipped or degenerate. Uncertified: its mesh is moved back onto the
/// given map (place_on_given_map) and must pass the checker there.
std::int64_t untangle(TriMesh& m, int rings, int iterations);

/// The input's triangles with their topology and the transitions of one map, as the searches for
/// preimages read them (place_on_given_map, separate_sheets): made on first use and kept for the
/// next search on the same map. On armadillo_geo_180 each made took 30-40 ms, and one judgement
/// made it up to three times (placement, then both separations of the sheets).
class MapGraph {
public:
    explicit MapGraph(const Input& input) : input_(input) {}
    const Input& input() const { return input_; }
    /// The graph of `map` (per input corner); nullptr where the input's topology cannot be built.
    const TriMesh* of(const std::vector<std::array<double, 2>>& map);

private:
    const Input& input_;
    std::vector<std::array<double, 2>> map_;
    TriMesh graph_;
    bool made_ = false, ok_ = false;
};

/// For a mesh extracted from a relaxed map: moves every output vertex onto a preimage of its grid
/// point in `given` (the sanitized map as given, per input corner, NaN where collapsed), found
/// by a breadth-first search from its provenance triangle, and sets its provenance and the
/// mesh's map to that map. Returns the number of vertices it could not place.
/// The given map's graph is taken from (or made into) `graph`.
std::int64_t place_on_given_map(MapGraph& graph, const std::vector<std::array<double, 2>>& given, QuadMesh& mesh);

/// Where some vertices lie in space: the mean of their positions and the largest squared distance
/// of one from it. A point within twice that distance of the mean is near them (the split and
/// separate_sheets take a free preimage only there).
struct Neighbourhood {
    std::array<double, 3> mean{0, 0, 0};
    double reach2 = 0.0;
    template <class Indices>
    Neighbourhood(const std::vector<std::array<double, 3>>& positions, const Indices& vertices) {
        const auto n = static_cast<double>(std::size(vertices));
        for (const int v : vertices)
            for (std::size_t d = 0; d < 3; ++d) mean[d] += positions[static_cast<std::size_t>(v)][d] / n;
        for (const int v : vertices) reach2 = std::max(reach2, distance2(positions[static_cast<std::size_t>(v)]));
    }
    double distance2(const std::array<double, 3>& x) const {
        double d = 0.0;
        for (std::size_t k = 0; k < 3; ++k) d += (x[k] - mean[k]) * (x[k] - mean[k]);
        return d;
    }
    bool near(const std::array<double, 3>& x) const { return distance2(x) <= 4 * reach2; }
};

/// Per point (a provenance: a grid point in the chart of its triangle), the preimages of its grid
/// point in `map` (per input corner) that a breadth-first search from its triangle finds, as
/// place_on_given_map searches (crossing edges with their transitions, up to its budget):
/// positive triangles' first, then flipped ones'; one per place on the surface, with its
/// position, in the order found.
std::vector<std::vector<std::pair<Provenance, std::array<double, 3>>>> preimages(
    MapGraph& graph, const std::vector<std::array<double, 2>>& map, const std::vector<Provenance>& points);

/// For a mesh the checker rejected: each edge with more than two face sides (sheets of a
/// fold-over joined there by merged clones) is cut by splitting an end into one vertex per fan
/// round it (faces joined across edges of two face sides): an end that ends no other such edge
/// first, and of an edge's ends the one of smaller index first, or of larger with
/// `larger_end_first`; then every end still the corner of several fans. The copies are appended.
/// Each vertex split then takes the preimage of its grid point in the mesh's map (preimages)
/// nearest the vertices round its fan. Returns one explanation (SheetsSeparated) per edge cut;
/// none, and no candidate, if the mesh has no such edge, lacks provenance, or the vertices of one
/// split would coincide (a grid point with one preimage there: the sheets stay joined in space).
/// A candidate only: the caller keeps it if the checker accepts the result.
std::vector<Defect> separate_sheets(const Input& input, QuadMesh& mesh, bool larger_end_first);
/// As above, the mesh's map's graph taken from (or made into) `graph`.
std::vector<Defect> separate_sheets(MapGraph& graph, QuadMesh& mesh, bool larger_end_first);

/// The cuts of separate_sheets alone, without moving a vertex: returns the explanations, and per
/// vertex split, it then its copies (`groups`).
std::vector<Defect> cut_joined_edges(QuadMesh& mesh, bool larger_end_first, std::vector<std::vector<int>>& groups);

/// The longest rim close_holes closes: a hole of a few cells, not a missing region of the map.
inline constexpr std::size_t kMaxClosedRim = 16;
/// The longest rim fill_holes fills (its search over quadrangulations is bounded too).
inline constexpr std::size_t kMaxFilledRim = 24;

/// The holes of an all-quad, manifold mesh with provenance (none otherwise): those away from the
/// input's boundary whose rims are simple loops of 4 to `max_rim` of its vertices.
struct Holes {
    /// Each rim with the hole on its left (the faces' boundary edges reversed), from its vertex of
    /// smallest index: a face of rim vertices in this order is oriented as the mesh.
    std::vector<std::vector<int>> rims;
    std::vector<int> corners; ///< per vertex of the mesh: the faces it is a corner of
    /// Per vertex of the mesh: the quarter turns round it as the fan of the input vertex it lies
    /// on winds in the map the mesh carries (a singularity's valence), 4 elsewhere or unread.
    std::vector<int> wound;
    /// The faces' half-edges (a -> b as (a << 32) | b), sorted.
    std::vector<std::uint64_t> half;
};
Holes find_holes(const Input& input, const QuadMesh& mesh, std::size_t max_rim = kMaxClosedRim);

/// "its rim through output vertices ...", for explanations.
std::string rim_description(const std::vector<int>& rim);

/// Puts `faces` (of rim vertices, oriented as the mesh) into the hole of `mesh` that `rim` bounds,
/// each with unit-square local UVs; returns the explanation of `kind` saying `what`, placed at the
/// rim's first vertex (its chart triangle and grid point).
Defect patch_hole(QuadMesh& mesh, const std::vector<int>& rim, const std::vector<std::vector<int>>& faces,
                  DefectKind kind, const std::string& what);

/// close_holes on the holes found (find_holes on `mesh` as it was): adds an explanation per hole
/// closed to `done`, and returns per rim whether it was closed.
std::vector<char> close_rims(const Holes& holes, QuadMesh& mesh, bool wound_first, std::vector<Defect>& done);

/// For a mesh the checker rejected: closes each hole away from the input's boundary whose rim (a
/// simple loop of at most 16 vertices) encloses, laid out in the grid from the quarter turns its
/// faces leave each rim vertex (four each, or as many as the fan of the input vertex it lies on
/// winds; `wound_first` picks which reading is tried first, the other where a rim does not close),
/// unit cells whose corners are all rim vertices: those cells are added as faces. Returns one
/// explanation (HoleClosed) per hole closed. A candidate only: the caller keeps it if the checker
/// accepts the result.
std::vector<Defect> close_holes(const Input& input, QuadMesh& mesh, bool wound_first = false);

/// Last resort, for a mesh no scale's attempt made valid: closes the holes of find_holes() (rims
/// of up to kMaxFilledRim vertices) that cells close, as close_holes closes them (with
/// `wound_first` as there), then fills each other one whose rim has an even number of vertices (its
/// rim lays out in no grid, or round grid points with no vertex) with quads that join rim vertices,
/// no new vertex: of every such quadrangulation whose diagonals are no edges of the mesh, the one
/// that leaves the rim vertices' face counts nearest their quarter turns (Holes::wound), then with
/// the shortest diagonals (squared, in space), exactly (a dynamic programme), the first of its
/// order from the rim's vertex of smallest index among equals. Returns one
/// explanation per hole (HoleClosed, HoleFilled). A candidate only: the caller keeps it if the
/// checker accepts the result.
std::vector<Defect> fill_holes(const Input& input, QuadMesh& mesh, bool wound_first = false);

// ============================================================================ scales

/// The sanitized map before stage repair and after it, with what the repair reported: kept from
/// the map at its own scale for its refinements. Refining multiplies the UVs by a power of two,
/// exactly, and leaves the repair's problem as it was (the same triangles, rims and
/// singularities), so the repair is not run again where the refined map's sanitized state is
/// exactly the kept one times the factor.
struct RepairMemo {
    bool filled = false;
    /// Whether the rung that repaired has handed over its connectivity and transitions
    /// (keep_for_refinements): until then a refinement cannot take this repair.
    bool connectivity = false;
    // Before the repair: connectivity, UVs and map state.
    std::vector<std::array<int, 3>> tri;
    std::vector<int> input_triangle, input_vertex, corner_vertex;
    std::vector<Point2> sanitized;
    TransitionTable transitions;
    std::vector<char> singular;
    std::vector<int> valence, winding_valence;
    // After it: the corners and half-edges it changed (by their bits), with their new values,
    // and the per-vertex state (a copy of the whole map cost 12 ms on the twice-subdivided duck).
    std::vector<std::size_t> repaired_corners;
    std::vector<Point2> repaired_uvs;
    std::vector<std::size_t> repaired_half_edges;
    std::vector<GridAutomorphism> repaired_transitions;
    std::vector<char> repaired_singular;
    std::vector<int> repaired_valence, repaired_winding_valence;
    RepairOutcome outcome;
    std::vector<Defect> explanations; ///< the ones the repair added (merged singularities)
    /// repaired_half_edges with their transitions before the repair: keep_for_refinements undoes
    /// the repair's changes with them.
    std::vector<std::pair<int, GridAutomorphism>> transitions_before;
};

/// One attempt at the ladder: the map's own scale, or a refinement of it.
/// The checker's analysis of the input (qex::PreparedInput), made once for every check in one
/// extract() call, at every scale (a scaled map keeps the triangles). With threads to spare it
/// is made on a thread of its own from start() on (prepare_map starts it before the repair), for
/// an input of kParallelMinElements corners or more; else at the first check.
/// The checker's own code makes it: the extractor only keeps it.
class CheckedInput {
public:
    CheckedInput(const Input& input, int threads) : input_(input), threads_(threads) {}
    CheckedInput(const CheckedInput&) = delete;
    CheckedInput& operator=(const CheckedInput&) = delete;
    /// Starts the analysis beside the caller (once; the input must be valid).
    void start();
    /// The analysis, once it is made (here, if it was not started).
    const PreparedInput& get();

private:
    const Input& input_;
    int threads_;
    std::mutex mutex_;
    std::future<std::unique_ptr<PreparedInput>> beside_; ///< waited for when destroyed
    std::unique_ptr<PreparedInput> prepared_;
};

struct AtScale {
    /// The UVs times this power of two (1: the map as given).
    std::int64_t factor = 1;
    /// The map at its own scale passed check_seams: its solver noise, multiplied with it, can
    /// exceed the check's bound and is noise still, so a refinement's seams are trusted.
    bool seams_checked = false;
    /// Factor 1: filled by the repair, if one runs. Larger: the repair it holds is taken, times
    /// the factor, where it applies (RepairMemo).
    RepairMemo* memo = nullptr;
    /// The checker's analysis of the input, for every check at this scale (none: each check
    /// analyses the input itself).
    CheckedInput* checked = nullptr;
};

// ============================================================================ the ladder (ladder.cpp)

/// The whole ladder on `input` at its own scale (`scale`: which attempt this is): the first
/// rung whose mesh the checker accepts, else the one with the fewest violations, located.
/// With `fillable` (and Options::fill_holes), the first rung's rejected attempt whose violations
/// are topology_only() is copied there (its report's rung says which; none: its rung is empty),
/// for the last resort once every scale failed.
Result extract_at_scale(const Input& input, const Options& options, const AtScale& scale = {},
                        Result* fillable = nullptr);

/// Whether the rung named `name` (Report::rung) relaxed the map: a last resort.
bool relaxed_rung(const std::string& name);

/// The feature edges to snap: the input's, and every boundary edge with Options::snap_boundary.
std::vector<std::array<int, 2>> feature_edges(const TriMesh& m, const Input& input, const Options& options);

/// The sanitized map, per input corner, for the checker (NaN for triangles collapsed away).
/// Only the map and the triangle numbering of the working mesh are still needed: the rest is
/// released first, and when no triangle was collapsed away the map is handed over uncopied.
std::vector<std::array<double, 2>> take_map(TriMesh& m, const Input& input);

/// The map as given, sanitized (stages validate and collapse, then sanitize's rounds), in `m`.
bool sanitize_as_given(const Input& input, const Options& options, TriMesh& m, Report& report);

/// Adds `from`'s stage times to `to`'s, stage by stage.
void add_stage_seconds(const Report& from, Report& to);

// ============================================================================ a rung's stages (rung_stages.cpp)

/// Stages generate_qvertices to merge_vertices on the map m: the output faces, flat, in `faces`.
Error extract_mesh(const TriMesh& m, const Options& options, Result& result, StageTimer& timer, FaceWalks& faces);

// ============================================================================ a rejected mesh mended (mend.cpp)

/// The violations of `mesh` judged without its provenance against the given map, as
/// `qex check --param` judges any extractor's mesh (fold-over regions on the surface only, or not).
std::vector<Violation> located_violations(const Input& input, const QuadMesh& mesh, VerifyOptions options,
                                          bool fold_regions);

/// Stages separate_sheets and close_holes, on a mesh the checker rejected. Where the checker
/// found an edge of more than two face sides, the edges that join sheets of a fold-over are cut
/// (of an edge's ends, the smaller first where the order is free, then the larger); each such
/// mesh is kept if it is accepted (the checker passes it, and the oracle without provenance
/// against the given map: fold-over regions judged on the surface, or everywhere after a
/// relaxed rung), or once its holes are closed too. Else the holes of the mesh as it is are
/// closed, and the result kept if it is accepted. Nothing is tried (no stage runs) when the
/// checker found what no mend step changes: a face that is no quad or whose local UVs are no unit
/// square, or a fault of the carried map, its certificate or the mesh's size.
/// `graph`, if given, is the input's (MapGraph), shared with the judgement's other searches.
void mend_if_accepted(const Input& input, bool relaxed, const VerifyOptions& verify_options, StageTimer& timer,
                      Result& attempt, MapGraph* graph = nullptr);

/// Stage fill_holes, the last resort, on an attempt (at the scale of `input`) that no rung made
/// valid, then on `other` (another rung's rejected mesh at that scale, if given and another
/// rung): its holes filled (fill_holes), on the mesh as it is and, where sheets are joined at an
/// edge, on each separation of them (separate_sheets); kept if the checker accepts the mesh so,
/// as a mended mesh must be accepted (against the map it carries and the given map; everywhere
/// after a relaxed rung). Then `attempt` becomes that mesh's attempt, valid: its explanations
/// gain the cuts and filled holes, its located checker violations go (its extraction defects
/// stay), and its report keeps `attempt`'s totals (stage times, rungs and refinements tried). False, and
/// nothing changed but the stages' time, otherwise.
/// `checked`: the checker's analysis of the input, if kept (AtScale::checked).
bool fill_holes_if_accepted(const Input& input, const Options& options, Result& attempt, const Result* other = nullptr,
                            CheckedInput* checked = nullptr);

/// Whether a rejected mesh's violations are all of its topology (non-manifold edges and
/// vertices, holes, Euler characteristic, boundary loops, components), a hole or an edge joining
/// sheets among them: what the last resort can mend.
bool topology_only(const std::vector<Violation>& violations);

// ============================================================================ refinement (refine.cpp)

/// Stage repair on the sanitized map m, or its result at the map's own scale taken from
/// `scale.memo` (see RepairMemo), which the repair at that scale fills; on up to `threads` threads.
/// `look` as for repair().
RepairOutcome repair_at_scale(TriMesh& m, const std::vector<std::array<int, 2>>& features, bool valences_given,
                              int threads, const AtScale& scale, Report& report, const LookBeforeLastRing& look = {});

/// Hands the map's connectivity and its transitions (as they were before the repair) over to a
/// memo that the repair filled: the rung that repaired calls it once it is done with m, whose
/// connectivity and transitions it leaves empty (its input_triangle is copied: take_map reads
/// it). Nothing where the memo is not filled, or has them already.
void keep_for_refinements(TriMesh& m, RepairMemo& memo);

/// Whether refinement is worth trying after the map at its own scale (and coarsened) gave
/// `result`, invalid: not when Options::max_refinement is below 2, nor once the map is proved to
/// collapse a handle (`handle_collapsed`: no scale keeps it), unless Options::best_effort looks
/// for a mesh that loses nothing else and `result` loses more.
bool refinement_can_help(const Options& options, bool handle_collapsed, const Result& result);

/// Refinement, after the map at its own scale (and coarsened) gave `result`, invalid: the ladder
/// on the map times 2, 4, ... up to Options::max_refinement. Replaces `result` with the first
/// valid mesh, or adds to it one explanation per factor tried. With Options::best_effort, none
/// valid: `result` becomes the attempt with the fewest violations (ties to the smaller scale),
/// a BestEffortMesh explanation first; refinement stops, once `handle_collapsed`, at an attempt
/// that loses only the surface's topology. Before that, with Options::fill_holes and no scale
/// valid, the last resort (fill_holes_if_accepted) at the smallest scale where it passes: the map's
/// own (`result`, then `fillable`, its other candidate there), then each refinement tried.
/// `checked`: the checker's analysis of the input, for every check (AtScale::checked).
void extract_refined(const Input& input, const Options& options, RepairMemo& memo, CheckedInput* checked,
                     bool handle_collapsed, const Result& fillable, Result& result);

/// The explanation of a best-effort mesh (Options::best_effort): which attempt it is (`scale`,
/// 1 for the map's own), its violations, and `tried`, the violations of each attempt.
Defect best_effort_explanation(int scale, const std::string& tried, std::size_t violations);

/// The explanation of a mesh extracted at another scale: what failed at the map's own scale,
/// and where, then `how`.
Defect scale_explanation(DefectKind kind, const Result& at_scale_one, const std::string& how);

// ============================================================================ coarsening (coarsen.cpp, split_onto_map.cpp)

/// Whether the sanitized map `m` (transitions and singularities computed) is k times an
/// integer-grid map laid from some grid point `origin` (u = k u' + origin, origin in [0, k)^2):
/// every singularity's grid point, and every boundary or feature edge (input vertex pairs) on an
/// iso-line, on a line of that coarse grid, and every transition one of its automorphisms. The
/// origin is fixed by the singularities and iso-lines, else it is the first (in (u, v) order)
/// that the turning transitions allow (for k up to 64; above, a free coordinate is 0).
bool map_divisible_by(const TriMesh& m, const std::vector<std::array<int, 2>>& feature_edges, std::int64_t k,
                      IPoint& origin);

/// For a mesh extracted from the map laid from `origin` with its UVs divided by k (a power of
/// two; map_divisible_by): the mesh with every quad split into k x k, on `map` (the coarse
/// mesh's map times k, plus origin). Each coarse vertex keeps its element, its grid point g
/// becoming k g + origin;
/// each new one is placed on a preimage of its grid point found from its face's first corner,
/// in the chart in which the face's other corners are found where the coarse mesh has them.
/// False, with `out` unusable, when a face has no such chart or a grid point no preimage.
bool split_onto_map(const Input& input, const std::vector<std::array<double, 2>>& map, const QuadMesh& coarse, int k,
                    const IPoint& origin, QuadMesh& out);

/// Whether a valid mesh at the map's own scale has more quads than the map's signed UV area.
bool over_covered(const Result& r);

/// Coarsening (Options::max_coarsening), after the map at its own scale gave `result`, invalid
/// (or valid but over_covered):
/// the ladder on the map with its UVs divided by 2, 4, ... while that is an integer-grid map, and
/// the first valid mesh there split back onto the given map. Replaces `result` and returns true
/// when that mesh passes the checker against the given map.
bool extract_coarsened(const Input& input, const Options& options, Result& result);

} // namespace qex::detail

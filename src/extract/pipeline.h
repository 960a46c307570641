// The extraction pipeline: its stage table, the data the stages hand on, and the stages in the
// order they run. A stage has one name, used by its file (src/extract/NN_<name>.cpp, NN its
// place in the pipeline; validate's topology half is build_topology.cpp, repair is the folder
// src/extract/repair/, the steps only some rungs of the fallback ladder take are
// src/extract/ladder/<name>.cpp, declared in ladder/ladder.h, and check is the checker,
// src/verify/), its function, its timer label in
// Report::stage_seconds and its benchmark (BM_<name>/<input>).
#pragma once

#include "predicates.h"
#include "repair/repair.h"
#include "tri_mesh.h"
#include "qex/extract.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <functional>
#include <iterator>
#include <limits>
#include <cstdint>
#include <memory>
#include <vector>

namespace qex::detail {

// ============================================================================ stage table

/// The pipeline's stages in the order extract() runs them (src/README.md: the stage table), then
/// the steps only some rungs of the fallback ladder take (src/extract/ladder/, where ladder.cpp's
/// table gives their order), then the checker every rung ends with.
enum class Stage : int {
    validate,            ///< 01: values, indices and topology of the input; the working mesh
    collapse,            ///< 02: collapse of UV-degenerate edges (again after each sanitize round but a capped last)
    compute_transitions, ///< 03: Section 3.1
    count_valences,      ///< 04: Algorithm 8
    sanitize,            ///< 05: Algorithms 1 and 2, Section 3.2
    repair,              ///< 06 (repair/): certified re-embedding of fold-over regions (not in the paper)
    generate_qvertices,  ///< 07: Algorithm 3
    enumerate_ports,     ///< 08: Algorithm 4
    trace_ports,         ///< 09: Algorithm 5
    extract_faces,       ///< 10: Algorithm 6
    merge_vertices,      ///< 11: Section 5.5, Algorithm 7 (and 11_cancel_ghosts.cpp)
    canonicalize,        ///< 12: order-independent output
    untangle,            ///< ladder/untangle.cpp: last-resort rungs relax the folded regions first
    place_on_given_map,  ///< ladder/place_on_given_map.cpp: last-resort rungs move the mesh back
    separate_sheets,     ///< ladder/separate_sheets.cpp: a rejected mesh's edges joining two sheets, cut
    close_holes,         ///< ladder/close_holes.cpp: a rejected mesh's holes closed by the cells their rims enclose
    fill_holes,          ///< ladder/fill_holes.cpp: last resort, holes no cells close filled from their rims
    check,               ///< src/verify/: the independent checker (qex::verify) judges the rung's mesh
};
inline constexpr int kNumStages = static_cast<int>(Stage::check) + 1;

/// The stages' names, indexed by Stage.
inline constexpr const char* kStageNames[] = {"validate",
                                              "collapse",
                                              "compute_transitions",
                                              "count_valences",
                                              "sanitize",
                                              "repair",
                                              "generate_qvertices",
                                              "enumerate_ports",
                                              "trace_ports",
                                              "extract_faces",
                                              "merge_vertices",
                                              "canonicalize",
                                              "untangle",
                                              "place_on_given_map",
                                              "separate_sheets",
                                              "close_holes",
                                              "fill_holes",
                                              "check"};

static_assert(sizeof(kStageNames) / sizeof(kStageNames[0]) == kNumStages, "one name per stage");

inline const char* stage_name(Stage s) { return kStageNames[static_cast<int>(s)]; }

/// Adds the wall time since the last call (or construction) to the stage's entry in
/// Report::stage_seconds, appending the entry the first time the stage runs.
class StageTimer {
public:
    explicit StageTimer(Report& report);
    /// Adds the time since the last call (or construction) to `stage`, and tells the progress hook.
    void done(Stage stage);
    /// The hook extract() sets for its own thread while it runs (Options::on_stage), and the
    /// refinement factor being tried.
    static thread_local const std::function<void(const char*, int)>* hook;
    static thread_local int hook_scale;

private:
    Report& report_;
    std::chrono::steady_clock::time_point last_;
};

// ============================================================================ stages

/// The working mesh of an input whose values are valid (validate_input_values).
TriMesh make_mesh(const Input& in);

/// Checks indices, finiteness, magnitudes and isolated vertices of the raw input.
Error validate_input_values(const Input& in);

/// Stage validate: validate_input_values, then the working mesh and its topology (`threads`
/// for its parallel loops).
Error validate(const Input& in, int threads, TriMesh& m);

/// Builds opposite half-edges and clockwise vertex fans; rejects non-manifold or misoriented meshes.
/// `what` names the stage in messages ("input" or "after collapsing UV-degenerate edges").
Error build_topology(TriMesh& m, const char* what);

/// Collapses edges of zero length in the parameter domain, keeping 3D positions in the corners.
/// Returns the number collapsed in `collapsed`. A collapse replaces the connectivity, and the
/// mesh's map state with an empty one: transitions, valences and sanitization must run again.
Error collapse(TriMesh& m, std::int64_t& collapsed);

/// Extracts and rounds a transition function per interior half-edge (Section 3.1).
void compute_transitions(TriMesh& m);

/// The turn (sum of rotations, mod 4) of interior vertex v's fan; -1 for a boundary vertex or
/// an open fan.
int fan_turn(const TriMesh& m, int v);

/// How far solver noise and float storage leave a real map from exact (1/1024 of a cell, or a few
/// ulps of coordinates of this magnitude). The worst of the shared MIQ and paper maps is 9.5e-7
/// cells; an offset beyond this is not noise. It classifies the input (a seam no transition
/// explains; a vertex that winds twice off every grid point is a fold, not a branch point).
/// `noise_scale`: the factor a refinement multiplied the map by (TriMesh::noise_scale), and its
/// noise with it.
inline double solver_noise_bound(double magnitude, double noise_scale = 1.0) {
    return std::max(noise_scale / 1024, 8.0 * magnitude * std::numeric_limits<double>::epsilon());
}

/// How the first sanitize round treats seams whose two UV copies the computed transition maps
/// onto each other only up to more than solver noise (1/1024 of a cell, or a few ulps of the
/// coordinates): such a seam is not an integer-grid transition, and sanitizing moves the map by
/// up to half a cell there.
enum class SeamPolicy {
    Trusted, ///< not checked (a map a rung has moved)
    Checked, ///< the first such seam (in half-edge order) is an input error naming it
    Rounded, ///< each is rounded, as sanitizing does, and named in the report's explanations
};

/// Applies `policy` to the map's seams (after compute_transitions).
Error check_seams(const TriMesh& m, SeamPolicy policy, Report& report);

/// The angle atan2(y, x) for y >= 0, within kApproximateAngleError of it (a polynomial, no
/// libm call); NaN when x and y are both 0 or not finite.
double approximate_angle(double y, double x);
/// A bound on |approximate_angle - atan2|, with a margin of 10 over the polynomial's 1e-5 (the
/// unit test samples the whole range).
inline constexpr double kApproximateAngleError = 1e-4;

/// Valence counting robust to fold-overs (Algorithm 8) and winding valences; interior vertices
/// only. Vertices not counted (boundary, or regular when `singular_only`) get 4.
void count_valences(TriMesh& m, bool singular_only = false);

/// The orientation of every triangle's UVs (exact predicate), in parallel.
std::vector<signed char> triangle_signs(const TriMesh& m);

/// Precision truncation, singularity snapping and propagation (Algorithms 1 and 2); feature
/// snapping (Section 3.2). `given_valences` may be empty.
/// Branch points (r = 0, valence 8 or more; without given valences, only on a grid point up to
/// solver_noise_bound: elsewhere a fold winds the fan twice) are snapped only when `branch_points` is set; with
/// it unset they are truncated like regular vertices and counted in `*deferred`. (Their
/// valence comes from angles, which noise makes meaningless next to an edge that is about to
/// become degenerate: the caller decides them once such edges are collapsed.)
Error sanitize(TriMesh& m, const std::vector<int>& given_valences, const std::vector<std::array<int, 2>>& feature_edges,
               Report& report, bool branch_points = true, std::int64_t* deferred = nullptr);

/// The corners of v's fan, clockwise from fan_start[v] or (`canonical_start`, a closed fan) from
/// the canonical corner: the smallest UV, then the 3D positions of its next and previous
/// corners, then those corners' UVs (all of it the input's data, none of it its order; two
/// corners tie only if their triangles agree in every 3D position and UV). And the transitions
/// from the first corner's chart to each corner's.
void walk_fan_corners(const TriMesh& m, int v, bool canonical_start, std::vector<int>& corners,
                      std::vector<GridAutomorphism>& to_c);

/// u0 (in the chart of corners[0]) truncated to a power of two at least as large as every
/// coordinate of the fan's corners, before and after propagation through `to_c` (chart of
/// corners[0] -> chart of corners[i]), plus `headroom`: truncated to it, u0 propagates exactly,
/// and with a headroom of 1 every propagated corner p also stays exact as k p + o for any power
/// of two k and integer point o in [0, k)^2 (the map coarsening splits back onto), while k times
/// that power is at most 2^52. u0 itself if the fan is all zero or no such power is found.
Point2 truncated_for_fan(const TriMesh& m, const std::vector<int>& corners, const std::vector<GridAutomorphism>& to_c,
                         Point2 u0, double headroom = 0.0);

/// The most sanitize rounds after the first; the last round is not followed by a collapse.
inline constexpr int kMaxSanitizeRounds = 8;

// Stage repair is a subsystem of its own: src/extract/repair/, its one door repair/repair.h
// (RepairOutcome, repair, explain_unrepaired), included above.

/// Stages compute_transitions, count_valences, sanitize and collapse, repeated until a round
/// collapses nothing (and deferred branch points are decided), at most `max_rounds` + 1 times.
/// Ends with a map state that describes the mesh's connectivity. The first round's seams are
/// treated by `seams` (check_seams).
Error sanitize_until_stable(TriMesh& m, const Input& input, const std::vector<std::array<int, 2>>& features,
                            Report& report, StageTimer& timer, int max_rounds = kMaxSanitizeRounds,
                            SeamPolicy seams = SeamPolicy::Checked);

// ============================================================================ q-vertices and q-ports

struct QVertex {
    QVertexKind kind;
    int element; ///< vertex id (Vertex), canonical half-edge (Edge), triangle (Face)
    int chart;   ///< triangle whose chart `grid` is expressed in
    IPoint grid; ///< integer parameter position in that chart
    std::array<double, 3> position;
    std::array<double, 3> barycentric; ///< in triangle `chart` (corner order)
    int first_port = 0, num_ports = 0;
};

/// An outgoing unconnected q-edge: q-vertex, triangle it points into, direction (R90^dir (1,0) in
/// that triangle's chart) and the q-vertex's grid point in that chart.
struct Port {
    int qvertex;
    /// A corner of the triangle the port points into (face(corner) is that triangle): the fan's
    /// corner at the vertex (Vertex), the edge's half-edge on that side (Edge), 3f (Face).
    int corner;
    int dir;
    IPoint grid;
};

/// A traced iso-line from one port to another; `g` maps the chart of the source port's triangle
/// to the chart of the target port's triangle.
struct Connection {
    int to = -1; ///< target port, -1 if the trace ran into the boundary or failed
    GridAutomorphism g;
};

struct QState {
    std::vector<QVertex> qvertices;
    std::vector<int> vertex_qvertex; ///< per mesh vertex: its vertex-q-vertex or -1
    /// Edge-q-vertices of half-edge h: [edge_first[h], edge_first[h + 1]) (empty unless h is its
    /// edge's canonical half-edge, canonical_half_edge); size 3F + 1.
    std::vector<int> edge_first;
    /// Face-q-vertices of triangle f: [face_first[f], face_first[f + 1]); size F + 1.
    std::vector<int> face_first;
    std::vector<Port> ports;
    std::vector<Connection> connections; ///< per port
    std::vector<char> into_boundary;     ///< per port: its trace left the surface through a boundary
};

/// Generates vertex-, edge- and face-q-vertices (Algorithm 3).
Error generate_qvertices(const TriMesh& m, const Options& opt, QState& q);

/// Barycentric coordinates of x in triangle f (corner order), for placing a grid point in 3D,
/// not for decisions: computed with the corners in 3D order, so that the result does not depend
/// on the input's corner order; in doubles, exactly for a sliver (whose doubles lose them).
std::array<double, 3> barycentric(const TriMesh& m, int f, const Point2& x);

/// Enumerates q-ports of every q-vertex in clockwise order on the surface (Algorithm 4).
void enumerate_ports(const TriMesh& m, QState& q);

/// Traces every port's iso-line to its opposite port (Algorithm 5).
void trace_ports(const TriMesh& m, const Options& opt, QState& q, Report& report);

// ============================================================================ faces

/// The closed face walks, stored flat (one allocation for all of them, not two per face):
/// walk i is corners [first[i], first[i + 1]) of `qv` and `uv`. merge_vertices hands the output
/// faces on in this form too (`qv` then holds output vertices).
struct FaceWalks {
    std::vector<std::size_t> first{0};
    std::vector<int> qv;    ///< q-vertices (output vertices after merge_vertices)
    std::vector<IPoint> uv; ///< local UVs in the chart of the walk's first port's triangle
    std::size_t size() const { return first.size() - 1; }
};

/// Walks the faces of the q-port graph, accumulating local UVs (Algorithm 6). A walk that is not
/// a plain quad starts at its canonical corner (canonical_start): around a singularity its local
/// UVs depend on where the accumulation starts, and so would every choice made on them later.
FaceWalks extract_faces(const TriMesh& m, const QState& q, Report& report);

/// A triangle's key in an order that does not depend on the input's: its corners' 3D positions,
/// read from its smallest corner on.
using TriangleKey = std::array<std::array<double, 3>, 3>;
TriangleKey triangle_key(const TriMesh& m, int f);

/// a < b as std::array's operator< orders them, written out: positions are finite (validation
/// refuses NaN), and the nested std::lexicographical_compare was a call per level in the sorts.
inline bool key_less(const TriangleKey& a, const TriangleKey& b) {
    for (std::size_t i = 0; i < 3; ++i)
        for (std::size_t j = 0; j < 3; ++j)
            if (a[i][j] != b[i][j]) return a[i][j] < b[i][j];
    return false;
}

/// Whether triangle f comes before triangle g in that order.
bool triangle_less(const TriMesh& m, int f, int g);

/// The half-edge of h's edge that carries its edge-q-vertices: the one running from the end with
/// the smaller 3D position (h itself on a boundary), so their positions and charts do not depend
/// on the input's order. O(1): it is asked for every half-edge.
int canonical_half_edge(const TriMesh& m, int h);

/// Ports in an order that does not depend on the input's: by q-vertex (qvertex_less), then the
/// triangle the port points into, then its direction there.
bool port_less(const TriMesh& m, const QState& q, int a, int b);

/// A total order on q-vertices that does not depend on the input's order: by 3D position (then
/// kind, and index for the rare q-vertices at one point).
bool qvertex_less(const QState& q, int a, int b);

/// The start of the rotation of the cyclic q-vertex sequence qv[0..n) that is smallest in
/// qvertex_less order.
std::size_t canonical_start(const QState& q, const int* qv, std::size_t n);

/// Transition from the chart of port a's triangle to that of port b (same q-vertex), stepping
/// clockwise around the q-vertex; `ok` is false if the step would cross the mesh boundary.
GridAutomorphism fan_transition_cw(const TriMesh& m, const QState& q, int a, int b, bool& ok);

/// Sorts output vertices and faces canonically (so any input order gives the same mesh) and
/// sets the mesh's faces from `faces` (merge_vertices'), in that order; returns, per old face
/// index, its new index. `threads` for its sorts (the order is the same for any).
std::vector<int> canonicalize(QuadMesh& mesh, FaceWalks faces, int threads);

/// Sets the mesh's faces from `faces` (merge_vertices'), in their order (no canonical order).
void set_faces(QuadMesh& mesh, const FaceWalks& faces);

/// Recovers lost q-edges (Section 5.5), merges q-vertex clones (Algorithm 7) and simplifies faces;
/// fills the output mesh's vertices and returns its faces, flat (canonicalize or set_faces
/// puts them in the mesh). Of `q` it reads only the q-vertices (the driver releases the ports
/// and traces before calling it).
FaceWalks merge_vertices(const TriMesh& m, const QState& q, FaceWalks faces, const Options& opt, QuadMesh& out,
                         Report& report);

// ============================================================================ after the check

/// For a mesh the checker rejected: appends one CheckerViolation defect per violation of
/// `result.check`, with the violation's kind and the face, input triangle and grid point it is
/// near (through the provenance).
void locate_violations(const Input& input, Result& result);

/// A place a defect or an explanation names by triangle f (working index) and grid point g in
/// f's chart, as vertices of the working mesh: those of every triangle round the element g lies
/// on (a corner's fan, an edge's two triangles, else f), appended to `out`. Which triangle round
/// a place is named follows the input's order; these vertices do not.
void place_vertices(const TriMesh& m, int f, const std::array<std::int64_t, 2>& g, std::vector<int>& out);

// ============================================================================ collapsed handles (collapsed_handles.cpp)

/// The handles of the surface the map (as given) collapses: each a region of triangles whose UV
/// areas are at most 1/64 of a cell with the map multiplied by max(16, max_refinement), folded
/// onto itself (its signed UV area at most half its absolute one) and net below one cell at
/// that factor, that with the disks of the surface it encloses is no disk (genus, or several
/// rims) and not the whole surface. No mesh that follows the map keeps such a handle, at any
/// scale up to that factor. The input must have passed validate().
std::vector<CollapsedHandle> find_collapsed_handles(const Input& input, int max_refinement);

/// The defect that names a collapsed handle: its vertex, triangles (the first few) and areas.
Defect collapsed_handle_defect(const Input& input, const CollapsedHandle& handle, int max_refinement);

} // namespace qex::detail

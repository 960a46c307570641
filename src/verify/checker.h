// The checker's internal interface between its files. Like every file in src/verify/, it
// includes only the public headers and the checker's own files: the build fails otherwise
// (CMakeLists.txt, "the checker's wall"). Nothing here includes CGAL: the files that use it
// (certificate.cpp, map_check.cpp, signed_area.cpp, surface.cpp, quality.cpp) keep it to
// themselves. Two checks have rooms of their own behind this interface: coverage.h and
// face_cells.h.
#pragma once

#include "grid.h"
#include "qex/verify.h"

#include <array>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace qex::verify_detail {

// ============================================================================ violations

/// Most checks list a violation only while the list (all kinds together) is shorter than this;
/// undecided checks likewise. A few are listed always: bad indices, non-finite positions, and
/// verify.cpp's findings about the whole mesh.
inline constexpr std::size_t kMaxListed = 1000;

/// Appends the violation (or undecided check) to `out` unless it lists kMaxListed already.
inline void add_capped(std::vector<Violation>& out, ViolationKind kind, std::string message, std::int64_t element) {
    if (out.size() < kMaxListed) out.push_back({kind, std::move(message), element});
}

// ============================================================================ topology (topology.cpp)

struct Topology {
    std::int64_t vertices = 0, edges = 0, faces = 0, boundary_loops = 0, components = 0;
    std::int64_t euler() const { return vertices - edges + faces; }
};

/// Per corner c: the other corner whose outgoing edge joins the same two vertices, when exactly
/// two face sides share that edge (in either direction); -1 otherwise.
using EdgePairs = std::vector<std::int32_t>;

/// Topology of a polygon mesh with valid indices (at most 2^31 - 1 corners); appends violations
/// when `out` is given. `offset` (size F+1) and `corner_vertex` describe the faces as flat
/// arrays. Edges are found without hashing or a global sort: the corners are bucketed by the
/// smaller vertex of their outgoing edge (a counting pass), and each bucket is ordered by the
/// larger one. Everything is decided in the order (smaller vertex, larger vertex, corner),
/// whatever the thread count. With `pairs_out`, the edge pairs; with `single_fan_out`, per
/// vertex whether its faces form a single fan (0 for a vertex no face uses).
Topology analyse(std::size_t num_vertices, const std::vector<std::size_t>& offset,
                 const std::vector<int>& corner_vertex, std::vector<Violation>* out, int threads,
                 EdgePairs* pairs_out = nullptr, std::vector<char>* single_fan_out = nullptr);

// ============================================================================ the input map's area (signed_area.cpp)

/// The input map's signed UV area: `r.input_signed_uv_area` for display and
/// `r.input_signed_uv_area_rounded`, the exact area rounded to the nearest integer, halves
/// upwards (left 0 when a triangle's doubled area is not finite in doubles). The input's UVs
/// must be 3 per triangle.
void signed_uv_area(const Input& input, VerifyResult& r);

/// Per input triangle: its UV area is exactly zero (its corners' UVs collinear or coincident),
/// decided exactly (a filtered orientation, rationals when the filter cannot tell).
std::vector<char> uv_degenerate_triangles(const Input& input);

// ============================================================================ the mesh's map (map_check.cpp)

/// The map the mesh claims to come from (`mesh.map_uvs`, as many as the input's UVs): an exact
/// integer-grid map (across every interior edge the two charts differ by a rotation by k*90
/// degrees and an integer translation, every singularity on a grid point), and each vertex's
/// provenance grid point lies on the element it names; also its displacement from the input's
/// UVs. `pairs` and `single_fan` are the input's (analyse). Decided exactly.
void check_map(const Input& input, const QuadMesh& mesh, const EdgePairs& pairs, const std::vector<char>& single_fan,
               int threads, VerifyResult& r, std::vector<Violation>& out);

/// The quarter turns R of the grid automorphism x -> R x + t (t integer) that carries a to a2
/// and b to b2 exactly, or -1 when there is none. For an edge of non-zero length at most one
/// rotation passes the first test; for a zero-length edge the first that passes is returned.
int grid_automorphism(const std::array<double, 2>& a, const std::array<double, 2>& b, const std::array<double, 2>& a2,
                      const std::array<double, 2>& b2);

// ============================================================================ certificates (certificate.cpp)

/// A certificate (qex::Certificate) against `given`, the given map with its UVs times the
/// certificate's grid scale: its CertificateMismatch violations, none when it holds. `tol`:
/// the located mode's UV tolerance at that scale (grid_tolerance).
std::vector<Violation> check_certificate(const Input& given, const Certificate& certificate, double tol, int threads);

// ============================================================================ located mode (check_located.cpp)

/// Located mode (meshes without provenance): locates every output vertex on the input surface
/// and checks faces and coverage against the map; appends violations to `out` and undecided
/// checks to `r.undecided`. With `located_triangle`, per output vertex the input triangle it
/// was located in (-1 where it was not); with `closest_triangle`, the input triangle of its
/// closest surface point, on the surface or not (-1 for a non-finite position).
/// `noise_scale`: the map is a given map with its UVs multiplied by this (QuadMesh::grid_scale),
/// its solver noise too: a vertex may lie that many times opt.uv_tolerance off its grid point
/// (at most 0.1, or opt.uv_tolerance itself when larger).
void check_located(const Input& in, const QuadMesh& mesh, const VerifyOptions& opt, VerifyResult& r,
                   std::vector<Violation>& out, std::vector<std::int64_t>* located_triangle = nullptr,
                   std::vector<std::int64_t>* closest_triangle = nullptr, double noise_scale = 1.0);

// ============================================================================ holes (holes.cpp)

/// The mesh's boundary loops (sides without a twin: the reverse side, the edge's only other), each
/// with the faces whose sides it follows. A vertex with several boundary sides continues along
/// the first unused one.
struct Boundary {
    std::vector<std::vector<std::int64_t>> loops, faces;
};
Boundary boundary_loops(const QuadMesh& mesh);

/// The input's boundary edges (edges of one triangle side).
std::vector<std::array<int, 2>> input_boundary_edges(const Input& in);

/// The squared distance from x to the segment ab.
double segment_distance2(const std::array<double, 3>& x, const std::array<double, 3>& a,
                         const std::array<double, 3>& b);

/// Per input component (by triangles sharing vertices) with no located vertex: its first triangle.
std::vector<std::int64_t> empty_input_components(const Input& in, const std::vector<std::int64_t>& located_triangle);

/// The loops of `b` (the mesh's) that run along no boundary loop of the input: a loop runs along
/// one when each of its vertices lies within `tol` plus a cell (twice its faces' diagonal) of
/// it, and each input loop keeps the mesh loop whose farthest vertex is closest (holes.cpp).
/// Every loop when the input has no boundary; none when too large to decide.
std::vector<std::size_t> find_holes(const Input& in, const QuadMesh& mesh, const Boundary& b, double tol);

/// Appends a Hole violation per loop find_holes names (its loop, its faces and, in located mode,
/// the input triangles of its vertices' closest points), and in located mode (`located_triangle`
/// not empty) a MissingComponent violation per input component no vertex lies on.
/// `has_boundary`: the mesh has boundary loops (else no hole is looked for).
void check_holes(const Input& in, const QuadMesh& mesh, bool has_boundary, double tol,
                 const std::vector<std::int64_t>& closest_triangle, const std::vector<std::int64_t>& located_triangle,
                 std::vector<Violation>& out);

// ============================================================================ places (places.cpp)

/// What place_violations needs besides the mesh and the input.
struct PlaceContext {
    bool indices_ok = false; ///< every face's vertex indices are in range
    /// A mesh vertex within this distance (model units) of the input's boundary edges is on it.
    double boundary_tolerance = 0;
    /// Located mode: per output vertex the input triangle it lies on (-1: not located); empty otherwise.
    std::vector<std::int64_t> located_triangle;
    /// Located mode: per output vertex the input triangle of its closest surface point (-1: not
    /// finite); empty otherwise.
    std::vector<std::int64_t> closest_triangle;
};

/// Gives every violation (and undecided check) the place its element names, and the violations
/// of the whole mesh their candidates (Violation::places); in located mode, a violation of an
/// output vertex or face also the input triangle where it lies (the vertex's, or the first
/// corner's closest). Decides nothing.
void place_violations(const Input& in, const QuadMesh& mesh, const PlaceContext& ctx, VerifyResult& r);

/// An integer grid point (or translation).
using GridPoint = std::array<std::int64_t, 2>;

/// x -> R^r x + t between the charts of two adjacent triangles (integers only).
struct Transition {
    int r = 0;
    std::int64_t tx = 0, ty = 0;
};

/// Grid points far beyond any map (|coordinate| >= 2^60) are not compared (they make no unit
/// step): a path through a broken map can compose translations without bound.
inline constexpr std::int64_t kFar = std::int64_t{1} << 60;

/// m composed with a (x -> m(a(x))); false when the translation grows far.
inline bool compose(const Transition& m, const Transition& a, Transition& out) {
    const GridPoint t = rotate_quarter(GridPoint{a.tx, a.ty}, m.r);
    if (std::llabs(t[0]) >= kFar || std::llabs(t[1]) >= kFar || std::llabs(m.tx) >= kFar || std::llabs(m.ty) >= kFar)
        return false;
    out = {(m.r + a.r) & 3, t[0] + m.tx, t[1] + m.ty};
    return true;
}

/// The grid point p carried by m (its coordinates below 2^62 in magnitude, m's translation below kFar).
inline GridPoint map_point(const Transition& m, const GridPoint& p) {
    const GridPoint q = rotate_quarter(p, m.r);
    return {q[0] + m.tx, q[1] + m.ty};
}

inline bool same(const Transition& x, const Transition& y) { return x.r == y.r && x.tx == y.tx && x.ty == y.ty; }

/// The input's half-edges (corners 3t + k, the edge from corner k to corner k + 1) and the
/// transitions across them, rounded to integers (transitions.cpp).
struct InputEdges {
    /// The half-edge across, when its transition was determined; -1 otherwise.
    std::vector<std::int64_t> opposite;
    /// The transition from the half-edge's chart to the chart across (where `opposite` >= 0).
    std::vector<Transition> across;
    /// The other half-edge of the edge when it has exactly two (in either direction), crossed or
    /// not (its transition determined or not); -1 otherwise.
    std::vector<std::int64_t> partner;
};

/// The input's half-edges and their transitions. An edge is paired when exactly two half-edges
/// share it; its transition is determined when both sides' edge vectors are longer than 4
/// `uv_tolerance` (inf-norm) in UV, the quarter turn that carries the one closest onto the other
/// does so within `uv_tolerance`, and the translation, rounded to integers, is below 9e15.
InputEdges input_edges(const Input& in, double uv_tolerance);

/// Per input vertex: singular, i.e. its fan is closed and the transitions around it compose to a
/// turn, or it includes a paired edge whose transition was not determined.
std::vector<char> singular_vertices(const Input& in, const InputEdges& edges);

/// Where a point lies on the input surface (Surface::locate).
struct SurfacePoint {
    std::uint32_t triangle = 0;     ///< the input triangle of the closest surface point
    std::array<double, 2> uv{0, 0}; ///< the closest point's UV in that triangle's chart
    double distance = 0;            ///< from the point to the closest surface point
    int corner = -1; ///< the triangle's first corner within the distance tolerance of the closest point, or -1
};

/// The input surface for locating points: an AABB tree over the triangles that are not
/// degenerate in 3D (surface.cpp, the located mode's one use of CGAL's trees).
class Surface {
public:
    /// The surface of `in`, or null when a position or UV of a triangle is not finite (not a map
    /// this mode can judge; validation names the problem) or no triangle is non-degenerate.
    /// Points count as on it within `distance_tolerance` times the bounding-box diagonal.
    static std::unique_ptr<Surface> build(const Input& in, double distance_tolerance);
    ~Surface();
    /// The closest point of the surface to `x`; its `corner` within `snap` (default: the
    /// distance tolerance) of the closest point.
    SurfacePoint locate(const std::array<double, 3>& x, double snap = -1) const;
    /// The bounding-box diagonal of the input's triangles.
    double diagonal() const;
    /// The distance tolerance: distance_tolerance times the diagonal.
    double max_distance() const;

private:
    struct Tree;
    explicit Surface(std::unique_ptr<Tree> tree);
    std::unique_ptr<Tree> tree_;
};

/// Per input triangle: a fold-over, i.e. its UV area is not positive (flipped: < 0, or
/// degenerate: == 0), decided exactly. Adds the flipped ones to `r.map_flipped_triangles`
/// (surface.cpp).
std::vector<char> fold_overs(const Input& in, VerifyResult& r);

/// Per half-edge c with `edges.opposite[c]` >= 0: the distance between the centroids of the
/// two triangles, in 3D (surface.cpp); 0 for the others.
std::vector<double> centroid_steps(const Input& in, const InputEdges& edges);

/// An output vertex located on the input surface.
struct Located {
    std::uint32_t triangle = 0;
    std::int64_t on_vertex = -1; ///< the input vertex it sits on (within the distance tolerance)
    GridPoint grid{0, 0};        ///< its grid point in the chart of `triangle`
    bool ok = false; ///< located, on the surface and on a grid point (else reported, here or as NonFinitePosition)
    /// On the surface, in a fold-over region of the map (LocatedMap::region_of): judged on the
    /// surface only, not for being on a grid point; `grid` is the raw map's nearest one, and a
    /// face with such a corner that is no grid cell there is undecided, not a violation.
    bool surface_only = false;
    /// On the surface, off its grid point by less than its positions' precision can tell
    /// (NotOnGridPoint undecided): not `ok`; `grid` is the nearest one, and any grid point within
    /// `spread` steps of it (in each coordinate) may be its own.
    bool undecided = false;
    int spread = 0;
};

/// What the located mode knows of the input map, shared by its steps.
struct LocatedMap {
    const Input& in;
    const Surface& surface;
    InputEdges edges;
    std::vector<char> singular;  ///< per input vertex (singular_vertices)
    std::vector<char> fold_over; ///< per input triangle (fold_overs)
    /// Per input triangle: the index of its fold-over region in VerifyResult::fold_regions, or
    /// -1 (fold_regions below).
    std::vector<std::int32_t> region_of;
};

/// The precision the positions carry (VerifyResult::position_digits, positions_float32)
/// (locate_vertices.cpp).
void position_precision(const QuadMesh& mesh, VerifyResult& r);

/// The UV tolerance for noise on a map that is a given map times `noise_scale` (check_located)
/// (locate_vertices.cpp).
double grid_tolerance(const VerifyOptions& opt, double noise_scale);

/// Vertices: the closest surface point, its UV in that triangle's chart (on an input vertex:
/// the vertex's UV there), the nearest grid point. A vertex off the surface or off the grid is
/// reported (and not `ok`). Each vertex's tolerances grow with what rounding its coordinates to
/// opt.position_digits may move it (VerifyOptions) (locate_vertices.cpp).
std::vector<Located> locate_vertices(const LocatedMap& map, const QuadMesh& mesh, const VerifyOptions& opt,
                                     double noise_scale, VerifyResult& r, std::vector<Violation>& out);

/// Per input triangle: a corner lies within `rings` edges (rings of input vertices, through any
/// vertex) of a corner of a fold-over (check_located.cpp).
std::vector<char> near_fold_overs(const Input& in, const std::vector<char>& fold_over, int rings);

/// The map's fold-over regions: the triangles near_fold_overs(kFoldRegionRings) names, grouped
/// where they share a vertex. Fills `r.fold_regions` (ordered by their first fold-over triangle)
/// and returns per triangle its region or -1 (check_located.cpp).
std::vector<std::int32_t> fold_regions(const Input& in, const std::vector<char>& fold_over, VerifyResult& r);

/// Faces: every quad's corners, carried into one chart along the input's transitions, must be
/// the corners of one grid cell in counter-clockwise order (face_cells.cpp). Appends violations
/// to `out`, and failures that paths across fold-overs or singular fans, or a corner in a
/// fold-over region (Located::surface_only), leave undecided to `r.undecided`.
void check_face_cells(const LocatedMap& map, const QuadMesh& mesh, const std::vector<Located>& loc, VerifyResult& r,
                      std::vector<Violation>& out);

namespace coverage {
struct Scratch;
}

/// The unit cells round a grid point g of the input's boundary, as coverage judges them
/// (coverage_cells.cpp), read in one chart carried from the chart of the triangle holding g
/// across the edges near g (within coverage's claim reach): `cells`, those on the map's side (a
/// triangle near g meets the cell farther than the band inside), and `cut`, how many of them the
/// input's boundary cuts (CellState::Cut: it passes through the cell farther than the band from
/// its sides, so the cell is no face of a map covering it whole, and coverage does not require
/// it). Not `read` where the charts near g disagree or a fold-over lies near.
struct CellsRound {
    bool read = false;
    int cells = 0, cut = 0;
    std::vector<std::pair<std::uint32_t, GridPoint>> at; ///< g in the chart of each triangle near it
};

/// Reads CellsRound at grid points of the boundary, keeping the floods' scratch between them.
class BoundaryCells {
public:
    /// `tol`: the UV tolerance that read the boundary along iso-lines, the band (at least
    /// coverage's kBoundaryBand): a cut within it is the noise that reading let pass.
    BoundaryCells(const LocatedMap& map, double tol);
    ~BoundaryCells();
    /// The cells round g, a grid point in the chart of triangle t (which holds it).
    CellsRound round(std::uint32_t t, const GridPoint& g);

private:
    const LocatedMap& map_;
    double reach_, band_;
    std::unique_ptr<coverage::Scratch> scratch_;
};

/// The singularity match (singularities.cpp): every vertex of the mesh located on the map (in a
/// fold-over region or not) has as many faces as the map's valence where it lies, and every
/// singularity of the map (and corner of a boundary along iso-lines) carries a vertex. Input
/// vertices joined by edges shorter than `tol` in UV are one cone. Appends ValenceMismatch and
/// SingularityNotCarried violations to `out`; counts into r.map_cones and the like.
void check_singularities(const LocatedMap& map, const QuadMesh& mesh, const std::vector<Located>& loc, double tol,
                         VerifyResult& r, std::vector<Violation>& out);

/// A unit grid cell in the chart of an input triangle: (triangle, lower-left u, v).
using FaceCell = std::array<std::int64_t, 3>;

/// Per input triangle: far from every fold-over, i.e. not `near_rings` and farther than the
/// reach of a fold-over an extractor leaves as it is (2.5 cells, in UV along the surface) from
/// every flipped or degenerate triangle (coverage.cpp).
std::vector<char> far_from_fold_overs(const Input& in, const InputEdges& edges, const std::vector<char>& fold_over,
                                      const std::vector<char>& near_rings);

/// Coverage (coverage.cpp): every unit grid cell the map covers once, where every triangle over
/// it is `far_from_folds` and no boundary cuts it by more than a noise band, must be a face, its
/// corners vertices (VerifyResult::coverage_cells). Appends GridPointNotCovered and
/// GridCellNotCovered violations to `out` (a cell whose corner vertex lies in a fold-over region
/// or is undecided, to `r.undecided`), and the cells no face covers to `uncovered`. Vertices
/// claim their grid points in the triangles within `uv_tolerance` (at least 1e-4) of them. Runs
/// on `threads` threads; the verdict does not depend on them.
void check_coverage(const LocatedMap& map, const QuadMesh& mesh, const std::vector<Located>& loc,
                    const std::vector<char>& far_from_folds, double uv_tolerance, int threads, VerifyResult& r,
                    std::vector<Violation>& out, std::vector<FaceCell>& uncovered);

} // namespace qex::verify_detail

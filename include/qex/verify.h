// The independent checker: judges a quad mesh against the input map with its own code and exact
// arithmetic. It is its own library (qex::verify) and sees nothing of the extractor; every test,
// fuzz target and the `qex check` command use it as their oracle.
#pragma once

#include "qex/mesh.h"

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
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
    /// Located mode: a grid point that the map covers once (a corner of a required cell, see
    /// VerifyResult::coverage_cells) on which no vertex lies; Violation::element is the input
    /// triangle whose chart holds it
    GridPointNotCovered,
    /// Located mode: a unit grid cell that the map covers once whose corners are vertices, but no
    /// face joins them in counter-clockwise order (a hole, a rotated edge, a reversed face);
    /// Violation::element is the input triangle whose chart holds it
    GridCellNotCovered,
    /// Located mode: a vertex whose number of faces differs from the map's valence where it lies
    /// (an interior vertex: 4 at a regular point, the singularity's valence on one; a boundary
    /// vertex on a boundary along iso-lines: the corner's quarter turns), decided in fold-over
    /// regions too; Violation::element is the vertex
    ValenceMismatch,
    /// Located mode: a singularity of the map (or a corner of a boundary along iso-lines) on which
    /// no vertex of the mesh lies; Violation::element is its input vertex
    SingularityNotCarried,
    /// A boundary loop of the mesh that does not run along the input's boundary (a hole);
    /// Violation::element is its first vertex, its places the loop, its faces and the input
    /// triangles under it
    Hole,
    /// Located mode: a component of the input on which no vertex of the mesh lies;
    /// Violation::element is its first input triangle
    MissingComponent,
    /// A certificate (verify with a Certificate) that is not the given map repaired inside its
    /// listed triangles: other positions or triangles, a UV moved outside them, a transition or
    /// a valence changed, a listed triangle not positively oriented, another newly flipped;
    /// Violation::element is the input triangle at fault (an input vertex's first triangle,
    /// the vertex then its place)
    CertificateMismatch,
};
const char* to_string(ViolationKind kind);

/// What Violation::element indexes, for each kind of violation.
enum class ViolationElement {
    None,          ///< nothing: a violation of the whole mesh (topology counts, coverage, size)
    OutputFace,    ///< a face of the judged mesh
    OutputVertex,  ///< a vertex of the judged mesh
    InputVertex,   ///< a vertex of the input (SingularityOffGrid)
    InputTriangle, ///< a triangle of the input (MapNotIntegerGrid, RepairNotCertified, CertificateMismatch)
};
/// What a violation of kind `kind` names in Violation::element.
ViolationElement element_kind(ViolationKind kind);

/// What one place of a violation lists (Place::indices).
enum class PlaceKind {
    Vertex,        ///< output vertices
    Edge,          ///< output edges, each as its two vertices (indices in pairs)
    Face,          ///< output faces
    Loop,          ///< one closed loop of output vertices, in order (a boundary loop: a hole)
    InputVertex,   ///< input vertices
    InputTriangle, ///< input triangles
    /// Unit grid cells the map covers and no face does: per cell the input triangle whose
    /// chart holds it, then the cell's lower-left grid point (u, v) there (indices in triples)
    GridCell,
    /// Grid points: per point the input triangle whose chart holds it, then the point (u, v)
    /// there (indices in triples)
    GridPoint,
};
const char* to_string(PlaceKind kind);

/// A place of a violation: elements of one kind.
struct Place {
    PlaceKind kind = PlaceKind::Face;
    std::vector<std::int64_t> indices;
};

struct Violation {
    Violation() = default;
    Violation(ViolationKind k, std::string m, std::int64_t e = -1, std::vector<Place> p = {})
        : kind(k), message(std::move(m)), element(e), places(std::move(p)) {}

    ViolationKind kind = ViolationKind::NotQuad;
    std::string message;
    /// The element at fault, of the kind element_kind(kind) says; -1 when the violation has no
    /// single place (always for ViolationElement::None).
    std::int64_t element = -1;
    /// Where it is, as lists of elements (more than `element` says): a non-manifold edge's
    /// vertices and faces; for a violation of the whole mesh the candidates (a hole's boundary
    /// loop and the faces around it, an extra component's faces, the uncovered grid cells).
    /// verify() gives every violation at least the place `element` names, when it names one.
    std::vector<Place> places;
};

/// Located mode: how far around the map's fold-overs the checker allows the map a correct mesh
/// follows to differ from the raw map, in rings of input vertices: a repair (qex's stage repair
/// re-embeds free vertices up to 8 rings around flipped or degenerate triangles) moves the grid
/// points there. Nine rings: the repair's eight and one for its sanitized map's collapsed edges.
inline constexpr int kFoldRegionRings = 9;

/// Located mode: a fold-over region of the raw map: its flipped or degenerate triangles (exact),
/// connected through shared vertices, and the input triangles with a corner within
/// kFoldRegionRings edges of them. A mesh's vertex located on one of its triangles is judged on
/// the surface only (not for being on a grid point of the raw map), and faces with such a
/// corner are not judged as grid cells of it. Information, not a violation.
struct FoldRegion {
    std::int64_t triangles = 0;         ///< input triangles in the region
    std::int64_t fold_triangles = 0;    ///< of which flipped or degenerate in UV
    std::int64_t first_triangle = -1;   ///< the smallest index of a flipped or degenerate triangle in it
    double uv_area = 0.0;               ///< signed UV area of its triangles in the raw map (a double sum)
    double fold_uv_area = 0.0;          ///< signed UV area of its flipped or degenerate triangles
    std::int64_t vertices = 0;          ///< the mesh's vertices located in it
    std::int64_t off_grid_vertices = 0; ///< of which off the raw map's grid points (beyond the UV tolerance)
};

struct VerifyResult {
    bool valid = false;
    std::vector<Violation> violations;
    std::int64_t faces = 0, vertices = 0, edges = 0, boundary_loops = 0, components = 0;
    std::int64_t euler = 0;
    std::int64_t input_euler = 0, input_boundary_loops = 0, input_components = 0;
    std::int64_t input_triangles = 0; ///< the map's triangles (the undecided share's whole)
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
    /// Located mode: the precision the judged positions carry: the most significant decimal
    /// digits a coordinate needs to be read back exactly (1..17; 0 without finite coordinates),
    /// and whether every coordinate is a float32 value.
    int position_digits = 0;
    bool positions_float32 = false;
    /// Located mode: the distance tolerance in model units: distance_tolerance times the
    /// diagonal, and the largest per-vertex allowance for rounding (VerifyOptions::position_digits).
    double surface_tolerance = 0.0, max_rounding_tolerance = 0.0;
    /// Located mode: input triangles of negative UV area (exact; degenerate ones not counted).
    /// Any of them lifts the coverage check (CoverageMismatch).
    std::int64_t map_flipped_triangles = 0;
    std::int64_t coverage_difference = 0; ///< faces - input_signed_uv_area_rounded
    /// Located mode, the coverage check: the unit grid cells the map covers once (required: away
    /// from fold-overs by kFoldRegionRings rings, not cut by the boundary, no cone inside), each
    /// of which must be a face with its corners vertices; of those, the grid points no vertex
    /// lies on (GridPointNotCovered) and the cells no face joins (GridCellNotCovered); and the
    /// input triangles whose UV boxes were too large to enumerate (not checked).
    std::int64_t coverage_cells = 0, uncovered_grid_points = 0, uncovered_cells = 0;
    std::int64_t coverage_skipped_triangles = 0;
    /// Located mode, the singularity match: the raw map's singularities (cones of valence other
    /// than 4, modulo 4 where a fold-over lies in their fan), its interior cones whose angle sum
    /// reads as no whole number of quarter turns (not judged), the mesh's interior vertices of
    /// valence other than 4, and the vertices whose valence was judged against the map
    /// (ValenceMismatch, SingularityNotCarried).
    std::int64_t map_cones = 0, unread_cones = 0, irregular_vertices = 0, valences_judged = 0;
    /// Located mode, the singularity match in fold-over footprints (the vertices of the map's
    /// flipped or degenerate triangles, the triangles round them): the footprints whose
    /// valences the mesh does not match one by one but sums as a fold-free map of their rim
    /// requires (the fold may have merged or moved singularities; its mismatches are listed as
    /// undecided), and their input triangles and signed UV area (a double sum).
    std::int64_t undecided_footprints = 0, undecided_triangles = 0;
    double undecided_uv_area = 0.0;
    /// Located mode: checks that could not be decided because the map folds over there (a
    /// face's corners carried across flipped or degenerate triangles, or next to them) or
    /// through the fan of a singular vertex; not violations, listed for review.
    std::vector<Violation> undecided;
    /// Located mode: the raw map's fold-over regions (FoldRegion), ordered by first_triangle, and
    /// the mesh's vertices located in them and faces with such a corner: judged on the surface
    /// only (as far as the topology checks do not judge them).
    std::vector<FoldRegion> fold_regions;
    std::int64_t surface_only_vertices = 0, surface_only_faces = 0;
    /// Located mode: of those vertices, how many are off the raw map's grid points (beyond the UV
    /// tolerance: a violation outside the regions), and the largest UV distance (inf-norm) of one
    /// to its nearest grid point of the raw map (max_grid_distance leaves them out).
    std::int64_t off_grid_region_vertices = 0;
    double max_region_grid_distance = 0.0;
    /// Judged on a certificate (verify with a Certificate): the certificate passed its check
    /// against the given map, and the located mode judged the mesh on the certificate's map
    /// (fold-over regions, footprints and the undecided share are the certificate's, where it
    /// still folds); and how many triangles it lists as repaired. False when the certificate
    /// failed (CertificateMismatch) or none was given.
    bool on_certificate = false;
    std::int64_t certificate_triangles = 0;
    /// Signed UV area of the input map for display, printed with six decimals: the double sum,
    /// or the exact area rounded to a double where the sum's error bound left the rounding open.
    std::string input_signed_uv_area;
    /// The exact signed UV area rounded to the nearest integer, halves upwards; decided with
    /// exact rationals wherever the double sum's error bound does not decide it.
    std::int64_t input_signed_uv_area_rounded = 0;
};

class PreparedInput;

struct VerifyOptions {
    /// Meshes without provenance are located on the input surface (see below); off: topology only.
    bool locate = true;
    /// Located mode: a vertex must map within this UV distance (inf-norm) of an integer grid point
    /// (the map is the raw input, with its solver noise; qex's own output is within 1e-6), plus
    /// what rounding its position may move it in UV (see position_digits); and seams whose UV
    /// copies no transition relates within it are not crossed. A mesh with QuadMesh::grid_scale
    /// K is judged against the map times K, whose noise is K times the map's: K times this (at
    /// most 0.1, or this where larger) then. Above 1 it is taken as 1 (every point lies within
    /// 0.5 of a grid point); NaN or negative, as 0.
    double uv_tolerance = 1e-3;
    /// Located mode: and lie within this fraction of the bounding-box diagonal of the surface,
    /// plus what rounding its position may move it (see position_digits).
    double distance_tolerance = 1e-6;
    /// Located mode: the positions may be rounded to this many significant decimal digits (6:
    /// single precision, as written with %.6g or as float32). A coordinate x rounded so is off
    /// by at most 0.5 * 10^(1 - position_digits) * |x|, so a vertex at x may lie up to
    /// 0.5 * 10^(1 - position_digits) * |x| (Euclidean norm, model units) farther from the
    /// surface, and its UV may move by that times twice the map's largest stretch on the
    /// triangles around it (where that exceeds 0.25 UV, a vertex off its grid point is
    /// undecided, not a violation). 0: strict, the positions are taken as exact (doubles).
    int position_digits = 6;
    /// Located mode: find the raw map's fold-over regions (FoldRegion: kFoldRegionRings rings
    /// around its flipped or degenerate triangles, where a repair such as qex's may have moved
    /// the map) and judge the vertices located there on the surface only, their faces' failures
    /// as undecided (the singularity match is decided there all the same). On by default, as
    /// every front end judges (`qex check`, `qex draw --quads`, the C API, Python: check_mesh in
    /// qex/check.h); off (`qex check --no-fold-regions`): the raw map judged everywhere, as the
    /// extractor's own gate for its relaxed rungs requires.
    bool fold_regions = true;
    /// Located mode, strict on the map (`qex check --strict-map`): every check decided against
    /// the raw map everywhere, fold-over regions and footprints too (fold_regions off), and what
    /// would be undecided there is a violation. For a map without fold-overs, or to demand that
    /// an extractor's mesh matches every singularity one by one and puts every face on a cell.
    bool strict_map = false;
    /// Threads for the checker's parallel loops (0: every core, 1: serial). The verdict and the
    /// violations do not depend on it.
    int threads = 0;
    /// The input's topology, found once for many checks (PreparedInput). Taken where it was made
    /// from an input with the same vertex count and triangles; otherwise the input is analysed
    /// as without it. The verdict and the violations are the same either way.
    const PreparedInput* prepared = nullptr;
};

/// An input's topology (its edges, fans, Euler characteristic, boundary loops and components),
/// found once to judge many meshes against it, as an extractor judges its attempts: without it,
/// every verify() call finds it again. It keeps a pointer to the input's triangles, which must
/// outlive it unchanged.
class PreparedInput {
public:
    explicit PreparedInput(const Input& input, int threads = 0);
    ~PreparedInput();
    PreparedInput(const PreparedInput&) = delete;
    PreparedInput& operator=(const PreparedInput&) = delete;
    /// Whether it is the topology of `input`: the same vertex count and triangles.
    bool describes(const Input& input) const;
    struct Analysis; ///< the checker's own (verify.cpp)
    const Analysis& analysis() const { return *analysis_; }

private:
    const std::vector<std::array<int, 3>>* triangles_;
    std::size_t vertices_;
    std::unique_ptr<const Analysis> analysis_;
};

/// Judges `mesh` against `input` with its own code (no extraction code is shared) and exact
/// arithmetic: all-quad, manifold, oriented, boundary and Euler characteristic and components as
/// the input's, local UVs unit squares (when given). With `mesh.map_uvs` and provenance (qex's
/// own output): the sanitized map is an exact integer-grid map and every vertex is on its grid
/// point, exactly. Without provenance (any other extractor's mesh, or an OBJ read back), the
/// vertices are located on the surface: each must be the image of an integer grid point, each
/// face's corners one counter-clockwise grid cell, and the faces must cover the map: as many as
/// its area, and every cell it covers once (away from fold-overs and the boundary) a face.
/// Does not throw on malformed meshes.
VerifyResult verify(const Input& input, const QuadMesh& mesh, const VerifyOptions& options = {});

/// What a verdict left undecided, and where: the checks (VerifyResult::undecided), and the
/// map's fold-over regions that hold them, with their triangles and their share of the map's.
struct UndecidedShare {
    std::int64_t checks = 0, regions = 0, triangles = 0;
    double share = 0.0; ///< triangles / the map's triangles
};
UndecidedShare undecided_share(const VerifyResult& verdict);

/// The verdict in one line, as every front end prints it: "VALID" when nothing was left
/// undecided, else for example "VALID, 21 checks undecided in 1 fold-over region (12634
/// triangles, 64.1% of the map)"; "INVALID (3 violations)", with the same tail where some checks
/// were undecided.
std::string verdict_line(const VerifyResult& verdict);

/// qex extract's certificate: the repaired map a mesh of qex's own was extracted from, written
/// beside it (`qex extract --certificate`, qex::write_certificate), so that the mesh, read back
/// without provenance, is judged on the map it follows where the repair re-embedded fold-overs.
struct Certificate {
    /// The given map's positions and triangles, with the repaired map's UVs per corner (times
    /// grid_scale; a triangle collapsed for a zero-length UV edge keeps the given UVs).
    Input map;
    /// The triangles the repair changed (sorted, distinct); may be empty (sanitized map only).
    std::vector<std::int32_t> repaired;
    /// The factor the given map's UVs were multiplied by (QuadMesh::grid_scale), a power of two.
    int grid_scale = 1;
};

/// The certificate of qex's own result `mesh` (which carries its map) extracted from `input`;
/// an empty map when the mesh carries none. Not for a result split from the map divided by k
/// (Report::coarsening > 1): its mesh was extracted and checked at the coarse scale, and fails
/// the located mode on this map times k where the coarse extraction lost quads near its folds
/// (`qex extract --certificate` writes none then).
Certificate make_certificate(const Input& input, const QuadMesh& mesh);

/// Judges `mesh` on a certificate (located mode; its provenance and map, if any, are ignored).
/// First the certificate is checked against `input`, exactly: the same positions and triangles;
/// outside its listed triangles every corner's UV within the located mode's UV tolerance of the
/// given map's (times the grid scale); across every edge whose transition the given map
/// determines, the same grid automorphism, exactly; every interior edge a grid automorphism and
/// every singularity on a grid point (as for QuadMesh::map_uvs); the same windings (valences)
/// at the vertices of listed triangles where the given map's fan holds no fold, and no vertex
/// whose fan composes to no turn winding other than once or as given; every listed triangle
/// positively oriented and no other newly flipped or degenerate (CGAL's exact orientation).
/// A certificate that fails gives CertificateMismatch violations and an invalid verdict (the
/// mesh judged on the given map besides). One that passes: the mesh judged in located mode on
/// the certificate's map at grid scale 1 (VerifyResult::on_certificate).
VerifyResult verify(const Input& input, const QuadMesh& mesh, const Certificate& certificate,
                    const VerifyOptions& options = {});

} // namespace qex

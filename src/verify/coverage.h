// The located mode's coverage check, without provenance: every unit grid cell that the map
// covers once, away from its fold-overs and its boundary, must be a face of the mesh, and each of
// its corners a vertex. The input's triangles are enumerated: each owns the cells whose centre
// lies inside it (in its chart). A cell is required when the triangles over it (a flood across
// the input's transitions, from the owner) are positive, far from every fold-over, agree on one
// chart (no cone inside) and leave no boundary across it;
// its corners are then looked up among the grid points that the mesh's vertices claim (each
// vertex its grid point, in every triangle that holds it), and its four corner vertices must be
// one face's, in counter-clockwise order. Grid points and cells are compared as integers; the
// doubles only decide which cells are required and which triangles a claim reaches (with the
// margins below), never which grid point a vertex claims or that a face is a cell's.
// This header is the check's room: its tolerances, its types and the class that runs it, whose
// steps live in coverage.cpp (the run and its reports), coverage_claims.cpp (the grid points the
// vertices claim) and coverage_cells.cpp (which cells are required, and the cells round a grid
// point of the boundary that the singularity match asks for). Only these files include it.
#pragma once

#include "checker.h"
#include "grid.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <tuple>
#include <utility>
#include <vector>

namespace qex::verify_detail::coverage {

// === tolerances (UV units)

/// A boundary within this distance of a cell's side counts as on the side (solver noise on a
/// boundary along an iso-line): the cell is required. Farther inside, the boundary cuts the cell,
/// and the paper discards such partial faces: it is not required.
constexpr double kBoundaryBand = 1e-6;
/// A required cell's corner is looked up in a triangle over the cell within this distance of it.
constexpr double kCornerReach = 4 * kBoundaryBand;
/// A vertex claims its grid point in every triangle within this distance of it (at least; the
/// UV tolerance when larger): more than kCornerReach plus the charts' disagreement along an edge.
constexpr double kClaimReach = 1e-4;
/// A cell's reference point: its centre, the one point a grid automorphism (a quarter turn and
/// an integer translation) keeps inside it, so that every chart names the same point.
constexpr double kRefU = 0.5, kRefV = 0.5;
/// Triangles one cell's flood holds at most, triangles a vertex's claim visits at most, and steps
/// of the walk from a vertex's triangle to its grid point.
constexpr std::size_t kCellTriangles = 1u << 12, kClaimTriangles = 1u << 10;
constexpr int kWalkSteps = 1 << 12;
/// Cells looked at in all (a broken map can span huge UV boxes), per triangle of the input and
/// face of the mesh, and at least.
constexpr double kCellsPerElement = 64, kMinCells = 1e7;
/// Grid coordinates beyond this are not compared (a path through a broken map can compose
/// translations without bound).
constexpr double kFarGrid = 1e15;
/// How far (UV, along the surface) a fold-over reaches: an extractor that leaves it as the map
/// gives it (the paper's local handling) may lose the quads over it and, where its face walks
/// collapse, those of the cells next to them (on the real maps up to 2.5 cells away). Cells within
/// this distance are not required.
constexpr double kFoldReach = 3;

using P2 = std::array<double, 2>;

/// The length of (x, y) (std::hypot guards against overflow that UVs below kFarGrid cannot reach, slowly).
inline double norm(double x, double y) { return std::sqrt(x * x + y * y); }

inline double cross(const P2& a, const P2& b, const P2& c) {
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

inline double segment_distance(const P2& x, const P2& a, const P2& b) {
    const double dx = b[0] - a[0], dy = b[1] - a[1], len2 = dx * dx + dy * dy;
    const double s = len2 > 0 ? std::clamp(((x[0] - a[0]) * dx + (x[1] - a[1]) * dy) / len2, 0.0, 1.0) : 0.0;
    const double ex = x[0] - a[0] - s * dx, ey = x[1] - a[1] - s * dy;
    return std::sqrt(ex * ex + ey * ey);
}

/// The distance from x to the closed triangle p (0 inside; either orientation).
inline double triangle_distance(const P2& x, const std::array<P2, 3>& p) {
    const double d0 = cross(p[0], p[1], x), d1 = cross(p[1], p[2], x), d2 = cross(p[2], p[0], x);
    if ((d0 >= 0 && d1 >= 0 && d2 >= 0) || (d0 <= 0 && d1 <= 0 && d2 <= 0)) return 0.0;
    return std::min(
        {segment_distance(x, p[0], p[1]), segment_distance(x, p[1], p[2]), segment_distance(x, p[2], p[0])});
}

/// A grid point in the chart of an input triangle.
struct Key {
    std::uint32_t triangle = 0;
    GridPoint p{0, 0};
    bool operator<(const Key& o) const { return std::tie(triangle, p) < std::tie(o.triangle, o.p); }
    bool operator==(const Key& o) const { return triangle == o.triangle && p == o.p; }
};

/// A vertex on a grid point p, in the chart of one triangle.
struct Claim {
    GridPoint p{0, 0};
    std::uint32_t triangle = 0;
    std::int32_t vertex = 0;
    bool operator<(const Claim& o) const { return std::tie(triangle, p, vertex) < std::tie(o.triangle, o.p, o.vertex); }
};

/// Why a cell is not required (the flood's findings), or that it is.
enum class CellState { Required, NearFold, Cut, Cone, Unknown };

/// A required cell: its corners (counter-clockwise from the lower left), each in the chart of a
/// triangle over the cell that holds it.
struct RequiredCell {
    Key cell; ///< the owner and the cell's lower-left grid point in its chart
    std::array<Key, 4> corner;
};

/// Triangle t's corner UVs, less `origin`.
inline std::array<P2, 3> corner_uvs(const Input& in, std::uint32_t t, const P2& origin) {
    std::array<P2, 3> p;
    for (std::size_t k = 0; k < 3; ++k) p[k] = {in.uvs[3 * t + k][0] - origin[0], in.uvs[3 * t + k][1] - origin[1]};
    return p;
}

/// What one thread's floods over the triangles use: per triangle its generation and the map
/// from the flood's start's chart; the flood's queue; the triangles within reach of a point.
struct Scratch {
    explicit Scratch(std::size_t triangles) : stamp(triangles, 0), to(triangles) {}
    /// A new flood: every triangle unvisited.
    void next() {
        if (++generation == 0) {
            std::fill(stamp.begin(), stamp.end(), 0);
            generation = 1;
        }
    }
    std::vector<std::uint32_t> stamp;
    std::vector<Transition> to;
    std::vector<std::uint32_t> queue;
    std::uint32_t generation = 0;
    std::vector<std::pair<std::uint32_t, P2>> reach;
};

/// What judging one cell reads (judge_cell): the map; per triangle whether it lies far from every
/// fold-over (null: every triangle that is no fold-over); how near a corner a cone counts as at
/// it; and the band: a boundary within it of a side counts as on the side.
struct CellRules {
    const LocatedMap& map;
    const std::vector<char>* far;
    double claim_reach;
    double band;
};

/// The cell with lower-left p in the chart of triangle t0 (a triangle over its interior, which
/// does not hold it whole): whether it is required, and its corners (coverage_cells.cpp). The
/// triangles over it are flooded from t0; the first finding that makes it not required is the
/// answer.
CellState judge_cell(const CellRules& rules, std::uint32_t t0, const GridPoint& p, RequiredCell& cell,
                     Scratch& scratch);

/// A required cell and the claims at its corners, as the enumeration found it.
struct Found {
    RequiredCell cell;
    std::array<std::pair<const Claim*, const Claim*>, 4> at;
    bool all = false; ///< every corner claimed
};

/// The required cells no face covers, as run sorts them: the grid points no vertex claims (by
/// their canonical key) with the required cells at them, in the order first met, and the cells
/// whose corners are vertices that no face joins (one per set of corner vertices).
struct Uncovered {
    /// A cell whose corners are vertices but no face's: its corner vertices, and whether it is
    /// undecided (a corner's vertices all soft: in a fold-over region or undecided themselves).
    struct Missing {
        RequiredCell cell;
        std::array<std::int32_t, 4> vertices;
        bool soft;
    };
    std::map<Key, std::vector<Key>> points;
    std::vector<Key> point_order;
    std::vector<Missing> cells;
};

/// The coverage check of one mesh against one map.
class Coverage {
public:
    Coverage(const LocatedMap& map, const QuadMesh& mesh, const std::vector<Located>& loc,
             const std::vector<char>& far_from_folds, double uv_tolerance, int threads);
    /// Runs the check: violations to `out`, undecided cells to `r.undecided`, counts to `r`.
    void run(VerifyResult& r, std::vector<Violation>& out, std::vector<FaceCell>& uncovered);

private:
    // --- the check's steps (coverage.cpp)
    /// The triangles whose cells are looked at: far from fold-overs, within the budget of cells
    /// (in triangle order, so the same whatever the thread count); the others counted in `r`.
    /// `cells`: how many cells the chosen ones span (the budget they use).
    std::vector<std::uint32_t> triangles_to_enumerate(VerifyResult& r, double& cells) const;
    /// The required cells of `triangles` that no face covers, ordered by their key (each
    /// thread its triangles' cells); how many cells they require to `r.coverage_cells`.
    std::vector<Found> enumerate_all(const std::vector<std::uint32_t>& triangles, double cells, VerifyResult& r) const;
    /// The cells without a face, sorted out: at uncovered grid points, or with every corner a
    /// vertex but no face joining them.
    Uncovered sort_out(const std::vector<Found>& found) const;
    /// Whether some corner's claims are all soft: vertices in a fold-over region or that their
    /// precision cannot place (the cell is then undecided).
    bool soft_corner(const std::array<std::pair<const Claim*, const Claim*>, 4>& at) const;
    /// Reports the grid points that no vertex claims, each with the required cells at it.
    void report_points(const Uncovered& u, VerifyResult& r, std::vector<Violation>& out,
                       std::vector<FaceCell>& uncovered) const;
    /// Reports the cells whose corners are vertices that no face joins.
    void report_cells(const Uncovered& u, VerifyResult& r, std::vector<Violation>& out,
                      std::vector<FaceCell>& uncovered) const;
    /// The faces at two or more of the corner vertices: what the mesh has in a cell's place.
    std::vector<std::int64_t> faces_in_place(const std::array<std::int32_t, 4>& vertices) const;

    // --- the vertices' claims (coverage_claims.cpp)
    /// Triangle t's corner UVs, less `origin`.
    std::array<P2, 3> uv(std::uint32_t t, const P2& origin) const;
    /// Every vertex's claims: its grid point in each triangle within the claim reach of it.
    void claim_grid_points();
    /// Walks from triangle t towards the grid point p (in t's chart) until a triangle holds it
    /// within the claim reach; false when the walk leaves the surface, meets a fold-over or an
    /// edge without a transition, or runs too long.
    bool walk_to(std::uint32_t& t, GridPoint& p) const;
    /// The triangles within the claim reach of the point x (in the chart of triangle t, which
    /// holds it within the reach), reached from t across edges within twice the reach of it,
    /// with x in each one's chart, into `scratch.reach` (t first). Exact for integer points.
    void reach_from(std::uint32_t t, const P2& x, Scratch& scratch) const;
    /// The claims at key k.
    std::pair<const Claim*, const Claim*> claims_at(const Key& k) const;
    /// A face whose corners, in order, are claims at the four corners; -1 if none.
    std::int64_t face_at(const std::array<std::pair<const Claim*, const Claim*>, 4>& at) const;
    /// The smallest key of the grid point k (over the triangles within the claim reach).
    Key canonical(const Key& k, Scratch& scratch) const;

    // --- the required cells (coverage_cells.cpp)
    /// The required cells that triangle t owns whose corners are not one face's, to `found`;
    /// returns how many cells it requires.
    std::int64_t enumerate(std::uint32_t t, Scratch& scratch, std::vector<Found>& found) const;
    /// Whether triangle t owns the cell with reference point x (in t's chart) at `depth` inside
    /// it (EdgeLines::depth): x lies inside it, and where x lies within the claim reach of its
    /// edges, no triangle of smaller index holds it as well (or, if none holds it, lies within the
    /// reach). Solver noise can leave x in two triangles' charts or in none: each cell has one owner.
    bool owns(std::uint32_t t, double depth, const P2& x, Scratch& scratch) const;

    const LocatedMap& map_;
    const Input& in_;
    const QuadMesh& mesh_;
    const std::vector<Located>& loc_;
    const std::vector<char>& far_;
    double claim_reach_;
    int threads_;
    std::vector<Claim> claims_;        ///< sorted by key
    std::vector<std::size_t> claimed_; ///< per triangle, where its claims start in claims_ (CSR)
    /// Per vertex, its faces (CSR): each as the face and, for a quad, the three corners that
    /// follow the vertex.
    struct Around {
        std::int32_t face;
        std::array<std::int32_t, 3> next;
    };
    std::vector<std::uint32_t> face_start_;
    std::vector<Around> around_;
};

} // namespace qex::verify_detail::coverage

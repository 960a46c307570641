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
#include "checker.h"
#include "grid.h"
#include "parallel.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <string>
#include <tuple>

namespace qex::verify_detail {
namespace {

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
double norm(double x, double y) { return std::sqrt(x * x + y * y); }

double cross(const P2& a, const P2& b, const P2& c) {
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

double segment_distance(const P2& x, const P2& a, const P2& b) {
    const double dx = b[0] - a[0], dy = b[1] - a[1], len2 = dx * dx + dy * dy;
    const double s = len2 > 0 ? std::clamp(((x[0] - a[0]) * dx + (x[1] - a[1]) * dy) / len2, 0.0, 1.0) : 0.0;
    const double ex = x[0] - a[0] - s * dx, ey = x[1] - a[1] - s * dy;
    return std::sqrt(ex * ex + ey * ey);
}

/// The distance from x to the closed triangle p (0 inside; either orientation).
double triangle_distance(const P2& x, const std::array<P2, 3>& p) {
    const double d0 = cross(p[0], p[1], x), d1 = cross(p[1], p[2], x), d2 = cross(p[2], p[0], x);
    if ((d0 >= 0 && d1 >= 0 && d2 >= 0) || (d0 <= 0 && d1 <= 0 && d2 <= 0)) return 0.0;
    return std::min(
        {segment_distance(x, p[0], p[1]), segment_distance(x, p[1], p[2]), segment_distance(x, p[2], p[0])});
}

/// The closed box [lo, hi] and the closed segment ab meet (separating axes: the box's and the
/// segment's normal).
bool segment_meets_box(const P2& a, const P2& b, const P2& lo, const P2& hi) {
    if (std::max(a[0], b[0]) < lo[0] || std::min(a[0], b[0]) > hi[0] || std::max(a[1], b[1]) < lo[1] ||
        std::min(a[1], b[1]) > hi[1])
        return false;
    const P2 corners[4] = {lo, {hi[0], lo[1]}, hi, {lo[0], hi[1]}};
    bool left = false, right = false;
    for (const P2& c : corners) {
        const double s = cross(a, b, c);
        left = left || s >= 0;
        right = right || s <= 0;
    }
    return left && right;
}

/// A positive triangle's edges as lines: the signed distance of a point inside from each.
struct EdgeLines {
    std::array<P2, 3> from, along;   ///< each edge's start and vector
    std::array<double, 3> inverse{}; ///< 1 / its length (0 for a point)
    explicit EdgeLines(const std::array<P2, 3>& q) {
        for (std::size_t k = 0; k < 3; ++k) {
            from[k] = q[k];
            along[k] = {q[(k + 1) % 3][0] - q[k][0], q[(k + 1) % 3][1] - q[k][1]};
            const double len = norm(along[k][0], along[k][1]);
            inverse[k] = len > 0 ? 1 / len : 0;
        }
    }
    /// Distance from x to the nearest edge's line, positive inside (negative outside).
    double depth(const P2& x) const {
        double d = HUGE_VAL;
        for (std::size_t k = 0; k < 3; ++k)
            d = std::min(d, (along[k][0] * (x[1] - from[k][1]) - along[k][1] * (x[0] - from[k][0])) * inverse[k]);
        return d;
    }
    /// The unit cell centred at x lies inside, farther than `band` from every edge's line.
    bool holds_cell(const P2& x, double band) const {
        for (std::size_t k = 0; k < 3; ++k) {
            const double d = (along[k][0] * (x[1] - from[k][1]) - along[k][1] * (x[0] - from[k][0])) * inverse[k];
            // The corners' distances differ from the centre's by at most this (an affine function).
            const double spread = 0.5 * (std::abs(along[k][0]) + std::abs(along[k][1])) * inverse[k];
            if (!(d - spread > band)) return false;
        }
        return true;
    }
};

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

/// A required cell and the claims at its corners, as the enumeration found it.
struct Found {
    RequiredCell cell;
    std::array<std::pair<const Claim*, const Claim*>, 4> at;
    bool all = false; ///< every corner claimed
};

class Coverage {
public:
    Coverage(const LocatedMap& map, const QuadMesh& mesh, const std::vector<Located>& loc,
             const std::vector<char>& far_from_folds, double uv_tolerance, int threads);
    /// Runs the check: violations to `out`, undecided cells to `r.undecided`, counts to `r`.
    void run(VerifyResult& r, std::vector<Violation>& out, std::vector<FaceCell>& uncovered);

private:
    std::array<P2, 3> uv(std::uint32_t t, const P2& origin) const;
    /// Every vertex's claims: its grid point in each triangle within the claim reach of it.
    void claim_grid_points();
    /// The required cells that triangle t owns whose corners are not one face's, to `found`;
    /// returns how many cells it requires.
    std::int64_t enumerate(std::uint32_t t, Scratch& scratch, std::vector<Found>& found) const;
    /// Walks from triangle t towards the grid point p (in t's chart) until a triangle holds it
    /// within the claim reach; false when the walk leaves the surface, meets a fold-over or an
    /// edge without a transition, or runs too long.
    bool walk_to(std::uint32_t& t, GridPoint& p) const;
    /// The triangles within the claim reach of the point x (in the chart of triangle t, which
    /// holds it within the reach), reached from t across edges within twice the reach of it,
    /// with x in each one's chart, into `scratch.reach` (t first). Exact for integer points.
    void reach_from(std::uint32_t t, const P2& x, Scratch& scratch) const;
    /// Whether triangle t owns the cell with reference point x (in t's chart) at `depth` inside
    /// it (EdgeLines::depth): x lies inside it, and where x lies within the claim reach of its
    /// edges, no triangle of smaller index holds it as well (or, if none holds it, lies within the
    /// reach). Solver noise can leave x in two triangles' charts or in none: each cell has one owner.
    bool owns(std::uint32_t t, double depth, const P2& x, Scratch& scratch) const;
    /// The cell with lower-left p in the chart of triangle t0 (which does not hold it whole):
    /// whether it is required, and its corners.
    CellState judge_cell(std::uint32_t t0, const GridPoint& p, RequiredCell& cell, Scratch& scratch) const;
    /// The claims at key k.
    std::pair<const Claim*, const Claim*> claims_at(const Key& k) const;
    /// A face whose corners, in order, are claims at the four corners; -1 if none.
    std::int64_t face_at(const std::array<std::pair<const Claim*, const Claim*>, 4>& at) const;
    /// The smallest key of the grid point k (over the triangles within the claim reach).
    Key canonical(const Key& k, Scratch& scratch) const;

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

Coverage::Coverage(const LocatedMap& map, const QuadMesh& mesh, const std::vector<Located>& loc,
                   const std::vector<char>& far_from_folds, double uv_tolerance, int threads)
    : map_(map),
      in_(map.in),
      mesh_(mesh),
      loc_(loc),
      far_(far_from_folds),
      claim_reach_(std::max(kClaimReach, uv_tolerance)),
      threads_(threads) {
    // The faces at each vertex (the located mode runs only when every index is in range); a
    // quad with the three corners that follow the vertex, any other polygon with none (-1).
    const std::size_t nv = mesh.positions.size();
    face_start_.assign(nv + 1, 0);
    for (const auto& f : mesh.faces)
        for (int v : f) ++face_start_[static_cast<std::size_t>(v) + 1];
    for (std::size_t v = 0; v < nv; ++v) face_start_[v + 1] += face_start_[v];
    around_.resize(face_start_[nv]);
    std::vector<std::uint32_t> fill(face_start_.begin(), face_start_.end() - 1);
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
        const auto& q = mesh.faces[f];
        for (std::size_t k = 0; k < q.size(); ++k)
            around_[fill[static_cast<std::size_t>(q[k])]++] = {
                static_cast<std::int32_t>(f),
                q.size() == 4 ? std::array<std::int32_t, 3>{q[(k + 1) % 4], q[(k + 2) % 4], q[(k + 3) % 4]}
                              : std::array<std::int32_t, 3>{-1, -1, -1}};
    }
}

std::array<P2, 3> Coverage::uv(std::uint32_t t, const P2& origin) const {
    std::array<P2, 3> p;
    for (std::size_t k = 0; k < 3; ++k) p[k] = {in_.uvs[3 * t + k][0] - origin[0], in_.uvs[3 * t + k][1] - origin[1]};
    return p;
}

bool Coverage::walk_to(std::uint32_t& t, GridPoint& p) const {
    for (int step = 0; step < kWalkSteps; ++step) {
        const P2 origin{static_cast<double>(p[0]), static_cast<double>(p[1])};
        const std::array<P2, 3> q = uv(t, origin);
        if (triangle_distance({0, 0}, q) <= claim_reach_) return true;
        // Across the edge the point lies farthest beyond (in the triangle's orientation).
        const double area = cross(q[0], q[1], q[2]);
        int best = -1;
        double beyond = 0;
        for (int k = 0; k < 3; ++k) {
            const P2 &a = q[static_cast<std::size_t>(k)], &b = q[static_cast<std::size_t>((k + 1) % 3)];
            const double len = norm(b[0] - a[0], b[1] - a[1]);
            const double s = len > 0 ? -cross(a, b, {0, 0}) / len * (area < 0 ? -1 : 1) : 0;
            if (s > beyond) beyond = s, best = k;
        }
        if (best < 0) return false;
        const std::size_t c = 3 * t + static_cast<std::size_t>(best);
        const std::int64_t o = map_.edges.opposite[c];
        if (o < 0 || map_.fold_over[static_cast<std::size_t>(o / 3)]) return false;
        p = map_point(map_.edges.across[c], p);
        if (std::abs(static_cast<double>(p[0])) > kFarGrid || std::abs(static_cast<double>(p[1])) > kFarGrid)
            return false;
        t = static_cast<std::uint32_t>(o / 3);
    }
    return false;
}

void Coverage::reach_from(std::uint32_t t, const P2& x, Scratch& scratch) const {
    scratch.next();
    auto& reach = scratch.reach;
    reach.assign(1, {t, x});
    scratch.stamp[t] = scratch.generation;
    for (std::size_t head = 0; head < reach.size() && reach.size() < kClaimTriangles; ++head) {
        const auto [s, q] = reach[head];
        const std::array<P2, 3> here = uv(s, q);
        for (std::size_t k = 0; k < 3; ++k) {
            // Only across an edge near the point (the charts on its two sides disagree by less
            // than the reach): the triangle beyond holds no point farther from it.
            if (segment_distance({0, 0}, here[k], here[(k + 1) % 3]) > 2 * claim_reach_) continue;
            const std::size_t c = 3 * s + k;
            const std::int64_t o = map_.edges.opposite[c];
            if (o < 0) continue;
            const auto n = static_cast<std::uint32_t>(o / 3);
            if (scratch.stamp[n] == scratch.generation || map_.fold_over[n]) continue;
            const Transition& m = map_.edges.across[c];
            const P2 r = rotate_quarter(q, m.r);
            const P2 qn{r[0] + static_cast<double>(m.tx), r[1] + static_cast<double>(m.ty)};
            if (!(std::abs(qn[0]) < kFarGrid && std::abs(qn[1]) < kFarGrid)) continue;
            if (triangle_distance({0, 0}, uv(n, qn)) > claim_reach_) continue;
            scratch.stamp[n] = scratch.generation;
            reach.push_back({n, qn});
        }
    }
}

void Coverage::claim_grid_points() {
    // Each thread its vertices' claims (their order does not matter: they are sorted below).
    const auto nv = static_cast<std::int64_t>(loc_.size());
    const int threads = run_parallel(threads_, nv) ? threads_ : 1;
    std::vector<std::vector<Claim>> part(static_cast<std::size_t>(threads));
#if defined(_OPENMP)
#pragma omp parallel num_threads(threads)
#endif
    {
        const std::size_t me = thread_slot();
        Scratch scratch(in_.triangles.size());
        std::vector<Claim>& mine = part[me];
#if defined(_OPENMP)
#pragma omp for schedule(dynamic, 4096)
#endif
        for (std::int64_t vi = 0; vi < nv; ++vi) {
            const Located& L = loc_[static_cast<std::size_t>(vi)];
            if (!L.ok && !L.undecided) continue; // off the surface or off the grid: it claims nothing
            // Its grid point; one its precision cannot place, every grid point it may be on.
            for (int du = -L.spread; du <= L.spread; ++du)
                for (int dv = -L.spread; dv <= L.spread; ++dv) {
                    std::uint32_t t = L.triangle;
                    GridPoint p{L.grid[0] + du, L.grid[1] + dv};
                    if (map_.fold_over[t] || !walk_to(t, p)) continue;
                    reach_from(t, {static_cast<double>(p[0]), static_cast<double>(p[1])}, scratch);
                    for (const auto& [n, q] : scratch.reach)
                        mine.push_back({{static_cast<std::int64_t>(q[0]), static_cast<std::int64_t>(q[1])},
                                        n,
                                        static_cast<std::int32_t>(vi)});
                }
        }
    }
    // By triangle (a counting pass over the threads' claims), then each triangle's by grid point
    // and vertex.
    const std::size_t nt = in_.triangles.size();
    claimed_.assign(nt + 1, 0);
    for (const auto& p : part)
        for (const Claim& c : p) ++claimed_[c.triangle + 1];
    for (std::size_t t = 0; t < nt; ++t) claimed_[t + 1] += claimed_[t];
    claims_.resize(claimed_[nt]);
    std::vector<std::size_t> fill(claimed_.begin(), claimed_.end() - 1);
    for (auto& p : part) {
        for (const Claim& c : p) claims_[fill[c.triangle]++] = c;
        std::vector<Claim>().swap(p);
    }
    for (std::size_t t = 0; t < nt; ++t)
        std::sort(claims_.begin() + static_cast<std::ptrdiff_t>(claimed_[t]),
                  claims_.begin() + static_cast<std::ptrdiff_t>(claimed_[t + 1]));
}

std::pair<const Claim*, const Claim*> Coverage::claims_at(const Key& k) const {
    const Claim* from = claims_.data() + claimed_[k.triangle];
    const Claim* to = claims_.data() + claimed_[k.triangle + 1];
    return std::equal_range(from, to, Claim{k.p, k.triangle, 0},
                            [](const Claim& a, const Claim& b) { return a.p < b.p; });
}

std::int64_t Coverage::face_at(const std::array<std::pair<const Claim*, const Claim*>, 4>& at) const {
    auto claimed = [&](std::size_t i, int v) {
        for (const Claim* c = at[i].first; c != at[i].second; ++c)
            if (c->vertex == v) return true;
        return false;
    };
    for (const Claim* c = at[0].first; c != at[0].second; ++c) {
        const auto v = static_cast<std::size_t>(c->vertex);
        for (std::size_t i = face_start_[v]; i < face_start_[v + 1]; ++i) {
            const Around& a = around_[i];
            if (claimed(1, a.next[0]) && claimed(2, a.next[1]) && claimed(3, a.next[2])) return a.face;
        }
    }
    return -1;
}

CellState Coverage::judge_cell(std::uint32_t t0, const GridPoint& p, RequiredCell& cell, Scratch& scratch) const {
    const GridPoint corners[4] = {p, {p[0] + 1, p[1]}, {p[0] + 1, p[1] + 1}, {p[0], p[1] + 1}};
    cell.cell = {t0, p};
    // The triangles over the cell's interior (shrunk by the band): from the owner across the edges
    // that cross it. Where the map is locally injective over the cell they are connected so.
    scratch.next();
    auto &stamp = scratch.stamp, &queue = scratch.queue;
    auto& to = scratch.to;
    stamp[t0] = scratch.generation;
    to[t0] = Transition{};
    queue.assign(1, t0);
    for (std::size_t head = 0; head < queue.size(); ++head) {
        if (queue.size() > kCellTriangles) return CellState::Unknown;
        const std::uint32_t t = queue[head];
        // The cell in t's chart: its corners carried, the lowest of each coordinate.
        GridPoint lo = map_point(to[t], corners[0]);
        for (std::size_t i = 1; i < 4; ++i) {
            const GridPoint c = map_point(to[t], corners[i]);
            lo = {std::min(lo[0], c[0]), std::min(lo[1], c[1])};
        }
        const std::array<P2, 3> q = uv(t, {static_cast<double>(lo[0]), static_cast<double>(lo[1])});
        // A cone inside the cell or on a side (not at a corner) breaks its grid.
        for (std::size_t k = 0; k < 3; ++k) {
            if (!map_.singular[static_cast<std::size_t>(in_.triangles[t][k])]) continue;
            const P2& x = q[k];
            const bool in_cell =
                x[0] > -claim_reach_ && x[0] < 1 + claim_reach_ && x[1] > -claim_reach_ && x[1] < 1 + claim_reach_;
            const bool at_corner = (std::abs(x[0]) <= claim_reach_ || std::abs(x[0] - 1) <= claim_reach_) &&
                                   (std::abs(x[1]) <= claim_reach_ || std::abs(x[1] - 1) <= claim_reach_);
            if (in_cell && !at_corner) return CellState::Cone;
        }
        const P2 slo{kBoundaryBand, kBoundaryBand}, shi{1 - kBoundaryBand, 1 - kBoundaryBand};
        for (std::size_t k = 0; k < 3; ++k) {
            if (!segment_meets_box(q[k], q[(k + 1) % 3], slo, shi)) continue;
            const std::size_t c = 3 * t + k;
            const std::int64_t o = map_.edges.opposite[c];
            if (o < 0) return map_.edges.partner[c] >= 0 ? CellState::Unknown : CellState::Cut;
            const auto n = static_cast<std::uint32_t>(o / 3);
            if (map_.fold_over[n] || !far_[n]) return CellState::NearFold;
            Transition m;
            if (!compose(map_.edges.across[c], to[t], m)) return CellState::Unknown;
            if (stamp[n] == scratch.generation) {
                if (!same(m, to[n])) return CellState::Cone; // the charts disagree: a cone inside
                continue;
            }
            stamp[n] = scratch.generation;
            to[n] = m;
            queue.push_back(n);
        }
    }
    // Each corner in the flooded triangle nearest to it (the first of equals).
    for (std::size_t i = 0; i < 4; ++i) {
        double best = HUGE_VAL;
        for (const std::uint32_t t : queue) {
            const GridPoint c = map_point(to[t], corners[i]);
            const double d = triangle_distance({0, 0}, uv(t, {static_cast<double>(c[0]), static_cast<double>(c[1])}));
            if (d < best) best = d, cell.corner[i] = {t, c};
        }
        if (!(best <= kCornerReach)) return CellState::Unknown;
    }
    return CellState::Required;
}

Key Coverage::canonical(const Key& k, Scratch& scratch) const {
    reach_from(k.triangle, {static_cast<double>(k.p[0]), static_cast<double>(k.p[1])}, scratch);
    Key best = k;
    for (const auto& [n, q] : scratch.reach)
        best = std::min(best, Key{n, {static_cast<std::int64_t>(q[0]), static_cast<std::int64_t>(q[1])}});
    return best;
}

bool Coverage::owns(std::uint32_t t, double depth, const P2& x, Scratch& scratch) const {
    if (depth > claim_reach_) return true;
    if (depth < -claim_reach_) return false;
    // Near an edge: the smallest triangle that holds x strictly, else the smallest near it.
    reach_from(t, x, scratch);
    std::uint32_t holder = UINT32_MAX, near = UINT32_MAX;
    for (const auto& [n, y] : scratch.reach) {
        const std::array<P2, 3> p = uv(n, y);
        near = std::min(near, n);
        if (cross(p[0], p[1], {0, 0}) > 0 && cross(p[1], p[2], {0, 0}) > 0 && cross(p[2], p[0], {0, 0}) > 0)
            holder = std::min(holder, n);
    }
    return (holder != UINT32_MAX ? holder : near) == t;
}

std::string point(const GridPoint& g) { return "(" + std::to_string(g[0]) + ", " + std::to_string(g[1]) + ")"; }

std::string list(const std::vector<std::int64_t>& xs) {
    std::string s;
    for (std::size_t i = 0; i < xs.size(); ++i) s += (i ? " " : "") + std::to_string(xs[i]);
    return s;
}

std::int64_t Coverage::enumerate(std::uint32_t t, Scratch& scratch, std::vector<Found>& found) const {
    const std::array<P2, 3> q = uv(t, {0, 0});
    const EdgeLines lines(q);
    std::int64_t required = 0;
    // The cells whose reference point lies within the claim reach of its UV box.
    const double u0 = std::floor(std::min({q[0][0], q[1][0], q[2][0]}) - kRefU - claim_reach_);
    const double u1 = std::max({q[0][0], q[1][0], q[2][0]}) + claim_reach_;
    const double v0 = std::floor(std::min({q[0][1], q[1][1], q[2][1]}) - kRefV - claim_reach_);
    const double v1 = std::max({q[0][1], q[1][1], q[2][1]}) + claim_reach_;
    for (double u = u0; u + kRefU <= u1; ++u)
        for (double v = v0; v + kRefV <= v1; ++v) {
            // The triangle owns the cell whose reference point lies inside it.
            const P2 x{u + kRefU, v + kRefV};
            const double depth = lines.depth(x);
            if (depth < -claim_reach_ || !owns(t, depth, x, scratch)) continue;
            Found f;
            const GridPoint lo{static_cast<std::int64_t>(u), static_cast<std::int64_t>(v)};
            if (lines.holds_cell(x, kBoundaryBand)) { // the whole cell inside its owner: its corners there
                f.cell.cell = {t, lo};
                f.cell.corner = {
                    Key{t, lo}, {t, {lo[0] + 1, lo[1]}}, {t, {lo[0] + 1, lo[1] + 1}}, {t, {lo[0], lo[1] + 1}}};
            } else if (judge_cell(t, lo, f.cell, scratch) != CellState::Required) {
                continue;
            }
            ++required;
            f.all = true;
            for (std::size_t i = 0; i < 4; ++i) {
                f.at[i] = claims_at(f.cell.corner[i]);
                f.all = f.all && f.at[i].first != f.at[i].second;
            }
            if (!f.all || face_at(f.at) < 0) found.push_back(f);
        }
    return required;
}

void Coverage::run(VerifyResult& r, std::vector<Violation>& out, std::vector<FaceCell>& uncovered) {
    claim_grid_points();
    const std::size_t nt = in_.triangles.size();
    // The triangles whose cells are looked at: far from fold-overs, within the budget of cells
    // (in triangle order, so the same whatever the thread count).
    std::vector<std::uint32_t> triangles;
    const double most = std::max(kMinCells, kCellsPerElement * static_cast<double>(nt + mesh_.faces.size()));
    double budget = most;
    for (std::size_t t = 0; t < nt; ++t) {
        if (!far_[t] || map_.fold_over[t]) continue;
        const std::array<P2, 3> q = uv(static_cast<std::uint32_t>(t), {0, 0});
        const double lo[2] = {std::min({q[0][0], q[1][0], q[2][0]}), std::min({q[0][1], q[1][1], q[2][1]})};
        const double hi[2] = {std::max({q[0][0], q[1][0], q[2][0]}), std::max({q[0][1], q[1][1], q[2][1]})};
        const double looked = (hi[0] - lo[0] + 2) * (hi[1] - lo[1] + 2);
        if (!(looked <= budget) || !(std::abs(lo[0]) < kFarGrid && std::abs(hi[0]) < kFarGrid &&
                                     std::abs(lo[1]) < kFarGrid && std::abs(hi[1]) < kFarGrid)) {
            ++r.coverage_skipped_triangles;
            continue;
        }
        budget -= looked;
        triangles.push_back(static_cast<std::uint32_t>(t));
    }
    // Each thread its triangles' cells (in parallel from as many cells as the other loops'
    // elements); the cells without a face, in triangle order.
    const auto count = static_cast<std::int64_t>(triangles.size());
    const int threads = run_parallel(threads_, static_cast<std::int64_t>(most - budget)) ? threads_ : 1;
    std::vector<std::vector<Found>> part(static_cast<std::size_t>(threads));
    std::int64_t required = 0;
#if defined(_OPENMP)
#pragma omp parallel num_threads(threads) reduction(+ : required)
#endif
    {
        const std::size_t me = thread_slot();
        Scratch scratch(nt);
#if defined(_OPENMP)
#pragma omp for schedule(dynamic, 256)
#endif
        for (std::int64_t i = 0; i < count; ++i)
            required += enumerate(triangles[static_cast<std::size_t>(i)], scratch, part[me]);
    }
    r.coverage_cells = required;
    std::vector<Found> found;
    for (auto& p : part) found.insert(found.end(), p.begin(), p.end());
    std::sort(found.begin(), found.end(), [](const Found& a, const Found& b) { return a.cell.cell < b.cell.cell; });
    // Uncovered grid points (by their canonical key) with the required cells at them, and cells
    // whose corners are vertices but no face (by their corner vertices) with their undecided mark.
    Scratch scratch(nt);
    std::map<Key, std::vector<Key>> points;
    std::vector<Key> point_order;
    std::map<std::array<std::int32_t, 4>, bool> cell_seen;
    struct Missing {
        RequiredCell cell;
        std::array<std::int32_t, 4> vertices;
        bool soft;
    };
    std::vector<Missing> cells;
    for (const Found& f : found) {
        const RequiredCell& cell = f.cell;
        const auto& at = f.at;
        if (!f.all) {
            for (std::size_t i = 0; i < 4; ++i) {
                if (at[i].first != at[i].second) continue;
                const Key k = canonical(cell.corner[i], scratch);
                auto& at_point = points[k];
                if (at_point.empty()) point_order.push_back(k);
                if (std::find(at_point.begin(), at_point.end(), cell.cell) == at_point.end())
                    at_point.push_back(cell.cell);
            }
            continue;
        }
        // Every corner is a vertex, but no face joins them: one report per set of corners;
        // undecided where a corner's vertices all lie in a fold-over region or cannot be placed by
        // their precision (soft claims).
        bool soft = false;
        for (std::size_t i = 0; i < 4; ++i) {
            bool firm = false;
            for (const Claim* c = at[i].first; c != at[i].second; ++c) {
                const Located& L = loc_[static_cast<std::size_t>(c->vertex)];
                firm = firm || !(L.surface_only || L.undecided);
            }
            soft = soft || !firm;
        }
        std::array<std::int32_t, 4> vertices;
        for (std::size_t i = 0; i < 4; ++i) vertices[i] = at[i].first->vertex;
        std::array<std::int32_t, 4> id = vertices;
        std::rotate(id.begin(), std::min_element(id.begin(), id.end()), id.end());
        if (!cell_seen.emplace(id, true).second) continue;
        cells.push_back({cell, vertices, soft});
    }
    // The grid points that no vertex claims, each with the required cells at it.
    for (const Key& k : point_order) {
        const std::vector<Key>& at = points[k];
        ++r.uncovered_grid_points;
        Place grid{PlaceKind::GridPoint, {static_cast<std::int64_t>(k.triangle), k.p[0], k.p[1]}};
        Place around{PlaceKind::GridCell, {}};
        for (const Key& c : at) {
            around.indices.insert(around.indices.end(), {static_cast<std::int64_t>(c.triangle), c.p[0], c.p[1]});
            uncovered.push_back({static_cast<std::int64_t>(c.triangle), c.p[0], c.p[1]});
        }
        if (out.size() < kMaxListed)
            out.push_back({ViolationKind::GridPointNotCovered,
                           "grid point " + point(k.p) + " in the chart of input triangle " +
                               std::to_string(k.triangle) + " is a corner of " + std::to_string(at.size()) +
                               " grid cells the map covers once, but no vertex lies on it",
                           static_cast<std::int64_t>(k.triangle),
                           {grid, around}});
    }
    // The cells whose corners are vertices that no face joins.
    for (const Missing& m : cells) {
        const Key& k = m.cell.cell;
        std::vector<std::int64_t> vertices(m.vertices.begin(), m.vertices.end());
        // The faces at two or more of its corners: what the mesh has in its place.
        std::map<std::int64_t, int> hits;
        for (const std::int32_t v : m.vertices)
            for (std::size_t i = face_start_[static_cast<std::size_t>(v)];
                 i < face_start_[static_cast<std::size_t>(v) + 1]; ++i)
                ++hits[around_[i].face];
        std::vector<std::int64_t> faces;
        for (const auto& [f, n] : hits)
            if (n >= 2) faces.push_back(f);
        std::vector<Place> places{{PlaceKind::GridCell, {static_cast<std::int64_t>(k.triangle), k.p[0], k.p[1]}},
                                  {PlaceKind::Vertex, vertices}};
        if (!faces.empty()) places.push_back({PlaceKind::Face, faces});
        const std::string msg =
            "grid cell " + point(k.p) + " in the chart of input triangle " + std::to_string(k.triangle) +
            " is covered by the map once, but no face joins its corners, vertices " + list(vertices);
        if (m.soft) {
            if (r.undecided.size() < kMaxListed)
                r.undecided.push_back({ViolationKind::GridCellNotCovered,
                                       msg + " (a corner's vertex is placed on the surface only)",
                                       static_cast<std::int64_t>(k.triangle), std::move(places)});
            continue;
        }
        ++r.uncovered_cells;
        uncovered.push_back({static_cast<std::int64_t>(k.triangle), k.p[0], k.p[1]});
        if (out.size() < kMaxListed)
            out.push_back(
                {ViolationKind::GridCellNotCovered, msg, static_cast<std::int64_t>(k.triangle), std::move(places)});
    }
}

} // namespace

std::vector<char> far_from_fold_overs(const Input& in, const InputEdges& edges, const std::vector<char>& fold_over,
                                      const std::vector<char>& near_rings) {
    // Multi-source shortest paths over the triangles from the fold-overs, each step the distance
    // between two neighbours' UV centroids in one chart, less the UV radii of the source and the
    // triangle: an estimate of their UV distance along the surface (an overestimate by the
    // paths' detours: kFoldReach leaves a margin over the reach measured).
    const std::size_t nt = in.triangles.size();
    std::vector<P2> centre(nt);
    std::vector<double> radius(nt, 0.0), dist(nt, HUGE_VAL);
    for (std::size_t t = 0; t < nt; ++t) {
        centre[t] = {0, 0};
        for (std::size_t k = 0; k < 3; ++k)
            for (int d = 0; d < 2; ++d) centre[t][d] += in.uvs[3 * t + k][d] / 3;
        for (std::size_t k = 0; k < 3; ++k)
            radius[t] =
                std::max(radius[t], norm(in.uvs[3 * t + k][0] - centre[t][0], in.uvs[3 * t + k][1] - centre[t][1]));
    }
    std::vector<std::pair<double, std::uint32_t>> heap;
    for (std::size_t t = 0; t < nt; ++t)
        if (fold_over[t]) dist[t] = -radius[t], heap.push_back({dist[t], static_cast<std::uint32_t>(t)});
    std::make_heap(heap.begin(), heap.end(), std::greater<>());
    while (!heap.empty()) {
        std::pop_heap(heap.begin(), heap.end(), std::greater<>());
        const auto [d, t] = heap.back();
        heap.pop_back();
        if (d > dist[t] || d - radius[t] > kFoldReach) continue;
        for (std::size_t k = 0; k < 3; ++k) {
            const std::size_t c = 3 * t + k;
            const std::int64_t o = edges.opposite[c];
            const std::int64_t across = edges.partner[c];
            if (across < 0) continue; // the boundary
            const auto n = static_cast<std::size_t>(across / 3);
            // The neighbour's centroid carried into t's chart (the transition from n's chart);
            // across an edge without a transition (nearly degenerate, or noise beyond the UV
            // tolerance) no step at all.
            double step = 0;
            if (o >= 0) {
                const Transition& back = edges.across[static_cast<std::size_t>(o)];
                const P2 r = rotate_quarter(centre[n], back.r);
                step = norm(r[0] + static_cast<double>(back.tx) - centre[t][0],
                            r[1] + static_cast<double>(back.ty) - centre[t][1]);
            }
            const double dn = d + (std::isfinite(step) ? step : 0.0);
            if (dn < dist[n])
                dist[n] = dn, heap.push_back({dn, static_cast<std::uint32_t>(n)}),
                std::push_heap(heap.begin(), heap.end(), std::greater<>());
        }
    }
    std::vector<char> far(nt, 0);
    for (std::size_t t = 0; t < nt; ++t) far[t] = !near_rings[t] && !fold_over[t] && dist[t] - radius[t] > kFoldReach;
    return far;
}

void check_coverage(const LocatedMap& map, const QuadMesh& mesh, const std::vector<Located>& loc,
                    const std::vector<char>& far_from_folds, double uv_tolerance, int threads, VerifyResult& r,
                    std::vector<Violation>& out, std::vector<FaceCell>& uncovered) {
    Coverage(map, mesh, loc, far_from_folds, uv_tolerance, threads).run(r, out, uncovered);
}

} // namespace qex::verify_detail

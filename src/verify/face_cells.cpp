// The located mode's face check: a face's corners, each located in some input triangle, are
// carried into the chart of one anchor triangle along the input's transitions (a shortest-path
// search over the triangles), and there must be the corners of one counter-clockwise unit grid
// cell. The search's distances choose the paths; the grid points are compared as integers.
#include "checker.h"
#include "grid.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <string>

namespace qex::verify_detail {
namespace {

/// a and b are neighbouring grid points (and not far).
bool unit_step(const GridPoint& a, const GridPoint& b) {
    for (int k = 0; k < 2; ++k)
        if (a[k] <= -kFar || a[k] >= kFar || b[k] <= -kFar || b[k] >= kFar) return false;
    return std::llabs(a[0] - b[0]) + std::llabs(a[1] - b[1]) == 1;
}

using Quad = std::array<GridPoint, 4>;

/// The four grid points are a counter-clockwise unit cell: unit steps and area 1.
bool is_cell(const Quad& q) {
    for (std::size_t i = 0; i < 4; ++i)
        if (!unit_step(q[i], q[(i + 1) % 4])) return false;
    // Unit steps keep every corner within 2 of the first: the area in differences is exact.
    std::int64_t twice_area = 0;
    for (std::size_t i = 1; i + 1 < 4; ++i) {
        const std::int64_t ax = q[i][0] - q[0][0], ay = q[i][1] - q[0][1];
        const std::int64_t bx = q[i + 1][0] - q[0][0], by = q[i + 1][1] - q[0][1];
        twice_area += ax * by - ay * bx;
    }
    return twice_area == 2;
}

std::string point(const GridPoint& g) { return "(" + std::to_string(g[0]) + ", " + std::to_string(g[1]) + ")"; }

/// What the anchors of one face showed: whether one showed a unit cell; the first anchor that
/// reached all four corners and the grid points there; per edge (i, i+1), whether an anchor at
/// one of its ends judged it, and whether one saw a unit step.
struct Anchors {
    bool cell = false, reached_all = false;
    Quad first{};
    std::uint32_t first_anchor = 0;
    std::array<bool, 4> edge_ok{false, false, false, false}, edge_seen{false, false, false, false};
};

/// The corridor of a face's edge (a, b): the triangles within kCorridor |ab| of the segment ab,
/// reached from a's triangle. Where the transitions compose to the same map along every path
/// inside it (checked edge by edge), no fold-over lies in it and no cone but at a or b (whose
/// fans are cut: turning about an end keeps the distance to it), carrying b's grid point
/// through it gives one answer, the one along any iso-line from a to b inside it: a path
/// homotopic to the edge. A correct mesh's edge is a unit iso-line whose arc stays within
/// kCorridor of its chord (an arc up to twice as long as its chord does).
constexpr double kCorridor = 0.5;
/// Triangles a corridor holds at most (beyond: not certified).
constexpr std::size_t kCorridorBudget = 1u << 14;

/// An edge carried through its corridor: b's grid point in the chart of a's triangle, and the
/// map from the chart b was read in to that chart.
struct Edge {
    GridPoint b{0, 0};
    Transition m;
    bool b_on_cone = false;
};

using Vec = std::array<double, 3>;
Vec sub(const Vec& x, const Vec& y) { return {x[0] - y[0], x[1] - y[1], x[2] - y[2]}; }
double dot(const Vec& x, const Vec& y) { return x[0] * y[0] + x[1] * y[1] + x[2] * y[2]; }
Vec cross(const Vec& x, const Vec& y) {
    return {x[1] * y[2] - x[2] * y[1], x[2] * y[0] - x[0] * y[2], x[0] * y[1] - x[1] * y[0]};
}
double norm(const Vec& x) { return std::sqrt(dot(x, x)); }

/// The distance from x to the segment ab.
double segment_distance(const Vec& x, const Vec& a, const Vec& b) {
    const Vec ab = sub(b, a), ax = sub(x, a);
    const double len2 = dot(ab, ab);
    const double s = len2 > 0 ? std::clamp(dot(ab, ax) / len2, 0.0, 1.0) : 0.0;
    return norm({ax[0] - s * ab[0], ax[1] - s * ab[1], ax[2] - s * ab[2]});
}

/// The distance between the segments pq and rs (the closest points by clamped parameters).
double segments_distance(const Vec& p, const Vec& q, const Vec& r, const Vec& s) {
    const Vec d1 = sub(q, p), d2 = sub(s, r), w = sub(p, r);
    const double a = dot(d1, d1), e = dot(d2, d2), f = dot(d2, w);
    if (a <= 0 || e <= 0) return std::min(segment_distance(p, r, s), segment_distance(r, p, q));
    const double b = dot(d1, d2), c = dot(d1, w), den = a * e - b * b;
    double sc = den > 0 ? std::clamp((b * f - c * e) / den, 0.0, 1.0) : 0.0;
    double tc = (b * sc + f) / e;
    if (tc < 0)
        tc = 0, sc = std::clamp(-c / a, 0.0, 1.0);
    else if (tc > 1)
        tc = 1, sc = std::clamp((b - c) / a, 0.0, 1.0);
    return norm(sub({p[0] + sc * d1[0], p[1] + sc * d1[1], p[2] + sc * d1[2]},
                    {r[0] + tc * d2[0], r[1] + tc * d2[1], r[2] + tc * d2[2]}));
}

/// The distance from x to the triangle p (its plane where x projects inside, else its edges).
double point_triangle_distance(const Vec& x, const std::array<Vec, 3>& p) {
    const Vec n = cross(sub(p[1], p[0]), sub(p[2], p[0]));
    const double nn = dot(n, n);
    if (nn > 0) {
        bool inside = true;
        for (int k = 0; k < 3; ++k) inside = inside && dot(cross(sub(p[(k + 1) % 3], p[k]), sub(x, p[k])), n) >= 0;
        if (inside) return std::abs(dot(sub(x, p[0]), n)) / std::sqrt(nn);
    }
    double d = HUGE_VAL;
    for (int k = 0; k < 3; ++k) d = std::min(d, segment_distance(x, p[k], p[(k + 1) % 3]));
    return d;
}

/// The distance from the segment ab to the triangle p: 0 where the segment crosses it, else the
/// least of its ends' distances and its distances to the triangle's edges.
double segment_triangle_distance(const Vec& a, const Vec& b, const std::array<Vec, 3>& p) {
    const Vec n = cross(sub(p[1], p[0]), sub(p[2], p[0]));
    const double da = dot(sub(a, p[0]), n), db = dot(sub(b, p[0]), n);
    if ((da <= 0 && db >= 0) || (da >= 0 && db <= 0)) {
        if (da != db) {
            const double s = da / (da - db);
            const Vec x{a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1]), a[2] + s * (b[2] - a[2])};
            bool inside = true;
            for (int k = 0; k < 3; ++k) inside = inside && dot(cross(sub(p[(k + 1) % 3], p[k]), sub(x, p[k])), n) >= 0;
            if (inside) return 0.0;
        }
    }
    double d = std::min(point_triangle_distance(a, p), point_triangle_distance(b, p));
    for (int k = 0; k < 3; ++k) d = std::min(d, segments_distance(a, b, p[k], p[(k + 1) % 3]));
    return d;
}

/// Judges the faces one by one; keeps the search's scratch between them.
class FaceJudge {
public:
    FaceJudge(const LocatedMap& map, const QuadMesh& mesh, const std::vector<Located>& loc);
    /// Face f: passes, or appends its violation (or undecided check).
    void judge(std::size_t f, VerifyResult& r, std::vector<Violation>& out);

private:
    /// Each corner's triangle in turn, then the triangle under the face's centre.
    Anchors try_anchors(const std::vector<int>& face, const std::array<double, 3>& centre);
    /// All four corners carried into the chart of anchor tc (into g_); false when the search
    /// does not reach them all.
    bool transport(const std::vector<int>& face, std::uint32_t tc);
    /// The triangle where the search from tc reached each corner, or -1.
    std::array<std::int64_t, 4> search(const std::vector<int>& face, std::uint32_t tc);
    /// The grid point of the located vertex L, read in triangle t0, carried back to tc along the search's path.
    GridPoint carry(const Located& L, std::uint32_t t0, std::uint32_t tc);
    /// Reports the failure of face f: a violation when `certified` and no path or corner
    /// touched a fold-over or a singular fan, else undecided.
    void report(std::size_t f, const std::string& msg, bool certified, VerifyResult& r,
                std::vector<Violation>& out) const;
    /// Carries vertex b's grid point into the chart of vertex a's triangle through the corridor
    /// of the edge (a, b) (see below): false when the corridor does not certify one answer.
    bool along_edge(int a, int b, Edge& e);
    /// The corridor's triangles: within kCorridor |ab| of the segment ab (a superset: by centroid
    /// distance less the triangle's radius).
    bool in_corridor(std::uint32_t t, const std::array<double, 3>& a, const std::array<double, 3>& b, double rho) const;
    /// A fold-over shares a vertex with triangle t.
    bool near_fold(std::uint32_t t) const;

    const LocatedMap& map_;
    const Input& in_;
    const QuadMesh& mesh_;
    const std::vector<Located>& loc_;
    std::vector<double> step_;      ///< per half-edge: the distance between the centroids across it
    std::vector<char> fold_vertex_; ///< per input vertex: a corner of a fold-over
    std::size_t budget_;            ///< triangles a search settles at most
    // The search's scratch: triangles stamped with the current generation were reached.
    std::vector<std::uint32_t> stamp_;
    std::vector<double> best_;
    std::vector<std::int64_t> via_; ///< the half-edge through which a triangle was reached
    std::vector<std::pair<double, std::uint32_t>> heap_;
    std::uint32_t generation_ = 0;
    // The corridors' scratch: per triangle its generation, and the map from its chart to the
    // chart of the corridor's start.
    std::vector<std::array<double, 3>> centre_;
    std::vector<double> radius_; ///< per triangle: the largest distance from its centroid to a corner
    std::vector<std::uint32_t> cstamp_;
    std::vector<Transition> to_start_;
    std::vector<std::uint32_t> queue_;
    std::uint32_t cgeneration_ = 0;
    // The face being judged: its corners in the last anchor's chart, and whether any anchor's
    // paths (or a corner) touched a fold-over or a singular fan.
    Quad g_{};
    bool corner_near_fold_ = false, through_fold_ = false, through_singular_ = false;
    bool corner_in_region_ = false; ///< a corner lies in a fold-over region (judged on the surface only)
};

FaceJudge::FaceJudge(const LocatedMap& map, const QuadMesh& mesh, const std::vector<Located>& loc)
    : map_(map),
      in_(map.in),
      mesh_(mesh),
      loc_(loc),
      step_(centroid_steps(map.in, map.edges)),
      fold_vertex_(map.in.positions.size(), 0),
      stamp_(map.in.triangles.size(), 0),
      best_(map.in.triangles.size(), 0.0),
      via_(map.in.triangles.size(), -1),
      centre_(map.in.triangles.size()),
      radius_(map.in.triangles.size(), 0.0),
      cstamp_(map.in.triangles.size(), 0),
      to_start_(map.in.triangles.size()) {
    const std::size_t nt = in_.triangles.size();
    for (std::size_t t = 0; t < nt; ++t) {
        std::array<double, 3> c{0, 0, 0};
        for (int k = 0; k < 3; ++k)
            for (int d = 0; d < 3; ++d) c[d] += in_.positions[static_cast<std::size_t>(in_.triangles[t][k])][d] / 3;
        double r2 = 0;
        for (int k = 0; k < 3; ++k) {
            const auto& x = in_.positions[static_cast<std::size_t>(in_.triangles[t][k])];
            r2 = std::max(
                r2, (x[0] - c[0]) * (x[0] - c[0]) + (x[1] - c[1]) * (x[1] - c[1]) + (x[2] - c[2]) * (x[2] - c[2]));
        }
        centre_[t] = c;
        radius_[t] = std::sqrt(r2);
    }
    budget_ = std::max<std::size_t>(1u << 14, 64 * nt / std::max<std::size_t>(mesh.faces.size(), 1));
    // Vertices next to a fold-over: a flipped or degenerate triangle shares a vertex with the
    // triangle the output vertex lies on. There the grid point can have several preimages, and a
    // vertex that stands for all of them (merged clones) can be judged from none.
    for (std::size_t t = 0; t < nt; ++t)
        if (map_.fold_over[t])
            for (int k = 0; k < 3; ++k) fold_vertex_[static_cast<std::size_t>(in_.triangles[t][k])] = 1;
}

bool FaceJudge::near_fold(std::uint32_t t) const {
    for (int k = 0; k < 3; ++k)
        if (fold_vertex_[static_cast<std::size_t>(in_.triangles[t][k])]) return true;
    return false;
}

std::array<std::int64_t, 4> FaceJudge::search(const std::vector<int>& face, std::uint32_t tc) {
    if (++generation_ == 0) {
        std::fill(stamp_.begin(), stamp_.end(), 0);
        generation_ = 1;
    }
    std::array<std::int64_t, 4> reached{-1, -1, -1, -1};
    int missing = 4;
    // A corner is reached in its triangle, or (on an input vertex) in any triangle of its fan.
    auto visit = [&](std::uint32_t t) {
        for (std::size_t i = 0; i < 4; ++i) {
            if (reached[i] >= 0) continue;
            const Located& L = loc_[static_cast<std::size_t>(face[i])];
            bool hit = L.triangle == t;
            for (int k = 0; k < 3 && !hit && L.on_vertex >= 0; ++k) hit = in_.triangles[t][k] == L.on_vertex;
            if (hit) reached[i] = t, --missing;
        }
    };
    // Dijkstra over triangle centroids: the paths approximate geodesics, so the path to the
    // corner across the cell runs through the cell, not round a singular corner.
    heap_.clear();
    best_[tc] = 0.0;
    stamp_[tc] = generation_;
    via_[tc] = -1;
    heap_.push_back({0.0, tc});
    std::size_t settled = 0;
    while (!heap_.empty() && missing > 0 && settled < budget_) {
        std::pop_heap(heap_.begin(), heap_.end(), std::greater<>());
        const auto [d, t] = heap_.back();
        heap_.pop_back();
        if (d > best_[t]) continue;
        ++settled;
        visit(t);
        for (int k = 0; k < 3; ++k) {
            const std::int64_t o = map_.edges.opposite[3 * t + k];
            if (o < 0) continue;
            const auto n = static_cast<std::uint32_t>(o / 3);
            const double dn = d + step_[3 * t + k];
            if (stamp_[n] == generation_ && dn >= best_[n]) continue;
            stamp_[n] = generation_;
            best_[n] = dn;
            via_[n] = o; // entered n through its half-edge o
            heap_.push_back({dn, n});
            std::push_heap(heap_.begin(), heap_.end(), std::greater<>());
        }
    }
    return reached;
}

GridPoint FaceJudge::carry(const Located& L, std::uint32_t t0, std::uint32_t tc) {
    // The grid point in the reached triangle's chart (for a corner on an input vertex, that
    // vertex's rounded UV there), then back to the anchor's triangle.
    GridPoint p = L.grid;
    if (t0 != L.triangle) {
        int k = 0;
        while (k < 2 && in_.triangles[t0][k] != L.on_vertex) ++k;
        const auto& u = in_.uvs[3 * t0 + static_cast<std::size_t>(k)];
        p = {static_cast<std::int64_t>(std::nearbyint(u[0])), static_cast<std::int64_t>(std::nearbyint(u[1]))};
    }
    through_fold_ = through_fold_ || map_.fold_over[L.triangle] || map_.fold_over[tc];
    for (std::uint32_t t = t0; t != tc;) {
        through_fold_ = through_fold_ || map_.fold_over[t];
        const auto o = static_cast<std::size_t>(via_[t]);
        through_singular_ = through_singular_ || map_.singular[static_cast<std::size_t>(in_.triangles[o / 3][o % 3])] ||
                            map_.singular[static_cast<std::size_t>(in_.triangles[o / 3][(o % 3 + 1) % 3])];
        const Transition& T = map_.edges.across[o]; // from t's chart to the chart it was reached from
        const auto q = rotate_quarter(p, T.r);
        if (std::llabs(q[0]) >= kFar || std::llabs(q[1]) >= kFar) return {kFar, kFar}; // judged as no unit step
        p = {q[0] + T.tx, q[1] + T.ty};
        t = static_cast<std::uint32_t>(map_.edges.opposite[o] / 3);
    }
    return p;
}

bool FaceJudge::transport(const std::vector<int>& face, std::uint32_t tc) {
    const std::array<std::int64_t, 4> reached = search(face, tc);
    for (std::size_t i = 0; i < 4; ++i) {
        if (reached[i] < 0) return false;
        g_[i] = carry(loc_[static_cast<std::size_t>(face[i])], static_cast<std::uint32_t>(reached[i]), tc);
    }
    return true;
}

bool FaceJudge::in_corridor(std::uint32_t t, const std::array<double, 3>& a, const std::array<double, 3>& b,
                            double rho) const {
    // Cheap rejection by the centroid, then the distance from the segment to the triangle.
    if (segment_distance(centre_[t], a, b) > rho + radius_[t]) return false;
    std::array<std::array<double, 3>, 3> p;
    for (int k = 0; k < 3; ++k) p[k] = in_.positions[static_cast<std::size_t>(in_.triangles[t][k])];
    return segment_triangle_distance(a, b, p) <= rho;
}

bool FaceJudge::along_edge(int a, int b, Edge& e) {
    const Located &A = loc_[static_cast<std::size_t>(a)], &B = loc_[static_cast<std::size_t>(b)];
    const auto &pa = mesh_.positions[static_cast<std::size_t>(a)], &pb = mesh_.positions[static_cast<std::size_t>(b)];
    const double rho = kCorridor * std::sqrt((pb[0] - pa[0]) * (pb[0] - pa[0]) + (pb[1] - pa[1]) * (pb[1] - pa[1]) +
                                             (pb[2] - pa[2]) * (pb[2] - pa[2]));
    // Cones at the ends: their fans are cut (no path crosses an edge at them).
    const std::int64_t cone_a =
        A.on_vertex >= 0 && map_.singular[static_cast<std::size_t>(A.on_vertex)] ? A.on_vertex : -1;
    const std::int64_t cone_b =
        B.on_vertex >= 0 && map_.singular[static_cast<std::size_t>(B.on_vertex)] ? B.on_vertex : -1;
    if (++cgeneration_ == 0) {
        std::fill(cstamp_.begin(), cstamp_.end(), 0);
        cgeneration_ = 1;
    }
    const std::uint32_t t0 = A.triangle;
    if (map_.fold_over[t0]) return false;
    cstamp_[t0] = cgeneration_;
    to_start_[t0] = Transition{};
    queue_.assign(1, t0);
    for (std::size_t head = 0; head < queue_.size(); ++head) {
        if (queue_.size() > kCorridorBudget) return false;
        const std::uint32_t t = queue_[head];
        for (std::size_t k = 0; k < 3; ++k) {
            const std::size_t c = 3 * t + k;
            const int u = in_.triangles[t][k], w = in_.triangles[t][(k + 1) % 3];
            if (u == cone_a || w == cone_a || u == cone_b || w == cone_b) continue; // a cut fan
            const std::int64_t o = map_.edges.opposite[c];
            if (o < 0) {
                if (map_.edges.partner[c] >= 0) return false; // a crossing without a known transition
                continue;                                     // the boundary
            }
            const auto n = static_cast<std::uint32_t>(o / 3);
            if (!in_corridor(n, pa, pb, rho)) continue;
            if (map_.fold_over[n]) return false;
            Transition m;
            if (!compose(to_start_[t], map_.edges.across[static_cast<std::size_t>(o)], m)) return false;
            if (cstamp_[n] == cgeneration_) {
                if (!same(m, to_start_[n])) return false; // a cone (or an inconsistent loop) inside
                continue;
            }
            cstamp_[n] = cgeneration_;
            to_start_[n] = m;
            queue_.push_back(n);
        }
    }
    // b read in its own triangle, or at a cone, in any triangle of its fan the corridor reached.
    e.b_on_cone = cone_b >= 0;
    if (cone_b < 0) {
        if (cstamp_[B.triangle] != cgeneration_) return false;
        e.m = to_start_[B.triangle];
        e.b = map_point(e.m, B.grid);
        return true;
    }
    for (const std::uint32_t t : queue_)
        for (std::size_t k = 0; k < 3; ++k)
            if (in_.triangles[t][k] == cone_b) {
                const auto& uv = in_.uvs[3 * t + k];
                e.m = to_start_[t];
                e.b = map_point(e.m, {static_cast<std::int64_t>(std::nearbyint(uv[0])),
                                      static_cast<std::int64_t>(std::nearbyint(uv[1]))});
                return true;
            }
    return false;
}

Anchors FaceJudge::try_anchors(const std::vector<int>& face, const std::array<double, 3>& centre) {
    // A path from an anchor that sits on a singularity, or inside a fold-over next to one, may
    // pass either way round it and turn the other corners about it. The face passes when one
    // anchor shows a unit cell. From the anchor at corner i, the paths to corners i - 1 and
    // i + 1 can only turn about corner i or about their own end, which keeps their distance to
    // corner i: so each edge is judged from its own ends, and only the cell's shape depends on
    // the way round.
    Anchors a;
    for (int attempt = 0; attempt < 5 && !a.cell; ++attempt) {
        const auto i = static_cast<std::size_t>(attempt);
        const std::uint32_t tc = attempt < 4 ? loc_[static_cast<std::size_t>(face[i])].triangle
                                             : map_.surface.locate(centre).triangle; // the triangle under the centre
        if (!transport(face, tc)) continue;
        if (!a.reached_all) a.first = g_, a.first_anchor = tc;
        a.reached_all = true;
        a.cell = is_cell(g_);
        if (attempt < 4) {
            for (std::size_t e : {i, (i + 3) % 4}) { // edges (i, i+1) and (i-1, i)
                a.edge_seen[e] = true;
                a.edge_ok[e] = a.edge_ok[e] || unit_step(g_[e], g_[(e + 1) % 4]);
            }
        }
    }
    return a;
}

void FaceJudge::report(std::size_t f, const std::string& msg, bool certified, VerifyResult& r,
                       std::vector<Violation>& out) const {
    // A path across a fold-over, or through the fan of a singular vertex (it passes the
    // singularity on one side, the iso-lines perhaps on the other), does not fix the chart it
    // arrives in, nor does a corner next to a fold-over; nor does a shortest path that no
    // corridor of the face's edges certifies (it may pass a cone on the other side): a failure
    // there is undecided, not a violation.
    // A corner in a fold-over region, where a repaired map may differ from the given one, is on
    // no grid point the given map decides: the face is judged on the surface only.
    if (!through_fold_ && !through_singular_ && !corner_near_fold_ && !corner_in_region_ && certified)
        add_capped(out, ViolationKind::FaceNotGridCell, msg, static_cast<std::int64_t>(f));
    else
        add_capped(r.undecided, ViolationKind::FaceNotGridCell,
                   msg + (corner_in_region_   ? " (a corner lies in a fold-over region of the map)"
                          : through_fold_     ? " (the paths cross fold-overs of the map)"
                          : corner_near_fold_ ? " (a corner lies next to a fold-over of the map)"
                          : through_singular_ ? " (the paths pass through the fan of a singularity)"
                                              : " (no path along the face's edges certifies it)"),
                   static_cast<std::int64_t>(f));
}

void FaceJudge::judge(std::size_t f, VerifyResult& r, std::vector<Violation>& out) {
    const auto& face = mesh_.faces[f];
    if (face.size() != 4) return; // reported as NotQuad
    std::array<double, 3> centre{0, 0, 0};
    for (int v : face) {
        const auto vi = static_cast<std::size_t>(v);
        if (v < 0 || vi >= loc_.size() || !loc_[vi].ok) return; // its vertices are reported already
        for (int d = 0; d < 3; ++d) centre[d] += 0.25 * mesh_.positions[vi][d];
    }
    through_fold_ = through_singular_ = corner_in_region_ = false;
    for (int v : face) corner_in_region_ = corner_in_region_ || loc_[static_cast<std::size_t>(v)].surface_only;
    const Anchors a = try_anchors(face, centre);
    if (a.cell) return;
    corner_near_fold_ = false;
    for (int v : face) corner_near_fold_ = corner_near_fold_ || near_fold(loc_[static_cast<std::size_t>(v)].triangle);
    if (!a.reached_all) {
        report(f,
               "face " + std::to_string(f) + ": its corners lie too far apart on the input surface to be one grid cell",
               true, r, out);
        return;
    }
    // Each edge carried through its corridor (a path homotopic to the edge, or none).
    std::array<Edge, 4> along{};
    std::array<bool, 4> certified{};
    for (std::size_t e = 0; e < 4; ++e) certified[e] = along_edge(face[e], face[(e + 1) % 4], along[e]);
    auto grid_of = [&](std::size_t i) { return loc_[static_cast<std::size_t>(face[i])].grid; };
    bool edges_ok = true;
    for (std::size_t e = 0; e < 4; ++e) {
        const bool unit = certified[e] && unit_step(grid_of(e), along[e].b);
        if (a.edge_seen[e] && !a.edge_ok[e] && !unit) {
            edges_ok = false;
            report(f,
                   "face " + std::to_string(f) + ": its edge from vertex " + std::to_string(face[e]) + " to vertex " +
                       std::to_string(face[(e + 1) % 4]) + " does not join neighbouring grid points",
                   certified[e], r, out);
        }
    }
    if (!edges_ok) return;
    // Every edge judged is a unit step (none is judged when only the centre's anchor reached all
    // four corners), but no anchor shows one cell. The corridors certify the cell when all four
    // do, no corner is a cone, and the transitions around the face compose to the identity:
    // then its corners in the chart of corner 0's triangle are the answer.
    bool cell_certified = true;
    Transition around{};
    Quad q{};
    q[0] = grid_of(0);
    for (std::size_t e = 0; e < 4 && cell_certified; ++e) {
        cell_certified = certified[e] && !along[e].b_on_cone;
        if (e < 3 && cell_certified) q[e + 1] = map_point(around, along[e].b);
        cell_certified = cell_certified && compose(around, along[e].m, around);
    }
    cell_certified = cell_certified && same(around, Transition{});
    if (cell_certified && is_cell(q)) return; // the corridors show one unit cell
    report(f,
           "face " + std::to_string(f) + ": its corners are the grid points " + point(a.first[0]) + " " +
               point(a.first[1]) + " " + point(a.first[2]) + " " + point(a.first[3]) +
               " in the chart of input triangle " + std::to_string(a.first_anchor) +
               ", not a counter-clockwise unit cell",
           cell_certified, r, out);
}

} // namespace

void check_face_cells(const LocatedMap& map, const QuadMesh& mesh, const std::vector<Located>& loc, VerifyResult& r,
                      std::vector<Violation>& out) {
    FaceJudge judge(map, mesh, loc);
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) judge.judge(f, r, out);
}

} // namespace qex::verify_detail

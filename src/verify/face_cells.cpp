// The face check (face_cells.h): per face, its corners carried into the chart of each anchor in
// turn by a shortest-path search; where no anchor shows a unit cell, each edge judged through its
// corridor, and the failure reported as a violation or, where a path or corner touched a
// fold-over or a singular fan, as undecided.
#include "face_cells.h"
#include "grid.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <string>

namespace qex::verify_detail {
namespace face_cells {
namespace {

/// a and b are neighbouring grid points (and not far).
bool unit_step(const GridPoint& a, const GridPoint& b) {
    for (int k = 0; k < 2; ++k)
        if (a[k] <= -kFar || a[k] >= kFar || b[k] <= -kFar || b[k] >= kFar) return false;
    return std::llabs(a[0] - b[0]) + std::llabs(a[1] - b[1]) == 1;
}

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

/// The grid point as "(u, v)".
std::string point(const GridPoint& g) { return "(" + std::to_string(g[0]) + ", " + std::to_string(g[1]) + ")"; }

/// Whether the corridors of a face's four edges (`along`, `certified`) certify its cell: all four
/// do, no corner is a cone, and the transitions around the face compose to the identity; then
/// its corners in the chart of corner 0's triangle (whose grid point is g0), into q, are the
/// answer.
bool corridor_cell(const GridPoint& g0, const std::array<Edge, 4>& along, const std::array<bool, 4>& certified,
                   Quad& q) {
    bool cell_certified = true;
    Transition around{};
    q[0] = g0;
    for (std::size_t e = 0; e < 4 && cell_certified; ++e) {
        cell_certified = certified[e] && !along[e].b_on_cone;
        if (e < 3 && cell_certified) q[e + 1] = map_point(around, along[e].b);
        cell_certified = cell_certified && compose(around, along[e].m, around);
    }
    return cell_certified && same(around, Transition{});
}

} // namespace

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
    out_of_budget_ = out_of_budget_ || (missing > 0 && settled >= budget_);
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
                          : out_of_budget_    ? ""
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
    through_fold_ = through_singular_ = corner_in_region_ = out_of_budget_ = false;
    for (int v : face) corner_in_region_ = corner_in_region_ || loc_[static_cast<std::size_t>(v)].surface_only;
    const Anchors a = try_anchors(face, centre);
    if (a.cell) return;
    corner_near_fold_ = false;
    for (int v : face) corner_near_fold_ = corner_near_fold_ || near_fold(loc_[static_cast<std::size_t>(v)].triangle);
    if (!a.reached_all) {
        // Not connected at all is a violation; not reached within the search's budget is open.
        report(f,
               "face " + std::to_string(f) + ": its corners lie too far apart on the input surface to be one grid cell" +
                   (out_of_budget_ ? " (the search for them ran out of its budget of triangles)" : ""),
               !out_of_budget_, r, out);
        return;
    }
    // Each edge carried through its corridor (a path homotopic to the edge, or none).
    std::array<Edge, 4> along{};
    std::array<bool, 4> certified{};
    for (std::size_t e = 0; e < 4; ++e) certified[e] = along_edge(face[e], face[(e + 1) % 4], along[e]);
    if (!report_edges(f, a, along, certified, r, out)) return;
    // Every edge judged is a unit step (none is judged when only the centre's anchor reached all
    // four corners), but no anchor shows one cell.
    Quad q{};
    const bool cell_certified = corridor_cell(loc_[static_cast<std::size_t>(face[0])].grid, along, certified, q);
    if (cell_certified && is_cell(q)) return; // the corridors show one unit cell
    report(f,
           "face " + std::to_string(f) + ": its corners are the grid points " + point(a.first[0]) + " " +
               point(a.first[1]) + " " + point(a.first[2]) + " " + point(a.first[3]) +
               " in the chart of input triangle " + std::to_string(a.first_anchor) +
               ", not a counter-clockwise unit cell",
           cell_certified, r, out);
}

bool FaceJudge::report_edges(std::size_t f, const Anchors& a, const std::array<Edge, 4>& along,
                             const std::array<bool, 4>& certified, VerifyResult& r, std::vector<Violation>& out) const {
    const auto& face = mesh_.faces[f];
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
    return edges_ok;
}

} // namespace face_cells

void check_face_cells(const LocatedMap& map, const QuadMesh& mesh, const std::vector<Located>& loc, VerifyResult& r,
                      std::vector<Violation>& out) {
    face_cells::FaceJudge judge(map, mesh, loc);
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) judge.judge(f, r, out);
}

} // namespace qex::verify_detail

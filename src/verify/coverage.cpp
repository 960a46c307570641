// The located mode's coverage check (coverage.h says what it decides): its run, from the
// vertices' claims and the triangles' required cells to the reports of the grid points and cells
// no vertex or face covers; and how far each input triangle lies from the map's fold-overs.
#include "coverage.h"
#include "parallel.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <map>
#include <string>

namespace qex::verify_detail {
namespace coverage {
namespace {

/// The grid point as "(u, v)".
std::string point(const GridPoint& g) { return "(" + std::to_string(g[0]) + ", " + std::to_string(g[1]) + ")"; }

/// The numbers, separated by spaces.
std::string list(const std::vector<std::int64_t>& xs) {
    std::string s;
    for (std::size_t i = 0; i < xs.size(); ++i) s += (i ? " " : "") + std::to_string(xs[i]);
    return s;
}

} // namespace

void Coverage::run(VerifyResult& r, std::vector<Violation>& out, std::vector<FaceCell>& uncovered) {
    claim_grid_points();
    double cells = 0;
    const std::vector<std::uint32_t> triangles = triangles_to_enumerate(r, cells);
    const Uncovered u = sort_out(enumerate_all(triangles, cells, r));
    report_points(u, r, out, uncovered);
    report_cells(u, r, out, uncovered);
}

std::vector<std::uint32_t> Coverage::triangles_to_enumerate(VerifyResult& r, double& cells) const {
    const std::size_t nt = in_.triangles.size();
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
    cells = most - budget;
    return triangles;
}

std::vector<Found> Coverage::enumerate_all(const std::vector<std::uint32_t>& triangles, double cells,
                                           VerifyResult& r) const {
    // Each thread its triangles' cells (in parallel from as many cells as the other loops'
    // elements); the cells without a face, in triangle order.
    const std::size_t nt = in_.triangles.size();
    const auto count = static_cast<std::int64_t>(triangles.size());
    const int threads = run_parallel(threads_, static_cast<std::int64_t>(cells)) ? threads_ : 1;
    std::vector<std::vector<Found>> part(static_cast<std::size_t>(threads));
    std::vector<std::int64_t> required(static_cast<std::size_t>(threads), 0);
    share_chunks(threads, count, 256, [&](std::size_t me, const auto& next) {
        Scratch scratch(nt);
        for (std::int64_t from = 0, to = 0; next(from, to);)
            for (std::int64_t i = from; i < to; ++i)
                required[me] += enumerate(triangles[static_cast<std::size_t>(i)], scratch, part[me]);
    });
    r.coverage_cells = 0;
    for (const std::int64_t n : required) r.coverage_cells += n;
    std::vector<Found> found;
    for (auto& p : part) found.insert(found.end(), p.begin(), p.end());
    std::sort(found.begin(), found.end(), [](const Found& a, const Found& b) { return a.cell.cell < b.cell.cell; });
    return found;
}

Uncovered Coverage::sort_out(const std::vector<Found>& found) const {
    // Uncovered grid points (by their canonical key) with the required cells at them, and cells
    // whose corners are vertices but no face (by their corner vertices) with their undecided mark.
    Scratch scratch(in_.triangles.size());
    Uncovered u;
    std::map<std::array<std::int32_t, 4>, bool> cell_seen;
    for (const Found& f : found) {
        const RequiredCell& cell = f.cell;
        const auto& at = f.at;
        if (!f.all) {
            for (std::size_t i = 0; i < 4; ++i) {
                if (at[i].first != at[i].second) continue;
                const Key k = canonical(cell.corner[i], scratch);
                auto& at_point = u.points[k];
                if (at_point.empty()) u.point_order.push_back(k);
                if (std::find(at_point.begin(), at_point.end(), cell.cell) == at_point.end())
                    at_point.push_back(cell.cell);
            }
            continue;
        }
        // Every corner is a vertex, but no face joins them: one report per set of corners;
        // undecided where a corner's vertices all lie in a fold-over region or cannot be placed by
        // their precision (soft claims).
        const bool soft = soft_corner(at);
        std::array<std::int32_t, 4> vertices;
        for (std::size_t i = 0; i < 4; ++i) vertices[i] = at[i].first->vertex;
        std::array<std::int32_t, 4> id = vertices;
        std::rotate(id.begin(), std::min_element(id.begin(), id.end()), id.end());
        if (!cell_seen.emplace(id, true).second) continue;
        u.cells.push_back({cell, vertices, soft});
    }
    return u;
}

bool Coverage::soft_corner(const std::array<std::pair<const Claim*, const Claim*>, 4>& at) const {
    bool soft = false;
    for (std::size_t i = 0; i < 4; ++i) {
        bool firm = false;
        for (const Claim* c = at[i].first; c != at[i].second; ++c) {
            const Located& L = loc_[static_cast<std::size_t>(c->vertex)];
            firm = firm || !(L.surface_only || L.undecided);
        }
        soft = soft || !firm;
    }
    return soft;
}

void Coverage::report_points(const Uncovered& u, VerifyResult& r, std::vector<Violation>& out,
                             std::vector<FaceCell>& uncovered) const {
    for (const Key& k : u.point_order) {
        const std::vector<Key>& at = u.points.at(k);
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
}

std::vector<std::int64_t> Coverage::faces_in_place(const std::array<std::int32_t, 4>& vertices) const {
    std::map<std::int64_t, int> hits;
    for (const std::int32_t v : vertices)
        for (std::size_t i = face_start_[static_cast<std::size_t>(v)]; i < face_start_[static_cast<std::size_t>(v) + 1];
             ++i)
            ++hits[around_[i].face];
    std::vector<std::int64_t> faces;
    for (const auto& [f, n] : hits)
        if (n >= 2) faces.push_back(f);
    return faces;
}

void Coverage::report_cells(const Uncovered& u, VerifyResult& r, std::vector<Violation>& out,
                            std::vector<FaceCell>& uncovered) const {
    for (const Uncovered::Missing& m : u.cells) {
        const Key& k = m.cell.cell;
        std::vector<std::int64_t> vertices(m.vertices.begin(), m.vertices.end());
        // The faces at two or more of its corners: what the mesh has in its place.
        const std::vector<std::int64_t> faces = faces_in_place(m.vertices);
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

} // namespace coverage

std::vector<char> far_from_fold_overs(const Input& in, const InputEdges& edges, const std::vector<char>& fold_over,
                                      const std::vector<char>& near_rings) {
    using coverage::kFoldReach, coverage::norm, coverage::P2;
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
    coverage::Coverage(map, mesh, loc, far_from_folds, uv_tolerance, threads).run(r, out, uncovered);
}

} // namespace qex::verify_detail

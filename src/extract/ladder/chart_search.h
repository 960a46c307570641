// Finding grid points on a map a mesh was not extracted from: a breadth-first search over the
// map's triangles that carries each one's transition, and where a grid point it finds lies on the
// input. Shared by place_on_given_map, preimages (for separate_sheets) and split_onto_map.
#pragma once

#include "../pipeline.h"

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

namespace qex::detail {

/// Breadth-first search over the live triangles of the given map `g` (its transitions computed),
/// crossing edges with their transitions (not edges next to a collapsed triangle), each
/// triangle's neighbours in canonical order; every listed triangle carries the transition from
/// the search's chart to its own.
class ChartSearch {
public:
    explicit ChartSearch(const TriMesh& g)
        : g_(g),
          stamp_(static_cast<std::size_t>(g.num_faces()), 0),
          to_(static_cast<std::size_t>(g.num_faces())),
          order_(static_cast<std::size_t>(g.num_faces()), {-1, -1, -1}) {}

    /// A triangle that holds `grid` (in the chart of triangle `start`): the first positive one
    /// found, else the first flipped one; -1 if none is found or `start` is not a live triangle.
    int find(int start, const IPoint& grid);

    /// After find() found nothing: a listed triangle that holds `grid` in the chart of another
    /// listed neighbour than the one the search entered it from (a path round a singularity the
    /// other way, which the search, listing each triangle once, did not take), positive before
    /// flipped, in the order listed and its edges' canonical order; its transition in `to`. -1 if
    /// none.
    int find_round_singularities(const IPoint& grid, GridAutomorphism& to) const;

    /// Every triangle the search lists (up to its budget) that holds `grid` (in the chart of
    /// triangle `start`), each with `grid` in its own chart: the positive ones in the order
    /// listed, then the flipped ones.
    std::vector<std::pair<int, IPoint>> find_all(int start, const IPoint& grid);

    /// Lists the triangles of a grid cell, the open box (lo, hi) in the seeds' chart: those that
    /// meet it and are reached from the seeds through such triangles. Kept inside the cell, the
    /// search cannot wind round a singularity at one of its corners into another sheet. False
    /// past the budget.
    bool cell(const std::vector<std::pair<int, GridAutomorphism>>& seeds, const IPoint& lo, const IPoint& hi);
    bool listed(int t) const { return stamp_[static_cast<std::size_t>(t)] == generation_; }
    /// The transition from the chart of the last search's start to that of triangle t (listed by it).
    const GridAutomorphism& to(int t) const { return to_[static_cast<std::size_t>(t)]; }
    const std::vector<int>& triangles() const { return queue_; }

    /// Every listed triangle that holds q (the search's chart): positive ones first, in order.
    std::vector<int> holders(const IPoint& q) const;

private:
    static constexpr std::size_t kMaxSearchTriangles = 4096; ///< find() stops listing here
    static constexpr std::size_t kMaxCellTriangles = std::size_t{1} << 16;
    struct Box {
        IPoint lo, hi;
    };

    /// Whether triangle t survived the collapses (its UVs are not NaN).
    bool alive(int t) const;
    void begin() {
        ++generation_;
        queue_.clear();
    }
    /// Lists t, reached with transition `to`, unless it is listed, collapsed, or (with a box)
    /// misses the box.
    void enter(int t, const GridAutomorphism& to, const Box* box);
    /// Lists t's neighbours, in canonical order, so that which path reaches a triangle first (and
    /// so its transition past a singularity), and which preimage is found first, do not depend on
    /// the input's order.
    void expand(int t, const Box* box);

    const TriMesh& g_;
    std::vector<std::uint32_t> stamp_; ///< per triangle: the search that listed it last
    std::vector<GridAutomorphism> to_; ///< per triangle: chart of the start -> its chart
    std::vector<int> queue_;           ///< the listed triangles, in the order listed
    /// Per triangle, its edges in canonical order (-1: not computed yet). The order depends on
    /// the triangle alone, and the searches expand each triangle many times.
    std::vector<std::array<std::int8_t, 3>> order_;
    std::uint32_t generation_ = 0;
};

/// The provenance of grid point q (in the chart of triangle `found` of the given map `g`) in
/// that triangle: on a corner, on an edge, or inside.
Provenance located(const Input& input, const TriMesh& g, int found, const IPoint& q, int merged);

/// The 3D position of a provenance from located(): the input vertex's own position on a corner,
/// else the barycentric combination of its triangle's corners.
std::array<double, 3> position_of(const Input& input, const Provenance& p);

} // namespace qex::detail

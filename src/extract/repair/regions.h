// The repair's regions (inside the subsystem only; its door is repair.h): the fan of a free
// vertex, a region of free vertices and its triangles, canonical vertex keys, and how the
// regions round the fold-overs are found (regions.cpp).
#pragma once

#include "extract/pipeline.h"

#include <array>
#include <vector>

namespace qex::detail::repair_impl {

using Vec2 = std::array<double, 2>;

/// Whether triangle f is positively oriented, by the exact predicate.
inline bool positive(const TriMesh& m, int f) {
    return sign(orient2d(m.uv[3 * f], m.uv[3 * f + 1], m.uv[3 * f + 2])) > 0;
}

// ============================================================================ a free vertex

/// A free vertex's fan, starting at a canonical corner (so the sums below do not depend on the
/// input's order), with the transitions from the first corner's chart to each corner's.
struct FreeFan {
    int vertex = -1;
    std::vector<int> corners;
    std::vector<GridAutomorphism> to_c;
    double length = 1.0; ///< mean UV edge length around the vertex, the scale of its steps
};

/// Free vertex v's fan, from the canonical corner, and its mean UV edge length.
FreeFan free_fan(const TriMesh& m, int v);

/// The corners of interior vertex v's fan, clockwise from the one whose next and previous
/// corners have the smallest 3D positions: an order that depends neither on the input's order
/// nor on its charts.
std::vector<int> fan_in_3d_order(const TriMesh& m, int v);

/// Writes x (in the fan's first chart), truncated so that it propagates exactly, to every corner;
/// with a unit of headroom, so that the map times a power of two k, plus an integer point below
/// k, stays exact too (coarsening splits its mesh back onto that map).
void place(TriMesh& m, const FreeFan& fan, const Vec2& x);

// ============================================================================ a region

struct Region {
    /// Canonical order once made (make_fans). Before, as find_regions lists them, only each fan's
    /// vertex is set, the one with the smallest key first.
    std::vector<FreeFan> fans;
    std::vector<int> faces; ///< canonical order
};

/// Makes r's fans, in canonical order, from the vertices find_regions listed; nothing where they
/// are made. They read the UVs of r's triangles, as they are when it is called.
void make_fans(const TriMesh& m, Region& r);

/// The UVs of the region's free corners, fan by fan (restore_region_uvs puts them back).
std::vector<Point2> region_uvs(const TriMesh& m, const Region& r);

/// Puts back the UVs region_uvs took.
void restore_region_uvs(TriMesh& m, const Region& r, const std::vector<Point2>& uvs);

/// The canonical key of a vertex: its smallest corner position in 3D, then its input index.
struct VertexKey {
    std::array<double, 3> pos;
    int input;
    bool operator<(const VertexKey& o) const { return pos != o.pos ? pos < o.pos : input < o.input; }
};

/// The canonical key of vertex v.
VertexKey vertex_key(const TriMesh& m, int v);

// ============================================================================ finding the regions

/// Vertices that never move: boundary, singular, on a feature edge, or without a fan.
std::vector<char> pinned_vertices(const TriMesh& m, const std::vector<std::array<int, 2>>& feature_edges);

/// The vertices within `radius` edges of the seeds (breadth first over the fans).
std::vector<int> ring_neighbourhood(const TriMesh& m, const std::vector<int>& seeds, int radius,
                                    std::vector<int>& distance);

/// Splits the free vertices into regions connected through shared triangles: each with its
/// triangles in canonical order and its free vertices listed, their fans not made (make_fans).
/// The fans are most of the cost, and a region the room certificate refuses needs none of them.
std::vector<Region> find_regions(const TriMesh& m, const std::vector<int>& free, std::vector<int>& label);

/// find_regions with every region's fans made.
std::vector<Region> split_regions(const TriMesh& m, const std::vector<int>& free, std::vector<int>& label);

/// The free vertices of r within `rings` triangles of its inverted ones (not positive by the
/// exact predicate), as a region of their own: their fans as r has them, and r's triangles
/// round them, both in r's canonical order (the untangler's local mend).
Region around_inverted(const TriMesh& m, const Region& r, int rings);

/// The flipped or degenerate triangles, split into those with a free vertex (seeds of the
/// repair) and those whose corners are all pinned (no repair can change them).
void bad_triangles(const TriMesh& m, const std::vector<char>& pinned, std::vector<int>& repairable,
                   std::vector<int>& stuck);

/// bad_triangles' two lists split again by a new `pinned`, where no triangle's sign changed
/// (as bad_triangles would split them, without its scan of every triangle).
void split_again(const TriMesh& m, const std::vector<char>& pinned, std::vector<int>& repairable,
                 std::vector<int>& stuck);

/// Connected groups (through shared vertices) of the given triangles, for the report.
std::vector<std::vector<int>> triangle_groups(const TriMesh& m, const std::vector<int>& faces);

} // namespace qex::detail::repair_impl

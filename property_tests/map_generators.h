// Test-only generators of exact integer-grid maps with known structure, and perturbations.
//
// A map is built from a quad *layout* (a coarse closed or bounded quad mesh): every layout quad
// becomes an n x n block of grid quads in its own chart [0,n]^2, sampled by a k x k lattice of
// triangle vertices. Layout vertices of valence v != 4 become singularities of valence v.
#pragma once

#include "qex/qex.h"

#include <array>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace qex::testing {

struct QuadLayout {
    std::string name;
    std::vector<std::array<double, 3>> positions;
    std::vector<std::array<int, 4>> quads; ///< counter-clockwise
};

/// Each polygon split into quads around its centre (one Catmull-Clark topology step).
QuadLayout split_polygons(const std::string& name, const std::vector<std::array<double, 3>>& positions,
                          const std::vector<std::vector<int>>& polygons);

QuadLayout torus_layout(int nu = 4, int nv = 3);   ///< genus 1, all valence 4
QuadLayout cube_layout();                          ///< 8 singularities of valence 3
QuadLayout icosahedron_layout();                   ///< valence 5 (and 3)
QuadLayout prism_layout(int sides);                ///< valence `sides` at the cap centres
QuadLayout disk_layout(int n = 3);                 ///< a grid with one boundary loop
QuadLayout annulus_layout(int nu = 6, int nv = 2); ///< two boundary loops

/// The exact integer-grid map of a layout. `n` grid quads per layout edge; `k` lattice steps per
/// layout edge (k = n: vertices on grid points and edges along iso-lines; k coprime to n: general
/// position). `diagonals`: 0 all one way, 1 alternating, 2 random (with `seed`).
/// `single_chart`, if given, marks the vertices strictly inside one layout quad (all their corners
/// share one chart; only those may be moved by displace_vertex).
Input make_map(const QuadLayout& layout, int n, int k, int diagonals = 1, std::uint32_t seed = 1,
               std::vector<char>* single_chart = nullptr);

/// Expected number of quads of make_map: quads * n^2.
std::int64_t expected_quads(const QuadLayout& layout, int n);

// ---------------------------------------------------------------------------- perturbations

/// Re-charts every triangle by a random grid automorphism (every edge becomes a cut).
void rechart(Input& in, std::mt19937& rng, std::int64_t max_translation = 1000);
/// Randomly renumbers vertices, reorders triangles and rotates the corner order in each.
void shuffle(Input& in, std::mt19937& rng);
/// Adds an integer translation to all UVs.
void translate(Input& in, std::int64_t dx, std::int64_t dy);
/// Rotates all UVs by r * 90 degrees.
void rotate(Input& in, int r);
/// Adds uniform noise of magnitude `eps` to every corner UV independently.
void add_noise(Input& in, double eps, std::mt19937& rng);
/// Moves one vertex by (dx, dy) in all its corners, which must share one chart (see make_map);
/// returns the number of flipped triangles afterwards, or -1 if the corners' UVs differ.
std::int64_t displace_vertex(Input& in, int vertex, double dx, double dy);
/// The map as OBJ text (v, one vt per corner, f a/ta b/tb c/tc), UVs with 17 digits.
std::string to_obj(const Input& in);
/// 1-to-4 midpoint subdivision with linearly interpolated per-corner UVs (the map is unchanged).
Input subdivide(const Input& in);
/// Counts triangles with negative UV area.
std::int64_t count_flipped(const Input& in);
/// Splits triangle f by a new vertex placed at corner `corner`'s UV (in 3D at the centroid):
/// the new vertex and that corner's vertex are joined by an edge of zero UV length.
void insert_collapsed_edge(Input& in, int f, int corner);

} // namespace qex::testing

namespace qex::testing {
/// Splits triangle f by a new vertex whose UV lies on the segment between two of its corners
/// (the midpoint of corners `corner` and `corner`+1), so one sub-triangle has zero UV area.
void insert_zero_area_triangle(Input& in, int f, int corner);
} // namespace qex::testing

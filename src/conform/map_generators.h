// Generators of exact integer-grid maps with known structure, and perturbations: the property
// tests' and `qex conform`'s known and hostile cases (src/conform/README.md).
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

namespace qex::gen {

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

} // namespace qex::gen

namespace qex::gen {
/// Splits triangle f by a new vertex whose UV lies on the segment between two of its corners
/// (the midpoint of corners `corner` and `corner`+1), so one sub-triangle has zero UV area.
void insert_zero_area_triangle(Input& in, int f, int corner);

// ---------------------------------------------------------------------------- large fold-overs
//
// Folds of any size, through the charts: a vertex's corners in different charts move by one
// displacement turned into each chart. The charts of neighbouring triangles are matched by the
// quarter turn that best maps their shared edge (so noisy maps work too); a vertex whose charts
// compose to the identity around it moves consistently, and the map keeps its signed UV area.

/// The interior vertices whose fan is not a regular vertex's: its charts compose to a turn, or
/// its UV angle sum is not one full turn (a singularity of valence 4k != 4, or a vertex already
/// pushed out of its neighbours' polygon). Sorted.
std::vector<int> singular_vertices(const Input& in);

/// Moves the vertex of corner `corner` (3f + k) by (dx, dy) in the chart of that corner, and its
/// other corners by the same displacement turned into their charts. Only an interior vertex whose
/// charts compose to the identity around it, with angle sum one turn or none (a pushed-out vertex),
/// moves. Returns the number of flipped triangles afterwards, or -1 (nothing moved) for any other.
std::int64_t displace_vertex_in_charts(Input& in, std::size_t corner, double dx, double dy);

/// How fold_patch moves the points of the plane, in the centre's chart (a, b: its parameters).
enum class PatchMotion {
    Translate, ///< by (a, b)
    Twist,     ///< about the centre by the angle a (radians) times (1 - ring / (rings + 1))
    Mirror,    ///< across the line through the centre at the angle a (turns the patch inside out)
    Expand,    ///< about the centre by the factor a (negative: through the centre)
};

/// Moves the vertices within `rings` edges of `centre` by `motion`, each as
/// displace_vertex_in_charts moves it (singular and boundary vertices stay). Points are carried
/// from the centre's chart into each vertex's along the triangles, and every displacement is
/// rounded to a multiple of 2^-12 (so a vertex moves by the same in all its charts, exactly, while
/// its UVs are below 2^40). Returns the number of flipped triangles afterwards, or -1 if no vertex
/// moved.
std::int64_t fold_patch(Input& in, int centre, int rings, PatchMotion motion, double a, double b = 0.0);

/// Squeezes the fan of the interior vertex `v` in the parameter domain: walking round v from one
/// of its triangles, every neighbour at developed angle A (0 <= A <= the fan's angle sum) is moved
/// to angle A / `factor`, at the same distance, in every chart that holds it. Turning about v
/// commutes with the transitions around v, so the map stays an integer-grid map; with a factor
/// above the fan's angle sum over a half turn, the triangles beyond the squeezed ring fold over.
void squeeze_fan(Input& in, int v, double factor);
} // namespace qex::gen

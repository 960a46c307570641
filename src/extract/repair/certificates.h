// The repair's certificates (inside the subsystem only; its door is repair.h): whether a
// region's fixed data leave room for a re-embedding (Gauss-Bonnet over the angles its fixed
// vertices leave it, and the angle its rim turns about its one singularity), and whether a
// re-embedded region keeps every vertex's winding (certificates.cpp).
#pragma once

#include "extract/repair/regions.h"

#include <algorithm>
#include <vector>

namespace qex::detail::repair_impl {

/// The signed angle at corner h of its triangle (from the edge to its next corner to the edge to
/// its previous one): in (0, pi) when the triangle is positive.
double corner_angle(const TriMesh& m, int h);

/// The angle an interior vertex's fan sums to in an embedding of the map: a full turn, or a
/// singularity's valence in quarter turns.
double target_angle(const TriMesh& m, int v);

/// What the certificate needs of a region: its triangles and free vertices marked, and its
/// fixed vertices (sorted).
struct RegionMarks {
    std::vector<char> face;   ///< per triangle
    std::vector<char> vertex; ///< per vertex: 1 free in the region, 2 fixed in it
    std::vector<int> fixed;
    /// Per triangle, scratch for a region triangle's place in its list (-1 between uses).
    std::vector<int> slot;
    /// A singularity whose angle Gauss-Bonnet fixes otherwise than Algorithm 8 counted it (the
    /// fold took whole turns from its fan without flipping any), and that angle.
    int cone = -1;
    double cone_angle = 0.0;
    /// Set when the rim winds round the region's one singularity otherwise than its angle
    /// (admits_embedding): that singularity, and the angle the rim turns about it.
    int rim_cone = -1;
    double rim_angle = 0.0;
    /// Set when admits_embedding proves that no orientation-preserving map of the region keeps
    /// every vertex's winding: a fixed vertex (working index) whose fixed triangles leave the
    /// region an angle (`room_left`) outside (0, pi per region corner, `room_corners`); or, with
    /// `room_vertex` -1, the angles the fixed vertices leave it summing to `room_missing` less than
    /// pi per triangle (by a radian or more).
    bool room_proved = false;
    int room_vertex = -1, room_corners = 0;
    double room_left = 0.0, room_missing = 0.0;

    /// Sized for m, nothing marked.
    void size_for(const TriMesh& m) {
        face.assign(static_cast<std::size_t>(m.num_faces()), 0);
        vertex.assign(static_cast<std::size_t>(m.num_vertices), 0);
        slot.assign(face.size(), -1);
    }

    /// What v's angles sum to in an embedding of the region's map.
    double target(const TriMesh& m, int v) const { return v == cone ? cone_angle : target_angle(m, v); }

    /// Marks r's triangles, its free vertices and its fixed ones (collected in `fixed`).
    void mark(const TriMesh& m, const Region& r) {
        for (const int f : r.faces) face[f] = 1;
        for (const FreeFan& fan : r.fans) vertex[fan.vertex] = 1;
        for (const int f : r.faces)
            for (const int v : m.tri[f])
                if (!vertex[v]) vertex[v] = 2, fixed.push_back(v);
        std::sort(fixed.begin(), fixed.end());
    }
    /// Unmarks what mark marked, and forgets the cones.
    void clear(const Region& r) {
        for (const int f : r.faces) face[f] = 0;
        for (const FreeFan& fan : r.fans) vertex[fan.vertex] = 0;
        for (const int v : fixed) vertex[v] = 0;
        fixed.clear();
        cone = rim_cone = room_vertex = -1;
        room_proved = false;
    }
};

/// Sums the signed angles at v's corners, inside the region and outside it.
void fan_angles(const TriMesh& m, int v, const RegionMarks& marks, double& inside, double& outside, int& corners);

// ============================================================================ the room certificate

/// Whether the region's fixed data leave room for an orientation-preserving re-embedding. In one,
/// every interior vertex's angles sum to its target (a full turn, or a singularity's), so a fixed
/// vertex leaves the region its target less its fixed triangles' angles, which must lie between
/// 0 and pi per region corner; and the angles of the region's triangles sum to pi each. Where
/// these fail, no motion of the free vertices helps: the fold reaches past the region's
/// boundary (its boundary winds wrongly), and the region must grow. A region that touches the
/// mesh's boundary is judged by the first test only. When the sum misses whole turns, they are
/// those of singularities inside the region: Algorithm 8 counts a turn only for a flipped run of
/// a fan, and a fold can take one without flipping any (Figure 2 (d), the fan squeezed). With one
/// singularity inside, the turns are its own, and the region is admitted with its angle
/// corrected.
bool admits_embedding(const TriMesh& m, const Region& r, bool valences_given, RegionMarks& marks);

// ============================================================================ the winding certificate

/// Whether every interior vertex of the region (all its triangles positive) winds by its
/// target: positive triangles alone can still wind twice round a vertex (a branch point the
/// map does not have) or leave a singularity a turn short.
bool windings_kept(const TriMesh& m, const Region& r, const RegionMarks& marks);

/// By how many whole turns v's fan winds past its target (0 for a boundary vertex).
int winding_excess(const TriMesh& m, int v, const RegionMarks& marks);

} // namespace qex::detail::repair_impl

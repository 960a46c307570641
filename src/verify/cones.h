// The located mode's reading of the map's cones and fold-over footprints, for the singularity
// match (singularities.cpp): a room of the checker behind checker.h, built by cones.cpp.
#pragma once

#include "checker.h"

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace qex::verify_detail {

/// How far from a whole number of quarter turns an angle sum may be and still read as one.
inline constexpr double kQuarterTurnSlack = 0.2;

/// Most edges between two co-located singularities (on one grid point, charted along the path
/// between them): no locally injective map keeps both, a valid extraction has one vertex
/// there, or none where their turns cancel (a dipole, which qex's repair merges).
inline constexpr int kColocationReach = 8;

/// How far a footprint grows, half a cell (UV) at a time, to explain its mismatches by its sums:
/// an extractor that leaves a fold as the map gives it may move a singularity out of it, by up
/// to 2.5 cells (measured: the paper's local handling, coverage.cpp's reach of fold-overs).
inline constexpr int kFootprintGrowth = 5;
inline constexpr double kFootprintStep = 0.5;

/// A cone of the map: input vertices joined by edges shorter than the UV tolerance (an
/// extractor collapses such edges), with the fan of the triangles that have one corner in it.
struct Cone {
    double quarter_turns = 0; ///< the fan's UV angle sum (signed angles) in quarter turns
    bool interior = true;     ///< every vertex of it is interior
    /// Its fan holds a flipped or degenerate triangle, or it is `extreme`: its valence is known
    /// modulo 4 only.
    bool folded = false;
    bool extreme = false;        ///< at most one quarter turn, or eight or more
    bool iso_boundary = true;    ///< on the boundary: its boundary edges run along integer iso-lines
    std::int64_t vertex = -1;    ///< its smallest input vertex
    std::int32_t footprint = -1; ///< the fold-over footprint it lies in, or -1

    /// The valence it reads as, into n; false where the sum is not near a whole number of
    /// quarter turns (then not judged).
    bool valence(int& n) const {
        const double q = std::nearbyint(quarter_turns);
        n = static_cast<int>(q);
        return std::abs(quarter_turns - q) <= kQuarterTurnSlack && std::abs(q) < 1e6;
    }
    /// Whether `faces` faces round a vertex here match valence n (modulo 4 where folded: a fold
    /// leaves the winding known up to whole turns).
    bool matches(int faces, int n) const { return folded ? ((faces - n) % 4 + 4) % 4 == 0 : faces == n; }
    /// A singularity: interior, and a valence other than 4 (modulo 4 where folded).
    bool singular() const {
        int n = 0;
        return interior && valence(n) && !matches(4, n);
    }
    /// A corner of a boundary along iso-lines, not straight, no fold in its fan.
    bool boundary_corner() const {
        int n = 0;
        return !interior && iso_boundary && !folded && valence(n) && n != 2;
    }
};

/// A fold-over footprint, where the map is not locally injective: the vertices of flipped or
/// degenerate triangles (grouped where they share a triangle) and the cones on them, the
/// singularities off the grid or extreme, and singularities on one grid point (co-located), each group
/// joined; its triangles are those with a corner among those vertices. Inside it the map is not locally
/// injective, and an extractor that leaves the fold as the map gives it (the paper's local
/// handling) may merge or move its singularities across it: there the mesh's valences are
/// judged one by one, and where they differ, by their sum (Gauss-Bonnet on the footprint).
struct Footprint {
    std::int64_t triangles = 0;       ///< input triangles with a corner in it
    double uv_area = 0;               ///< their signed UV area (a double sum)
    std::int64_t first_triangle = -1; ///< its smallest flipped or degenerate triangle
    /// Quarter turns a fold-free map of the same rim has beyond the folded one's angle sums:
    /// per fold triangle, a half turn less its signed angle sum (4 per flipped triangle).
    double correction = 0;
    double cone_turns = 0; ///< the sum over its interior cones of (quarter turns - 4)
};

struct ConeMap {
    std::vector<std::int32_t> cone_of; ///< per input vertex its cone
    std::vector<Cone> cones;
    /// Per cone: a seed of a footprint (on a fold triangle, a singularity off the grid or
    /// co-located with another); and the pairs of co-located singularities, joined.
    std::vector<char> seed;
    std::vector<std::array<std::int32_t, 2>> links;
    std::vector<std::int32_t> footprint_of_triangle; ///< per input triangle its footprint or -1
    std::vector<Footprint> footprints;
};

/// The map's cones, their angle sums and footprints (the seeds'). `tol`: the UV tolerance
/// (seams, short edges, co-location, off the grid).
ConeMap map_cones(const LocatedMap& map, double tol);

/// The footprints again: the seeds, and every cone within `cells` (UV, along the surface) of
/// the fan of a cone `grow` names.
void regroup_footprints(const LocatedMap& map, ConeMap& k, const std::vector<char>& grow, double cells);

} // namespace qex::verify_detail

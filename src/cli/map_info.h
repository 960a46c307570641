// What `qex info` and `qex draw` know of a map before extraction: its topology, the orientation
// of every triangle in UV space (exact signs), the fold-over regions, the singularities with
// their valences and grid points, and, from a sanitizing run of the extractor, the charts after
// cutting and the largest sanitization displacement.
#pragma once

#include "qex/qex.h"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace qex::cli {

/// A connected set of flipped or degenerate triangles (sharing edges).
struct FoldRegion {
    std::vector<int> triangles;
    double uv_area = 0.0;                             ///< signed, summed in each triangle's chart
    std::array<std::int64_t, 2> grid_lo{}, grid_hi{}; ///< integer box around its UVs (charts as given)
};

struct Singularity {
    int vertex = -1;
    /// Quarter turns of the fan's signed UV angles (4: regular); in a fold, where the fan winds
    /// back, the valence closest to 4 with the fan's rotation (3, 5 or 6).
    int valence = 4;
    std::array<std::int64_t, 2> grid{};
    int triangle = -1; ///< whose chart `grid` is in
    bool in_fold = false;
};

struct MapInfo {
    std::int64_t vertices = 0, triangles = 0, edges = 0, components = 0, boundary_loops = 0, euler = 0;
    std::int64_t genus = 0; ///< sum over components of (2 - euler - boundary loops) / 2
    double signed_uv_area = 0.0;
    std::int64_t flipped = 0, degenerate = 0;
    std::vector<std::int8_t>
        orientation; ///< per triangle: +1, 0 (degenerate) or -1 (flipped), exactly (qex::uv_orientations)
    std::vector<FoldRegion> fold_regions;
    std::vector<int> region_of; ///< per triangle: its fold region, or -1
    std::vector<Singularity> singularities;
    // From a sanitizing extraction (sanitized = false if it was not run or failed):
    bool sanitized = false;
    std::int64_t charts = 0; ///< charts of the sanitized map cut along its non-identity transitions
    double max_sanitization_displacement = 0.0;
    std::int64_t sanitized_singularities = 0;
};

/// Everything but the sanitized part; the input must have passed qex::validate().
MapInfo analyse_map(const Input& input);
/// Runs the extractor once (first rung only, no fallback ladder) and fills the sanitized part from its report
/// and map; an input the extractor rejects comes back as the error.
Error add_sanitized(const Input& input, int threads, MapInfo& info);

} // namespace qex::cli

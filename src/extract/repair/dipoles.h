// The repair's co-located dipoles (inside the subsystem only; its door is repair.h): two
// singularities of opposite index on one grid point, which no fold-free map allows, merged into
// regular vertices before the regions are grown, and the merge undone unless the repair
// re-embeds it (dipoles.cpp).
#pragma once

#include "extract/repair/regions.h"

#include <array>
#include <utility>
#include <vector>

namespace qex::detail::repair_impl {

/// A pair of singularities merged into regular vertices: the path of half-edges between them
/// (each from a vertex to the next) and their transitions before the merge.
struct DipoleMerge {
    int a = -1, b = -1;
    std::vector<int> path;
    std::vector<GridAutomorphism> old;
    std::array<int, 2> valences{0, 0}, winding_valences{0, 0};
};

/// Merges the co-located dipoles next to the fold-overs, trying each singularity next to a
/// flipped or degenerate triangle in the order of its vertex key: the merges made (their
/// singularities are regular vertices now). `scratch_a` and `scratch_b`: per-vertex, all -1, left so.
std::vector<DipoleMerge> merge_colocated_dipoles(TriMesh& m, const std::vector<char>& pinned, std::vector<int>& scratch_a,
                                                 std::vector<int>& scratch_b);

/// Each half-edge on the merges' paths and its opposite once, by half-edge, with its transition
/// before the first merge that changed it (the merges in the order made: a later one's old
/// transitions may be an earlier one's).
std::vector<std::pair<int, GridAutomorphism>> transitions_before_merges(const TriMesh& m,
                                                                        const std::vector<DipoleMerge>& merges);

/// Whether merge `d` stands: every vertex of its path was re-embedded by a certified region
/// (`reembedded`, per vertex), and the path's UVs agree with its new transitions.
bool merge_reembedded(const TriMesh& m, const DipoleMerge& d, const std::vector<char>& reembedded);

/// Undoes the merges that do not stand (in reverse order: a later path may run along an
/// earlier one's edges), and names each one that does in report.explanations.
void settle_merges(TriMesh& m, const std::vector<DipoleMerge>& merges, const std::vector<char>& reembedded,
                   Report& report);

/// The map along the merges' paths: their transitions (both ways) and their singularities' flags
/// and valences, as merges_state found them; restore_merges puts them back (after a look at the
/// map with settle_merges done).
struct MergesState {
    std::vector<GridAutomorphism> transitions;
    std::vector<int> vertex;
};
MergesState merges_state(const TriMesh& m, const std::vector<DipoleMerge>& merges);
void restore_merges(TriMesh& m, const std::vector<DipoleMerge>& merges, const MergesState& state);

} // namespace qex::detail::repair_impl

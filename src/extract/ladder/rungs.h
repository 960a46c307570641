// The rungs of the fallback ladder, for the files that run them: ladder.cpp (a rung's map,
// stages and verdict), at_scale.cpp (the ladder at one scale: which rungs run, in what order,
// and which mesh stands) and losses.cpp (which lost faces a proof backs).
#pragma once

#include "ladder.h"

#include <array>
#include <vector>

namespace qex::detail {

// ============================================================================ the rungs

/// A rung of the fallback ladder: how it prepares the map before the pipeline's stages run on
/// it. Each rung re-runs the pipeline from the validated, collapsed mesh.
struct Rung {
    const char* name;   ///< its name in Report::rung
    bool repair;        ///< stage repair runs (certified: the mesh carries the repaired map)
    int untangle_rings; ///< > 0: stage untangle relaxes the map first (uncertified)
    int untangle_iterations;
};

/// The fallback ladder: its rungs in the order extract_at_scale tries them, until the checker
/// accepts one's mesh. The certified rungs come first. Every later rung changes only the
/// flipped and degenerate regions of the map, so on a map without any the first verdict stands.
inline constexpr Rung kLadder[] = {
    // 1. The sanitized map with its fold-over regions re-embedded (certified), then the paper's
    //    method. First: on a map without fold-overs it is the paper's method on the map as given
    //    (reported as the as-given rung), and on one with fold-overs the repair's certificate
    //    lets the checker verify the mesh against the repaired map.
    {"repaired", true, 0, 0},
    // 2. The paper's method, and its local handling of fold-overs, on the map as given. Second:
    //    where the repaired map's mesh is rejected, the paper's own handling may still give a
    //    valid one. Skipped when the repair changed nothing (rung 1 was this rung); the first
    //    rung without Options::repair_fold_overs.
    {"as-given", false, 0, 0},
    // 3, 4. Last resorts without a certificate: relax the folded regions (one ring, then three),
    //    extract, and move the mesh back onto the given map, where the checker must accept it.
    //    Last: they need the as-given rung's sanitized map to move the mesh onto, and their mesh
    //    must pass the checker against it everywhere; one ring first, as it moves the fewest
    //    vertices.
    {"untangled-1", false, 1, 30},
    {"untangled-3", false, 3, 100},
};

/// The as-given rung: the first without Options::repair_fold_overs, and the one whose sanitized
/// map the relaxed rungs' meshes are moved onto and coarsening divides.
inline constexpr int kAsGiven = 1;
static_assert(!kLadder[kAsGiven].repair && kLadder[kAsGiven].untangle_rings == 0, "the map as given");

/// The fold-overs a rung's repair left: per working triangle its fold-over (-1: none), and per
/// fold-over its smallest input triangle and whether a proof backs it (RepairOutcome::Unrepaired).
/// Empty when the rung did not repair.
struct FoldsLeft {
    std::vector<int> group_of, first;
    std::vector<char> proved;
};

/// The fold-overs `outcome` left on m.
FoldsLeft folds_left(const TriMesh& m, const RepairOutcome& outcome);

/// Each explanation in `report` that removed faces, matched to the fold-over left nearest it
/// (within the repair's largest ring): its message names that fold-over and says whether a proof
/// backs it, and Report::losses_proved or losses_not_proved counts it.
void name_losses(const TriMesh& m, const FoldsLeft& folds, Report& report);

/// Stages validate and collapse (Section 3): the input's, before any rung changes the map.
Error prepare_mesh(const Input& input, const Options& options, TriMesh& m, Report& report);

/// One rung on the validated, collapsed mesh `m`, up to stage canonicalize. Returns false on an
/// input error (in result.error), which no rung can help. With `judged`, the rung may end judged
/// as well (then *judged is set): where its repair's look made and judged its mesh already.
bool run_rung(TriMesh m, const Input& input, const Options& options, const Rung& rung, Result& result,
              const AtScale& scale, bool* judged = nullptr);

/// Stages place_on_given_map (last resorts) and check: the checker's verdict on the rung's mesh
/// (mended where it is rejected). A relaxed rung's mesh is moved onto `given_map` first.
/// `checked`: the checker's analysis of the input, if kept (AtScale::checked).
void judge(const Input& input, const Options& options, const Rung& rung,
           const std::vector<std::array<double, 2>>& given_map, Result& attempt, CheckedInput* checked);

/// A fresh result for rung `r`, with what stages validate and collapse reported (`prepared`),
/// and the stage times so far.
Result start_attempt(const Report& prepared, int r, int tried);

} // namespace qex::detail

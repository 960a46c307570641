// The repair's solver (inside the subsystem only; its door is repair.h): a region untangled by
// minimising its energy with L-BFGS while the regularisation shrinks, what is left inverted
// moved into the kernels of its links, and a repaired region relaxed (solver.cpp).
#pragma once

#include "extract/repair/certificates.h"
#include "extract/repair/energy.h"

#include <atomic>
#include <vector>

namespace qex::detail::repair_impl {

/// The untangler's scratch: per triangle of the region its rest shape (of the last region a
/// problem was made for: a local mend's after one), and per corner of the mesh (sized once)
/// where it sits among the region's free corners (-1 between uses).
struct Workspace {
    explicit Workspace(const TriMesh& m);
    std::vector<RestShape> rest;
    std::vector<int> corner_slot;
    /// Set by another thread when the untangling's result is no longer wanted (RetryBeside):
    /// untangle_region then ends early, failing. Null: never.
    const std::atomic<bool>* stop = nullptr;
    /// Whether the attempt may hand work to a helper thread: its regions are attempted one at a
    /// time with threads to spare (the relaxation's Newton system, polish_region).
    bool beside = false;
    /// Whether a step whose first iterations leave much of the region inverted gives the region
    /// up there (solver.cpp, kGiveUpIteration). Off only to compare with the run without it.
    bool give_up_early = true;
};

/// How many regularisation steps in a row may leave no fewer triangles inverted than the
/// attempt's best before it stops. Short while a larger ring follows: a region that untangles
/// mostly does so in its first two steps (559 of 606 successes over the shared maps), and the
/// next ring holds the region again; long at the last ring, where nothing follows. Of 617
/// successful runs over the shared maps, one (at the last ring) had more than one such step in a
/// row; 123 failing runs spent a third one (2 rather than 3: the same meshes on the 50 maps and
/// on 540 transformed ones).
constexpr int kPatienceBeforeLastRing = 2;
constexpr int kPatienceAtLastRing = 8;

/// Untangles the region in place; true when every triangle of it is positively oriented.
/// `patience`: see above. `barrier` (sorted): triangles (positive at the start) kept positive
/// by a pure barrier.
bool untangle_region(TriMesh& m, const Region& r, Workspace& work, int patience, const std::vector<int>& barrier = {});

/// A repaired region (every triangle positive) relaxed to the minimum of its energy with no
/// regularisation: a pure barrier, so no triangle can invert and no vertex's winding change.
/// Where the untangler stops (the first iterate with nothing inverted) depends on rounding, so
/// an integer translation or a re-charting of the map would move the result; the minimum does
/// not. Kept only if the exact predicate still finds every triangle positive after placement,
/// and every vertex still winds as it must.
void polish_region(TriMesh& m, const Region& r, Workspace& work, const RegionMarks& marks);

} // namespace qex::detail::repair_impl

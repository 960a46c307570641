// The repair's retry with cone fans opened (inside the subsystem only; its door is repair.h):
// where the untangler wound a region wrongly round its singularities (open_cones.cpp).
#pragma once

#include "extract/repair/solver.h"

#include <atomic>
#include <exception>
#include <thread>
#include <vector>

namespace qex::detail::repair_impl {

/// After an untangling that failed: the region again from its given UVs (`before`), with the fans
/// of its singularities that wind short of their targets there (a run of flipped triangles, or a
/// squeezed fan) opened and kept open. True when that is certified. `patience` as for
/// untangle_region.
bool untangle_with_open_cones(TriMesh& m, const Region& r, const RegionMarks& marks, const std::vector<Point2>& before,
                              Workspace& work, int patience);

/// The retry with cone fans opened, run beside the first untangling on a second thread, on a
/// copy of the map (brought up to the map at each start). The retry starts over from the
/// region's given UVs and reads nothing the first try writes, so its outcome is the one it
/// would have after the first try, bit for bit: where the first try fails, the retry's time is
/// mostly spent already; where it is not needed, it is stopped.
class RetryBeside {
public:
    explicit RetryBeside(const TriMesh& m) : shadow_(m), work_(m) { work_.stop = &stop_; }
    RetryBeside(const RetryBeside&) = delete;
    RetryBeside& operator=(const RetryBeside&) = delete;
    ~RetryBeside() { stop(); }
    /// Starts the retry where the region has a singularity that winds short at its given UVs
    /// (m's now; the retry opens nothing elsewhere). False when it did not start.
    bool start(const TriMesh& m, const Region& r, const RegionMarks& marks, const std::vector<Point2>& before,
               int patience);
    /// Waits for the retry; true when it certified the region, whose free UVs it copies into m.
    bool take(TriMesh& m, const Region& r);
    /// Stops the retry (its outcome is not needed) and waits for it.
    void stop();

private:
    TriMesh shadow_;
    Workspace work_;
    std::thread thread_;
    std::atomic<bool> stop_{false};
    bool repaired_ = false;
    std::exception_ptr thrown_;
};

} // namespace qex::detail::repair_impl

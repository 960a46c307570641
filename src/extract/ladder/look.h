// The repair's look before its last ring, for ladder.cpp (defined in look.cpp): the rung's mesh
// extracted from the map as the repair left it so far, which the rung takes instead of making it
// again where the last ring changes nothing; and what the look shares with the rung's stages.
#pragma once

#include "rungs.h"

#include <chrono>
#include <cstdint>
#include <future>
#include <memory>
#include <optional>
#include <vector>

namespace qex::detail {

/// The look's mesh made as the rung's own would be and judged on a thread of its own, while the
/// last ring runs: where that ring changes nothing (duck_qc_8, duck_miq_28), the rung's verdict
/// is ready when the repair ends. Its destructor waits for the thread.
struct JudgedBeside {
    Result result;
    Report made;                     ///< the stage times of making it, which ran inside the repair's
    std::vector<const char*> heard;  ///< the stages the judge timed, for the caller's progress hook
    std::future<void> done;          ///< deferred where no thread could be had: get() judges
    ~JudgedBeside() { // a deferred judging nobody takes is not run
        if (done.valid() && done.wait_for(std::chrono::seconds(0)) != std::future_status::deferred) done.wait();
    }
};

/// The mesh the repair's look made: the rung's own extraction (and verdict, where the look judged
/// it), which the rung takes instead of making them again when its map is still the look's (the
/// repair says so: RepairOutcome::changed_after_look; it stopped at the look, or its last ring
/// repaired nothing).
struct LookedMesh {
    Result result;   ///< its report holds what the extraction (and the checker) said, nothing else
    FaceWalks faces; ///< the faces as walked, when not judged (the rung orders them)
    bool judged = false;
    /// Where the look did not judge its mesh (fewer quads than the area, or more, or defects):
    /// that mesh made as the rung's and judged beside the last ring (result and faces then moved
    /// into it). Null on large maps.
    std::unique_ptr<JudgedBeside> beside;
};

/// The repair's look before its last ring (repair.h) at the rung's mesh from m as the repair
/// left it so far (`outcome`): enough when that mesh is valid with as many quads as the map's
/// signed UV area (`report`'s); when it has fewer and its extraction no defect, the vertices
/// round where it lost them (place_vertices). What it made is kept in `looked`.
RepairLook look_so_far(const TriMesh& m, const RepairOutcome& outcome, const Input& input, const Options& options,
                       const Rung& rung, const Report& report, CheckedInput* checked,
                       std::optional<LookedMesh>& looked);

/// The rung's result from the mesh its repair's look made (and judged): the mesh, the verdict,
/// and what the extraction and the checker reported, after what the rung's own stages reported
/// (as if they had run), their times moved out of the repair's (those of `ran_inside`, where
/// not all of them ran inside it). The extraction's report fields are named one by one: a field
/// the extraction stages gain must be added here.
void take_looked(Result looked, Result& result, const Report* ran_inside = nullptr);

/// The map of m per input corner, a copy (take_map hands it over).
std::vector<std::array<double, 2>> map_of(const TriMesh& m, const Input& input);

/// The repair's certificate: the triangles it changed (working indices), by input index, sorted.
std::vector<std::int32_t> certificate_of(const TriMesh& m, const std::vector<int>& repaired_faces);

/// The output's faces from the face walks: in canonical order when the options ask for it (the
/// defects that name an output face renumbered with them), else as walked.
void order_faces(const Options& options, FaceWalks faces, Result& result);

} // namespace qex::detail

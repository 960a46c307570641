// What pipeline.h declares beside the stages: the stage timer, and the sanitization rounds that
// repeat stages compute_transitions, count_valences, sanitize and collapse until the map is stable.
#include "pipeline.h"

#include <chrono>
#include <cstdint>

namespace qex::detail {

// ============================================================================ timing

thread_local const std::function<void(const char*, int)>* StageTimer::hook = nullptr;
thread_local int StageTimer::hook_scale = 1;

StageTimer::StageTimer(Report& report) : report_(report), last_(std::chrono::steady_clock::now()) {}

void StageTimer::done(Stage stage) {
    const auto now = std::chrono::steady_clock::now();
    const double seconds = std::chrono::duration<double>(now - last_).count();
    last_ = now;
    const char* name = stage_name(stage);
    if (hook) (*hook)(name, hook_scale);
    for (auto& [label, total] : report_.stage_seconds)
        if (label == name) {
            total += seconds;
            return;
        }
    report_.stage_seconds.emplace_back(name, seconds);
}

// ============================================================================ sanitization rounds

Error sanitize_until_stable(TriMesh& m, const Input& input, const std::vector<std::array<int, 2>>& features,
                            Report& report, StageTimer& timer, int max_rounds, SeamPolicy seams) {
    // Branch points (r = 0 singularities) are decided by angles. Without given valences they are
    // snapped only once the truncated map's degenerate edges are collapsed: before, a noisy
    // sliver next to a vertex can add a full turn to its angle sum.
    bool branch_points = !input.valences.empty();
    for (int round = 0;; ++round) {
        compute_transitions(m);
        if (round == 0)
            if (Error e = check_seams(m, seams, report); e.code != ErrorCode::None) return e;
        timer.done(Stage::compute_transitions);
        count_valences(m);
        timer.done(Stage::count_valences);
        std::int64_t deferred = 0;
        if (Error e = sanitize(m, input.valences, features, report, branch_points, &deferred);
            e.code != ErrorCode::None)
            return e;
        timer.done(Stage::sanitize);
        // The last round ends on a sanitized map: a collapse after it would leave the map
        // state of the old connectivity (degenerate edges left over are handled downstream).
        if (round == max_rounds) return {};
        std::int64_t collapsed = 0;
        if (Error e = collapse(m, collapsed); e.code != ErrorCode::None) return e;
        timer.done(Stage::collapse);
        report.collapsed_edges += collapsed;
        if (collapsed == 0) {
            if (branch_points || deferred == 0) return {};
            branch_points = true; // one more pass, now on the collapsed map
        }
    }
}

} // namespace qex::detail

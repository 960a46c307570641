// The public extract(): the fallback ladder (ladder/ladder.h) on the map at its own scale; when
// no rung's mesh is valid, the ladder on the map coarsened, then refined.
#include "ladder/ladder.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <optional>
#include <vector>

namespace qex {
namespace {

/// An invalid result's report names the handles the map collapses first among its defects,
/// before the symptoms that follow from them (found here unless `handles` holds them), and a
/// best-effort one which attempt it is.
void name_collapsed_handles(const Input& input, const Options& options,
                            std::optional<std::vector<CollapsedHandle>> handles, Result& result) {
    if (result.check.valid) return;
    if (!handles) handles = detail::find_collapsed_handles(input, options.max_refinement);
    std::vector<Defect> named;
    for (const CollapsedHandle& h : *handles)
        named.push_back(detail::collapsed_handle_defect(input, h, options.max_refinement));
    result.report.defects.insert(result.report.defects.begin(), named.begin(), named.end());
    result.report.collapsed_handles = std::move(*handles);
    // A best-effort result says which attempt it is, also where no refinement was tried.
    auto& explanations = result.report.explanations;
    if (options.best_effort && std::none_of(explanations.begin(), explanations.end(),
                                            [](const Defect& d) { return d.kind == DefectKind::BestEffortMesh; })) {
        const std::size_t n = result.check.violations.size();
        explanations.insert(explanations.begin(),
                            detail::best_effort_explanation(1, "the map's own scale: " + std::to_string(n), n));
    }
}

} // namespace

Result extract(const Input& input, const Options& options) {
    using namespace detail;
    // The progress hook, for this thread and this call only.
    struct Hook {
        explicit Hook(const Options& o) {
            StageTimer::hook = o.on_stage ? &o.on_stage : nullptr;
            StageTimer::hook_scale = 1;
        }
        ~Hook() { StageTimer::hook = nullptr; }
    } hook(options);
    // The repair at the map's own scale, kept for its refinements (if any can run).
    RepairMemo memo;
    const bool may_refine = options.fallback_ladder && options.max_refinement >= 2;
    Result fillable; // the last resort's other candidate at the map's own scale
    CheckedInput checked(input, thread_count(options.threads)); // one analysis for every check
    Result result = extract_at_scale(input, options, AtScale{1, false, may_refine ? &memo : nullptr, &checked},
                                     options.fallback_ladder && options.fill_holes ? &fillable : nullptr);
    if (!result.ok()) return result;
    if (!options.fallback_ladder) {
        name_collapsed_handles(input, options, std::nullopt, result);
        return result;
    }
    if (result.check.valid) {
        // More quads than the signed area: faces on two sheets of a fold-over cover some cells
        // twice (a pleat the checker, judging fold-over regions on the surface, lets pass). The
        // coarsened map's mesh is taken instead if its count is closer to the area.
        if (options.max_coarsening < 2 || !over_covered(result)) return result;
        Result coarse = result;
        if (!extract_coarsened(input, options, coarse)) return result;
        const double area = result.report.signed_uv_area;
        const auto off = [area](const Result& r) { return std::abs(static_cast<double>(r.mesh.faces.size()) - area); };
        return off(coarse) < off(result) ? coarse : result;
    }
    // No rung's mesh is valid: the map coarsened (coarsen.cpp), then refined (refine.cpp).
    if (options.max_coarsening >= 2 && extract_coarsened(input, options, result)) return result;
    // A handle the map collapses is lost at every scale: then refinement is not tried (fail
    // fast), unless Options::best_effort looks for the mesh that loses only that handle.
    std::vector<CollapsedHandle> handles = find_collapsed_handles(input, options.max_refinement);
    if (refinement_can_help(options, !handles.empty(), result))
        extract_refined(input, options, memo, &checked, !handles.empty(), fillable, result);
    else if (options.fill_holes) // the last resort, which extract_refined tries after every scale
        (void)fill_holes_if_accepted(input, options, result, &fillable, &checked);
    name_collapsed_handles(input, options, std::move(handles), result);
    return result;
}

} // namespace qex

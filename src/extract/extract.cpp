// The public extract(): the fallback ladder (ladder/ladder.h) on the map at its own scale; when
// no rung's mesh is valid, the ladder on the map coarsened, then refined.
#include "ladder/ladder.h"

#include <cmath>

namespace qex {

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
    Result result = extract_at_scale(input, options, AtScale{1, false, may_refine ? &memo : nullptr});
    if (!result.ok() || !options.fallback_ladder) return result;
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
    if (options.max_refinement < 2) return result;
    extract_refined(input, options, memo, result);
    return result;
}

} // namespace qex

// Refinement: when no rung gives a valid mesh at the map's own scale (nor coarsened), the ladder
// runs again on the map with its UVs multiplied by 2, 4, 8 and 16 (exact: powers of two), each
// quad of the map's own size becoming K x K. The repair runs once, at the map's own scale: a
// refined attempt whose sanitized map is exactly the own-scale one times the factor takes its
// result (RepairMemo). And the explanations of a mesh found at another scale, or of none.
#include "ladder.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

namespace qex::detail {
namespace {

/// Refinement stops short of this many quads: a map with many quads is not too coarse, and
/// refining it would only multiply the cost.
constexpr double kMaxRefinedQuads = 200'000;

/// Whether the map of signed UV area `area` on `triangles` triangles is refined by `factor`:
/// not past kMaxRefinedQuads, nor past as many quads as triangles. There a cell is smaller than
/// a triangle on average, the map's own resolution: a feature a coarser grid lost (a handle, a
/// hole, singularities within a cell) spans cells by then, and a finer grid only multiplies the
/// cost of failing (a 9,000-triangle map refined x16 spent 6 of its 7 s there, and lost).
/// The area is rounded to whole quads first: summed in the input's order, it differs in its last
/// bits between orders of one map, and a closed map's area is a whole number of quads.
bool within_refinement_budget(double area, std::int64_t triangles, std::int64_t factor) {
    const double quads = std::round(std::abs(area) * static_cast<double>(factor * factor));
    return quads <= kMaxRefinedQuads && quads <= static_cast<double>(triangles);
}

// ============================================================================ the repair, kept

/// A UV of the map at its own scale, `factor` times (exact for a power of two; NaN stays NaN).
Point2 times(const Point2& u, std::int64_t factor) {
    const auto k = static_cast<double>(factor);
    return {k * u[0], k * u[1]};
}

/// A transition of the map at its own scale, in the map `factor` times it.
GridAutomorphism times(const GridAutomorphism& g, std::int64_t factor) { return {g.r, factor * g.tx, factor * g.ty}; }

/// Whether m's sanitized state is exactly the memo's times `factor`.
bool memo_applies(const TriMesh& m, const RepairMemo& memo, std::int64_t factor) {
    if (!memo.filled || !memo.connectivity || m.tri != memo.tri || m.input_triangle != memo.input_triangle ||
        m.input_vertex != memo.input_vertex || m.corner_vertex != memo.corner_vertex ||
        m.uv.size() != memo.sanitized.size() || m.map.singular != memo.singular || m.map.valence != memo.valence ||
        m.map.winding_valence != memo.winding_valence || m.map.transition.size() != memo.transitions.size())
        return false;
    for (std::size_t c = 0; c < m.uv.size(); ++c) {
        const Point2 u = times(memo.sanitized[c], factor);
        for (int d = 0; d < 2; ++d)
            if (m.uv[c][d] != u[d] && !(std::isnan(m.uv[c][d]) && std::isnan(u[d]))) return false;
    }
    for (std::size_t h = 0; h < memo.transitions.size(); ++h)
        if (!(m.map.transition[h] == times(memo.transitions[h], factor))) return false;
    return true;
}

/// The repair at the map's own scale, times `factor` (memo_applies), put into m: UVs,
/// transitions, singularities and valences, and its explanations into the report.
RepairOutcome repair_from_memo(TriMesh& m, const RepairMemo& memo, std::int64_t factor, Report& report) {
    // m is the memo's sanitized map times the factor (memo_applies, which takes -0.0 for 0.0: the
    // UVs are written from the memo's bits); only what the repair changed differs.
    for (std::size_t c = 0; c < m.uv.size(); ++c) m.uv[c] = times(memo.sanitized[c], factor);
    for (std::size_t i = 0; i < memo.repaired_corners.size(); ++i)
        m.uv[memo.repaired_corners[i]] = times(memo.repaired_uvs[i], factor);
    for (std::size_t i = 0; i < memo.repaired_half_edges.size(); ++i)
        m.map.transition.set(memo.repaired_half_edges[i], times(memo.repaired_transitions[i], factor));
    m.map.singular = memo.repaired_singular;
    m.map.valence = memo.repaired_valence;
    m.map.winding_valence = memo.repaired_winding_valence;
    m.map.face_sign = triangle_signs(m);
    report.explanations.insert(report.explanations.end(), memo.explanations.begin(), memo.explanations.end());
    return memo.outcome;
}

/// Stage repair on m at the map's own scale, with the map before it and after it, and what it
/// reported, kept in `memo` for the refinements. The connectivity and the transitions before the
/// repair are not copied here: the rung hands them over once it is done with the map
/// (keep_for_refinements), which spares a copy that faulted in fresh pages beside the stages
/// (0.5-3.8 ms on duck_miq_8) where no refinement follows.
RepairOutcome repair_into_memo(TriMesh& m, const std::vector<std::array<int, 2>>& features, bool valences_given,
                               int threads, RepairMemo& memo, Report& report, const LookBeforeLastRing& look) {
    memo = RepairMemo{};
    memo.sanitized = m.uv;
    memo.singular = m.map.singular;
    memo.valence = m.map.valence;
    memo.winding_valence = m.map.winding_valence;
    const std::size_t explained = report.explanations.size();
    RepairOutcome outcome = repair(m, features, valences_given, threads, report, look, &memo.sanitized);
    memo.repaired_corners = differing_entries(m.uv.data(), memo.sanitized.data(), m.uv.size());
    for (const std::size_t c : memo.repaired_corners) memo.repaired_uvs.push_back(m.uv[c]);
    // Only a dipole merge changes a transition (transitions_before lists every half-edge one did).
    for (const auto& [h, g] : outcome.transitions_before)
        if (!(m.map.transition[static_cast<std::size_t>(h)] == g)) {
            memo.repaired_half_edges.push_back(static_cast<std::size_t>(h));
            memo.repaired_transitions.push_back(m.map.transition[static_cast<std::size_t>(h)]);
            memo.transitions_before.push_back({h, g});
        }
    outcome.transitions_before.clear(); // scale 1's: not in the outcome refinements return
    memo.repaired_singular = m.map.singular;
    memo.repaired_valence = m.map.valence;
    memo.repaired_winding_valence = m.map.winding_valence;
    memo.outcome = outcome;
    memo.explanations.assign(report.explanations.begin() + static_cast<std::ptrdiff_t>(explained),
                             report.explanations.end());
    memo.filled = true;
    return outcome;
}

} // namespace

RepairOutcome repair_at_scale(TriMesh& m, const std::vector<std::array<int, 2>>& features, bool valences_given,
                              int threads, const AtScale& scale, Report& report, const LookBeforeLastRing& look) {
    RepairMemo* memo = scale.memo;
    if (memo && scale.factor > 1 && memo_applies(m, *memo, scale.factor))
        return repair_from_memo(m, *memo, scale.factor, report);
    // No refinement can follow when doubling the map takes it past the budget.
    if (!memo || scale.factor != 1 || !within_refinement_budget(report.signed_uv_area, report.input_triangles, 2))
        return repair(m, features, valences_given, threads, report, look);
    return repair_into_memo(m, features, valences_given, threads, *memo, report, look);
}

void keep_for_refinements(TriMesh& m, RepairMemo& memo) {
    if (!memo.filled || memo.connectivity) return;
    // The copy first (take_map reads it after this): if it throws, nothing has moved.
    memo.input_triangle = m.input_triangle;
    memo.tri = std::move(m.tri);
    memo.input_vertex = std::move(m.input_vertex);
    memo.corner_vertex = std::move(m.corner_vertex);
    memo.transitions = std::move(m.map.transition);
    for (const auto& [h, g] : memo.transitions_before) memo.transitions.set(static_cast<std::size_t>(h), g);
    memo.connectivity = true;
}

// ============================================================================ explanations

Defect scale_explanation(DefectKind kind, const Result& at_scale_one, const std::string& how) {
    Defect d{kind, "", -1, -1, {0, 0}, std::nullopt};
    if (at_scale_one.check.valid) { // over_covered
        d.message = "the mesh at the map's own scale is valid but has " +
                    std::to_string(at_scale_one.mesh.faces.size()) + " quads for a signed UV area of " +
                    std::to_string(std::llround(at_scale_one.report.signed_uv_area)) +
                    " (faces on two sheets of a fold-over cover some cells twice); this mesh is closer to the "
                    "area: " +
                    how;
        return d;
    }
    std::string what = std::to_string(at_scale_one.check.violations.size()) + " checker violations";
    if (!at_scale_one.report.defects.empty()) {
        const Defect& first = at_scale_one.report.defects.front();
        d.input_element = first.input_element;
        d.grid = first.grid;
        what += "; the first: " + first.message;
    }
    d.message = "the map gives no valid quad mesh at its own scale (" + what + "); " + how;
    return d;
}

namespace {

/// What a refined attempt that gave no valid mesh failed by: the first of its checker
/// violations as located on the input (else its first defect).
Defect refinement_failure(const Result& refined, std::int64_t scale) {
    const std::string k = std::to_string(scale);
    const std::vector<Defect>& defects = refined.report.defects;
    const auto located = std::find_if(defects.begin(), defects.end(),
                                      [](const Defect& d) { return d.kind == DefectKind::CheckerViolation; });
    const Defect* first = located != defects.end() ? &*located : defects.empty() ? nullptr : &defects.front();
    Defect d{DefectKind::RefinementFailed, "", first ? first->input_element : -1, -1, {0, 0}, std::nullopt};
    d.message = "the map with its UVs multiplied by " + k + " gives no valid mesh either (" +
                std::to_string(refined.check.violations.size()) + " checker violations" +
                (first ? "; the first: " + first->message : std::string()) + ")";
    return d;
}

/// The explanation of a refined mesh.
Defect refinement_explanation(const Result& at_scale_one, int scale) {
    const std::string k = std::to_string(scale);
    return scale_explanation(DefectKind::MapRefined, at_scale_one,
                             "the mesh is extracted on the map with its UVs multiplied by " + k +
                                 ", so each quad of the map's own size is " + k + " x " + k + " quads");
}

} // namespace

// ============================================================================ best effort

namespace {

/// Whether every violation of r's mesh is of the whole mesh's topology (Euler characteristic,
/// boundary loops, components): all a mesh can be left with once the map collapses a handle.
bool only_lost_topology(const Result& r) {
    return std::all_of(r.check.violations.begin(), r.check.violations.end(), [](const Violation& v) {
        return v.kind == ViolationKind::EulerMismatch || v.kind == ViolationKind::BoundaryMismatch ||
               v.kind == ViolationKind::ComponentMismatch;
    });
}

} // namespace

Defect best_effort_explanation(int scale, const std::string& tried, std::size_t violations) {
    const std::string which = scale == 1 ? std::string("the map at its own scale")
                                         : "the map with its UVs multiplied by " + std::to_string(scale);
    return {DefectKind::BestEffortMesh,
            "no attempt gives a valid mesh; the mesh is the one closest to valid (best effort): " + which + ", " +
                std::to_string(violations) + " checker violations (" + tried + ")",
            -1,
            -1,
            {0, 0},
            std::nullopt};
}

namespace {

/// `closest`, refined `scale` times, in place of `result` (the map's own scale), with what
/// `result` says of the refinements (`failed`: one RefinementFailed per factor tried).
void take_refined(Result& closest, int scale, std::vector<Defect> failed, const std::string& tried, Result& result) {
    closest.mesh.grid_scale = scale;
    closest.report.grid_scale = scale;
    closest.report.refinements_tried = result.report.refinements_tried;
    closest.report.stage_seconds = std::move(result.report.stage_seconds);
    std::vector<Defect>& explanations = closest.report.explanations;
    explanations.insert(explanations.begin(), best_effort_explanation(scale, tried, closest.check.violations.size()));
    for (const Defect& d : result.report.explanations)
        if (d.kind == DefectKind::SeamRounded) explanations.push_back(d);
    explanations.insert(explanations.end(), failed.begin(), failed.end());
    result = std::move(closest);
}

/// `refined`, valid at `scale`, in place of `result` (the map's own scale, invalid).
void take_valid_refined(Result&& refined, int scale, Result& result) {
    refined.mesh.grid_scale = scale;
    refined.report.grid_scale = scale;
    refined.report.refinements_tried = result.report.refinements_tried;
    refined.report.stage_seconds = std::move(result.report.stage_seconds);
    refined.report.explanations.insert(refined.report.explanations.begin(), refinement_explanation(result, scale));
    // Seams rounded at scale 1 (Options::round_inconsistent_seams) are the refined map's too,
    // rounded there without a check: their explanations carry over.
    for (const Defect& d : result.report.explanations)
        if (d.kind == DefectKind::SeamRounded) refined.report.explanations.push_back(d);
    result = std::move(refined);
}

} // namespace

bool refinement_can_help(const Options& options, bool handle_collapsed, const Result& result) {
    if (options.max_refinement < 2) return false;
    return !handle_collapsed || (options.best_effort && !only_lost_topology(result));
}

// ============================================================================ the map refined

void extract_refined(const Input& input, const Options& options, RepairMemo& memo, CheckedInput* checked,
                     bool handle_collapsed, const Result& fillable, Result& result) {
    // The map at twice, four times, ... its scale. Multiplying by two is exact; a map that would
    // leave the range integer transitions need comes back as an input error, and ends the
    // refinement with the scale-1 result.
    Input scaled = input;
    std::vector<Defect> failed; // per refinement tried
    Result closest;             // best effort: the refined attempt closest to valid so far
    int closest_scale = 1;
    Result filled; // the first refined attempt that fill_holes made valid
    int filled_scale = 0;
    std::string tried = "the map's own scale: " + std::to_string(result.check.violations.size());
    for (int scale = 2; scale <= options.max_refinement; scale *= 2) {
        if (!within_refinement_budget(result.report.signed_uv_area, static_cast<std::int64_t>(input.triangles.size()),
                                      scale))
            break;
        for (auto& uv : scaled.uvs) uv = {2.0 * uv[0], 2.0 * uv[1]};
        StageTimer::hook_scale = scale;
        // The map at scale 1 passed the seam check (or this would not run).
        Result other; // the last resort's other candidate at this scale
        Result refined =
            extract_at_scale(scaled, options, AtScale{scale, true, &memo, checked}, filled_scale == 0 ? &other : nullptr);
        ++result.report.refinements_tried;
        // The last resort, kept for the end: the smallest scale whose holes, filled, pass.
        const bool filled_here = options.fill_holes && refined.ok() && !refined.check.valid && filled_scale == 0 &&
                                 fill_holes_if_accepted(scaled, options, refined, &other, checked);
        add_stage_seconds(refined.report, result.report);
        if (!refined.ok()) break;
        if (filled_here) {
            filled = std::move(refined);
            filled_scale = scale;
            continue;
        }
        if (refined.check.valid) return take_valid_refined(std::move(refined), scale, result);
        failed.push_back(refinement_failure(refined, scale));
        if (!options.best_effort) continue;
        tried += "; x" + std::to_string(scale) + ": " + std::to_string(refined.check.violations.size());
        // Ties go to the smaller scale, tried first. Once the map is proved to collapse a
        // handle, an attempt that loses only that topology is as close as any can come.
        const bool stop = handle_collapsed && only_lost_topology(refined);
        const Result& best = closest_scale > 1 ? closest : result;
        if (refined.check.violations.size() < best.check.violations.size())
            closest = std::move(refined), closest_scale = scale;
        if (stop) break;
    }
    // No scale gives a valid mesh as extracted: the last resort, holes filled, at the smallest
    // scale where that passes.
    StageTimer::hook_scale = 1;
    if (options.fill_holes && fill_holes_if_accepted(input, options, result, &fillable, checked)) return;
    if (filled_scale > 0) return take_valid_refined(std::move(filled), filled_scale, result);
    if (closest_scale > 1) return take_refined(closest, closest_scale, std::move(failed), tried, result);
    result.report.explanations.insert(result.report.explanations.end(), failed.begin(), failed.end());
    if (options.best_effort)
        result.report.explanations.insert(result.report.explanations.begin(),
                                          best_effort_explanation(1, tried, result.check.violations.size()));
}

} // namespace qex::detail

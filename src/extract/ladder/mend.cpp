// A rung's mesh the checker rejected, mended: the edges that join sheets of a fold-over cut
// (stage separate_sheets), the holes its face walks left closed (stage close_holes). Each mended
// mesh is a candidate only, kept if the checker accepts it, against the map it carries and
// against the given map alone, as `qex check --param` judges any extractor's mesh.
#include "ladder.h"

#include <algorithm>

namespace qex::detail {

std::vector<Violation> located_violations(const Input& input, const QuadMesh& mesh, VerifyOptions options,
                                          bool fold_regions) {
    QuadMesh bare;
    bare.positions = mesh.positions;
    bare.faces = mesh.faces;
    options.fold_regions = fold_regions;
    return verify(input, bare, options).violations;
}

namespace {

/// Whether the checker accepts `mesh` against the map it carries, and the oracle without
/// provenance against the given map too (fold-over regions judged on the surface, or everywhere
/// after a relaxed rung), as `qex check --param` would; its verdict in `check`.
bool accepted(const Input& input, const QuadMesh& mesh, bool relaxed, const VerifyOptions& verify_options,
              VerifyResult& check) {
    check = verify(input, mesh, verify_options);
    return check.valid && located_violations(input, mesh, verify_options, !relaxed).empty();
}

/// Keeps `mended` (with `explanations` for what was done to it) as the attempt's mesh.
void keep(QuadMesh&& mended, VerifyResult&& check, std::vector<Defect>&& explanations, Result& attempt) {
    attempt.mesh = std::move(mended);
    attempt.check = std::move(check);
    for (Defect& d : explanations) attempt.report.explanations.push_back(std::move(d));
}

/// Stage close_holes, on a mesh the checker rejected: the holes its face walks left, closed by the
/// grid cells their rims enclose; or, with `fill`, stage fill_holes (the last resort), and only
/// where it filled a hole from its rim (holes cells close alone were tried when the rung's mesh
/// was mended; longer rims closed so are judged only beside a filled one). Kept (with `done`,
/// what was done to `mesh` before) only if it is then accepted(). `mesh` is read only before the
/// result is kept, so it may be attempt.mesh.
bool holes_closed_if_accepted(const Input& input, const QuadMesh& mesh, bool relaxed,
                              const VerifyOptions& verify_options, const std::vector<Defect>& done, bool fill,
                              Result& attempt) {
    // Rim vertices read as regular first; then, if that is rejected, as their fans wind (a
    // valence-3 and a valence-5 vertex on one rim cancel in the first reading).
    std::vector<std::vector<int>> first_faces; // the first reading's result, not judged twice
    for (const bool wound_first : {false, true}) {
        QuadMesh closed = mesh;
        std::vector<Defect> explanations =
            fill ? fill_holes(input, closed, wound_first) : close_holes(input, closed, wound_first);
        const bool changed = fill ? std::any_of(explanations.begin(), explanations.end(),
                                                [](const Defect& d) { return d.kind == DefectKind::HoleFilled; })
                                  : !explanations.empty();
        if (!changed || (wound_first && closed.faces == first_faces)) continue;
        if (!wound_first) first_faces = closed.faces;
        VerifyResult check;
        if (!accepted(input, closed, relaxed, verify_options, check)) continue;
        explanations.insert(explanations.begin(), done.begin(), done.end());
        keep(std::move(closed), std::move(check), std::move(explanations), attempt);
        return true;
    }
    return false;
}

/// Whether the checker found what no mend step changes, so that every mended mesh would be
/// rejected again: a face with other than four corners or whose local UVs are no unit square
/// (separate_sheets renumbers corners and moves vertices, close_holes adds unit squares; neither
/// touches an existing face's size or local UVs), or a fault of the map the mesh carries, of its
/// certificate or of its size.
bool beyond_mending(const std::vector<Violation>& violations) {
    return std::any_of(violations.begin(), violations.end(), [](const Violation& v) {
        switch (v.kind) {
            case ViolationKind::NotQuad:
            case ViolationKind::LocalUvNotUnitSquare:
            case ViolationKind::MapNotIntegerGrid:
            case ViolationKind::SingularityOffGrid:
            case ViolationKind::RepairNotCertified:
            case ViolationKind::CertificateMismatch:
            case ViolationKind::EmptyMesh:
            case ViolationKind::TooLarge: return true;
            default: return false;
        }
    });
}

} // namespace

void mend_if_accepted(const Input& input, bool relaxed, const VerifyOptions& verify_options, StageTimer& timer,
                      Result& attempt, MapGraph* graph) {
    // Fail fast: mending cannot change the verdict (decimated-knight_miq_18 spent 0.8 of its 1.8 s
    // mending meshes refined x8 and x16 with faces of other local UVs).
    if (beyond_mending(attempt.check.violations)) return;
    const bool joined = std::any_of(attempt.check.violations.begin(), attempt.check.violations.end(),
                                    [](const Violation& v) { return v.kind == ViolationKind::NonManifoldEdge; });
    MapGraph own(input); // made only if no graph is given and a separation needs it
    MapGraph& charts = graph ? *graph : own;
    for (const bool larger_end_first : {false, true}) {
        if (!joined) break;
        QuadMesh separated = attempt.mesh;
        std::vector<Defect> explanations = separate_sheets(charts, separated, larger_end_first);
        timer.done(Stage::separate_sheets);
        if (explanations.empty()) continue;
        VerifyResult check;
        const bool ok = accepted(input, separated, relaxed, verify_options, check);
        timer.done(Stage::separate_sheets);
        if (ok) {
            keep(std::move(separated), std::move(check), std::move(explanations), attempt);
            return;
        }
        const bool closed = holes_closed_if_accepted(input, separated, relaxed, verify_options, explanations, false, attempt);
        timer.done(Stage::close_holes);
        if (closed) return;
    }
    (void)holes_closed_if_accepted(input, attempt.mesh, relaxed, verify_options, {}, false, attempt);
    timer.done(Stage::close_holes);
}

namespace {

/// Stage fill_holes on `candidate`'s mesh as it is, and, where the checker found sheets joined at
/// an edge, on each separation of them (separate_sheets, the smaller end first, then the larger):
/// the first that the checker accepts, filled, goes into `out` (a copy of `candidate`, its
/// explanations added, its located violations dropped). The stages' time goes to `timer`.
bool fill_candidate(const Input& input, const VerifyOptions& verify_options, const Result& candidate, StageTimer& timer,
                    Result& out) {
    if (candidate.check.valid || beyond_mending(candidate.check.violations)) return false;
    const bool relaxed = relaxed_rung(candidate.report.rung);
    const bool joined = std::any_of(candidate.check.violations.begin(), candidate.check.violations.end(),
                                    [](const Violation& v) { return v.kind == ViolationKind::NonManifoldEdge; });
    std::vector<std::pair<QuadMesh, std::vector<Defect>>> starts;
    starts.emplace_back(candidate.mesh, std::vector<Defect>{});
    MapGraph graph(input); // the candidate's map's, for both separations
    for (const bool larger_end_first : {false, true}) {
        if (!joined) break;
        QuadMesh separated = candidate.mesh;
        std::vector<Defect> cuts = separate_sheets(graph, separated, larger_end_first);
        timer.done(Stage::separate_sheets);
        if (!cuts.empty()) starts.emplace_back(std::move(separated), std::move(cuts));
    }
    out = candidate;
    for (const auto& [mesh, done] : starts) {
        const bool ok = holes_closed_if_accepted(input, mesh, relaxed, verify_options, done, true, out);
        timer.done(Stage::fill_holes);
        if (!ok) continue;
        // The violations located on the input are gone with them; the extraction's defects stay.
        auto& defects = out.report.defects;
        defects.erase(std::remove_if(defects.begin(), defects.end(),
                                     [](const Defect& d) { return d.kind == DefectKind::CheckerViolation; }),
                      defects.end());
        out.report.check_violations = 0;
        return true;
    }
    return false;
}

} // namespace

bool fill_holes_if_accepted(const Input& input, const Options& options, Result& attempt, const Result* other,
                            CheckedInput* checked) {
    if (attempt.check.valid) return false;
    VerifyOptions verify_options;
    verify_options.threads = options.threads;
    if (checked) verify_options.prepared = &checked->get();
    Result filled;
    {
        StageTimer timer(attempt.report);
        if (!fill_candidate(input, verify_options, attempt, timer, filled) &&
            (!other || other->report.rung.empty() || other->report.rung == attempt.report.rung ||
             !fill_candidate(input, verify_options, *other, timer, filled)))
            return false;
    }
    // The attempt's report keeps the totals: the stages' times, the rungs and refinements tried.
    filled.report.stage_seconds = std::move(attempt.report.stage_seconds);
    filled.report.rungs_tried = attempt.report.rungs_tried;
    filled.report.refinements_tried = attempt.report.refinements_tried;
    attempt = std::move(filled);
    return true;
}

bool topology_only(const std::vector<Violation>& violations) {
    const bool mendable = std::any_of(violations.begin(), violations.end(), [](const Violation& v) {
        return v.kind == ViolationKind::Hole || v.kind == ViolationKind::NonManifoldEdge;
    });
    return mendable && std::all_of(violations.begin(), violations.end(), [](const Violation& v) {
               switch (v.kind) {
                   case ViolationKind::NonManifoldEdge:
                   case ViolationKind::NonManifoldVertex:
                   case ViolationKind::Hole:
                   case ViolationKind::EulerMismatch:
                   case ViolationKind::BoundaryMismatch:
                   case ViolationKind::ComponentMismatch: return true;
                   default: return false;
               }
           });
}

} // namespace qex::detail

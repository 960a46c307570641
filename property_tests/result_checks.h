// Invariants of an extraction's Result that the tests and the fuzz targets assert: the report
// agrees with the checker's verdict, the verdict with an independent re-run of the checker, and
// every defect and explanation names a place that exists. Each check returns "" when it holds,
// else what is wrong (for a test's message or a fuzz target's abort).
#pragma once

#include "qex/qex.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace qex::testing {

/// A violation of the whole mesh, which names no single place (Euler characteristic, boundary
/// loops, components, no faces, coverage, size).
inline bool is_whole_mesh_violation(ViolationKind k) {
    return k == ViolationKind::EulerMismatch || k == ViolationKind::BoundaryMismatch ||
           k == ViolationKind::ComponentMismatch || k == ViolationKind::EmptyMesh ||
           k == ViolationKind::CoverageMismatch || k == ViolationKind::TooLarge;
}

/// An explanation of a quad count below the UV area, not a defect.
inline bool is_explanation_kind(DefectKind k) {
    return k == DefectKind::FaceCollapsed || k == DefectKind::GhostFacesCancelled ||
           k == DefectKind::BoundaryFaceDiscarded || k == DefectKind::FoldOverNotRepaired ||
           k == DefectKind::MapRefined || k == DefectKind::MapCoarsened || k == DefectKind::SeamRounded ||
           k == DefectKind::SingularitiesMerged || k == DefectKind::HoleClosed || k == DefectKind::SheetsSeparated ||
           k == DefectKind::RefinementFailed || k == DefectKind::BestEffortMesh ||
           k == DefectKind::RimShortOfSingularity || k == DefectKind::FoldPinnedBySingularities ||
           k == DefectKind::AnglesLeaveNoRoom || k == DefectKind::RegionAreaNotPositive || k == DefectKind::HoleFilled;
}

/// The violations extract() must have found on `r.mesh`, judged again here: the checker on the
/// mesh, and where that passes, as judge() in src/extract/ladder/ladder.cpp holds them, also the
/// checker on the mesh without its provenance against the given map: everywhere after a relaxed
/// (last-resort) rung, fold-over regions on the surface only where clones of two sheets were
/// merged (Report::near_ghost_faces_cancelled).
inline std::vector<Violation> expected_violations(const Input& in, const Result& r, const VerifyResult& rerun) {
    std::vector<Violation> out = rerun.violations;
    const bool relaxed = r.report.rung.rfind("untangled", 0) == 0;
    if (rerun.valid && (relaxed || r.report.near_ghost_faces_cancelled > 0)) {
        QuadMesh bare;
        bare.positions = r.mesh.positions;
        bare.faces = r.mesh.faces;
        bare.grid_scale = r.mesh.grid_scale;
        VerifyOptions given;
        given.fold_regions = !relaxed;
        for (const Violation& v : verify(in, bare, given).violations) out.push_back(v);
    }
    return out;
}

/// "" when r.check is the verdict the checker gives again, r.report counts its violations and the
/// report's checker defects are its violations one to one, kind for kind and in order.
inline std::string verdict_inconsistency(const Input& in, const Result& r, const VerifyResult& rerun) {
    const std::vector<Violation>& found = r.check.violations;
    if (r.check.valid != found.empty()) return "check.valid disagrees with check.violations";
    if (r.report.check_violations != static_cast<std::int64_t>(found.size()))
        return "report.check_violations " + std::to_string(r.report.check_violations) + ", check has " +
               std::to_string(found.size());
    const std::vector<Violation> expected = expected_violations(in, r, rerun);
    if (expected.size() != found.size())
        return "the checker, run again, finds " + std::to_string(expected.size()) + " violations; check has " +
               std::to_string(found.size());
    for (std::size_t i = 0; i < found.size(); ++i)
        if (expected[i].kind != found[i].kind || expected[i].element != found[i].element)
            return std::string("violation ") + std::to_string(i) + " is " + to_string(found[i].kind) +
                   ", the checker run again finds " + to_string(expected[i].kind);
    std::size_t checker = 0;
    for (const Defect& d : r.report.defects) {
        if (d.violation.has_value() != (d.kind == DefectKind::CheckerViolation))
            return std::string("defect ") + to_string(d.kind) + " and its violation kind disagree: " + d.message;
        if (!d.violation) continue;
        if (checker >= found.size()) return "more checker defects than violations: " + d.message;
        if (*d.violation != found[checker].kind)
            return std::string("checker defect ") + std::to_string(checker) + " has kind " + to_string(*d.violation) +
                   ", its violation is " + to_string(found[checker].kind);
        ++checker;
    }
    if (checker != found.size())
        return std::to_string(checker) + " checker defects for " + std::to_string(found.size()) + " violations";
    return {};
}

/// Whether output vertex `v` (of `face`, or of the whole mesh when face < 0) has the defect's
/// input triangle and grid point as its provenance.
inline bool names_an_output_vertex(const Result& r, const Defect& d) {
    const auto& prov = r.mesh.provenance;
    auto matches = [&](int v) {
        return v >= 0 && v < static_cast<int>(prov.size()) &&
               prov[static_cast<std::size_t>(v)].chart_triangle == d.input_element &&
               prov[static_cast<std::size_t>(v)].grid == d.grid;
    };
    if (d.output_face >= 0) {
        const auto& face = r.mesh.faces[static_cast<std::size_t>(d.output_face)];
        return std::any_of(face.begin(), face.end(), matches);
    }
    for (int v = 0; v < static_cast<int>(prov.size()); ++v)
        if (matches(v)) return true;
    return false;
}

/// "" when the defect names a place that exists: an input triangle or an output face in range;
/// every defect of the extractor names an input triangle; a checker defect of one element names
/// an input triangle, and for an output face or vertex that face and an output vertex's
/// triangle and grid point (`v`: the violation a checker defect came from).
inline std::string misplaced(const Input& in, const Result& r, const Defect& d, const Violation* v = nullptr) {
    const auto triangles = static_cast<std::int64_t>(in.triangles.size());
    const auto faces = static_cast<std::int64_t>(r.mesh.faces.size());
    const std::string what = std::string(to_string(d.kind)) + " '" + d.message + "'";
    if (d.input_element < -1 || d.input_element >= triangles) return what + ": input triangle out of range";
    if (d.output_face < -1 || d.output_face >= faces) return what + ": output face out of range";
    if (d.kind == DefectKind::NonQuadFace &&
        (d.output_face < 0 || r.mesh.faces[static_cast<std::size_t>(d.output_face)].size() == 4))
        return what + ": does not name a face with other than 4 vertices";
    // A refinement or coarsening names the first failure at scale 1, and a failed refinement its
    // own first, either of which may be one of the whole mesh; a best-effort mesh names no place.
    const bool rescaled = d.kind == DefectKind::MapRefined || d.kind == DefectKind::MapCoarsened ||
                          d.kind == DefectKind::RefinementFailed || d.kind == DefectKind::BestEffortMesh;
    if (d.kind != DefectKind::CheckerViolation)
        return d.input_element < 0 && !rescaled ? what + ": names no input triangle" : std::string();
    const ViolationElement element = element_kind(*d.violation);
    if (is_whole_mesh_violation(*d.violation) != (element == ViolationElement::None))
        return what + ": element_kind disagrees with the kind's scope";
    if (element == ViolationElement::None) return {};
    if (!v) return what + ": matches no violation of the check";
    if (v->element < 0) return {}; // the checker named no single element
    if (d.input_element < 0) return what + ": names no place";
    if (element == ViolationElement::OutputFace && d.output_face != v->element)
        return what + ": names face " + std::to_string(d.output_face) + ", the violation face " +
               std::to_string(v->element);
    if ((element == ViolationElement::OutputFace || element == ViolationElement::OutputVertex) &&
        !names_an_output_vertex(r, d))
        return what + ": its triangle and grid point are no output vertex's there";
    return {};
}

/// "" when every defect names a place (misplaced()) and is no explanation, and every
/// explanation is one and names an input triangle.
inline std::string place_inconsistency(const Input& in, const Result& r) {
    // The checker defects are the violations one to one and in order (verdict_inconsistency):
    // the k-th checker defect came from violation k.
    std::size_t k = 0;
    for (const Defect& d : r.report.defects) {
        if (is_explanation_kind(d.kind)) return std::string("an explanation among the defects: ") + d.message;
        const Violation* v = nullptr;
        if (d.violation) v = k < r.check.violations.size() ? &r.check.violations[k++] : nullptr;
        if (std::string why = misplaced(in, r, d, v); !why.empty()) return why;
    }
    for (const Defect& d : r.report.explanations) {
        if (!is_explanation_kind(d.kind) || d.violation)
            return std::string("a defect among the explanations: ") + d.message;
        if (std::string why = misplaced(in, r, d); !why.empty()) return why;
        if (d.output_face != -1) return "an explanation names an output face: " + d.message;
    }
    return {};
}

/// "" when a valid result keeps the area promise of Report::signed_uv_area and
/// Report::explanations, else what breaks it: a quad count below the signed UV area of the map
/// the mesh carries (sanitized and repaired; a repair keeps the area) has an explanation other
/// than MapRefined, MapCoarsened (which explain the scale, not a loss), HoleClosed and HoleFilled
/// (which add quads) or SheetsSeparated (which removes none); and once that map has no flipped or
/// degenerate triangle left (Report::flipped_after_repair == 0) and nothing is explained, the
/// quad count is that area, rounded. The promise is for maps without boundaries or whose
/// boundaries lie on iso-lines; the caller decides that it applies.
inline std::string area_inconsistency(const Result& r) {
    if (!r.ok() || !r.check.valid) return {};
    const auto quads = static_cast<std::int64_t>(r.mesh.faces.size());
    const std::int64_t area = std::llround(r.report.signed_uv_area);
    bool explained = false;
    for (const Defect& d : r.report.explanations)
        explained = explained || (d.kind != DefectKind::MapRefined && d.kind != DefectKind::MapCoarsened &&
                                  d.kind != DefectKind::HoleClosed && d.kind != DefectKind::HoleFilled &&
                                  d.kind != DefectKind::SheetsSeparated);
    const std::string about = std::to_string(quads) + " quads on a map of signed UV area " +
                              std::to_string(r.report.signed_uv_area) + " (rung " + r.report.rung + ", grid scale " +
                              std::to_string(r.mesh.grid_scale) + ", " + std::to_string(r.report.flipped_after_repair) +
                              " triangles flipped or degenerate after the repair)";
    if (quads < area && !explained) return "no explanation for " + about;
    if (r.report.flipped_after_repair == 0 && !explained && quads != area) return "a fold-free map gives " + about;
    return {};
}

/// Every invariant above on a successful extraction; `rerun` is verify(in, r.mesh) if the caller
/// has it already.
inline std::string result_inconsistency(const Input& in, const Result& r, const VerifyResult* rerun = nullptr) {
    if (!r.ok()) return "extraction failed: " + r.error.message;
    const VerifyResult own = rerun ? VerifyResult{} : verify(in, r.mesh);
    if (std::string why = verdict_inconsistency(in, r, rerun ? *rerun : own); !why.empty()) return why;
    return place_inconsistency(in, r);
}

} // namespace qex::testing

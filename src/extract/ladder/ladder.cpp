// A rung of the fallback ladder (its rungs as data: rungs.h; the order they run in: at_scale.cpp):
// its map, its run through the pipeline's stages in the order of the stage table (pipeline.h),
// each timed under its own name (from the map to the mesh: rung_stages.cpp), and the checker's
// verdict on the rung's mesh (mended where it is rejected: mend.cpp). The repair's look before its
// last ring is look.cpp's.
#include "look.h"

#include "extract/union_find.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <limits>
#include <optional>
#include <string>
#include <utility>

namespace qex::detail {

bool relaxed_rung(const std::string& name) {
    for (const Rung& r : kLadder)
        if (name == r.name) return r.untangle_rings > 0;
    return false;
}

// ============================================================================ a rung's map

namespace {

/// How boundary half-edge h lies to the integer iso-lines of its chart: on one exactly, on one
/// up to solver noise (both ends within the noise bound of the same integer in one coordinate),
/// or off them.
enum class OnIsoLine { Exactly, UpToNoise, Off };

OnIsoLine on_iso_line(const TriMesh& m, int h) {
    const Point2 &a = m.uv[h], &b = m.uv[TriMesh::next(h)];
    const double bound =
        solver_noise_bound(std::max({std::abs(a[0]), std::abs(a[1]), std::abs(b[0]), std::abs(b[1])}), m.noise_scale);
    OnIsoLine best = OnIsoLine::Off;
    for (int d = 0; d < 2; ++d) {
        const double line = std::nearbyint(a[d]);
        if (a[d] == line && b[d] == line) return OnIsoLine::Exactly;
        if (std::abs(a[d] - line) <= bound && std::abs(b[d] - line) <= bound && std::nearbyint(b[d]) == line)
            best = OnIsoLine::UpToNoise;
    }
    return best;
}

/// The boundary edges that follow iso-lines up to solver noise: every edge of each boundary loop
/// whose edges all lie on iso-lines, exactly or up to noise, with some up to noise (a rim that
/// crosses the grid, as a circle does, keeps its edges near a tangent iso-line as they are). The
/// exact ones too: an edge exactly on its iso-line can end at a corner of the loop whose other
/// coordinate is noisy, and only both edges as features put that corner on its grid point.
std::vector<int> noisy_aligned_boundary(const TriMesh& m) {
    const int nh = 3 * m.num_faces();
    UnionFind loops(static_cast<std::size_t>(m.num_vertices));
    std::vector<OnIsoLine> how(static_cast<std::size_t>(nh), OnIsoLine::Off);
    for (int h = 0; h < nh; ++h) {
        if (m.opp[h] >= 0) continue;
        how[static_cast<std::size_t>(h)] = on_iso_line(m, h);
        const int x = loops.find(m.origin(h)), y = loops.find(m.target(h));
        if (x != y) loops.attach(std::max(x, y), std::min(x, y));
    }
    std::vector<char> crosses(static_cast<std::size_t>(m.num_vertices), 0), noisy(crosses);
    for (int h = 0; h < nh; ++h) {
        if (m.opp[h] >= 0) continue;
        const auto loop = static_cast<std::size_t>(loops.find(m.origin(h)));
        crosses[loop] |= how[static_cast<std::size_t>(h)] == OnIsoLine::Off;
        noisy[loop] |= how[static_cast<std::size_t>(h)] == OnIsoLine::UpToNoise;
    }
    std::vector<int> out;
    for (int h = 0; h < nh; ++h) {
        const auto loop = static_cast<std::size_t>(loops.find(m.origin(h)));
        if (m.opp[h] < 0 && noisy[loop] && !crosses[loop]) out.push_back(h);
    }
    return out;
}

} // namespace

std::vector<std::array<int, 2>> feature_edges(const TriMesh& m, const Input& input, const Options& options) {
    std::vector<std::array<int, 2>> features = input.feature_edges;
    const auto add = [&](int h) { features.push_back({m.input_vertex[m.origin(h)], m.input_vertex[m.target(h)]}); };
    if (options.snap_boundary) {
        for (int h = 0; h < 3 * m.num_faces(); ++h)
            if (m.opp[h] < 0) add(h);
        return features;
    }
    // Without being asked: a boundary that follows iso-lines up to solver noise is snapped onto
    // them, as a seam within noise of a grid transition is rounded to it.
    for (const int h : noisy_aligned_boundary(m)) add(h);
    return features;
}

namespace {

/// A working mesh's map (`uv`, per working corner) per input corner: NaN for triangles
/// collapsed away; handed over as it is when no triangle was.
std::vector<std::array<double, 2>> per_input_corner(std::vector<Point2> uv, const std::vector<int>& input_triangle,
                                                    const Input& input) {
    bool same_numbering = input_triangle.size() == input.triangles.size();
    for (std::size_t f = 0; f < input_triangle.size() && same_numbering; ++f)
        same_numbering = input_triangle[f] == static_cast<int>(f);
    if (same_numbering) return uv;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    std::vector<std::array<double, 2>> map(input.uvs.size(), {nan, nan});
    for (std::size_t f = 0; f < input_triangle.size(); ++f)
        for (std::size_t k = 0; k < 3; ++k) map[3 * static_cast<std::size_t>(input_triangle[f]) + k] = uv[3 * f + k];
    return map;
}

} // namespace

std::vector<std::array<double, 2>> map_of(const TriMesh& m, const Input& input) {
    return per_input_corner(m.uv, m.input_triangle, input);
}

std::vector<std::array<double, 2>> take_map(TriMesh& m, const Input& input) {
    std::vector<Point2> uv = std::move(m.uv);
    std::vector<int> input_triangle = std::move(m.input_triangle);
    m = TriMesh{};
    return per_input_corner(std::move(uv), input_triangle, input);
}

namespace {

/// What the sanitized map tells the report: flipped and degenerate triangles, signed UV area.
void report_map(const TriMesh& m, Report& report) {
    double area2 = 0.0;
    for (int f = 0; f < m.num_faces(); ++f) {
        report.flipped_triangles += m.map.face_sign[f] < 0;
        report.degenerate_triangles += m.map.face_sign[f] == 0;
        const auto &a = m.uv[3 * f], &b = m.uv[3 * f + 1], &c = m.uv[3 * f + 2];
        area2 += (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    }
    report.signed_uv_area = 0.5 * area2;
}

/// What the repair leaves for the rung's stages after it: the triangles whose UVs it changed, the
/// mesh its look judged enough (if it stopped there), and the fold-overs it left.
struct Repaired {
    std::vector<int> faces;
    /// This rung's repair filled the memo of `scale` (it hands m over when done: keep_for_refinements).
    RepairMemo* memo = nullptr;
    std::optional<LookedMesh> looked;
    FoldsLeft folds;
};

/// Stages untangle (last resorts) to repair: the map, ready for extraction, and what the repair
/// leaves (`repaired`). `scale`: the attempt's refinement factor (solver noise is that many times
/// the map's own) and the repair kept for its refinements.
Error prepare_map(TriMesh& m, const Input& input, const Options& options, const Rung& rung, Report& report,
                  StageTimer& timer, Repaired& repaired, const AtScale& scale = {}) {
    m.noise_scale = static_cast<double>(scale.factor);
    if (rung.untangle_rings > 0) {
        compute_transitions(m);
        count_valences(m);
        (void)untangle(m, rung.untangle_rings, rung.untangle_iterations);
        timer.done(Stage::untangle);
    }
    const std::vector<std::array<int, 2>> features = feature_edges(m, input, options);
    const SeamPolicy seams = rung.untangle_rings > 0 || scale.seams_checked ? SeamPolicy::Trusted
                             : options.round_inconsistent_seams             ? SeamPolicy::Rounded
                                                                            : SeamPolicy::Checked;
    if (Error e = sanitize_until_stable(m, input, features, report, timer, kMaxSanitizeRounds, seams);
        e.code != ErrorCode::None)
        return e;
    count_valences(m, true); // on the sanitized map, for lost-edge detection at singularities
    if (!input.valences.empty())
        for (int v = 0; v < m.num_vertices; ++v) m.map.valence[v] = input.valences[m.input_vertex[v]];
    timer.done(Stage::count_valences);
    report_map(m, report);
    timer.done(Stage::sanitize);
    // The input is valid: the checker's analysis beside the repair and the extraction. Not beside
    // the stages before: their loops run on every core, and a thread more stalled them (duck_miq_8's
    // transitions took 3.9 ms with it beside, 1.4 ms without).
    if (scale.checked) scale.checked->start();
    if (rung.repair && report.flipped_triangles + report.degenerate_triangles > 0) {
        const LookBeforeLastRing look = [&](const TriMesh& so_far, const RepairOutcome& outcome) {
            return look_so_far(so_far, outcome, input, options, rung, report, scale.checked, repaired.looked);
        };
        RepairOutcome outcome =
            repair_at_scale(m, features, !input.valences.empty(), options.threads, scale, report, look);
        // At the map's own scale only this repair fills the memo; a refinement reads it.
        if (scale.factor == 1 && scale.memo && scale.memo->filled) repaired.memo = scale.memo;
        explain_unrepaired(m, outcome, report);
        repaired.folds = folds_left(m, outcome);
        if (outcome.changed_after_look) repaired.looked.reset();
        report.repaired_regions = outcome.regions_repaired;
        report.unrepaired_regions = static_cast<std::int64_t>(outcome.unrepaired.size());
        report.repaired_triangles = static_cast<std::int64_t>(outcome.repaired_faces.size());
        for (int f = 0; f < m.num_faces(); ++f) report.flipped_after_repair += m.map.face_sign[f] <= 0;
        repaired.faces = std::move(outcome.repaired_faces);
        timer.done(Stage::repair);
    } else {
        report.flipped_after_repair = report.flipped_triangles + report.degenerate_triangles;
    }
    return {};
}

} // namespace

// ============================================================================ shared with the look (look.h)

void order_faces(const Options& options, FaceWalks faces, Result& result) {
    if (options.canonical_order) {
        const std::vector<int> new_index = canonicalize(result.mesh, std::move(faces), thread_count(options.threads));
        for (Defect& d : result.report.defects)
            if (d.output_face >= 0) d.output_face = new_index[static_cast<std::size_t>(d.output_face)];
    } else {
        set_faces(result.mesh, faces);
    }
}

std::vector<std::int32_t> certificate_of(const TriMesh& m, const std::vector<int>& repaired_faces) {
    std::vector<std::int32_t> certificate;
    for (const int f : repaired_faces) certificate.push_back(m.input_triangle[f]);
    std::sort(certificate.begin(), certificate.end());
    return certificate;
}

// ============================================================================ a rung's steps, for at_scale.cpp

Error prepare_mesh(const Input& input, const Options& options, TriMesh& m, Report& report) {
    StageTimer timer(report);
    if (Error e = validate(input, thread_count(options.threads), m); e.code != ErrorCode::None) return e;
    timer.done(Stage::validate);
    if (Error e = collapse(m, report.collapsed_edges); e.code != ErrorCode::None) return e;
    timer.done(Stage::collapse);
    return {};
}

bool run_rung(TriMesh m, const Input& input, const Options& options, const Rung& rung, Result& result,
              const AtScale& scale, bool* judged) {
    Report& report = result.report;
    StageTimer timer(report);
    Repaired repaired;
    struct HandOver { // however the rung ends, the memo its repair filled gets the connectivity
        TriMesh& m;
        const Repaired& repaired;
        ~HandOver() {
            try {
                if (repaired.memo) keep_for_refinements(m, *repaired.memo);
            } catch (...) { // out of memory: the memo stays without them, and no refinement takes it
            }
        }
    } hand_over{m, repaired};
    if ((result.error = prepare_map(m, input, options, rung, report, timer, repaired, scale)).code != ErrorCode::None)
        return false;
    if (rung.repair && repaired.faces.empty()) report.rung = "as-given"; // nothing to repair: the map as given
    std::optional<LookedMesh>& looked = repaired.looked;
    const bool as_looked = judged && looked;
    const Report* ran_inside = nullptr; // the look's stage times that ran inside the repair's: all of them
    if (as_looked && looked->beside) { // the last ring changed nothing: the look's mesh judged beside it
        JudgedBeside& beside = *looked->beside;
        beside.done.get(); // what the judge threw, thrown here
        if (StageTimer::hook)
            for (const char* stage : beside.heard) (*StageTimer::hook)(stage, StageTimer::hook_scale);
        looked->result = std::move(beside.result), looked->judged = true, ran_inside = &beside.made;
    }
    if (as_looked && looked->judged) {
        take_looked(std::move(looked->result), result, ran_inside);
        name_losses(m, repaired.folds, report);
        *judged = true;
        return true;
    }
    std::vector<std::int32_t> certificate = certificate_of(m, repaired.faces);
    FaceWalks faces;
    if (as_looked) { // the last ring changed nothing: the look's extraction is this map's
        faces = std::move(looked->faces);
        take_looked(std::move(looked->result), result);
    } else if ((result.error = extract_mesh(m, options, result, timer, faces)).code != ErrorCode::None) {
        return false;
    }
    looked.reset();
    name_losses(m, repaired.folds, report);
    if (repaired.memo) keep_for_refinements(m, *repaired.memo); // before take_map empties m
    result.mesh.map_uvs = take_map(m, input);
    result.mesh.map_repaired = std::move(certificate);
    order_faces(options, std::move(faces), result);
    timer.done(Stage::canonicalize);
    return true;
}

void judge(const Input& input, const Options& options, const Rung& rung,
           const std::vector<std::array<double, 2>>& given_map, Result& attempt, CheckedInput* checked) {
    StageTimer timer(attempt.report);
    const bool relaxed = rung.untangle_rings > 0;
    MapGraph graph(input); // the placement's map is the mesh's then, which mending searches too
    if (relaxed && !given_map.empty()) {
        // Every vertex moves onto its grid point in the given (sanitized) map, so the mesh is
        // judged against that map.
        attempt.report.unplaced_vertices = place_on_given_map(graph, given_map, attempt.mesh);
        timer.done(Stage::place_on_given_map);
    }
    VerifyOptions verify_options;
    verify_options.threads = options.threads;
    if (checked) verify_options.prepared = &checked->get();
    attempt.check = verify(input, attempt.mesh, verify_options);
    timer.done(Stage::check);
    if (!attempt.check.valid) mend_if_accepted(input, relaxed, verify_options, timer, attempt, &graph);
    if (relaxed && attempt.check.valid) {
        // And it must pass the oracle that judges it against the given map alone (as
        // `qex check` would), everywhere, or the rung is rejected.
        for (const Violation& v : located_violations(input, attempt.mesh, verify_options, false))
            attempt.check.violations.push_back(
                {v.kind, v.message + " (against the given map; this rung relaxed it)", v.element});
        attempt.check.valid = attempt.check.violations.empty();
    } else if (attempt.check.valid && attempt.report.near_ghost_faces_cancelled > 0) {
        // Merged clones of two sheets take one clone's place: the faces round it must still join
        // neighbouring grid points on the given map, as `qex check --param` judges (fold-over
        // regions on the surface only).
        for (const Violation& v : located_violations(input, attempt.mesh, verify_options, true))
            attempt.check.violations.push_back(
                {v.kind, v.message + " (against the given map, without provenance; clones of two sheets were merged)",
                 v.element});
        attempt.check.valid = attempt.check.violations.empty();
    }
    attempt.report.check_violations = static_cast<std::int64_t>(attempt.check.violations.size());
    timer.done(Stage::check);
}

Result start_attempt(const Report& prepared, int r, int tried) {
    Result attempt;
    Report& report = attempt.report;
    report.input_vertices = prepared.input_vertices;
    report.input_triangles = prepared.input_triangles;
    report.stage_seconds = prepared.stage_seconds;
    report.collapsed_edges = prepared.collapsed_edges;
    report.rung = kLadder[r].name;
    report.rungs_tried = tried;
    return attempt;
}

bool sanitize_as_given(const Input& input, const Options& options, TriMesh& m, Report& report) {
    Report own;
    if (prepare_mesh(input, options, m, own).code != ErrorCode::None) return false;
    StageTimer timer(own);
    Repaired unused; // the as-given rung repairs nothing
    const bool ok = prepare_map(m, input, options, kLadder[kAsGiven], own, timer, unused).code == ErrorCode::None;
    add_stage_seconds(own, report);
    return ok;
}

void add_stage_seconds(const Report& from, Report& to) {
    for (const auto& [name, seconds] : from.stage_seconds) {
        const std::string& stage = name; // clang before 16 cannot capture a structured binding
        auto it = std::find_if(to.stage_seconds.begin(), to.stage_seconds.end(),
                               [&](const auto& entry) { return entry.first == stage; });
        if (it == to.stage_seconds.end())
            to.stage_seconds.emplace_back(name, seconds);
        else
            it->second += seconds;
    }
}

} // namespace qex::detail

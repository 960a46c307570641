// The fallback ladder at one scale: its rungs as data (kLadder: the order they are tried in), a
// rung run through the pipeline's stages in the order of the stage table (pipeline.h), each timed
// under its own name (from the map to the mesh: rung_stages.cpp), and the checker's verdict on the
// rung's mesh (mended where it is rejected: mend.cpp).
#include "ladder.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <limits>
#include <string>

namespace qex::detail {
namespace {

// ============================================================================ the rungs

/// A rung of the fallback ladder: how it prepares the map before the pipeline's stages run on
/// it. Each rung re-runs the pipeline from the validated, collapsed mesh.
struct Rung {
    const char* name;   ///< its name in Report::rung
    bool repair;        ///< stage repair runs (certified: the mesh carries the repaired map)
    int untangle_rings; ///< > 0: stage untangle relaxes the map first (uncertified)
    int untangle_iterations;
};

/// The fallback ladder: its rungs in the order extract_at_scale tries them, until the checker
/// accepts one's mesh. The certified rungs come first. Every later rung changes only the
/// flipped and degenerate regions of the map, so on a map without any the first verdict stands.
constexpr Rung kLadder[] = {
    // 1. The sanitized map with its fold-over regions re-embedded (certified), then the paper's
    //    method. First: on a map without fold-overs it is the paper's method on the map as given
    //    (reported as the as-given rung), and on one with fold-overs the repair's certificate
    //    lets the checker verify the mesh against the repaired map.
    {"repaired", true, 0, 0},
    // 2. The paper's method, and its local handling of fold-overs, on the map as given. Second:
    //    where the repaired map's mesh is rejected, the paper's own handling may still give a
    //    valid one. Skipped when the repair changed nothing (rung 1 was this rung); the first
    //    rung without Options::repair_fold_overs.
    {"as-given", false, 0, 0},
    // 3, 4. Last resorts without a certificate: relax the folded regions (one ring, then three),
    //    extract, and move the mesh back onto the given map, where the checker must accept it.
    //    Last: they need the as-given rung's sanitized map to move the mesh onto, and their mesh
    //    must pass the checker against it everywhere; one ring first, as it moves the fewest
    //    vertices.
    {"untangled-1", false, 1, 30},
    {"untangled-3", false, 3, 100},
};

/// The as-given rung: the first without Options::repair_fold_overs, and the one whose sanitized
/// map the relaxed rungs' meshes are moved onto and coarsening divides.
constexpr int kAsGiven = 1;
static_assert(!kLadder[kAsGiven].repair && kLadder[kAsGiven].untangle_rings == 0, "the map as given");

} // namespace

bool relaxed_rung(const std::string& name) {
    for (const Rung& r : kLadder)
        if (name == r.name) return r.untangle_rings > 0;
    return false;
}

// ============================================================================ a rung's map

std::vector<std::array<int, 2>> feature_edges(const TriMesh& m, const Input& input, const Options& options) {
    std::vector<std::array<int, 2>> features = input.feature_edges;
    if (options.snap_boundary)
        for (int h = 0; h < 3 * m.num_faces(); ++h)
            if (m.opp[h] < 0) features.push_back({m.input_vertex[m.origin(h)], m.input_vertex[m.target(h)]});
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

/// The map of m per input corner, a copy (take_map hands it over).
std::vector<std::array<double, 2>> map_of(const TriMesh& m, const Input& input) {
    return per_input_corner(m.uv, m.input_triangle, input);
}

} // namespace

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

/// Stages validate and collapse (Section 3): the input's, before any rung changes the map.
Error prepare_mesh(const Input& input, const Options& options, TriMesh& m, Report& report) {
    StageTimer timer(report);
    if (Error e = validate(input, thread_count(options.threads), m); e.code != ErrorCode::None) return e;
    timer.done(Stage::validate);
    if (Error e = collapse(m, report.collapsed_edges); e.code != ErrorCode::None) return e;
    timer.done(Stage::collapse);
    return {};
}

/// The repair's look before its last ring (repair.h) at the rung's mesh from m as the repair
/// left it so far (`outcome`): enough when that mesh is valid with as many quads as the map's
/// signed UV area (`report`'s); when it has fewer and its extraction no defect, the vertices
/// round where it lost them (place_vertices).
RepairLook look_so_far(const TriMesh& m, const RepairOutcome& outcome, const Input& input, const Options& options,
                       const Rung& rung, const Report& report);

/// Stages untangle (last resorts) to repair: the map, ready for extraction. `repaired_faces`: the
/// triangles whose UVs the repair changed. `scale`: the attempt's refinement factor (solver
/// noise is that many times the map's own) and the repair kept for its refinements.
Error prepare_map(TriMesh& m, const Input& input, const Options& options, const Rung& rung, Report& report,
                  StageTimer& timer, std::vector<int>& repaired_faces, const AtScale& scale = {}) {
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
    if (rung.repair && report.flipped_triangles + report.degenerate_triangles > 0) {
        const LookBeforeLastRing look = [&](const TriMesh& so_far, const RepairOutcome& outcome) {
            return look_so_far(so_far, outcome, input, options, rung, report);
        };
        RepairOutcome outcome =
            repair_at_scale(m, features, !input.valences.empty(), options.threads, scale, report, look);
        explain_unrepaired(m, outcome, report);
        report.repaired_regions = outcome.regions_repaired;
        report.unrepaired_regions = static_cast<std::int64_t>(outcome.unrepaired.size());
        report.repaired_triangles = static_cast<std::int64_t>(outcome.repaired_faces.size());
        for (int f = 0; f < m.num_faces(); ++f) report.flipped_after_repair += m.map.face_sign[f] <= 0;
        repaired_faces = std::move(outcome.repaired_faces);
        timer.done(Stage::repair);
    } else {
        report.flipped_after_repair = report.flipped_triangles + report.degenerate_triangles;
    }
    return {};
}

// ============================================================================ a rung's stages

/// The repair's certificate: the triangles it changed (working indices), by input index, sorted.
std::vector<std::int32_t> certificate_of(const TriMesh& m, const std::vector<int>& repaired_faces) {
    std::vector<std::int32_t> certificate;
    for (const int f : repaired_faces) certificate.push_back(m.input_triangle[f]);
    std::sort(certificate.begin(), certificate.end());
    return certificate;
}

/// One rung on the validated, collapsed mesh `m`, up to stage canonicalize. Returns false on an
/// input error (in result.error), which no rung can help.
bool run_rung(TriMesh m, const Input& input, const Options& options, const Rung& rung, Result& result,
              const AtScale& scale) {
    Report& report = result.report;
    StageTimer timer(report);
    std::vector<int> repaired_faces;
    if ((result.error = prepare_map(m, input, options, rung, report, timer, repaired_faces, scale)).code !=
        ErrorCode::None)
        return false;
    std::vector<std::int32_t> certificate = certificate_of(m, repaired_faces);
    if (rung.repair && repaired_faces.empty()) report.rung = "as-given"; // nothing to repair: the map as given
    FaceWalks faces;
    if ((result.error = extract_mesh(m, options, result, timer, faces)).code != ErrorCode::None) return false;
    result.mesh.map_uvs = take_map(m, input);
    result.mesh.map_repaired = std::move(certificate);
    if (options.canonical_order) {
        const std::vector<int> new_index = canonicalize(result.mesh, std::move(faces), thread_count(options.threads));
        for (Defect& d : report.defects)
            if (d.output_face >= 0) d.output_face = new_index[static_cast<std::size_t>(d.output_face)];
    } else {
        set_faces(result.mesh, faces);
    }
    timer.done(Stage::canonicalize);
    return true;
}

// ============================================================================ the verdict on a rung's mesh

/// Stages place_on_given_map (last resorts) and check: the checker's verdict on the rung's mesh,
/// against the map it carries (with the repair's certificate, which the checker verifies on its
/// own). A relaxed rung's mesh is moved onto the given map and must pass there.
void judge(const Input& input, const Options& options, const Rung& rung,
           const std::vector<std::array<double, 2>>& given_map, Result& attempt) {
    StageTimer timer(attempt.report);
    const bool relaxed = rung.untangle_rings > 0;
    if (relaxed && !given_map.empty()) {
        // Every vertex moves onto its grid point in the given (sanitized) map, so the mesh is
        // judged against that map.
        attempt.report.unplaced_vertices = place_on_given_map(input, given_map, attempt.mesh);
        timer.done(Stage::place_on_given_map);
    }
    VerifyOptions verify_options;
    verify_options.threads = options.threads;
    attempt.check = verify(input, attempt.mesh, verify_options);
    timer.done(Stage::check);
    if (!attempt.check.valid) mend_if_accepted(input, relaxed, verify_options, timer, attempt);
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

RepairLook look_so_far(const TriMesh& m, const RepairOutcome& outcome, const Input& input, const Options& options,
                       const Rung& rung, const Report& report) {
    Result attempt;
    attempt.report.signed_uv_area = report.signed_uv_area;
    StageTimer timer(attempt.report);
    FaceWalks faces;
    if (extract_mesh(m, options, attempt, timer, faces).code != ErrorCode::None) return {};
    set_faces(attempt.mesh, faces);
    const std::int64_t area = std::llround(report.signed_uv_area);
    const auto quads = static_cast<std::int64_t>(attempt.mesh.faces.size());
    // A cell covered twice is not located, nor is what went wrong in an extraction with defects:
    // the last ring goes everywhere.
    if (quads > area || !attempt.report.defects.empty()) return {};
    RepairLook look;
    if (quads == area) {
        attempt.mesh.map_uvs = map_of(m, input);
        attempt.mesh.map_repaired = certificate_of(m, outcome.repaired_faces);
        judge(input, options, rung, {}, attempt);
        look.enough = attempt.check.valid && static_cast<std::int64_t>(attempt.mesh.faces.size()) == area;
        return look;
    }
    // Fewer quads, and no defect: where they were lost, by the explanations that name a place (one
    // that names none sends the last ring everywhere). Not judged here (the checker's memory on
    // top of the repair's would raise the peak); the rung's mesh is judged as ever.
    std::vector<int> working(input.triangles.size(), -1);
    for (int f = 0; f < m.num_faces(); ++f) working[static_cast<std::size_t>(m.input_triangle[f])] = f;
    for (const Defect& d : attempt.report.explanations) {
        const int f = d.input_element >= 0 ? working[static_cast<std::size_t>(d.input_element)] : -1;
        if (f < 0) return {};
        place_vertices(m, f, d.grid, look.near);
    }
    return look;
}

/// A fresh result for rung `r`, with what stages validate and collapse reported, and the stage
/// times so far (the rungs before it included).
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

} // namespace

// ============================================================================ the ladder at one scale

Result extract_at_scale(const Input& input, const Options& options, const AtScale& scale, Result* fillable) {
    Result prepared;
    prepared.report.input_vertices = static_cast<std::int64_t>(input.positions.size());
    prepared.report.input_triangles = static_cast<std::int64_t>(input.triangles.size());
    TriMesh m;
    if ((prepared.error = prepare_mesh(input, options, m, prepared.report)).code != ErrorCode::None) return prepared;
    // The ladder: the first rung whose output the checker accepts wins; if none does, the rung
    // with the fewest violations is returned, its defects and violations in the report.
    const int first = options.repair_fold_overs ? 0 : kAsGiven;
    const int rungs = options.fallback_ladder ? static_cast<int>(std::size(kLadder)) : first + 1;
    Result best;
    std::size_t best_violations = SIZE_MAX;
    std::vector<std::array<double, 2>> given_map; // the as-given rung's sanitized map
    std::vector<Defect> proofs;                   // what the repair proved, for a later rung's mesh
    for (int r = first; r < rungs; ++r) {
        // The first rung takes the prepared mesh; a later rung (rarely needed) prepares it again
        // rather than every run paying for a copy. Preparing succeeded once, so it does again.
        // Its time, like every rung's, is added to the stages' totals.
        if (r > first) {
            Report again;
            again.stage_seconds = std::move(prepared.report.stage_seconds);
            (void)prepare_mesh(input, options, m, again);
            prepared.report.stage_seconds = std::move(again.stage_seconds);
        }
        Result attempt = start_attempt(prepared.report, r, r - first + 1);
        if (!run_rung(std::move(m), input, options, kLadder[r], attempt, scale)) return attempt;
        judge(input, options, kLadder[r], given_map, attempt);
        prepared.report.stage_seconds = attempt.report.stage_seconds; // this rung's and all before
        // A later rung's mesh: the repair's proofs say why the certified rung could not remove the
        // folds (they hold of the map, whichever rung's mesh stands or is mended).
        if (kLadder[r].repair) {
            for (const Defect& d : attempt.report.explanations)
                if (is_proof(d.kind)) proofs.push_back(d);
        } else {
            auto& explanations = attempt.report.explanations;
            explanations.insert(explanations.begin(), proofs.begin(), proofs.end());
        }
        if (attempt.check.valid) return attempt;
        // The last resort's other candidate: the first rung whose mesh lost only its topology,
        // with a hole or sheets joined at an edge (what it mends; another rung may have fewer
        // violations, of other kinds).
        if (fillable && options.fill_holes && fillable->report.rung.empty() && topology_only(attempt.check.violations))
            *fillable = attempt;
        // A repair that changed nothing had the map as given: the next rung would repeat it.
        const bool as_given = kLadder[r].untangle_rings == 0 && attempt.report.repaired_triangles == 0;
        if (as_given) given_map = attempt.mesh.map_uvs;
        // The further rungs change only flipped or degenerate regions: without any, they would
        // repeat this one.
        const bool another_map = attempt.report.flipped_triangles + attempt.report.degenerate_triangles > 0;
        if (attempt.check.violations.size() < best_violations) {
            best_violations = attempt.check.violations.size();
            best = std::move(attempt);
        }
        best.report.rungs_tried = r - first + 1;
        if (!another_map) break;
        if (kLadder[r].repair && as_given) ++r; // skip the as-given rung
    }
    best.report.stage_seconds = std::move(prepared.report.stage_seconds);
    // No rung gave a valid mesh: locate every violation on the input through the provenance.
    locate_violations(input, best);
    return best;
}

bool sanitize_as_given(const Input& input, const Options& options, TriMesh& m, Report& report) {
    Report own;
    if (prepare_mesh(input, options, m, own).code != ErrorCode::None) return false;
    StageTimer timer(own);
    std::vector<int> unused;
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

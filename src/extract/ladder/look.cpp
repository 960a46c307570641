// The repair's look before its last ring (look.h): the rung's mesh extracted from the map as the
// repair left it so far, judged there where it has as many quads as the area, and beside the last
// ring where it has fewer.
#include "look.h"

#include <cmath>
#include <cstdint>
#include <functional>
#include <future>
#include <memory>
#include <system_error>
#include <utility>

namespace qex::detail {
namespace {

/// Maps up to this many triangles judge the look's mesh beside the last ring: the checker's memory
/// then comes on top of the repair's, 0.4-1 MB on the paper's ducks (duck_qc_8 0.95x, duck_miq_28
/// 0.97x in process), but 11 MB (8%) on duck_miq_8 subdivided twice, where the check is a small
/// share of the run and the wall time was the same.
constexpr std::int64_t kJudgeBesideMaxTriangles = std::int64_t{1} << 16;

/// Moves the look's mesh (looked.result, its faces looked.faces) into a job that makes it as the
/// rung's own and judges it on a thread of one core's share, into looked.beside; where no thread
/// can be had, the judging is deferred to when the rung takes it. Not for large maps (the rung
/// then judges as ever). The judge reads only its copy, the input and the checker's prepared
/// input; the stages it times are heard by the caller's progress hook when the rung takes it.
template <class Make>
void judge_beside(const TriMesh& m, LookedMesh& looked, const Make& make_as_rungs, const Input& input,
                  const Options& options, const Rung& rung, CheckedInput* checked) {
    const auto triangles = static_cast<std::int64_t>(m.num_faces());
    if (!run_parallel(thread_count(options.threads), 3 * triangles) || triangles > kJudgeBesideMaxTriangles) return;
    auto job = std::make_unique<JudgedBeside>();
    job->result = std::move(looked.result); // with the extraction's stage times, which ran inside the repair's
    StageTimer clock(job->result.report);
    make_as_rungs(job->result, std::move(looked.faces), clock);
    job->made = job->result.report;
    Options one = options;
    one.threads = 1; // beside the last ring's attempts, which have the cores
    one.on_stage = nullptr;
    JudgedBeside* const j = job.get();
    const auto judging = [=, &input, &rung] {
        const std::function<void(const char*, int)> heard = [j](const char* stage, int) { j->heard.push_back(stage); };
        const auto* const hook = StageTimer::hook;
        StageTimer::hook = &heard;
        struct Restore {
            const std::function<void(const char*, int)>* hook;
            ~Restore() { StageTimer::hook = hook; }
        } restore{hook};
        judge(input, one, rung, {}, j->result, checked);
    };
    try {
        job->done = std::async(std::launch::async, judging);
    } catch (const std::system_error&) {
        job->done = std::async(std::launch::deferred, judging);
    }
    looked.beside = std::move(job);
}

} // namespace

RepairLook look_so_far(const TriMesh& m, const RepairOutcome& outcome, const Input& input, const Options& options,
                       const Rung& rung, const Report& report, CheckedInput* checked,
                       std::optional<LookedMesh>& looked) {
    Result attempt;
    attempt.report.signed_uv_area = report.signed_uv_area;
    StageTimer timer(attempt.report);
    FaceWalks faces;
    if (extract_mesh(m, options, attempt, timer, faces).code != ErrorCode::None) return {};
    const std::int64_t area = std::llround(report.signed_uv_area);
    const auto quads = static_cast<std::int64_t>(faces.size());
    // A cell covered twice is not located, nor is what went wrong in an extraction with defects:
    // the last ring goes everywhere (and the rung may still take this extraction).
    const bool everywhere = quads > area || !attempt.report.defects.empty();
    RepairLook look;
    // The mesh as the rung's own would be: the map as it stands, its certificate, its faces in order.
    const auto make_as_rungs = [&](Result& made, FaceWalks walks, StageTimer& clock) {
        made.mesh.map_uvs = map_of(m, input);
        made.mesh.map_repaired = certificate_of(m, outcome.repaired_faces);
        order_faces(options, std::move(walks), made);
        clock.done(Stage::canonicalize);
    };
    if (quads == area && !everywhere) {
        make_as_rungs(attempt, std::move(faces), timer);
        judge(input, options, rung, {}, attempt, checked);
        look.enough = attempt.check.valid && static_cast<std::int64_t>(attempt.mesh.faces.size()) == area;
        looked = LookedMesh{std::move(attempt), {}, true, nullptr};
        return look;
    }
    // Fewer quads, and no defect: where they were lost, by the explanations that name a place (one
    // that names none sends the last ring everywhere, as a defect or a cell covered twice does).
    // Judged beside the last ring where the map is small (as any extraction the look did not judge:
    // more quads than the area, or defects, too): it is the rung's where that ring changes nothing.
    set_faces(attempt.mesh, faces);
    if (!everywhere) {
        std::vector<int> working(input.triangles.size(), -1);
        for (int f = 0; f < m.num_faces(); ++f) working[static_cast<std::size_t>(m.input_triangle[f])] = f;
        for (const Defect& d : attempt.report.explanations) {
            const int f = d.input_element >= 0 ? working[static_cast<std::size_t>(d.input_element)] : -1;
            if (f < 0) {
                look.near.clear();
                break;
            }
            place_vertices(m, f, d.grid, look.near);
        }
    }
    looked = LookedMesh{std::move(attempt), std::move(faces), false, nullptr};
    judge_beside(m, *looked, make_as_rungs, input, options, rung, checked);
    return look;
}

void take_looked(Result looked, Result& result, const Report* ran_inside) {
    Report &to = result.report, &from = looked.report;
    for (const auto& [name, seconds] : (ran_inside ? *ran_inside : from).stage_seconds)
        for (auto& [stage, total] : to.stage_seconds)
            if (stage == "repair") total -= seconds;
    add_stage_seconds(from, to);
    to.qvertices_on_vertices = from.qvertices_on_vertices, to.qvertices_on_edges = from.qvertices_on_edges;
    to.qvertices_in_faces = from.qvertices_in_faces, to.ports = from.ports, to.traces = from.traces;
    to.traces_connected = from.traces_connected, to.traces_failed = from.traces_failed;
    to.traces_into_boundary = from.traces_into_boundary, to.faces_traced = from.faces_traced;
    to.orientation_flips_crossed = from.orientation_flips_crossed, to.open_face_walks = from.open_face_walks;
    to.non_quad_faces = from.non_quad_faces, to.collapsed_faces = from.collapsed_faces;
    to.recovered_edges = from.recovered_edges, to.merged_qvertices = from.merged_qvertices;
    to.ghost_faces_cancelled = from.ghost_faces_cancelled;
    to.near_ghost_faces_cancelled = from.near_ghost_faces_cancelled;
    to.boundary_faces_discarded = from.boundary_faces_discarded, to.check_violations = from.check_violations;
    to.defects.insert(to.defects.end(), from.defects.begin(), from.defects.end());
    to.explanations.insert(to.explanations.end(), from.explanations.begin(), from.explanations.end());
    result.mesh = std::move(looked.mesh);
    result.check = std::move(looked.check);
}

} // namespace qex::detail

// The fallback ladder at one scale: which rungs run, and which mesh stands.
//
// The first rung runs alone, with every thread: on most maps its mesh stands. Where the checker
// rejects it and the map has fold-overs, the later rungs run side by side, each on a copy of the
// prepared mesh with its share of the threads; a relaxed rung waits for the as-given rung's map
// only to be judged on it. Their verdicts are then read in the ladder's order, as if the rungs
// had run one after another, so the mesh that stands is the serial one, bit for bit, for any
// thread count. A rung the serial ladder would not have reached costs a core, not wall time; on
// one thread the rungs run in the ladder's order and stop where the reading would.
#include "rungs.h"

#include "../parallel.h"

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <exception>
#include <future>
#include <iterator>
#include <mutex>
#include <optional>
#include <system_error>
#include <thread>
#include <utility>
#include <vector>

namespace qex::detail {
namespace {

/// What reading the rungs' verdicts in the ladder's order keeps.
struct Standing {
    Result best;
    std::size_t best_violations = SIZE_MAX;
    std::vector<Defect> proofs; ///< what the repair proved, for a later rung's mesh
    Report totals;              ///< the stage times of the rungs read so far
};

/// Whether a copy of the prepared mesh is kept for the later rungs (without one they prepare the
/// mesh again, to the same mesh). Only where a later rung could run (a triangle not positive in
/// double precision: sanitizing only rounds a map by noise, so without one the first rung is the
/// last), and only where preparing collapsed edges. A copy costs about what preparing a mesh
/// without collapses does (the paper's ducks: 1.5 ms of a 38 ms run, mostly its fresh pages),
/// and most maps with fold-overs end at the first rung; collapsing is what makes preparing long
/// (armadillo_geo_180: 47 ms), and 8 of the 9 shared maps that reach the later rungs collapse.
bool keep_prepared_copy(const TriMesh& m, const Report& prepared) {
    if (prepared.collapsed_edges == 0) return false;
    for (int f = 0; f < m.num_faces(); ++f) {
        const Point2 &a = m.uv[3 * f], &b = m.uv[3 * f + 1], &c = m.uv[3 * f + 2];
        if (!((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]) > 0)) return true;
    }
    return false;
}

/// Reads rung r's attempt in the ladder's order. Returns true when its mesh stands (the checker
/// accepted it); otherwise keeps it if it has the fewest violations so far.
bool read_verdict(int r, int first, const Options& options, Result& attempt, Standing& st, Result* fillable) {
    add_stage_seconds(attempt.report, st.totals);
    attempt.report.stage_seconds = st.totals.stage_seconds; // this rung's and all before
    // A later rung's mesh: the repair's proofs say why the certified rung could not remove the
    // folds (they hold of the map, whichever rung's mesh stands or is mended).
    if (kLadder[r].repair) {
        for (const Defect& d : attempt.report.explanations)
            if (is_proof(d.kind)) st.proofs.push_back(d);
    } else {
        auto& explanations = attempt.report.explanations;
        explanations.insert(explanations.begin(), st.proofs.begin(), st.proofs.end());
    }
    if (attempt.check.valid) return true;
    // The last resort's other candidate: the first rung whose mesh lost only its topology,
    // with a hole or sheets joined at an edge (what it mends; another rung may have fewer
    // violations, of other kinds).
    if (fillable && options.fill_holes && fillable->report.rung.empty() && topology_only(attempt.check.violations))
        *fillable = attempt;
    if (attempt.check.violations.size() < st.best_violations) {
        st.best_violations = attempt.check.violations.size();
        st.best = std::move(attempt);
    }
    st.best.report.rungs_tried = r - first + 1;
    return false;
}

/// The further rungs change only flipped or degenerate regions: without any, they would repeat
/// this one.
bool another_map(const Result& attempt) {
    return attempt.report.flipped_triangles + attempt.report.degenerate_triangles > 0;
}

/// The order the workers take the rungs of `order` in (positions in it): on one thread the
/// ladder's. On several, the as-given rung first (the relaxed rungs are judged on its map), then
/// the other rungs, the most untangling first: it is the longest (on armadillo_geo_180 untangled-3
/// took 391 ms and untangled-1 221), so it starts at once on its own thread rather than after
/// another rung.
std::vector<std::size_t> taking_order(const std::vector<int>& order, int workers) {
    std::vector<std::size_t> queue(order.size());
    for (std::size_t i = 0; i < queue.size(); ++i) queue[i] = i;
    if (workers == 1) return queue;
    const auto key = [&](std::size_t i) { return order[i] == kAsGiven ? -1 : -kLadder[order[i]].untangle_rings; };
    std::stable_sort(queue.begin(), queue.end(), [&](std::size_t x, std::size_t y) { return key(x) < key(y); });
    return queue;
}

/// Whether the ladder's reading (extract_at_scale) stops at a rung's attempt: an input error, a
/// mesh that stands, or a map no later rung changes.
bool reading_stops(const Result& attempt, bool ok) { return !ok || attempt.check.valid || !another_map(attempt); }

/// Runs the rungs `order` (ascending) on copies of `base`, side by side on up to the options'
/// threads, into `out` (`ok`: run_rung's verdict). `given`: the as-given rung's sanitized map,
/// when the first rung was that rung; else the as-given rung among `order` publishes it. On one
/// thread the rungs run in the ladder's order, up to the first the reading stops at.
void run_side_by_side(const Input& input, const Options& options, const AtScale& scale, const TriMesh& base,
                      const Report& prepared, int first, const std::vector<int>& order,
                      std::vector<std::array<double, 2>> given, std::vector<Result>& out, std::vector<char>& ok) {
    const int threads = thread_count(options.threads);
    const int workers = std::max(1, std::min(threads, static_cast<int>(order.size())));
    Options inner = options;
    inner.threads = std::max(1, threads / workers);
    std::promise<void> promised;
    const std::shared_future<void> ready = promised.get_future().share();
    std::once_flag once;
    const auto publish = [&] { std::call_once(once, [&] { promised.set_value(); }); };
    if (std::find(order.begin(), order.end(), kAsGiven) == order.end()) publish();
    const std::vector<std::size_t> queue = taking_order(order, workers);
    std::atomic<std::size_t> next{0};
    std::vector<std::exception_ptr> thrown(static_cast<std::size_t>(workers));
    const auto work = [&](std::size_t t) {
        try {
            for (std::size_t k = next++; k < order.size(); k = next++) {
                const std::size_t i = queue[k];
                const int r = order[i];
                out[i] = start_attempt(prepared, r, r - first + 1);
                TriMesh m = base;
                m.threads = inner.threads;
                ok[i] = run_rung(std::move(m), input, inner, kLadder[r], out[i], scale);
                if (r == kAsGiven) {
                    if (ok[i]) given = out[i].mesh.map_uvs; // before judging, which may replace the mesh
                    publish();
                }
                if (ok[i]) {
                    if (kLadder[r].untangle_rings > 0) ready.wait();
                    judge(input, inner, kLadder[r], given, out[i], scale.checked);
                }
                if (workers == 1 && reading_stops(out[i], ok[i])) break; // the later ones would not be read
            }
        } catch (...) {
            thrown[t] = std::current_exception();
            next = order.size();
            publish();
        }
    };
    run_workers(static_cast<std::size_t>(workers), work, thrown);
}

} // namespace

void CheckedInput::start() {
    const std::lock_guard<std::mutex> lock(mutex_);
    // A small input's analysis costs less than starting a thread (fuzzing runs thousands a minute).
    const auto corners = static_cast<std::int64_t>(3 * input_.triangles.size());
    if (!run_parallel(threads_, corners) || prepared_ || beside_.valid()) return;
    try {
        beside_ = std::async(std::launch::async, [this] { return std::make_unique<PreparedInput>(input_, 1); });
    } catch (const std::system_error&) { // no thread to be had: get() makes it
    }
}

const PreparedInput& CheckedInput::get() {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (!prepared_) prepared_ = beside_.valid() ? beside_.get() : std::make_unique<PreparedInput>(input_, threads_);
    return *prepared_;
}

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
    std::optional<TriMesh> base;
    if (rungs > first + 1 && keep_prepared_copy(m, prepared.report)) base.emplace(m);
    Standing st;
    Result attempt = start_attempt(prepared.report, first, 1);
    bool judged = false;
    if (!run_rung(std::move(m), input, options, kLadder[first], attempt, scale, &judged)) return attempt;
    if (!judged) judge(input, options, kLadder[first], {}, attempt, scale.checked);
    prepared.report.stage_seconds.clear(); // in the first attempt's, which the totals take
    // A repair that changed nothing had the map as given: the as-given rung would repeat it.
    const bool as_given = kLadder[first].untangle_rings == 0 && attempt.report.repaired_triangles == 0;
    std::vector<std::array<double, 2>> given;
    if (as_given && !attempt.check.valid) given = attempt.mesh.map_uvs;
    const bool further = another_map(attempt);
    if (read_verdict(first, first, options, attempt, st, fillable)) return attempt;
    std::vector<int> order;
    for (int r = first + 1; further && r < rungs; ++r)
        if (!(r == kAsGiven && kLadder[first].repair && as_given)) order.push_back(r);
    if (!order.empty()) {
        if (!base) {
            base.emplace();
            (void)prepare_mesh(input, options, *base, prepared.report); // it succeeded once, so it does again
        }
        std::vector<Result> out(order.size());
        std::vector<char> ok(order.size(), 0);
        run_side_by_side(input, options, scale, *base, prepared.report, first, order, std::move(given), out, ok);
        for (std::size_t i = 0; i < order.size(); ++i) {
            if (!ok[i]) return std::move(out[i]);
            const bool go_on = another_map(out[i]);
            if (read_verdict(order[i], first, options, out[i], st, fillable)) return std::move(out[i]);
            if (!go_on) break;
        }
    }
    st.best.report.stage_seconds = std::move(st.totals.stage_seconds);
    // No rung gave a valid mesh: locate every violation on the input through the provenance.
    locate_violations(input, st.best);
    return std::move(st.best);
}

} // namespace qex::detail

// When and on how many threads the extractor's loops (and the OBJ reader's) run in parallel: a
// setting, not extraction logic. The checker keeps its own copy of these few lines, on its side
// of the wall (src/verify/parallel.h).
#pragma once

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <exception>
#include <system_error>
#include <thread>
#include <vector>
#if defined(_OPENMP)
#include <omp.h>
#endif

namespace qex::detail {

/// Loops over fewer elements than this stay serial: starting threads costs more than it saves.
/// 2^12 was faster alone on this VM, but two processes side by side (ctest -j2, `qex batch`)
/// then spin for each other's cores: the test suite took 159 s instead of 105 (bench/RESULTS.md).
inline constexpr std::int64_t kParallelMinElements = std::int64_t{1} << 12;

/// Threads for `requested` (Options::threads and the like): 0 means every core; without
/// OpenMP always 1.
inline int thread_count(int requested) {
#if defined(_OPENMP)
    return requested > 0 ? requested : std::max(1, omp_get_max_threads());
#else
    (void)requested;
    return 1;
#endif
}

/// Whether a loop over `n` elements runs in parallel on `threads` threads.
inline bool run_parallel(int threads, std::int64_t n) { return threads > 1 && n >= kParallelMinElements; }

/// A job for the helper threads: job(ctx, t) runs share t of it.
using HelperJob = void (*)(const void* ctx, std::size_t t);

/// Runs job(ctx, t) for t = 1 .. workers - 1 on the process's helper threads (helper_threads.cpp:
/// they wait between jobs, 2 ms before they sleep) and job(ctx, 0) on the caller's, and returns
/// once all have run; false, running nothing, when another call holds the helpers (a loop
/// inside a job) or threads cannot be had.
bool run_on_helpers(std::size_t workers, HelperJob job, const void* ctx);

/// Runs work(t) for t = 0 .. workers - 1, work(0) on the caller's thread: on the helper threads
/// (not OpenMP's, which spin inside users' parallel jobs), or on threads started for this call
/// where those are busy. A thread that cannot be had leaves its share to the others. `work`
/// records what it throws in `thrown[t]` (sized `workers`), rethrown here once all have ended.
template <class Work>
void run_workers(std::size_t workers, const Work& work, const std::vector<std::exception_ptr>& thrown) {
    const HelperJob job = [](const void* ctx, std::size_t t) { (*static_cast<const Work*>(ctx))(t); };
    if (workers <= 1) {
        work(0);
    } else if (!run_on_helpers(workers, job, &work)) {
        std::vector<std::thread> helpers;
        try {
            for (std::size_t t = 1; t < workers; ++t) helpers.emplace_back(work, t);
        } catch (const std::system_error&) {}
        work(0);
        for (std::thread& h : helpers) h.join();
    }
    for (const std::exception_ptr& e : thrown)
        if (e) std::rethrow_exception(e);
}

/// Runs body(part, begin, end) once for each of `parts` contiguous ranges of [0, n), part p
/// being [n p / parts, n (p + 1) / parts), on `workers` threads (the caller's among them): each
/// takes the next part not taken. Every part runs even where no thread can be had. What a part
/// throws is rethrown here, the first part's first.
template <class Body>
void for_parts(int workers, int parts, std::int64_t n, const Body& body) {
    if (parts <= 1 || workers <= 1) { // none at all for no parts
        for (int p = 0; p < parts; ++p) body(p, n * p / parts, n * (p + 1) / parts);
        return;
    }
    std::atomic<int> next{0};
    std::vector<std::exception_ptr> thrown(static_cast<std::size_t>(parts));
    const auto work = [&](std::size_t) {
        for (int p = next++; p < parts; p = next++) try {
                body(p, n * p / parts, n * (p + 1) / parts);
            } catch (...) { thrown[static_cast<std::size_t>(p)] = std::current_exception(); }
    };
    run_workers(static_cast<std::size_t>(std::min(workers, parts)), work, thrown);
}

/// How many parts a loop over `n` elements is split into on `threads` threads: one each where
/// it runs in parallel, else one.
inline int parts_for(int threads, std::int64_t n) { return run_parallel(threads, n) ? threads : 1; }

} // namespace qex::detail

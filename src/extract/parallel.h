// When and on how many threads the extractor's loops (and the OBJ reader's) run in parallel: a
// setting, not extraction logic. The checker keeps its own copy of these few lines, on its side
// of the wall (src/verify/parallel.h).
#pragma once

#include <algorithm>
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
inline constexpr std::int64_t kParallelMinElements = std::int64_t{1} << 16;

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

/// Runs work(t) for t = 0 .. workers - 1 on plain threads (not OpenMP: a few per call, none left
/// spinning inside users' parallel jobs), work(0) on the caller's. A thread that cannot be had
/// leaves its share to the others. `work` records what it throws in `thrown[t]` (sized
/// `workers`), rethrown here once every thread has joined.
template <class Work>
void run_workers(std::size_t workers, const Work& work, const std::vector<std::exception_ptr>& thrown) {
    std::vector<std::thread> helpers;
    try {
        for (std::size_t t = 1; t < workers; ++t) helpers.emplace_back(work, t);
    } catch (const std::system_error&) {
    }
    work(0);
    for (std::thread& h : helpers) h.join();
    for (const std::exception_ptr& e : thrown)
        if (e) std::rethrow_exception(e);
}

} // namespace qex::detail

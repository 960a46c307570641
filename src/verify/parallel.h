// When and on how many threads the checker's loops run in parallel. The extractor has the same
// few lines on its side (src/extract/parallel.h): the checker includes nothing of the extractor.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <system_error>
#include <thread>
#include <vector>
#if defined(_OPENMP)
#include <omp.h>
#endif

namespace qex::verify_detail {

/// Loops over fewer elements than this stay serial: starting a thread costs more than it saves.
/// The loops run on plain threads that end with the loop (share_chunks), so nothing spins after
/// it, as OpenMP's idle threads do: two processes side by side would fight for the cores.
inline constexpr std::int64_t kParallelMinElements = std::int64_t{1} << 12;

/// Threads for `requested` (VerifyOptions::threads): 0 (or less) means OpenMP's default, every
/// core unless OMP_NUM_THREADS says otherwise; without OpenMP 1.
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

/// Hands out [0, n) in chunks of `chunk` elements (at least 1) to `workers` threads, the
/// caller's among them: work(t, next) runs once per thread t, and next(begin, end) gives it the
/// next chunk not taken, false once none is left. Every chunk is handed out even where no
/// thread can be had (the caller's takes the rest). What a thread throws is rethrown here once
/// all have ended.
template <class Work>
void share_chunks(int workers, std::int64_t n, std::int64_t chunk, const Work& work) {
    chunk = std::max<std::int64_t>(chunk, 1);
    std::atomic<std::int64_t> taken{0};
    const auto next = [&](std::int64_t& begin, std::int64_t& end) {
        begin = taken.fetch_add(chunk);
        end = std::min(n, begin + chunk);
        return begin < n;
    };
    const auto count = static_cast<std::size_t>(std::max(workers, 1));
    std::vector<std::exception_ptr> thrown(count);
    const auto run = [&](std::size_t t) {
        try {
            work(t, next);
        } catch (...) {
            thrown[t] = std::current_exception();
            taken = n; // the others stop at their next chunk
        }
    };
    std::vector<std::thread> helpers;
    try {
        for (std::size_t t = 1; t < count; ++t) helpers.emplace_back(run, t);
    } catch (const std::system_error&) {}
    run(0);
    for (std::thread& h : helpers) h.join();
    for (const std::exception_ptr& e : thrown)
        if (e) std::rethrow_exception(e);
}

/// A loop over [0, n) split evenly over `threads` threads where it runs in parallel, else on
/// the caller's: body(t, begin, end) per chunk, t the thread's slot.
template <class Body>
void for_range(int threads, std::int64_t n, const Body& body) {
    if (!run_parallel(threads, n)) {
        body(std::size_t{0}, std::int64_t{0}, n);
        return;
    }
    share_chunks(threads, n, (n + threads - 1) / threads, [&](std::size_t t, const auto& next) {
        for (std::int64_t begin = 0, end = 0; next(begin, end);) body(t, begin, end);
    });
}

} // namespace qex::verify_detail

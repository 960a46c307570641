// When and on how many threads the checker's loops run in parallel. The extractor has the same
// few lines on its side (src/extract/parallel.h): the checker includes nothing of the extractor.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#if defined(_OPENMP)
#include <omp.h>
#endif

namespace qex::verify_detail {

/// Loops over fewer elements than this stay serial: starting threads costs more than it saves.
/// 2^12 was faster alone on this VM, but two processes side by side (ctest -j2, `qex batch`)
/// then spin for each other's cores: the test suite took 159 s instead of 105 (bench/RESULTS.md).
inline constexpr std::int64_t kParallelMinElements = std::int64_t{1} << 16;

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

/// The calling thread's index in the enclosing parallel region (0 outside one, or without OpenMP).
inline std::size_t thread_slot() {
#if defined(_OPENMP)
    return static_cast<std::size_t>(omp_get_thread_num());
#else
    return 0;
#endif
}

/// Whether a loop over `n` elements runs in parallel on `threads` threads.
inline bool run_parallel(int threads, std::int64_t n) { return threads > 1 && n >= kParallelMinElements; }

} // namespace qex::verify_detail

// When and on how many threads the extractor's loops (and the OBJ reader's) run in parallel: a
// setting, not extraction logic. The checker keeps its own copy of these few lines, on its side
// of the wall (src/verify/parallel.h).
#pragma once

#include <algorithm>
#include <cstdint>
#if defined(_OPENMP)
#include <omp.h>
#endif

namespace qex::detail {

/// Loops over fewer elements than this stay serial: starting threads costs more than it saves.
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

} // namespace qex::detail

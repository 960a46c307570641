// How many threads a parallel loop may use: shared by the core, the reader and the checker
// (a setting, not extraction logic).
#pragma once

#include <algorithm>
#if defined(_OPENMP)
#include <omp.h>
#endif

namespace qex::detail {

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

} // namespace qex::detail

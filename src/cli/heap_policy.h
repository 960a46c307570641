// The qex program's heap policy (not the library's: the library never changes the allocator).
// Shared by the CLI and the benchmark, so the benchmark measures what the program runs with.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace qex::cli {

#if defined(__SANITIZE_ADDRESS__)
#define QEX_OWN_ALLOCATOR 1 // a sanitizer's allocator: no glibc heap to shape
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(memory_sanitizer) || __has_feature(thread_sanitizer)
#define QEX_OWN_ALLOCATOR 1
#endif
#endif

/// The process's heap policy, for a run that reads about `input_bytes` of OBJ. Page faults, not
/// arithmetic, dominated a fresh process (on the 315K-triangle duck, 29,000 faults took half of
/// the run). So:
/// - one arena serves every thread: memory the reader's threads free is reused by the
///   extraction (with an arena per thread, the 1.26M-triangle duck's peak grew by 16%);
/// - every block comes from the heap, which is never trimmed: memory freed by one stage is
///   reused by the next, instead of being unmapped and faulted in again;
/// - the heap is extended once, by about what the run will use.
/// The extension is not advised as huge pages. A fresh huge page is memory the kernel must find
/// and zero whole, and on a virtual machine that hands freed memory back to its host that is
/// memory the host faults in again: a run after a pause of a few seconds took 0.70-0.82 s with
/// the advice and 0.36 s without on duck_miq_8 subdivided twice (armadillo_geo_180 1.61 -> 1.41
/// s, duck_miq_8 0.07-0.09 -> 0.06 s). Only runs back to back gained from it.
/// What the run does not touch of the extension costs address space, not memory. The library
/// itself never changes the allocator: it is a policy of this program.
inline void prepare_heap(std::uintmax_t input_bytes) {
#if defined(__GLIBC__) && !defined(QEX_OWN_ALLOCATOR)
    mallopt(M_ARENA_MAX, 1);
#endif
#if defined(__GLIBC__) && defined(__linux__) && !defined(QEX_OWN_ALLOCATOR)
    mallopt(M_MMAP_MAX, 0);
    mallopt(M_TRIM_THRESHOLD, -1); // never trim (a finite threshold would give back a large set-aside at once)
    // Peak heap use was 1.3-1.6 times the file size on the subdivided ducks, but 50 times on a
    // map with many quads per triangle: at least 1 GiB of address space is set aside.
    const std::uintmax_t pad = std::min(std::max(2 * input_bytes, std::uintmax_t{1} << 30), std::uintmax_t{1} << 36);
    void* volatile block = std::malloc(static_cast<std::size_t>(pad)); // volatile: not optimised away
    // Freed at once: back to the top of the heap, which stays.
    std::free(block);
#else
    (void)input_bytes;
#endif
}

} // namespace qex::cli

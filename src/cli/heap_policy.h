// The qex program's heap policy (not the library's: the library never changes the allocator).
// Shared by the CLI and the benchmark, so the benchmark measures what the program runs with.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#if defined(__GLIBC__)
#include <malloc.h>
#endif
#if defined(__linux__)
#include <sys/mman.h>
#include <unistd.h>
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
/// - the heap is extended once, by about what the run will use, and that region is advised to
///   the kernel as huge pages (2 MiB per fault instead of 4 KiB; only with transparent huge
///   pages in `madvise` or `always` mode).
/// What the run does not touch of the extension costs address space, not memory. The library
/// itself never changes the allocator: it is a policy of this program.
inline void prepare_heap(std::uintmax_t input_bytes) {
#if defined(__GLIBC__) && !defined(QEX_OWN_ALLOCATOR)
    mallopt(M_ARENA_MAX, 1);
#endif
#if defined(__GLIBC__) && defined(__linux__) && defined(MADV_HUGEPAGE) && !defined(QEX_OWN_ALLOCATOR)
    mallopt(M_MMAP_MAX, 0);
    mallopt(M_TRIM_THRESHOLD, -1); // never trim (a finite threshold would give back a large set-aside at once)
    // Peak heap use was 1.3-1.6 times the file size on the subdivided ducks, but 50 times on a
    // map with many quads per triangle: at least 1 GiB of address space is set aside.
    const std::uintmax_t pad = std::min(std::max(2 * input_bytes, std::uintmax_t{1} << 30), std::uintmax_t{1} << 36);
    auto* const before = static_cast<char*>(sbrk(0));
    void* volatile block = std::malloc(static_cast<std::size_t>(pad)); // volatile: not optimised away
    auto* const after = static_cast<char*>(sbrk(0));
    constexpr std::uintptr_t kHuge = std::uintptr_t{1} << 21;
    const std::uintptr_t lo = (reinterpret_cast<std::uintptr_t>(before) + kHuge - 1) & ~(kHuge - 1);
    const std::uintptr_t hi = reinterpret_cast<std::uintptr_t>(after) & ~(kHuge - 1);
    if (block != nullptr && hi > lo) (void)madvise(reinterpret_cast<void*>(lo), hi - lo, MADV_HUGEPAGE);
    std::free(block); // back to the top of the heap, which stays
#else
    (void)input_bytes;
#endif
}

} // namespace qex::cli

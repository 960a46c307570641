// The process's helper threads for run_workers (parallel.h). A loop's threads used to be
// started for it and joined after it: on the paper's 20K-triangle maps, with a dozen loops a
// run, that cost a tenth of what the loops saved. Helpers that wait between loops hand a loop
// over at once. They wait a few milliseconds before they sleep, yielding the core as they wait:
// a helper that slept between the loops of one stage was woken late (on this VM, one loop in
// three started its second part after the first had ended), and a thread that yields costs a
// neighbour process little (OpenMP's idle threads spin without yielding, and two processes side
// by side then fought for the cores: bench/RESULTS.md).
#include "parallel.h"

#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <thread>
#include <unistd.h>
#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

namespace qex::detail {
namespace {

/// How long an idle helper, or the caller waiting for its helpers, checks before it sleeps: long
/// enough to catch the next loop of a stage and the stage after it. Past its first checks it
/// yields the core between checks, so another thread that can run does.
constexpr std::chrono::microseconds kSpin{2000};
/// Checks that only pause before the waiting thread yields between them.
constexpr int kPauses = 64;

void relax() {
#if defined(__x86_64__) || defined(__i386__)
    _mm_pause();
#endif
}

/// Waits until ready() holds: checks for kSpin (pausing, then yielding), then sleeps on `cv`
/// (notified under `mutex`).
template <class Ready>
void wait_for(std::mutex& mutex, std::condition_variable& cv, const Ready& ready) {
    const auto until = std::chrono::steady_clock::now() + kSpin;
    for (int i = 0; !ready(); ++i) {
        if (i < kPauses)
            relax();
        else
            std::this_thread::yield();
        if ((i & 7) == 7 && std::chrono::steady_clock::now() > until) {
            std::unique_lock<std::mutex> lock(mutex);
            cv.wait(lock, ready);
            return;
        }
    }
}

class Helpers {
public:
    /// Runs job(ctx, t) for t = 1 .. workers - 1 on helpers and job(ctx, 0) on the caller; false
    /// (nothing run) when another call holds the helpers or too few threads can be had.
    bool run(std::size_t workers, HelperJob job, const void* ctx) {
        std::unique_lock<std::mutex> busy(submit_, std::try_to_lock);
        if (!busy.owns_lock() || !enough(workers - 1)) return false;
        {
            const std::lock_guard<std::mutex> lock(mutex_);
            job_ = job, ctx_ = ctx, workers_ = workers;
            pending_.store(threads_.size(), std::memory_order_relaxed);
            generation_.fetch_add(1, std::memory_order_release);
        }
        wake_.notify_all();
        job(ctx, 0);
        wait_for(mutex_, done_, [&] { return pending_.load(std::memory_order_acquire) == 0; });
        return true;
    }

private:
    /// At least `n` helpers, started as needed.
    bool enough(std::size_t n) {
        // A new helper waits for the generation after this one (the next job is its first).
        const std::uint64_t now = generation_.load(std::memory_order_acquire);
        try {
            while (threads_.size() < n) {
                const std::size_t index = threads_.size() + 1;
                threads_.emplace_back([this, index, now] { serve(index, now); });
                threads_.back().detach(); // the helpers live as long as the process
            }
        } catch (const std::system_error&) { // nothing was added (emplace_back's strong guarantee)
        }
        return threads_.size() >= n;
    }

    /// A helper: every job is acknowledged, run where its index is among the job's workers.
    void serve(std::size_t index, std::uint64_t seen) {
        for (;;) {
            wait_for(mutex_, wake_, [&] { return generation_.load(std::memory_order_acquire) != seen; });
            seen = generation_.load(std::memory_order_acquire);
            if (index < workers_) job_(ctx_, index);
            if (pending_.fetch_sub(1, std::memory_order_acq_rel) == 1) {
                const std::lock_guard<std::mutex> lock(mutex_); // the caller may be going to sleep
                done_.notify_one();
            }
        }
    }

    std::mutex submit_; ///< held by the one call running
    std::mutex mutex_;
    std::condition_variable wake_, done_;
    std::atomic<std::uint64_t> generation_{0};
    std::atomic<std::size_t> pending_{0}; ///< helpers yet to acknowledge the job
    HelperJob job_ = nullptr;
    const void* ctx_ = nullptr;
    std::size_t workers_ = 0;
    std::vector<std::thread> threads_; ///< detached; only their count matters
};

} // namespace

bool run_on_helpers(std::size_t workers, HelperJob job, const void* ctx) {
    // Never freed: a helper may still be waiting on it at exit. A forked child has none of its
    // parent's threads, so it starts helpers of its own.
    static std::mutex mutex;
    static Helpers* helpers = nullptr;
    static pid_t owner = 0;
    Helpers* h = nullptr;
    {
        const std::lock_guard<std::mutex> lock(mutex);
        if (!helpers || owner != getpid()) helpers = new Helpers, owner = getpid();
        h = helpers;
    }
    return h->run(workers, job, ctx);
}

} // namespace qex::detail

// A progress line for runs longer than about two seconds: on stderr, and only when stderr is a
// terminal (never in logs or pipes). It names the program's current step ("step 2/3: extracting
// and checking") with the library's last finished stage (Options::on_stage), and the time so far.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <mutex>
#include <string>
#include <thread>
#include <unistd.h>

namespace qex::cli {

class Progress {
public:
    /// `steps` steps in all; shown only if `enabled` and stderr is a terminal.
    Progress(bool enabled, int steps) : steps_(steps) {
        if (!enabled || !isatty(2)) return;
        thread_ = std::thread([this] { run(); });
        active() = this;
    }
    ~Progress() { stop(); }
    /// Ends the line (cleared from the terminal) for good, before anything else is printed.
    void stop() {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            done_ = true;
        }
        wake_.notify_all();
        if (thread_.joinable()) thread_.join();
        if (active() == this) active() = nullptr;
    }
    /// The progress line shown now, if any (error messages stop it first: stop_progress()).
    static Progress*& active() {
        static Progress* current = nullptr;
        return current;
    }
    Progress(const Progress&) = delete;
    Progress& operator=(const Progress&) = delete;

    /// Starts the next step, named `name`.
    void step(const std::string& name) {
        std::lock_guard<std::mutex> lock(mutex_);
        ++step_;
        name_ = name;
        detail_.clear();
    }
    /// What the current step is doing now (the library's last finished stage, say).
    void detail(const std::string& text) {
        std::lock_guard<std::mutex> lock(mutex_);
        detail_ = text;
    }

private:
    void run() {
        const auto start = std::chrono::steady_clock::now();
        std::unique_lock<std::mutex> lock(mutex_);
        // Nothing for the first two seconds; then the line, twice a second.
        if (wake_.wait_for(lock, std::chrono::seconds(2), [this] { return done_; })) return;
        bool shown = false;
        while (!done_) {
            const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            const int percent = steps_ > 0 ? 100 * (step_ - 1) / steps_ : 0;
            std::fprintf(stderr, "\r\033[Kqex: %d%% step %d/%d: %s%s%s (%.0f s)", percent, step_, steps_, name_.c_str(),
                         detail_.empty() ? "" : ", ", detail_.c_str(), seconds);
            std::fflush(stderr);
            shown = true;
            wake_.wait_for(lock, std::chrono::milliseconds(500), [this] { return done_; });
        }
        if (shown) std::fprintf(stderr, "\r\033[K"), std::fflush(stderr);
    }

    const int steps_;
    int step_ = 0;
    std::string name_, detail_;
    bool done_ = false;
    std::mutex mutex_;
    std::condition_variable wake_;
    std::thread thread_;
};

/// Stops the progress line, if one is shown, so that a message can be printed.
inline void stop_progress() {
    if (Progress* p = Progress::active()) p->stop();
}

} // namespace qex::cli

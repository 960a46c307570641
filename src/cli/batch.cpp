// `qex batch IN_DIR|LIST -o OUT_DIR`: every map of a folder (or a list file) extracted by its own
// `qex extract` process, --jobs at a time, so one bad map never stops the rest. A map whose
// output exists and whose report says valid is skipped (the batch resumes where it stopped).
// One JSON line per map goes to the summary; the exit code is 7 if any map failed.
#include "cli.h"
#include "qex/conform.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

namespace qex::cli {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr int kBatchFailed = 7; // some map failed (the count is printed and in the summary)

/// One map of the batch and what became of it.
struct Job {
    std::string map, output, report, log;
    std::string status; ///< "ok", "skipped" or "failed"
    int exit_code = 0;
    double seconds = 0.0;
    pid_t pid = -1;
    Clock::time_point start;
};

/// The report of a finished (or earlier) run, or null if there is none or it does not parse.
nlohmann::json read_report(const std::string& path) {
    std::ifstream f(path);
    if (!f) return nullptr;
    return nlohmann::json::parse(f, nullptr, false);
}

bool report_says_valid(const nlohmann::json& r) {
    return r.is_object() && r.contains("check") && r["check"].value("valid", false);
}

/// Starts `qex extract` on the job's map, its output and errors into the job's log.
bool start(Job& job, const BatchArgs& a, int threads) {
    std::vector<std::string> args = {
        a.self, "extract", job.map, "-o", job.output, "--report", job.report, "--threads", std::to_string(threads),
        "-q"};
    if (a.snap_boundary) args.push_back("--snap-boundary");
    if (a.best_effort) args.push_back("--best-effort");
    if (a.no_fill_holes) args.push_back("--no-fill-holes");
    if (a.no_repair) args.push_back("--no-repair");
    job.start = Clock::now();
    const pid_t pid = fork();
    if (pid < 0) return false;
    if (pid == 0) {
        const int fd = open(job.log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (fd >= 0) dup2(fd, 1), dup2(fd, 2), close(fd);
        std::vector<char*> argv;
        for (auto& s : args) argv.push_back(s.data());
        argv.push_back(nullptr);
        execv(a.self.c_str(), argv.data());
        _exit(127);
    }
    job.pid = pid;
    return true;
}

nlohmann::json summary_line(const Job& job) {
    const nlohmann::json r = read_report(job.report);
    nlohmann::json j = {
        {"map", job.map},         {"output", job.output}, {"status", job.status}, {"exit_code", job.exit_code},
        {"seconds", job.seconds}, {"quads", nullptr},     {"area", nullptr},      {"defects", nullptr},
        {"violations", nullptr}};
    if (r.is_object() && job.exit_code != kIo && (job.status != "failed" || job.exit_code == kInvalidOutput)) {
        if (r.contains("check")) {
            j["quads"] = r["check"].value("faces", 0);
            j["violations"] = r["check"].contains("violations") ? r["check"]["violations"].size() : 0;
        }
        if (r.contains("input")) j["area"] = r["input"].value("signed_uv_area", 0.0);
        if (r.contains("defects")) j["defects"] = r["defects"].size();
        if (r.contains("fallback")) j["rung"] = r["fallback"].value("rung", "");
    }
    if (job.status == "skipped") j["seconds"] = 0.0;
    return j;
}

/// The progress line, on a terminal only.
void show_progress(std::size_t done, std::size_t total, std::size_t failed, const std::vector<Job*>& running) {
    std::string names;
    for (const Job* j : running) names += (names.empty() ? "" : ", ") + fs::path(j->map).filename().string();
    if (names.size() > 60) names = names.substr(0, 57) + "...";
    std::fprintf(stderr, "\r\033[K[%zu/%zu] %zu failed  %s", done, total, failed, names.c_str());
    std::fflush(stderr);
}

/// The jobs of `maps`: each one's output, report and log in the output folder, named by its stem.
std::vector<Job> plan_jobs(const std::vector<std::string>& maps, const BatchArgs& a) {
    std::vector<Job> jobs(maps.size());
    std::map<std::string, int> seen_stems; // two maps with one stem (a.obj, a.ply) get distinct outputs
    for (std::size_t i = 0; i < maps.size(); ++i) {
        std::string stem = fs::path(maps[i]).stem().string();
        if (const int n = seen_stems[stem]++; n > 0) stem += "_" + std::to_string(n + 1);
        const std::string base = (fs::path(a.out_dir) / stem).string();
        jobs[i] = {maps[i], base + "." + a.format, base + ".report.json", base + ".log", "", 0, 0.0, -1, {}};
    }
    return jobs;
}

/// How far the batch is: the next job to start, the jobs done and those failed.
struct Tally {
    std::size_t next = 0, done = 0, failed = 0;
};

/// Starts jobs until `parallel` run or none is left; a job whose output exists with a valid
/// report is skipped (unless --force), one that cannot be started has failed.
void start_jobs(std::vector<Job>& jobs, const BatchArgs& a, std::size_t parallel, int threads, Tally& n,
                std::vector<Job*>& running) {
    std::error_code ec;
    while (running.size() < parallel && n.next < jobs.size()) {
        Job& job = jobs[n.next++];
        if (!a.force && fs::exists(job.output) && report_says_valid(read_report(job.report))) {
            job.status = "skipped";
            ++n.done;
            continue;
        }
        fs::remove(job.output, ec);
        fs::remove(job.report, ec); // a report left by an earlier run must not describe this one
        if (!start(job, a, threads)) {
            job.status = "failed";
            job.exit_code = kIo;
            ++n.done, ++n.failed;
            continue;
        }
        running.push_back(&job);
    }
}

/// Records how the job's process ended (its wait status `status`), and says so if it failed.
void finish_job(Job& job, int status, const BatchArgs& a, bool progress, Tally& n) {
    job.seconds = std::chrono::duration<double>(Clock::now() - job.start).count();
    job.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
    job.status = job.exit_code == 0 ? "ok" : "failed";
    ++n.done;
    if (job.exit_code != 0) {
        ++n.failed;
        if (progress) std::fprintf(stderr, "\r\033[K");
        if (!a.quiet)
            std::fprintf(stderr, "qex: %s failed (exit code %d, see %s)\n", job.map.c_str(), job.exit_code,
                         job.log.c_str());
    }
}

/// Runs the jobs, `parallel` processes at a time, until all are done; returns how many failed.
std::size_t run_jobs(std::vector<Job>& jobs, const BatchArgs& a, std::size_t parallel, int threads, bool progress) {
    Tally n;
    std::vector<Job*> running;
    while (n.done < jobs.size()) {
        start_jobs(jobs, a, parallel, threads, n, running);
        if (progress) show_progress(n.done, jobs.size(), n.failed, running);
        if (running.empty()) continue;
        int status = 0;
        const pid_t pid = waitpid(-1, &status, 0);
        if (pid < 0) break;
        const auto it = std::find_if(running.begin(), running.end(), [&](const Job* j) { return j->pid == pid; });
        if (it == running.end()) continue;
        Job& job = **it;
        running.erase(it);
        finish_job(job, status, a, progress, n);
    }
    if (progress) std::fprintf(stderr, "\r\033[K");
    return n.failed;
}

/// Writes the summary (one JSON line per map) and prints the tally; the batch's exit code.
int write_summary(const std::vector<Job>& jobs, const BatchArgs& a, std::size_t failed) {
    std::string summary;
    std::size_t ok = 0, skipped = 0;
    for (const Job& job : jobs) {
        summary += summary_line(job).dump() + "\n";
        ok += job.status == "ok";
        skipped += job.status == "skipped";
    }
    const std::string summary_path =
        a.summary_path.empty() ? (fs::path(a.out_dir) / "summary.jsonl").string() : a.summary_path;
    if (!write_text(summary_path, summary)) {
        std::cerr << "qex: cannot write the summary '" << summary_path << "'\n";
        return kIo;
    }
    if (!a.quiet)
        std::printf("qex batch: %zu maps: %zu extracted, %zu skipped (valid output already), %zu failed -> %s\n",
                    jobs.size(), ok, skipped, failed, summary_path.c_str());
    if (failed > 0) {
        std::fprintf(stderr, "qex batch: %zu of %zu maps failed\n", failed, jobs.size());
        return kBatchFailed;
    }
    return kOk;
}

} // namespace

CLI::App* add_batch(CLI::App& app, BatchArgs& a) {
    auto* batch = app.add_subcommand("batch", "Extract every map of a folder or list, in parallel processes");
    batch->add_option("input", a.input, "a folder of maps (*.obj, *.ply) or a file listing them, one per line")
        ->required();
    batch->add_option("-o,--output", a.out_dir, "folder for the meshes, reports (.report.json) and logs (.log)")
        ->required();
    batch->add_option("--jobs", a.jobs, "maps run at once (0: one per core)")->check(CLI::Range(0, 256));
    batch->add_option("--summary", a.summary_path, "JSON lines, one per map (default OUT_DIR/summary.jsonl)");
    batch->add_option("--format", a.format, "format of the meshes written")->check(CLI::IsMember({"obj", "ply"}));
    batch->add_flag("--snap-boundary", a.snap_boundary, "passed to every extraction");
    batch->add_flag(
        "--best-effort", a.best_effort,
        "passed to every extraction: a map with no valid mesh gets the one closest to valid (still failed)");
    batch->add_flag("--no-fill-holes", a.no_fill_holes,
                    "passed to every extraction: no last resort (holes no grid cells close are not filled)");
    batch->add_flag("--no-repair", a.no_repair,
                    "passed to every extraction: fast and uncertified, no re-embedding of fold-over regions");
    batch->add_flag("--force", a.force, "run every map, even those with a valid output already");
    batch->add_flag("-q,--quiet", a.quiet, "print nothing but errors");
    return batch;
}

int run_batch(const BatchArgs& a) {
    std::vector<std::string> maps;
    if (!qex::collect_map_files(a.input, maps)) {
        std::cerr << "qex: cannot read the folder or list '" << a.input << "'\n";
        return kIo;
    }
    std::error_code ec;
    fs::create_directories(a.out_dir, ec);
    if (!fs::is_directory(a.out_dir)) {
        std::cerr << "qex: cannot create the folder '" << a.out_dir << "'\n";
        return kIo;
    }
    std::vector<Job> jobs = plan_jobs(maps, a);
    const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    const std::size_t parallel = static_cast<std::size_t>(a.jobs > 0 ? a.jobs : cores);
    const int threads = parallel > 1 ? 1 : 0; // parallel maps, serial loops (same meshes either way)
    const bool progress = !a.quiet && isatty(2);
    const std::size_t failed = run_jobs(jobs, a, parallel, threads, progress);
    return write_summary(jobs, a, failed);
}

} // namespace qex::cli

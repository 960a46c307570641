// The runner of `qex conform`: every case in its own process (fork; a command extractor execs
// /bin/sh -c), in its own process group, under an address-space limit (RLIMIT_AS) and killed
// with its group at the time limit; options.jobs at a time. The parent judges each finished
// case, writes its reproducer when it is not right, and shrinks it on request.
#include "conform_internal.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <csignal>
#include <fcntl.h>
#include <filesystem>
#include <sys/resource.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

namespace qex {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using namespace conform_detail;

/// One case running.
struct Running {
    std::size_t index = 0;
    pid_t pid = -1;
    Clock::time_point start;
    bool killed = false;
};

std::string safe_name(const std::string& name) {
    std::string out = name;
    for (char& ch : out)
        if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '-' && ch != '.') ch = '_';
    return out;
}

/// Writes the case's map into its work folder (a user's map is read where it is).
bool prepare(const ConformCase& c, const std::string& dir, const std::string& ext, Paths& p) {
    std::error_code ec;
    fs::remove_all(dir, ec);
    fs::create_directories(dir, ec);
    p = {dir, c.generated ? dir + "/map.obj" : c.map_path, dir + "/output." + ext, dir + "/stdout.txt",
         dir + "/stderr.txt"};
    return !c.generated || write_file(p.map, conform_map_text(c));
}

/// In the child: the limits, the files, then the extractor; never returns.
[[noreturn]] void run_child(const ConformExtractor& extractor, const Paths& p, std::int64_t memory_mb) {
    setpgid(0, 0); // its own group, so a timeout kills what the shell started too
    if (memory_mb > 0) {
        const rlim_t bytes = static_cast<rlim_t>(memory_mb) << 20;
        const rlimit limit{bytes, bytes};
        setrlimit(RLIMIT_AS, &limit);
    }
    const int in = open("/dev/null", O_RDONLY);
    const int out = open(p.stdout_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int err = open(p.stderr_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (in >= 0) dup2(in, 0), close(in);
    if (out >= 0) dup2(out, 1), close(out);
    if (err >= 0) dup2(err, 2), close(err);
    int code = 127;
    try {
        code = extractor(p.map, p.out);
    } catch (...) {
        code = 126; // a callback that throws has failed, cleanly
    }
    _exit(code);
}

pid_t start_case(const ConformExtractor& extractor, const Paths& p, std::int64_t memory_mb) {
    const pid_t pid = fork();
    if (pid == 0) run_child(extractor, p, memory_mb);
    if (pid > 0) setpgid(pid, pid); // as the child does: no race with a kill at the time limit
    return pid;
}

ConformRun finished(const Running& r, int status) {
    ConformRun run;
    run.seconds = std::chrono::duration<double>(Clock::now() - r.start).count();
    run.timed_out = r.killed;
    if (WIFSIGNALED(status)) run.signal = WTERMSIG(status);
    else run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 0;
    return run;
}

/// Kills the groups of the cases past the time limit.
void enforce_timeout(std::vector<Running>& running, double timeout) {
    for (Running& r : running)
        if (!r.killed && std::chrono::duration<double>(Clock::now() - r.start).count() > timeout) {
            kill(-r.pid, SIGKILL);
            r.killed = true;
        }
}

/// A finished child of ours (never another child of a program that calls the library), its
/// group killed (what the extractor left behind in it) and the child reaped only then, so the
/// group's id cannot be taken by another process before the kill.
pid_t wait_any(std::vector<Running>& running, double timeout, int& status) {
    for (;;) {
        for (const Running& r : running) {
            siginfo_t info{};
            if (waitid(P_PID, static_cast<id_t>(r.pid), &info, WEXITED | WNOHANG | WNOWAIT) < 0) return -1;
            if (info.si_pid == 0) continue;
            kill(-r.pid, SIGKILL);
            return waitpid(r.pid, &status, 0);
        }
        enforce_timeout(running, timeout);
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
}

} // namespace

std::string shell_command(const std::string& command, const std::string& in, const std::string& out) {
    std::string s = command;
    const std::pair<std::string, std::string> fill[] = {
        {"{in}", shell_quote(in)}, {"{out}", shell_quote(out)}, {"{report}", shell_quote(out + ".report.json")}};
    for (const auto& [key, value] : fill)
        for (std::size_t at = s.find(key); at != std::string::npos; at = s.find(key, at + value.size()))
            s.replace(at, key.size(), value);
    return s;
}

ConformExtractor shell_extractor(const std::string& command) {
    return [command](const std::string& in, const std::string& out) {
        const std::string line = shell_command(command, in, out);
        execl("/bin/sh", "sh", "-c", line.c_str(), static_cast<char*>(nullptr));
        return 127;
    };
}

void conform_detail::run_cases(const std::vector<ConformCase>& cases, const ConformExtractor& extractor,
                               const ConformOptions& o, const std::string& work, const Judged& judged) {
    std::vector<Running> running;
    std::vector<Paths> paths(cases.size());
    std::size_t next = 0, done = 0;
    const std::size_t jobs = static_cast<std::size_t>(std::max(1, o.jobs));
    while (done < cases.size()) {
        while (running.size() < jobs && next < cases.size()) {
            const std::size_t i = next++;
            const std::string dir = work + "/" + std::to_string(i) + "_" + safe_name(cases[i].name);
            const pid_t pid = prepare(cases[i], dir, o.out_extension, paths[i]) ? start_case(extractor, paths[i], o.memory_mb) : -1;
            if (pid < 0) { // no process: an error of this machine, reported as the case's
                ConformRun run{127, 0, false, 0.0};
                ConformResult r = conform_judge(cases[i], paths[i].map, paths[i].out, run);
                r.detail = "could not start the case (fork or its files)";
                judged(i, r, paths[i]), ++done;
                continue;
            }
            running.push_back({i, pid, Clock::now(), false});
        }
        if (running.empty()) continue;
        int status = 0;
        const pid_t pid = wait_any(running, o.timeout, status);
        if (pid < 0) break;
        const auto it = std::find_if(running.begin(), running.end(), [&](const Running& r) { return r.pid == pid; });
        if (it == running.end()) continue;
        const Running r = *it;
        running.erase(it);
        ConformResult result = conform_judge(cases[r.index], paths[r.index].map, paths[r.index].out, finished(r, status));
        judged(r.index, result, paths[r.index]);
        ++done;
    }
}

} // namespace qex

// `qex conform --extractor 'CMD {in} {out}' -o REPORT_DIR`: any extractor run on known, hostile
// and the user's maps, each case in its own process (qex::conform, src/conform/), every output
// judged by qex::check_mesh; the table per family, summary.jsonl and a reproducer folder per
// case not right. Exit code 7 when some case is not right, as `qex batch`.
#include "cli.h"
#include "draw.h"
#include "qex/conform.h"

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <thread>
#include <unistd.h>

namespace qex::cli {
namespace {

namespace fs = std::filesystem;
constexpr int kSomeWrong = 7; // as qex batch: some cases are not right (the count is printed)

/// The progress bar, on a terminal: cases done of all, and how many are not right so far.
void show_progress(std::size_t done, std::size_t total, std::size_t wrong) {
    const int width = 30, filled = static_cast<int>(width * done / (total ? total : 1));
    std::fprintf(stderr, "\r\033[K[%s%s] %zu/%zu cases, %zu not right", std::string(filled, '#').c_str(),
                 std::string(width - filled, '.').c_str(), done, total, wrong);
    std::fflush(stderr);
}

/// The cases not right, one line each, with their reproducer folders.
void print_wrong(const std::vector<ConformResult>& results) {
    for (const ConformResult& r : results)
        if (!r.right)
            std::printf("  %s: %s (%s) -> %s%s%s\n", r.c.name.c_str(), to_string(r.outcome), r.detail.c_str(),
                        r.folder.c_str(), r.shrunk.empty() ? "" : "; shrunk to ", r.shrunk.c_str());
}

} // namespace

CLI::App* add_conform(CLI::App& app, ConformArgs& a) {
    auto* c = app.add_subcommand("conform", "Judge any quad extractor on known, hostile and your own maps");
    c->add_option("--extractor", a.extractor,
                  "the extractor's command line, run by /bin/sh -c, with {in} (the map) and {out} (the quad mesh "
                  "to write), optionally {report}")
        ->required();
    c->add_option("-o,--output", a.out_dir, "folder for summary.jsonl and the reproducers (cases/)")->required();
    c->add_option("--cases", a.sets,
                  "known, hostile, a folder of maps or a list file; repeat for several (default: known and hostile)");
    c->add_option("--count", a.count, "cases per generated set")->check(CLI::Range(1, 1000000));
    c->add_option("--seed", a.seed, "the seed of the generated cases (the same cases on any machine)");
    c->add_option("--timeout", a.timeout, "seconds per case before it is killed")
        ->check(finite_number())
        ->check(CLI::Range(0.1, 1e6));
    c->add_option("--memory", a.memory_mb, "address-space limit per case in MiB (0: none)")
        ->check(CLI::Range(std::int64_t{0}, std::int64_t{1} << 30));
    c->add_option("--jobs", a.jobs, "cases run at once (0: one per core)")->check(CLI::Range(0, 256));
    c->add_flag("--shrink", a.shrink, "reduce each failing generated case to a smaller one that still fails");
    c->add_flag("-q,--quiet", a.quiet, "no progress bar and no table; the count of cases not right still printed");
    return c;
}

int run_conform(const ConformArgs& a) {
    std::string error;
    const std::vector<std::string> sets = a.sets.empty() ? std::vector<std::string>{"known", "hostile"} : a.sets;
    const std::vector<ConformCase> cases = conform_cases(sets, a.count, a.seed, &error);
    if (cases.empty()) {
        std::cerr << "qex: " << (error.empty() ? "no cases" : error) << "\n";
        return error.empty() ? kUsage : kIo;
    }
    std::error_code ec;
    fs::create_directories(a.out_dir, ec);
    if (!fs::is_directory(a.out_dir)) {
        std::cerr << "qex: cannot create the folder '" << a.out_dir << "'\n";
        return kIo;
    }
    ConformOptions o;
    o.out_dir = a.out_dir;
    o.jobs = a.jobs > 0 ? a.jobs : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    o.timeout = a.timeout;
    o.memory_mb = a.memory_mb;
    o.shrink = a.shrink;
    o.replay_command = a.extractor;
    o.checker = a.self;
    // The picture qex check --svg and qex draw --quads draw of a verdict.
    o.picture = [](const Input& map, const QuadMesh& mesh, const VerifyResult& v) {
        return verdict_svg(map, mesh, v, 1, "the extractor's output on the case's map");
    };
    const bool progress = !a.quiet && isatty(2);
    if (progress) o.on_progress = show_progress;
    const std::vector<ConformResult> results = conform(cases, shell_extractor(a.extractor), o);
    if (progress) std::fprintf(stderr, "\r\033[K");
    std::vector<std::string> rows;
    std::size_t wrong = 0;
    for (const ConformResult& r : results) rows.push_back(conform_summary_line(r)), wrong += !r.right;
    if (!a.quiet) {
        std::printf("%s", conform_table(rows).c_str());
        print_wrong(results);
    }
    const std::string summary = (fs::path(a.out_dir) / "summary.jsonl").string();
    std::printf("qex conform: %zu cases: %zu right, %zu not right -> %s\n", results.size(), results.size() - wrong,
                wrong, summary.c_str());
    return wrong > 0 ? kSomeWrong : kOk;
}

} // namespace qex::cli

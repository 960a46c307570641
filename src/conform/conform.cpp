// qex::conform: the cases run and judged (run.cpp, judge.cpp), the reproducer of each case not
// right written, shrunk on request (shrink.cpp), and summary.jsonl.
#include "conform_internal.h"

#include <filesystem>

namespace qex {

namespace fs = std::filesystem;

std::vector<ConformResult> conform(const std::vector<ConformCase>& cases, const ConformExtractor& extractor,
                                   const ConformOptions& o) {
    std::error_code ec;
    fs::create_directories(o.out_dir, ec);
    const std::string work = (fs::path(o.out_dir) / "work").string();
    std::vector<ConformResult> results(cases.size());
    std::size_t done = 0, wrong = 0;
    conform_detail::run_cases(cases, extractor, o, work, [&](std::size_t i, ConformResult& r, const conform_detail::Paths& p) {
        if (!r.right) r.folder = write_reproducer(r, p.map, p.out, p.stderr_path, o);
        fs::remove_all(p.dir, ec); // its files are in the reproducer now, or not needed
        results[i] = r;
        ++done, wrong += !r.right;
        if (o.on_progress) o.on_progress(done, cases.size(), wrong);
    });
    fs::remove_all(work, ec);
    // Shrinking after the run: its candidates run as cases of their own, o.jobs at a time.
    if (o.shrink)
        for (ConformResult& r : results)
            if (!r.right && r.c.generated) r.shrunk = conform_describe(conform_detail::shrink_case(r, extractor, o).c);
    std::string summary;
    for (const ConformResult& r : results) summary += conform_summary_line(r) + "\n";
    conform_detail::write_file((fs::path(o.out_dir) / "summary.jsonl").string(), summary);
    return results;
}

} // namespace qex

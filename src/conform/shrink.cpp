// --shrink: a generated case not right reduced, as property testing shrinks, to a smaller recipe
// that still ends the same way: a step left out, or a smaller grid, one at a time, greedily.
#include "conform_internal.h"

#include <filesystem>

namespace qex {
namespace {

namespace fs = std::filesystem;
constexpr int kMaxRounds = 12; // each round runs every candidate once, o.jobs at a time

/// The recipes one edit smaller than `r`: each step left out, fewer grid quads per layout edge
/// (the lattice kept on or off the grid as it was), the lattice on the grid.
std::vector<ConformRecipe> smaller_recipes(const ConformRecipe& r) {
    std::vector<ConformRecipe> out;
    for (std::size_t i = 0; i < r.steps.size(); ++i) {
        ConformRecipe s = r;
        s.steps.erase(s.steps.begin() + static_cast<std::ptrdiff_t>(i));
        out.push_back(s);
    }
    if (r.n > 1) {
        ConformRecipe s = r;
        s.n = r.n - 1;
        s.k = std::max(1, r.k - 1);
        out.push_back(s);
    }
    if (r.k > r.n) {
        ConformRecipe s = r;
        s.k = r.n;
        out.push_back(s);
    }
    return out;
}

} // namespace

ConformResult conform_detail::shrink_case(const ConformResult& failed, const ConformExtractor& extractor,
                                          const ConformOptions& o) {
    ConformResult best;
    ConformCase current = failed.c;
    const std::string work = (fs::path(o.out_dir) / "work_shrink").string();
    for (int round = 0; round < kMaxRounds; ++round) {
        std::vector<ConformCase> candidates;
        for (const ConformRecipe& r : smaller_recipes(current.recipe)) {
            ConformCase c = current;
            c.recipe = r;
            if (c.expected_quads >= 0) c.expected_quads = expected_quads(r);
            candidates.push_back(c);
        }
        if (candidates.empty()) break;
        std::vector<ConformResult> results(candidates.size());
        std::vector<Paths> files(candidates.size());
        run_cases(candidates, extractor, o, work + "/" + std::to_string(round),
                  [&](std::size_t i, ConformResult& r, const Paths& p) { results[i] = r, files[i] = p; });
        std::size_t i = 0;
        while (i < results.size() && (results[i].right || results[i].outcome != failed.outcome)) ++i;
        if (i == results.size()) break;
        best = results[i];
        best.c.name = failed.c.name + "_shrunk";
        best.folder = write_reproducer(best, files[i].map, files[i].out, files[i].stderr_path, o);
        current = candidates[i];
    }
    std::error_code ec;
    fs::remove_all(work, ec);
    return best;
}

} // namespace qex

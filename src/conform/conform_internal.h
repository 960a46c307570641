// What the files of src/conform/ share: portable random draws (std::mt19937_64 is the same
// sequence everywhere; the standard's distributions are not), and small file helpers.
#pragma once

#include "qex/conform.h"

#include <cstdint>
#include <functional>
#include <random>
#include <string>
#include <vector>

namespace qex::conform_detail {

/// Draws from std::mt19937_64 alone, so a seed gives the same cases on any machine.
class Draw {
public:
    explicit Draw(std::uint64_t seed) : rng_(seed) {}
    std::uint64_t below(std::uint64_t n) { return rng_() % n; }
    std::int64_t between(std::int64_t lo, std::int64_t hi) {
        return lo + static_cast<std::int64_t>(below(static_cast<std::uint64_t>(hi - lo) + 1));
    }
    double unit() { return static_cast<double>(rng_() >> 11) * 0x1p-53; } ///< in [0, 1)
    double signed_unit() { return 2.0 * unit() - 1.0; }                     ///< in [-1, 1)

private:
    std::mt19937_64 rng_;
};

/// The seed of case `i` of a set: the run's seed, the set's name and the index mixed.
std::uint64_t case_seed(std::uint64_t seed, const std::string& set, int i);
/// The known quad count of a recipe: the layout's quads times n^2, times K^2 per "scale K".
std::int64_t expected_quads(const ConformRecipe& r);
/// Whether a path names a PLY file (by its extension, any case).
bool is_ply_path(const std::string& path);
bool read_file(const std::string& path, std::string& text);
bool write_file(const std::string& path, const std::string& text);
/// `text` quoted for /bin/sh.
std::string shell_quote(const std::string& text);

/// A case's files while it runs: its folder, its map, the output, the extractor's stdout and stderr.
struct Paths {
    std::string dir, map, out, stdout_path, stderr_path;
};
using Judged = std::function<void(std::size_t index, ConformResult&, const Paths&)>;
/// Runs the cases (o.jobs at a time, each in its own process under work/), judging each as it
/// finishes; `judged` is called with each result and its files, in the order they finish.
void run_cases(const std::vector<ConformCase>& cases, const ConformExtractor& extractor, const ConformOptions& o,
               const std::string& work, const Judged& judged);
/// Shrinks a generated case not right: a smaller recipe (fewer steps, a smaller grid) that ends
/// the same way, its reproducer written beside the case's (NAME_shrunk). Its result, or one
/// with an empty name when no smaller recipe fails so.
ConformResult shrink_case(const ConformResult& failed, const ConformExtractor& extractor, const ConformOptions& o);

} // namespace qex::conform_detail

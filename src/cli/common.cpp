// The subcommands' shared helpers: exit codes of I/O errors, files by extension, atomic output.
#include "cli.h"
#include "progress.h"

#include "io/checked_int.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <unordered_set>

namespace qex::cli {

int io_exit(const IoError& e) {
    return e.code == IoError::Code::CannotOpen || e.code == IoError::Code::CannotWrite ? kIo : kParse;
}

bool is_ply(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    return ext == ".ply";
}

int read_map(const std::string& path, Input& input, int threads) {
    const IoError e = is_ply(path) ? qex::read_ply(path, input) : qex::read_obj(path, input, threads);
    if (e.ok()) return kOk;
    stop_progress();
    std::cerr << "qex: " << path << ": " << e.message << "\n";
    return io_exit(e);
}

int read_quads(const std::string& path, QuadMesh& mesh) {
    const IoError e = is_ply(path) ? qex::read_polygon_ply(path, mesh) : qex::read_polygon_obj(path, mesh);
    if (e.ok()) return kOk;
    stop_progress();
    std::cerr << "qex: " << path << ": " << e.message << "\n";
    return io_exit(e);
}

IoError write_quads(const std::string& path, const QuadMesh& mesh, int threads) {
    return is_ply(path) ? qex::write_ply(path, mesh) : qex::write_obj(path, mesh, threads);
}

bool write_text(const std::string& path, const std::string& text) {
    const std::string tmp = path + ".tmp";
    {
        std::ofstream f(tmp, std::ios::binary);
        if (!f || !(f << text) || !f.flush()) {
            f.close();
            std::remove(tmp.c_str());
            return false;
        }
    }
    if (std::rename(tmp.c_str(), path.c_str()) == 0) return true;
    std::remove(tmp.c_str());
    return false;
}

int read_features(const std::string& path, Input& input) {
    std::ifstream f(path, std::ios::binary);
    if (!f) {
        std::cerr << "qex: cannot open feature file '" << path << "'\n";
        return kIo;
    }
    // The mesh's edges, as (smaller, larger) vertex pairs packed into one key.
    const auto key = [](std::int64_t a, std::int64_t b) { return std::min(a, b) << 32 | std::max(a, b); };
    std::unordered_set<std::int64_t> edges;
    for (const auto& t : input.triangles)
        for (int k = 0; k < 3; ++k) edges.insert(key(t[k], t[(k + 1) % 3]));
    const auto nv = static_cast<long long>(input.positions.size());
    std::vector<std::array<int, 2>> features;
    std::string line;
    for (long long number = 1; std::getline(f, line); ++number) {
        if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
        std::istringstream words(line);
        long long i = 0, j = 0;
        std::string rest;
        if (!(words >> std::ws).good() && words.eof()) continue; // blank or comment only
        if (!(words >> i >> j) || (words >> rest)) {
            std::cerr << "qex: " << path << ": line " << number << ": expected two vertex indices 'i j'\n";
            return kParse;
        }
        // istream refuses a number beyond long long (malformed); one beyond the vertices here.
        std::array<int, 2> edge{-1, -1};
        if (i < 0 || j < 0 || i >= nv || j >= nv || !io_detail::checked_int(i, edge[0]) ||
            !io_detail::checked_int(j, edge[1])) {
            std::cerr << "qex: " << path << ": line " << number << ": vertex index out of range (" << nv
                      << " vertices, 0-based)\n";
            return kBadInput;
        }
        if (!edges.count(key(i, j))) {
            std::cerr << "qex: " << path << ": line " << number << ": (" << i << ", " << j
                      << ") is not an edge of the mesh\n";
            return kBadInput;
        }
        features.push_back(edge);
    }
    input.feature_edges = std::move(features);
    return kOk;
}

CLI::Validator finite_number() {
    return CLI::Validator(
        [](std::string& s) -> std::string {
            double x = 0;
            if (!CLI::detail::lexical_cast(s, x) || !std::isfinite(x)) return "Value " + s + " is not a finite number";
            return std::string();
        },
        "FINITE");
}

std::uintmax_t size_of(const std::string& path) {
    std::error_code ec;
    const std::uintmax_t bytes = std::filesystem::file_size(path, ec);
    return ec ? 0 : bytes;
}

} // namespace qex::cli

// One case judged: how the extractor's process ended, then its output through the oracle's one
// entry (qex::check_mesh, as `qex check` judges), into an outcome.
#include "conform_internal.h"
#include "qex/check.h"
#include "qex/io.h"
#include "qex/report.h"

#include <algorithm>
#include <cctype>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace qex {
namespace {

namespace fs = std::filesystem;
using conform_detail::is_ply_path;

/// The signal's name ("SIGSEGV"), or its number.
std::string signal_name(int sig) {
    switch (sig) {
        case SIGSEGV: return "SIGSEGV";
        case SIGABRT: return "SIGABRT";
        case SIGKILL: return "SIGKILL";
        case SIGBUS: return "SIGBUS";
        case SIGFPE: return "SIGFPE";
        case SIGILL: return "SIGILL";
        case SIGTERM: return "SIGTERM";
        case SIGINT: return "SIGINT";
        case SIGPIPE: return "SIGPIPE";
        default: return "signal " + std::to_string(sig);
    }
}

/// The first violations, named with their elements, in a line.
std::string first_violations(const VerifyResult& v) {
    std::string out;
    for (std::size_t i = 0; i < v.violations.size() && i < 3; ++i) {
        const Violation& x = v.violations[i];
        out += (i ? "; " : ": ") + std::string(to_string(x.kind));
        if (x.element >= 0) out += " at " + std::to_string(x.element);
    }
    return out;
}

/// The grid scales above 1 that `qex check --grid-scale` accepts.
constexpr int kFinerScales[] = {2, 4, 8, 16, 32, 64};

bool names_off_grid(const std::vector<Violation>& list) {
    return std::any_of(list.begin(), list.end(),
                       [](const Violation& x) { return x.kind == ViolationKind::NotOnGridPoint; });
}

/// Whether a mesh invalid at grid scale 1 may be valid at grid scale k, a refined mesh's (qex
/// extract's when the map's own scale gives none): vertices off the map's grid points (in a
/// fold-over region such vertices are undecided, not violations), and a face for each of the
/// k^2 cells every required cell splits into, as a valid mesh there has. So an ordinary
/// invalid mesh (a face dropped, a vertex moved) costs no second check.
bool may_be_valid_at(const VerifyResult& at_1, std::int64_t faces, int k) {
    return (names_off_grid(at_1.violations) || names_off_grid(at_1.undecided)) &&
           faces >= static_cast<std::int64_t>(k) * k * at_1.coverage_cells;
}

/// The verdict at grid scale 1, or at the first finer scale where the mesh is valid (then
/// r.grid_scale is set to it): one verdict everywhere, as `qex check --grid-scale K` gives.
/// r.area is the map's own area, from the verdict at scale 1.
MeshCheck check_at_its_scale(const Input& map, const QuadMesh& mesh, ConformResult& r) {
    VerifyOptions options;
    options.threads = 1; // the cases run in parallel processes already
    r.grid_scale = 1;
    MeshCheck check = check_mesh(map, mesh, 1, options);
    if (!check.map_ok()) return check;
    r.area = check.verdict.input_signed_uv_area_rounded;
    if (check.verdict.valid) return check;
    for (const int k : kFinerScales) {
        if (!may_be_valid_at(check.verdict, static_cast<std::int64_t>(mesh.faces.size()), k)) break; // k^2 grows
        MeshCheck finer = check_mesh(map, mesh, k, options);
        if (finer.verdict.valid) {
            r.grid_scale = k;
            return finer;
        }
    }
    return check;
}

/// The outcome of a mesh the checker judged (at r.grid_scale), and the detail's tail.
void classify(ConformResult& r, const VerifyResult& v) {
    const std::string at = r.grid_scale == 1 ? "" : " at grid scale " + std::to_string(r.grid_scale);
    if (!v.valid)
        r.outcome = ConformOutcome::InvalidExit0;
    else if (r.c.expected_quads >= 0)
        r.outcome =
            r.quads == r.c.expected_quads && r.grid_scale == 1 ? ConformOutcome::Exact : ConformOutcome::WrongCount;
    else
        r.outcome = r.quads < v.input_signed_uv_area_rounded ? ConformOutcome::ValidFewerQuads : ConformOutcome::Valid;
    if (r.grid_scale != 1)
        r.detail += at + " (qex check --grid-scale " + std::to_string(r.grid_scale) + "; the map's area there " +
                    std::to_string(v.input_signed_uv_area_rounded) + ")";
    if (r.outcome == ConformOutcome::WrongCount)
        r.detail += ": " + std::to_string(r.quads) + " quads" + at + ", known " + std::to_string(r.c.expected_quads) +
                    (r.grid_scale == 1 ? "" : " at grid scale 1");
}

/// Judges an output of a run that exited 0; the map read as the extractor read it.
void judge_output(ConformResult& r, const std::string& map_path, const std::string& out_path) {
    Input map;
    const IoError me = is_ply_path(map_path) ? read_ply(map_path, map) : read_obj(map_path, map, 1);
    if (!me.ok()) {
        r.outcome = ConformOutcome::InvalidExit0;
        r.detail = "exit 0 for a malformed map (" + me.message + ")";
        return;
    }
    QuadMesh mesh;
    const IoError oe = is_ply_path(out_path) ? read_polygon_ply(out_path, mesh) : read_polygon_obj(out_path, mesh);
    if (!oe.ok()) {
        r.outcome = ConformOutcome::InvalidExit0;
        r.detail = "exit 0 with an output that cannot be read (" + oe.message + ")";
        return;
    }
    r.quads = static_cast<std::int64_t>(mesh.faces.size());
    const MeshCheck check = check_at_its_scale(map, mesh, r);
    if (!check.map_ok()) {
        r.outcome = ConformOutcome::InvalidExit0;
        r.detail = "exit 0 for a map that is no valid input (" + std::string(to_string(check.error.code)) + ": " +
                   check.error.message + ")";
        return;
    }
    const VerifyResult& v = check.verdict;
    r.detail = verdict_line(v) + first_violations(v);
    if (v.valid) r.quality = mesh_quality(map, mesh); // on the map as given, whatever the scale
    r.verdict_json = r.quality.computed ? verify_json(v, r.quality) : verify_json(v);
    classify(r, v);
}

} // namespace

const char* to_string(ConformOutcome outcome) {
    switch (outcome) {
        case ConformOutcome::Exact: return "exact";
        case ConformOutcome::Valid: return "valid";
        case ConformOutcome::ValidFewerQuads: return "valid_fewer_quads";
        case ConformOutcome::CleanFailure: return "clean_failure";
        case ConformOutcome::InvalidExit0: return "invalid_exit_0";
        case ConformOutcome::WrongCount: return "wrong_count";
        case ConformOutcome::Crash: return "crash";
        case ConformOutcome::Timeout: return "timeout";
        case ConformOutcome::NoOutput: return "no_output";
    }
    return "?";
}

bool conform_right(const std::string& kind, ConformOutcome o) {
    if (kind == "known") return o == ConformOutcome::Exact;
    return o == ConformOutcome::Exact || o == ConformOutcome::Valid || o == ConformOutcome::ValidFewerQuads ||
           o == ConformOutcome::CleanFailure;
}

ConformResult conform_judge(const ConformCase& c, const std::string& map_path, const std::string& out_path,
                            const ConformRun& run) {
    ConformResult r;
    r.c = c;
    r.run = run;
    std::error_code ec;
    if (run.timed_out) {
        r.outcome = ConformOutcome::Timeout;
        r.detail = "killed after " + std::to_string(static_cast<long long>(run.seconds)) + " s";
    } else if (run.signal != 0) {
        r.outcome = ConformOutcome::Crash;
        r.detail = "ended by " + signal_name(run.signal);
    } else if (run.exit_code > 128 && run.exit_code <= 128 + 64) {
        // The shell's status for a command a signal ended (/bin/sh -c need not exec it).
        r.outcome = ConformOutcome::Crash;
        r.detail =
            "ended by " + signal_name(run.exit_code - 128) + " (exit status " + std::to_string(run.exit_code) + ")";
    } else if (run.exit_code != 0) {
        r.outcome = ConformOutcome::CleanFailure;
        r.detail = "exit code " + std::to_string(run.exit_code);
    } else if (!fs::exists(out_path, ec) || fs::file_size(out_path, ec) == 0) {
        r.outcome = ConformOutcome::NoOutput;
        r.detail = fs::exists(out_path, ec) ? "exit 0 with an empty output file" : "exit 0 without an output file";
    } else {
        judge_output(r, map_path, out_path);
    }
    r.right = conform_right(c.kind, r.outcome);
    return r;
}

// ============================================================================ shared helpers

std::uint64_t conform_detail::case_seed(std::uint64_t seed, const std::string& set, int i) {
    std::uint64_t h = 1469598103934665603ull; // FNV-1a of the set's name, then splitmix64
    for (const unsigned char ch : set) h = (h ^ ch) * 1099511628211ull;
    std::uint64_t z = seed * 0x9E3779B97F4A7C15ull + h + static_cast<std::uint64_t>(i);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

bool conform_detail::is_ply_path(const std::string& path) {
    std::string ext = fs::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char ch) { return std::tolower(ch); });
    return ext == ".ply";
}

bool conform_detail::read_file(const std::string& path, std::string& text) {
    std::ifstream f(path, std::ios::binary);
    if (!f) return false;
    std::ostringstream s;
    s << f.rdbuf();
    text = s.str();
    return true;
}

bool conform_detail::write_file(const std::string& path, const std::string& text) {
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    return f && f.write(text.data(), static_cast<std::streamsize>(text.size()));
}

std::string conform_detail::shell_quote(const std::string& text) {
    std::string out = "'";
    for (const char ch : text) out += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
    return out + "'";
}

bool collect_map_files(const std::string& input, std::vector<std::string>& maps) {
    std::error_code ec;
    if (fs::is_directory(input, ec)) {
        for (const auto& e : fs::directory_iterator(input, ec)) {
            std::string ext = e.path().extension().string();
            std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char ch) { return std::tolower(ch); });
            if (e.is_regular_file() && (ext == ".obj" || ext == ".ply")) maps.push_back(e.path().string());
        }
        std::sort(maps.begin(), maps.end());
        return !ec;
    }
    std::ifstream f(input);
    if (!f) return false;
    const fs::path base = fs::path(input).parent_path();
    for (std::string line; std::getline(f, line);) {
        if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
        line.erase(0, line.find_first_not_of(" \t\r"));
        line.erase(line.find_last_not_of(" \t\r") + 1);
        if (line.empty()) continue;
        maps.push_back(fs::path(line).is_absolute() ? line : (base / line).string());
    }
    return true;
}

} // namespace qex

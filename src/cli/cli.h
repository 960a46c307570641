// What the qex program's subcommands share: exit codes, reading maps and meshes by file
// extension (OBJ or PLY), atomic text output, and the subcommands' entry points.
#pragma once

#include "qex/layout.h"
#include "qex/qex.h"

#include <CLI/CLI.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace qex::cli {

// Exit codes; each failure family has its own.
enum Exit : int {
    kOk = 0,
    kUsage = 1,         // bad command line
    kIo = 2,            // a file cannot be read or written
    kParse = 3,         // malformed OBJ, PLY, VVAL or features file
    kBadInput = 4,      // the mesh or map is not acceptable input
    kInvalidOutput = 5, // extraction finished but the checker rejects its output
    kRejected = 6,      // `qex check`: the judged mesh is not valid
};

/// The exit code of a reader's or writer's error.
int io_exit(const IoError& e);

/// The version and the git commit this program was built from ("0.2.0 (commit abc123)").
const char* version_string();

/// Whether `path` names a PLY file (by its extension, any case).
bool is_ply(const std::string& path);
/// Reads a map (OBJ or PLY by extension); on a problem prints it and returns its exit code.
int read_map(const std::string& path, Input& input, int threads = 0);
/// Reads a polygon mesh (OBJ or PLY by extension); on a problem prints it and returns its exit code.
int read_quads(const std::string& path, QuadMesh& mesh);
/// Writes the quad mesh (OBJ or PLY by extension) through a temporary file renamed into place;
/// `threads` format an OBJ's records (0: every core; the file is the same).
IoError write_quads(const std::string& path, const QuadMesh& mesh, int threads = 0);
/// Writes `text` to `path` through a temporary file renamed into place.
bool write_text(const std::string& path, const std::string& text);
/// Reads a feature-edge file (`i j` per line, 0-based vertex indices, `#` comments) into
/// `input.feature_edges`; on a problem prints it (with its line) and returns kParse or kIo.
int read_features(const std::string& path, Input& input);
/// Size of the file at `path` in bytes (0 if unknown).
std::uintmax_t size_of(const std::string& path);
/// A check of a real option: a finite number. CLI11's number checks compare, and NaN compares
/// false: they let `nan` through. Chain it with them.
CLI::Validator finite_number();

// The subcommands, each in its own file: its options (add_*), then its run (run_*).
struct ExtractArgs {
    std::string in_path, out_path, vval_path, report_path, features_path;
    std::string layout_path;      ///< --layout: the mesh's quad layout as JSON
    std::string certificate_path; ///< --certificate: the repaired map beside the mesh (qex::Certificate)
    bool poly = false, quiet = false, snap_boundary = false, round_seams = false, best_effort = false;
    bool no_fill_holes = false;
    bool no_repair = false; ///< --no-repair: the paper's handling of fold-overs, fast and uncertified
    int threads = 0;
    int max_refinement = Options{}.max_refinement;
    int max_coarsening = Options{}.max_coarsening;
};
CLI::App* add_extract(CLI::App& app, ExtractArgs& a);
int run_extract(const ExtractArgs& a);

struct CheckArgs {
    std::string param_path, mesh_path;
    std::string report_path, svg_path; ///< --report (the JSON verdict) and --svg (its picture)
    std::string certificate_path;      ///< --certificate: judge the mesh on qex extract's certificate
    bool json = false;
    int grid_scale = 1;
    VerifyOptions options;
};
CLI::App* add_check(CLI::App& app, CheckArgs& a);
int run_check(const CheckArgs& a);

struct InfoArgs {
    std::string map_path;
    bool json = false;
    int threads = 0;
};
CLI::App* add_info(CLI::App& app, InfoArgs& a);
int run_info(const InfoArgs& a);

struct DrawArgs {
    std::string map_path, quads_path, report_path, out_path;
    long long around = -1;
    double radius = 6.0;
    bool png = false;
    bool layout = false;          ///< with --quads: draw the mesh's quad layout instead of its defects
    int grid_scale = 0;           ///< with --quads: the scale to judge the mesh at (0: the report's, else 1)
    std::string certificate_path; ///< with --quads: judge the mesh on qex extract's certificate
};
CLI::App* add_draw(CLI::App& app, DrawArgs& a);
int run_draw(const DrawArgs& a);

struct BatchArgs {
    std::string input, out_dir, summary_path, format = "obj";
    int jobs = 0;
    bool quiet = false, force = false, snap_boundary = false, best_effort = false, no_fill_holes = false;
    bool no_repair = false;
    std::string self; ///< this program, run once per map
};
CLI::App* add_batch(CLI::App& app, BatchArgs& a);
int run_batch(const BatchArgs& a);

struct ConformArgs {
    std::string extractor, out_dir;
    std::vector<std::string> sets; ///< --cases, repeated (default: known and hostile)
    int count = 100, jobs = 0;
    std::uint64_t seed = 1;
    double timeout = 60.0;
    std::int64_t memory_mb = 4096;
    bool shrink = false, quiet = false;
    std::string self; ///< this program: replay.sh judges with it
};
CLI::App* add_conform(CLI::App& app, ConformArgs& a);
int run_conform(const ConformArgs& a);

struct LayoutArgs {
    std::string quads_path, out_path, param_path, obj_path, features_path;
    bool quiet = false;
};
CLI::App* add_layout(CLI::App& app, LayoutArgs& a);
int run_layout(const LayoutArgs& a);
/// The layout of `mesh` to `json_path` (and the mesh grouped by patch to `obj_path`, if not
/// empty); a summary on stdout unless `quiet`. kInvalidOutput when the layout check rejects it.
int write_layout(const std::string& json_path, const std::string& obj_path, const QuadMesh& mesh,
                 const LayoutOptions& options, bool quiet);

} // namespace qex::cli

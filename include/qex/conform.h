// A conformance run for any quad extractor (`qex conform`, Python's qex.conform): cases with a
// known answer (generated maps), hostile ones (folds, degeneracies, malformed files) and the
// user's own maps; each run in its own process with a time and memory limit, every output
// judged by the oracle's one entry (qex::check_mesh), and each case that is not right saved as
// a folder that replays it. src/conform/README.md has the case families and the outcomes.
#pragma once

#include "qex/mesh.h"
#include "qex/quality.h"
#include "qex/verify.h"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace qex {

/// How one case ended. to_string gives the snake-case names of the summary.
enum class ConformOutcome {
    Exact,           ///< a valid mesh with the known quad count
    Valid,           ///< a valid mesh (no count known, or as many quads as the map's area)
    ValidFewerQuads, ///< a valid mesh with fewer quads than the map's area (no count known)
    CleanFailure,    ///< a non-zero exit status
    InvalidExit0,    ///< exit 0 with a mesh the checker rejects (or for a map that is no valid input)
    WrongCount,      ///< exit 0, a valid mesh, but not the known quad count
    Crash,           ///< ended by a signal (named in the detail), or exit status 128 + N (the shell's for signal N)
    Timeout,         ///< killed at the time limit
    NoOutput,        ///< exit 0 without an output file, or with an empty one
};
const char* to_string(ConformOutcome outcome);

/// One perturbation of a generated map, applied in order: op names it (src/conform/README.md),
/// a and b are its parameters (a seed, a size, a place).
struct ConformStep {
    std::string op;
    double a = 0.0, b = 0.0;
};

/// What a generated case is built from: a layout's exact map, then its steps. Shrinking edits it.
struct ConformRecipe {
    std::string layout; ///< torus, cube, icosahedron, prism, disk, annulus
    int n = 2;          ///< grid quads per layout edge
    int k = 2;          ///< lattice steps per layout edge
    int diagonals = 1;  ///< make_map's diagonals (0 one way, 1 alternating, 2 random)
    std::uint64_t seed = 1;
    std::vector<ConformStep> steps;
};

struct ConformCase {
    std::string name;                 ///< stable for a seed: "known/torus/0003"
    std::string family;               ///< the table's row: "known/torus", "hostile/fold", "user"
    std::string kind;                 ///< "known", "hostile" or "user"
    std::string map_path;             ///< a user's map (then no recipe)
    bool generated = false;           ///< built from `recipe`
    ConformRecipe recipe;             ///< generated cases
    std::int64_t expected_quads = -1; ///< known cases: the exact count; -1 unknown
};

/// The cases of `sets`, each "known", "hostile", a folder of maps (*.obj, *.ply) or a list file
/// (one path per line, `#` comments); `count` cases per generated set, drawn from `seed` alone
/// (the same cases on any machine). On a problem: empty, with `error` set.
std::vector<ConformCase> conform_cases(const std::vector<std::string>& sets, int count, std::uint64_t seed,
                                       std::string* error = nullptr);
/// The maps of a folder (its *.obj and *.ply files, sorted) or of a list file (one path per
/// line, `#` comments, relative to the list's folder), as `qex batch` and `qex conform` read them.
bool collect_map_files(const std::string& input, std::vector<std::string>& maps);
/// A generated case's map file: OBJ text (malformed on purpose for some hostile steps).
std::string conform_map_text(const ConformCase& c);
/// The recipe in words ("cube n=2 k=3; rechart 81; noise 1e-07").
std::string conform_describe(const ConformCase& c);

/// How the extractor's process ended.
struct ConformRun {
    int exit_code = 0;      ///< its exit status (when not signalled)
    int signal = 0;         ///< the signal that ended it, 0 if none
    bool timed_out = false; ///< killed at the time limit
    double seconds = 0.0;   ///< wall-clock time
};

/// One case judged.
struct ConformResult {
    ConformCase c;
    ConformRun run;
    ConformOutcome outcome = ConformOutcome::NoOutput;
    bool right = false;
    std::int64_t quads = -1; ///< faces of the output mesh, -1 without one
    std::int64_t area = -1;  ///< the map's signed UV area rounded (at grid scale 1), -1 for a map no valid input
    /// The grid scale the output was judged at: 1, or the first power of two (2 to 64, as
    /// `qex check --grid-scale` takes) at which a mesh off the map's grid points is valid (a
    /// refined mesh, as `qex extract` writes when the map's own scale gives none).
    int grid_scale = 1;
    std::string detail;       ///< why, in a line: the verdict line, the signal, the exit code
    std::string verdict_json; ///< the checker's verdict on the output at grid_scale (empty if none was judged)
    MeshQuality quality;      ///< of a valid mesh
    std::string folder;       ///< the reproducer's folder (cases not right), else empty
    std::string shrunk;       ///< --shrink: the smaller failing recipe in words, else empty
};

/// Whether `outcome` is right for a case of `kind`: known cases must be Exact; hostile cases
/// and user maps a valid mesh (Exact, Valid, ValidFewerQuads) or a CleanFailure.
bool conform_right(const std::string& kind, ConformOutcome outcome);

/// Judges one finished run through qex::check_mesh: the map at `map_path`, the output at
/// `out_path` (OBJ or PLY by its extension); at grid scale 1, and when the mesh is invalid there
/// with vertices off the grid points, at grid scales 2 to 64 (ConformResult::grid_scale).
ConformResult conform_judge(const ConformCase& c, const std::string& map_path, const std::string& out_path,
                            const ConformRun& run);

/// The extractor, called in a child process (its stdout and stderr go to files) with the map's
/// path and the output's; its return value is the exit status. A command extractor execs.
using ConformExtractor = std::function<int(const std::string& in, const std::string& out)>;
/// Runs `command` through /bin/sh -c with {in} and {out} (and {report}: a file beside the
/// output) replaced by the paths, quoted for the shell.
ConformExtractor shell_extractor(const std::string& command);
/// `command` with its placeholders replaced, as shell_extractor runs it.
std::string shell_command(const std::string& command, const std::string& in, const std::string& out);

struct ConformOptions {
    std::string out_dir;               ///< the report's folder: summary.jsonl, cases/ for the reproducers
    int jobs = 1;                      ///< cases run at once
    double timeout = 60.0;             ///< seconds per case
    std::int64_t memory_mb = 4096;     ///< address-space limit per case (RLIMIT_AS), 0: none
    bool shrink = false;               ///< reduce each failing generated case to a smaller one
    std::string out_extension = "obj"; ///< the output file's extension ({out})
    /// The reproducer's command line with {in} and {out}, for replay.sh (the CLI's --extractor);
    /// empty: replay.sh says the extractor has no command line.
    std::string replay_command;
    std::string checker = "qex"; ///< the qex program replay.sh judges the output with
    /// An SVG of a verdict for the reproducer (the CLI draws as `qex draw --quads`); may be empty.
    std::function<std::string(const Input&, const QuadMesh&, const VerifyResult&)> picture;
    /// Called after each case (done, total, not right so far).
    std::function<void(std::size_t, std::size_t, std::size_t)> on_progress;
};

/// Runs every case (options.jobs at a time, each in its own process), judges it, writes the
/// reproducer of every case not right and summary.jsonl into options.out_dir. The results in
/// the cases' order.
std::vector<ConformResult> conform(const std::vector<ConformCase>& cases, const ConformExtractor& extractor,
                                   const ConformOptions& options);

/// Writes the folder that replays a case not right, under options.out_dir/cases/: the map, the
/// output, the extractor's stderr, the verdict (JSON, SVG), case.json and replay.sh. Returns
/// the folder, or empty when it cannot be written.
std::string write_reproducer(const ConformResult& r, const std::string& map_path, const std::string& out_path,
                             const std::string& stderr_path, const ConformOptions& options);

/// A summary row as one line of JSON: case, family, kind, outcome, right, exit_code, signal,
/// seconds, quads, expected_quads, area, grid_scale, detail, recipe, folder, shrunk.
std::string conform_summary_line(const ConformResult& r);
/// The table per family: counts per outcome, the extractor's seconds per case (median,
/// worst), and the quality of the valid meshes (smallest scaled Jacobian, mean of the means).
/// `rows` are summary lines as conform_summary_line writes them (what Python collects too).
std::string conform_table(const std::vector<std::string>& rows);
/// The case as JSON (name, family, kind, map_path, generated, recipe, expected_quads), and back.
std::string conform_case_json(const ConformCase& c);
ConformCase conform_case_from_json(const std::string& json);

} // namespace qex

// qex: command-line front end. `qex extract` turns an OBJ with an integer-grid map into a quad
// mesh and checks it; `qex check` judges any quad mesh against a map.
#include "qex/qex.h"
#include "heap_policy.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <cstdio>
#include <fstream>
#include <iostream>

namespace {

// Exit codes; each failure family has its own.
enum Exit : int {
    kOk = 0,
    kUsage = 1,         // bad command line
    kIo = 2,            // a file cannot be read or written
    kParse = 3,         // malformed OBJ or VVAL
    kBadInput = 4,      // the mesh or map is not acceptable input
    kInvalidOutput = 5, // extraction finished but the checker rejects its output
    kRejected = 6,      // `qex check`: the judged mesh is not valid
};

int io_exit(const qex::IoError& e) {
    return e.code == qex::IoError::Code::CannotOpen || e.code == qex::IoError::Code::CannotWrite ? kIo : kParse;
}

/// One violation: its kind, the element it names and that element's kind, and its places.
nlohmann::json violation_json(const qex::Violation& x) {
    static const char* const element_names[] = {"none", "face", "vertex", "input_vertex", "input_triangle"};
    nlohmann::json places = nlohmann::json::array();
    for (const auto& p : x.places) places.push_back({{"kind", qex::to_string(p.kind)}, {"indices", p.indices}});
    return {{"kind", qex::to_string(x.kind)},
            {"element", x.element},
            {"element_kind", element_names[static_cast<int>(qex::element_kind(x.kind))]},
            {"places", places},
            {"message", x.message}};
}

nlohmann::json to_json(const qex::VerifyResult& v) {
    nlohmann::json j;
    j["valid"] = v.valid;
    j["faces"] = v.faces;
    j["vertices"] = v.vertices;
    j["edges"] = v.edges;
    j["euler"] = v.euler;
    j["boundary_loops"] = v.boundary_loops;
    j["components"] = v.components;
    j["map_displacement"] = {{"max", v.max_map_displacement}, {"sum", v.sum_map_displacement}};
    j["map_singularities"] = v.map_singularities;
    if (v.located)
        j["located"] = {{"max_grid_distance", v.max_grid_distance},
                        {"max_surface_distance", v.max_surface_distance},
                        {"map_flipped_triangles", v.map_flipped_triangles},
                        {"coverage_difference", v.coverage_difference}};
    j["input"] = {{"euler", v.input_euler},
                  {"boundary_loops", v.input_boundary_loops},
                  {"components", v.input_components},
                  {"signed_uv_area", v.input_signed_uv_area}};
    if (v.located)
        j["located"]["precision"] = {{"position_digits", v.position_digits},
                                     {"positions_float32", v.positions_float32},
                                     {"surface_tolerance", v.surface_tolerance},
                                     {"max_rounding_tolerance", v.max_rounding_tolerance}};
    j["undecided"] = nlohmann::json::array();
    for (const auto& x : v.undecided) j["undecided"].push_back(violation_json(x));
    j["violations"] = nlohmann::json::array();
    for (const auto& x : v.violations) j["violations"].push_back(violation_json(x));
    return j;
}

nlohmann::json to_json(const qex::Defect& d) {
    nlohmann::json j = {{"kind", qex::to_string(d.kind)},
                        {"input_element", d.input_element},
                        {"output_face", d.output_face},
                        {"grid", {d.grid[0], d.grid[1]}},
                        {"message", d.message}};
    if (d.violation) j["violation"] = qex::to_string(*d.violation);
    return j;
}

/// The report's counts, stage by stage.
nlohmann::json counts_json(const qex::Report& r) {
    nlohmann::json j;
    j["input"] = {{"vertices", r.input_vertices},
                  {"triangles", r.input_triangles},
                  {"flipped_triangles", r.flipped_triangles},
                  {"degenerate_triangles", r.degenerate_triangles},
                  {"collapsed_edges", r.collapsed_edges},
                  {"singularities", r.singularities},
                  {"signed_uv_area", r.signed_uv_area}};
    j["sanitization"] = {{"max_displacement", r.max_sanitization_displacement},
                         {"sum_displacement", r.sum_sanitization_displacement}};
    j["qvertices"] = {{"on_vertices", r.qvertices_on_vertices},
                      {"on_edges", r.qvertices_on_edges},
                      {"in_faces", r.qvertices_in_faces}};
    j["ports"] = r.ports;
    j["traces"] = {{"started", r.traces},
                   {"connected", r.traces_connected},
                   {"into_boundary", r.traces_into_boundary},
                   {"failed", r.traces_failed},
                   {"orientation_flips_crossed", r.orientation_flips_crossed}};
    j["faces"] = {{"traced", r.faces_traced},
                  {"boundary_discarded", r.boundary_faces_discarded},
                  {"open_walks", r.open_face_walks},
                  {"recovered_edges", r.recovered_edges},
                  {"merged_qvertices", r.merged_qvertices},
                  {"collapsed", r.collapsed_faces},
                  {"ghosts_cancelled", r.ghost_faces_cancelled},
                  {"non_quad", r.non_quad_faces}};
    return j;
}

nlohmann::json to_json(const qex::Report& r) {
    nlohmann::json j = counts_json(r);
    j["fallback"] = {{"rung", r.rung}, {"rungs_tried", r.rungs_tried}, {"unplaced_vertices", r.unplaced_vertices}};
    j["repair"] = {{"repaired_regions", r.repaired_regions},
                   {"repaired_triangles", r.repaired_triangles},
                   {"unrepaired_regions", r.unrepaired_regions},
                   {"flipped_after_repair", r.flipped_after_repair}};
    j["defects"] = nlohmann::json::array();
    for (const auto& d : r.defects) j["defects"].push_back(to_json(d));
    j["explanations"] = nlohmann::json::array();
    for (const auto& d : r.explanations)
        j["explanations"].push_back({{"kind", qex::to_string(d.kind)},
                                     {"input_element", d.input_element},
                                     {"grid", {d.grid[0], d.grid[1]}},
                                     {"message", d.message}});
    j["stage_seconds"] = nlohmann::json::object();
    for (const auto& [name, s] : r.stage_seconds) j["stage_seconds"][name] = s;
    return j;
}

bool write_text(const std::string& path, const std::string& text) {
    const std::string tmp = path + ".tmp";
    {
        std::ofstream f(tmp, std::ios::binary);
        if (!f || !(f << text)) return false;
    }
    return std::rename(tmp.c_str(), path.c_str()) == 0;
}

void print_violations(const qex::VerifyResult& v, std::size_t limit = 20) {
    for (std::size_t i = 0; i < v.violations.size() && i < limit; ++i)
        std::cerr << "  " << qex::to_string(v.violations[i].kind) << ": " << v.violations[i].message << "\n";
    if (v.violations.size() > limit) std::cerr << "  ... and " << v.violations.size() - limit << " more\n";
    for (std::size_t i = 0; i < v.undecided.size() && i < limit; ++i)
        std::cerr << "  undecided: " << qex::to_string(v.undecided[i].kind) << ": " << v.undecided[i].message << "\n";
    if (v.undecided.size() > limit) std::cerr << "  ... and " << v.undecided.size() - limit << " more undecided\n";
}

/// What `qex extract` was asked to do.
struct ExtractArgs {
    std::string in_path, out_path, vval_path, report_path;
    bool poly = false, quiet = false;
    int threads = 0;
};

/// Reads the map (and valences); returns the exit code of a failure, or kOk.
int read_input(const ExtractArgs& a, qex::Input& input) {
    if (const auto e = qex::read_obj(a.in_path, input, a.threads); !e.ok()) {
        std::cerr << "qex: " << a.in_path << ": " << e.message << "\n";
        return io_exit(e);
    }
    if (!a.vval_path.empty())
        if (const auto e = qex::read_vval(a.vval_path, input.valences); !e.ok()) {
            std::cerr << "qex: " << a.vval_path << ": " << e.message << "\n";
            return io_exit(e);
        }
    return kOk;
}

bool write_report(const std::string& path, const qex::Result& result, double read_seconds, double extract_seconds) {
    nlohmann::json j = to_json(result.report);
    j["check"] = to_json(result.check);
    j["seconds"] = {{"read", read_seconds}, {"extract_and_check", extract_seconds}};
    return write_text(path, j.dump(2) + "\n");
}

/// The checker rejected the mesh: its defects and violations on stderr, the mesh only with --poly.
int reject(const ExtractArgs& a, const qex::Result& result) {
    const qex::VerifyResult& check = result.check;
    const auto& defects = result.report.defects;
    std::cerr << "qex: " << a.in_path << ": the extracted mesh fails the check (" << check.violations.size()
              << " violations, " << defects.size() << " extraction defects)\n";
    for (std::size_t i = 0; i < defects.size() && i < 20; ++i)
        std::cerr << "  " << qex::to_string(defects[i].kind)
                  << (defects[i].violation ? std::string(" ") + qex::to_string(*defects[i].violation) : "") << ": "
                  << defects[i].message << "\n";
    print_violations(check);
    if (a.poly) {
        if (const auto e = qex::write_obj(a.out_path, result.mesh); !e.ok()) {
            std::cerr << "qex: " << e.message << "\n";
            return kIo;
        }
        std::cerr << "qex: wrote the invalid mesh to " << a.out_path << " (--poly)\n";
    }
    return kInvalidOutput;
}

int run_extract(const ExtractArgs& a) {
    const auto t0 = std::chrono::steady_clock::now();
    qex::Input input;
    if (const int code = read_input(a, input); code != kOk) return code;
    const auto t1 = std::chrono::steady_clock::now();
    qex::Options options;
    options.threads = a.threads;
    const qex::Result result = qex::extract(input, options);
    if (!result.ok()) {
        std::cerr << "qex: " << a.in_path << ": invalid input (" << qex::to_string(result.error.code)
                  << "): " << result.error.message << "\n";
        return kBadInput;
    }
    const auto t2 = std::chrono::steady_clock::now();
    const auto seconds = [](auto d) { return std::chrono::duration<double>(d).count(); };
    if (!a.report_path.empty() && !write_report(a.report_path, result, seconds(t1 - t0), seconds(t2 - t1))) {
        std::cerr << "qex: cannot write report '" << a.report_path << "'\n";
        return kIo;
    }
    if (!result.check.valid) return reject(a, result); // the checker's verdict, taken inside extract()
    if (const auto e = qex::write_obj(a.out_path, result.mesh); !e.ok()) {
        std::cerr << "qex: " << e.message << "\n";
        return kIo;
    }
    const auto& r = result.report;
    if (!a.quiet)
        std::printf(
            "qex: %zu quads, %zu vertices (signed UV area %.1f, %lld flipped triangles, %lld merged, "
            "%lld recovered edges, map %s) -> %s\n",
            result.mesh.faces.size(), result.mesh.positions.size(), r.signed_uv_area,
            static_cast<long long>(r.flipped_triangles), static_cast<long long>(r.merged_qvertices),
            static_cast<long long>(r.recovered_edges), r.rung.c_str(), a.out_path.c_str());
    return kOk;
}

/// What `qex check` was asked to do.
struct CheckArgs {
    std::string param_path, mesh_path;
    bool json = false;
    qex::VerifyOptions options;
};

/// The verdict in words, on stdout.
void print_verdict(const std::string& mesh_path, const qex::VerifyResult& v) {
    std::printf(
        "%s: %lld faces, %lld vertices, euler %lld (input %lld), boundary loops %lld (input %lld), "
        "components %lld (input %lld), input signed UV area %s\n",
        mesh_path.c_str(), static_cast<long long>(v.faces), static_cast<long long>(v.vertices),
        static_cast<long long>(v.euler), static_cast<long long>(v.input_euler),
        static_cast<long long>(v.boundary_loops), static_cast<long long>(v.input_boundary_loops),
        static_cast<long long>(v.components), static_cast<long long>(v.input_components),
        v.input_signed_uv_area.c_str());
    if (v.located) {
        std::printf(
            "located on the map: largest distance to a grid point %.3g (UV), to the surface %.3g (of the "
            "diagonal); %lld faces against the map's area %lld",
            v.max_grid_distance, v.max_surface_distance, static_cast<long long>(v.faces),
            static_cast<long long>(v.input_signed_uv_area_rounded));
        if (v.coverage_difference != 0 && v.map_flipped_triangles > 0)
            std::printf(" (the map has %lld flipped triangles, so full coverage may be impossible)",
                        static_cast<long long>(v.map_flipped_triangles));
        std::printf("\n");
        std::printf(
            "positions carry up to %d significant digits%s; distance tolerance %.3g + up to %.3g for rounding "
            "(model units)\n",
            v.position_digits, v.positions_float32 ? " (float32 values)" : "", v.surface_tolerance,
            v.max_rounding_tolerance);
    }
    print_violations(v);
    std::printf("%s\n", v.valid ? "VALID" : "INVALID");
}

int run_check(const CheckArgs& a) {
    qex::Input input;
    if (const auto e = qex::read_obj(a.param_path, input); !e.ok()) {
        std::cerr << "qex: " << a.param_path << ": " << e.message << "\n";
        return io_exit(e);
    }
    // The map is the judge's reference: one that extraction would reject judges nothing.
    if (const qex::Error e = qex::validate(input); e.code != qex::ErrorCode::None) {
        std::cerr << "qex: " << a.param_path << ": invalid input (" << qex::to_string(e.code) << "): " << e.message
                  << "\n";
        return kBadInput;
    }
    qex::QuadMesh mesh;
    if (const auto e = qex::read_polygon_obj(a.mesh_path, mesh); !e.ok()) {
        std::cerr << "qex: " << a.mesh_path << ": " << e.message << "\n";
        return io_exit(e);
    }
    const qex::VerifyResult v = qex::verify(input, mesh, a.options);
    if (a.json)
        std::cout << to_json(v).dump(2) << "\n";
    else
        print_verdict(a.mesh_path, v);
    return v.valid ? kOk : kRejected;
}

std::uintmax_t size_of(const std::string& path) {
    std::error_code ec;
    const std::uintmax_t bytes = std::filesystem::file_size(path, ec);
    return ec ? 0 : bytes;
}

CLI::App* add_extract(CLI::App& app, ExtractArgs& a) {
    auto* extract = app.add_subcommand("extract", "Extract the quad mesh of an OBJ carrying per-corner UVs (vt)");
    extract->add_option("input", a.in_path, "input OBJ: v, vt and f a/ta b/tb c/tc records")->required();
    extract->add_option("-o,--output", a.out_path, "output OBJ (quads, local UVs as vt)")->required();
    extract->add_option("--valences", a.vval_path, "VVAL file with per-vertex cross-field valences");
    extract->add_option("--report", a.report_path, "write a JSON report (counts, defects, timings, check)");
    extract->add_flag("--poly", a.poly, "write the mesh even if faces are not quads (exit code stays 5)");
    extract
        ->add_option("--threads", a.threads, "threads for the parallel loops (0: every core, 1: serial); same output")
        ->check(CLI::Range(0, 1024));
    extract->add_flag("-q,--quiet", a.quiet, "print nothing on success");
    return extract;
}

CLI::App* add_check(CLI::App& app, CheckArgs& a) {
    auto* check = app.add_subcommand("check", "Judge a quad mesh (from any extractor) against an integer-grid map");
    check->add_option("--param", a.param_path, "the map: OBJ with per-corner UVs")->required();
    check->add_option("mesh", a.mesh_path, "the quad mesh OBJ to judge")->required();
    check->add_flag("--json", a.json, "print the verdict as JSON");
    check
        ->add_option("--uv-tolerance", a.options.uv_tolerance,
                     "largest UV distance of a vertex to its grid point (default 1e-3)")
        ->check(CLI::NonNegativeNumber);
    check
        ->add_option("--distance-tolerance", a.options.distance_tolerance,
                     "largest distance of a vertex to the surface, as a fraction of the diagonal (default 1e-6)")
        ->check(CLI::NonNegativeNumber);
    check
        ->add_option("--digits", a.options.position_digits,
                     "the positions may be rounded to this many significant digits (default 6: float precision)")
        ->check(CLI::Range(0, 17));
    check->add_flag(
        "--strict", [&a](std::int64_t) { a.options.position_digits = 0; },
        "double-precision output: no allowance for rounded positions (--digits 0)");
    check->add_flag(
        "--topology-only", [&a](std::int64_t) { a.options.locate = false; }, "skip locating the vertices on the map");
    return check;
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"qex: robust quad mesh extraction from integer-grid maps (QEx)"};
    app.require_subcommand(0, 1);
    ExtractArgs extract_args;
    CheckArgs check_args;
    CLI::App* extract = add_extract(app, extract_args);
    CLI::App* check = add_check(app, check_args);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) { return app.exit(e) == 0 ? kOk : kUsage; }
    if (*extract) {
        qex::cli::prepare_heap(size_of(extract_args.in_path));
        return run_extract(extract_args);
    }
    if (*check) {
        qex::cli::prepare_heap(size_of(check_args.param_path) + size_of(check_args.mesh_path));
        return run_check(check_args);
    }
    std::cout << app.help();
    return kUsage;
}

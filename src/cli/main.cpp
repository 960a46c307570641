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
    kUsage = 1,        // bad command line
    kIo = 2,           // a file cannot be read or written
    kParse = 3,        // malformed OBJ or VVAL
    kBadInput = 4,     // the mesh or map is not acceptable input
    kInvalidOutput = 5,// extraction finished but the checker rejects its output
    kRejected = 6,     // `qex check`: the judged mesh is not valid
};

int io_exit(const qex::IoError& e) {
    return e.code == qex::IoError::Code::CannotOpen || e.code == qex::IoError::Code::CannotWrite ? kIo : kParse;
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
    j["undecided"] = nlohmann::json::array();
    for (const auto& x : v.undecided)
        j["undecided"].push_back({{"kind", qex::to_string(x.kind)}, {"element", x.element}, {"message", x.message}});
    j["violations"] = nlohmann::json::array();
    for (const auto& x : v.violations)
        j["violations"].push_back({{"kind", qex::to_string(x.kind)}, {"element", x.element}, {"message", x.message}});
    return j;
}

nlohmann::json to_json(const qex::Report& r) {
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
    j["fallback"] = {{"rung", r.rung},
                     {"rungs_tried", r.rungs_tried},
                     {"flipped_after_untangling", r.flipped_after_untangling},
                     {"unplaced_vertices", r.unplaced_vertices}};
    j["defects"] = nlohmann::json::array();
    for (const auto& d : r.defects) {
        nlohmann::json defect = {{"kind", qex::to_string(d.kind)},
                                 {"input_element", d.input_element},
                                 {"output_face", d.output_face},
                                 {"grid", {d.grid[0], d.grid[1]}},
                                 {"message", d.message}};
        if (d.violation) defect["violation"] = qex::to_string(*d.violation);
        j["defects"].push_back(std::move(defect));
    }
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

int run_extract(const std::string& in_path, const std::string& out_path, const std::string& vval_path,
                const std::string& report_path, bool poly, bool quiet, int threads) {
    const auto t0 = std::chrono::steady_clock::now();
    qex::Input input;
    if (const auto e = qex::read_obj(in_path, input, threads); !e.ok()) {
        std::cerr << "qex: " << in_path << ": " << e.message << "\n";
        return io_exit(e);
    }
    if (!vval_path.empty())
        if (const auto e = qex::read_vval(vval_path, input.valences); !e.ok()) {
            std::cerr << "qex: " << vval_path << ": " << e.message << "\n";
            return io_exit(e);
        }
    const auto t1 = std::chrono::steady_clock::now();
    qex::Options options;
    options.threads = threads;
    qex::Result result = qex::extract(input, options);
    if (!result.ok()) {
        std::cerr << "qex: " << in_path << ": invalid input (" << qex::to_string(result.error.code)
                  << "): " << result.error.message << "\n";
        return kBadInput;
    }
    const qex::VerifyResult& check = result.check; // the checker's verdict, taken inside extract()
    const auto t2 = std::chrono::steady_clock::now();
    const auto& r = result.report;
    if (!report_path.empty()) {
        nlohmann::json j = to_json(r);
        j["check"] = to_json(check);
        j["seconds"] = {{"read", std::chrono::duration<double>(t1 - t0).count()},
                        {"extract_and_check", std::chrono::duration<double>(t2 - t1).count()}};
        if (!write_text(report_path, j.dump(2) + "\n")) {
            std::cerr << "qex: cannot write report '" << report_path << "'\n";
            return kIo;
        }
    }
    if (!check.valid) {
        std::cerr << "qex: " << in_path << ": the extracted mesh fails the check (" << check.violations.size()
                  << " violations, " << r.defects.size() << " extraction defects)\n";
        for (std::size_t i = 0; i < r.defects.size() && i < 20; ++i)
            std::cerr << "  " << qex::to_string(r.defects[i].kind)
                      << (r.defects[i].violation ? std::string(" ") + qex::to_string(*r.defects[i].violation) : "")
                      << ": " << r.defects[i].message << "\n";
        print_violations(check);
        if (poly) {
            if (const auto e = qex::write_obj(out_path, result.mesh); !e.ok()) {
                std::cerr << "qex: " << e.message << "\n";
                return kIo;
            }
            std::cerr << "qex: wrote the invalid mesh to " << out_path << " (--poly)\n";
        }
        return kInvalidOutput;
    }
    if (const auto e = qex::write_obj(out_path, result.mesh); !e.ok()) {
        std::cerr << "qex: " << e.message << "\n";
        return kIo;
    }
    if (!quiet)
        std::printf("qex: %zu quads, %zu vertices (signed UV area %.1f, %lld flipped triangles, %lld merged, "
                    "%lld recovered edges, map %s) -> %s\n",
                    result.mesh.faces.size(), result.mesh.positions.size(), r.signed_uv_area,
                    static_cast<long long>(r.flipped_triangles), static_cast<long long>(r.merged_qvertices),
                    static_cast<long long>(r.recovered_edges), r.rung.c_str(), out_path.c_str());
    return kOk;
}

int run_check(const std::string& param_path, const std::string& mesh_path, bool json, const qex::VerifyOptions& options) {
    qex::Input input;
    if (const auto e = qex::read_obj(param_path, input); !e.ok()) {
        std::cerr << "qex: " << param_path << ": " << e.message << "\n";
        return io_exit(e);
    }
    // The map is the judge's reference: one that extraction would reject judges nothing.
    if (const qex::Error e = qex::validate(input); e.code != qex::ErrorCode::None) {
        std::cerr << "qex: " << param_path << ": invalid input (" << qex::to_string(e.code) << "): " << e.message << "\n";
        return kBadInput;
    }
    qex::QuadMesh mesh;
    if (const auto e = qex::read_polygon_obj(mesh_path, mesh); !e.ok()) {
        std::cerr << "qex: " << mesh_path << ": " << e.message << "\n";
        return io_exit(e);
    }
    const qex::VerifyResult v = qex::verify(input, mesh, options);
    if (json) {
        std::cout << to_json(v).dump(2) << "\n";
    } else {
        std::printf("%s: %lld faces, %lld vertices, euler %lld (input %lld), boundary loops %lld (input %lld), "
                    "components %lld (input %lld), input signed UV area %s\n",
                    mesh_path.c_str(), static_cast<long long>(v.faces), static_cast<long long>(v.vertices),
                    static_cast<long long>(v.euler), static_cast<long long>(v.input_euler),
                    static_cast<long long>(v.boundary_loops), static_cast<long long>(v.input_boundary_loops),
                    static_cast<long long>(v.components), static_cast<long long>(v.input_components),
                    v.input_signed_uv_area.c_str());
        if (v.located) {
            std::printf("located on the map: largest distance to a grid point %.3g (UV), to the surface %.3g (of the "
                        "diagonal); %lld faces against the map's area %lld",
                        v.max_grid_distance, v.max_surface_distance, static_cast<long long>(v.faces),
                        static_cast<long long>(v.input_signed_uv_area_rounded));
            if (v.coverage_difference != 0 && v.map_flipped_triangles > 0)
                std::printf(" (the map has %lld flipped triangles, so full coverage may be impossible)",
                            static_cast<long long>(v.map_flipped_triangles));
            std::printf("\n");
        }
        print_violations(v);
        std::printf("%s\n", v.valid ? "VALID" : "INVALID");
    }
    return v.valid ? kOk : kRejected;
}

std::uintmax_t size_of(const std::string& path) {
    std::error_code ec;
    const std::uintmax_t bytes = std::filesystem::file_size(path, ec);
    return ec ? 0 : bytes;
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"qex: robust quad mesh extraction from integer-grid maps (QEx)"};
    app.require_subcommand(0, 1);

    std::string in_path, out_path, vval_path, report_path;
    bool poly = false, quiet = false;
    auto* extract = app.add_subcommand("extract", "Extract the quad mesh of an OBJ carrying per-corner UVs (vt)");
    extract->add_option("input", in_path, "input OBJ: v, vt and f a/ta b/tb c/tc records")->required();
    extract->add_option("-o,--output", out_path, "output OBJ (quads, local UVs as vt)")->required();
    extract->add_option("--valences", vval_path, "VVAL file with per-vertex cross-field valences");
    extract->add_option("--report", report_path, "write a JSON report (counts, defects, timings, check)");
    extract->add_flag("--poly", poly, "write the mesh even if faces are not quads (exit code stays 5)");
    int threads = 0;
    extract->add_option("--threads", threads, "threads for the parallel loops (0: every core, 1: serial); same output")
        ->check(CLI::Range(0, 1024));
    extract->add_flag("-q,--quiet", quiet, "print nothing on success");

    std::string param_path, mesh_path;
    bool json = false;
    auto* check = app.add_subcommand("check", "Judge a quad mesh (from any extractor) against an integer-grid map");
    check->add_option("--param", param_path, "the map: OBJ with per-corner UVs")->required();
    check->add_option("mesh", mesh_path, "the quad mesh OBJ to judge")->required();
    check->add_flag("--json", json, "print the verdict as JSON");
    qex::VerifyOptions verify_options;
    check->add_option("--uv-tolerance", verify_options.uv_tolerance,
                      "largest UV distance of a vertex to its grid point (default 1e-3)")
        ->check(CLI::NonNegativeNumber);
    check->add_option("--distance-tolerance", verify_options.distance_tolerance,
                      "largest distance of a vertex to the surface, as a fraction of the diagonal (default 1e-6)")
        ->check(CLI::NonNegativeNumber);
    check->add_flag("--topology-only", [&](std::int64_t) { verify_options.locate = false; },
                    "skip locating the vertices on the map");

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e) == 0 ? kOk : kUsage;
    }
    if (*extract) {
        qex::cli::prepare_heap(size_of(in_path));
        return run_extract(in_path, out_path, vval_path, report_path, poly, quiet, threads);
    }
    if (*check) {
        qex::cli::prepare_heap(size_of(param_path) + size_of(mesh_path));
        return run_check(param_path, mesh_path, json, verify_options);
    }
    std::cout << app.help();
    return kUsage;
}

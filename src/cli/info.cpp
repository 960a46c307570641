// `qex info MAP [--json]`: what is wrong with a map before extracting it (map_info.h).
#include "cli.h"
#include "map_info.h"
#include "progress.h"

#include <nlohmann/json.hpp>

#include <cstdio>
#include <iostream>

namespace qex::cli {
namespace {

nlohmann::json to_json(const MapInfo& m) {
    nlohmann::json j;
    j["vertices"] = m.vertices;
    j["triangles"] = m.triangles;
    j["edges"] = m.edges;
    j["components"] = m.components;
    j["boundary_loops"] = m.boundary_loops;
    j["euler"] = m.euler;
    j["genus"] = m.genus;
    j["signed_uv_area"] = m.signed_uv_area;
    j["flipped_triangles"] = m.flipped;
    j["degenerate_triangles"] = m.degenerate;
    j["fold_regions"] = nlohmann::json::array();
    for (const FoldRegion& r : m.fold_regions)
        j["fold_regions"].push_back({{"triangles", r.triangles},
                                     {"triangle_count", r.triangles.size()},
                                     {"uv_area", r.uv_area},
                                     {"grid_box", {{r.grid_lo[0], r.grid_lo[1]}, {r.grid_hi[0], r.grid_hi[1]}}}});
    j["singularities"] = nlohmann::json::array();
    for (const Singularity& s : m.singularities)
        j["singularities"].push_back({{"vertex", s.vertex},
                                      {"valence", s.valence},
                                      {"grid", {s.grid[0], s.grid[1]}},
                                      {"triangle", s.triangle},
                                      {"in_fold", s.in_fold}});
    if (m.sanitized) {
        j["charts"] = m.charts;
        j["max_sanitization_displacement"] = m.max_sanitization_displacement;
        j["sanitized_singularities"] = m.sanitized_singularities;
    }
    return j;
}

void print_text(const std::string& path, const MapInfo& m) {
    std::printf("%s\n", path.c_str());
    std::printf(
        "  %lld vertices, %lld triangles, %lld edges, %lld components, %lld boundary loops, euler %lld, "
        "genus %lld\n",
        static_cast<long long>(m.vertices), static_cast<long long>(m.triangles), static_cast<long long>(m.edges),
        static_cast<long long>(m.components), static_cast<long long>(m.boundary_loops), static_cast<long long>(m.euler),
        static_cast<long long>(m.genus));
    std::printf("  signed UV area %.3f (about the quad count), %lld flipped and %lld degenerate triangles\n",
                m.signed_uv_area, static_cast<long long>(m.flipped), static_cast<long long>(m.degenerate));
    if (m.sanitized)
        std::printf(
            "  %lld charts after cutting, largest sanitization displacement %.3g, %lld singularities "
            "after sanitization\n",
            static_cast<long long>(m.charts), m.max_sanitization_displacement,
            static_cast<long long>(m.sanitized_singularities));
    std::printf("  %zu fold-over regions%s\n", m.fold_regions.size(), m.fold_regions.empty() ? "" : ":");
    for (std::size_t i = 0; i < m.fold_regions.size() && i < 30; ++i) {
        const FoldRegion& r = m.fold_regions[i];
        std::printf("    R%zu: %zu triangles (first %d), UV area %.4f, grid box [%lld, %lld] x [%lld, %lld]\n", i + 1,
                    r.triangles.size(), r.triangles.front(), r.uv_area, static_cast<long long>(r.grid_lo[0]),
                    static_cast<long long>(r.grid_hi[0]), static_cast<long long>(r.grid_lo[1]),
                    static_cast<long long>(r.grid_hi[1]));
    }
    if (m.fold_regions.size() > 30)
        std::printf("    ... and %zu more (--json lists all)\n", m.fold_regions.size() - 30);
    std::printf("  %zu singularities%s\n", m.singularities.size(), m.singularities.empty() ? "" : ":");
    for (std::size_t i = 0; i < m.singularities.size() && i < 30; ++i) {
        const Singularity& s = m.singularities[i];
        std::printf("    vertex %d: valence %d at grid (%lld, %lld) of triangle %d%s\n", s.vertex, s.valence,
                    static_cast<long long>(s.grid[0]), static_cast<long long>(s.grid[1]), s.triangle,
                    s.in_fold ? ", in a fold-over" : "");
    }
    if (m.singularities.size() > 30)
        std::printf("    ... and %zu more (--json lists all)\n", m.singularities.size() - 30);
}

} // namespace

CLI::App* add_info(CLI::App& app, InfoArgs& a) {
    auto* info = app.add_subcommand("info", "Report a map before extraction: topology, fold-overs, singularities");
    info->add_option("map", a.map_path, "the map: OBJ or PLY with per-corner UVs")->required();
    info->add_flag("--json", a.json, "print one JSON object");
    info->add_option("--threads", a.threads, "threads (0: every core, 1: serial)")->check(CLI::Range(0, 1024));
    return info;
}

int run_info(const InfoArgs& a) {
    Progress progress(true, 3);
    progress.step("reading " + a.map_path);
    Input input;
    if (const int code = read_map(a.map_path, input, a.threads); code != kOk) return code;
    progress.step("analysing " + std::to_string(input.triangles.size()) + " triangles");
    if (const Error e = validate(input); e.code != ErrorCode::None) {
        progress.stop();
        std::cerr << "qex: " << a.map_path << ": invalid input (" << to_string(e.code) << "): " << e.message << "\n";
        return kBadInput;
    }
    MapInfo m = analyse_map(input);
    progress.step("extracting once (first rung only, no fallback ladder) for the sanitized map");
    const Error e = add_sanitized(input, a.threads, m);
    progress.stop();
    // A map the extractor rejects is still described (all but its sanitized part), then refused.
    const bool rejected = e.code != ErrorCode::None;
    if (a.json) {
        nlohmann::json j = to_json(m);
        if (rejected) j["error"] = {{"code", to_string(e.code)}, {"element", e.element}, {"message", e.message}};
        std::cout << j.dump(2) << "\n";
    } else {
        print_text(a.map_path, m);
    }
    if (rejected) {
        std::cerr << "qex: " << a.map_path << ": invalid input (" << to_string(e.code) << "): " << e.message << "\n";
        return kBadInput;
    }
    return kOk;
}

} // namespace qex::cli

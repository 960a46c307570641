// `qex draw`: pictures, as SVG written here (no dependency), optionally converted to PNG by
// rsvg-convert. The map in UV space (triangles, fold-overs in red, degenerate triangles marked,
// the integer grid, singularities with their valence, fold regions labelled: draw_map.cpp), or
// the quad mesh in three orthographic views (flat-shaded, back faces culled: draw_mesh.cpp) with
// every defect of a report and every violation of the checker circled and numbered. Also the
// checker's verdict as a picture, for `qex check --svg` (draw.h).
#include "cli.h"
#include "draw.h"
#include "qex/check.h"
#include "draw_parts.h"
#include "map_info.h"
#include "progress.h"
#include "svg.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <tuple>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace qex::cli {
namespace {

using svg::num;
using svg::svg_document;
using svg::text;

// === PNG

/// The path of `program` on PATH, or empty.
std::string on_path(const std::string& program) {
    const char* path = std::getenv("PATH");
    for (std::string dirs = path ? path : ""; !dirs.empty();) {
        const std::size_t colon = dirs.find(':');
        const std::string dir = dirs.substr(0, colon);
        dirs = colon == std::string::npos ? "" : dirs.substr(colon + 1);
        const std::string candidate = (dir.empty() ? "." : dir) + "/" + program;
        if (access(candidate.c_str(), X_OK) == 0) return candidate;
    }
    return {};
}

/// Converts the SVG file `svg` to the PNG file `png` with rsvg-convert; an exit code.
int to_png(const std::string& svg, const std::string& png) {
    const std::string tool = on_path("rsvg-convert");
    if (tool.empty()) {
        std::cerr << "qex: --png needs rsvg-convert (Debian package librsvg2-bin); the SVG is " << svg << "\n";
        return kIo;
    }
    const std::string tmp = png + ".tmp";
    std::vector<std::string> args = {tool, "-f", "png", "-o", tmp, svg};
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    pid_t pid;
    int status = 0;
    if (posix_spawn(&pid, tool.c_str(), nullptr, nullptr, argv.data(), environ) != 0 || waitpid(pid, &status, 0) < 0 ||
        !WIFEXITED(status) || WEXITSTATUS(status) != 0 || std::rename(tmp.c_str(), png.c_str()) != 0) {
        std::remove(tmp.c_str());
        std::cerr << "qex: rsvg-convert could not convert " << svg << " to " << png << "\n";
        return kIo;
    }
    return kOk;
}

// === the checker's verdict

/// The violations of a verdict, numbered: their marks on the map and in 3D, and the listing.
struct VerdictMarks {
    std::vector<MapMark> on_map;
    std::vector<Mark> in_3d;
    std::vector<std::string> listing;
};

/// Numbers the violations and places them; marks at one place are drawn once, with the numbers
/// of all violations there.
VerdictMarks number_violations(const Input& in, const QuadMesh& mesh, const VerifyResult& verdict) {
    VerdictMarks out;
    std::map<std::tuple<int, int, double, double>, std::size_t> map_mark_at;
    std::map<Vec3, std::size_t> mark_at;
    for (std::size_t i = 0; i < verdict.violations.size(); ++i) {
        const Violation& x = verdict.violations[i];
        const std::string label = std::to_string(i + 1);
        const std::vector<MapMark> m = map_marks(in, x, label);
        for (const MapMark& mark : m) {
            const auto key = std::make_tuple(static_cast<int>(mark.shape), mark.triangle, mark.at[0], mark.at[1]);
            const auto [it, added] = map_mark_at.emplace(key, out.on_map.size());
            if (added)
                out.on_map.push_back(mark);
            else if (!mark.label.empty())
                out.on_map[it->second].label += (out.on_map[it->second].label.empty() ? "" : ", ") + mark.label;
        }
        Vec3 at{};
        if (violation_at(in, mesh, x, at)) {
            const auto [it, added] = mark_at.emplace(at, out.in_3d.size());
            if (added)
                out.in_3d.push_back({at, label});
            else
                out.in_3d[it->second].label += ", " + label;
        }
        out.listing.push_back(label + ": " + to_string(x.kind) + ": " + x.message +
                              (m.empty() ? " (not on the map)" : ""));
    }
    return out;
}

// === qex draw

/// `qex draw` without --quads: the map, whole (in outline when large) or around a triangle.
int map_picture(const DrawArgs& a, const Input& in, const std::string& name, std::string& body, double& width,
                double& height) {
    const MapInfo info = analyse_map(in);
    std::vector<int> tris;
    std::string title = name + ": the map in UV space";
    if (a.around >= static_cast<long long>(in.triangles.size())) {
        stop_progress();
        std::cerr << "qex: --around " << a.around << ": the map has " << in.triangles.size() << " triangles\n";
        return kUsage;
    }
    const bool outline = a.around < 0 && in.triangles.size() > kWholeMapTriangles;
    if (a.around >= 0) {
        tris = around(in, static_cast<int>(a.around), a.radius);
        title += " around triangle " + std::to_string(a.around);
    } else {
        tris.resize(in.triangles.size());
        for (std::size_t t = 0; t < tris.size(); ++t) tris[t] = static_cast<int>(t);
        if (outline) title += " (outline: " + std::to_string(tris.size()) + " triangles; --around T for detail)";
    }
    body = draw_map(in, info, tris, outline, title, width, height);
    return kOk;
}

/// `qex draw --quads`: the quad mesh, checked, with the defects of --report and the violations.
/// The quad layout of the mesh (`--layout`); exit code 5 if the layout check rejects it.
int layout_picture(const DrawArgs& a, const QuadMesh& mesh, std::string& body, double& width, double& height) {
    const Layout layout = extract_layout(mesh);
    if (!layout.valid) {
        stop_progress();
        std::cerr << "qex: no valid layout: " << layout.error << "\n";
        return kInvalidOutput;
    }
    const std::string title = std::filesystem::path(a.quads_path).filename().string() + ": " +
                              std::to_string(layout.patches.size()) + " patches, " +
                              std::to_string(layout.separatrices.size()) + " separatrices (qex layout)";
    body = draw_layout(mesh, layout, title, width, height);
    return kOk;
}

int quads_picture(const DrawArgs& a, const Input& in, const std::string& name, std::string& body, double& width,
                  double& height) {
    QuadMesh mesh;
    if (const int code = read_quads(a.quads_path, mesh); code != kOk) return code;
    if (a.layout) return layout_picture(a, mesh, body, width, height);
    nlohmann::json report;
    if (!a.report_path.empty()) {
        std::ifstream f(a.report_path);
        if (!f) {
            stop_progress();
            std::cerr << "qex: cannot open report '" << a.report_path << "'\n";
            return kIo;
        }
        report = nlohmann::json::parse(f, nullptr, false);
        if (report.is_discarded() || !report.is_object()) {
            stop_progress();
            std::cerr << "qex: " << a.report_path << ": not a JSON report\n";
            return kParse;
        }
        if (const std::string problem = report_problem(report); !problem.empty()) {
            stop_progress();
            std::cerr << "qex: " << a.report_path << ": " << problem << "\n";
            return kParse;
        }
    }
    // Judged as `qex check` judges it (qex/check.h), at the grid scale given, or the report's.
    int grid_scale = a.grid_scale;
    if (grid_scale == 0) {
        const auto* scale = report.is_object() && report.contains("fallback") && report["fallback"].is_object() &&
                                    report["fallback"].contains("grid_scale")
                                ? &report["fallback"]["grid_scale"]
                                : nullptr;
        grid_scale = scale && scale->is_number_integer() ? scale->get<int>() : 1;
    }
    qex::Certificate certificate;
    if (!a.certificate_path.empty()) {
        if (const auto e = qex::read_certificate(a.certificate_path, certificate); !e.ok()) {
            stop_progress();
            std::cerr << "qex: " << e.message << "\n";
            return io_exit(e);
        }
    }
    const VerifyResult check = a.certificate_path.empty() ? check_mesh(in, mesh, grid_scale).verdict
                                                          : check_mesh(in, mesh, certificate).verdict;
    std::vector<std::string> listing;
    const std::vector<Mark> marks = collect_marks(in, mesh, report, check, listing);
    const std::string title = std::filesystem::path(a.quads_path).filename().string() + " on " + name + ": " +
                              (check.valid ? "VALID" : "INVALID") + " (qex check)";
    body = draw_mesh(in, mesh, marks, listing, title, width, height);
    return kOk;
}

} // namespace

std::string verdict_svg(const Input& input, const QuadMesh& mesh, const VerifyResult& verdict, int grid_scale,
                        const std::string& title) {
    // The map as the checker judged it (its UVs times the grid scale, a power of two: exact).
    Input in = input;
    if (grid_scale != 1)
        for (auto& uv : in.uvs) uv = {uv[0] * grid_scale, uv[1] * grid_scale};
    const VerdictMarks marks = number_violations(in, mesh, verdict);
    const std::vector<std::string>& listing = marks.listing;
    std::vector<int> tris(in.triangles.size());
    for (std::size_t t = 0; t < tris.size(); ++t) tris[t] = static_cast<int>(t);
    const bool outline = tris.size() > kWholeMapTriangles;
    double map_width = 0, map_height = 0, mesh_width = 0, mesh_height = 0;
    const std::string verdict_line = std::string(verdict.valid ? "VALID" : "INVALID") + ", " +
                                     std::to_string(verdict.violations.size()) + " violations (numbered)";
    std::string body = draw_map(in, analyse_map(in), tris, outline,
                                title + ": " + verdict_line + "; the map" +
                                    (grid_scale != 1 ? " at grid scale " + std::to_string(grid_scale) : "") +
                                    (outline ? " in outline" : ""),
                                map_width, map_height, marks.on_map);
    if (mesh.faces.size() <= kMeshViewFaces) {
        body += "<g transform=\"translate(0," + num(map_height) + ")\">\n" +
                draw_mesh(in, mesh, marks.in_3d, listing, title + ": the mesh", mesh_width, mesh_height) + "</g>\n";
    } else { // the listing alone
        double y = map_height + 20;
        for (std::size_t i = 0; i < listing.size() && i < kListed; ++i, y += 17)
            body +=
                text(20, y, listing[i].size() > 200 ? listing[i].substr(0, 197) + "..." : listing[i], "fill=\"#900\"");
        if (listing.size() > kListed)
            body += text(20, y, "... and " + std::to_string(listing.size() - kListed) + " more");
        mesh_height = y - map_height + 20;
    }
    return svg_document(std::max(map_width, mesh_width), map_height + mesh_height, body);
}

CLI::App* add_draw(CLI::App& app, DrawArgs& a) {
    auto* draw = app.add_subcommand("draw", "Draw a map in UV space, or a quad mesh in 3 views with its defects (SVG)");
    draw->add_option("map", a.map_path, "the map: OBJ or PLY with per-corner UVs")->required();
    draw->add_option("-o,--output", a.out_path, "the SVG to write")->required();
    draw->add_option("--quads", a.quads_path, "draw this quad mesh (OBJ or PLY) instead of the map");
    draw->add_option("--report", a.report_path, "with --quads: circle the defects of this `qex extract --report`");
    draw->add_option("--grid-scale", a.grid_scale,
                     "with --quads: judge the mesh at this grid scale, as `qex check --grid-scale` (default: the "
                     "report's, else 1)")
        ->check(CLI::IsMember({1, 2, 4, 8, 16, 32, 64}));
    draw->add_option("--certificate", a.certificate_path,
                     "with --quads: judge the mesh on this certificate of `qex extract --certificate`, as `qex check "
                     "--certificate` (its grid scale is the certificate's)")
        ->excludes("--grid-scale");
    // A range of long long: a number past 2^63 is refused as such, not saturated to 2^63 - 1.
    draw->add_option("--around", a.around, "draw the map around this triangle only")
        ->check(CLI::Range(0LL, static_cast<long long>(INT32_MAX)));
    draw->add_option("--radius", a.radius, "with --around: how far, in grid units (default 6)")
        ->check(finite_number())
        ->check(CLI::PositiveNumber);
    draw->add_flag("--layout", a.layout, "with --quads: draw the mesh's quad layout (patches coloured, separatrices)");
    draw->add_flag("--png", a.png, "also write a PNG beside the SVG (needs rsvg-convert)");
    return draw;
}

int run_draw(const DrawArgs& a) {
    Progress progress(true, 2);
    progress.step("reading " + a.map_path);
    Input in;
    if (const int code = read_map(a.map_path, in); code != kOk) return code;
    progress.step("drawing");
    if (const Error e = validate(in); e.code != ErrorCode::None) {
        progress.stop();
        std::cerr << "qex: " << a.map_path << ": invalid input (" << to_string(e.code) << "): " << e.message << "\n";
        return kBadInput;
    }
    double width = 0, height = 0;
    std::string body;
    const std::string name = std::filesystem::path(a.map_path).filename().string();
    const int code = a.quads_path.empty() ? map_picture(a, in, name, body, width, height)
                                          : quads_picture(a, in, name, body, width, height);
    if (code != kOk) return code;
    progress.stop();
    if (!write_text(a.out_path, svg_document(width, height, body))) {
        std::cerr << "qex: cannot write '" << a.out_path << "'\n";
        return kIo;
    }
    if (a.png) return to_png(a.out_path, std::filesystem::path(a.out_path).replace_extension(".png").string());
    return kOk;
}

} // namespace qex::cli

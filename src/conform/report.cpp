// What `qex conform` writes: a summary row per case, the table per family, and the folder that
// replays a case not right (the map, the output, stderr, the verdict, case.json, replay.sh).
#include "conform_internal.h"
#include "qex/extract.h"
#include "qex/io.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>

namespace qex {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace conform_detail;

constexpr ConformOutcome kOutcomes[] = {
    ConformOutcome::Exact,        ConformOutcome::Valid,        ConformOutcome::ValidFewerQuads,
    ConformOutcome::CleanFailure, ConformOutcome::InvalidExit0, ConformOutcome::WrongCount,
    ConformOutcome::Crash,        ConformOutcome::Timeout,      ConformOutcome::NoOutput};

json recipe_json(const ConformRecipe& r) {
    json steps = json::array();
    for (const ConformStep& s : r.steps) steps.push_back({{"op", s.op}, {"a", s.a}, {"b", s.b}});
    return {{"layout", r.layout},       {"n", r.n},       {"k", r.k},
            {"diagonals", r.diagonals}, {"seed", r.seed}, {"steps", steps}};
}

/// The replay script: the extractor's command on the folder's map, then qex check on its output.
std::string replay_script(const ConformResult& r, const std::string& map, const std::string& out,
                          const ConformOptions& o) {
    std::string s = "#!/bin/sh\n# qex conform: " + r.c.name + " (" + conform_describe(r.c) +
                    "): " + to_string(r.outcome) + ", " + r.detail +
                    "\n# Replays it: sh replay.sh\ncd \"$(dirname \"$0\")\"\n";
    if (o.replay_command.empty())
        s += "echo 'the extractor has no command line: run it on " + map + "'\n";
    else
        s += shell_command(o.replay_command, map, out) + "\necho \"extractor exit status $?\"\n";
    // The check at the scale the judge chose, so that replay.sh gives the summary's verdict.
    const std::string scale = r.grid_scale == 1 ? "" : " --grid-scale " + std::to_string(r.grid_scale);
    return s + shell_quote(o.checker) + " check --param " + shell_quote(map) + " " + shell_quote(out) + scale + "\n";
}

void copy_if_there(const std::string& from, const std::string& to) {
    std::error_code ec;
    if (!from.empty() && fs::exists(from, ec)) fs::copy_file(from, to, fs::copy_options::overwrite_existing, ec);
}

/// The verdict's picture, for a mesh that can be read and a map that is valid input; at grid
/// scale K > 1 the map drawn is the one judged, its UVs times K (a power of two: exact).
void write_picture(const std::string& map_path, const std::string& out_path, const std::string& svg_path,
                   int grid_scale, const ConformOptions& o) {
    if (!o.picture) return;
    Input map;
    QuadMesh mesh;
    const bool ply = is_ply_path(map_path), out_ply = is_ply_path(out_path);
    if (!(ply ? read_ply(map_path, map) : read_obj(map_path, map, 1)).ok()) return;
    if (!(out_ply ? read_polygon_ply(out_path, mesh) : read_polygon_obj(out_path, mesh)).ok()) return;
    if (validate(map).code != ErrorCode::None) return;
    for (auto& uv : map.uvs) uv = {uv[0] * grid_scale, uv[1] * grid_scale};
    VerifyOptions options;
    options.threads = 1;
    write_file(svg_path, o.picture(map, mesh, verify(map, mesh, options)));
}

double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

} // namespace

std::string conform_case_json(const ConformCase& c) {
    return json{{"name", c.name},
                {"family", c.family},
                {"kind", c.kind},
                {"map_path", c.map_path},
                {"generated", c.generated},
                {"recipe", recipe_json(c.recipe)},
                {"expected_quads", c.expected_quads}}
        .dump();
}

ConformCase conform_case_from_json(const std::string& text) {
    const json j = json::parse(text);
    ConformCase c;
    c.name = j.at("name"), c.family = j.at("family"), c.kind = j.at("kind");
    c.map_path = j.value("map_path", ""), c.generated = j.value("generated", false);
    c.expected_quads = j.value("expected_quads", std::int64_t{-1});
    if (j.contains("recipe")) {
        const json& r = j["recipe"];
        c.recipe.layout = r.value("layout", ""), c.recipe.n = r.value("n", 2), c.recipe.k = r.value("k", 2);
        c.recipe.diagonals = r.value("diagonals", 1), c.recipe.seed = r.value("seed", std::uint64_t{1});
        for (const json& s : r.value("steps", json::array()))
            c.recipe.steps.push_back({s.at("op"), s.value("a", 0.0), s.value("b", 0.0)});
    }
    return c;
}

std::string conform_summary_line(const ConformResult& r) {
    json j = {{"case", r.c.name},       {"family", r.c.family},
              {"kind", r.c.kind},       {"outcome", to_string(r.outcome)},
              {"right", r.right},       {"exit_code", r.run.exit_code},
              {"signal", r.run.signal}, {"seconds", r.run.seconds},
              {"quads", r.quads},       {"expected_quads", r.c.expected_quads},
              {"area", r.area},         {"grid_scale", r.grid_scale},
              {"detail", r.detail},     {"recipe", conform_describe(r.c)},
              {"folder", r.folder},     {"shrunk", r.shrunk}};
    if (r.quality.computed)
        j["quality"] = {{"min_scaled_jacobian", r.quality.min_scaled_jacobian},
                        {"mean_scaled_jacobian", r.quality.mean_scaled_jacobian},
                        {"irregular_vertex_share", r.quality.irregular_vertex_share}};
    return j.dump();
}

std::string write_reproducer(const ConformResult& r, const std::string& map_path, const std::string& out_path,
                             const std::string& stderr_path, const ConformOptions& o) {
    std::string name = r.c.name;
    std::replace(name.begin(), name.end(), '/', '_');
    const std::string dir = (fs::path(o.out_dir) / "cases" / name).string();
    std::error_code ec;
    fs::remove_all(dir, ec);
    fs::create_directories(dir, ec);
    if (!fs::is_directory(dir, ec)) return "";
    const std::string map = is_ply_path(map_path) ? "map.ply" : "map.obj";
    const std::string out = "output." + o.out_extension;
    copy_if_there(map_path, dir + "/" + map);
    copy_if_there(out_path, dir + "/" + out);
    copy_if_there(stderr_path, dir + "/stderr.txt");
    if (!r.verdict_json.empty()) write_file(dir + "/verdict.json", r.verdict_json + "\n");
    if (!r.verdict_json.empty()) write_picture(map_path, out_path, dir + "/verdict.svg", r.grid_scale, o);
    write_file(dir + "/case.json", conform_case_json(r.c) + "\n");
    write_file(dir + "/replay.sh", replay_script(r, map, out, o));
    fs::permissions(dir + "/replay.sh", fs::perms::owner_exec | fs::perms::group_exec | fs::perms::others_exec,
                    fs::perm_options::add, ec);
    return dir;
}

std::string conform_table(const std::vector<std::string>& rows) {
    struct Family {
        std::map<std::string, int> outcomes;
        std::vector<double> seconds;
        int valid = 0, right = 0, cases = 0;
        double min_jacobian = 1.0, mean_jacobian = 0.0;
    };
    std::map<std::string, Family> families;
    for (const std::string& line : rows) {
        const json j = json::parse(line);
        Family& f = families[j.at("family").get<std::string>()];
        ++f.cases, f.right += j.value("right", false);
        ++f.outcomes[j.at("outcome").get<std::string>()];
        f.seconds.push_back(j.value("seconds", 0.0));
        if (!j.contains("quality")) continue;
        ++f.valid;
        f.min_jacobian = std::min(f.min_jacobian, j["quality"].value("min_scaled_jacobian", 1.0));
        f.mean_jacobian += j["quality"].value("mean_scaled_jacobian", 0.0);
    }
    std::string out;
    char line[512];
    std::snprintf(line, sizeof line, "%-28s %5s %5s", "family", "cases", "right");
    out += line;
    for (const ConformOutcome o : kOutcomes) out += " " + std::string(to_string(o));
    out += "  seconds(median worst)  scaled Jacobian(min mean)\n";
    for (const auto& [name, f] : families) {
        std::snprintf(line, sizeof line, "%-28s %5d %5d", name.c_str(), f.cases, f.right);
        out += line;
        for (const ConformOutcome o : kOutcomes) {
            const auto it = f.outcomes.find(to_string(o));
            std::snprintf(line, sizeof line, " %*d", static_cast<int>(std::string(to_string(o)).size()),
                          it == f.outcomes.end() ? 0 : it->second);
            out += line;
        }
        std::snprintf(line, sizeof line, "  %8.3f %8.3f", median(f.seconds),
                      *std::max_element(f.seconds.begin(), f.seconds.end()));
        out += line;
        if (f.valid > 0)
            std::snprintf(line, sizeof line, "         %6.3f %6.3f\n", f.min_jacobian, f.mean_jacobian / f.valid);
        else
            std::snprintf(line, sizeof line, "              -      -\n");
        out += line;
    }
    return out;
}

} // namespace qex

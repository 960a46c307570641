// `qex layout QUADS -o LAYOUT.json`: the quad layout of a quad mesh (qex/layout.h): separatrices,
// patches, their sizes and adjacency as JSON; with --obj the mesh with a group per patch
// (`g patch_N`); with --param MAP the mesh is first judged against the map, as `qex check` does.
// Also `qex extract ... --layout LAYOUT.json` (write_layout below).
#include "cli.h"
#include "violations.h"
#include "qex/layout.h"

#include <cstdio>
#include <iostream>
#include <map>
#include <sstream>

namespace qex::cli {
namespace {

/// The mesh as OBJ with its faces grouped by patch (`g patch_N`), positions with 17 digits.
std::string grouped_obj(const QuadMesh& mesh, const Layout& layout) {
    std::ostringstream out;
    out << "# qex layout: " << layout.patches.size() << " patches, a group each\n";
    char line[96];
    for (const auto& p : mesh.positions) {
        std::snprintf(line, sizeof line, "v %.17g %.17g %.17g\n", p[0], p[1], p[2]);
        out << line;
    }
    for (std::size_t p = 0; p < layout.patches.size(); ++p) {
        out << "g patch_" << p << "\n";
        for (const int f : layout.patches[p].faces) {
            out << "f";
            for (const int v : mesh.faces[f]) out << ' ' << v + 1;
            out << "\n";
        }
    }
    return out.str();
}

/// The layout in one line: patches, their sizes, separatrices by ending.
std::string summary(const Layout& l) {
    std::map<std::string, int> ends;
    for (const Separatrix& s : l.separatrices) ++ends[to_string(s.end)];
    std::ostringstream out;
    out << l.patches.size() << " patches, " << l.separatrices.size() << " separatrices (";
    bool first = true;
    for (const auto& [name, n] : ends) {
        out << (first ? "" : ", ") << n << " " << name;
        first = false;
    }
    out << "), " << l.special_vertices.size() << " special vertices";
    for (const std::string& note : l.notes) out << "; " << note;
    return out.str();
}

/// The feature file's vertex pairs, checked against the quad mesh's vertex count.
int read_quad_features(const std::string& path, const QuadMesh& mesh, LayoutOptions& options) {
    Input edges; // read_features knows a mesh's edges by its triangles: each quad's two halves
    edges.positions = mesh.positions;
    for (const auto& f : mesh.faces)
        if (f.size() == 4) {
            edges.triangles.push_back({f[0], f[1], f[2]});
            edges.triangles.push_back({f[2], f[3], f[0]});
        }
    if (const int code = read_features(path, edges); code != kOk) return code;
    options.feature_edges = edges.feature_edges; // a quad's diagonal is refused by extract_layout
    return kOk;
}

} // namespace

int write_layout(const std::string& json_path, const std::string& obj_path, const QuadMesh& mesh,
                 const LayoutOptions& options, bool quiet) {
    const Layout layout = extract_layout(mesh, options);
    if (!json_path.empty() && !write_text(json_path, layout_json(layout) + "\n")) {
        std::cerr << "qex: cannot write '" << json_path << "'\n";
        return kIo;
    }
    if (!layout.valid) {
        std::cerr << "qex: no valid layout: " << layout.error << "\n";
        return kInvalidOutput;
    }
    if (!obj_path.empty() && !write_text(obj_path, grouped_obj(mesh, layout))) {
        std::cerr << "qex: cannot write '" << obj_path << "'\n";
        return kIo;
    }
    if (!quiet) std::printf("qex: layout: %s -> %s\n", summary(layout).c_str(), json_path.c_str());
    return kOk;
}

int run_layout(const LayoutArgs& a) {
    QuadMesh mesh;
    if (const int code = read_quads(a.quads_path, mesh); code != kOk) return code;
    if (!a.param_path.empty()) {
        Input input;
        if (const int code = read_map(a.param_path, input); code != kOk) return code;
        if (const Error e = validate(input); e.code != ErrorCode::None) {
            std::cerr << "qex: " << a.param_path << ": invalid input (" << to_string(e.code) << "): " << e.message
                      << "\n";
            return kBadInput;
        }
        VerifyOptions vo;
        vo.fold_regions = true;
        const VerifyResult v = verify(input, mesh, vo);
        if (!v.valid) {
            std::cerr << "qex: " << a.quads_path << " is not a valid quad mesh of " << a.param_path << "\n";
            print_violations(v);
            return kRejected;
        }
    }
    LayoutOptions options;
    if (!a.features_path.empty())
        if (const int code = read_quad_features(a.features_path, mesh, options); code != kOk) return code;
    return write_layout(a.out_path, a.obj_path, mesh, options, a.quiet);
}

CLI::App* add_layout(CLI::App& app, LayoutArgs& a) {
    auto* layout = app.add_subcommand("layout", "The quad layout of a quad mesh: separatrices and rectangular patches");
    layout->add_option("quads", a.quads_path, "the quad mesh (OBJ or PLY)")->required();
    layout->add_option("-o,--output", a.out_path, "the layout as JSON (separatrices, patches, sizes, adjacency)")
        ->required();
    layout->add_option("--param", a.param_path, "judge the mesh against this map first (as `qex check` does)");
    layout->add_option("--obj", a.obj_path, "also write the mesh as OBJ with a group per patch (g patch_N)");
    layout->add_option("--features", a.features_path,
                       "feature edges of the quad mesh to cut along: one 'i j' per line (0-based vertices)");
    layout->add_flag("-q,--quiet", a.quiet, "print nothing on success");
    return layout;
}

} // namespace qex::cli

// qex: the command-line front end. One file per subcommand (extract.cpp, check.cpp, info.cpp,
// draw.cpp, batch.cpp, conform.cpp, layout.cpp), each with its options (add_*) and its run (run_*); cli.h lists what
// they share. draw.cpp's pictures are drawn by draw_map.cpp and draw_mesh.cpp (draw_parts.h)
// in the SVG of svg.cpp. Here: the program's help, version and dispatch.
#include "cli.h"
#include "heap_policy.h"

#include <CLI/CLI.hpp>

#include <filesystem>
#include <iostream>
#include <system_error>

using namespace qex::cli;

namespace {

/// The help's closing lines: one example per subcommand, on the shared maps.
const char* kExamples = R"(Examples (the maps in ../shared/meshes/):
  qex extract paper/fandisk_param.obj -o fandisk.obj --report fandisk.json   extract and check
  qex check --param paper/fandisk_param.obj fandisk.obj                      judge any quad mesh
  qex extract paper/fandisk_param.obj -o fandisk.obj --certificate c.obj     the repaired map beside the mesh
  qex check --param paper/fandisk_param.obj fandisk.obj --certificate c.obj  qex's mesh judged on it
  qex info paper/duck_miq_8_param.obj --json                                 the map before extraction
  qex extract paper/fandisk_param.obj -o fandisk.ply --features f.txt        PLY out, feature edges
  qex draw paper/duck_miq_8_param.obj -o duck_map.svg --png                  the map in UV space
  qex draw paper/fandisk_param.obj --quads fandisk.obj -o fandisk.svg        the mesh, defects circled
  qex batch paper -o out --jobs 2 --summary out/summary.jsonl                a folder of maps
  qex conform --extractor 'qex extract {in} -o {out}' -o report --jobs 2     judge any extractor
  qex layout fandisk.obj -o fandisk_layout.json --obj fandisk_patches.obj    the patches of a quad mesh
Exit codes: 0 ok, 1 command line, 2 file, 3 malformed file, 4 input rejected, 5 mesh invalid,
6 check found violations, 7 batch: some maps failed, conform: some cases not right (the count is printed).)";

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"qex: robust quad mesh extraction from integer-grid maps (QEx)"};
    app.require_subcommand(0, 1);
    app.set_version_flag("--version", version_string());
    app.footer(kExamples);
    ExtractArgs extract_args;
    CheckArgs check_args;
    InfoArgs info_args;
    DrawArgs draw_args;
    BatchArgs batch_args;
    LayoutArgs layout_args;
    ConformArgs conform_args;
    CLI::App* extract = add_extract(app, extract_args);
    CLI::App* check = add_check(app, check_args);
    CLI::App* info = add_info(app, info_args);
    CLI::App* draw = add_draw(app, draw_args);
    CLI::App* batch = add_batch(app, batch_args);
    CLI::App* layout = add_layout(app, layout_args);
    CLI::App* conform = add_conform(app, conform_args);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) { return app.exit(e) == 0 ? kOk : kUsage; }
    if (*extract) {
        prepare_heap(size_of(extract_args.in_path));
        return run_extract(extract_args);
    }
    if (*check) {
        prepare_heap(size_of(check_args.param_path) + size_of(check_args.mesh_path));
        return run_check(check_args);
    }
    if (*info) return run_info(info_args);
    if (*draw) return run_draw(draw_args);
    if (*layout) return run_layout(layout_args);
    std::error_code ec;
    const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (*batch) {
        batch_args.self = ec ? std::string(argv[0]) : self.string();
        return run_batch(batch_args);
    }
    if (*conform) {
        conform_args.self = ec ? std::string(argv[0]) : self.string();
        return run_conform(conform_args);
    }
    std::cout << app.help();
    return kUsage;
}

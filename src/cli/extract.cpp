// `qex extract MAP -o OUT`: the quad mesh of a map (OBJ or PLY, by extension), checked by the
// independent checker inside extract(); the mesh is written only if the checker accepts it
// (or with --poly, or --best-effort: the attempt closest to valid), the report with --report.
#include "cli.h"
#include "progress.h"
#include "violations.h"
#include "qex/check.h"
#include "qex/report.h"

#include <algorithm>
#include <cmath>
#include <chrono>
#include <cstdio>
#include <iostream>

namespace qex::cli {
namespace {

/// Reads the map (and valences); returns the exit code of a failure, or kOk.
int read_input(const ExtractArgs& a, qex::Input& input) {
    if (const int code = read_map(a.in_path, input, a.threads); code != kOk) return code;
    if (!a.vval_path.empty())
        if (const auto e = qex::read_vval(a.vval_path, input.valences); !e.ok()) {
            stop_progress();
            std::cerr << "qex: " << a.vval_path << ": " << e.message << "\n";
            return io_exit(e);
        }
    if (!a.features_path.empty()) {
        stop_progress(); // a problem in the file is printed at once
        return read_features(a.features_path, input);
    }
    return kOk;
}

/// The report with the mesh's quality figures. They are measured here, so that an extraction
/// without --report does not spend the time.
bool write_report(const std::string& path, const qex::Input& input, const qex::Result& result, double read_seconds,
                  double extract_seconds) {
    const auto t0 = std::chrono::steady_clock::now();
    const qex::MeshQuality quality = qex::mesh_quality(input, result.mesh);
    const double quality_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return write_text(path, qex::report_json(result, read_seconds, extract_seconds, quality, quality_seconds) + "\n");
}

/// The certificate (the repaired map the mesh was extracted from) beside the mesh, with
/// --certificate: written whenever the mesh is, also when the repair changed nothing (then it
/// lists no triangle and holds the sanitized map); not for a mesh split from the map divided by
/// k (coarsened: extracted and checked at the coarse scale, which no map at this scale
/// describes), which is said on stderr; nor one its own check rejects (kInvalidOutput). Returns
/// kOk, kIo or kInvalidOutput.
int write_certificate_beside(const ExtractArgs& a, const qex::Input& input, const qex::Result& result) {
    if (a.certificate_path.empty()) return kOk;
    if (result.report.coarsening != 1) {
        std::cerr << "qex: no certificate written: the mesh was split from the map divided by "
                  << result.report.coarsening << " (judge it with `qex check --param` alone)\n";
        return kOk;
    }
    const qex::Certificate c = qex::make_certificate(input, result.mesh);
    // Judged first as `qex check --param MAP --certificate` will judge it: one it rejects is not written.
    const qex::MeshCheck held = qex::check_own_certificate(input, result.mesh, c);
    // A mesh the checker accepted must pass on it; beside a rejected one (--poly, --best-effort)
    // the certificate must still hold against the map.
    if (result.check.valid ? !held.verdict.valid : !held.verdict.on_certificate) {
        std::cerr << "qex: " << a.in_path << ": no certificate written: `qex check --certificate` would reject it ("
                  << held.verdict.violations.size() << " violations)\n";
        print_violations(held.verdict);
        return kInvalidOutput;
    }
    if (const auto e = qex::write_certificate(a.certificate_path, c); !e.ok()) {
        std::cerr << "qex: " << e.message << "\n";
        return kIo;
    }
    if (!a.quiet)
        std::printf(
            "qex: certificate: %zu repaired triangles, grid scale %d -> %s (judge the mesh on it with `qex "
            "check --param MAP --certificate %s`)\n",
            c.repaired.size(), c.grid_scale, a.certificate_path.c_str(), a.certificate_path.c_str());
    return kOk;
}

/// The checker rejected the mesh: its defects and violations on stderr, the mesh only with --poly.
int reject(const ExtractArgs& a, const qex::Input& input, const qex::Result& result) {
    const qex::VerifyResult& check = result.check;
    const auto& defects = result.report.defects;
    std::cerr << "qex: " << a.in_path << ": the extracted mesh fails the check (" << check.violations.size()
              << " violations, " << defects.size() << " extraction defects)\n";
    for (std::size_t i = 0; i < defects.size() && i < 20; ++i)
        std::cerr << "  " << qex::to_string(defects[i].kind)
                  << (defects[i].violation ? std::string(" ") + qex::to_string(*defects[i].violation) : "") << ": "
                  << defects[i].message << "\n";
    print_violations(check);
    // What the map itself forbids, before what the attempts found (the first ten; the report has
    // them all).
    std::size_t proofs = 0;
    for (const qex::Defect& d : result.report.explanations) {
        if (d.kind != qex::DefectKind::FoldPinnedBySingularities && d.kind != qex::DefectKind::RimShortOfSingularity &&
            d.kind != qex::DefectKind::AnglesLeaveNoRoom && d.kind != qex::DefectKind::RegionAreaNotPositive)
            continue;
        if (++proofs <= 10) std::cerr << "  " << qex::to_string(d.kind) << ": " << d.message << "\n";
    }
    if (proofs > 10) std::cerr << "  ... and " << proofs - 10 << " more proofs (the report's explanations)\n";
    for (const qex::Defect& d : result.report.explanations)
        if (d.kind == qex::DefectKind::RefinementFailed) std::cerr << "  RefinementFailed: " << d.message << "\n";
    for (const qex::Defect& d : result.report.explanations)
        if (d.kind == qex::DefectKind::BestEffortMesh) std::cerr << "  BestEffortMesh: " << d.message << "\n";
    if (a.poly || a.best_effort) {
        if (const auto e = write_quads(a.out_path, result.mesh, a.threads); !e.ok()) {
            std::cerr << "qex: " << e.message << "\n";
            return kIo;
        }
        if (const int e = write_certificate_beside(a, input, result); e != kOk) return e;
        const int k = result.mesh.grid_scale;
        std::cerr << "qex: wrote the invalid mesh to " << a.out_path << (a.best_effort ? " (--best-effort" : " (--poly")
                  << (k != 1 ? "; judge it with `qex check --grid-scale " + std::to_string(k) + "`)" : ")") << "\n";
    }
    return kInvalidOutput;
}

/// What stderr says of a written mesh beside its line: a refined or coarsened scale, seams
/// rounded (both said even with -q: the quads or the map differ from the map as given), and with
/// fewer quads than the area, how many of the places that removed faces a proof backs.
void say_what_the_map_needed(const ExtractArgs& a, const qex::Result& result) {
    const auto& r = result.report;
    if (r.grid_scale != 1) // said even with -q: the quads are smaller than the map's
        std::cerr << "qex: " << a.in_path << ": " << r.explanations.front().message
                  << " (judge it with `qex check --grid-scale " << r.grid_scale << "`)\n";
    if (r.coarsening != 1 && !a.quiet)
        std::cerr << "qex: " << a.in_path << ": " << r.explanations.front().message << "\n";
    const auto is_rounded = [](const Defect& d) { return d.kind == DefectKind::SeamRounded; };
    const auto first = std::find_if(r.explanations.begin(), r.explanations.end(), is_rounded);
    if (first != r.explanations.end()) { // said even with -q: the map moved by up to half a cell there
        const auto rounded = std::count_if(first, r.explanations.end(), is_rounded);
        std::cerr << "qex: " << a.in_path << ": " << rounded
                  << " seams no grid transition relates were rounded (--round-seams); the first: " << first->message
                  << "\n";
    }
    const auto quads = static_cast<long long>(result.mesh.faces.size());
    if (!a.quiet && r.losses_proved + r.losses_not_proved > 0 && quads < std::llround(r.signed_uv_area))
        std::cerr << "qex: " << a.in_path << ": faces were removed at " << r.losses_proved + r.losses_not_proved
                  << " places: " << r.losses_proved << " next to fold-overs a proof shows no fold-free map of, "
                  << r.losses_not_proved << " elsewhere (where the repair failed, or no fold-over is left); "
                  << "each is named in the report's explanations\n";
}

} // namespace

int run_extract(const ExtractArgs& a) {
    if (!a.certificate_path.empty() && a.certificate_path == a.out_path) {
        std::cerr << "qex: --certificate must name another file than the mesh (-o)\n";
        return kUsage;
    }
    const auto t0 = std::chrono::steady_clock::now();
    Progress progress(!a.quiet, 3);
    progress.step("reading " + a.in_path);
    qex::Input input;
    if (const int code = read_input(a, input); code != kOk) return code;
    const auto t1 = std::chrono::steady_clock::now();
    qex::Options options;
    options.threads = a.threads;
    options.snap_boundary = a.snap_boundary;
    options.round_inconsistent_seams = a.round_seams;
    options.max_refinement = a.max_refinement;
    options.max_coarsening = a.max_coarsening;
    options.best_effort = a.best_effort;
    options.fill_holes = !a.no_fill_holes;
    options.repair_fold_overs = !a.no_repair;
    options.on_stage = [&progress](const char* stage, int grid_scale) {
        progress.detail(std::string("stage ") + stage + " done" +
                        (grid_scale > 1 ? " (map refined x" + std::to_string(grid_scale) + ")" : ""));
    };
    progress.step("extracting and checking " + std::to_string(input.triangles.size()) + " triangles");
    const qex::Result result = qex::extract(input, options);
    progress.step("writing " + a.out_path);
    if (!result.ok()) {
        progress.stop();
        std::cerr << "qex: " << a.in_path << ": invalid input (" << qex::to_string(result.error.code)
                  << "): " << result.error.message << "\n";
        return kBadInput;
    }
    const auto t2 = std::chrono::steady_clock::now();
    const auto seconds = [](auto d) { return std::chrono::duration<double>(d).count(); };
    if (!a.report_path.empty() && !write_report(a.report_path, input, result, seconds(t1 - t0), seconds(t2 - t1))) {
        std::cerr << "qex: cannot write report '" << a.report_path << "'\n";
        return kIo;
    }
    if (!result.check.valid) {
        progress.stop();
        return reject(a, input, result); // the checker's verdict, taken inside extract()
    }
    if (const auto e = write_quads(a.out_path, result.mesh, a.threads); !e.ok()) {
        std::cerr << "qex: " << e.message << "\n";
        return kIo;
    }
    progress.stop();
    say_what_the_map_needed(a, result);
    const auto& r = result.report;
    if (!a.quiet)
        std::printf(
            "qex: %zu quads, %zu vertices (signed UV area %.1f, %lld flipped triangles, %lld merged, "
            "%lld recovered edges, map %s, grid scale %d%s) -> %s\n",
            result.mesh.faces.size(), result.mesh.positions.size(), r.signed_uv_area,
            static_cast<long long>(r.flipped_triangles), static_cast<long long>(r.merged_qvertices),
            static_cast<long long>(r.recovered_edges), r.rung.c_str(), r.grid_scale,
            r.coarsening == 1 ? "" : (", coarsened /" + std::to_string(r.coarsening)).c_str(), a.out_path.c_str());
    if (const int e = write_certificate_beside(a, input, result); e != kOk) return e;
    if (!a.layout_path.empty()) { // cut along the mesh's edges on the map's feature edges
        LayoutOptions layout;
        layout.feature_edges = quad_feature_edges(input, result.mesh);
        return write_layout(a.layout_path, "", result.mesh, layout, a.quiet);
    }
    return kOk;
}

CLI::App* add_extract(CLI::App& app, ExtractArgs& a) {
    auto* extract = app.add_subcommand("extract", "Extract the quad mesh of a map (OBJ or PLY with per-corner UVs)");
    extract->add_option("input", a.in_path, "input map: OBJ (v, vt, f a/ta b/tb c/tc) or PLY (per-face texcoord)")
        ->required();
    extract->add_option("-o,--output", a.out_path, "output quad mesh, OBJ or PLY by extension (local UVs)")->required();
    extract->add_option("--valences", a.vval_path, "VVAL file with per-vertex cross-field valences");
    extract->add_option("--report", a.report_path, "write a JSON report (counts, defects, timings, check, quality)");
    extract->add_option("--features", a.features_path,
                        "feature edges to snap onto iso-lines: one 'i j' per line (0-based vertices), # comments");
    extract->add_flag("--snap-boundary", a.snap_boundary, "snap every boundary edge onto its closest iso-line");
    extract->add_flag("--round-seams", a.round_seams,
                      "round seams no grid transition relates to the nearest one and report each (default: exit 4)");
    extract->add_flag("--poly", a.poly, "write the mesh even if faces are not quads (exit code stays 5)");
    extract->add_flag("--best-effort", a.best_effort,
                      "when no attempt gives a valid mesh, write the one closest to valid (fewest checker violations, "
                      "ties to the smallest grid scale), every violation located in the report (exit code stays 5)");
    extract->add_flag("--no-fill-holes", a.no_fill_holes,
                      "no last resort: where no attempt gives a valid mesh, do not fill holes that no grid cells close "
                      "with quads joining their rim vertices (such quads follow no cells of the map)");
    extract->add_flag("--no-repair", a.no_repair,
                      "fast and uncertified: no re-embedding of fold-over regions, the paper's local handling "
                      "of them only (a mesh may have fewer quads than the map's area; the default is certified)");
    extract
        ->add_option("--threads", a.threads, "threads for the parallel loops (0: every core, 1: serial); same output")
        ->check(CLI::Range(0, 1024));
    extract
        ->add_option("--max-refinement", a.max_refinement,
                     "when the map gives no valid mesh at its own scale, retry with its UVs x2, x4, ... up to this "
                     "power of two (1: never; default 16)")
        ->check(CLI::IsMember({1, 2, 4, 8, 16}));
    extract
        ->add_option("--max-coarsening", a.max_coarsening,
                     "when the map gives no valid mesh at its own scale and its UVs /2, /4, ... (up to this power of "
                     "two) are an integer-grid map too, extract there and split each quad back (1: never; default 16)")
        ->check(CLI::IsMember({1, 2, 4, 8, 16}));
    extract->add_option("--layout", a.layout_path,
                        "also write the mesh's quad layout as JSON (separatrices, patches, sizes, adjacency)");
    extract->add_option("--certificate", a.certificate_path,
                        "also write the repaired map the mesh was extracted from (OBJ with a header: grid scale, "
                        "repaired triangles), for `qex check --certificate`");
    extract->add_flag("-q,--quiet", a.quiet, "print nothing on success");
    return extract;
}

} // namespace qex::cli

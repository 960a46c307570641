// `qex check --param MAP MESH`: judges any quad mesh (OBJ or PLY) against a map with the
// independent checker; the verdict, and the mesh's quality figures, in words or as JSON.
#include "cli.h"
#include "draw.h"
#include "progress.h"
#include "violations.h"
#include "qex/check.h"
#include "qex/report.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>

namespace qex::cli {
namespace {

/// The quality figures in one line (percentages of the counts and of the input's diagonal).
void print_quality(const qex::MeshQuality& q) {
    if (!q.computed) {
        std::printf("quality: not measured (a surface without area, a bad index or a non-finite position)\n");
        return;
    }
    std::printf("quality: scaled Jacobian min %.3g, 5%% %.3g, mean %.3g (%lld quads", q.min_scaled_jacobian,
                q.p5_scaled_jacobian, q.mean_scaled_jacobian, static_cast<long long>(q.quads));
    if (q.other_faces > 0) std::printf(", %lld other faces skipped", static_cast<long long>(q.other_faces));
    std::printf(
        "); irregular vertices %.3g%% (%lld of %lld); distance input->mesh %.3g%%, mesh->input %.3g%% of the "
        "bounding-box diagonal\n",
        100 * q.irregular_vertex_share, static_cast<long long>(q.irregular_vertices),
        static_cast<long long>(q.vertices), 100 * q.distance_input_to_mesh, 100 * q.distance_mesh_to_input);
}

/// The verdict in words, on stdout.
void print_verdict(const std::string& mesh_path, const qex::VerifyResult& v, const qex::MeshQuality& quality) {
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
            "coverage: %lld grid cells the map covers once away from fold-overs and the boundary; %lld grid "
            "points of them without a vertex, %lld cells without a face",
            static_cast<long long>(v.coverage_cells), static_cast<long long>(v.uncovered_grid_points),
            static_cast<long long>(v.uncovered_cells));
        if (v.coverage_skipped_triangles > 0)
            std::printf(" (%lld triangles too large in UV to enumerate, not checked)",
                        static_cast<long long>(v.coverage_skipped_triangles));
        std::printf("\n");
        std::printf(
            "singularities: %lld of the map, %lld irregular vertices of the mesh, %lld valences judged; "
            "%lld fold-over footprints undecided (%lld triangles, UV area %.4g)\n",
            static_cast<long long>(v.map_cones), static_cast<long long>(v.irregular_vertices),
            static_cast<long long>(v.valences_judged), static_cast<long long>(v.undecided_footprints),
            static_cast<long long>(v.undecided_triangles), v.undecided_uv_area);
        std::printf(
            "positions carry up to %d significant digits%s; distance tolerance %.3g + up to %.3g for rounding "
            "(model units)\n",
            v.position_digits, v.positions_float32 ? " (float32 values)" : "", v.surface_tolerance,
            v.max_rounding_tolerance);
        if (!v.fold_regions.empty()) {
            std::int64_t triangles = 0;
            for (const auto& g : v.fold_regions) triangles += g.triangles;
            std::printf(
                "%zu fold-over regions of the map (%lld triangles, within %d rings of its flipped or "
                "degenerate triangles), where a repaired map may differ: %lld vertices and %lld faces "
                "there judged on the surface only (%lld vertices off the map's grid points, by up to %.3g UV)\n",
                v.fold_regions.size(), static_cast<long long>(triangles), qex::kFoldRegionRings,
                static_cast<long long>(v.surface_only_vertices), static_cast<long long>(v.surface_only_faces),
                static_cast<long long>(v.off_grid_region_vertices), v.max_region_grid_distance);
            const std::size_t shown = std::min<std::size_t>(v.fold_regions.size(), 10);
            for (std::size_t i = 0; i < shown; ++i) {
                const auto& g = v.fold_regions[i];
                std::printf(
                    "  F%zu: %lld triangles (%lld flipped or degenerate, the first input triangle %lld), "
                    "UV area %.4g (folds %.4g), %lld vertices (%lld off the grid)\n",
                    i + 1, static_cast<long long>(g.triangles), static_cast<long long>(g.fold_triangles),
                    static_cast<long long>(g.first_triangle), g.uv_area, g.fold_uv_area,
                    static_cast<long long>(g.vertices), static_cast<long long>(g.off_grid_vertices));
            }
            if (shown < v.fold_regions.size()) std::printf("  ... and %zu more\n", v.fold_regions.size() - shown);
        }
    }
    print_quality(quality);
    print_violations(v);
    std::fflush(stderr); // the listing before the verdict, on a terminal and in a log alike
    std::printf("%s\n", qex::verdict_line(v).c_str());
}

/// Where the mesh was judged, with --certificate: on the certificate (which holds against the
/// map), or, when it does not hold, on the given map.
void print_certificate(const std::string& path, const qex::VerifyResult& v) {
    if (v.on_certificate)
        std::printf(
            "judged on the certificate %s (%lld repaired triangles; it holds against the map): the located "
            "figures are the certificate map's\n",
            path.c_str(), static_cast<long long>(v.certificate_triangles));
    else
        std::printf("the certificate %s does not hold against the map (CertificateMismatch): judged on the given map\n",
                    path.c_str());
}

} // namespace

int run_check(const CheckArgs& a) {
    Progress progress(true, a.certificate_path.empty() ? 3 : 4);
    progress.step("reading " + a.param_path);
    qex::Input input;
    if (const int code = read_map(a.param_path, input); code != kOk) return code;
    progress.step("reading " + a.mesh_path);
    qex::QuadMesh mesh;
    if (const int code = read_quads(a.mesh_path, mesh); code != kOk) return code;
    qex::Certificate certificate;
    if (!a.certificate_path.empty()) {
        progress.step("reading " + a.certificate_path);
        if (const auto e = qex::read_certificate(a.certificate_path, certificate); !e.ok()) {
            progress.stop();
            std::cerr << "qex: " << e.message << "\n";
            return io_exit(e);
        }
    }
    progress.step("checking " + std::to_string(mesh.faces.size()) + " faces");
    // The oracle's one entry (qex/check.h), as qex draw --quads, the C API and Python judge.
    const qex::MeshCheck c = a.certificate_path.empty() ? qex::check_mesh(input, mesh, a.grid_scale, a.options)
                                                        : qex::check_mesh(input, mesh, certificate, a.options);
    if (!c.map_ok()) {
        // The map is the judge's reference: one that extraction would reject judges nothing.
        progress.stop();
        std::cerr << "qex: " << a.param_path << ": invalid input (" << qex::to_string(c.error.code)
                  << "): " << c.error.message << "\n";
        return kBadInput;
    }
    const qex::VerifyResult& v = c.verdict;
    // Measured on the mesh and the map as given, whatever the grid scale or certificate.
    const qex::MeshQuality quality = qex::mesh_quality(input, mesh);
    progress.stop();
    // The verdict to files first: a file that cannot be written is an error, whatever the verdict.
    if (!a.report_path.empty() && !write_text(a.report_path, qex::verify_json(v, quality) + "\n")) {
        std::cerr << "qex: cannot write '" << a.report_path << "'\n";
        return kIo;
    }
    if (!a.svg_path.empty()) {
        const std::string title = std::filesystem::path(a.mesh_path).filename().string() + " on " +
                                  std::filesystem::path(a.param_path).filename().string();
        if (!write_text(a.svg_path,
                        verdict_svg(input, mesh, v, a.certificate_path.empty() ? a.grid_scale : certificate.grid_scale,
                                    title))) {
            std::cerr << "qex: cannot write '" << a.svg_path << "'\n";
            return kIo;
        }
    }
    if (a.json) {
        std::cout << qex::verify_json(v, quality) << "\n";
    } else {
        if (!a.certificate_path.empty()) print_certificate(a.certificate_path, v);
        print_verdict(a.mesh_path, v, quality);
    }
    return v.valid ? kOk : kRejected;
}

CLI::App* add_check(CLI::App& app, CheckArgs& a) {
    auto* check = app.add_subcommand("check", "Judge a quad mesh (from any extractor) against an integer-grid map");
    check->add_option("--param", a.param_path, "the map: OBJ or PLY with per-corner UVs")->required();
    check->add_option("mesh", a.mesh_path, "the quad mesh (OBJ or PLY) to judge")->required();
    check->add_flag("--json", a.json, "print the verdict (and the mesh's quality figures) as JSON");
    check->add_option("--report", a.report_path, "also write the JSON verdict to this file");
    check->add_option("--svg", a.svg_path,
                      "also draw the violations on the map (and on the mesh, up to 30,000 faces) into this SVG");
    auto* certificate = check->add_option(
        "--certificate", a.certificate_path,
        "judge the mesh on the repaired map `qex extract --certificate` wrote beside it, once it holds against the "
        "map (its grid scale is the certificate's)");
    check
        ->add_option("--grid-scale", a.grid_scale,
                     "judge the mesh against the map with its UVs multiplied by this power of two (a mesh qex "
                     "extracted with refinement)")
        ->check(CLI::IsMember({1, 2, 4, 8, 16, 32, 64}))
        ->excludes(certificate);
    check
        ->add_option("--uv-tolerance", a.options.uv_tolerance,
                     "largest UV distance of a vertex to its grid point (default 1e-3; K times it, at most 0.1, "
                     "with --grid-scale K); at most 1 (every point lies within 0.5 of a grid point)")
        ->check(finite_number())
        ->check(CLI::Range(0.0, 1.0));
    check
        ->add_option("--distance-tolerance", a.options.distance_tolerance,
                     "largest distance of a vertex to the surface, as a fraction of the diagonal (default 1e-6)")
        ->check(finite_number())
        ->check(CLI::NonNegativeNumber);
    check
        ->add_option("--digits", a.options.position_digits,
                     "the positions may be rounded to this many significant digits (default 6: float precision)")
        ->check(CLI::Range(0, 17));
    check->add_flag(
        "--strict", [&a](std::int64_t) { a.options.position_digits = 0; },
        "double-precision output: no allowance for rounded positions (--digits 0)");
    check->add_flag(
        "--no-fold-regions", [&a](std::int64_t) { a.options.fold_regions = false; },
        "judge vertices in the raw map's fold-over regions against its grid points too (a repaired map's mesh "
        "fails there)");
    check->add_flag(
        "--strict-map", [&a](std::int64_t) { a.options.strict_map = true; },
        "decide every check against the raw map, in fold-over regions too: what would be undecided there is a "
        "violation (every singularity matched one by one, every face on a grid cell)");
    check->add_flag(
        "--topology-only", [&a](std::int64_t) { a.options.locate = false; }, "skip locating the vertices on the map");
    return check;
}

} // namespace qex::cli

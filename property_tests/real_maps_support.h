// Helpers of the tests on real maps (real_maps_test.cpp, real_maps_proofs_test.cpp,
// real_maps_mend_test.cpp): the shared maps by folder, the located mode, the first rung alone, and
// the checks that a mesh passes bare, that a scaled map is repaired, and that proofs are placed.
#pragma once

#include "ladder/ladder.h"
#include "map_transforms.h"
#include "pipeline.h"
#include "result_checks.h"
#include "test_support.h"
#include "transform_checks.h"
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <optional>
#include <random>
#include <set>
#include <tuple>
#include <optional>
#include <string>
#include <vector>

namespace qex::testing {

namespace fs = std::filesystem;

inline std::vector<fs::path> maps(const std::string& sub) {
    std::vector<fs::path> out;
    const fs::path dir = fs::path(QEX_SHARED_DIR) / "meshes" / sub;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir, ec))
        if (e.path().extension() == ".obj") out.push_back(e.path());
    std::sort(out.begin(), out.end());
    return out;
}

/// The located mode as `qex check` runs it: fold-over regions judged on the surface only.
inline VerifyOptions with_fold_regions() {
    VerifyOptions o;
    o.fold_regions = true;
    return o;
}

/// The repaired rung alone, at the map's own scale (no fallback ladder): what the repair leaves
/// is reported as it is, not covered by a later rung or scale.
inline Result first_rung(const Input& in) {
    Options one_rung;
    one_rung.fallback_ladder = false;
    return extract(in, one_rung);
}

/// qex's mesh with positions and faces only (as `qex check --param RAW --grid-scale K OUT` reads
/// it) passes the located mode against the raw map. Where the repair moved the map, the vertices
/// lie in the raw map's fold-over regions (kFoldRegionRings around its flipped or degenerate
/// triangles).
inline void expect_bare_valid(const Input& in, const QuadMesh& mesh, const fs::path& path) {
    QuadMesh bare;
    bare.positions = mesh.positions;
    bare.faces = mesh.faces;
    bare.grid_scale = mesh.grid_scale; // a refined mesh is judged against the map at its scale
    const VerifyResult located = verify(in, bare, with_fold_regions());
    EXPECT_TRUE(located.located) << path;
    EXPECT_TRUE(located.valid) << path << ": " << (located.violations.empty() ? "" : located.violations[0].message);
    if (!mesh.map_repaired.empty()) { EXPECT_FALSE(located.fold_regions.empty()) << path; }
    std::int64_t vertices = 0;
    for (const FoldRegion& g : located.fold_regions) {
        EXPECT_GT(g.fold_triangles, 0) << path;
        EXPECT_GE(g.triangles, g.fold_triangles) << path;
        EXPECT_GE(g.first_triangle, 0) << path;
        vertices += g.vertices;
    }
    EXPECT_EQ(vertices, located.surface_only_vertices) << path;
}

/// A paper map with its UVs x k, extracted and judged: valid by both checkers, every fold
/// repaired, singularities gone only in the named merges of co-located dipoles, exactly the signed
/// area's quads, the input's Euler characteristic. Returns the merges' explanations; nullopt when
/// the map is not there (the caller skips).
inline std::optional<std::vector<Defect>> expect_scaled_map_repaired(const std::string& name, std::int64_t k) {
    const fs::path path = fs::path(QEX_SHARED_DIR) / "meshes" / "paper" / (name + "_param.obj");
    Input in;
    if (!read_obj(path.string(), in).ok()) return std::nullopt;
    EXPECT_EQ(transforms::scale_uvs(in, k), 0);
    const Result r = extract(in);
    EXPECT_TRUE(r.ok()) << r.error.message;
    std::vector<Defect> merged;
    for (const Defect& d : r.report.explanations)
        if (d.kind == DefectKind::SingularitiesMerged) merged.push_back(d);
    const VerifyResult v = verify(in, r.mesh);
    EXPECT_TRUE(r.check.valid) << (r.check.violations.empty() ? "" : r.check.violations[0].message);
    EXPECT_TRUE(v.valid) << (v.violations.empty() ? "" : v.violations[0].message);
    EXPECT_EQ(r.report.rung, "repaired");
    EXPECT_EQ(r.report.unrepaired_regions, 0);
    EXPECT_EQ(r.report.flipped_after_repair, 0);
    EXPECT_EQ(v.map_singularities, r.report.singularities - 2 * static_cast<std::int64_t>(merged.size()));
    EXPECT_EQ(static_cast<std::int64_t>(r.mesh.faces.size()), v.input_signed_uv_area_rounded);
    EXPECT_EQ(v.euler, v.input_euler);
    return merged;
}

/// The grid point of input triangle t's corner at input vertex v, at the mesh's grid scale; or
/// nothing if v is no corner of t.
inline std::optional<std::array<std::int64_t, 2>> corner_grid(const Input& in, std::int64_t t, int v, int scale) {
    const auto& tri = in.triangles[static_cast<std::size_t>(t)];
    const auto at = std::find(tri.begin(), tri.end(), v);
    if (at == tri.end()) return std::nullopt;
    const auto& uv = in.uvs[3 * static_cast<std::size_t>(t) + static_cast<std::size_t>(at - tri.begin())];
    return std::array<std::int64_t, 2>{std::llround(uv[0] * scale), std::llround(uv[1] * scale)};
}

/// A proof that a fold-over's region has no fold-free map (AnglesLeaveNoRoom,
/// RegionAreaNotPositive) placed on the region's first triangle, near its first corner's grid
/// point at the mesh's grid scale, and stating what proves it: a vertex's angle outside what its
/// corners can take (0 to 2 quarter turns each), a sum of angles a radian or more off, or an area
/// that is not positive.
inline void expect_region_proof(const Input& in, const Result& r, const Defect& d) {
    ASSERT_GE(d.input_element, 0) << d.message;
    ASSERT_LT(d.input_element, static_cast<std::int64_t>(in.triangles.size())) << d.message;
    const auto first = static_cast<int>(in.triangles[static_cast<std::size_t>(d.input_element)][0]);
    const auto g = corner_grid(in, d.input_element, first, r.mesh.grid_scale);
    ASSERT_TRUE(g.has_value());
    EXPECT_LE(std::abs(d.grid[0] - (*g)[0]) + std::abs(d.grid[1] - (*g)[1]), 2) << d.message;
    int rings = 0, triangles = 0, singularities = 0, from = -1;
    ASSERT_EQ(std::sscanf(d.message.c_str() + d.message.find("within "),
                          "within %d rings (%d triangles, %d singularities inside, from input triangle %d)", &rings,
                          &triangles, &singularities, &from),
              4)
        << d.message;
    EXPECT_EQ(from, d.input_element) << d.message;
    EXPECT_GT(triangles, 0) << d.message;
    if (d.kind == DefectKind::RegionAreaNotPositive) {
        double area = 1.0;
        ASSERT_EQ(std::sscanf(d.message.c_str() + d.message.find("signed UV area of "), "signed UV area of %lf", &area),
                  1)
            << d.message;
        EXPECT_LE(area, 0.0) << d.message;
        return;
    }
    double q = 0.0;
    if (const std::size_t at = d.message.find(" miss "); at != std::string::npos) {
        ASSERT_EQ(std::sscanf(d.message.c_str() + at, " miss %lf quarter turns", &q), 1) << d.message;
        EXPECT_GE(std::abs(q), 1.0 / (0.5 * M_PI) - 0.01) << d.message << ": within the angles' rounding";
        return;
    }
    int corners = 0;
    const std::size_t at = d.message.find("from input triangle ");
    ASSERT_EQ(
        std::sscanf(d.message.c_str() + at, "from input triangle %*d) %lf quarter turns for %d corners", &q, &corners),
        2)
        << d.message;
    EXPECT_GT(corners, 0) << d.message;
    EXPECT_TRUE(q <= 0.0 || q >= 2.0 * corners) << d.message << ": room for positive triangles";
}

/// Every proof among r's explanations placed and stated as it must be, each once, before the
/// folds it backs: a RimShortOfSingularity names a triangle with a corner at its singularity,
/// whose grid point (at the mesh's grid scale) is its `grid`, and a rim short of the quarter turns
/// it needs by whole turns; a FoldPinnedBySingularities names a triangle flipped in the map as
/// given, its corners, and one corner's grid point. Returns how many of each there are.
inline std::array<int, 4> expect_proofs_placed(const Input& in, const Result& r) {
    std::array<int, 4> count{0, 0, 0, 0};
    const int k = r.mesh.grid_scale;
    const std::vector<std::int8_t> sign = uv_orientations(in);
    std::set<std::int64_t> seen_vertices, seen_triangles;
    std::set<std::string> seen_regions;
    std::size_t last_proof = 0, first_fold = r.report.explanations.size();
    for (std::size_t i = 0; i < r.report.explanations.size(); ++i) {
        const Defect& d = r.report.explanations[i];
        if (d.kind == DefectKind::FoldOverNotRepaired) first_fold = std::min(first_fold, i);
        if (d.kind == DefectKind::AnglesLeaveNoRoom || d.kind == DefectKind::RegionAreaNotPositive) {
            last_proof = i;
            ++count[d.kind == DefectKind::AnglesLeaveNoRoom ? 2 : 3];
            expect_region_proof(in, r, d);
            EXPECT_TRUE(seen_regions.insert(d.message).second) << "named twice: " << d.message;
            continue;
        }
        const bool rim = d.kind == DefectKind::RimShortOfSingularity;
        if (!rim && d.kind != DefectKind::FoldPinnedBySingularities) continue;
        last_proof = i;
        ++count[rim ? 0 : 1];
        EXPECT_GE(d.input_element, 0) << d.message;
        EXPECT_LT(d.input_element, static_cast<std::int64_t>(in.triangles.size())) << d.message;
        if (d.input_element < 0 || d.input_element >= static_cast<std::int64_t>(in.triangles.size())) continue;
        if (rim) {
            int vertex = -1, needs = 0, turns = 0;
            const std::size_t at_needs = d.message.find(" needs "), at_turns = d.message.find(") turns ");
            if (std::sscanf(d.message.c_str(), "the singularity at input vertex %d", &vertex) != 1 ||
                at_needs == std::string::npos || at_turns == std::string::npos) {
                ADD_FAILURE() << "unreadable: " << d.message;
                continue;
            }
            needs = std::stoi(d.message.substr(at_needs + 7));
            turns = std::stoi(d.message.substr(at_turns + 8));
            EXPECT_LT(turns, needs) << d.message;
            EXPECT_EQ((needs - turns) % 4, 0) << d.message;
            EXPECT_TRUE(seen_vertices.insert(vertex).second) << "named twice: " << d.message;
            const auto g = corner_grid(in, d.input_element, vertex, k);
            EXPECT_TRUE(g.has_value()) << d.message << ": its triangle has no corner at the singularity";
            if (g) { EXPECT_EQ(d.grid, *g) << d.message << " (grid scale " << k << ")"; }
        } else {
            EXPECT_LT(sign[static_cast<std::size_t>(d.input_element)], 0) << d.message << ": not flipped as given";
            EXPECT_TRUE(seen_triangles.insert(d.input_element).second) << "named twice: " << d.message;
            const std::size_t at = d.message.find("at input vertices ");
            int a = -1, b = -1, c = -1, va = 0, vb = 0, vc = 0;
            if (at == std::string::npos ||
                std::sscanf(d.message.c_str() + at,
                            "at input vertices %d (valence %d), %d (valence %d) and %d (valence %d)", &a, &va, &b, &vb,
                            &c, &vc) != 6) {
                ADD_FAILURE() << "unreadable: " << d.message;
                continue;
            }
            std::array<int, 3> named{a, b, c}, corners = in.triangles[static_cast<std::size_t>(d.input_element)];
            std::sort(named.begin(), named.end());
            std::sort(corners.begin(), corners.end());
            EXPECT_EQ(named, corners) << d.message;
            for (const int v : {va, vb, vc})
                EXPECT_NE(v, 4) << d.message << ": a corner of valence 4 is no singularity";
            bool placed = false;
            for (const int v : corners) placed = placed || corner_grid(in, d.input_element, v, k) == d.grid;
            EXPECT_TRUE(placed) << d.message << ": its grid point is no corner's (grid scale " << k << ")";
        }
    }
    if (count[0] + count[1] + count[2] + count[3] > 0) {
        EXPECT_LT(last_proof, first_fold) << "the proofs come before the folds they back";
    }
    return count;
}

} // namespace qex::testing

// The checker as an oracle for meshes written with ordinary precision: qex's own outputs of the
// real maps (../shared, skipped where absent), written as other tools write them (positions as
// %.6g, or as float32 values), pass where the double-precision mesh passes; --strict
// (VerifyOptions::position_digits = 0) keeps judging them as exact doubles.
#include "test_support.h"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>

namespace qex::testing {
namespace {

namespace fs = std::filesystem;

std::vector<fs::path> real_maps() {
    std::vector<fs::path> out;
    for (const char* sub : {"paper", "miq", "miq-more"}) {
        std::error_code ec;
        for (const auto& e : fs::directory_iterator(fs::path(QEX_SHARED_DIR) / "meshes" / sub, ec))
            if (e.path().extension() == ".obj") out.push_back(e.path());
    }
    std::sort(out.begin(), out.end());
    return out;
}

QuadMesh bare(const QuadMesh& m) {
    QuadMesh b;
    b.positions = m.positions;
    b.faces = m.faces;
    return b;
}

/// The mesh with every coordinate as printf("%.6g") writes it.
QuadMesh printed_6g(QuadMesh m) {
    char buf[32];
    for (auto& p : m.positions)
        for (double& x : p) {
            std::snprintf(buf, sizeof buf, "%.6g", x);
            x = std::strtod(buf, nullptr);
        }
    return m;
}

/// The mesh with every coordinate rounded to a float32 (through a volatile float: with
/// -frounding-math GCC 12 drops the double -> float -> double round trip).
QuadMesh as_float32(QuadMesh m) {
    for (auto& p : m.positions)
        for (double& x : p) {
            volatile float narrow = static_cast<float>(x);
            x = narrow;
        }
    return m;
}

std::string first_message(const VerifyResult& v) { return v.violations.empty() ? "" : v.violations[0].message; }

TEST(CheckerPrecision, RoundedPositionsOfCorrectMeshesPass) {
    const auto files = real_maps();
    if (files.empty()) GTEST_SKIP() << "no maps in " << QEX_SHARED_DIR << "/meshes";
    VerifyOptions strict;
    strict.position_digits = 0;
    int judged = 0;
    for (const auto& path : files) {
        Input in;
        ASSERT_TRUE(read_obj(path.string(), in).ok()) << path;
        const Result r = extract(in);
        if (!r.ok() || !r.check.valid) continue;
        const QuadMesh exact = bare(r.mesh);
        // Only meshes the located mode accepts in double precision (not those whose repaired
        // map moved vertices off the given map's grid points).
        const VerifyResult d = verify(in, exact, strict);
        if (!d.valid) continue;
        ++judged;
        EXPECT_TRUE(verify(in, exact).valid) << path;
        const VerifyResult p = verify(in, printed_6g(exact));
        EXPECT_TRUE(p.valid) << path << " (%.6g): " << first_message(p);
        EXPECT_LE(p.position_digits, 6) << path;
        const VerifyResult f = verify(in, as_float32(exact));
        EXPECT_TRUE(f.valid) << path << " (float32): " << first_message(f);
        EXPECT_TRUE(f.positions_float32) << path;
        EXPECT_LE(f.max_rounding_tolerance, 5e-6 * 1e4) << path;
    }
    std::cout << judged << " of " << files.size() << " real maps' outputs judged at three precisions\n";
    EXPECT_GT(judged, 0);
}

TEST(CheckerPrecision, StrictModeTakesPositionsAsExact) {
    // A vertex moved off the surface by 3e-6 of its coordinates' magnitude: within the rounding
    // of 6 significant digits (5e-6), beyond the strict tolerance (1e-6 of the diagonal).
    const Input in = make_map(torus_layout(), 3, 2);
    QuadMesh m = bare(extract(in).mesh);
    VerifyOptions strict;
    strict.position_digits = 0;
    ASSERT_TRUE(verify(in, m, strict).valid);
    auto& x = m.positions[3];
    const double norm = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
    // Along the direction away from the torus' core circle's axis (z): off the surface.
    const double rxy = std::sqrt(x[0] * x[0] + x[1] * x[1]);
    const double shift = 3e-6 * norm;
    if (rxy > 0) x[0] += shift * x[0] / rxy, x[1] += shift * x[1] / rxy;
    const VerifyResult s = verify(in, m, strict);
    const VerifyResult d = verify(in, m);
    EXPECT_EQ(d.position_digits, 17);
    // The default tolerance takes it as rounding; strict mode does not, where the shift left the
    // surface by more than its tolerance (1e-6 of the diagonal: max_surface_distance's unit).
    EXPECT_TRUE(d.valid) << first_message(d);
    EXPECT_GT(d.max_rounding_tolerance, shift);
    if (s.max_surface_distance > 1e-6) {
        ASSERT_FALSE(s.valid);
        EXPECT_EQ(s.violations.front().kind, ViolationKind::OffSurface);
    }
}

} // namespace
} // namespace qex::testing

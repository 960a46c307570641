// Metamorphic properties on real maps (issue 12), one test per map and transform: an integer
// translation and a re-charting must give the same mesh up to rounding, a shuffle of vertices,
// triangles and corners the identical mesh (the output is in canonical order), and a 1-to-4
// subdivision a valid mesh of the map's area. The three slowest ducks (their fold-overs take the
// repair seconds per extraction) are in the instantiation LongMetamorphic (-DQEX_LONG_TESTS=ON).
#include "map_transforms.h"
#include "transform_checks.h"

#include <gtest/gtest.h>

#include <iostream>
#include <string>
#include <vector>

namespace qex::testing {
namespace {

enum class Transform { Translate, Rechart, Shuffle, Subdivide };

struct MapTransformCase {
    std::string folder, map; ///< meshes/<folder>/<map>_param.obj
    Transform transform;
};

const char* name(Transform t) {
    switch (t) {
        case Transform::Translate: return "translate";
        case Transform::Rechart: return "rechart";
        case Transform::Shuffle: return "shuffle";
        default: return "subdivide";
    }
}

void PrintTo(const MapTransformCase& c, std::ostream* os) {
    *os << c.folder << "/" << c.map << " " << name(c.transform);
}

std::string case_name(const ::testing::TestParamInfo<MapTransformCase>& info) {
    return info.param.map + "_" + name(info.param.transform);
}

std::vector<MapTransformCase> cases(const std::string& folder, const std::vector<std::string>& maps) {
    std::vector<MapTransformCase> out;
    for (const std::string& map : maps)
        for (Transform t : {Transform::Translate, Transform::Rechart, Transform::Shuffle, Transform::Subdivide})
            out.push_back({folder, map, t});
    return out;
}

/// Relative tolerance of positions after a transform that rounds UVs (of the bounding-box
/// diagonal): sanitizing re-truncates every UV to a precision set by its magnitude, which a
/// translation or re-charting changes, and grid points move with it by about 1e-7 relative.
constexpr double kRelativeTolerance = 1e-6;
/// Of the median edge length, for the vertices a repaired region places (the owner's decision:
/// translation and re-charting keep the connectivity exactly, those positions within 1%).
constexpr double kRepairedTolerance = 0.01;

class RealMapTransform : public ::testing::TestWithParam<MapTransformCase> {};

TEST_P(RealMapTransform, KeepsTheMesh) {
    const MapTransformCase& c = GetParam();
    Input in;
    if (const std::string why = read_real_map(c.folder, c.map, in); !why.empty()) GTEST_SKIP() << why;
    Input moved = in;
    std::int64_t rounded = 0;
    switch (c.transform) {
        case Transform::Translate: rounded = transforms::translate_uvs(moved, 37, -23); break;
        case Transform::Rechart: rounded = transforms::rechart(moved, 12, 16); break;
        case Transform::Shuffle: transforms::shuffle(moved, 12); break;
        case Transform::Subdivide: moved = transforms::subdivide(in); break;
    }
    const Result r = extract(moved);
    ASSERT_TRUE(r.ok()) << to_string(r.error.code) << ": " << r.error.message;
    const VerifyResult v = verify(moved, r.mesh);
    const std::string about =
        c.map + " " + name(c.transform) + " (" + std::to_string(rounded) + " UV coordinates rounded): " + summary(r, v);
    std::cout << about << "\n";

    if (c.transform == Transform::Subdivide) {
        // The same map on four times the triangles: valid, and on a closed map whose fold-overs
        // were all repaired, as many quads as the area.
        EXPECT_TRUE(r.check.valid) << about << "\nextract's check: " << violations_text(r.check.violations);
        EXPECT_TRUE(v.valid) << about << "\nverify: " << violations_text(v.violations);
        if (r.report.unrepaired_regions == 0 && v.input_boundary_loops == 0) {
            EXPECT_EQ(static_cast<std::int64_t>(r.mesh.faces.size()), v.input_signed_uv_area_rounded) << about;
        }
        return;
    }

    const Result base = extract(in);
    ASSERT_TRUE(base.ok()) << to_string(base.error.code) << ": " << base.error.message;
    const VerifyResult bv = verify(in, base.mesh);
    const std::string base_about = "as given: " + summary(base, bv);
    EXPECT_EQ(r.check.valid, base.check.valid) << about << "\n" << base_about;
    EXPECT_EQ(r.mesh.faces.size(), base.mesh.faces.size()) << about << "\n" << base_about;
    EXPECT_EQ(r.mesh.positions.size(), base.mesh.positions.size()) << about << "\n" << base_about;
    EXPECT_EQ(v.euler, bv.euler) << about << "\n" << base_about;
    if (c.transform == Transform::Shuffle) {
        // The map is the same and the output canonical: the same doubles, the same faces.
        EXPECT_EQ(position_difference(r.mesh.positions, base.mesh.positions), "") << about << "\n" << base_about;
        EXPECT_TRUE(r.mesh.faces == base.mesh.faces) << about << "\n" << base_about;
        return;
    }
    // Connectivity exactly; positions up to rounding, and inside repaired regions (whose
    // relaxation need not reach its minimum) up to 1% of the median edge length.
    const double tol = kRelativeTolerance * bbox_diagonal(in.positions);
    const double repaired_tol = kRepairedTolerance * median_edge_length(base.mesh);
    EXPECT_EQ(mesh_difference(r.mesh, base.mesh, tol, repaired_tol, placed_by_repair(r.mesh, base.mesh)), "")
        << about << "\n" << base_about;
}

// The paper's three fast maps and four small MIQ maps (genus 0, 3 and 4, and one with a
// boundary) run by default: a few seconds together.
INSTANTIATE_TEST_SUITE_P(PaperMaps, RealMapTransform,
                         ::testing::ValuesIn(cases("paper", {"duck_miq_4", "duck_miq_8", "fandisk"})), case_name);
INSTANTIATE_TEST_SUITE_P(MiqMaps, RealMapTransform,
                         ::testing::ValuesIn(cases("miq", {"bunny_miq_40", "3holes_miq_20", "fertility_miq_40",
                                                           "camelhead_miq_40"})),
                         case_name);
INSTANTIATE_TEST_SUITE_P(LongMetamorphic, RealMapTransform,
                         ::testing::ValuesIn(cases("paper", {"duck_miq_16", "duck_miq_28", "duck_qc_8"})), case_name);

} // namespace
} // namespace qex::testing

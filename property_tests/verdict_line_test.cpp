// The verdict in one line (qex::verdict_line) and what it left undecided (qex::undecided_share):
// bare "VALID" only when nothing was left undecided, the undecided checks and the fold-over
// regions that hold them otherwise, the same figures in the JSON; and --strict-map, under which
// nothing is undecided: what would be is a violation.
#include "map_generators.h"
#include "test_support.h"
#include "qex/io.h"
#include "qex/report.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>

namespace qex::testing {
namespace {

namespace fs = std::filesystem;

/// qex's mesh with positions and faces only, as `qex check --param` reads another tool's.
QuadMesh bare(const QuadMesh& mesh) {
    QuadMesh b;
    b.positions = mesh.positions;
    b.faces = mesh.faces;
    b.grid_scale = mesh.grid_scale;
    return b;
}

TEST(VerdictLine, AMeshOnAFoldFreeMapIsBareValidAndStaysValidUnderStrictMap) {
    const Input in = make_map(cube_layout(), 3, 4);
    const Result r = extract_valid(in);
    const VerifyResult v = verify(in, bare(r.mesh));
    ASSERT_TRUE(v.valid);
    EXPECT_TRUE(v.undecided.empty());
    EXPECT_EQ(verdict_line(v), "VALID");
    VerifyOptions strict;
    strict.strict_map = true;
    const VerifyResult s = verify(in, bare(r.mesh), strict);
    EXPECT_TRUE(s.valid) << (s.violations.empty() ? "" : s.violations[0].message);
    EXPECT_EQ(verdict_line(s), "VALID");
}

TEST(VerdictLine, ARejectedMeshCountsItsViolations) {
    const Input in = make_map(cube_layout(), 3, 4);
    QuadMesh m = bare(extract_valid(in).mesh);
    m.faces.pop_back(); // a hole
    const VerifyResult v = verify(in, m);
    ASSERT_FALSE(v.valid);
    const std::string n = std::to_string(v.violations.size());
    EXPECT_EQ(verdict_line(v).rfind("INVALID (" + n + (v.violations.size() == 1 ? " violation)" : " violations)"), 0),
              0u)
        << verdict_line(v);
}

// On a map with fold-overs, qex's mesh judged without provenance leaves checks undecided in the
// map's fold-over regions: the line names them with the regions' triangles and share, as the
// JSON does; under --strict-map each of them is a violation and nothing is undecided.
TEST(VerdictLine, UndecidedChecksAreNamedWithTheirRegionsAndBecomeViolationsUnderStrictMap) {
    const fs::path path = fs::path(QEX_SHARED_DIR) / "meshes" / "paper" / "duck_miq_16_param.obj";
    Input in;
    if (!read_obj(path.string(), in).ok()) GTEST_SKIP() << "no " << path;
    const Result r = extract_valid(in);
    const VerifyResult v = verify(in, bare(r.mesh));
    ASSERT_TRUE(v.valid);
    ASSERT_FALSE(v.undecided.empty()) << "the fold-over regions decide everything: this test needs another map";
    const UndecidedShare u = undecided_share(v);
    EXPECT_EQ(u.checks, static_cast<std::int64_t>(v.undecided.size()));
    EXPECT_EQ(u.regions, static_cast<std::int64_t>(v.fold_regions.size()));
    std::int64_t triangles = 0;
    for (const FoldRegion& g : v.fold_regions) triangles += g.triangles;
    EXPECT_EQ(u.triangles, triangles);
    EXPECT_DOUBLE_EQ(u.share, static_cast<double>(triangles) / static_cast<double>(in.triangles.size()));
    const std::string line = verdict_line(v);
    EXPECT_EQ(line.rfind("VALID, " + std::to_string(u.checks) + " checks undecided in " + std::to_string(u.regions) +
                             (u.regions == 1 ? " fold-over region (" : " fold-over regions (") +
                             std::to_string(u.triangles) + " triangles, ",
                         0),
              0u)
        << line;
    const nlohmann::json j = nlohmann::json::parse(verify_json(v));
    EXPECT_EQ(j["verdict_line"], line);
    EXPECT_EQ(j["undecided_share"]["checks"], u.checks);
    EXPECT_EQ(j["undecided_share"]["triangles"], u.triangles);
    VerifyOptions strict;
    strict.strict_map = true;
    const VerifyResult s = verify(in, bare(r.mesh), strict);
    EXPECT_FALSE(s.valid);
    EXPECT_TRUE(s.undecided.empty());
    EXPECT_FALSE(s.violations.empty()); // judged against the raw map: not the same checks, but none open
    EXPECT_EQ(verdict_line(s).rfind("INVALID (", 0), 0u) << verdict_line(s);
}

} // namespace
} // namespace qex::testing

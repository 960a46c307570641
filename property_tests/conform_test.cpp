// qex::conform (qex/conform.h) with in-process callbacks as extractors: qex's extraction exact on
// known cases, a callback that aborts or throws classified; the case list fixed by its seed.
#include "qex/conform.h"
#include "qex/qex.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>

namespace {

namespace fs = std::filesystem;

std::string out_dir(const std::string& name) {
    const fs::path dir = fs::temp_directory_path() / ("qex_conform_test_" + name + "_" + std::to_string(getpid()));
    fs::remove_all(dir);
    return dir.string();
}

/// qex's extraction, in the case's child process.
int extract_with_qex(const std::string& in, const std::string& out) {
    qex::Input input;
    if (!qex::read_obj(in, input, 1).ok()) return 3;
    qex::Options options;
    options.threads = 1;
    const qex::Result r = qex::extract(input, options);
    if (!r.ok() || !r.check.valid) return 5;
    return qex::write_obj(out, r.mesh, 1).ok() ? 0 : 2;
}

/// qex's extraction of the map with its UVs times k: for k = 2 a mesh valid at grid scale 2 (as
/// qex extract refines), for k = 3 one on a grid no power of two refines (the wrong map).
int extract_scaled(const std::string& in, const std::string& out, double k) {
    qex::Input input;
    if (!qex::read_obj(in, input, 1).ok()) return 3;
    for (auto& uv : input.uvs) uv = {k * uv[0], k * uv[1]};
    qex::Options options;
    options.threads = 1;
    const qex::Result r = qex::extract(input, options);
    if (!r.ok() || !r.check.valid) return 5;
    qex::QuadMesh mesh = r.mesh;
    mesh.face_uvs.clear(); // the scaled map's
    return qex::write_obj(out, mesh, 1).ok() ? 0 : 2;
}

TEST(Conform, CasesAreFixedBySeed) {
    const auto a = qex::conform_cases({"known", "hostile"}, 12, 7), b = qex::conform_cases({"known", "hostile"}, 12, 7);
    const auto c = qex::conform_cases({"known"}, 12, 8);
    ASSERT_EQ(a.size(), 24u);
    bool differs = false;
    for (std::size_t i = 0; i < a.size(); ++i) {
        EXPECT_EQ(a[i].name, b[i].name);
        EXPECT_EQ(qex::conform_map_text(a[i]), qex::conform_map_text(b[i]));
        if (i < c.size()) differs |= qex::conform_map_text(a[i]) != qex::conform_map_text(c[i]);
        EXPECT_EQ(qex::conform_case_json(qex::conform_case_from_json(qex::conform_case_json(a[i]))),
                  qex::conform_case_json(a[i]));
    }
    EXPECT_TRUE(differs);
    std::string error;
    EXPECT_TRUE(qex::conform_cases({"no/such/folder"}, 3, 1, &error).empty());
    EXPECT_NE(error.find("no/such/folder"), std::string::npos);
}

TEST(Conform, CallbackExtractorIsExactOnKnownCases) {
    qex::ConformOptions o;
    o.out_dir = out_dir("exact");
    o.jobs = 2;
    const auto results = qex::conform(qex::conform_cases({"known"}, 6, 1), extract_with_qex, o);
    ASSERT_EQ(results.size(), 6u);
    for (const auto& r : results) {
        EXPECT_EQ(r.outcome, qex::ConformOutcome::Exact) << r.c.name << ": " << r.detail;
        EXPECT_EQ(r.quads, r.c.expected_quads) << r.c.name;
        EXPECT_TRUE(r.quality.computed) << r.c.name;
    }
    std::ifstream summary(fs::path(o.out_dir) / "summary.jsonl");
    int lines = 0;
    for (std::string line; std::getline(summary, line);) ++lines;
    EXPECT_EQ(lines, 6);
    fs::remove_all(o.out_dir);
}

TEST(Conform, AbortingAndThrowingCallbacks) {
    qex::ConformOptions o;
    o.out_dir = out_dir("broken");
    const auto cases = qex::conform_cases({"known"}, 1, 1);
    const auto aborted = qex::conform(
        cases, [](const std::string&, const std::string&) -> int { std::abort(); }, o);
    EXPECT_EQ(aborted[0].outcome, qex::ConformOutcome::Crash);
    EXPECT_NE(aborted[0].detail.find("SIGABRT"), std::string::npos) << aborted[0].detail;
    EXPECT_TRUE(fs::exists(fs::path(aborted[0].folder) / "replay.sh"));
    const auto thrown = qex::conform(
        cases, [](const std::string&, const std::string&) -> int { throw std::runtime_error("no"); }, o);
    EXPECT_EQ(thrown[0].outcome, qex::ConformOutcome::CleanFailure);
    EXPECT_FALSE(thrown[0].right);
    fs::remove_all(o.out_dir);
}

TEST(Conform, RefinedMeshIsJudgedAtItsGridScale) {
    qex::ConformOptions o;
    o.out_dir = out_dir("refined");
    o.jobs = 2;
    const auto cases = qex::conform_cases({"known"}, 2, 1);
    const auto refined = qex::conform(
        cases, [](const std::string& in, const std::string& out) { return extract_scaled(in, out, 2); }, o);
    for (const auto& r : refined) {
        // Valid at grid scale 2, but a known count is at scale 1.
        EXPECT_EQ(r.outcome, qex::ConformOutcome::WrongCount) << r.c.name << ": " << r.detail;
        EXPECT_EQ(r.grid_scale, 2) << r.c.name;
        EXPECT_EQ(r.quads, 4 * r.c.expected_quads) << r.c.name;
        EXPECT_NE(r.detail.find("grid scale 2"), std::string::npos) << r.detail;
        std::ifstream replay(fs::path(r.folder) / "replay.sh");
        const std::string script((std::istreambuf_iterator<char>(replay)), std::istreambuf_iterator<char>());
        EXPECT_NE(script.find("--grid-scale 2\n"), std::string::npos) << script;
        // The same files as a user's map (no count known): valid, so right.
        qex::ConformCase user;
        user.name = user.family = user.kind = "user";
        const auto u = qex::conform_judge(user, r.folder + "/map.obj", r.folder + "/output.obj", {});
        EXPECT_EQ(u.outcome, qex::ConformOutcome::Valid) << u.detail;
        EXPECT_TRUE(u.right);
        EXPECT_EQ(u.grid_scale, 2);
        EXPECT_EQ(u.area, r.c.expected_quads); // the map's own area, at grid scale 1
    }
    const auto thirds = qex::conform(
        cases, [](const std::string& in, const std::string& out) { return extract_scaled(in, out, 3); }, o);
    for (const auto& r : thirds) {
        EXPECT_EQ(r.outcome, qex::ConformOutcome::InvalidExit0) << r.c.name << ": " << r.detail;
        EXPECT_EQ(r.grid_scale, 1) << r.c.name;
    }
    fs::remove_all(o.out_dir);
}

} // namespace

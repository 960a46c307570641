// The parallel loops: any thread count gives the serial output, and the serial error.
#include "test_support.h"
#include "transform_checks.h"

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

namespace qex::testing {
namespace {

std::string temp_path(const std::string& name) {
    return (std::filesystem::temp_directory_path() / ("qex_parallel_test_" + name)).string();
}

std::string read_text(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

TEST(Extraction, ParallelLoopsGiveTheSerialOutput) {
    // Options::threads changes who computes, not what: bit-identical meshes, provenance and maps.
    std::vector<Input> inputs;
    // Loops run in parallel from 2^12 corners on; the large torus and its subdivided cube are
    // far above that (2^16 and more).
    for (const auto& layout : {cube_layout(), prism_layout(5), annulus_layout(), torus_layout(32, 16)}) {
        Input in = make_map(layout, 2, layout.quads.size() > 100 ? 6 : 5, 2, 7);
        std::mt19937 rng(3);
        rechart(in, rng);
        add_noise(in, 1e-9, rng);
        inputs.push_back(in);
    }
    {
        std::vector<char> single;
        Input folded = make_map(torus_layout(), 2, 5, 1, 1, &single);
        for (int v = 0; v < static_cast<int>(folded.positions.size()); ++v)
            if (single[v] && displace_vertex(folded, v, 0.7, 0.7) > 0) break;
        inputs.push_back(folded);
        inputs.push_back(subdivide(subdivide(subdivide(subdivide(make_map(cube_layout(), 3, 3, 2, 5))))));
    }
    ASSERT_GE(3 * inputs[3].triangles.size(), std::size_t{1} << 16);
    ASSERT_GE(3 * inputs.back().triangles.size(), std::size_t{1} << 16);
    for (const Input& in : inputs) {
        Options serial, parallel;
        serial.threads = 1;
        parallel.threads = 2;
        const Result a = extract(in, serial), b = extract(in, parallel);
        ASSERT_TRUE(a.ok() && b.ok());
        EXPECT_EQ(a.mesh.positions, b.mesh.positions);
        EXPECT_EQ(a.mesh.faces, b.mesh.faces);
        EXPECT_EQ(a.mesh.face_uvs, b.mesh.face_uvs);
        EXPECT_EQ(a.mesh.map_uvs, b.mesh.map_uvs);
        ASSERT_EQ(a.mesh.provenance.size(), b.mesh.provenance.size());
        for (std::size_t i = 0; i < a.mesh.provenance.size(); ++i) {
            EXPECT_EQ(a.mesh.provenance[i].grid, b.mesh.provenance[i].grid);
            EXPECT_EQ(a.mesh.provenance[i].chart_triangle, b.mesh.provenance[i].chart_triangle);
        }
        EXPECT_EQ(a.report.singularities, b.report.singularities);
    }
}

/// Whether two maps hold the same bits (a corner no rung placed carries NaN, which == rejects).
bool same_bits(const std::vector<std::array<double, 2>>& a, const std::vector<std::array<double, 2>>& b) {
    return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(a[0])) == 0);
}

/// Extracts `in` on 2 and 3 threads and expects the serial result `a`: the map, the mesh, the
/// rung that stands and the report's explanations and verdict.
void expect_serial_result_on_threads(const Input& in, const Result& a, const std::string& name) {
    for (const int threads : {2, 3}) {
        Options parallel;
        parallel.threads = threads;
        const Result b = extract(in, parallel);
        ASSERT_TRUE(b.ok()) << name;
        const std::string at = name + ", " + std::to_string(threads) + " threads";
        EXPECT_TRUE(same_bits(a.mesh.map_uvs, b.mesh.map_uvs)) << at;
        EXPECT_EQ(a.mesh.map_repaired, b.mesh.map_repaired) << at;
        EXPECT_EQ(a.mesh.positions, b.mesh.positions) << at;
        EXPECT_EQ(a.mesh.faces, b.mesh.faces) << at;
        EXPECT_EQ(a.report.rung, b.report.rung) << at;
        EXPECT_EQ(a.report.rungs_tried, b.report.rungs_tried) << at;
        EXPECT_EQ(a.check.valid, b.check.valid) << at;
        EXPECT_EQ(a.check.violations.size(), b.check.violations.size()) << at;
        ASSERT_EQ(a.report.explanations.size(), b.report.explanations.size()) << at;
        for (std::size_t i = 0; i < a.report.explanations.size(); ++i)
            EXPECT_EQ(a.report.explanations[i].message, b.report.explanations[i].message) << at;
    }
}

TEST(Extraction, RepairOnSeveralThreadsGivesTheSerialOutput) {
    // The repair attempts the regions of a ring radius side by side, in groups that share no
    // vertex, and a large region's retry beside its first try (RetryBeside). On real maps with
    // many fold-over regions, some repaired and some not (several groups per ring), and with a
    // large region repaired by its retry (duck_miq_8's within 4 rings) or failing it (duck_qc_8's),
    // two and three threads must give the serial map, mesh and explanations. On duck_qc_8 the
    // look before the last ring loses quads and that ring changes nothing: with threads, the
    // look's mesh is judged beside the ring, and its verdict must be the serial one.
    for (const auto& [name, some_left] :
         {std::pair{"duck_qc_8", true}, std::pair{"duck_miq_16", true}, std::pair{"duck_miq_8", false}}) {
        Input in;
        if (const std::string why = read_real_map("paper", name, in); !why.empty()) GTEST_SKIP() << why;
        Options serial;
        serial.threads = 1;
        const Result a = extract(in, serial);
        ASSERT_TRUE(a.ok()) << name;
        ASSERT_GT(a.report.repaired_regions, 1) << name;
        ASSERT_EQ(a.report.unrepaired_regions > 0, some_left) << name;
        expect_serial_result_on_threads(in, a, name);
    }
}

TEST(Extraction, StageHookHearsTheLooksCheckJudgedBesideTheLastRing) {
    // duck_qc_8's look before the last ring loses a quad and that ring changes nothing: on two
    // threads the look's mesh is judged beside it, on a thread of its own. The caller's hook must
    // still hear every stage the report times, the check last, as on one thread.
    Input in;
    if (const std::string why = read_real_map("paper", "duck_qc_8", in); !why.empty()) GTEST_SKIP() << why;
    for (const int threads : {1, 2}) {
        std::vector<std::string> heard;
        Options options;
        options.threads = threads;
        options.on_stage = [&](const char* stage, int) { heard.emplace_back(stage); };
        const Result r = extract(in, options);
        ASSERT_TRUE(r.ok() && r.check.valid) << threads;
        ASSERT_FALSE(heard.empty()) << threads;
        EXPECT_EQ(heard.back(), "check") << threads << " threads";
        for (const auto& [name, seconds] : r.report.stage_seconds)
            EXPECT_NE(std::find(heard.begin(), heard.end(), name), heard.end()) << name << ", " << threads;
    }
}

TEST(Extraction, LadderOnSeveralThreadsGivesTheSerialOutput) {
    // Where the repaired rung's mesh is rejected, the later rungs run side by side (the longest
    // first) or, on one thread, in the ladder's order up to the first whose verdict the reading
    // stops at. Either way the rung that stands, its mesh and its report are the serial ladder's:
    // on cow_miq_10 untangled-1 stands (untangled-3 not needed), on fertility_miq_5 no rung
    // gives a valid mesh and the one with the fewest violations is returned.
    for (const auto& [set, name, rung] : {std::tuple{"miq-more", "cow_miq_10", "untangled-1"},
                                          std::tuple{"miq", "fertility_miq_5", "as-given"}}) {
        Input in;
        if (const std::string why = read_real_map(set, name, in); !why.empty()) GTEST_SKIP() << why;
        Options serial;
        serial.threads = 1;
        const Result a = extract(in, serial);
        ASSERT_TRUE(a.ok()) << name;
        ASSERT_EQ(a.report.rung, rung) << name;
        ASSERT_GE(a.report.rungs_tried, 3) << name;
        expect_serial_result_on_threads(in, a, name);
    }
}

TEST(Extraction, ParallelSortsAndWriterGiveTheSerialOutputOnLargeMeshes) {
    // Canonicalize sorts vertices and faces on two threads from 2^16 of them on, and the OBJ
    // writer writes out on a second thread from 2^16 faces on: a torus map of 73,728 quads at
    // threads 1 and 2 gives the same mesh and the same bytes.
    const Input in = make_map(torus_layout(32, 16), 12, 5, 2, 7);
    Options serial, parallel;
    serial.threads = 1;
    parallel.threads = 2;
    const Result a = extract(in, serial), b = extract(in, parallel);
    ASSERT_TRUE(a.ok() && b.ok());
    ASSERT_TRUE(a.check.valid);
    ASSERT_GE(a.mesh.faces.size(), std::size_t{1} << 16);
    ASSERT_GE(a.mesh.positions.size(), std::size_t{1} << 16);
    EXPECT_EQ(a.mesh.positions, b.mesh.positions);
    EXPECT_EQ(a.mesh.faces, b.mesh.faces);
    const std::string one = temp_path("serial.obj"), two = temp_path("overlapped.obj");
    ASSERT_TRUE(write_obj(one, a.mesh, 1).ok());
    ASSERT_TRUE(write_obj(two, a.mesh, 2).ok());
    const std::string text = read_text(one);
    EXPECT_GT(text.size(), std::size_t{8} << 20); // several of the writer's 4 MiB blocks
    const std::string overlapped = read_text(two);
    EXPECT_TRUE(text == overlapped) << text.size() << " bytes serially, " << overlapped.size() << " overlapped";
    // A face of more corners than a block holds is written block by block: the same text.
    QuadMesh long_face = a.mesh;
    long_face.faces.resize(1 << 16);
    long_face.face_uvs.clear();
    for (int v = 0; v < static_cast<int>(long_face.positions.size()); ++v) long_face.faces[0].push_back(v);
    ASSERT_TRUE(write_obj(one, long_face, 1).ok());
    ASSERT_TRUE(write_obj(two, long_face, 2).ok());
    EXPECT_TRUE(read_text(one) == read_text(two)); // not EXPECT_EQ: no diff of megabytes
    std::remove(one.c_str());
    std::remove(two.c_str());
}

TEST(Extraction, ParallelTopologyReportsTheSerialError) {
    // The edge table is filled and checked on several threads; a broken large input must get
    // the error (kind, message, element) a serial run reports: the first in the serial order.
    const Input base = subdivide(subdivide(subdivide(subdivide(make_map(cube_layout(), 3, 3, 2, 5)))));
    ASSERT_GE(3 * base.triangles.size(), std::size_t{1} << 16);
    ASSERT_GT(base.triangles.size(), std::size_t{25000});
    // Two defects of one kind per input; the serial order reports the one on the edge whose
    // smaller vertex comes first, so each is also extracted alone to know its message.
    auto doubled = [&](std::vector<std::size_t> faces) {
        Input in = base;
        for (std::size_t f : faces) {
            in.triangles.push_back(in.triangles[f]);
            for (std::size_t k = 0; k < 3; ++k) in.uvs.push_back(in.uvs[3 * f + k]);
        }
        return in;
    };
    auto flipped = [&](std::vector<std::size_t> faces) {
        Input in = base;
        for (std::size_t f : faces) {
            std::swap(in.triangles[f][1], in.triangles[f][2]);
            std::swap(in.uvs[3 * f + 1], in.uvs[3 * f + 2]);
        }
        return in;
    };
    auto smaller_vertex = [](const std::string& message) {
        int a = -1, b = -1;
        EXPECT_EQ(std::sscanf(message.c_str(), "edge (%d, %d)", &a, &b), 2) << message;
        return std::min(a, b);
    };
    Options serial, parallel;
    serial.threads = 1;
    parallel.threads = 2;
    for (int kind = 0; kind < 2; ++kind) {
        const std::size_t f1 = kind == 0 ? 20000 : 25000, f2 = kind == 0 ? 7 : 123;
        auto make = [&](std::vector<std::size_t> faces) { return kind == 0 ? doubled(faces) : flipped(faces); };
        const Input both = make({f1, f2});
        const Result a = extract(both, serial), b = extract(both, parallel);
        ASSERT_FALSE(a.ok());
        EXPECT_EQ(a.error.code, b.error.code);
        EXPECT_EQ(a.error.message, b.error.message);
        EXPECT_EQ(a.error.element, b.error.element);
        const Result one = extract(make({f1}), parallel), two = extract(make({f2}), parallel);
        const Result& first = smaller_vertex(one.error.message) < smaller_vertex(two.error.message) ? one : two;
        EXPECT_EQ(b.error.message, first.error.message);
    }
    // Q-vertices are generated in ranges on all threads: a budget exhausted partway is reported
    // at the same triangle as in a serial run, for edge- and for face-q-vertices.
    const Input grid = make_map(torus_layout(32, 16), 8, 7);
    ASSERT_GE(3 * grid.triangles.size(), std::size_t{1} << 16);
    const Result full = extract(grid, parallel);
    ASSERT_TRUE(full.ok());
    ASSERT_GT(full.report.qvertices_on_edges, 1000);
    ASSERT_GT(full.report.qvertices_in_faces, 1000);
    const std::int64_t total =
        full.report.qvertices_on_vertices + full.report.qvertices_on_edges + full.report.qvertices_in_faces;
    for (const std::int64_t budget : {full.report.qvertices_on_vertices + full.report.qvertices_on_edges / 2,
                                      total - full.report.qvertices_in_faces / 3}) {
        Options a = serial, b = parallel;
        a.max_qvertices = b.max_qvertices = budget;
        const Result x = extract(grid, a), y = extract(grid, b);
        EXPECT_EQ(x.error.code, ErrorCode::MapTooLarge);
        EXPECT_EQ(x.error.code, y.error.code);
        EXPECT_EQ(x.error.element, y.error.element);
        EXPECT_GE(x.error.element, 0);
    }
}
} // namespace
} // namespace qex::testing

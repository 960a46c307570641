// The PLY reader and writer: maps read back exactly from ASCII and both binary byte orders, the
// writer's quad meshes read back, and every malformed file an error with its place and nothing
// read.
#include "test_support.h"

#include <cstdio>
#include <cstring>
#include <string>

namespace qex::testing {
namespace {

/// A map as PLY text or bytes, written here independently of the library's writer.
std::string map_ply(const Input& in, const char* format) {
    const std::string kind = format;
    std::string s = "ply\nformat " + kind + " 1.0\nelement vertex " + std::to_string(in.positions.size()) +
                    "\nproperty double x\nproperty double y\nproperty double z\nelement face " +
                    std::to_string(in.triangles.size()) +
                    "\nproperty list uchar int vertex_indices\nproperty list uchar double texcoord\nend_header\n";
    const bool big = kind == "binary_big_endian";
    const auto put = [&](const void* p, std::size_t n) {
        std::string b(static_cast<const char*>(p), n);
        if (big) std::reverse(b.begin(), b.end()); // the tests run on little-endian hosts
        s += b;
    };
    char buf[64];
    for (const auto& p : in.positions)
        for (double x : p) {
            if (kind == "ascii")
                std::snprintf(buf, sizeof buf, "%.17g ", x), s += buf;
            else
                put(&x, 8);
        }
    if (kind == "ascii") s += "\n";
    for (std::size_t t = 0; t < in.triangles.size(); ++t) {
        if (kind == "ascii") {
            s += "3";
            for (int v : in.triangles[t]) s += " " + std::to_string(v);
            s += " 6";
            for (int k = 0; k < 3; ++k)
                for (double x : in.uvs[3 * t + k]) std::snprintf(buf, sizeof buf, " %.17g", x), s += buf;
            s += "\n";
        } else {
            const unsigned char three = 3, six = 6;
            put(&three, 1);
            for (int v : in.triangles[t]) put(&v, 4);
            put(&six, 1);
            for (int k = 0; k < 3; ++k)
                for (double x : in.uvs[3 * t + k]) put(&x, 8);
        }
    }
    return s;
}

TEST(Ply, MapsReadBackExactly) {
    Input in = make_map(torus_layout(), 2, 3);
    for (auto& uv : in.uvs) uv[0] += 1e-7 / 3, uv[1] -= 1.0 / 3; // digits that need all 17
    for (const char* format : {"ascii", "binary_little_endian", "binary_big_endian"}) {
        const std::string ply = map_ply(in, format);
        Input out;
        const IoError e = parse_ply(ply.data(), ply.size(), out);
        ASSERT_TRUE(e.ok()) << format << ": " << e.message;
        EXPECT_EQ(out.positions, in.positions) << format;
        EXPECT_EQ(out.triangles, in.triangles) << format;
        EXPECT_EQ(out.uvs, in.uvs) << format;
    }
}

TEST(Ply, WrittenQuadMeshesReadBack) {
    const Result r = extract(make_map(cube_layout(), 3, 4));
    ASSERT_TRUE(r.ok());
    for (bool binary : {true, false}) {
        const std::string path = ::testing::TempDir() + "qex_ply_test.ply";
        ASSERT_TRUE(write_ply(path, r.mesh, binary).ok());
        QuadMesh back;
        const IoError e = read_polygon_ply(path, back);
        ASSERT_TRUE(e.ok()) << e.message;
        EXPECT_EQ(back.positions, r.mesh.positions);
        EXPECT_EQ(back.faces, r.mesh.faces);
        // The located checker accepts what was read back, as it does the OBJ.
        Input in = make_map(cube_layout(), 3, 4);
        EXPECT_TRUE(verify(in, back).valid) << (binary ? "binary" : "ascii");
        std::remove(path.c_str());
    }
}

/// Parses `text` as a map; expects a failure of `code` whose message holds `where`, and nothing read.
void expect_error(const std::string& text, IoError::Code code, const std::string& where) {
    Input out;
    const IoError e = parse_ply(text.data(), text.size(), out);
    EXPECT_EQ(e.code, code) << e.message;
    EXPECT_NE(e.message.find(where), std::string::npos) << e.message;
    EXPECT_TRUE(out.positions.empty() && out.triangles.empty() && out.uvs.empty());
}

const std::string kHeader =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
    "element face 1\nproperty list uchar int vertex_indices\nproperty list uchar float texcoord\nend_header\n";
const std::string kVertices = "0 0 0\n1 0 0\n0 1 0\n";

TEST(Ply, AValidTriangleReads) {
    const std::string text = kHeader + kVertices + "3 0 1 2 6 0 0 1 0 0 1\n";
    Input out;
    ASSERT_TRUE(parse_ply(text.data(), text.size(), out).ok());
    EXPECT_EQ(out.triangles.size(), 1u);
    EXPECT_EQ(out.uvs[1][0], 1.0);
}

TEST(Ply, MalformedFilesNameTheirPlace) {
    expect_error("plx\n", IoError::Code::PlySyntax, "header line 1");
    expect_error("ply\nformat ascii 2.0\nend_header\n", IoError::Code::PlySyntax, "header line 2");
    expect_error("ply\nformat ascii 1.0\nelement vertex 3\n", IoError::Code::PlySyntax, "end_header");
    expect_error("ply\nformat ascii 1.0\nelement vertex -3\nend_header\n", IoError::Code::PlySyntax, "header line 3");
    expect_error("ply\nformat ascii 1.0\nproperty float x\nend_header\n", IoError::Code::PlySyntax,
                 "before any element");
    // A malformed value: the byte offset of the value and the element instance.
    const std::string bad = kHeader + "0 0 0\n1 x 0\n0 1 0\n3 0 1 2 6 0 0 1 0 0 1\n";
    expect_error(bad, IoError::Code::PlySyntax,
                 "byte " + std::to_string(kHeader.size() + 8) + ": element vertex 1, property y");
    // Truncated data: the element that ran out.
    expect_error(kHeader + kVertices + "3 0 1 2 6 0 0 1", IoError::Code::PlySyntax,
                 "element face 0, property texcoord");
    // A count the file cannot hold is refused before anything is allocated for it.
    std::string huge = kHeader;
    huge.replace(huge.find("face 1"), 6, "face 2000000000");
    expect_error(huge + kVertices, IoError::Code::PlySyntax, "cannot fit");
    expect_error(kHeader + kVertices + "3 0 1 7 6 0 0 1 0 0 1\n", IoError::Code::IndexOutOfRange, "face 0");
    expect_error(kHeader + kVertices + "3 0 1 2 4 0 0 1 0\n", IoError::Code::MissingUv, "expected 6");
    expect_error(kHeader + kVertices + "3 0 1 2 6 0 0 1 0 0 1\n5\n", IoError::Code::PlySyntax,
                 "after the last element");
    std::string quad = kHeader;
    quad.replace(quad.find("vertex 3"), 8, "vertex 4");
    expect_error(quad + kVertices + "1 1 0\n4 0 1 3 2 8 0 0 1 0 1 1 0 1\n", IoError::Code::NonTriangle, "face 0");
    std::string no_uv = kHeader;
    no_uv.erase(no_uv.find("property list uchar float texcoord\n"), 35);
    expect_error(no_uv + kVertices + "3 0 1 2\n", IoError::Code::MissingUv, "no UVs");
}

TEST(Ply, WriterLeavesNoPartialFile) {
    QuadMesh mesh;
    mesh.positions = {{0, 0, 0}};
    const std::string path = ::testing::TempDir() + "no_such_dir/qex.ply";
    EXPECT_EQ(write_ply(path, mesh).code, IoError::Code::CannotWrite);
    EXPECT_EQ(std::fopen((path + ".tmp").c_str(), "rb"), nullptr);
}

} // namespace
} // namespace qex::testing

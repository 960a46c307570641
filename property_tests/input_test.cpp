// Bad input: every problem gets its own error code and names its place; nothing crashes.
#include "result_checks.h"
#include "test_support.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <set>
#include <string>

namespace qex::testing {
namespace {

Input small_map() { return make_map(torus_layout(), 1, 2); }

ErrorCode extract_error(const Input& in) {
    const Result r = extract(in);
    EXPECT_EQ(validate(in).code, r.error.code);
    return r.error.code;
}

TEST(BadInput, EmptyMesh) { EXPECT_EQ(extract_error(Input{}), ErrorCode::EmptyMesh); }

TEST(BadInput, IndexOutOfRange) {
    Input in = small_map();
    in.triangles[3][1] = static_cast<int>(in.positions.size());
    const Result r = extract(in);
    EXPECT_EQ(r.error.code, ErrorCode::IndexOutOfRange);
    EXPECT_EQ(r.error.element, 3);
    EXPECT_NE(r.error.message.find("triangle 3"), std::string::npos);
}

TEST(BadInput, UvCountMismatch) {
    Input in = small_map();
    in.uvs.pop_back();
    EXPECT_EQ(extract_error(in), ErrorCode::UvCountMismatch);
}

TEST(BadInput, NonFinite) {
    Input in = small_map();
    in.uvs[10][1] = std::numeric_limits<double>::quiet_NaN();
    EXPECT_EQ(extract_error(in), ErrorCode::NonFiniteValue);
    in = small_map();
    in.positions[2][0] = std::numeric_limits<double>::infinity();
    const Result r = extract(in);
    EXPECT_EQ(r.error.code, ErrorCode::NonFiniteValue);
    EXPECT_EQ(r.error.element, 2);
}

TEST(BadInput, CoordinateBeyond2To52) {
    Input in = small_map();
    in.uvs[0][0] = 9007199254740992.0; // 2^53
    EXPECT_EQ(extract_error(in), ErrorCode::CoordinateTooLarge);
}

TEST(BadInput, DegenerateTriangleAndIsolatedVertex) {
    Input in = small_map();
    in.triangles[0][2] = in.triangles[0][0];
    EXPECT_EQ(extract_error(in), ErrorCode::DegenerateTriangle);
    in = small_map();
    in.positions.push_back({0, 0, 0});
    const Result r = extract(in);
    EXPECT_EQ(r.error.code, ErrorCode::IsolatedVertex);
    EXPECT_EQ(r.error.element, static_cast<std::int64_t>(in.positions.size()) - 1);
}

TEST(BadInput, NonManifoldAndMisoriented) {
    Input in = small_map();
    std::swap(in.triangles[4][0], in.triangles[4][1]); // one triangle reversed
    EXPECT_EQ(extract_error(in), ErrorCode::InconsistentOrientation);
    in = small_map();
    in.triangles.push_back(in.triangles[0]); // a third triangle on three edges (same direction)
    in.uvs.insert(in.uvs.end(), {in.uvs[0], in.uvs[1], in.uvs[2]});
    const ErrorCode c = extract_error(in);
    EXPECT_TRUE(c == ErrorCode::InconsistentOrientation || c == ErrorCode::NonManifoldEdge) << to_string(c);
    // Two disks sharing one vertex: a non-manifold vertex.
    Input a = make_map(disk_layout(1), 1, 1);
    Input b = a;
    const int offset = static_cast<int>(a.positions.size());
    for (auto& p : b.positions) p[2] += 5;
    a.positions.insert(a.positions.end(), b.positions.begin(), b.positions.end());
    for (auto t : b.triangles) {
        for (int& v : t) v = v == 0 ? 0 : v + offset; // glue vertex 0
        a.triangles.push_back(t);
    }
    a.uvs.insert(a.uvs.end(), b.uvs.begin(), b.uvs.end());
    a.positions.erase(a.positions.begin() + offset); // b's own vertex 0 is unused now
    for (auto& t : a.triangles)
        for (int& v : t)
            if (v > offset) --v;
    EXPECT_EQ(extract_error(a), ErrorCode::NonManifoldVertex);
}

TEST(BadInput, ValencesAndFeatures) {
    Input in = small_map();
    in.valences = {4, 4};
    EXPECT_EQ(extract_error(in), ErrorCode::ValenceCountMismatch);
    in = small_map();
    in.feature_edges.push_back({0, static_cast<int>(in.positions.size())});
    EXPECT_EQ(extract_error(in), ErrorCode::BadFeatureEdge);
}

// A seam whose two UV copies no grid transition relates (one triangle's chart moved off the grid
// by a fraction of a cell) is an input error naming the seam; solver noise and integer moves are
// not.
TEST(BadInput, SeamNoTransitionExplains) {
    std::mt19937 rng(5);
    Input base = make_map(cube_layout(), 2, 3);
    rechart(base, rng); // every edge a seam
    auto moved = [&](double dx) {
        Input in = base;
        for (int c = 0; c < 3; ++c) in.uvs[c][0] += dx;
        return in;
    };
    for (const double dx : {0.3, -0.02, 0.5}) {
        const Result r = extract(moved(dx));
        ASSERT_EQ(r.error.code, ErrorCode::InconsistentMap) << dx;
        EXPECT_NE(r.error.message.find("seam edge between input vertices"), std::string::npos) << r.error.message;
        // The seam named is one of triangle 0's edges.
        const auto t = static_cast<std::int64_t>(r.error.element);
        ASSERT_GE(t, 0);
        ASSERT_LT(t, static_cast<std::int64_t>(base.triangles.size()));
        int shared = 0;
        for (const int a : base.triangles[static_cast<std::size_t>(t)])
            for (const int b : base.triangles[0]) shared += a == b;
        EXPECT_GE(shared, 2) << r.error.message;
    }
    const std::int64_t quads = expected_quads(cube_layout(), 2);
    for (const double dx : {1e-6, 1.0, -3.0}) {
        const Result r = extract(moved(dx));
        ASSERT_TRUE(r.ok()) << dx << ": " << r.error.message;
        EXPECT_TRUE(r.check.valid) << dx;
        EXPECT_EQ(static_cast<std::int64_t>(r.mesh.faces.size()), quads) << dx;
    }
}

TEST(BadInput, AbsurdlyLargeMap) {
    Input in = small_map();
    for (auto& uv : in.uvs) uv = {uv[0] * 1e6, uv[1] * 1e6};
    Options opt;
    opt.max_qvertices = 1000;
    EXPECT_EQ(extract(in, opt).error.code, ErrorCode::MapTooLarge);
}

// --- OBJ ------------------------------------------------------------------------------------------

IoError parse(const std::string& text, Input& in) { return parse_obj(text.data(), text.size(), in); }

TEST(Obj, ParsesCornerUvsAndRelativeIndices) {
    Input in;
    const IoError e = parse("# c\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf -3/-3 -2/-2 -1/-1\n", in);
    ASSERT_TRUE(e.ok()) << e.message;
    ASSERT_EQ(in.triangles.size(), 1u);
    EXPECT_EQ(in.uvs[1], (std::array<double, 2>{1, 0}));
}

TEST(Obj, ErrorsNameTheLine) {
    struct Bad {
        const char* text;
        IoError::Code code;
        std::int64_t line;
    };
    const Bad cases[] = {
        {"v 0 0 0\nv 1 0\n", IoError::Code::Syntax, 2},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", IoError::Code::MissingUv, 4},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/2\n", IoError::Code::IndexOutOfRange, 5},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nf 1/1 2/1 3/1 4/1\n", IoError::Code::NonTriangle, 6},
        {"v nan 0 0\n", IoError::Code::NonFinite, 1},
        {"vt 0 inf\n", IoError::Code::NonFinite, 1},
        {"v 0 0 0\nbogus 1\n", IoError::Code::Syntax, 2},
        {"v 0 0 0 \nvt 0.5\n", IoError::Code::Syntax, 2},
        {"v 1 2 3\nv 1 2 3\nv 1 2 3\nvt 0 0\nf 1/1 2/1\n", IoError::Code::NonTriangle, 5},
        {"v 1e999 0 0\n", IoError::Code::NonFinite, 1},
    };
    for (const Bad& b : cases) {
        Input in;
        const IoError e = parse(b.text, in);
        EXPECT_EQ(e.code, b.code) << b.text;
        EXPECT_EQ(e.line, b.line) << b.text;
        EXPECT_NE(e.message.find("line " + std::to_string(b.line)), std::string::npos) << e.message;
    }
}

/// What became of one truncation of an OBJ text: a parse error, an extraction error, an
/// extracted mesh the checker rejects (with the defects reported), or a valid one.
enum class Outcome { ParseError, ExtractionError, Invalid, Valid };

/// Asserts what must hold for `text`: a parse error has a message, a line of the text and leaves
/// nothing read; parsed data has consistent sizes and indices; an extraction error has a code
/// and a message; an extracted mesh comes with a consistent result (result_checks.h).
Outcome truncation_outcome(const std::string& text) {
    Input in;
    const IoError e = parse(text, in);
    if (!e.ok()) {
        const auto lines = std::count(text.begin(), text.end(), '\n') + (!text.empty() && text.back() != '\n');
        EXPECT_FALSE(e.message.empty()) << text;
        EXPECT_GE(e.line, 1) << text;
        EXPECT_LE(e.line, lines) << text;
        EXPECT_TRUE(in.positions.empty() && in.triangles.empty() && in.uvs.empty()) << text;
        return Outcome::ParseError;
    }
    EXPECT_EQ(in.uvs.size(), 3 * in.triangles.size()) << text;
    for (const auto& t : in.triangles)
        for (int v : t) EXPECT_TRUE(v >= 0 && v < static_cast<int>(in.positions.size())) << text;
    Options at_own_scale; // refinement would turn the half cell of one triangle into a valid quad
    at_own_scale.max_refinement = 1;
    const Result r = extract(in, at_own_scale);
    if (!r.ok()) {
        EXPECT_FALSE(r.error.message.empty()) << text;
        return Outcome::ExtractionError;
    }
    EXPECT_EQ(result_inconsistency(in, r), "") << text;
    if (r.check.valid) return Outcome::Valid;
    EXPECT_FALSE(r.report.defects.empty()) << text;
    return Outcome::Invalid;
}

TEST(Obj, TruncatedFilesNeverCrash) {
    // A unit square of two triangles, the second one's vertex after the first one's face; cut
    // after any byte. The first triangle alone extracts to an empty mesh (its cell is cut by the
    // diagonal boundary), which the report explains.
    const std::string good =
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nf 1/1 2/2 3/3\n"
        "v 0 1 0\nvt 0 1\nf 1/1 3/3 4/4\n";
    std::set<Outcome> seen;
    for (std::size_t n = 0; n <= good.size(); ++n) seen.insert(truncation_outcome(good.substr(0, n)));
    // Every outcome occurs, and the whole text gives the one quad.
    EXPECT_EQ(seen.size(), 4u);
    Input in;
    ASSERT_TRUE(parse(good, in).ok());
    const Result r = extract_valid(in);
    EXPECT_EQ(r.mesh.faces.size(), 1u);
}

TEST(Obj, FilesAreReadInChunksLikeOneBuffer) {
    // read_obj streams 4 MiB chunks cut at line ends; a file of several chunks must read exactly
    // as parse_obj reads the whole text, and a bad line past the first chunk keeps its number.
    Input big = subdivide(subdivide(make_map(torus_layout(8, 6), 2, 8)));
    std::string text = to_obj(big);
    ASSERT_GT(text.size(), std::size_t{9} << 20); // three chunks at least
    const std::string path = ::testing::TempDir() + "qex_chunks.obj";
    auto write = [&](const std::string& t) {
        std::FILE* f = std::fopen(path.c_str(), "wb");
        ASSERT_NE(f, nullptr);
        std::fwrite(t.data(), 1, t.size(), f);
        std::fclose(f);
    };
    write(text);
    Input from_file, from_text;
    ASSERT_TRUE(read_obj(path, from_file).ok());
    ASSERT_TRUE(parse_obj(text.data(), text.size(), from_text).ok());
    EXPECT_EQ(from_file.positions, from_text.positions);
    EXPECT_EQ(from_file.triangles, from_text.triangles);
    EXPECT_EQ(from_file.uvs, from_text.uvs);
    EXPECT_EQ(from_file.uvs, big.uvs);
    // A malformed record in the last chunk, and a file without a final line end.
    const std::size_t at = text.rfind("\nf ");
    ASSERT_NE(at, std::string::npos);
    std::string broken = text.substr(0, at + 1) + "f 1/1 2/x 3/3\n" + text.substr(at + 1);
    broken.pop_back();
    write(broken);
    Input a, b;
    const IoError ef = read_obj(path, a), et = parse_obj(broken.data(), broken.size(), b);
    EXPECT_FALSE(ef.ok());
    EXPECT_EQ(ef.line, et.line);
    EXPECT_EQ(ef.message, et.message);
    EXPECT_EQ(ef.line, static_cast<std::int64_t>(std::count(broken.begin(), broken.begin() + at + 1, '\n')) + 1);
    EXPECT_TRUE(a.triangles.empty());
    // A comment line longer than a chunk: no line end among a whole chunk's bytes.
    const std::size_t mid = text.find("\nvt ");
    ASSERT_NE(mid, std::string::npos);
    const std::string long_line =
        text.substr(0, mid + 1) + "# " + std::string(std::size_t{5} << 20, 'x') + "\n" + text.substr(mid + 1);
    write(long_line);
    Input c;
    ASSERT_TRUE(read_obj(path, c).ok());
    EXPECT_EQ(c.positions, from_text.positions);
    EXPECT_EQ(c.triangles, from_text.triangles);
    EXPECT_EQ(c.uvs, from_text.uvs);
    std::remove(path.c_str());
}

TEST(Obj, PiecesParsedInParallelReadLikeASerialRead) {
    // Large texts are cut into pieces at line ends, parsed in parallel and committed in order.
    // Relative indices resolve across pieces, and the first problem in file order is reported
    // with its line, whatever the thread count. Here v, vt and f records interleave, and every
    // face refers to the records just before it by negative indices.
    const Input base = subdivide(make_map(torus_layout(10, 8), 2, 8));
    std::string text;
    char line[160];
    for (std::size_t f = 0; f < base.triangles.size(); ++f) {
        for (int k = 0; k < 3; ++k) {
            const auto& p = base.positions[static_cast<std::size_t>(base.triangles[f][k])];
            std::snprintf(line, sizeof line, "v %.17g %.17g %.17g\nvt %.17g %.17g\n", p[0], p[1], p[2],
                          base.uvs[3 * f + k][0], base.uvs[3 * f + k][1]);
            text += line;
        }
        text += f % 7 == 0 ? "# a comment\nf -3/-3 -2/-2 -1/-1\n" : "f -3/-3 -2/-2 -1/-1\n";
    }
    ASSERT_GT(text.size(), std::size_t{8} << 20); // read in parallel from 8 MiB, in pieces of at least 256 KiB
    Input serial;
    ASSERT_TRUE(parse_obj(text.data(), text.size(), serial, 1).ok());
    ASSERT_EQ(serial.triangles.size(), base.triangles.size());
    EXPECT_EQ(serial.uvs, base.uvs);
    for (int threads : {2, 3, 8}) {
        Input in;
        ASSERT_TRUE(parse_obj(text.data(), text.size(), in, threads).ok());
        EXPECT_EQ(in.positions, serial.positions);
        EXPECT_EQ(in.triangles, serial.triangles);
        EXPECT_EQ(in.uvs, serial.uvs);
    }
    // Problems at several places; each text has two, and the earlier one must be reported.
    auto insert_at = [&](std::string t, double where, const std::string& record) {
        const std::size_t at = t.find('\n', static_cast<std::size_t>(where * static_cast<double>(t.size())));
        return t.insert(at + 1, record);
    };
    const std::vector<std::string> broken = {
        insert_at(insert_at(text, 0.7, "f 1/1 2/x 3/3\n"), 0.2, "f -3/-3 -2/-2 -100000000/-1\n"),
        insert_at(insert_at(text, 0.7, "vt 1 nan\n"), 0.45, "f 1/1 2/2 99999999/3\n"),
        insert_at(insert_at(text, 0.9, "f 1/1 2/2\n"), 0.55, "v 1 2\n"),
        insert_at(text, 0.999, "f 1/1 2/2 3/3 4/4\n"),
    };
    for (const std::string& t : broken) {
        Input in;
        const IoError e1 = parse_obj(t.data(), t.size(), in, 1);
        ASSERT_FALSE(e1.ok());
        EXPECT_TRUE(in.triangles.empty() && in.positions.empty() && in.uvs.empty());
        for (int threads : {2, 3, 8}) {
            const IoError e = parse_obj(t.data(), t.size(), in, threads);
            EXPECT_EQ(e.code, e1.code);
            EXPECT_EQ(e.line, e1.line);
            EXPECT_EQ(e.message, e1.message);
            EXPECT_TRUE(in.triangles.empty());
        }
    }
    // The reported lines are the earlier insertions'.
    auto line_of = [](const std::string& t, const std::string& record) {
        return static_cast<std::int64_t>(
                   std::count(t.begin(), t.begin() + static_cast<std::ptrdiff_t>(t.find(record)), '\n')) +
               1;
    };
    Input in;
    EXPECT_EQ(parse_obj(broken[0].data(), broken[0].size(), in, 2).line, line_of(broken[0], "-100000000/-1"));
    EXPECT_EQ(parse_obj(broken[1].data(), broken[1].size(), in, 2).line, line_of(broken[1], "99999999/3"));
    EXPECT_EQ(parse_obj(broken[2].data(), broken[2].size(), in, 2).line, line_of(broken[2], "v 1 2\n"));
    EXPECT_EQ(parse_obj(broken[3].data(), broken[3].size(), in, 2).code, IoError::Code::NonTriangle);
}

TEST(Vval, HeaderCountAndValues) {
    std::vector<int> val;
    const std::string ok = "{\"file_format\":\"VVAL\",\"version\":1}\n3\n4\n5\n3\n";
    ASSERT_TRUE(parse_vval(ok.data(), ok.size(), val).ok());
    EXPECT_EQ(val, (std::vector<int>{4, 5, 3}));
    const std::string short_file = "{\"file_format\":\"VVAL\",\"version\":1}\n3\n4\n";
    EXPECT_EQ(parse_vval(short_file.data(), short_file.size(), val).code, IoError::Code::VvalSyntax);
    const std::string no_header = "3\n4\n4\n4\n";
    EXPECT_EQ(parse_vval(no_header.data(), no_header.size(), val).code, IoError::Code::VvalSyntax);
}

TEST(Readers, LeaveNothingOnAProblem) {
    // io.h: on a problem every reader leaves its output empty, whatever it held or had read.
    const std::string missing = ::testing::TempDir() + "qex_no_such_file.obj";
    Input in = make_map(torus_layout(), 1, 1);
    EXPECT_EQ(read_obj(missing, in).code, IoError::Code::CannotOpen);
    EXPECT_TRUE(in.positions.empty() && in.triangles.empty() && in.uvs.empty());
    std::vector<int> val{4, 4, 4};
    EXPECT_EQ(read_vval(missing, val).code, IoError::Code::CannotOpen);
    EXPECT_TRUE(val.empty());
    const std::string late = "{\"file_format\":\"VVAL\",\"version\":1}\n3\n4\n5\nx\n"; // two read, then junk
    EXPECT_EQ(parse_vval(late.data(), late.size(), val).line, 5);
    EXPECT_TRUE(val.empty());
    QuadMesh mesh;
    mesh.faces = {{0, 1, 2, 3}};
    EXPECT_EQ(read_polygon_obj(missing, mesh).code, IoError::Code::CannotOpen);
    EXPECT_TRUE(mesh.faces.empty());
    const std::string path = ::testing::TempDir() + "qex_polygon_late_error.obj";
    std::FILE* f = std::fopen(path.c_str(), "wb");
    ASSERT_NE(f, nullptr);
    std::fputs("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\nf 1 2 9\n", f);
    std::fclose(f);
    const IoError e = read_polygon_obj(path, mesh);
    EXPECT_EQ(e.code, IoError::Code::IndexOutOfRange);
    EXPECT_EQ(e.line, 6);
    EXPECT_NE(e.message.find("vertex index 9"), std::string::npos) << e.message;
    EXPECT_TRUE(mesh.positions.empty() && mesh.faces.empty());
    std::remove(path.c_str());
}

} // namespace
} // namespace qex::testing

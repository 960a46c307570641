// Numbers at the edges, where a file's number becomes an integer: the one checked conversion
// (src/io/checked_int.h) at 2^31 +- 1, 2^53 + 1, 2^63, 1e308, -0, NaN, infinities, 1e96 and
// fractions; and every reader given them: a clean refusal naming the place, or (for -0 and the
// largest values that fit) the same reading as the plain number.
#include "test_support.h"

#include "io/checked_int.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

namespace qex::testing {
namespace {

using io_detail::checked_int;
using io_detail::clamped_int;

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
constexpr std::int64_t k2To31 = std::int64_t{1} << 31;
constexpr std::int64_t k2To53 = std::int64_t{1} << 53;

/// checked_int's verdict on `x` as a T, and the integer when it converts.
template <class T, class From>
std::pair<bool, T> as(From x) {
    T out = 7; // untouched on a refusal
    const bool ok = checked_int(x, out);
    if (!ok) { EXPECT_EQ(out, T{7}); }
    return {ok, out};
}

TEST(CheckedInt, Int32EdgesFromDoubles) {
    EXPECT_EQ(as<std::int32_t>(double(k2To31 - 1)), std::make_pair(true, INT32_MAX));
    EXPECT_FALSE(as<std::int32_t>(double(k2To31)).first);
    EXPECT_FALSE(as<std::int32_t>(double(k2To31 + 1)).first);
    EXPECT_EQ(as<std::int32_t>(-double(k2To31)), std::make_pair(true, INT32_MIN));
    EXPECT_FALSE(as<std::int32_t>(-double(k2To31) - 1).first);
    EXPECT_FALSE(as<std::int32_t>(2147483647.5).first);
    EXPECT_FALSE(as<std::int32_t>(-2147483648.5).first);
}

TEST(CheckedInt, Int32EdgesFromIntegers) {
    EXPECT_EQ(as<std::int32_t>(k2To31 - 1), std::make_pair(true, INT32_MAX));
    EXPECT_FALSE(as<std::int32_t>(k2To31).first);
    EXPECT_FALSE(as<std::int32_t>(k2To31 + 1).first);
    EXPECT_EQ(as<std::int32_t>(-k2To31), std::make_pair(true, INT32_MIN));
    EXPECT_FALSE(as<std::int32_t>(-k2To31 - 1).first);
    EXPECT_EQ(as<std::uint32_t>(k2To31 + 1), std::make_pair(true, std::uint32_t(k2To31 + 1)));
    EXPECT_FALSE(as<std::uint32_t>(std::int64_t{-1}).first);
    EXPECT_FALSE(as<std::int32_t>(std::uint64_t{1} << 63).first);
    EXPECT_FALSE(as<std::int64_t>(std::uint64_t{1} << 63).first);
    EXPECT_EQ(as<std::int64_t>(INT64_MIN), std::make_pair(true, INT64_MIN));
    EXPECT_FALSE(as<std::uint64_t>(INT64_MIN).first);
    EXPECT_EQ(as<std::size_t>(std::int64_t{0}), std::make_pair(true, std::size_t{0}));
}

TEST(CheckedInt, TwoTo53PlusOne) {
    // As an integer, exact; as a double it was rounded to 2^53 when parsed, and is taken as such.
    EXPECT_EQ(as<std::int64_t>(k2To53 + 1), std::make_pair(true, k2To53 + 1));
    EXPECT_FALSE(as<std::int32_t>(k2To53 + 1).first);
    EXPECT_EQ(as<std::int64_t>(double(k2To53 + 1)), std::make_pair(true, k2To53));
    EXPECT_EQ(as<std::int64_t>(9007199254740993.0), std::make_pair(true, k2To53));
    EXPECT_FALSE(as<std::int32_t>(9007199254740993.0).first);
}

TEST(CheckedInt, TwoTo63AndBeyond) {
    const double two63 = std::ldexp(1.0, 63);
    EXPECT_FALSE(as<std::int64_t>(two63).first); // (double)INT64_MAX is 2^63: out of range
    EXPECT_FALSE(as<std::int64_t>(double(INT64_MAX)).first);
    EXPECT_EQ(as<std::int64_t>(-two63), std::make_pair(true, INT64_MIN));
    EXPECT_FALSE(as<std::int64_t>(std::nextafter(-two63, -kInf)).first);
    EXPECT_EQ(as<std::int64_t>(std::nextafter(two63, 0.0)).second, std::int64_t{0x7ffffffffffffc00});
    EXPECT_EQ(as<std::uint64_t>(two63), std::make_pair(true, std::uint64_t{1} << 63));
    EXPECT_FALSE(as<std::uint64_t>(std::ldexp(1.0, 64)).first);
    EXPECT_FALSE(as<std::int64_t>(std::ldexp(1.0f, 63)).first); // a float's 2^63 too
    EXPECT_FALSE(as<std::int32_t>(1e308).first);
    EXPECT_FALSE(as<std::int64_t>(1e308).first);
    EXPECT_FALSE(as<std::int64_t>(-1e308).first);
    EXPECT_FALSE(as<std::int64_t>(std::numeric_limits<double>::max()).first);
    EXPECT_FALSE(as<std::int64_t>(6.666666666666666e95).first); // the fuzz finding's index
    EXPECT_FALSE(as<std::uint32_t>(1e96).first);
}

TEST(CheckedInt, SignedZeroNanInfinitiesAndFractions) {
    EXPECT_EQ(as<std::int32_t>(-0.0), std::make_pair(true, 0));
    EXPECT_EQ(as<std::uint32_t>(-0.0), std::make_pair(true, 0u));
    EXPECT_EQ(as<std::uint8_t>(-0.0f), std::make_pair(true, std::uint8_t{0}));
    for (double bad : {kNan, -kNan, kInf, -kInf, 0.5, -0.5, 1.5, 2.5, -1e-300, 5e-324, 4503599627370495.5})
        EXPECT_FALSE(as<std::int64_t>(bad).first) << bad;
    EXPECT_FALSE(as<std::int32_t>(std::numeric_limits<float>::quiet_NaN()).first);
    EXPECT_FALSE(as<std::int32_t>(std::numeric_limits<long double>::infinity()).first);
    EXPECT_EQ(as<std::int8_t>(-128.0), std::make_pair(true, std::int8_t{-128}));
    EXPECT_FALSE(as<std::int8_t>(128.0).first);
    EXPECT_EQ(as<std::uint8_t>(255.0), std::make_pair(true, std::uint8_t{255}));
    EXPECT_FALSE(as<std::uint8_t>(256.0).first);
    EXPECT_FALSE(as<std::uint8_t>(-1.0).first);
}

TEST(CheckedInt, ClampedAndNamed) {
    EXPECT_EQ(clamped_int<std::int64_t>(1e308), INT64_MAX);
    EXPECT_EQ(clamped_int<std::int64_t>(-kInf), INT64_MIN);
    EXPECT_EQ(clamped_int<std::int64_t>(kNan), 0);
    EXPECT_EQ(clamped_int<int>(-2.75), -2);
    EXPECT_EQ(clamped_int<int>(std::int64_t{1} << 40), INT32_MAX);
    EXPECT_EQ(clamped_int<std::int64_t>(std::floor(-3.5)), -4);
    const double finding = 6.666666666666666e95;
    EXPECT_EQ(std::strtod(io_detail::number_text(finding).c_str(), nullptr), finding); // 17 digits name it
    EXPECT_NE(io_detail::number_text(finding).find("e+95"), std::string::npos);
    EXPECT_EQ(io_detail::number_text(4294967296.0), "4294967296");
    EXPECT_EQ(io_detail::number_text(kNan).find("nan") != std::string::npos, true);
}

// === the readers

/// A PLY map of one triangle whose face list is `face` (ASCII), its index list of `index_type`.
std::string ply_triangle(const std::string& face, const std::string& index_type = "int",
                         const std::string& count_type = "uchar") {
    return "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
           "property float s\nproperty float t\nelement face 1\nproperty list " +
           count_type + " " + index_type + " vertex_indices\nend_header\n0 0 0 0 0\n1 0 0 1 0\n0 1 0 0 1\n" + face +
           "\n";
}

/// Parses `text` as a PLY map; expects a refusal whose message holds `what` and the face's place.
void expect_ply_refusal(const std::string& text, const std::string& what) {
    Input in;
    const IoError e = parse_ply(text.data(), text.size(), in);
    EXPECT_FALSE(e.ok()) << text;
    EXPECT_NE(e.message.find("element face 0, property vertex_indices"), std::string::npos) << e.message;
    EXPECT_NE(e.message.find(what), std::string::npos) << e.message;
    EXPECT_GT(e.offset, 0) << e.message;
    EXPECT_TRUE(in.positions.empty() && in.triangles.empty() && in.uvs.empty());
}

TEST(PlyHostileNumbers, IndicesAreRefusedWithTheirPlace) {
    const std::string digits96(95, '6');
    expect_ply_refusal(ply_triangle("3 0 1 " + digits96 + "4", "uint"),
                       "vertex index 6.666666666666667e+95 out of range");
    expect_ply_refusal(ply_triangle("3 0 1 " + digits96 + "4", "float"),
                       "vertex index 6.666666666666667e+95 out of range");
    expect_ply_refusal(ply_triangle("3 0 1 2147483648", "uint"), "vertex index 2147483648 out of range");
    expect_ply_refusal(ply_triangle("3 0 1 2147483648"), "vertex index 2147483648 out of range");
    expect_ply_refusal(ply_triangle("3 0 1 4294967296", "uint"), "vertex index 4294967296 out of range");
    expect_ply_refusal(ply_triangle("3 0 1 9007199254740993", "double"), "vertex index 9007199254740992 out of");
    expect_ply_refusal(ply_triangle("3 0 1 -1"), "vertex index -1 out of range");
    expect_ply_refusal(ply_triangle("3 0 1 1e308", "double"), "e+308 out of range");
    expect_ply_refusal(ply_triangle("3 0 1 1.5", "float"), "vertex index 1.5 is not an integer");
    expect_ply_refusal(ply_triangle("3 0 1 1.5"), "vertex index 1.5 is not an integer");
    for (const char* spelling : {"nan", "NaN", "-nan", "inf", "-inf", "Infinity", "+inf"})
        for (const char* type : {"float", "int", "uchar"})
            expect_ply_refusal(ply_triangle(std::string("3 0 1 ") + spelling, type), "vertex index");
}

TEST(PlyHostileNumbers, ValuesOfIntegerTypesMustFitThem) {
    // A texcoord list (or any value) of an integer type holds integers of that type.
    const std::string head =
        "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
        "property float z\nproperty uchar s\nproperty float t\nelement face 0\n"
        "property list uchar int vertex_indices\nend_header\n";
    for (const char* s : {"256", "-1", "0.5", "inf", "nan", "1e96"}) {
        const std::string text = head + "0 0 0 " + s + " 0\n";
        Input in;
        const IoError e = parse_ply(text.data(), text.size(), in);
        EXPECT_NE(e.message.find("element vertex 0, property s: value"), std::string::npos) << e.message;
        EXPECT_NE(e.message.find("does not fit its type uint8"), std::string::npos) << e.message;
    }
}

TEST(PlyHostileNumbers, ListCountsAreRefusedWithTheirPlace) {
    for (const char* count : {"inf", "nan", "1e96", "3.5", "256", "-1"})
        expect_ply_refusal(ply_triangle(std::string(count) + " 0 1 2"), "list count");
    expect_ply_refusal(ply_triangle("-1 0 1 2", "int", "char"), "list count -1 out of range");
    expect_ply_refusal(ply_triangle("4294967295 0 1 2", "int", "uint"), "a list of 4294967295 values runs past");
}

TEST(PlyHostileNumbers, NegativeZeroAndTheLargestIndicesRead) {
    Input in;
    const std::string zero = ply_triangle("3 -0 1 2");
    ASSERT_TRUE(parse_ply(zero.data(), zero.size(), in).ok());
    EXPECT_EQ(in.triangles[0], (std::array<int, 3>{0, 1, 2}));
    // 2^31 - 1 converts, and is then out of range of the three vertices, as any index.
    const std::string big = ply_triangle("3 0 1 2147483647", "uint");
    const IoError e = parse_ply(big.data(), big.size(), in);
    EXPECT_EQ(e.code, IoError::Code::IndexOutOfRange) << e.message;
    EXPECT_NE(e.message.find("vertex index 2147483647 out of range (3 vertices)"), std::string::npos) << e.message;
}

TEST(PlyHostileNumbers, BinaryFloatIndicesAreChecked) {
    const std::string head =
        "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty double x\n"
        "property double y\nproperty double z\nproperty double s\nproperty double t\n"
        "element face 1\nproperty list uchar double vertex_indices\nend_header\n";
    for (double bad : {6.666666666666666e95, kNan, -kInf, 0.5, double(k2To31), -1.0}) {
        std::string text = head;
        const double vertices[15] = {0, 0, 0, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
        text.append(reinterpret_cast<const char*>(vertices), sizeof vertices); // little-endian hosts
        text += '\3';
        for (double x : {0.0, 1.0, bad}) text.append(reinterpret_cast<const char*>(&x), 8);
        expect_ply_refusal(text, "vertex index");
    }
}

TEST(PlyHostileNumbers, TheFuzzFindingIsRefused) {
    const std::string path = QEX_CORPUS_DIR "/fuzz_ply/regressions/ff5b116df7be31e6.ply";
    Input in;
    const IoError e = read_ply(path, in);
    EXPECT_EQ(e.code, IoError::Code::PlySyntax) << e.message;
    EXPECT_NE(e.message.find("element face 0, property vertex_index: vertex index 6.666666666666667e+95 out of range"),
              std::string::npos)
        << e.message;
    EXPECT_TRUE(in.positions.empty() && in.triangles.empty());
}

/// Parses `text` as an OBJ map; expects a refusal (of kind `code`, unless None) on line `line`
/// whose message holds `what`.
void expect_obj_refusal(const std::string& text, IoError::Code code, std::int64_t line, const std::string& what = "") {
    Input in;
    const IoError e = parse_obj(text.data(), text.size(), in);
    EXPECT_FALSE(e.ok()) << text;
    if (code != IoError::Code::None) { EXPECT_EQ(e.code, code) << text << ": " << e.message; }
    EXPECT_EQ(e.line, line) << e.message;
    EXPECT_NE(e.message.find("line " + std::to_string(line) + ": " + what), std::string::npos) << e.message;
    EXPECT_TRUE(in.positions.empty() && in.triangles.empty() && in.uvs.empty());
}

TEST(ObjHostileNumbers, IndicesAreRefusedWithTheirLine) {
    const std::string v = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\n";
    using C = IoError::Code;
    expect_obj_refusal(v + "f 1/1 2/1 2147483648/1\n", C::IndexOutOfRange, 5, "vertex index 2147483648 out of");
    expect_obj_refusal(v + "f 1/1 2/1 2147483647/1\n", C::IndexOutOfRange, 5, "vertex index 2147483647 out of");
    expect_obj_refusal(v + "f 1/1 2/1 -2147483648/1\n", C::IndexOutOfRange, 5, "vertex index -2147483648 out of");
    expect_obj_refusal(v + "f 1/1 2/1 3/4294967297\n", C::IndexOutOfRange, 5, "texture index 4294967297 out of");
    // Past what read_int() takes (2^40): out of range too, the number named (shortened if long).
    expect_obj_refusal(v + "f 1/1 2/1 9007199254740993/1\n", C::IndexOutOfRange, 5,
                       "vertex index 9007199254740993 out of range");
    expect_obj_refusal(v + "f 1/1 2/1 " + std::string(96, '6') + "/1\n", C::IndexOutOfRange, 5,
                       "vertex index 66666666666666666666... (96 digits) out of range");
    expect_obj_refusal(v + "f 1/1 2/1 -9223372036854775808/1\n", C::IndexOutOfRange, 5,
                       "vertex index -9223372036854775808 out of range");
    expect_obj_refusal(v + "f 1/1 2/1 3/+" + std::string(30, '1') + "\n", C::IndexOutOfRange, 5, "texture index +111");
    for (const char* bad : {"1.5/1", "1e2/1", "nan/1", "inf/1", "3/1.0"})
        expect_obj_refusal(v + "f 1/1 2/1 " + bad + "\n", C::None, 5); // malformed or without its vt
    Input in;
    const std::string zero = v + "f 1/1 2/-0 3/1\n"; // -0 is no index at all
    EXPECT_EQ(parse_obj(zero.data(), zero.size(), in).code, C::IndexOutOfRange);
}

TEST(ObjHostileNumbers, PolygonObjIndicesAreRefusedWithTheirLine) {
    for (const std::string& index : {std::string("2147483648"), std::string("-2147483649"), std::string(96, '9'),
                                     std::string("-9223372036854775808"), std::string("1.5"), std::string("2e0")}) {
        const std::string path = ::testing::TempDir() + "qex_hostile_polygon.obj";
        std::FILE* f = std::fopen(path.c_str(), "wb");
        ASSERT_NE(f, nullptr);
        std::fputs(("v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 " + index + "\n").c_str(), f);
        std::fclose(f);
        QuadMesh mesh;
        const IoError e = read_polygon_obj(path, mesh);
        const bool fraction = index.find_first_of(".e") != std::string::npos;
        EXPECT_EQ(e.code, fraction ? IoError::Code::Syntax : IoError::Code::IndexOutOfRange) << e.message;
        EXPECT_EQ(e.line, 4) << index << ": " << e.message;
        EXPECT_TRUE(mesh.faces.empty());
        std::remove(path.c_str());
    }
}

TEST(VvalHostileNumbers, CountsAndValencesAreRefusedWithTheirLine) {
    const std::string head = "{\"file_format\":\"VVAL\",\"version\":1}\n";
    const std::pair<std::string, std::string> cases[] = {
        {"2\n4\n2147483649\n", "line 4: implausible valence 2147483649"},
        {"2\n4\n4294967300\n", "line 4: implausible valence 4294967300"},
        {"2\n4\n" + std::string(96, '6') + "\n", "line 4: implausible valence 66666666666666666666... (96 digits)"},
        {"2\n4\n4.0\n", "line 4: trailing characters"},
        {"2\n4\nnan\n", "line 4: expected an integer"},
        {"2\n4\ninf\n", "line 4: expected an integer"},
        {"2\n4\n-1\n", "line 4: implausible valence -1"},
        {"9007199254740993\n4\n4\n", "line 2: implausible vertex count 9007199254740993"},
        {"-9223372036854775808\n", "line 2: implausible vertex count -9223372036854775808"},
    };
    for (const auto& [body, message] : cases) {
        const std::string text = head + body;
        std::vector<int> val;
        const IoError e = parse_vval(text.data(), text.size(), val);
        EXPECT_EQ(e.code, IoError::Code::VvalSyntax) << body;
        EXPECT_NE(e.message.find(message), std::string::npos) << e.message;
        EXPECT_TRUE(val.empty());
    }
    const std::string zero = head + "1\n-0\n";
    std::vector<int> val;
    ASSERT_TRUE(parse_vval(zero.data(), zero.size(), val).ok());
    EXPECT_EQ(val, std::vector<int>{0});
}

} // namespace
} // namespace qex::testing

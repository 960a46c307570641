// Readers and hostile numbers, as properties (RapidCheck): every reader (OBJ, PLY, VVAL, the polygon OBJ
// of `qex check`, the certificate's header) is given a file with one number at the edges in one of its fields: 2^31 +- 1, 2^53 + 1,
// 2^63, 2^64, 1e308 and past it, -0, denormals, NaN and infinities spelled every way, hexadecimal,
// fractions, and integers of up to 10^6 digits. A field that holds an index or a count refuses every one
// of them, naming its place, unless the spelling is of an integer in range (-0, +1, 2e0 where a float
// holds an index), which then reads as that integer; a coordinate either reads as the number strtod makes
// of it (finite), or is refused with its place. Nothing crashes, and nothing is left half-read. The fixed cases, with the
// messages they give, are hostile_numbers_test.cpp.
#include "test_support.h"

#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace qex::testing {
namespace {

/// Spellings at the edges of what a file's number can be.
const std::vector<std::string>& edge_spellings() {
    static const std::vector<std::string> spellings = {
        "2147483647", "2147483648", "2147483649", "-2147483648", "-2147483649", "4294967295", "4294967296",
        "4294967297", "9007199254740992", "9007199254740993", "9223372036854775807", "9223372036854775808",
        "-9223372036854775808", "-9223372036854775809", "18446744073709551615", "18446744073709551616", "1e308",
        "-1e308", "1.7976931348623157e308", "1.7976931348623159e308", "1e309", "1e999", "-1e999", "-0", "+0",
        "-0.0", "0e0", "4.9e-324", "2.4703282292062327e-324", "2.2250738585072014e-308", "1e-400", "nan", "NaN",
        "NAN", "-nan", "+nan", "nan(0x1)", "inf", "-inf", "+inf", "Inf", "INF", "infinity", "Infinity",
        "-Infinity", "INFINITY", "0x10", "0x1p3", "1.5", "2e0", "1e2", "+1", "--1", "1e", ".", "-"};
    return spellings;
}

/// An edge spelling, or an integer of 20 to 10^6 digits (either sign).
rc::Gen<std::string> gen_hostile() {
    const auto long_integer = rc::gen::apply(
        [](int digits, bool negative, char first, char rest) {
            return std::string(negative ? "-" : "") + first + std::string(static_cast<std::size_t>(digits - 1), rest);
        },
        rc::gen::element(20, 40, 400, 1000000), rc::gen::arbitrary<bool>(), rc::gen::inRange('1', ':'),
        rc::gen::inRange('0', ':'));
    return rc::gen::weightedOneOf<std::string>({{6, rc::gen::elementOf(edge_spellings())}, {1, long_integer}});
}

/// The number strtod makes of `s` when it reads all of it (else NaN, read as "no number").
double strtod_whole(const std::string& s) {
    if (s.empty()) return std::nan("");
    char* end = nullptr;
    const double x = std::strtod(s.c_str(), &end);
    return end == s.c_str() + s.size() ? x : std::nan("");
}

/// Whether `s` spells an integer in [lo, hi] (by strtod: "+1", "-0", "2e0" do).
bool spells_integer_in(const std::string& s, double lo, double hi) {
    const double x = strtod_whole(s);
    return x >= lo && x <= hi && std::floor(x) == x;
}

/// Same value and, for zero, the same sign.
bool same_number(double a, double b) { return a == b && std::signbit(a) == std::signbit(b); }

const char* const kObjHead = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\n";

/// A refused OBJ: its line named, nothing read.
void expect_obj_refused_at(const std::string& text, int line) {
    Input in;
    const IoError e = parse_obj(text.data(), text.size(), in);
    RC_ASSERT(!e.ok());
    RC_ASSERT(e.line == line);
    RC_ASSERT(!e.message.empty());
    RC_ASSERT(in.positions.empty() && in.triangles.empty() && in.uvs.empty());
}

RC_GTEST_PROP(HostileNumberProperties, ObjIndicesAreRefusedWithTheirLine, ()) {
    const std::string h = *gen_hostile();
    const bool texture = *rc::gen::arbitrary<bool>();
    const std::string corner = texture ? "3/" + h : h + "/1";
    const std::string text = std::string(kObjHead) + "f 1/1 2/1 " + corner + "\n";
    Input in;
    if (parse_obj(text.data(), text.size(), in).ok()) { // an index in range, read as itself
        RC_ASSERT(spells_integer_in(h, texture ? 1 : 1, texture ? 1 : 3));
        RC_ASSERT(texture || in.triangles[0][2] == static_cast<int>(strtod_whole(h)) - 1);
        return;
    }
    expect_obj_refused_at(text, 5);
}

RC_GTEST_PROP(HostileNumberProperties, ObjCoordinatesReadAsTheirNumberOrAreRefused, ()) {
    const std::string h = *gen_hostile();
    const bool texture = *rc::gen::arbitrary<bool>();
    const std::string text = texture ? "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt " + h + " 0\nf 1/1 2/1 3/1\n"
                                     : "v 0 0 " + h + "\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1\n";
    Input in;
    const IoError e = parse_obj(text.data(), text.size(), in);
    const double x = strtod_whole(h);
    if (e.ok()) {
        RC_ASSERT(std::isfinite(x));
        RC_ASSERT(same_number(texture ? in.uvs[0][0] : in.positions[0][2], x));
    } else {
        RC_ASSERT(e.line == (texture ? 4 : 1));
        RC_ASSERT(in.positions.empty() && in.triangles.empty() && in.uvs.empty());
    }
}

std::string ply_with(const std::string& coordinate, const std::string& index, const std::string& index_type) {
    return "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\n"
           "property double s\nproperty double t\nelement face 1\nproperty list uchar " +
           index_type + " vertex_indices\nend_header\n0 0 " + coordinate + " 0 0\n1 0 0 1 0\n0 1 0 0 1\n3 0 1 " +
           index + "\n";
}

RC_GTEST_PROP(HostileNumberProperties, PlyIndicesAreRefusedWithTheirPlace, ()) {
    const std::string h = *gen_hostile();
    const std::string type = *rc::gen::element<std::string>("int", "uint", "int32", "uint32", "float", "double");
    const std::string text = ply_with("0", h, type);
    Input in;
    const IoError e = parse_ply(text.data(), text.size(), in);
    if (e.ok()) { // an index in range, read as itself ("2e0" in a float-typed list, "+1", "-0")
        RC_ASSERT(spells_integer_in(h, 0, 2));
        RC_ASSERT(in.triangles[0][2] == static_cast<int>(strtod_whole(h)));
        return;
    }
    // Refused while the list is read ("element face 0, property vertex_indices: ...") or once the
    // faces are, against the vertex count ("face 0: vertex index 100 out of range").
    RC_ASSERT(e.message.find("face 0") != std::string::npos);
    RC_ASSERT(in.positions.empty() && in.triangles.empty() && in.uvs.empty());
}

RC_GTEST_PROP(HostileNumberProperties, PlyCoordinatesReadAsTheirNumberOrAreRefused, ()) {
    const std::string h = *gen_hostile();
    const std::string text = ply_with(h, "2", "int");
    Input in;
    const IoError e = parse_ply(text.data(), text.size(), in);
    if (e.ok()) {
        RC_ASSERT(std::isfinite(strtod_whole(h)));
        RC_ASSERT(same_number(in.positions[0][2], strtod_whole(h)));
    } else {
        RC_ASSERT(!e.message.empty());
        RC_ASSERT(in.positions.empty() && in.triangles.empty() && in.uvs.empty());
    }
}

RC_GTEST_PROP(HostileNumberProperties, VvalCountsAndValencesAreRefusedWithTheirLine, ()) {
    const std::string h = *gen_hostile();
    const bool count = *rc::gen::arbitrary<bool>();
    const std::string text =
        "{\"file_format\":\"VVAL\",\"version\":1}\n" + (count ? h + "\n4\n4\n" : std::string("2\n4\n") + h + "\n");
    std::vector<int> val;
    const IoError e = parse_vval(text.data(), text.size(), val);
    if (e.ok()) { // a plain spelling of a plausible valence, read as itself
        RC_ASSERT(!count);
        RC_ASSERT(spells_integer_in(h, 0, 1e6));
        RC_ASSERT(val.size() == 2u);
        RC_ASSERT(static_cast<double>(val[1]) == strtod_whole(h));
        return;
    }
    // A count that is a plausible integer (-0: no vertices) is refused further on, at what follows it.
    if (!(count && spells_integer_in(h, 0, 1e6))) RC_ASSERT(e.line == (count ? 2 : 4));
    RC_ASSERT(!e.message.empty());
    RC_ASSERT(val.empty());
}

RC_GTEST_PROP(HostileNumberProperties, CertificateHeaderNumbersAreRefusedWithTheirLine, ()) {
    // The certificate's header (qex check --certificate) takes plain digits only, in range: the
    // grid scale (line 2, 1 to 2^20), the count of repaired triangles (line 3; one follows) and
    // a repaired triangle (line 4, below 2^31).
    const std::string h = *gen_hostile();
    const int field = *rc::gen::inRange(0, 3);
    const std::string text = "# qex certificate 1\n# grid_scale " + std::string(field == 0 ? h : "1") +
                             "\n# repaired " + (field == 1 ? h : "1") + "\n# r " + (field == 2 ? h : "0") + "\n" +
                             kObjHead + "vt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n";
    Certificate c;
    const IoError e = parse_certificate(text.data(), text.size(), c);
    const bool digits = h.size() <= 19 && h.find_first_not_of("0123456789") == std::string::npos;
    const double x = digits ? strtod_whole(h) : -1;
    const bool in_range = field == 0 ? x >= 1 && x <= 1 << 20 : field == 1 ? x == 1 : x >= 0 && x <= 2147483647.0;
    if (e.ok()) {
        RC_ASSERT(digits && in_range);
        RC_ASSERT(c.grid_scale == (field == 0 ? static_cast<int>(x) : 1));
        RC_ASSERT(c.repaired.size() == 1u);
        RC_ASSERT(static_cast<double>(c.repaired[0]) == (field == 2 ? x : 0.0));
        RC_ASSERT(c.map.triangles.size() == 1u);
        return;
    }
    RC_ASSERT(!(digits && in_range));
    // A count in range other than 1 is refused where the triangles do not match it: at line 4
    // (none announced) or 5 (more announced).
    const bool count_in_range = field == 1 && digits && x <= 2147483647.0;
    RC_ASSERT(e.line == (count_in_range ? (x == 0 ? 4 : 5) : field + 2));
    RC_ASSERT(!e.message.empty());
    RC_ASSERT(c.repaired.empty() && c.map.triangles.empty());
}

RC_GTEST_PROP(HostileNumberProperties, PolygonObjIndicesAreRefusedWithTheirLine, ()) {
    const std::string h = *gen_hostile();
    const std::string path = ::testing::TempDir() + "qex_hostile_polygon_property.obj";
    std::FILE* f = std::fopen(path.c_str(), "wb");
    RC_ASSERT(f != nullptr);
    const std::string text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 " + h + "\n";
    std::fwrite(text.data(), 1, text.size(), f);
    std::fclose(f);
    QuadMesh mesh;
    const IoError e = read_polygon_obj(path, mesh);
    std::remove(path.c_str());
    if (e.ok()) { // an index in range, read as itself
        RC_ASSERT(spells_integer_in(h, 1, 3));
        RC_ASSERT(mesh.faces.size() == 1u);
        RC_ASSERT(mesh.faces[0].back() == static_cast<int>(strtod_whole(h)) - 1);
        return;
    }
    RC_ASSERT(e.line == 4);
    RC_ASSERT(mesh.faces.empty());
}

} // namespace
} // namespace qex::testing

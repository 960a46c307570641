// Raw bytes as a PLY file: the map reader and the polygon reader, and where the map parses, the
// whole pipeline and the checker. Only clean errors are allowed (a message, a byte offset
// within the data when one is named, and nothing read); a result must be consistent
// (property_tests/result_checks.h).
#include "fuzz_input.h"
#include "result_checks.h"

#include <cstring>

namespace {

void check_error(const qex::IoError& e, std::size_t size) {
    if (e.message.empty()) qex::fuzz::fail("a PLY error without a message");
    if (e.offset < -1 || e.offset > static_cast<std::int64_t>(size)) qex::fuzz::fail("a PLY error past the data");
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const char* bytes = reinterpret_cast<const char*>(data);
    qex::QuadMesh mesh;
    if (const qex::IoError e = qex::parse_polygon_ply(bytes, size, mesh); !e.ok()) {
        check_error(e, size);
        if (!mesh.positions.empty() || !mesh.faces.empty()) qex::fuzz::fail("a failed polygon read left data");
    }
    qex::Input in;
    const qex::IoError e = qex::parse_ply(bytes, size, in);
    if (!e.ok()) {
        check_error(e, size);
        if (!in.positions.empty() || !in.triangles.empty() || !in.uvs.empty())
            qex::fuzz::fail("a failed read left data");
        return 0;
    }
    if (in.uvs.size() != 3 * in.triangles.size()) qex::fuzz::fail("a read map without one UV per corner");
    qex::Options opt;
    opt.max_qvertices = 5000; // keep each run short (broken maps run every fallback rung)
    const qex::Result r = qex::extract(in, opt);
    if (!r.ok()) {
        if (r.error.message.empty()) qex::fuzz::fail("an error without a message");
        return 0;
    }
    if (const std::string why = qex::testing::result_inconsistency(in, r); !why.empty()) qex::fuzz::fail(why);
    return 0;
}

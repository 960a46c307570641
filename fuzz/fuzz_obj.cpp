// Raw bytes as an OBJ file (and as a VVAL file): the readers and, where the OBJ parses, the whole
// pipeline and the checker. Only clean errors are allowed (a message; for the OBJ reader a line
// within the text and nothing read). A result must be consistent (property_tests/result_checks.h):
// its verdict is the checker's run again, its checker defects are the violations kind for kind,
// and every defect names a place.
#include "fuzz_input.h"
#include "result_checks.h"

#include <algorithm>
#include <cstring>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const char* text = reinterpret_cast<const char*>(data);
    std::vector<int> valences;
    const qex::IoError ve = qex::parse_vval(text, size, valences);
    if (!ve.ok() && ve.message.empty()) qex::fuzz::fail("a VVAL error without a message");
    qex::Input in;
    const qex::IoError e = qex::parse_obj(text, size, in);
    if (!e.ok()) {
        const auto lines = std::count(text, text + size, '\n') + 1;
        if (e.message.empty() || e.line < 1 || e.line > lines)
            qex::fuzz::fail("an OBJ error without a message or a line of the text");
        if (!in.positions.empty() || !in.triangles.empty() || !in.uvs.empty())
            qex::fuzz::fail("a failed read left data");
        return 0;
    }
    if (valences.size() == in.positions.size()) in.valences = valences;
    qex::Options opt;
    opt.max_qvertices = 5000; // keep each run short (broken maps run every fallback rung)
    const qex::Result r = qex::extract(in, opt);
    if (!r.ok()) {
        if (r.error.message.empty() || std::strlen(qex::to_string(r.error.code)) == 0)
            qex::fuzz::fail("an error without a message");
        return 0;
    }
    if (const std::string why = qex::testing::result_inconsistency(in, r); !why.empty()) qex::fuzz::fail(why);
    for (const auto& d : r.report.defects)
        if (d.message.empty() || std::strlen(qex::to_string(d.kind)) == 0)
            qex::fuzz::fail("a defect without a message");
    for (const auto& x : r.check.violations)
        if (x.message.empty() || std::strlen(qex::to_string(x.kind)) == 0)
            qex::fuzz::fail("a violation without a message");
    return 0;
}

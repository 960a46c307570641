// Raw bytes as an OBJ file: the reader and, where it parses, the whole pipeline and the checker.
// Only clean errors are allowed; an invalid mesh must come with reported defects.
#include "qex/qex.h"

#include <cstdlib>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    qex::Input in;
    if (!qex::parse_obj(reinterpret_cast<const char*>(data), size, in).ok()) return 0;
    qex::Options opt;
    opt.max_qvertices = 5000; // keep each run short (broken maps run every fallback rung)
    const qex::Result r = qex::extract(in, opt);
    if (!r.ok()) {
        if (r.error.message.empty()) std::abort();
        return 0;
    }
    if (!qex::verify(in, r.mesh).valid && r.report.defects.empty()) std::abort();
    return 0;
}

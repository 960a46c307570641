// Raw bytes as an OBJ file (and as a VVAL file): the readers and, where the OBJ parses, the whole
// pipeline and the checker. Only clean errors are allowed; an invalid mesh must come with
// reported defects, each with a name and a message.
#include "qex/qex.h"

#include <cstdlib>
#include <cstring>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const char* text = reinterpret_cast<const char*>(data);
    std::vector<int> valences;
    const qex::IoError ve = qex::parse_vval(text, size, valences);
    if (!ve.ok() && ve.message.empty()) std::abort();
    qex::Input in;
    const qex::IoError e = qex::parse_obj(text, size, in);
    if (!e.ok()) {
        if (e.message.empty() || e.line < 0) std::abort();
        return 0;
    }
    if (valences.size() == in.positions.size()) in.valences = valences;
    qex::Options opt;
    opt.max_qvertices = 5000; // keep each run short (broken maps run every fallback rung)
    const qex::Result r = qex::extract(in, opt);
    if (!r.ok()) {
        if (r.error.message.empty() || std::strlen(qex::to_string(r.error.code)) == 0) std::abort();
        return 0;
    }
    // The checker is deterministic: it must repeat extract()'s verdict. A mesh from a relaxed
    // rung was also judged without its provenance, against the given map (as `qex check` judges
    // it), so that judgement is repeated too.
    const qex::VerifyResult v = qex::verify(in, r.mesh);
    bool valid = v.valid;
    if (valid && r.report.rung != "as-given") {
        qex::QuadMesh bare;
        bare.positions = r.mesh.positions;
        bare.faces = r.mesh.faces;
        valid = qex::verify(in, bare).valid;
    }
    if (valid != r.check.valid) std::abort();
    if (!valid && r.report.defects.empty()) std::abort();
    for (const auto& d : r.report.defects)
        if (d.message.empty() || std::strlen(qex::to_string(d.kind)) == 0) std::abort();
    for (const auto& x : v.violations)
        if (x.message.empty() || std::strlen(qex::to_string(x.kind)) == 0) std::abort();
    return 0;
}

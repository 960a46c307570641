// The checker's internal interface between its files. Like every file in src/verify/, it
// includes only the public headers and the checker's own files: the build fails otherwise
// (CMakeLists.txt, "the checker's wall").
#pragma once

#include "qex/verify.h"

#include <vector>

namespace qex::verify_detail {

/// Located mode (meshes without provenance): locates every output vertex on the input surface
/// and checks faces and coverage against the map; appends violations to `out` and undecided
/// checks to `r.undecided`.
void check_located(const Input& in, const QuadMesh& mesh, const VerifyOptions& opt, VerifyResult& r,
                   std::vector<Violation>& out);

} // namespace qex::verify_detail

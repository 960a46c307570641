// The checker's violations on stderr, for `qex extract` and `qex check`. (The JSON of reports and
// verdicts is the library's: qex/report.h.)
#pragma once

#include "qex/qex.h"

#include <cstddef>

namespace qex::cli {

/// The first `limit` violations and undecided cases, one per line.
void print_violations(const VerifyResult& v, std::size_t limit = 20);

} // namespace qex::cli

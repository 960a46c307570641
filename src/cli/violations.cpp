// The checker's violations on stderr (violations.h).
#include "violations.h"

#include <iostream>

namespace qex::cli {

void print_violations(const qex::VerifyResult& v, std::size_t limit) {
    for (std::size_t i = 0; i < v.violations.size() && i < limit; ++i)
        std::cerr << "  " << qex::to_string(v.violations[i].kind) << ": " << v.violations[i].message << "\n";
    if (v.violations.size() > limit) std::cerr << "  ... and " << v.violations.size() - limit << " more\n";
    for (std::size_t i = 0; i < v.undecided.size() && i < limit; ++i)
        std::cerr << "  undecided: " << qex::to_string(v.undecided[i].kind) << ": " << v.undecided[i].message << "\n";
    if (v.undecided.size() > limit) std::cerr << "  ... and " << v.undecided.size() - limit << " more undecided\n";
}

} // namespace qex::cli

// The generators of exact integer-grid maps now live in the library (src/conform/, namespace
// qex::gen), where `qex conform` draws its cases from them; the tests keep their old names.
#pragma once

#include "conform/map_generators.h"

namespace qex::testing {
using namespace qex::gen;
} // namespace qex::testing

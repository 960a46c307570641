// The map transforms now live in the library (src/conform/map_transforms.h, namespace
// qex::gen::transforms); the tests keep their old names.
#pragma once

#include "conform/map_transforms.h"

namespace qex::testing {
namespace transforms = qex::gen::transforms;
} // namespace qex::testing

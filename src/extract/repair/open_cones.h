// The repair's retry with cone fans opened (inside the subsystem only; its door is repair.h):
// where the untangler wound a region wrongly round its singularities (open_cones.cpp).
#pragma once

#include "extract/repair/solver.h"

#include <vector>

namespace qex::detail::repair_impl {

/// After an untangling that failed: the region again from its given UVs (`before`), with the fans
/// of its singularities that wind short of their targets there (a run of flipped triangles, or a
/// squeezed fan) opened and kept open. True when that is certified. `patience` as for
/// untangle_region.
bool untangle_with_open_cones(TriMesh& m, const Region& r, const RegionMarks& marks, const std::vector<Point2>& before,
                              Workspace& work, int patience);

} // namespace qex::detail::repair_impl

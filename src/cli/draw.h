// The checker's verdict as a picture (src/cli/draw.cpp), for `qex check --svg`.
#pragma once

#include "qex/qex.h"

#include <string>

namespace qex::cli {

/// The verdict `verdict` on `mesh` as an SVG document: the map in UV space (its UVs times
/// `grid_scale`, as the checker judged it; in outline when large) with each violation's places
/// marked and numbered (grid cells and grid points where it names them, else the input triangle
/// it names or lies on: groups of class "violation-mark"), and, for meshes of up to 30,000 faces,
/// the mesh in three views with the same numbers; the violations listed under the pictures.
std::string verdict_svg(const Input& input, const QuadMesh& mesh, const VerifyResult& verdict, int grid_scale,
                        const std::string& title);

} // namespace qex::cli

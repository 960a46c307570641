// The two pictures `qex draw` and `qex check --svg` put together (draw.cpp): the map in UV space
// (draw_map.cpp) and the quad mesh in three orthographic views (draw_mesh.cpp), each with the
// places of violations and defects marked. Each returns an SVG fragment and its size.
#pragma once

#include "map_info.h"
#include "qex/layout.h"
#include "qex/qex.h"

#include <nlohmann/json_fwd.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace qex::cli {

using Vec2 = std::array<double, 2>;
using Vec3 = std::array<double, 3>;

constexpr std::size_t kWholeMapTriangles = 30000; ///< larger maps are drawn in outline
constexpr std::size_t kListed = 40;               ///< defects listed under the mesh picture
constexpr std::size_t kMeshViewFaces = 30000;     ///< larger meshes are not drawn in 3D by `qex check --svg`

// === the map in UV space (draw_map.cpp)

/// A violation's place on the map, in the chart of `triangle`: a grid cell (lower-left `at`), a
/// grid point, or the triangle itself (`at` its UV centroid).
struct MapMark {
    enum class Shape { Cell, Point, Triangle } shape = Shape::Point;
    Vec2 at{0, 0};
    int triangle = -1;
    std::string label; ///< the violation's number (on its first mark only)
};

/// The triangles to draw around triangle `t`: those reached from it across edges whose ends
/// keep their UVs (one chart), within `radius` grid units of its centroid.
std::vector<int> around(const Input& in, int t, double radius);

/// The map's picture: every triangle of `tris`, or with `outline` (large maps) only its
/// boundary and seam edges, its flipped and degenerate triangles and its singularities; and the
/// violations' marks, each a group of class "violation-mark".
std::string draw_map(const Input& in, const MapInfo& info, const std::vector<int>& tris, bool outline,
                     const std::string& title, double& width, double& height, const std::vector<MapMark>& marks = {});

/// Where a violation is on the map: its grid cells and grid points (up to four of each), else the
/// input triangle it names or lies on, else an input vertex (in its first triangle's chart). The
/// first mark carries `label`; none where the violation has no place on the map.
std::vector<MapMark> map_marks(const Input& in, const Violation& x, const std::string& label);

// === the quad mesh in three views (draw_mesh.cpp)

/// A numbered place in 3D.
struct Mark {
    Vec3 at;
    std::string label;
};

/// Where a violation is in 3D: the element it names, else its first place this picture can show
/// (a grid cell's centre or a grid point on the surface through its chart's triangle).
bool violation_at(const Input& in, const QuadMesh& mesh, const Violation& x, Vec3& at);

/// What `qex draw --report` cannot read in a report's defects, naming the defect ("" if
/// nothing): a list of objects whose `output_face` and `input_element`, where given, are
/// integers of 64 bits (a JSON float too, if it holds one exactly: io/checked_int.h), and whose
/// `kind` and `message` are strings.
std::string report_problem(const nlohmann::json& report);

/// The marks (and the listing under the picture): the report's defects (report_problem() finds
/// nothing wrong with them), then the checker's violations.
std::vector<Mark> collect_marks(const Input& in, const QuadMesh& mesh, const nlohmann::json& report,
                                const VerifyResult& check, std::vector<std::string>& listing);

/// The mesh's picture: three views with the marks circled and numbered, the title, and the
/// listing under them (its first kListed lines).
std::string draw_mesh(const Input& in, const QuadMesh& mesh, const std::vector<Mark>& marks,
                      const std::vector<std::string>& listing, const std::string& title, double& width, double& height);

// === the quad layout in three views (draw_layout.cpp)

/// The layout's picture: three views (front, back, side) with each patch in its own colour, the
/// separatrices as dark lines; the title above.
std::string draw_layout(const QuadMesh& mesh, const Layout& layout, const std::string& title, double& width,
                        double& height);

} // namespace qex::cli

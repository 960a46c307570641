// The checker's oracle mode for meshes that carry no provenance (from another extractor, or read
// back from an OBJ): every output vertex is located on the input surface (CGAL's AABB tree,
// surface.cpp) and must be the image of an integer grid point; every face's corners, carried
// into one chart along the input's transitions, must be the corners of one grid cell in
// counter-clockwise order (face_cells.cpp); and the faces must cover the map (their number
// equals the map's signed area) unless the map has flipped triangles. Positions from other
// tools are rounded, so locating needs two tolerances (UV units and a fraction of the
// bounding-box diagonal), and the input's transitions are rounded with the UV tolerance too
// (transitions.cpp); the grid points are then compared as integers.
#include "checker.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace qex::verify_detail {
namespace {

/// Vertices: the closest surface point, its UV in that triangle's chart (on an input vertex:
/// the vertex's UV there), the nearest grid point. A vertex off the surface or off the grid is
/// reported (and not `ok`).
std::vector<Located> locate_vertices(const LocatedMap& map, const QuadMesh& mesh, const VerifyOptions& opt,
                                     VerifyResult& r, std::vector<Violation>& out) {
    const double diag = map.surface.diagonal(), max_dist = map.surface.max_distance();
    std::vector<Located> loc(mesh.positions.size());
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
        const auto& x = mesh.positions[v];
        if (!std::isfinite(x[0]) || !std::isfinite(x[1]) || !std::isfinite(x[2])) continue;
        const SurfacePoint hit = map.surface.locate(x);
        std::array<double, 2> uv = hit.uv;
        loc[v].triangle = hit.triangle;
        if (hit.corner >= 0) {
            loc[v].on_vertex = map.in.triangles[loc[v].triangle][hit.corner];
            uv = map.in.uvs[3 * loc[v].triangle + static_cast<std::size_t>(hit.corner)];
        }
        r.max_surface_distance = std::max(r.max_surface_distance, diag > 0 ? hit.distance / diag : 0.0);
        if (hit.distance > max_dist) {
            add_capped(out, ViolationKind::OffSurface,
                       "vertex " + std::to_string(v) + " is " + std::to_string(hit.distance) +
                           " from the input surface (tolerance " + std::to_string(max_dist) + ")",
                       static_cast<std::int64_t>(v));
            continue;
        }
        const double gx = std::nearbyint(uv[0]), gy = std::nearbyint(uv[1]);
        const double off = std::max(std::abs(uv[0] - gx), std::abs(uv[1] - gy));
        r.max_grid_distance = std::max(r.max_grid_distance, off);
        if (!(off <= opt.uv_tolerance) || !(std::abs(gx) < 9e15 && std::abs(gy) < 9e15)) {
            add_capped(out, ViolationKind::NotOnGridPoint,
                       "vertex " + std::to_string(v) + " maps to (" + std::to_string(uv[0]) + ", " +
                           std::to_string(uv[1]) + ") in the chart of input triangle " +
                           std::to_string(loc[v].triangle) + ", not within " + std::to_string(opt.uv_tolerance) +
                           " of an integer grid point",
                       static_cast<std::int64_t>(v));
            continue;
        }
        loc[v].grid = {static_cast<std::int64_t>(gx), static_cast<std::int64_t>(gy)};
        loc[v].ok = true;
    }
    return loc;
}

} // namespace

void check_located(const Input& in, const QuadMesh& mesh, const VerifyOptions& opt, VerifyResult& r,
                   std::vector<Violation>& out) {
    if (mesh.positions.empty()) return; // nothing to locate
    const std::unique_ptr<Surface> surface = Surface::build(in, opt.distance_tolerance);
    if (!surface) return;
    r.located = true;
    // The input's half-edges and transitions, its singular vertices, and its fold-overs
    // (triangles flipped or degenerate in UV: there the map is not locally injective, and a path
    // across them does not fix the chart it arrives in).
    LocatedMap map{in, *surface, input_edges(in, opt.uv_tolerance), {}, {}};
    map.singular = singular_vertices(in, map.edges);
    map.fold_over = fold_overs(in, r);
    const std::vector<Located> loc = locate_vertices(map, mesh, opt, r, out);
    check_face_cells(map, mesh, loc, r, out);
    // Coverage: a closed, consistently oriented mesh of positive unit cells covers the map once
    // exactly when it has as many faces as the map has area. Flipped triangles (UV area < 0) can
    // make that impossible: with any, the difference is reported but not a violation (degenerate
    // ones alone do not excuse it).
    r.coverage_difference = static_cast<std::int64_t>(mesh.faces.size()) - r.input_signed_uv_area_rounded;
    if (r.coverage_difference != 0 && r.map_flipped_triangles == 0)
        add_capped(out, ViolationKind::CoverageMismatch,
                   std::to_string(mesh.faces.size()) + " faces, but the map (without fold-overs) has area " +
                       std::to_string(r.input_signed_uv_area_rounded),
                   -1);
}

} // namespace qex::verify_detail

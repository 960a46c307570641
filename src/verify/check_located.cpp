// The checker's oracle mode for meshes that carry no provenance (from another extractor, or read
// back from an OBJ): every output vertex is located on the input surface (CGAL's AABB tree,
// surface.cpp) and must be the image of an integer grid point; every face's corners, carried
// into one chart along the input's transitions, must be the corners of one grid cell in
// counter-clockwise order (face_cells.cpp); and the faces must cover the map: their number
// equals the map's signed area unless the map has flipped triangles, and every cell the map
// covers once away from its fold-overs and its boundary is a face (coverage.cpp). Around the map's
// fold-overs (fold_regions: kFoldRegionRings rings of input vertices around its flipped or
// degenerate triangles), where a repair may have moved the map a correct mesh follows, vertices
// are judged on the surface only, and their faces' failures are undecided. Positions from other
// tools are rounded, so locating needs two tolerances (UV units and a fraction of the
// bounding-box diagonal), and the input's transitions are rounded with the UV tolerance too
// (transitions.cpp); the grid points are then compared as integers.
// This file holds the mode's order and the fold-over regions; locate_vertices.cpp locates the
// vertices.
#include "checker.h"
#include "grid.h"
#include "parallel.h"
#include "union_find.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace qex::verify_detail {
namespace {

/// Per output vertex the input triangle it was located in (-1 where it was not), and that of
/// its closest surface point (-1 for a non-finite position), where asked for.
void record_triangles(const QuadMesh& mesh, const std::vector<Located>& loc,
                      std::vector<std::int64_t>* located_triangle, std::vector<std::int64_t>* closest_triangle) {
    if (located_triangle) {
        located_triangle->assign(loc.size(), -1);
        for (std::size_t v = 0; v < loc.size(); ++v)
            if (loc[v].ok || loc[v].surface_only) (*located_triangle)[v] = loc[v].triangle;
    }
    if (closest_triangle) {
        closest_triangle->assign(loc.size(), -1);
        for (std::size_t v = 0; v < loc.size(); ++v) {
            const auto& x = mesh.positions[v];
            if (std::isfinite(x[0]) && std::isfinite(x[1]) && std::isfinite(x[2]))
                (*closest_triangle)[v] = loc[v].triangle;
        }
    }
}

/// Counts the faces with a corner in a fold-over region (VerifyResult::surface_only_faces).
void count_surface_only_faces(const QuadMesh& mesh, const std::vector<Located>& loc, VerifyResult& r) {
    for (const auto& face : mesh.faces) {
        bool surface_only = false;
        for (int v : face)
            surface_only = surface_only || (v >= 0 && static_cast<std::size_t>(v) < loc.size() &&
                                            loc[static_cast<std::size_t>(v)].surface_only);
        r.surface_only_faces += surface_only;
    }
}

/// Whether every boundary edge of the input runs along an integer iso-line (its ends on one
/// integer u or v, within `tol`): else the boundary cuts cells, which an extractor discards.
bool boundary_along_iso_lines(const LocatedMap& map, double tol) {
    const auto on_line = [tol](double a, double b) {
        const double k = std::nearbyint(a);
        return std::abs(a - k) <= tol && std::abs(b - k) <= tol;
    };
    for (std::size_t c = 0; c < map.edges.partner.size(); ++c) {
        if (map.edges.partner[c] >= 0) continue;
        const auto &a = map.in.uvs[c], &b = map.in.uvs[next_corner(c)];
        if (!on_line(a[0], b[0]) && !on_line(a[1], b[1])) return false;
    }
    return true;
}

/// Coverage by count: a consistently oriented mesh of positive unit cells covers the map once
/// exactly when it has as many faces as the map has area, on a closed map or one whose boundary
/// runs along iso-lines (a boundary off them cuts cells, which extractors discard). Flipped
/// triangles (UV area < 0) can make that impossible: with any, the difference is reported but
/// not a violation (degenerate ones alone do not excuse it).
void check_face_count(const LocatedMap& map, const QuadMesh& mesh, double tol, VerifyResult& r,
                      std::vector<Violation>& out) {
    r.coverage_difference = static_cast<std::int64_t>(mesh.faces.size()) - r.input_signed_uv_area_rounded;
    if (r.coverage_difference != 0 && r.map_flipped_triangles == 0 && boundary_along_iso_lines(map, tol))
        add_capped(out, ViolationKind::CoverageMismatch,
                   std::to_string(mesh.faces.size()) + " faces, but the map (without fold-overs) has area " +
                       std::to_string(r.input_signed_uv_area_rounded),
                   -1);
}

/// The whole mesh's violations name the unit cells no face covers, with the triangle whose
/// chart holds each.
void name_uncovered_cells(const std::vector<FaceCell>& uncovered, std::vector<Violation>& out) {
    std::vector<Violation*> global;
    for (Violation& v : out)
        if (v.kind == ViolationKind::BoundaryMismatch || v.kind == ViolationKind::EulerMismatch ||
            v.kind == ViolationKind::CoverageMismatch)
            global.push_back(&v);
    if (global.empty() || uncovered.empty()) return;
    constexpr std::size_t kMostCells = 100;
    Place place{PlaceKind::GridCell, {}};
    for (std::size_t i = 0; i < uncovered.size() && i < kMostCells; ++i)
        place.indices.insert(place.indices.end(), uncovered[i].begin(), uncovered[i].end());
    const std::string first = "; " + std::to_string(std::min(uncovered.size(), kMostCells)) +
                              (uncovered.size() > kMostCells ? " or more" : "") +
                              " grid cells no face covers, the first (" + std::to_string(uncovered[0][1]) + ", " +
                              std::to_string(uncovered[0][2]) + ") in the chart of input triangle " +
                              std::to_string(uncovered[0][0]);
    for (Violation* v : global) {
        v->places.push_back(place);
        v->message += first;
    }
}

} // namespace

std::vector<char> near_fold_overs(const Input& in, const std::vector<char>& fold_over, int rings) {
    const std::size_t nt = in.triangles.size(), nv = in.positions.size();
    std::vector<char> near(nt, 0);
    // Rings: breadth first over the input's edges from every corner of a fold-over.
    std::vector<int> dist(nv, -1), queue;
    for (std::size_t t = 0; t < nt; ++t)
        if (fold_over[t])
            for (int v : in.triangles[t])
                if (dist[static_cast<std::size_t>(v)] < 0) dist[static_cast<std::size_t>(v)] = 0, queue.push_back(v);
    if (queue.empty()) return near;
    // Per vertex its triangles (counting sort), to walk the rings.
    std::vector<std::size_t> start(nv + 1, 0);
    for (const auto& tri : in.triangles)
        for (int v : tri) ++start[static_cast<std::size_t>(v) + 1];
    for (std::size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
    std::vector<std::uint32_t> fan(start[nv]);
    {
        std::vector<std::size_t> fill(start.begin(), start.end() - 1);
        for (std::size_t t = 0; t < nt; ++t)
            for (int v : in.triangles[t]) fan[fill[static_cast<std::size_t>(v)]++] = static_cast<std::uint32_t>(t);
    }
    for (std::size_t head = 0; head < queue.size(); ++head) {
        const auto v = static_cast<std::size_t>(queue[head]);
        if (dist[v] >= rings) continue;
        for (std::size_t i = start[v]; i < start[v + 1]; ++i)
            for (int w : in.triangles[fan[i]])
                if (dist[static_cast<std::size_t>(w)] < 0)
                    dist[static_cast<std::size_t>(w)] = dist[v] + 1, queue.push_back(w);
    }
    for (std::size_t t = 0; t < nt; ++t)
        for (int v : in.triangles[t]) near[t] = near[t] || dist[static_cast<std::size_t>(v)] >= 0;
    return near;
}

std::vector<std::int32_t> fold_regions(const Input& in, const std::vector<char>& fold_over, VerifyResult& r) {
    const std::size_t nt = in.triangles.size(), nv = in.positions.size();
    std::vector<std::int32_t> region_of(nt, -1);
    const std::vector<char> in_region = near_fold_overs(in, fold_over, kFoldRegionRings);
    // The region's triangles, grouped through shared vertices.
    UnionFind groups(nv);
    for (std::size_t t = 0; t < nt; ++t) {
        const auto& tri = in.triangles[t];
        if (in_region[t]) groups.unite(tri[0], tri[1]), groups.unite(tri[1], tri[2]);
    }
    // Regions numbered by their first fold-over triangle (the smallest index).
    std::vector<std::int32_t> index_of_root(nv, -1);
    for (std::size_t t = 0; t < nt; ++t) {
        if (!fold_over[t]) continue;
        const auto root = static_cast<std::size_t>(groups.find(in.triangles[t][0]));
        if (index_of_root[root] >= 0) continue;
        index_of_root[root] = static_cast<std::int32_t>(r.fold_regions.size());
        r.fold_regions.push_back({});
        r.fold_regions.back().first_triangle = static_cast<std::int64_t>(t);
    }
    for (std::size_t t = 0; t < nt; ++t) {
        if (!in_region[t]) continue;
        const std::int32_t k = index_of_root[static_cast<std::size_t>(groups.find(in.triangles[t][0]))];
        region_of[t] = k; // every group holds a fold-over: its rings grew from one
        FoldRegion& g = r.fold_regions[static_cast<std::size_t>(k)];
        const auto &a = in.uvs[3 * t], &b = in.uvs[3 * t + 1], &c = in.uvs[3 * t + 2];
        const double area = 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
        ++g.triangles;
        g.uv_area += area;
        if (fold_over[t]) ++g.fold_triangles, g.fold_uv_area += area;
    }
    return region_of;
}

void check_located(const Input& in, const QuadMesh& mesh, const VerifyOptions& opt, VerifyResult& r,
                   std::vector<Violation>& out, std::vector<std::int64_t>* located_triangle,
                   std::vector<std::int64_t>* closest_triangle, double noise_scale) {
    if (mesh.positions.empty()) return; // nothing to locate
    const std::unique_ptr<Surface> surface = Surface::build(in, opt.distance_tolerance);
    if (!surface) return;
    r.located = true;
    position_precision(mesh, r);
    // The input's half-edges and transitions, its singular vertices, and its fold-overs
    // (triangles flipped or degenerate in UV: there the map is not locally injective, and a path
    // across them does not fix the chart it arrives in).
    // The noise of a refined map is the given map's times the scale: in its seams too.
    const double seam_tolerance = grid_tolerance(opt, noise_scale);
    LocatedMap map{in, *surface, input_edges(in, seam_tolerance), {}, {}, {}};
    map.singular = singular_vertices(in, map.edges);
    map.fold_over = fold_overs(in, r);
    // Where a repair may have moved the map: around the fold-overs (VerifyResult::fold_regions).
    map.region_of =
        opt.fold_regions ? fold_regions(in, map.fold_over, r) : std::vector<std::int32_t>(in.triangles.size(), -1);
    const std::vector<Located> loc = locate_vertices(map, mesh, opt, noise_scale, r, out);
    record_triangles(mesh, loc, located_triangle, closest_triangle);
    // Faces with a corner in a fold-over region are judged on the surface only: check_face_cells
    // lists their failures as undecided.
    count_surface_only_faces(mesh, loc, r);
    check_face_cells(map, mesh, loc, r, out);
    check_singularities(map, mesh, loc, seam_tolerance, r, out);
    check_face_count(map, mesh, seam_tolerance, r, out);
    // And cell by cell, away from the fold-overs (as far as their regions reach, whether or not
    // the vertices there are judged on the surface only): every cell the map covers once is a
    // face, its corners vertices.
    const std::vector<char> far_from_folds =
        far_from_fold_overs(in, map.edges, map.fold_over, near_fold_overs(in, map.fold_over, kFoldRegionRings));
    std::vector<FaceCell> uncovered;
    check_coverage(map, mesh, loc, far_from_folds, opt.uv_tolerance, thread_count(opt.threads), r, out, uncovered);
    name_uncovered_cells(uncovered, out);
}

} // namespace qex::verify_detail

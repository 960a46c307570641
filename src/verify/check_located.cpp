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
#include "checker.h"
#include "grid.h"
#include "parallel.h"
#include "union_find.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <set>
#include <string>

namespace qex::verify_detail {
namespace {

/// Where a rounded UV tolerance stops identifying a grid point: beyond it, a vertex off its grid
/// point is undecided (the file's precision cannot place it), not a violation.
constexpr double kMaxUvTolerance = 0.25;

std::string num(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", x);
    return buf;
}

/// The fewest significant decimal digits (1..17) that read back as x exactly.
int digits_of(double x) {
    char buf[40];
    auto exact = [&](int d) {
        std::snprintf(buf, sizeof buf, "%.*g", d, x);
        return std::strtod(buf, nullptr) == x;
    };
    int lo = 1, hi = 17; // exact(hi) holds for every finite double
    if (exact(6))
        hi = 6;
    else
        lo = 7;
    while (lo < hi) {
        const int mid = (lo + hi) / 2;
        if (exact(mid))
            hi = mid;
        else
            lo = mid + 1;
    }
    return lo;
}

/// The precision the positions carry (VerifyResult::position_digits, positions_float32).
void position_precision(const QuadMesh& mesh, VerifyResult& r) {
    int digits = 0;
    bool float32 = true;
    for (const auto& p : mesh.positions)
        for (double x : p) {
            if (!std::isfinite(x)) continue;
            if (digits < 17) digits = std::max(digits, digits_of(x));
            // Through a volatile float: with -frounding-math (CGAL's flag) GCC 12 drops the
            // double -> float -> double round trip.
            volatile float narrow = static_cast<float>(x);
            float32 = float32 && static_cast<double>(narrow) == x;
        }
    r.position_digits = digits;
    r.positions_float32 = float32 && digits > 0;
}

/// Per input triangle: the largest stretch of the map, i.e. the largest singular value of the
/// linear map from the triangle's plane to UV (0 for a triangle degenerate in 3D).
std::vector<double> triangle_stretch(const Input& in) {
    std::vector<double> s(in.triangles.size(), 0.0);
    for (std::size_t t = 0; t < in.triangles.size(); ++t) {
        const auto& p0 = in.positions[static_cast<std::size_t>(in.triangles[t][0])];
        const auto& p1 = in.positions[static_cast<std::size_t>(in.triangles[t][1])];
        const auto& p2 = in.positions[static_cast<std::size_t>(in.triangles[t][2])];
        double e1[3], e2[3];
        for (int d = 0; d < 3; ++d) e1[d] = p1[d] - p0[d], e2[d] = p2[d] - p0[d];
        const double l1 = std::sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
        const double cx = e1[1] * e2[2] - e1[2] * e2[1], cy = e1[2] * e2[0] - e1[0] * e2[2],
                     cz = e1[0] * e2[1] - e1[1] * e2[0];
        const double area2 = std::sqrt(cx * cx + cy * cy + cz * cz);
        if (!(l1 > 0) || !(area2 > 0)) continue;
        // The edges in an orthonormal frame of the plane: e1 = (a, 0), e2 = (b, c).
        const double a = l1, b = (e1[0] * e2[0] + e1[1] * e2[1] + e1[2] * e2[2]) / l1, c = area2 / l1;
        const auto &u0 = in.uvs[3 * t], &u1 = in.uvs[3 * t + 1], &u2 = in.uvs[3 * t + 2];
        const double f1x = u1[0] - u0[0], f1y = u1[1] - u0[1], f2x = u2[0] - u0[0], f2y = u2[1] - u0[1];
        // M = F E^-1 with E = [[a, b], [0, c]]: E^-1 = [[1/a, -b/(a c)], [0, 1/c]].
        const double m00 = f1x / a, m10 = f1y / a;
        const double m01 = (f2x - b * m00) / c, m11 = (f2y - b * m10) / c;
        const double frob = m00 * m00 + m01 * m01 + m10 * m10 + m11 * m11, det = m00 * m11 - m01 * m10;
        s[t] = std::sqrt(0.5 * (frob + std::sqrt(std::max(0.0, frob * frob - 4 * det * det))));
    }
    return s;
}

/// The UV tolerance for noise on a map that is a given map times `noise_scale` (check_located).
double grid_tolerance(const VerifyOptions& opt, double noise_scale) {
    return std::min(opt.uv_tolerance * std::max(1.0, noise_scale), std::max(opt.uv_tolerance, 0.1));
}

/// Vertices: the closest surface point, its UV in that triangle's chart (on an input vertex:
/// the vertex's UV there), the nearest grid point. A vertex off the surface or off the grid is
/// reported (and not `ok`). Each vertex's tolerances grow with what rounding its coordinates to
/// opt.position_digits may move it (VerifyOptions).
std::vector<Located> locate_vertices(const LocatedMap& map, const QuadMesh& mesh, const VerifyOptions& opt,
                                     double noise_scale, VerifyResult& r, std::vector<Violation>& out) {
    const double off_grid_tolerance = grid_tolerance(opt, noise_scale);
    const double diag = map.surface.diagonal(), max_dist = map.surface.max_distance();
    const double rounding = opt.position_digits > 0 ? 0.5 * std::pow(10.0, 1 - opt.position_digits) : 0.0;
    const std::vector<double> stretch = rounding > 0 ? triangle_stretch(map.in) : std::vector<double>{};
    r.surface_tolerance = max_dist;
    std::vector<Located> loc(mesh.positions.size());
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
        const auto& x = mesh.positions[v];
        if (!std::isfinite(x[0]) || !std::isfinite(x[1]) || !std::isfinite(x[2])) continue;
        const double round_v = rounding * std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
        r.max_rounding_tolerance = std::max(r.max_rounding_tolerance, round_v);
        const SurfacePoint hit = map.surface.locate(x, max_dist + round_v);
        std::array<double, 2> uv = hit.uv;
        loc[v].triangle = hit.triangle;
        if (hit.corner >= 0) {
            // Within the distance tolerance of an input vertex: the vertex's own UV, unless that
            // is off the grid and the point's is on it (a fine grid puts grid points closer to
            // a vertex than the tolerance: duck_miq_4 with UVs x 32, 0.0155 UV away).
            const auto& corner = map.in.uvs[3 * loc[v].triangle + static_cast<std::size_t>(hit.corner)];
            const auto off_grid = [](const std::array<double, 2>& p) {
                return std::max(std::abs(p[0] - std::nearbyint(p[0])), std::abs(p[1] - std::nearbyint(p[1])));
            };
            if (!(off_grid(corner) > off_grid_tolerance && off_grid(hit.uv) <= off_grid_tolerance)) {
                loc[v].on_vertex = map.in.triangles[loc[v].triangle][hit.corner];
                uv = corner;
            }
        }
        r.max_surface_distance = std::max(r.max_surface_distance, diag > 0 ? hit.distance / diag : 0.0);
        if (hit.distance > max_dist + round_v) {
            add_capped(out, ViolationKind::OffSurface,
                       "vertex " + std::to_string(v) + " is " + num(hit.distance) +
                           " (model units) from the input surface; tolerance " + num(max_dist + round_v) + " (" +
                           num(opt.distance_tolerance) + " of the diagonal" +
                           (round_v > 0 ? " + " + num(rounding) + " of |x| = " + num(round_v / rounding) + " for " +
                                              std::to_string(opt.position_digits) + " significant digits"
                                        : std::string()) +
                           ")",
                       static_cast<std::int64_t>(v));
            continue;
        }
        // Rounding moves the closest point by up to round_v (twice, across a crease), and its UV
        // by that times the map's stretch there (the located triangle and its neighbours).
        double uv_round = 0.0;
        if (rounding > 0 && hit.corner < 0) {
            double s = stretch[loc[v].triangle];
            for (int k = 0; k < 3; ++k) {
                const std::int64_t o = map.edges.opposite[3 * loc[v].triangle + static_cast<std::size_t>(k)];
                if (o >= 0) s = std::max(s, stretch[static_cast<std::size_t>(o / 3)]);
            }
            uv_round = 2 * s * round_v;
        }
        // The UV is interpolated in doubles from corner UVs as large as the map's translations
        // make them: a few units in the last place of the largest (2^-9 at 2^43) is rounding,
        // not distance from the grid point.
        double magnitude = 0.0;
        for (std::size_t k = 0; k < 3; ++k)
            for (const double c : map.in.uvs[3 * loc[v].triangle + k]) magnitude = std::max(magnitude, std::abs(c));
        const double uv_tol = off_grid_tolerance + uv_round + 8 * std::numeric_limits<double>::epsilon() * magnitude;
        const double gx = std::nearbyint(uv[0]), gy = std::nearbyint(uv[1]);
        const double off = std::max(std::abs(uv[0] - gx), std::abs(uv[1] - gy));
        // In a fold-over region the map a correct mesh follows may be a repaired one (moved within
        // the region, not the raw map given here): the vertex is judged on the surface only. Its
        // nearest grid point of the raw map stands for it in the face checks, which list a
        // failure of a face with such a corner as undecided.
        if (map.region_of[loc[v].triangle] >= 0) {
            FoldRegion& g = r.fold_regions[static_cast<std::size_t>(map.region_of[loc[v].triangle])];
            loc[v].surface_only = true;
            ++r.surface_only_vertices;
            ++g.vertices;
            if (!(off <= std::min(uv_tol, kMaxUvTolerance))) ++g.off_grid_vertices, ++r.off_grid_region_vertices;
            r.max_region_grid_distance = std::max(r.max_region_grid_distance, off);
            if (std::abs(gx) < 9e15 && std::abs(gy) < 9e15) {
                loc[v].grid = {static_cast<std::int64_t>(gx), static_cast<std::int64_t>(gy)};
                loc[v].ok = true;
            }
            continue;
        }
        r.max_grid_distance = std::max(r.max_grid_distance, off);
        if (!(off <= std::min(uv_tol, kMaxUvTolerance)) || !(std::abs(gx) < 9e15 && std::abs(gy) < 9e15)) {
            const std::string msg = "vertex " + std::to_string(v) + " maps to (" + num(uv[0]) + ", " + num(uv[1]) +
                                    ") in the chart of input triangle " + std::to_string(loc[v].triangle) + ", " +
                                    num(off) + " from the nearest integer grid point; tolerance " + num(uv_tol) +
                                    " (UV)";
            if (uv_tol > kMaxUvTolerance && off <= uv_tol) {
                add_capped(r.undecided, ViolationKind::NotOnGridPoint,
                           msg + " (the positions' precision cannot place it on one grid point)",
                           static_cast<std::int64_t>(v));
                if (std::abs(gx) < 9e15 && std::abs(gy) < 9e15) {
                    loc[v].grid = {static_cast<std::int64_t>(gx), static_cast<std::int64_t>(gy)};
                    loc[v].undecided = true;
                    loc[v].spread = static_cast<int>(std::ceil(std::min(uv_tol, 2.0) + 0.5));
                }
            } else
                add_capped(out, ViolationKind::NotOnGridPoint, msg, static_cast<std::int64_t>(v));
            continue;
        }
        loc[v].grid = {static_cast<std::int64_t>(gx), static_cast<std::int64_t>(gy)};
        loc[v].ok = true;
    }
    return loc;
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
    // Faces with a corner in a fold-over region are judged on the surface only: check_face_cells
    // lists their failures as undecided.
    for (const auto& face : mesh.faces) {
        bool surface_only = false;
        for (int v : face)
            surface_only = surface_only || (v >= 0 && static_cast<std::size_t>(v) < loc.size() &&
                                            loc[static_cast<std::size_t>(v)].surface_only);
        r.surface_only_faces += surface_only;
    }
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
    // And cell by cell, away from the fold-overs (as far as their regions reach, whether or not
    // the vertices there are judged on the surface only): every cell the map covers once is a
    // face, its corners vertices.
    const std::vector<char> far_from_folds =
        far_from_fold_overs(in, map.edges, map.fold_over, near_fold_overs(in, map.fold_over, kFoldRegionRings));
    std::vector<FaceCell> uncovered;
    check_coverage(map, mesh, loc, far_from_folds, opt.uv_tolerance, thread_count(opt.threads), r, out, uncovered);
    // The whole mesh's violations name the unit cells no face covers, with the triangle whose
    // chart holds each.
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

} // namespace qex::verify_detail

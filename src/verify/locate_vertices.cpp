// The located mode's first step: every output vertex located on the input surface (its closest
// point, surface.cpp) and read on the map: its UV in the chart of the triangle it lies in, and
// the nearest integer grid point, within tolerances that grow with the noise of the map and the
// precision of the positions. A vertex off the surface or off its grid point is reported here.
#include "checker.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
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

/// A located point's UV and its nearest grid point (as doubles), and how far apart they are
/// (the larger coordinate difference).
struct GridReading {
    std::array<double, 2> uv;
    double gx, gy, off;
    /// The grid point is one the checker compares (below 9e15 in magnitude).
    bool in_range() const { return std::abs(gx) < 9e15 && std::abs(gy) < 9e15; }
    GridPoint grid() const { return {static_cast<std::int64_t>(gx), static_cast<std::int64_t>(gy)}; }
};

/// Locates the output vertices one at a time, with the tolerances that hold for them all.
class Locator {
public:
    Locator(const LocatedMap& map, const QuadMesh& mesh, const VerifyOptions& opt, double noise_scale);
    /// Locates vertex v (its position finite) into L; reports it when off the surface or off the grid.
    void locate(std::size_t v, Located& L, VerifyResult& r, std::vector<Violation>& out) const;

private:
    /// The closest point's UV, or the UV of the input vertex it lies on (then L.on_vertex).
    std::array<double, 2> surface_uv(const SurfacePoint& hit, Located& L) const;
    /// The UV tolerance for the point `hit` (in L's triangle), whose model coordinates rounding
    /// may move by round_v.
    double uv_tolerance(const Located& L, const SurfacePoint& hit, double round_v) const;
    /// Reports vertex v at `distance` from the surface, beyond the tolerance.
    void report_off_surface(std::size_t v, double distance, double round_v, std::vector<Violation>& out) const;
    /// A vertex in a fold-over region: counted there, judged on the surface only.
    void judge_in_region(std::size_t v, Located& L, const GridReading& g, double uv_tol, VerifyResult& r) const;
    /// Reports vertex v off its grid point: undecided where the positions' precision cannot
    /// place it, else a violation.
    void report_off_grid(std::size_t v, Located& L, const GridReading& g, double uv_tol, VerifyResult& r,
                         std::vector<Violation>& out) const;

    const LocatedMap& map_;
    const QuadMesh& mesh_;
    const VerifyOptions& opt_;
    double off_grid_tolerance_, diag_, max_dist_;
    double rounding_;             ///< per unit of |x|: what rounding to opt.position_digits moves a coordinate
    std::vector<double> stretch_; ///< per input triangle (triangle_stretch), when rounding_ > 0
};

Locator::Locator(const LocatedMap& map, const QuadMesh& mesh, const VerifyOptions& opt, double noise_scale)
    : map_(map),
      mesh_(mesh),
      opt_(opt),
      off_grid_tolerance_(grid_tolerance(opt, noise_scale)),
      diag_(map.surface.diagonal()),
      max_dist_(map.surface.max_distance()),
      rounding_(opt.position_digits > 0 ? 0.5 * std::pow(10.0, 1 - opt.position_digits) : 0.0),
      stretch_(rounding_ > 0 ? triangle_stretch(map.in) : std::vector<double>{}) {}

void Locator::locate(std::size_t v, Located& L, VerifyResult& r, std::vector<Violation>& out) const {
    const auto& x = mesh_.positions[v];
    const double round_v = rounding_ * std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
    r.max_rounding_tolerance = std::max(r.max_rounding_tolerance, round_v);
    const SurfacePoint hit = map_.surface.locate(x, max_dist_ + round_v);
    L.triangle = hit.triangle;
    const std::array<double, 2> uv = surface_uv(hit, L);
    r.max_surface_distance = std::max(r.max_surface_distance, diag_ > 0 ? hit.distance / diag_ : 0.0);
    if (hit.distance > max_dist_ + round_v) {
        report_off_surface(v, hit.distance, round_v, out);
        return;
    }
    const double uv_tol = uv_tolerance(L, hit, round_v);
    const double gx = std::nearbyint(uv[0]), gy = std::nearbyint(uv[1]);
    const GridReading g{uv, gx, gy, std::max(std::abs(uv[0] - gx), std::abs(uv[1] - gy))};
    // In a fold-over region the map a correct mesh follows may be a repaired one (moved within
    // the region, not the raw map given here): the vertex is judged on the surface only. Its
    // nearest grid point of the raw map stands for it in the face checks, which list a
    // failure of a face with such a corner as undecided.
    if (map_.region_of[L.triangle] >= 0) {
        judge_in_region(v, L, g, uv_tol, r);
        return;
    }
    r.max_grid_distance = std::max(r.max_grid_distance, g.off);
    if (!(g.off <= std::min(uv_tol, kMaxUvTolerance)) || !g.in_range()) {
        report_off_grid(v, L, g, uv_tol, r, out);
        return;
    }
    L.grid = g.grid();
    L.ok = true;
}

std::array<double, 2> Locator::surface_uv(const SurfacePoint& hit, Located& L) const {
    std::array<double, 2> uv = hit.uv;
    if (hit.corner >= 0) {
        // Within the distance tolerance of an input vertex: the vertex's own UV, unless that
        // is off the grid and the point's is on it (a fine grid puts grid points closer to
        // a vertex than the tolerance: duck_miq_4 with UVs x 32, 0.0155 UV away).
        const auto& corner = map_.in.uvs[3 * L.triangle + static_cast<std::size_t>(hit.corner)];
        const auto off_grid = [](const std::array<double, 2>& p) {
            return std::max(std::abs(p[0] - std::nearbyint(p[0])), std::abs(p[1] - std::nearbyint(p[1])));
        };
        if (!(off_grid(corner) > off_grid_tolerance_ && off_grid(hit.uv) <= off_grid_tolerance_)) {
            L.on_vertex = map_.in.triangles[L.triangle][hit.corner];
            uv = corner;
        }
    }
    return uv;
}

double Locator::uv_tolerance(const Located& L, const SurfacePoint& hit, double round_v) const {
    // Rounding moves the closest point by up to round_v (twice, across a crease), and its UV
    // by that times the map's stretch there (the located triangle and its neighbours).
    double uv_round = 0.0;
    if (rounding_ > 0 && hit.corner < 0) {
        double s = stretch_[L.triangle];
        for (int k = 0; k < 3; ++k) {
            const std::int64_t o = map_.edges.opposite[3 * L.triangle + static_cast<std::size_t>(k)];
            if (o >= 0) s = std::max(s, stretch_[static_cast<std::size_t>(o / 3)]);
        }
        uv_round = 2 * s * round_v;
    }
    // The UV is interpolated in doubles from corner UVs as large as the map's translations
    // make them: a few units in the last place of the largest (2^-9 at 2^43) is rounding,
    // not distance from the grid point.
    double magnitude = 0.0;
    for (std::size_t k = 0; k < 3; ++k)
        for (const double c : map_.in.uvs[3 * L.triangle + k]) magnitude = std::max(magnitude, std::abs(c));
    return off_grid_tolerance_ + uv_round + 8 * std::numeric_limits<double>::epsilon() * magnitude;
}

void Locator::report_off_surface(std::size_t v, double distance, double round_v, std::vector<Violation>& out) const {
    add_capped(out, ViolationKind::OffSurface,
               "vertex " + std::to_string(v) + " is " + num(distance) +
                   " (model units) from the input surface; tolerance " + num(max_dist_ + round_v) + " (" +
                   num(opt_.distance_tolerance) + " of the diagonal" +
                   (round_v > 0 ? " + " + num(rounding_) + " of |x| = " + num(round_v / rounding_) + " for " +
                                      std::to_string(opt_.position_digits) + " significant digits"
                                : std::string()) +
                   ")",
               static_cast<std::int64_t>(v));
}

void Locator::judge_in_region(std::size_t v, Located& L, const GridReading& g, double uv_tol, VerifyResult& r) const {
    FoldRegion& region = r.fold_regions[static_cast<std::size_t>(map_.region_of[L.triangle])];
    L.surface_only = true;
    ++r.surface_only_vertices;
    ++region.vertices;
    if (!(g.off <= std::min(uv_tol, kMaxUvTolerance))) {
        // Off the raw map's grid point: a repaired map may have its grid point here, or the
        // vertex slid off its own. Not a violation: listed as undecided.
        ++region.off_grid_vertices, ++r.off_grid_region_vertices;
        add_capped(r.undecided, ViolationKind::NotOnGridPoint,
                   "vertex " + std::to_string(v) + " maps to (" + num(g.uv[0]) + ", " + num(g.uv[1]) +
                       ") in the chart of input triangle " + std::to_string(L.triangle) + ", " + num(g.off) +
                       " from the nearest integer grid point, in fold-over region F" +
                       std::to_string(map_.region_of[L.triangle] + 1) +
                       " (judged on the surface only: a repaired map may have its grid point here)",
                   static_cast<std::int64_t>(v));
    }
    r.max_region_grid_distance = std::max(r.max_region_grid_distance, g.off);
    if (g.in_range()) {
        L.grid = g.grid();
        L.ok = true;
    }
}

void Locator::report_off_grid(std::size_t v, Located& L, const GridReading& g, double uv_tol, VerifyResult& r,
                              std::vector<Violation>& out) const {
    const std::string msg = "vertex " + std::to_string(v) + " maps to (" + num(g.uv[0]) + ", " + num(g.uv[1]) +
                            ") in the chart of input triangle " + std::to_string(L.triangle) + ", " + num(g.off) +
                            " from the nearest integer grid point; tolerance " + num(uv_tol) + " (UV)";
    if (uv_tol > kMaxUvTolerance && g.off <= uv_tol) {
        add_capped(r.undecided, ViolationKind::NotOnGridPoint,
                   msg + " (the positions' precision cannot place it on one grid point)", static_cast<std::int64_t>(v));
        if (g.in_range()) {
            L.grid = g.grid();
            L.undecided = true;
            L.spread = static_cast<int>(std::ceil(std::min(uv_tol, 2.0) + 0.5));
        }
    } else
        add_capped(out, ViolationKind::NotOnGridPoint, msg, static_cast<std::int64_t>(v));
}

} // namespace

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

double grid_tolerance(const VerifyOptions& opt, double noise_scale) {
    return std::min(opt.uv_tolerance * std::max(1.0, noise_scale), std::max(opt.uv_tolerance, 0.1));
}

std::vector<Located> locate_vertices(const LocatedMap& map, const QuadMesh& mesh, const VerifyOptions& opt,
                                     double noise_scale, VerifyResult& r, std::vector<Violation>& out) {
    const Locator locator(map, mesh, opt, noise_scale);
    r.surface_tolerance = map.surface.max_distance();
    std::vector<Located> loc(mesh.positions.size());
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
        const auto& x = mesh.positions[v];
        if (!std::isfinite(x[0]) || !std::isfinite(x[1]) || !std::isfinite(x[2])) continue;
        locator.locate(v, loc[v], r, out);
    }
    return loc;
}

} // namespace qex::verify_detail

// The face check's corridors (face_cells.h, kCorridor): an edge of a face carried through the
// triangles near it, so that its end's grid point is read along a path homotopic to the edge;
// and the 3D distances that decide which triangles lie near it.
#include "face_cells.h"

#include <algorithm>
#include <cmath>

namespace qex::verify_detail::face_cells {
namespace {

using Vec = std::array<double, 3>;
Vec sub(const Vec& x, const Vec& y) { return {x[0] - y[0], x[1] - y[1], x[2] - y[2]}; }
double dot(const Vec& x, const Vec& y) { return x[0] * y[0] + x[1] * y[1] + x[2] * y[2]; }
Vec cross(const Vec& x, const Vec& y) {
    return {x[1] * y[2] - x[2] * y[1], x[2] * y[0] - x[0] * y[2], x[0] * y[1] - x[1] * y[0]};
}
double norm(const Vec& x) { return std::sqrt(dot(x, x)); }

/// The distance from x to the segment ab.
double segment_distance(const Vec& x, const Vec& a, const Vec& b) {
    const Vec ab = sub(b, a), ax = sub(x, a);
    const double len2 = dot(ab, ab);
    const double s = len2 > 0 ? std::clamp(dot(ab, ax) / len2, 0.0, 1.0) : 0.0;
    return norm({ax[0] - s * ab[0], ax[1] - s * ab[1], ax[2] - s * ab[2]});
}

/// The distance between the segments pq and rs (the closest points by clamped parameters).
double segments_distance(const Vec& p, const Vec& q, const Vec& r, const Vec& s) {
    const Vec d1 = sub(q, p), d2 = sub(s, r), w = sub(p, r);
    const double a = dot(d1, d1), e = dot(d2, d2), f = dot(d2, w);
    if (a <= 0 || e <= 0) return std::min(segment_distance(p, r, s), segment_distance(r, p, q));
    const double b = dot(d1, d2), c = dot(d1, w), den = a * e - b * b;
    double sc = den > 0 ? std::clamp((b * f - c * e) / den, 0.0, 1.0) : 0.0;
    double tc = (b * sc + f) / e;
    if (tc < 0)
        tc = 0, sc = std::clamp(-c / a, 0.0, 1.0);
    else if (tc > 1)
        tc = 1, sc = std::clamp((b - c) / a, 0.0, 1.0);
    return norm(sub({p[0] + sc * d1[0], p[1] + sc * d1[1], p[2] + sc * d1[2]},
                    {r[0] + tc * d2[0], r[1] + tc * d2[1], r[2] + tc * d2[2]}));
}

/// The distance from x to the triangle p (its plane where x projects inside, else its edges).
double point_triangle_distance(const Vec& x, const std::array<Vec, 3>& p) {
    const Vec n = cross(sub(p[1], p[0]), sub(p[2], p[0]));
    const double nn = dot(n, n);
    if (nn > 0) {
        bool inside = true;
        for (int k = 0; k < 3; ++k) inside = inside && dot(cross(sub(p[(k + 1) % 3], p[k]), sub(x, p[k])), n) >= 0;
        if (inside) return std::abs(dot(sub(x, p[0]), n)) / std::sqrt(nn);
    }
    double d = HUGE_VAL;
    for (int k = 0; k < 3; ++k) d = std::min(d, segment_distance(x, p[k], p[(k + 1) % 3]));
    return d;
}

/// The distance from the segment ab to the triangle p: 0 where the segment crosses it, else the
/// least of its ends' distances and its distances to the triangle's edges.
double segment_triangle_distance(const Vec& a, const Vec& b, const std::array<Vec, 3>& p) {
    const Vec n = cross(sub(p[1], p[0]), sub(p[2], p[0]));
    const double da = dot(sub(a, p[0]), n), db = dot(sub(b, p[0]), n);
    if ((da <= 0 && db >= 0) || (da >= 0 && db <= 0)) {
        if (da != db) {
            const double s = da / (da - db);
            const Vec x{a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1]), a[2] + s * (b[2] - a[2])};
            bool inside = true;
            for (int k = 0; k < 3; ++k) inside = inside && dot(cross(sub(p[(k + 1) % 3], p[k]), sub(x, p[k])), n) >= 0;
            if (inside) return 0.0;
        }
    }
    double d = std::min(point_triangle_distance(a, p), point_triangle_distance(b, p));
    for (int k = 0; k < 3; ++k) d = std::min(d, segments_distance(a, b, p[k], p[(k + 1) % 3]));
    return d;
}

} // namespace

bool FaceJudge::in_corridor(std::uint32_t t, const std::array<double, 3>& a, const std::array<double, 3>& b,
                            double rho) const {
    // Cheap rejection by the centroid, then the distance from the segment to the triangle.
    if (segment_distance(centre_[t], a, b) > rho + radius_[t]) return false;
    std::array<std::array<double, 3>, 3> p;
    for (int k = 0; k < 3; ++k) p[k] = in_.positions[static_cast<std::size_t>(in_.triangles[t][k])];
    return segment_triangle_distance(a, b, p) <= rho;
}

bool FaceJudge::along_edge(int a, int b, Edge& e) {
    const Located &A = loc_[static_cast<std::size_t>(a)], &B = loc_[static_cast<std::size_t>(b)];
    const auto &pa = mesh_.positions[static_cast<std::size_t>(a)], &pb = mesh_.positions[static_cast<std::size_t>(b)];
    const double rho = kCorridor * std::sqrt((pb[0] - pa[0]) * (pb[0] - pa[0]) + (pb[1] - pa[1]) * (pb[1] - pa[1]) +
                                             (pb[2] - pa[2]) * (pb[2] - pa[2]));
    // Cones at the ends: their fans are cut (no path crosses an edge at them).
    const std::int64_t cone_a =
        A.on_vertex >= 0 && map_.singular[static_cast<std::size_t>(A.on_vertex)] ? A.on_vertex : -1;
    const std::int64_t cone_b =
        B.on_vertex >= 0 && map_.singular[static_cast<std::size_t>(B.on_vertex)] ? B.on_vertex : -1;
    if (!flood_corridor(A.triangle, pa, pb, rho, cone_a, cone_b)) return false;
    return read_end(B, cone_b, e);
}

bool FaceJudge::flood_corridor(std::uint32_t t0, const std::array<double, 3>& pa, const std::array<double, 3>& pb,
                               double rho, std::int64_t cone_a, std::int64_t cone_b) {
    if (++cgeneration_ == 0) {
        std::fill(cstamp_.begin(), cstamp_.end(), 0);
        cgeneration_ = 1;
    }
    if (map_.fold_over[t0]) return false;
    cstamp_[t0] = cgeneration_;
    to_start_[t0] = Transition{};
    queue_.assign(1, t0);
    for (std::size_t head = 0; head < queue_.size(); ++head) {
        if (queue_.size() > kCorridorBudget) return false;
        const std::uint32_t t = queue_[head];
        for (std::size_t k = 0; k < 3; ++k) {
            const std::size_t c = 3 * t + k;
            const int u = in_.triangles[t][k], w = in_.triangles[t][(k + 1) % 3];
            if (u == cone_a || w == cone_a || u == cone_b || w == cone_b) continue; // a cut fan
            const std::int64_t o = map_.edges.opposite[c];
            if (o < 0) {
                if (map_.edges.partner[c] >= 0) return false; // a crossing without a known transition
                continue;                                     // the boundary
            }
            const auto n = static_cast<std::uint32_t>(o / 3);
            if (!in_corridor(n, pa, pb, rho)) continue;
            if (map_.fold_over[n]) return false;
            Transition m;
            if (!compose(to_start_[t], map_.edges.across[static_cast<std::size_t>(o)], m)) return false;
            if (cstamp_[n] == cgeneration_) {
                if (!same(m, to_start_[n])) return false; // a cone (or an inconsistent loop) inside
                continue;
            }
            cstamp_[n] = cgeneration_;
            to_start_[n] = m;
            queue_.push_back(n);
        }
    }
    return true;
}

bool FaceJudge::read_end(const Located& B, std::int64_t cone_b, Edge& e) const {
    // b read in its own triangle, or at a cone, in any triangle of its fan the corridor reached.
    e.b_on_cone = cone_b >= 0;
    if (cone_b < 0) {
        if (cstamp_[B.triangle] != cgeneration_) return false;
        e.m = to_start_[B.triangle];
        e.b = map_point(e.m, B.grid);
        return true;
    }
    for (const std::uint32_t t : queue_)
        for (std::size_t k = 0; k < 3; ++k)
            if (in_.triangles[t][k] == cone_b) {
                const auto& uv = in_.uvs[3 * t + k];
                e.m = to_start_[t];
                e.b = map_point(e.m, {static_cast<std::int64_t>(std::nearbyint(uv[0])),
                                      static_cast<std::int64_t>(std::nearbyint(uv[1]))});
                return true;
            }
    return false;
}
} // namespace qex::verify_detail::face_cells

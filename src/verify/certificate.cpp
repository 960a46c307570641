// The certificate route: a mesh of qex's own, read back without provenance, judged on the
// repaired map it was extracted from (qex::Certificate, written by `qex extract --certificate`).
// The certificate is checked first against the given map, with the checker's own code and
// exact decisions: the same surface; outside its listed triangles the given UVs (up to the
// located mode's UV tolerance, the noise sanitization removes) and orientations; its listed
// triangles positive (CGAL's exact orientation); the given map's transitions and singularities
// (certificate_charts.cpp) and windings; an exact integer-grid map with its singularities on
// grid points (map_check.cpp's check, as on QuadMesh::map_uvs). Only then is the mesh located
// on it (check_located.cpp): its fold-over regions and footprints are where it still folds.
#include "certificate.h"
#include "cones.h"
#include "grid.h"
#include "parallel.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace qex {
namespace verify_detail {
namespace {

/// The exact orientation of triangle t in U.
CGAL::Orientation orientation(const UVs& U, std::size_t t) {
    using P = CGAL::Epick::Point_2;
    return CGAL::orientation(P(U[3 * t][0], U[3 * t][1]), P(U[3 * t + 1][0], U[3 * t + 1][1]),
                             P(U[3 * t + 2][0], U[3 * t + 2][1]));
}

/// The same positions (bit for bit: the certificate is written with every digit) and triangles,
/// and finite UVs, 3 per triangle. Returns whether the certificate's surface is the given one.
bool same_surface(const Input& given, const Input& cert, std::vector<Violation>& out) {
    const std::size_t nt = given.triangles.size();
    if (cert.positions.size() != given.positions.size() || cert.triangles.size() != nt || cert.uvs.size() != 3 * nt) {
        mismatch(out,
                 std::to_string(cert.positions.size()) + " vertices and " + std::to_string(cert.triangles.size()) +
                     " triangles (" + std::to_string(cert.uvs.size()) + " corner UVs), the map has " +
                     std::to_string(given.positions.size()) + " and " + std::to_string(nt),
                 -1);
        return false;
    }
    const std::size_t before = out.size();
    std::vector<char> moved(given.positions.size(), 0);
    for (std::size_t v = 0; v < moved.size(); ++v) moved[v] = cert.positions[v] != given.positions[v];
    for (std::size_t t = 0; t < nt; ++t) {
        const auto& tri = given.triangles[t];
        const auto T = static_cast<std::int64_t>(t);
        if (cert.triangles[t] != tri)
            mismatch(out, "triangle " + std::to_string(t) + " has other vertices than the map's", T);
        for (int v : tri)
            if (v >= 0 && static_cast<std::size_t>(v) < moved.size() && moved[static_cast<std::size_t>(v)]) {
                moved[static_cast<std::size_t>(v)] = 0; // named once, at its first triangle
                mismatch(out, "input vertex " + std::to_string(v) + " lies elsewhere than in the map", T,
                         {Place{PlaceKind::InputVertex, {v}}});
            }
        for (std::size_t k = 0; k < 3; ++k)
            if (!std::isfinite(cert.uvs[3 * t + k][0]) || !std::isfinite(cert.uvs[3 * t + k][1])) {
                mismatch(out, "triangle " + std::to_string(t) + " has a non-finite UV", T);
                break;
            }
    }
    return out.size() == before;
}

/// Per triangle whether the certificate lists it; a list not sorted, not distinct or out of
/// range is a mismatch.
std::vector<char> listed_triangles(const Certificate& c, std::size_t nt, std::vector<Violation>& out) {
    std::vector<char> listed(nt, 0);
    std::int64_t previous = -1;
    for (const std::int32_t t : c.repaired) {
        if (t <= previous || static_cast<std::size_t>(t) >= nt) {
            mismatch(out,
                     "the repaired triangles are not a sorted list of distinct triangles of the map (at " +
                         std::to_string(t) + ")",
                     t >= 0 && static_cast<std::size_t>(t) < nt ? t : -1);
            continue;
        }
        previous = t;
        listed[static_cast<std::size_t>(t)] = 1;
    }
    return listed;
}

/// Triangle t has an edge no longer than `tol` in UV (inf-norm): a sliver whose orientation a
/// move within the tolerance may decide either way.
bool has_short_edge(const UVs& U, std::size_t t, double tol) {
    for (std::size_t k = 0; k < 3; ++k) {
        const auto &a = U[3 * t + k], &b = U[3 * t + (k + 1) % 3];
        if (std::max(std::abs(a[0] - b[0]), std::abs(a[1] - b[1])) <= tol) return true;
    }
    return false;
}

/// Per input vertex: its fan holds a triangle the given map has flipped or degenerate (exactly).
std::vector<char> folded_vertices(const Input& given) {
    std::vector<char> folded(given.positions.size(), 0);
    for (std::size_t t = 0; t < given.triangles.size(); ++t)
        if (orientation(given.uvs, t) != CGAL::LEFT_TURN)
            for (int v : given.triangles[t]) folded[static_cast<std::size_t>(v)] = 1;
    return folded;
}

/// Per triangle: collapsed, i.e. not listed, its UVs exactly the given map's, and one of its
/// edges no longer than `tol` in UV (inf-norm; extraction collapses edges of zero length once
/// sanitized, and keeps no chart for the triangle: its transitions are not judged).
std::vector<char> collapsed_triangles(const UVs& given, const UVs& U, const std::vector<char>& listed, double tol) {
    std::vector<char> collapsed(listed.size(), 0);
    for (std::size_t t = 0; t < listed.size(); ++t) {
        if (listed[t]) continue;
        bool same = true;
        for (std::size_t k = 0; k < 3; ++k) same = same && U[3 * t + k] == given[3 * t + k];
        collapsed[t] = same && has_short_edge(given, t, tol);
    }
    return collapsed;
}

/// Every listed triangle positively oriented (exactly); outside them every corner's UV within
/// `tol` (inf-norm) of the given map's, and no triangle flipped (negative, exactly) that the
/// given map has positive or degenerate, but a sliver (an edge within `tol`: sanitization's
/// rounding may decide its orientation either way).
void check_moves(const UVs& given, const UVs& U, const std::vector<char>& listed, double tol,
                 std::vector<Violation>& out) {
    for (std::size_t t = 0; t < listed.size(); ++t) {
        if (listed[t]) {
            if (orientation(U, t) != CGAL::LEFT_TURN)
                mismatch(out, "repaired triangle " + std::to_string(t) + " is not positively oriented",
                         static_cast<std::int64_t>(t));
            continue;
        }
        const auto T = static_cast<std::int64_t>(t);
        double moved = 0;
        for (std::size_t c = 3 * t; c < 3 * t + 3; ++c)
            moved = std::max({moved, std::abs(U[c][0] - given[c][0]), std::abs(U[c][1] - given[c][1])});
        if (!(moved <= tol)) {
            mismatch(out,
                     "triangle " + std::to_string(t) + " is not listed as repaired, but a UV of it moved by " +
                         std::to_string(moved) + " (more than the UV tolerance " + std::to_string(tol) + ")",
                     T);
            continue;
        }
        if (orientation(U, t) == CGAL::RIGHT_TURN && orientation(given, t) != CGAL::RIGHT_TURN &&
            !has_short_edge(given, t, tol))
            mismatch(out,
                     "triangle " + std::to_string(t) + " is flipped, but not listed as repaired nor flipped in the map",
                     T);
    }
}

/// At every vertex of a listed triangle whose fan in the given map holds no flipped or
/// degenerate triangle (exactly), the certificate winds as the given map: the same number of
/// quarter turns (its angle sum, rounded; the same valence, or boundary corner). Not judged: a
/// singularity the certificate cancels (`cancelled`, check_charts), a vertex of a collapsed
/// triangle (its cone holds the collapsed edge's other end), and where the given map's
/// sum is no whole number of quarter turns (within kQuarterTurnSlack) or extreme (at most one
/// quarter turn, or eight and more: known modulo a whole turn, as the located mode reads it).
/// `sum_given`: the given map's angle sums (angle_sums).
void check_windings(const Input& given, const UVs& U, const std::vector<char>& listed, const std::vector<char>& folded,
                    const std::vector<char>& collapsed, const std::vector<char>& cancelled,
                    const std::vector<double>& sum_given, std::vector<Violation>& out) {
    const std::size_t nv = given.positions.size();
    const std::vector<double> sum_cert = angle_sums(given, U);
    std::vector<char> touched(nv, 0);
    std::vector<std::int64_t> first_listed(nv, -1);
    for (std::size_t c = 0; c < U.size(); ++c) {
        const std::size_t t = c / 3;
        const auto v = static_cast<std::size_t>(given.triangles[t][c % 3]);
        if (listed[t] && !touched[v]) touched[v] = 1, first_listed[v] = static_cast<std::int64_t>(t);
    }
    for (std::size_t t = 0; t < collapsed.size(); ++t) // a collapsed edge's ends are one cone, their sums split
        if (collapsed[t])
            for (int v : given.triangles[t]) touched[static_cast<std::size_t>(v)] = 0;
    constexpr double kQuarter = M_PI / 2;
    for (std::size_t v = 0; v < nv; ++v) {
        if (!touched[v] || folded[v] || cancelled[v]) continue;
        const double q = sum_given[v] / kQuarter;
        const long n_given = std::lround(q), n_cert = std::lround(sum_cert[v] / kQuarter);
        if (!(std::abs(q - static_cast<double>(n_given)) <= kQuarterTurnSlack) || n_given <= 1 || n_given >= 8)
            continue;
        if (n_given != n_cert || !std::isfinite(sum_cert[v]))
            mismatch(out,
                     "input vertex " + std::to_string(v) + " winds " + std::to_string(n_cert * 90) +
                         " degrees, in the map " + std::to_string(n_given * 90) + " (its fan there holds no fold)",
                     first_listed[v], {Place{PlaceKind::InputVertex, {static_cast<std::int64_t>(v)}}});
    }
}

/// The certificate's map as the checker judges a mesh's own (check_map): an exact integer-grid
/// map, singularities on grid points, its listed triangles positive, no new branch point; its
/// collapsed triangles left out (NaN). Each violation becomes a CertificateMismatch.
void check_as_map(const Input& given, const UVs& U, const Certificate& c, const std::vector<char>& collapsed,
                  int threads, std::vector<Violation>& out) {
    std::vector<std::size_t> offset(given.triangles.size() + 1);
    std::vector<int> corners;
    corners.reserve(3 * given.triangles.size());
    for (std::size_t t = 0; t < given.triangles.size(); ++t) {
        offset[t + 1] = 3 * (t + 1);
        corners.insert(corners.end(), given.triangles[t].begin(), given.triangles[t].end());
    }
    EdgePairs pairs;
    std::vector<char> single_fan;
    analyse(given.positions.size(), offset, corners, nullptr, threads, &pairs, &single_fan);
    QuadMesh as_mesh;
    as_mesh.map_uvs = U;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (std::size_t t = 0; t < collapsed.size(); ++t)
        if (collapsed[t]) as_mesh.map_uvs[3 * t] = as_mesh.map_uvs[3 * t + 1] = as_mesh.map_uvs[3 * t + 2] = {nan, nan};
    as_mesh.map_repaired = c.repaired;
    VerifyResult scratch;
    std::vector<Violation> found;
    check_map(given, as_mesh, pairs, single_fan, threads, scratch, found);
    for (const Violation& v : found) {
        // Those of an input vertex (a singularity off the grid, a new branch point) name its
        // first triangle, the vertex as their place.
        const bool of_vertex = v.kind == ViolationKind::SingularityOffGrid || v.message.rfind("input vertex ", 0) == 0;
        std::int64_t t = v.element;
        std::vector<Place> places;
        if (of_vertex && v.element >= 0) {
            places.push_back({PlaceKind::InputVertex, {v.element}});
            t = static_cast<std::int64_t>(std::find(corners.begin(), corners.end(), v.element) - corners.begin()) / 3;
        }
        mismatch(out, std::string(to_string(v.kind)) + ": " + v.message, t, std::move(places));
    }
}

} // namespace

// check_certificate (checker.h).
std::vector<Violation> check_certificate(const Input& given, const Certificate& c, double tol, int threads) {
    std::vector<Violation> out;
    if (!same_surface(given, c.map, out)) return out;
    const UVs& U = c.map.uvs;
    const std::vector<char> listed = listed_triangles(c, given.triangles.size(), out);
    const std::vector<char> collapsed = collapsed_triangles(given.uvs, U, listed, tol);
    check_moves(given.uvs, U, listed, tol, out);
    const std::vector<char> folded = folded_vertices(given);
    const std::vector<double> given_sums = angle_sums(given, given.uvs);
    const std::vector<char> cancelled = check_charts(given, U, listed, collapsed, folded, given_sums, tol, out);
    check_windings(given, U, listed, folded, collapsed, cancelled, given_sums, out);
    if (out.empty()) check_as_map(given, U, c, collapsed, threads, out);
    return out;
}

} // namespace verify_detail

Certificate make_certificate(const Input& input, const QuadMesh& mesh) {
    Certificate c;
    if (mesh.map_uvs.size() != input.uvs.size() || input.uvs.empty()) return c;
    c.grid_scale = mesh.grid_scale;
    c.repaired = mesh.map_repaired;
    c.map.positions = input.positions;
    c.map.triangles = input.triangles;
    c.map.uvs = mesh.map_uvs;
    // A triangle extraction removed (collapsed: NaN) keeps the given UVs, times the scale.
    for (std::size_t i = 0; i < c.map.uvs.size(); ++i)
        if (!std::isfinite(c.map.uvs[i][0]) || !std::isfinite(c.map.uvs[i][1]))
            c.map.uvs[i] = {input.uvs[i][0] * mesh.grid_scale, input.uvs[i][1] * mesh.grid_scale};
    return c;
}

VerifyResult verify(const Input& input, const QuadMesh& mesh, const Certificate& certificate,
                    const VerifyOptions& options) {
    QuadMesh judged = mesh; // located mode: what the mesh carries besides its faces is not judged
    judged.provenance.clear();
    judged.map_uvs.clear();
    judged.map_repaired.clear();
    const int k = certificate.grid_scale;
    std::vector<Violation> bad;
    bool map_ok = input.uvs.size() == 3 * input.triangles.size();
    for (const auto& tri : input.triangles)
        for (int v : tri) map_ok = map_ok && v >= 0 && static_cast<std::size_t>(v) < input.positions.size();
    if (!map_ok) {
        verify_detail::mismatch(bad, "the map has no valid triangles with 3 UVs each to check it against", -1);
    } else if (k < 1 || k > (1 << 20) || (k & (k - 1)) != 0) {
        verify_detail::mismatch(bad, "grid scale " + std::to_string(k) + " is not a power of two up to 2^20", -1);
    } else {
        Input given = input;
        for (auto& uv : given.uvs) uv = {uv[0] * k, uv[1] * k}; // exact: a power of two
        VerifyOptions o = options;
        o.uv_tolerance = o.uv_tolerance >= 0 ? std::min(o.uv_tolerance, 1.0) : 0.0;
        bad = verify_detail::check_certificate(given, certificate, verify_detail::grid_tolerance(o, k),
                                               verify_detail::thread_count(o.threads));
    }
    if (!bad.empty()) { // judged on the given map, the certificate's faults first
        judged.grid_scale = k;
        VerifyResult r = verify(input, judged, options);
        r.violations.insert(r.violations.begin(), bad.begin(), bad.end());
        r.valid = false;
        return r;
    }
    Input on = certificate.map;
    on.valences = input.valences;
    on.feature_edges = input.feature_edges;
    judged.grid_scale = 1;
    VerifyResult r = verify(on, judged, options);
    r.on_certificate = true;
    r.certificate_triangles = static_cast<std::int64_t>(certificate.repaired.size());
    return r;
}

} // namespace qex

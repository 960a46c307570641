// The map a mesh of qex's own claims to come from (`mesh.map_uvs`, the sanitized map), and its
// vertices' provenance: the map must be an exact integer-grid map, and every vertex's grid
// point must lie on the input element it names. Everything is decided exactly: the transitions
// with exact double sums (TwoSum), the provenance with CGAL's exact predicates.
#include "checker.h"
#include "grid.h"
#include "parallel.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <string>

namespace qex::verify_detail {

// grid_automorphism (checker.h).
int grid_automorphism(const std::array<double, 2>& a, const std::array<double, 2>& b, const std::array<double, 2>& a2,
                      const std::array<double, 2>& b2) {
    // Necessary: R (b - a) == b2 - a2 in doubles (a rotation commutes with the rounding of a
    // difference), which leaves one candidate for an edge of non-zero length.
    const std::array<double, 2> d{b[0] - a[0], b[1] - a[1]}, d2{b2[0] - a2[0], b2[1] - a2[1]};
    for (int rr = 0; rr < 4; ++rr) {
        if (rotate_quarter(d, rr) != d2) continue;
        const auto ra = rotate_quarter(a, rr), rb = rotate_quarter(b, rr);
        const double tx = a2[0] - ra[0], ty = a2[1] - ra[1];
        if (std::floor(tx) == tx && std::floor(ty) == ty && sums_exactly(ra[0], tx, a2[0]) &&
            sums_exactly(ra[1], ty, a2[1]) && sums_exactly(rb[0], tx, b2[0]) && sums_exactly(rb[1], ty, b2[1]))
            return rr;
    }
    return -1;
}

namespace {

using UVs = std::vector<std::array<double, 2>>;

/// Triangle f is still in the map: a collapse of UV-degenerate edges removed it otherwise (NaN UVs).
bool alive(const UVs& U, std::size_t f) { return std::isfinite(U[3 * f][0]); }

/// The largest move of an input UV (inf-norm) by which a carried map is still the input's.
constexpr double kMaxMapDisplacement = 1.0;

/// Largest and summed |map_uvs - input uvs| (inf-norm per corner) over the triangles still in
/// the map and not repaired, summed in fixed blocks of corners and then block by block in order: the sum is the
/// same whatever the thread count.
void map_displacement(const Input& input, const UVs& U, const std::vector<char>& repaired, int threads,
                      VerifyResult& r) {
    constexpr std::size_t kBlock = std::size_t{1} << 14;
    const auto blocks = static_cast<std::int64_t>((U.size() + kBlock - 1) / kBlock);
    std::vector<double> block_sum(static_cast<std::size_t>(blocks), 0.0);
    const int workers = run_parallel(threads, static_cast<std::int64_t>(U.size())) ? threads : 1;
    std::vector<double> largest(static_cast<std::size_t>(workers), 0.0); // per thread: a maximum does not round
    share_chunks(workers, blocks, 1, [&](std::size_t t, const auto& next) {
        for (std::int64_t b = 0, stop = 0; next(b, stop);) {
            const std::size_t from = static_cast<std::size_t>(b) * kBlock, to = std::min(U.size(), from + kBlock);
            double sum = 0.0;
            for (std::size_t c = from; c < to; ++c)
                if (alive(U, c / 3) && !repaired[c / 3]) {
                    const double d = std::max(std::abs(U[c][0] - input.uvs[c][0]), std::abs(U[c][1] - input.uvs[c][1]));
                    largest[t] = std::max(largest[t], d);
                    sum += d;
                }
            block_sum[static_cast<std::size_t>(b)] = sum;
        }
    });
    r.max_map_displacement = *std::max_element(largest.begin(), largest.end());
    for (const double sum : block_sum) r.sum_map_displacement += sum;
}

/// The map's interior edges, matched across (the input's edge pairs give each half-edge its
/// opposite). opposite[c]: the corner across the edge that starts at corner c, when the two
/// charts were matched by a unique grid automorphism (rotation[c] quarter turns from c's chart
/// to its neighbour's); -1 otherwise. rotation[c] == -1 marks an edge (found from its smaller
/// corner c) whose charts no grid automorphism matches.
struct ChartMatch {
    std::vector<std::int32_t> opposite;
    std::vector<std::int8_t> rotation;
};

ChartMatch match_charts(const UVs& U, const EdgePairs& pairs, int threads) {
    const auto nc = static_cast<std::int64_t>(U.size());
    ChartMatch m{std::vector<std::int32_t>(U.size(), -1), std::vector<std::int8_t>(U.size(), 0)};
    for_range(threads, nc, [&](std::size_t, std::int64_t begin, std::int64_t end) {
        for (std::int64_t ci = begin; ci < end; ++ci) {
            const auto c = static_cast<std::size_t>(ci);
            // Boundary, non-manifold, or done from the pair's other corner:
            if (pairs[c] < static_cast<std::int32_t>(ci)) continue;
            const auto o = static_cast<std::size_t>(pairs[c]);
            if (!alive(U, c / 3) || !alive(U, o / 3)) continue;
            // In c's chart the edge runs a -> b; in o's chart b -> a (for a consistently oriented
            // pair). Some rotation R and one integer translation t must give R a + t == a2 and
            // R b + t == b2 exactly.
            const auto &a = U[c], &b = U[next_corner(c)], &a2 = U[next_corner(o)], &b2 = U[o];
            const int found = grid_automorphism(a, b, a2, b2);
            // A zero-length edge admits every rotation: it is not matched, and the fan check skips
            // its vertices.
            if (found >= 0 && (a[0] != b[0] || a[1] != b[1])) {
                m.opposite[c] = static_cast<std::int32_t>(o);
                m.opposite[o] = static_cast<std::int32_t>(c);
                m.rotation[c] = static_cast<std::int8_t>(found);
                m.rotation[o] = static_cast<std::int8_t>((4 - found) & 3);
            }
            if (found < 0) m.rotation[c] = -1;
        }
    });
    return m;
}

/// Per input vertex: the quarter turns (mod 4) its fan's transitions compose to, or -1 when the
/// fan is not checked. Walking the fan crosses, once each, the edges that end at the vertex's
/// corners (prev(c) -> c), so the composed turn is a sum over the corners, taken in one pass.
/// A fan is left unchecked when an edge in it is unmatched (boundary, degenerate or not a grid
/// automorphism), a triangle in it was collapsed, or the vertex is non-manifold.
std::vector<std::int8_t> fan_turns(const Input& input, const UVs& U, const ChartMatch& m,
                                   const std::vector<char>& single_fan) {
    std::vector<std::int8_t> turns(single_fan.size(), 0);
    for (std::size_t c = 0; c < U.size(); ++c) {
        const auto v = static_cast<std::size_t>(input.triangles[c / 3][c % 3]);
        if (turns[v] < 0) continue;
        if (!alive(U, c / 3) || m.opposite[prev_corner(c)] < 0 || !single_fan[v])
            turns[v] = -1;
        else
            turns[v] = static_cast<std::int8_t>((turns[v] + m.rotation[prev_corner(c)]) & 3);
    }
    return turns;
}

/// Singularities: around every interior vertex whose fan is matched edge by edge, the
/// transitions compose to a rotation; each edge transition maps the vertex's UV onto itself
/// exactly, so a composed identity closes the fan, and a composed rotation (a singularity) must
/// have its fixed point, the vertex's UV, on an integer grid point (Algorithm 2). Counted and
/// judged at each vertex's first corner, in the order of those corners.
void check_singularities(const Input& input, const UVs& U, const std::vector<std::int8_t>& turns,
                         const std::vector<char>& single_fan, VerifyResult& r, std::vector<Violation>& out) {
    std::vector<std::int32_t> first(single_fan.size(), -1);
    for (std::size_t c = 0; c < U.size(); ++c) {
        const auto v = static_cast<std::size_t>(input.triangles[c / 3][c % 3]);
        if (first[v] < 0) first[v] = static_cast<std::int32_t>(c);
    }
    for (std::size_t c0 = 0; c0 < U.size(); ++c0) {
        const auto v = static_cast<std::size_t>(input.triangles[c0 / 3][c0 % 3]);
        if (first[v] != static_cast<std::int32_t>(c0) || turns[v] <= 0) continue;
        ++r.map_singularities;
        const auto& u = U[c0];
        if (std::floor(u[0]) != u[0] || std::floor(u[1]) != u[1])
            add_capped(out, ViolationKind::SingularityOffGrid,
                       "input vertex " + std::to_string(v) + ": a singularity (" + std::to_string(turns[v] * 90) +
                           " degree turn) at (" + std::to_string(u[0]) + ", " + std::to_string(u[1]) +
                           ") in the chart of triangle " + std::to_string(c0 / 3) + ", not at an integer grid point",
                       static_cast<std::int64_t>(v));
    }
}

/// The signed angle at corner c of its triangle in the UVs given (the chart does not matter).
double corner_angle(const UVs& U, std::size_t c) {
    const std::size_t t = c - c % 3;
    return signed_angle(U[c], U[t + (c % 3 + 1) % 3], U[t + (c % 3 + 2) % 3]);
}

/// Per input vertex with a checked fan, its winding in quarter turns: the signed angle sum of its
/// corners, which is congruent to its turn modulo a full turn (four quarter turns); only the
/// whole turns are taken from the (inexact) angles, with half a turn of margin either way.
/// INT_MIN where the sum is not finite (non-finite UVs): no winding. Only at the vertices `wanted`
/// marks (the others get 0): the angles cost most of the map's check where few are wanted.
std::vector<int> windings(const Input& input, const UVs& U, const std::vector<std::int8_t>& turns,
                          const std::vector<char>& wanted) {
    std::vector<double> sum(turns.size(), 0.0);
    for (std::size_t c = 0; c < U.size(); ++c) {
        const auto v = static_cast<std::size_t>(input.triangles[c / 3][c % 3]);
        if (turns[v] >= 0 && wanted[v]) sum[v] += corner_angle(U, c);
    }
    std::vector<int> out(turns.size(), 0);
    for (std::size_t v = 0; v < turns.size(); ++v)
        if (turns[v] >= 0 && wanted[v])
            out[v] = !std::isfinite(sum[v])
                         ? INT_MIN
                         : turns[v] + 4 * static_cast<int>(std::lround((sum[v] - turns[v] * M_PI / 2) / (2 * M_PI)));
    return out;
}

/// The repair adds no branch point: at each vertex of a repaired triangle whose fan's transitions
/// compose to no turn (with a checked fan), the carried map winds once, or as the input's does.
/// Positive triangles alone do not show this: they can wind twice round a vertex while a
/// singularity beside it loses a turn. (A singularity's winding is not judged here: a fold-over
/// can take whole turns from it, which the repair gives back, as Algorithm 8 counts them.)
void check_repair_windings(const Input& input, const UVs& U, const std::vector<char>& repaired,
                           const std::vector<std::int8_t>& turns, std::vector<Violation>& out) {
    // Per input vertex: the first repaired triangle round it (-1: none), the violation's place.
    std::vector<std::int64_t> touched(turns.size(), -1);
    bool any = false;
    for (std::size_t c = 0; c < U.size(); ++c) {
        std::int64_t& first = touched[static_cast<std::size_t>(input.triangles[c / 3][c % 3])];
        if (repaired[c / 3] && first < 0) first = static_cast<std::int64_t>(c / 3), any = true;
    }
    if (!any) return;
    std::vector<char> wanted(turns.size(), 0);
    for (std::size_t v = 0; v < turns.size(); ++v) wanted[v] = touched[v] >= 0 && turns[v] == 0;
    const std::vector<int> now = windings(input, U, turns, wanted), given = windings(input, input.uvs, turns, wanted);
    const auto degrees = [](int w) { return w == INT_MIN ? std::string("unknown") : std::to_string(w * 90); };
    for (std::size_t v = 0; v < turns.size(); ++v)
        if (touched[v] >= 0 && turns[v] == 0 && (now[v] == INT_MIN || (now[v] != given[v] && now[v] != 4)))
            add_capped(out, ViolationKind::RepairNotCertified,
                       "input vertex " + std::to_string(v) + " (of repaired triangle " + std::to_string(touched[v]) +
                           ") winds " + degrees(now[v]) + " degrees in the repaired map, " + degrees(given[v]) +
                           " in the input's: a vertex whose transitions compose to no turn must wind once, or "
                           "as in the input",
                       touched[v]);
}

/// The provenance's grid point lies on the element it names, in the chart of its triangle
/// (still in the map): on a corner for a vertex, strictly inside the named side for an edge,
/// strictly inside the (non-degenerate) triangle for a face. Grid points with a coordinate of
/// 2^53 or more are not exact in doubles and are judged off the element.
bool on_named_element(const Provenance& p, const UVs& U, std::size_t nf) {
    using P = CGAL::Epick::Point_2;
    const auto T = static_cast<std::size_t>(p.chart_triangle);
    constexpr std::int64_t kExact = std::int64_t{1} << 53;
    if (!(p.chart_triangle >= 0 && T < nf && alive(U, T) && std::abs(p.grid[0]) < kExact &&
          std::abs(p.grid[1]) < kExact))
        return false;
    const P g(static_cast<double>(p.grid[0]), static_cast<double>(p.grid[1]));
    const std::array<P, 3> t{P(U[3 * T][0], U[3 * T][1]), P(U[3 * T + 1][0], U[3 * T + 1][1]),
                             P(U[3 * T + 2][0], U[3 * T + 2][1])};
    if (p.kind == QVertexKind::Vertex) {
        // A corner of the named triangle sits on the grid point. (Its input vertex may be one
        // that a collapse of UV-degenerate edges merged into p.element.)
        return t[0] == g || t[1] == g || t[2] == g;
    }
    if (p.kind == QVertexKind::Edge) {
        const int k = p.local_edge;
        if (!(k >= 0 && k < 3 && static_cast<std::size_t>(p.element) == T)) return false;
        const P &e0 = t[static_cast<std::size_t>(k)], &e1 = t[static_cast<std::size_t>((k + 1) % 3)];
        return CGAL::collinear(e0, e1, g) && CGAL::collinear_are_strictly_ordered_along_line(e0, g, e1);
    }
    const auto s = CGAL::orientation(t[0], t[1], t[2]);
    return s != CGAL::COLLINEAR && CGAL::orientation(t[0], t[1], g) == s && CGAL::orientation(t[1], t[2], g) == s &&
           CGAL::orientation(t[2], t[0], g) == s;
}

/// Provenance: every vertex's grid point on the named vertex, edge or triangle, decided by
/// CGAL's exact predicates.
void check_provenance(const QuadMesh& mesh, std::size_t nf, std::vector<Violation>& out) {
    for (std::size_t i = 0; i < mesh.provenance.size() && i < mesh.positions.size(); ++i) {
        const Provenance& p = mesh.provenance[i];
        if (!on_named_element(p, mesh.map_uvs, nf))
            add_capped(out, ViolationKind::NotOnGridPoint,
                       "vertex " + std::to_string(i) + ": grid point (" + std::to_string(p.grid[0]) + ", " +
                           std::to_string(p.grid[1]) + ") is not on the element its provenance names (triangle " +
                           std::to_string(p.chart_triangle) + ")",
                       static_cast<std::int64_t>(i));
    }
}

/// The repair's certificate (QuadMesh::map_repaired): a sorted list of distinct live triangles,
/// each positively oriented in the map (CGAL's exact orientation). Returns, per triangle,
/// whether it is listed.
std::vector<char> check_repair(const QuadMesh& mesh, std::size_t nf, const Input& input, VerifyResult& r,
                               std::vector<Violation>& out) {
    using P = CGAL::Epick::Point_2;
    const UVs& U = mesh.map_uvs;
    std::vector<char> listed(nf, 0);
    std::int64_t previous = -1;
    for (const std::int32_t t : mesh.map_repaired) {
        const bool in_range = t > previous && static_cast<std::size_t>(t) < nf && alive(U, static_cast<std::size_t>(t));
        if (!in_range) {
            add_capped(out, ViolationKind::RepairNotCertified,
                       "the repaired triangles are not a sorted list of distinct triangles of the map (at " +
                           std::to_string(t) + ")",
                       t >= 0 && static_cast<std::size_t>(t) < nf ? t : -1);
            continue;
        }
        previous = t;
        const auto T = static_cast<std::size_t>(t);
        listed[T] = 1;
        ++r.repaired_triangles;
        const P a(U[3 * T][0], U[3 * T][1]), b(U[3 * T + 1][0], U[3 * T + 1][1]), c(U[3 * T + 2][0], U[3 * T + 2][1]);
        r.repaired_uv_area += 0.5 * ((b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x()));
        if (CGAL::orientation(a, b, c) != CGAL::LEFT_TURN)
            add_capped(out, ViolationKind::RepairNotCertified,
                       "repaired triangle " + std::to_string(t) + " is not positively oriented in the map",
                       static_cast<std::int64_t>(t));
        for (std::size_t k = 0; k < 3; ++k)
            r.max_repair_displacement =
                std::max({r.max_repair_displacement, std::abs(U[3 * T + k][0] - input.uvs[3 * T + k][0]),
                          std::abs(U[3 * T + k][1] - input.uvs[3 * T + k][1])});
    }
    return listed;
}

} // namespace

void check_map(const Input& input, const QuadMesh& mesh, const EdgePairs& pairs, const std::vector<char>& single_fan,
               int threads, VerifyResult& r, std::vector<Violation>& out) {
    const UVs& U = mesh.map_uvs;
    const std::vector<char> repaired = check_repair(mesh, input.triangles.size(), input, r, out);
    map_displacement(input, U, repaired, threads, r);
    // Sanitization rounds, and snaps singularities and features to the grid: it moves a UV by
    // half a cell at most. A map moved by more than a cell (outside the repair's certificate) is
    // another map than the input's, and the mesh is not judged against it.
    if (r.max_map_displacement > kMaxMapDisplacement)
        out.push_back({ViolationKind::MapNotIntegerGrid,
                       "the mesh's map moves an input UV by " + std::to_string(r.max_map_displacement) +
                           ", more than a cell: it is not the input's map",
                       -1});
    const ChartMatch m = match_charts(U, pairs, threads);
    for (std::size_t c = 0; c < U.size(); ++c)
        if (m.rotation[c] < 0)
            add_capped(out, ViolationKind::MapNotIntegerGrid,
                       "the charts of triangles " + std::to_string(c / 3) + " and " + std::to_string(pairs[c] / 3) +
                           " do not differ by a grid automorphism along their shared edge",
                       static_cast<std::int64_t>(c / 3));
    const std::vector<std::int8_t> turns = fan_turns(input, U, m, single_fan);
    check_singularities(input, U, turns, single_fan, r, out);
    check_repair_windings(input, U, repaired, turns, out);
    check_provenance(mesh, input.triangles.size(), out);
}

} // namespace qex::verify_detail

// The located mode's view of the input map's structure: which half-edges face each other, the
// transition across each (rounded to a grid automorphism: the input is the raw map, with its
// solver noise), and which input vertices are singular.
#include "checker.h"
#include "grid.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace qex::verify_detail {
namespace {

/// The half-edges sorted by their undirected edge ((smaller vertex) << 32 | larger vertex),
/// then by corner: the half-edges of one edge are neighbours.
std::vector<std::pair<std::uint64_t, std::uint32_t>> sorted_half_edges(const Input& in) {
    const std::size_t nc = 3 * in.triangles.size();
    std::vector<std::pair<std::uint64_t, std::uint32_t>> half(nc);
    for (std::size_t c = 0; c < nc; ++c) {
        const auto a = static_cast<std::uint32_t>(in.triangles[c / 3][c % 3]);
        const auto b = static_cast<std::uint32_t>(in.triangles[c / 3][(c % 3 + 1) % 3]);
        half[c] = {static_cast<std::uint64_t>(std::min(a, b)) << 32 | std::max(a, b), static_cast<std::uint32_t>(c)};
    }
    std::sort(half.begin(), half.end());
    return half;
}

/// The transition across the edge of half-edges c and o, when it is determined: the quarter
/// turn that carries c's edge vector onto o's (within the tolerance, both longer than 4
/// tolerances), and the translation rounded to integers (below 9e15 in magnitude). Sets
/// `edges.opposite` and `edges.across` for both half-edges.
void cross_edge(const Input& in, std::size_t c, std::size_t o, double uv_tolerance, InputEdges& edges) {
    const auto &p1 = in.uvs[c], &q1 = in.uvs[next_corner(c)], &p2 = in.uvs[next_corner(o)], &q2 = in.uvs[o];
    const double len1 = std::max(std::abs(q1[0] - p1[0]), std::abs(q1[1] - p1[1]));
    const double len2 = std::max(std::abs(q2[0] - p2[0]), std::abs(q2[1] - p2[1]));
    int best = 0;
    double best_err = HUGE_VAL;
    for (int rr = 0; rr < 4; ++rr) {
        const auto d = rotate_quarter(std::array<double, 2>{q1[0] - p1[0], q1[1] - p1[1]}, rr);
        const double e = std::max(std::abs(d[0] - (q2[0] - p2[0])), std::abs(d[1] - (q2[1] - p2[1])));
        if (e < best_err) best_err = e, best = rr;
    }
    if (!(len1 > 4 * uv_tolerance && len2 > 4 * uv_tolerance && best_err <= uv_tolerance)) return;
    const auto rp = rotate_quarter(p1, best);
    const double tx = std::nearbyint(p2[0] - rp[0]), ty = std::nearbyint(p2[1] - rp[1]);
    if (!(std::abs(tx) < 9e15 && std::abs(ty) < 9e15)) return;
    edges.opposite[c] = static_cast<std::int64_t>(o);
    edges.opposite[o] = static_cast<std::int64_t>(c);
    edges.across[c] = {best, static_cast<std::int64_t>(tx), static_cast<std::int64_t>(ty)};
    // The inverse: x = R^-r (x' - t).
    const GridPoint minus_t{-static_cast<std::int64_t>(tx), -static_cast<std::int64_t>(ty)};
    const auto back = rotate_quarter(minus_t, 4 - best);
    edges.across[o] = {(4 - best) & 3, back[0], back[1]};
}

} // namespace

InputEdges input_edges(const Input& in, double uv_tolerance) {
    const std::size_t nc = 3 * in.triangles.size();
    const auto half = sorted_half_edges(in);
    InputEdges edges{std::vector<std::int64_t>(nc, -1), std::vector<Transition>(nc), std::vector<std::int64_t>(nc, -1)};
    for (std::size_t i = 0, j = 0; i < nc; i = j) {
        j = i;
        while (j < nc && half[j].first == half[i].first) ++j;
        if (j - i != 2) continue;
        const std::size_t c = half[i].second, o = half[i + 1].second;
        edges.partner[c] = static_cast<std::int64_t>(o);
        edges.partner[o] = static_cast<std::int64_t>(c);
        cross_edge(in, c, o, uv_tolerance, edges);
    }
    return edges;
}

std::vector<char> singular_vertices(const Input& in, const InputEdges& edges) {
    const std::size_t nc = edges.opposite.size();
    std::vector<char> singular(in.positions.size(), 0), seen(nc, 0);
    // Walk each fan from a corner not seen yet, across the edge that ends at the corner's
    // vertex (prev(c) -> c), until it closes, stops at an edge without a transition, or runs
    // into corners seen before.
    for (std::size_t c0 = 0; c0 < nc; ++c0) {
        if (seen[c0]) continue;
        std::size_t c = c0;
        int turns = 0;
        bool closed = false;
        for (std::size_t steps = 0; steps <= nc; ++steps) {
            seen[c] = 1;
            const std::int64_t o = edges.opposite[prev_corner(c)];
            if (o < 0) {
                turns = edges.partner[prev_corner(c)] >= 0 ? 1 : 0; // undetermined turn: treated as singular
                closed = edges.partner[prev_corner(c)] >= 0;
                break;
            }
            turns += edges.across[prev_corner(c)].r;
            c = static_cast<std::size_t>(o);
            if (c == c0) {
                closed = true;
                break;
            }
            if (seen[c]) break;
        }
        if (closed && (turns & 3) != 0) singular[static_cast<std::size_t>(in.triangles[c0 / 3][c0 % 3])] = 1;
    }
    return singular;
}

} // namespace qex::verify_detail

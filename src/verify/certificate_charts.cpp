// The certificate's charts and singularities against the given map's (certificate.h,
// check_charts): exact on integers, the certificate's transitions read exactly from its UVs
// (grid_automorphism), the given map's rounded with the UV tolerance (input_edges).
#include "certificate.h"
#include "cones.h"
#include "grid.h"
#include "union_find.h"

#include <cmath>
#include <string>

namespace qex::verify_detail {
namespace {

/// The certificate's transition across the edge of half-edges c and o (its charts there, exactly
/// a grid automorphism), into m; false when there is none or the edge has zero length in it.
bool certificate_transition(const UVs& U, std::size_t c, std::size_t o, Transition& m) {
    const auto &a = U[c], &b = U[next_corner(c)], &a2 = U[next_corner(o)];
    if (a == b) return false;
    const int r = grid_automorphism(a, b, a2, U[o]);
    if (r < 0) return false;
    const auto ra = rotate_quarter(a, r);
    const double tx = a2[0] - ra[0], ty = a2[1] - ra[1]; // exact integers (grid_automorphism)
    if (!(std::abs(tx) < 9e15 && std::abs(ty) < 9e15)) return false;
    m = {r, static_cast<std::int64_t>(tx), static_cast<std::int64_t>(ty)};
    return true;
}

/// x -> R^-r (x - t), the inverse of m.
Transition inverse(const Transition& m) {
    const GridPoint back = rotate_quarter(GridPoint{-m.tx, -m.ty}, 4 - m.r);
    return {(4 - m.r) & 3, back[0], back[1]};
}

/// Per listed triangle its region (listed triangles sharing vertices: a singularity and the one
/// it cancels may lie in repaired patches that touch at a vertex), -1 for the others.
std::vector<std::int32_t> listed_regions(const Input& in, const std::vector<char>& listed) {
    const std::size_t nt = listed.size();
    UnionFind groups(nt);
    std::vector<std::int32_t> first_at(in.positions.size(), -1);
    for (std::size_t t = 0; t < nt; ++t) {
        if (!listed[t]) continue;
        for (int v : in.triangles[t]) {
            std::int32_t& f = first_at[static_cast<std::size_t>(v)];
            if (f < 0)
                f = static_cast<std::int32_t>(t);
            else
                groups.unite(f, static_cast<int>(t));
        }
    }
    std::vector<std::int32_t> region(nt, -1);
    for (std::size_t t = 0; t < nt; ++t)
        if (listed[t]) region[t] = groups.find(static_cast<int>(t));
    return region;
}

/// Per half-edge the certificate's transition across it (`found` 0 where it has none).
struct CertificateEdges {
    std::vector<Transition> across;
    std::vector<char> found;
};

CertificateEdges certificate_edges(const UVs& U, const InputEdges& edges, const std::vector<char>& collapsed) {
    CertificateEdges e{std::vector<Transition>(U.size()), std::vector<char>(U.size(), 0)};
    for (std::size_t c = 0; c < U.size(); ++c) {
        const std::int64_t o = edges.partner[c];
        if (o >= 0 && !collapsed[c / 3] && !collapsed[static_cast<std::size_t>(o) / 3])
            e.found[c] = certificate_transition(U, c, static_cast<std::size_t>(o), e.across[c]);
    }
    return e;
}

/// Charts breadth first from the unlisted triangles (identity) into the listed ones, across
/// the edges whose transition both maps determine. An edge with an unlisted side whose
/// transitions differ in the charts found is a mismatch (outside the repaired triangles or at
/// their rim); an edge of two listed triangles marks its region (`defect`: per region a
/// triangle at such an edge, or -1).
void compare_charts(const InputEdges& edges, const CertificateEdges& cert, const std::vector<char>& listed,
                    const std::vector<char>& collapsed, const std::vector<std::int32_t>& region,
                    std::vector<std::int64_t>& defect, std::vector<Violation>& out) {
    const std::size_t nt = listed.size();
    std::vector<Transition> gauge(nt);
    std::vector<char> known(nt, 0);
    std::vector<std::size_t> queue;
    for (std::size_t t = 0; t < nt; ++t)
        if (!listed[t] && !collapsed[t]) known[t] = 1, queue.push_back(t);
    std::size_t head = 0, seed = 0;
    for (;;) {
        for (; head < queue.size(); ++head) {
            const std::size_t t = queue[head];
            for (std::size_t c = 3 * t; c < 3 * t + 3; ++c) {
                if (edges.opposite[c] < 0 || !cert.found[c]) continue;
                const auto o = static_cast<std::size_t>(edges.opposite[c]), u = o / 3;
                const Transition& G = edges.across[c];
                Transition here, there;
                if (!compose(cert.across[c], gauge[t], here)) continue;
                if (!known[u]) { // the listed triangle's chart, from this neighbour
                    if (compose(here, inverse(G), gauge[u])) known[u] = 1, queue.push_back(u);
                    continue;
                }
                if (compose(gauge[u], G, there) && same(here, there)) continue;
                if (listed[t] && listed[u]) {
                    const std::int32_t k = region[t];
                    if (defect[static_cast<std::size_t>(k)] < 0)
                        defect[static_cast<std::size_t>(k)] = static_cast<std::int64_t>(t);
                } else if (c < o || listed[t] != listed[u]) {
                    const bool rim = listed[t] || listed[u];
                    if (rim && listed[u]) continue; // named once, from its listed side
                    mismatch(out,
                             "across the edge of triangles " + std::to_string(t) + " and " + std::to_string(u) +
                                 (rim ? ", at the rim of the repaired triangles" : ", neither listed as repaired") +
                                 ", the charts do not differ by the map's transition (" + std::to_string(G.r * 90) +
                                 " degrees, (" + std::to_string(G.tx) + ", " + std::to_string(G.ty) + "))" +
                                 (rim ? " in any chart of the repaired triangle" : ""),
                             static_cast<std::int64_t>(t));
                }
            }
        }
        // Listed triangles no determined edge reaches from an unlisted one: charted as given.
        while (seed < nt && (known[seed] || collapsed[seed])) ++seed;
        if (seed == nt) break;
        known[seed] = 1, gauge[seed] = Transition{}, queue.push_back(seed);
    }
}

/// Per vertex the quarter turns (mod 4) its fan's rotations compose to, from per half-edge
/// rotations (`rotation(c)`, -1 where unknown); -1 where a rotation in its fan is unknown.
template <class Rotation>
std::vector<int> fan_turns(const Input& in, Rotation rotation) {
    std::vector<int> turn(in.positions.size(), 0);
    for (std::size_t c = 0; c < 3 * in.triangles.size(); ++c) {
        const auto v = static_cast<std::size_t>(in.triangles[c / 3][c % 3]);
        const int r = rotation(prev_corner(c));
        turn[v] = turn[v] < 0 || r < 0 ? -1 : (turn[v] + r) & 3;
    }
    return turn;
}

/// Where a vertex's fan has an edge too short (in UV) for its transition to be read, the turns
/// (mod 4) its fan's rotations compose to, read from its angle sum (`sums`) instead: an interior
/// vertex whose fan holds no fold (`folded`) and whose angle sum is n quarter turns (within
/// kQuarterTurnSlack, 1 < n < 8) composes to -n. Solver noise on a finely cut map leaves such
/// short edges next to singularities; a repair that cancels one must still be read as cancelling.
void turns_from_angles(const Input& in, const InputEdges& edges, const std::vector<char>& folded,
                       const std::vector<double>& sums, std::vector<int>& turn) {
    const std::size_t nv = in.positions.size();
    std::vector<char> interior(nv, 1);
    for (std::size_t c = 0; c < 3 * in.triangles.size(); ++c)
        if (edges.partner[c] < 0) // a boundary edge: both its ends on the boundary
            for (const std::size_t e : {c, next_corner(c)})
                interior[static_cast<std::size_t>(in.triangles[e / 3][e % 3])] = 0;
    for (std::size_t v = 0; v < nv; ++v) {
        if (turn[v] >= 0 || !interior[v] || folded[v]) continue;
        const double q = sums[v] / (M_PI / 2);
        const long n = std::lround(q);
        if (std::abs(q - static_cast<double>(n)) <= kQuarterTurnSlack && n > 1 && n < 8)
            turn[v] = static_cast<int>((4 - n % 4) % 4);
    }
}

} // namespace

std::vector<double> angle_sums(const Input& in, const UVs& U) {
    std::vector<double> sum(in.positions.size(), 0.0);
    for (std::size_t c = 0; c < U.size(); ++c)
        sum[static_cast<std::size_t>(in.triangles[c / 3][c % 3])] +=
            signed_angle(U[c], U[next_corner(c)], U[prev_corner(c)]);
    return sum;
}

std::vector<char> check_charts(const Input& given, const UVs& U, const std::vector<char>& listed,
                               const std::vector<char>& collapsed, const std::vector<char>& folded,
                               const std::vector<double>& given_sums, double tol, std::vector<Violation>& out) {
    const InputEdges edges = input_edges(given, tol);
    const CertificateEdges cert = certificate_edges(U, edges, collapsed);
    const std::vector<std::int32_t> region = listed_regions(given, listed);
    std::vector<std::int64_t> defect(listed.size(), -1);
    compare_charts(edges, cert, listed, collapsed, region, defect, out);
    // The singularities: the same turns, but where the certificate cancels the given map's.
    std::vector<int> was =
        fan_turns(given, [&](std::size_t c) { return edges.opposite[c] < 0 ? -1 : edges.across[c].r; });
    turns_from_angles(given, edges, folded, given_sums, was);
    const std::vector<int> now = fan_turns(given, [&](std::size_t c) { return cert.found[c] ? cert.across[c].r : -1; });
    // Per region: whether a vertex of it lies on a fold of the given map, the turns it cancels
    // (fold-free regions), and a vertex it cancels.
    std::vector<std::int32_t> region_of_vertex(given.positions.size(), -1);
    std::vector<char> region_folded(listed.size(), 0);
    for (std::size_t c = 0; c < U.size(); ++c) {
        if (!listed[c / 3]) continue;
        const auto v = static_cast<std::size_t>(given.triangles[c / 3][c % 3]);
        region_of_vertex[v] = region[c / 3];
        if (folded[v]) region_folded[static_cast<std::size_t>(region[c / 3])] = 1;
    }
    std::vector<char> cancelled_vertex(now.size(), 0);
    std::vector<int> cancelled(listed.size(), 0);
    std::vector<std::int64_t> cancelled_at(listed.size(), -1);
    for (std::size_t v = 0; v < now.size(); ++v) {
        if (was[v] < 0 || now[v] < 0 || was[v] == now[v]) continue;
        const std::int32_t k = region_of_vertex[v];
        if (now[v] == 0 && k >= 0) { // a singularity cancelled inside the repair
            cancelled_vertex[v] = 1;
            cancelled[static_cast<std::size_t>(k)] += was[v];
            cancelled_at[static_cast<std::size_t>(k)] = static_cast<std::int64_t>(v);
            continue;
        }
        std::int64_t t = -1;
        for (std::size_t c = 0; c < U.size() && t < 0; ++c)
            if (given.triangles[c / 3][c % 3] == static_cast<int>(v)) t = static_cast<std::int64_t>(c / 3);
        mismatch(out,
                 "input vertex " + std::to_string(v) + " turns " + std::to_string(now[v] * 90) +
                     " degrees round its fan, in the map " + std::to_string(was[v] * 90) +
                     " (a singularity added, moved or changed)",
                 t, {Place{PlaceKind::InputVertex, {static_cast<std::int64_t>(v)}}});
    }
    for (std::size_t k = 0; k < listed.size(); ++k) {
        if (cancelled_at[k] >= 0 && !region_folded[k] && cancelled[k] % 4 != 0)
            mismatch(out,
                     "the singularities it makes regular in the repaired region of triangle " + std::to_string(k) +
                         ", which holds no fold of the map, do not cancel (their turns sum to " +
                         std::to_string(cancelled[k] * 90) + " degrees)",
                     static_cast<std::int64_t>(k), {Place{PlaceKind::InputVertex, {cancelled_at[k]}}});
        if (cancelled_at[k] < 0 && defect[k] >= 0)
            mismatch(out,
                     "in the repaired region of triangle " + std::to_string(k) +
                         ", which cancels no singularity, the charts do not differ from the map's by a chart per "
                         "triangle (at triangle " +
                         std::to_string(defect[k]) + ")",
                     defect[k]);
    }
    return cancelled_vertex;
}

} // namespace qex::verify_detail

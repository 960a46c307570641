// The checker: judges a polygon mesh against the input map with its own code (nothing from the
// extraction pipeline) and exact arithmetic wherever a number is compared: CGAL's exact
// predicates and rationals for doubles, 128-bit integers for integer grid coordinates.
#include "checker.h"
#include "parallel.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Exact_rational.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>

namespace qex {
namespace {

using Rational = CGAL::Exact_rational;

struct Topology {
    std::int64_t vertices = 0, edges = 0, faces = 0, boundary_loops = 0, components = 0;
    std::int64_t euler() const { return vertices - edges + faces; }
};

int find(std::vector<int>& parent, int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
}

/// Per corner c: the other corner whose outgoing edge joins the same two vertices, when exactly
/// two face sides share that edge (in either direction); -1 otherwise.
using EdgePairs = std::vector<std::int32_t>;

/// Topology of a polygon mesh with valid indices (at most 2^31 - 1 corners); appends violations
/// when `out` is given. `offset` (size F+1) and `corner_vertex` describe the faces as flat
/// arrays. Edges are found without hashing or a global sort: the corners are bucketed by the
/// smaller vertex of their outgoing edge (a counting pass), and each bucket is ordered by the
/// larger one. Everything is decided in the order (smaller vertex, larger vertex, corner),
/// whatever the thread count.
Topology analyse(std::size_t num_vertices, const std::vector<std::size_t>& offset, const std::vector<int>& corner_vertex,
                 std::vector<Violation>* out, int threads, EdgePairs* pairs_out = nullptr,
                 std::vector<char>* single_fan_out = nullptr) {
    Topology t;
    auto violate = [&](ViolationKind k, std::string msg, std::int64_t e) {
        if (out && out->size() < 1000) out->push_back({k, std::move(msg), e});
    };
    const std::size_t nf = offset.size() - 1, nc = offset.back();
    // Every face a triangle: then offset[f] == 3f, and corners need no face lookup.
    bool triangles = true;
    for (std::size_t f = 0; f < nf && triangles; ++f) triangles = offset[f + 1] - offset[f] == 3;
    std::vector<std::int32_t> corner_face(triangles ? 0 : nc);
    for (std::size_t f = 0; f < nf && !triangles; ++f)
        for (std::size_t c = offset[f]; c < offset[f + 1]; ++c) corner_face[c] = static_cast<std::int32_t>(f);
    auto face_of = [&](std::size_t c) { return triangles ? static_cast<std::int64_t>(c / 3) : corner_face[c]; };
    auto next_corner = [&](std::size_t c) {
        if (triangles) return c % 3 == 2 ? c - 2 : c + 1;
        const auto f = static_cast<std::size_t>(corner_face[c]);
        return c + 1 == offset[f + 1] ? offset[f] : c + 1;
    };
    auto prev_corner = [&](std::size_t c) {
        if (triangles) return c % 3 == 0 ? c + 2 : c - 1;
        const auto f = static_cast<std::size_t>(corner_face[c]);
        return c == offset[f] ? offset[f + 1] - 1 : c - 1;
    };
    // The vertex each corner's outgoing edge ends at.
    std::vector<std::int32_t> head(nc);
    const auto nc64 = static_cast<std::int64_t>(nc);
#if defined(_OPENMP)
#pragma omp parallel for schedule(static) num_threads(threads) if (verify_detail::run_parallel(threads, static_cast<std::int64_t>(nc)))
#endif
    for (std::int64_t c = 0; c < nc64; ++c) head[static_cast<std::size_t>(c)] = corner_vertex[next_corner(static_cast<std::size_t>(c))];
    // Buckets by the smaller vertex; after the placing pass, bucket v is [end[v-1], end[v]).
    // An entry is (larger vertex) << 32 | corner << 1 | direction, the direction 1 when the
    // corner's side runs from the larger vertex (so orientation needs no second look-up).
    std::vector<std::uint32_t> end(num_vertices + 1, 0);
    std::vector<std::uint64_t> bucket(nc);
    for (std::size_t c = 0; c < nc; ++c) ++end[static_cast<std::size_t>(std::min(corner_vertex[c], head[c])) + 1];
    for (std::size_t v = 0; v < num_vertices; ++v) end[v + 1] += end[v];
    for (std::size_t c = 0; c < nc; ++c) {
        const int a = corner_vertex[c], b = head[c];
        bucket[end[static_cast<std::size_t>(std::min(a, b))]++] =
            static_cast<std::uint64_t>(static_cast<std::uint32_t>(std::max(a, b))) << 32 |
            static_cast<std::uint32_t>(c) << 1 | (a > b ? 1u : 0u);
    }
    auto bucket_begin = [&](std::size_t v) { return v == 0 ? 0 : static_cast<std::size_t>(end[v - 1]); };
    // Runs of equal (smaller, larger) vertex are the undirected edges. twin[c] is the corner
    // whose outgoing edge is the reverse of c's, or -1 (boundary or non-manifold). Buckets are
    // sorted and paired on all threads; a bucket with a problem is marked, and its violations
    // are written afterwards in bucket order.
    std::vector<std::int32_t> twin(nc, -1);
    EdgePairs pair;
    if (pairs_out) pair.assign(nc, -1);
    std::vector<char> troubled(num_vertices, 0);
    auto pair_up = [&](std::size_t v, bool report) {
        std::int64_t edges = 0;
        for (std::size_t i = bucket_begin(v), stop = end[v]; i < stop;) {
            const std::uint64_t h = bucket[i] >> 32;
            std::size_t j = i + 1;
            while (j < stop && bucket[j] >> 32 == h) ++j;
            ++edges;
            const auto c0 = static_cast<std::uint32_t>(bucket[i]) >> 1;
            auto name = [&] { return "(" + std::to_string(v) + ", " + std::to_string(h) + ")"; };
            if (j - i > 2) {
                troubled[v] = 1;
                if (report)
                    violate(ViolationKind::NonManifoldEdge,
                            "edge " + name() + " has " + std::to_string(j - i) + " incident face sides", face_of(c0));
            } else if (j - i == 2) {
                const auto c1 = static_cast<std::uint32_t>(bucket[i + 1]) >> 1;
                if (pairs_out) pair[c0] = static_cast<std::int32_t>(c1), pair[c1] = static_cast<std::int32_t>(c0);
                if ((bucket[i] & 1) == (bucket[i + 1] & 1)) {
                    troubled[v] = 1;
                    if (report)
                        violate(ViolationKind::InconsistentOrientation,
                                "edge " + name() + " is traversed twice in the same direction", face_of(c1));
                } else {
                    twin[c0] = static_cast<std::int32_t>(c1), twin[c1] = static_cast<std::int32_t>(c0);
                }
            }
            i = j;
        }
        return edges;
    };
    const auto nv64 = static_cast<std::int64_t>(num_vertices);
    std::int64_t edges = 0;
#if defined(_OPENMP)
#pragma omp parallel for schedule(dynamic, 4096) num_threads(threads) if (verify_detail::run_parallel(threads, static_cast<std::int64_t>(nc))) reduction(+ : edges)
#endif
    for (std::int64_t v = 0; v < nv64; ++v) {
        std::uint64_t* b = bucket.data() + bucket_begin(static_cast<std::size_t>(v));
        std::uint64_t* e = bucket.data() + end[static_cast<std::size_t>(v)];
        if (e - b > 24) {
            std::sort(b, e);
        } else {
            for (std::uint64_t* i = b + 1; i < e; ++i)
                for (std::uint64_t* j = i; j > b && j[0] < j[-1]; --j) std::swap(j[0], j[-1]);
        }
        edges += pair_up(static_cast<std::size_t>(v), false);
    }
    t.edges = edges;
    for (std::size_t v = 0; v < num_vertices; ++v)
        if (troubled[v]) pair_up(v, true);
    std::vector<std::uint64_t>().swap(bucket);
    std::vector<int> boundary_next(num_vertices, -1), boundary_count(num_vertices, 0), corners(num_vertices, 0);
    std::vector<char> referenced(num_vertices, 0);
    std::vector<int> parent(num_vertices);
    std::iota(parent.begin(), parent.end(), 0);
    for (std::size_t c = 0; c < nc; ++c) {
        const int a = corner_vertex[c], b = head[c];
        referenced[a] = 1;
        ++corners[a];
        if (next_corner(c) > c) parent[find(parent, a)] = find(parent, b); // a face's last side joins nothing new
        if (twin[c] < 0) {
            ++boundary_count[a];
            if (boundary_next[a] < 0) boundary_next[a] = b;
        }
    }
    for (std::size_t v = 0; v < num_vertices; ++v)
        if (boundary_count[v] > 1)
            violate(ViolationKind::NonManifoldVertex,
                    "vertex " + std::to_string(v) + " has " + std::to_string(boundary_count[v]) + " boundary fans",
                    static_cast<std::int64_t>(v));
    // Fans: from a corner, cross its outgoing edge to the twin's face; the corner there follows the twin.
    std::vector<std::int32_t> start(num_vertices, -1);
    for (std::size_t c = 0; c < nc; ++c) {
        const int v = corner_vertex[c];
        if (start[v] < 0 || twin[prev_corner(c)] < 0) start[v] = static_cast<std::int32_t>(c);
    }
    // Each vertex's fan on all threads, in the order of the vertices' first corners (vertex
    // numbering may have no locality at all), and violations in that order.
    std::vector<std::int32_t> order;
    order.reserve(num_vertices);
    {
        std::vector<char> listed(num_vertices, 0);
        for (std::size_t c = 0; c < nc; ++c) {
            const auto v = static_cast<std::size_t>(corner_vertex[c]);
            if (!listed[v]) listed[v] = 1, order.push_back(static_cast<std::int32_t>(v));
        }
    }
    std::vector<char> single(num_vertices, 0);
    const auto listed = static_cast<std::int64_t>(order.size());
#if defined(_OPENMP)
#pragma omp parallel for schedule(static) num_threads(threads) if (verify_detail::run_parallel(threads, static_cast<std::int64_t>(nc)))
#endif
    for (std::int64_t i = 0; i < listed; ++i) {
        const auto v = static_cast<std::size_t>(order[static_cast<std::size_t>(i)]);
        if (start[v] < 0) continue;
        std::size_t c = static_cast<std::size_t>(start[v]);
        int seen = 0;
        do {
            ++seen;
            if (twin[c] < 0) break;
            c = next_corner(static_cast<std::size_t>(twin[c]));
        } while (c != static_cast<std::size_t>(start[v]) && seen <= corners[v]);
        single[v] = seen == corners[v];
    }
    for (const std::int32_t vi : order) {
        const auto v = static_cast<std::size_t>(vi);
        if (start[v] >= 0 && !single[v])
            violate(ViolationKind::NonManifoldVertex,
                    "the faces around vertex " + std::to_string(v) + " do not form a single fan", static_cast<std::int64_t>(v));
    }
    // Boundary loops: follow boundary half-edges.
    std::vector<char> used(num_vertices, 0);
    for (std::size_t v = 0; v < num_vertices; ++v) {
        if (boundary_next[v] < 0 || used[v]) continue;
        ++t.boundary_loops;
        for (int x = static_cast<int>(v); x >= 0 && !used[x]; x = boundary_next[x]) used[x] = 1;
    }
    for (std::size_t v = 0; v < num_vertices; ++v) {
        if (!referenced[v]) continue;
        ++t.vertices;
        if (find(parent, static_cast<int>(v)) == static_cast<int>(v)) ++t.components;
    }
    t.faces = static_cast<std::int64_t>(nf);
    if (pairs_out) *pairs_out = std::move(pair);
    if (single_fan_out) *single_fan_out = std::move(single);
    return t;
}

/// A counter-clockwise unit grid cell: every side one unit step along an axis, and each step a
/// quarter turn to the left of the one before (then the four close the cell and enclose area 1).
/// Decided on 128-bit integer differences, exactly.
bool unit_square_ccw(const std::vector<std::array<std::int64_t, 2>>& uv) {
    if (uv.size() != 4) return false;
    std::array<std::array<__int128, 2>, 4> step;
    for (std::size_t i = 0; i < 4; ++i) {
        const auto &a = uv[i], &b = uv[(i + 1) % 4];
        step[i] = {static_cast<__int128>(b[0]) - a[0], static_cast<__int128>(b[1]) - a[1]};
        const __int128 manhattan = (step[i][0] < 0 ? -step[i][0] : step[i][0]) + (step[i][1] < 0 ? -step[i][1] : step[i][1]);
        if (manhattan != 1) return false;
    }
    for (std::size_t i = 0; i < 4; ++i) {
        const auto &d = step[i], &e = step[(i + 1) % 4];
        if (e[0] != -d[1] || e[1] != d[0]) return false;
    }
    return true;
}

std::array<double, 2> rot_d(const std::array<double, 2>& p, int r) {
    switch (r & 3) {
        case 0: return p;
        case 1: return {-p[1], p[0]};
        case 2: return {-p[0], -p[1]};
        default: return {p[1], -p[0]};
    }
}

/// Exactly x + y == z? Knuth's TwoSum gives the rounding error of x + y without error
/// (round-to-nearest, no contraction: the build uses -ffp-contract=off); both must match.
bool sums_exactly(double x, double y, double z) {
    const double s = x + y;
    const double bb = s - x;
    const double err = (x - (s - bb)) + (y - bb);
    return s == z && err == 0.0;
}

/// The map the mesh claims to come from: an exact integer-grid map (across every interior edge
/// the two charts differ by a rotation by k*90 degrees and an integer translation), and each
/// vertex's provenance grid point lies on the element it names, decided with exact rationals.
void check_map(const Input& input, const QuadMesh& mesh, const EdgePairs& pairs, const std::vector<char>& single_fan,
               int threads, VerifyResult& r, std::vector<Violation>& out) {
    const auto& U = mesh.map_uvs;
    auto violate = [&](ViolationKind k, std::string msg, std::int64_t e) {
        if (out.size() < 1000) out.push_back({k, std::move(msg), e});
    };
    const std::size_t nf = input.triangles.size();
    auto alive = [&](std::size_t f) { return std::isfinite(U[3 * f][0]); };
    // Displacements, summed in fixed blocks of corners and then block by block in order: the
    // sum is the same whatever the thread count.
    {
        constexpr std::size_t kBlock = std::size_t{1} << 14;
        const auto blocks = static_cast<std::int64_t>((U.size() + kBlock - 1) / kBlock);
        std::vector<double> block_sum(static_cast<std::size_t>(blocks), 0.0);
        double largest = 0.0;
#if defined(_OPENMP)
#pragma omp parallel for schedule(static) num_threads(threads) if (threads > 1 && blocks > 4) reduction(max : largest)
#endif
        for (std::int64_t b = 0; b < blocks; ++b) {
            const std::size_t from = static_cast<std::size_t>(b) * kBlock, to = std::min(U.size(), from + kBlock);
            double sum = 0.0;
            for (std::size_t c = from; c < to; ++c)
                if (alive(c / 3)) {
                    const double d = std::max(std::abs(U[c][0] - input.uvs[c][0]), std::abs(U[c][1] - input.uvs[c][1]));
                    largest = std::max(largest, d);
                    sum += d;
                }
            block_sum[static_cast<std::size_t>(b)] = sum;
        }
        r.max_map_displacement = largest;
        for (const double sum : block_sum) r.sum_map_displacement += sum;
    }
    // Interior edges: the input's edge pairs give each half-edge its opposite.
    auto next = [](std::size_t c) { return c - c % 3 + (c % 3 + 1) % 3; };
    auto prev = [](std::size_t c) { return c - c % 3 + (c % 3 + 2) % 3; };
    // opposite[c]: the corner across the edge that starts at corner c, when the two charts were
    // matched by a unique grid automorphism (rotation[c] quarter turns from c's chart to its
    // neighbour's); -1 otherwise. rotation[c] == -1 marks an edge (found from its smaller
    // corner c) whose charts no grid automorphism matches.
    const auto nc = static_cast<std::int64_t>(U.size());
    std::vector<std::int32_t> opposite(U.size(), -1);
    std::vector<std::int8_t> rotation(U.size(), 0);
#if defined(_OPENMP)
#pragma omp parallel for schedule(static) num_threads(threads) if (verify_detail::run_parallel(threads, static_cast<std::int64_t>(nc)))
#endif
    for (std::int64_t ci = 0; ci < nc; ++ci) {
        const auto c = static_cast<std::size_t>(ci);
        if (pairs[c] < static_cast<std::int32_t>(ci)) continue; // boundary, non-manifold, or done from the pair's other corner
        const auto o = static_cast<std::size_t>(pairs[c]);
        if (!alive(c / 3) || !alive(o / 3)) continue;
        // In c's chart the edge runs a -> b; in o's chart b -> a (for a consistently oriented
        // pair). Some rotation R and one integer translation t must give R a + t == a2 and
        // R b + t == b2 exactly.
        const auto &a = U[c], &b = U[next(c)], &a2 = U[next(o)], &b2 = U[o];
        bool ok = false;
        int found = -1;
        // Necessary: R (b - a) == b2 - a2 in doubles (a rotation commutes with the rounding
        // of a difference), which leaves one candidate for an edge of non-zero length.
        const std::array<double, 2> d{b[0] - a[0], b[1] - a[1]}, d2{b2[0] - a2[0], b2[1] - a2[1]};
        for (int rr = 0; rr < 4 && !ok; ++rr) {
            if (rot_d(d, rr) != d2) continue;
            const auto ra = rot_d(a, rr), rb = rot_d(b, rr);
            const double tx = a2[0] - ra[0], ty = a2[1] - ra[1];
            ok = std::floor(tx) == tx && std::floor(ty) == ty && sums_exactly(ra[0], tx, a2[0]) &&
                 sums_exactly(ra[1], ty, a2[1]) && sums_exactly(rb[0], tx, b2[0]) && sums_exactly(rb[1], ty, b2[1]);
            if (ok) found = rr;
        }
        // A zero-length edge admits every rotation: the fan check below skips its vertices.
        if (ok && (a[0] != b[0] || a[1] != b[1])) {
            opposite[c] = static_cast<std::int32_t>(o);
            opposite[o] = static_cast<std::int32_t>(c);
            rotation[c] = static_cast<std::int8_t>(found);
            rotation[o] = static_cast<std::int8_t>((4 - found) & 3);
        }
        if (!ok) rotation[c] = -1;
    }
    for (std::size_t c = 0; c < U.size(); ++c)
        if (rotation[c] < 0)
            violate(ViolationKind::MapNotIntegerGrid,
                    "the charts of triangles " + std::to_string(c / 3) + " and " + std::to_string(pairs[c] / 3) +
                        " do not differ by a grid automorphism along their shared edge",
                    static_cast<std::int64_t>(c / 3));
    // Fans: around every interior vertex whose fan is matched edge by edge, the transitions
    // compose to a rotation; each edge transition maps the vertex's UV onto itself exactly, so a
    // composed identity closes the fan, and a composed rotation (a singularity) must have its
    // fixed point, the vertex's UV, on an integer grid point (Algorithm 2). Walking the fan
    // crosses, once each, the edges that end at the vertex's corners (prev(c) -> c), so the
    // composed turn is a sum over the corners, taken in one pass. A fan is left unchecked when
    // an edge in it is unmatched (boundary, degenerate or not a grid automorphism), a triangle
    // in it was collapsed, or the vertex is non-manifold.
    const std::size_t nv = single_fan.size();
    std::vector<std::int32_t> first(nv, -1);
    std::vector<std::int8_t> turns(nv, 0); // quarter turns mod 4; -1: the fan is not checked
    for (std::size_t c = 0; c < U.size(); ++c) {
        const auto v = static_cast<std::size_t>(input.triangles[c / 3][c % 3]);
        if (first[v] < 0) first[v] = static_cast<std::int32_t>(c);
        if (turns[v] < 0) continue;
        if (!alive(c / 3) || opposite[prev(c)] < 0 || !single_fan[v])
            turns[v] = -1;
        else
            turns[v] = static_cast<std::int8_t>((turns[v] + rotation[prev(c)]) & 3);
    }
    for (std::size_t c0 = 0; c0 < U.size(); ++c0) {
        const auto v = static_cast<std::size_t>(input.triangles[c0 / 3][c0 % 3]);
        if (first[v] != static_cast<std::int32_t>(c0) || turns[v] <= 0) continue;
        ++r.map_singularities;
        const auto& u = U[c0];
        if (std::floor(u[0]) != u[0] || std::floor(u[1]) != u[1])
            violate(ViolationKind::SingularityOffGrid,
                    "input vertex " + std::to_string(v) + ": a singularity (" + std::to_string(turns[v] * 90) +
                        " degree turn) at (" + std::to_string(u[0]) + ", " + std::to_string(u[1]) +
                        ") in the chart of triangle " + std::to_string(c0 / 3) + ", not at an integer grid point",
                    static_cast<std::int64_t>(v));
    }
    // Provenance: the grid point on the named vertex, edge or triangle, decided by CGAL's exact
    // predicates (the grid point is exact in doubles: the map's values are below 2^52).
    using P = CGAL::Epick::Point_2;
    for (std::size_t i = 0; i < mesh.provenance.size() && i < mesh.positions.size(); ++i) {
        const Provenance& p = mesh.provenance[i];
        const auto T = static_cast<std::size_t>(p.chart_triangle);
        constexpr std::int64_t kExact = std::int64_t{1} << 53;
        bool on = p.chart_triangle >= 0 && T < nf && alive(T) && std::abs(p.grid[0]) < kExact && std::abs(p.grid[1]) < kExact;
        if (on) {
            const P g(static_cast<double>(p.grid[0]), static_cast<double>(p.grid[1]));
            const std::array<P, 3> t{P(U[3 * T][0], U[3 * T][1]), P(U[3 * T + 1][0], U[3 * T + 1][1]),
                                     P(U[3 * T + 2][0], U[3 * T + 2][1])};
            if (p.kind == QVertexKind::Vertex) {
                // A corner of the named triangle sits on the grid point. (Its input vertex may be
                // one that a collapse of UV-degenerate edges merged into p.element.)
                on = t[0] == g || t[1] == g || t[2] == g;
            } else if (p.kind == QVertexKind::Edge) {
                const int k = p.local_edge;
                on = k >= 0 && k < 3 && static_cast<std::size_t>(p.element) == T;
                if (on) {
                    const P &e0 = t[static_cast<std::size_t>(k)], &e1 = t[static_cast<std::size_t>((k + 1) % 3)];
                    on = CGAL::collinear(e0, e1, g) && CGAL::collinear_are_strictly_ordered_along_line(e0, g, e1);
                }
            } else {
                const auto s = CGAL::orientation(t[0], t[1], t[2]);
                on = s != CGAL::COLLINEAR && CGAL::orientation(t[0], t[1], g) == s && CGAL::orientation(t[1], t[2], g) == s &&
                     CGAL::orientation(t[2], t[0], g) == s;
            }
        }
        if (!on)
            violate(ViolationKind::NotOnGridPoint,
                    "vertex " + std::to_string(i) + ": grid point (" + std::to_string(p.grid[0]) + ", " +
                        std::to_string(p.grid[1]) + ") is not on the element its provenance names (triangle " +
                        std::to_string(p.chart_triangle) + ")",
                    static_cast<std::int64_t>(i));
    }
}

} // namespace


VerifyResult verify(const Input& input, const QuadMesh& mesh, const VerifyOptions& options) {
    VerifyResult r;
    auto& out = r.violations;
    const std::size_t nv = mesh.positions.size();
    const int threads = verify_detail::thread_count(options.threads);
    if (mesh.faces.empty()) out.push_back({ViolationKind::EmptyMesh, "the mesh has no faces", -1});
    bool indices_ok = true;
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
        const auto& face = mesh.faces[f];
        if (face.size() != 4 && out.size() < 1000)
            out.push_back({ViolationKind::NotQuad, "face " + std::to_string(f) + " has " + std::to_string(face.size()) + " vertices",
                           static_cast<std::int64_t>(f)});
        for (std::size_t i = 0; i < face.size(); ++i) {
            if (face[i] < 0 || static_cast<std::size_t>(face[i]) >= nv) {
                indices_ok = false;
                out.push_back({ViolationKind::BadIndex, "face " + std::to_string(f) + " refers to vertex " + std::to_string(face[i]),
                               static_cast<std::int64_t>(f)});
            }
            for (std::size_t j = i + 1; j < face.size(); ++j)
                if (face[i] == face[j] && out.size() < 1000)
                    out.push_back({ViolationKind::RepeatedVertex, "face " + std::to_string(f) + " uses vertex " + std::to_string(face[i]) + " twice",
                                   static_cast<std::int64_t>(f)});
        }
    }
    for (std::size_t v = 0; v < nv; ++v)
        for (double x : mesh.positions[v])
            if (!std::isfinite(x)) {
                out.push_back({ViolationKind::NonFinitePosition, "vertex " + std::to_string(v) + " has a non-finite position",
                               static_cast<std::int64_t>(v)});
                break;
            }
    if (mesh.face_uvs.size() == mesh.faces.size())
        for (std::size_t f = 0; f < mesh.faces.size(); ++f)
            if (mesh.faces[f].size() == 4 && !unit_square_ccw(mesh.face_uvs[f]) && out.size() < 1000)
                out.push_back({ViolationKind::LocalUvNotUnitSquare,
                               "the local UVs of face " + std::to_string(f) + " are not a counter-clockwise unit square",
                               static_cast<std::int64_t>(f)});
    std::size_t total_corners = 0;
    for (const auto& face : mesh.faces) total_corners += face.size();
    if (total_corners > static_cast<std::size_t>(INT32_MAX) || 3 * input.triangles.size() > static_cast<std::size_t>(INT32_MAX)) {
        out.push_back({ViolationKind::TooLarge, "more than 2^31 - 1 face corners (mesh or input): beyond the checker's tables", -1});
        r.valid = false;
        return r;
    }
    if (indices_ok) {
        std::vector<std::size_t> offset(mesh.faces.size() + 1, 0);
        std::vector<int> corners;
        for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
            offset[f + 1] = offset[f] + mesh.faces[f].size();
            corners.insert(corners.end(), mesh.faces[f].begin(), mesh.faces[f].end());
        }
        const Topology t = analyse(nv, offset, corners, &out, threads);
        r.faces = t.faces;
        r.vertices = t.vertices;
        r.edges = t.edges;
        r.boundary_loops = t.boundary_loops;
        r.components = t.components;
        r.euler = t.euler();
        if (static_cast<std::int64_t>(nv) != t.vertices)
            out.push_back({ViolationKind::UnreferencedVertex,
                           std::to_string(static_cast<std::int64_t>(nv) - t.vertices) + " vertices are used by no face", -1});
    }
    // The input's topology and exact signed UV area.
    bool input_ok = input.uvs.size() == 3 * input.triangles.size();
    std::vector<std::size_t> tri_offset(input.triangles.size() + 1);
    std::vector<int> tri_corners;
    tri_corners.reserve(3 * input.triangles.size());
    for (std::size_t f = 0; f < input.triangles.size(); ++f) {
        tri_offset[f + 1] = 3 * (f + 1);
        for (int v : input.triangles[f]) {
            input_ok = input_ok && v >= 0 && static_cast<std::size_t>(v) < input.positions.size();
            tri_corners.push_back(v);
        }
    }
    EdgePairs input_pairs;
    std::vector<char> input_single_fan;
    if (input_ok) {
        const Topology ti = analyse(input.positions.size(), tri_offset, tri_corners, nullptr, threads, &input_pairs, &input_single_fan);
        r.input_euler = ti.euler();
        r.input_boundary_loops = ti.boundary_loops;
        r.input_components = ti.components;
        // Signed UV area: a double sum with a rigorous error bound decides the rounding; exact
        // rationals are used only when the bound does not.
        double approx = 0.0, bound = 0.0;
        bool finite = true;
        for (std::size_t f = 0; f < input.triangles.size(); ++f) {
            const auto &a = input.uvs[3 * f], &b = input.uvs[3 * f + 1], &c = input.uvs[3 * f + 2];
            const double t = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
            finite = finite && std::isfinite(t);
            approx += t;
            bound += std::abs(b[0] - a[0]) * std::abs(c[1] - a[1]) + std::abs(b[1] - a[1]) * std::abs(c[0] - a[0]) +
                     std::abs(approx);
        }
        bound *= 8 * std::numeric_limits<double>::epsilon();
        approx *= 0.5;
        bound *= 0.5;
        const double nearest = std::nearbyint(approx);
        if (finite && std::abs(approx - nearest) + bound < 0.5) {
            r.input_signed_uv_area_rounded = static_cast<std::int64_t>(nearest);
        } else if (finite) {
            Rational area = 0;
            for (std::size_t f = 0; f < input.triangles.size(); ++f) {
                const auto &a = input.uvs[3 * f], &b = input.uvs[3 * f + 1], &c = input.uvs[3 * f + 2];
                area += (Rational(b[0]) - Rational(a[0])) * (Rational(c[1]) - Rational(a[1])) -
                        (Rational(b[1]) - Rational(a[1])) * (Rational(c[0]) - Rational(a[0]));
            }
            area /= 2;
            approx = CGAL::to_double(area);
            // Round half away from zero, decided exactly.
            Rational lo = Rational(std::floor(approx));
            while (lo > area) lo -= 1;
            while (lo + 1 <= area) lo += 1;
            const Rational frac = area - lo;
            r.input_signed_uv_area_rounded = static_cast<std::int64_t>(CGAL::to_double(lo)) + (frac >= Rational(1, 2) ? 1 : 0);
        }
        r.input_signed_uv_area = std::to_string(approx);
        if (indices_ok && !mesh.faces.empty()) {
            if (r.euler != r.input_euler)
                out.push_back({ViolationKind::EulerMismatch,
                               "Euler characteristic " + std::to_string(r.euler) + ", input has " + std::to_string(r.input_euler), -1});
            if (r.boundary_loops != r.input_boundary_loops)
                out.push_back({ViolationKind::BoundaryMismatch,
                               std::to_string(r.boundary_loops) + " boundary loops, input has " + std::to_string(r.input_boundary_loops), -1});
            if (r.components != r.input_components)
                out.push_back({ViolationKind::ComponentMismatch,
                               std::to_string(r.components) + " components, input has " + std::to_string(r.input_components), -1});
        }
    }
    if (input_ok && !mesh.map_uvs.empty()) {
        if (mesh.map_uvs.size() != input.uvs.size())
            out.push_back({ViolationKind::MapNotIntegerGrid, "the mesh's map has " + std::to_string(mesh.map_uvs.size()) +
                                                                 " corner UVs, the input " + std::to_string(input.uvs.size()), -1});
        else
            check_map(input, mesh, input_pairs, input_single_fan, threads, r, out);
    }
    if (input_ok && indices_ok && options.locate && mesh.provenance.empty() && !input.triangles.empty())
        verify_detail::check_located(input, mesh, options, r, out);
    r.valid = out.empty();
    return r;
}

} // namespace qex

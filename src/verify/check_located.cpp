// The checker's oracle mode for meshes that carry no provenance (from another extractor, or read
// back from an OBJ): every output vertex is located on the input surface (CGAL's AABB tree) and
// must be the image of an integer grid point; every face's corners, carried into one chart along
// the input's transitions, must be the corners of one grid cell in counter-clockwise order; and
// the faces must cover the map (their number equals the map's signed area) unless fold-overs make
// that impossible. Positions from other tools are rounded, so locating needs two tolerances (UV
// units and a fraction of the bounding-box diagonal); every comparison after that is on integers.
#include "checker.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Simple_cartesian.h>

#include <algorithm>
#include <functional>
#include <cmath>
#include <cstdint>
#include <string>

namespace qex::verify_detail {
namespace {

using K = CGAL::Simple_cartesian<double>;
using Triangles = std::vector<K::Triangle_3>;
using Primitive = CGAL::AABB_triangle_primitive<K, Triangles::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;

/// x -> R^r x + t between the charts of two adjacent triangles (integers only).
struct Transition {
    int r = 0;
    std::int64_t tx = 0, ty = 0;
};

std::array<std::int64_t, 2> rot_i(std::array<std::int64_t, 2> p, int r) {
    switch (r & 3) {
        case 0: return p;
        case 1: return {-p[1], p[0]};
        case 2: return {-p[0], -p[1]};
        default: return {p[1], -p[0]};
    }
}

std::array<double, 2> rot_f(std::array<double, 2> p, int r) {
    switch (r & 3) {
        case 0: return p;
        case 1: return {-p[1], p[0]};
        case 2: return {-p[0], -p[1]};
        default: return {p[1], -p[0]};
    }
}

/// Grid points far beyond any map (|coordinate| >= 2^60) are not compared: a path through a
/// broken map can compose translations without bound.
constexpr std::int64_t kFar = std::int64_t{1} << 60;

bool unit_step(const std::array<std::int64_t, 2>& a, const std::array<std::int64_t, 2>& b) {
    for (int k = 0; k < 2; ++k)
        if (a[k] <= -kFar || a[k] >= kFar || b[k] <= -kFar || b[k] >= kFar) return false;
    return std::llabs(a[0] - b[0]) + std::llabs(a[1] - b[1]) == 1;
}

std::string point(const std::array<std::int64_t, 2>& g) {
    return "(" + std::to_string(g[0]) + ", " + std::to_string(g[1]) + ")";
}

} // namespace

void check_located(const Input& in, const QuadMesh& mesh, const VerifyOptions& opt, VerifyResult& r,
                   std::vector<Violation>& out) {
    auto violate = [&](ViolationKind k, std::string msg, std::int64_t e) {
        if (out.size() < 1000) out.push_back({k, std::move(msg), e});
    };
    const std::size_t nt = in.triangles.size();
    // Surface triangles (3D-degenerate ones cannot be closest to anything their neighbours miss).
    Triangles tris;
    std::vector<std::uint32_t> tri_index;
    tris.reserve(nt);
    tri_index.reserve(nt);
    double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    for (std::size_t t = 0; t < nt; ++t) {
        K::Point_3 p[3];
        bool finite = true;
        for (int k = 0; k < 3; ++k) {
            const auto& x = in.positions[static_cast<std::size_t>(in.triangles[t][k])];
            for (int d = 0; d < 3; ++d) {
                finite = finite && std::isfinite(x[d]) && std::isfinite(in.uvs[3 * t + k][d % 2]);
                lo[d] = std::min(lo[d], x[d]);
                hi[d] = std::max(hi[d], x[d]);
            }
            p[k] = K::Point_3(x[0], x[1], x[2]);
        }
        if (!finite) return; // not a map this mode can judge (validation names the problem)
        const K::Triangle_3 tri(p[0], p[1], p[2]);
        if (tri.is_degenerate()) continue;
        tris.push_back(tri);
        tri_index.push_back(static_cast<std::uint32_t>(t));
    }
    if (tris.empty() || mesh.positions.empty()) return;
    r.located = true;
    const double diag = std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                                  (hi[2] - lo[2]) * (hi[2] - lo[2]));
    const double max_dist = opt.distance_tolerance * diag;
    Tree tree(tris.cbegin(), tris.cend());
    tree.accelerate_distance_queries();

    // Adjacency of the input's half-edges and the rounded transition across each.
    const std::size_t nc = 3 * nt;
    std::vector<std::pair<std::uint64_t, std::uint32_t>> half(nc);
    auto next = [](std::size_t c) { return c - c % 3 + (c % 3 + 1) % 3; };
    for (std::size_t c = 0; c < nc; ++c) {
        const auto a = static_cast<std::uint32_t>(in.triangles[c / 3][c % 3]);
        const auto b = static_cast<std::uint32_t>(in.triangles[c / 3][(c % 3 + 1) % 3]);
        half[c] = {static_cast<std::uint64_t>(std::min(a, b)) << 32 | std::max(a, b), static_cast<std::uint32_t>(c)};
    }
    std::sort(half.begin(), half.end());
    std::vector<std::int64_t> opposite(nc, -1);
    std::vector<Transition> across(nc);
    std::vector<char> paired(nc, 0); // the half-edge has exactly one opposite
    for (std::size_t i = 0, j = 0; i < nc; i = j) {
        j = i;
        while (j < nc && half[j].first == half[i].first) ++j;
        if (j - i != 2) continue;
        const std::size_t c = half[i].second, o = half[i + 1].second;
        paired[c] = paired[o] = 1;
        const auto &p1 = in.uvs[c], &q1 = in.uvs[next(c)], &p2 = in.uvs[next(o)], &q2 = in.uvs[o];
        // The rotation is the quarter turn that carries one side's edge vector onto the other's;
        // an edge shorter than the tolerance in UV does not determine it and is not crossed.
        const double len1 = std::max(std::abs(q1[0] - p1[0]), std::abs(q1[1] - p1[1]));
        const double len2 = std::max(std::abs(q2[0] - p2[0]), std::abs(q2[1] - p2[1]));
        int best = 0;
        double best_err = HUGE_VAL;
        for (int rr = 0; rr < 4; ++rr) {
            const auto d = rot_f({q1[0] - p1[0], q1[1] - p1[1]}, rr);
            const double e = std::max(std::abs(d[0] - (q2[0] - p2[0])), std::abs(d[1] - (q2[1] - p2[1])));
            if (e < best_err) best_err = e, best = rr;
        }
        if (!(len1 > 4 * opt.uv_tolerance && len2 > 4 * opt.uv_tolerance && best_err <= opt.uv_tolerance)) continue;
        const auto rp = rot_f(p1, best);
        const double tx = std::nearbyint(p2[0] - rp[0]), ty = std::nearbyint(p2[1] - rp[1]);
        if (!(std::abs(tx) < 9e15 && std::abs(ty) < 9e15)) continue;
        opposite[c] = static_cast<std::int64_t>(o);
        opposite[o] = static_cast<std::int64_t>(c);
        across[c] = {best, static_cast<std::int64_t>(tx), static_cast<std::int64_t>(ty)};
        // The inverse: x = R^-r (x' - t).
        const auto back = rot_i({-static_cast<std::int64_t>(tx), -static_cast<std::int64_t>(ty)}, 4 - best);
        across[o] = {(4 - best) & 3, back[0], back[1]};
    }

    // Singular input vertices: their fans are closed and the transitions around them compose to a
    // turn (or include an edge too short to determine its transition).
    std::vector<char> singular(in.positions.size(), 0), seen(nc, 0);
    auto prev = [](std::size_t c) { return c - c % 3 + (c % 3 + 2) % 3; };
    for (std::size_t c0 = 0; c0 < nc; ++c0) {
        if (seen[c0]) continue;
        std::size_t c = c0;
        int turns = 0;
        bool closed = false;
        for (std::size_t steps = 0; steps <= nc; ++steps) {
            seen[c] = 1;
            const std::int64_t o = opposite[prev(c)];
            if (o < 0) {
                turns = paired[prev(c)] ? 1 : 0; // undetermined turn: treated as singular
                closed = paired[prev(c)] != 0;
                break;
            }
            turns += across[prev(c)].r;
            c = static_cast<std::size_t>(o);
            if (c == c0) {
                closed = true;
                break;
            }
            if (seen[c]) break;
        }
        if (closed && (turns & 3) != 0) singular[static_cast<std::size_t>(in.triangles[c0 / 3][c0 % 3])] = 1;
    }

    // Triangles that are flipped or degenerate in UV: there the map is not locally injective, and
    // a path across them does not fix the chart it arrives in.
    std::vector<char> folded(nt, 0);
    for (std::size_t t = 0; t < nt; ++t) {
        using P = CGAL::Epick::Point_2;
        const auto &a = in.uvs[3 * t], &b = in.uvs[3 * t + 1], &c = in.uvs[3 * t + 2];
        const auto o = CGAL::orientation(P(a[0], a[1]), P(b[0], b[1]), P(c[0], c[1]));
        folded[t] = o != CGAL::POSITIVE;
        r.map_flipped_triangles += o == CGAL::NEGATIVE;
    }

    // Vertices: the closest surface point, its UV in that triangle's chart, the nearest grid point.
    struct Located {
        std::uint32_t triangle = 0;
        std::int64_t on_vertex = -1; ///< the input vertex it sits on (within the distance tolerance)
        std::array<std::int64_t, 2> grid{0, 0};
        bool ok = false;
    };
    int corner_hit = -1; // set by locate(): the triangle's corner at the closest point, or -1
    auto locate = [&](const std::array<double, 3>& x, std::array<double, 2>& uv, double& dist) {
        const K::Point_3 p(x[0], x[1], x[2]);
        const auto hit = tree.closest_point_and_primitive(p);
        const std::size_t k = static_cast<std::size_t>(hit.second - tris.cbegin());
        const std::uint32_t t = tri_index[k];
        dist = std::sqrt(CGAL::squared_distance(p, hit.first));
        // Barycentric coordinates of the closest point (in the triangle's plane).
        const K::Triangle_3& tri = tris[k];
        const K::Vector_3 e0 = tri[1] - tri[0], e1 = tri[2] - tri[0], w = hit.first - tri[0];
        const double d00 = e0 * e0, d01 = e0 * e1, d11 = e1 * e1, d20 = w * e0, d21 = w * e1;
        const double den = d00 * d11 - d01 * d01;
        const double b1 = den != 0 ? (d11 * d20 - d01 * d21) / den : 0.0;
        const double b2 = den != 0 ? (d00 * d21 - d01 * d20) / den : 0.0;
        const double b0 = 1.0 - b1 - b2;
        corner_hit = -1;
        for (int q = 0; q < 3 && corner_hit < 0; ++q)
            if (std::sqrt(CGAL::squared_distance(hit.first, tri[q])) <= max_dist) corner_hit = q;
        const auto &u0 = in.uvs[3 * t], &u1 = in.uvs[3 * t + 1], &u2 = in.uvs[3 * t + 2];
        uv = {b0 * u0[0] + b1 * u1[0] + b2 * u2[0], b0 * u0[1] + b1 * u1[1] + b2 * u2[1]};
        return t;
    };
    // Vertices next to a fold-over: a flipped or degenerate triangle shares a vertex with the
    // triangle the output vertex lies on. There the grid point can have several preimages, and a
    // vertex that stands for all of them (merged clones) can be judged from none.
    std::vector<char> folded_vertex(in.positions.size(), 0);
    for (std::size_t t = 0; t < nt; ++t)
        if (folded[t])
            for (int k = 0; k < 3; ++k) folded_vertex[static_cast<std::size_t>(in.triangles[t][k])] = 1;
    auto near_fold = [&](std::uint32_t t) {
        for (int k = 0; k < 3; ++k)
            if (folded_vertex[static_cast<std::size_t>(in.triangles[t][k])]) return true;
        return false;
    };
    std::vector<Located> loc(mesh.positions.size());
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
        const auto& x = mesh.positions[v];
        if (!std::isfinite(x[0]) || !std::isfinite(x[1]) || !std::isfinite(x[2])) continue;
        std::array<double, 2> uv;
        double dist = 0;
        loc[v].triangle = locate(x, uv, dist);
        if (corner_hit >= 0) {
            loc[v].on_vertex = in.triangles[loc[v].triangle][corner_hit];
            uv = in.uvs[3 * loc[v].triangle + static_cast<std::size_t>(corner_hit)];
        }
        r.max_surface_distance = std::max(r.max_surface_distance, diag > 0 ? dist / diag : 0.0);
        if (dist > max_dist) {
            violate(ViolationKind::OffSurface,
                    "vertex " + std::to_string(v) + " is " + std::to_string(dist) + " from the input surface (tolerance " +
                        std::to_string(max_dist) + ")",
                    static_cast<std::int64_t>(v));
            continue;
        }
        const double gx = std::nearbyint(uv[0]), gy = std::nearbyint(uv[1]);
        const double off = std::max(std::abs(uv[0] - gx), std::abs(uv[1] - gy));
        r.max_grid_distance = std::max(r.max_grid_distance, off);
        if (!(off <= opt.uv_tolerance) || !(std::abs(gx) < 9e15 && std::abs(gy) < 9e15)) {
            violate(ViolationKind::NotOnGridPoint,
                    "vertex " + std::to_string(v) + " maps to (" + std::to_string(uv[0]) + ", " + std::to_string(uv[1]) +
                        ") in the chart of input triangle " + std::to_string(loc[v].triangle) +
                        ", not within " + std::to_string(opt.uv_tolerance) + " of an integer grid point",
                    static_cast<std::int64_t>(v));
            continue;
        }
        loc[v].grid = {static_cast<std::int64_t>(gx), static_cast<std::int64_t>(gy)};
        loc[v].ok = true;
    }

    // Faces: a breadth-first search over the input's triangles from the triangle under the face's
    // centre reaches each corner's triangle (for a corner on an input vertex, any triangle of its
    // fan); the transitions along the way carry the corner's grid point into the centre's chart.
    std::vector<std::uint32_t> stamp(nt, 0);
    std::vector<double> best(nt, 0.0);
    std::vector<std::pair<double, std::uint32_t>> heap;
    std::vector<K::Point_3> centroid(nt);
    for (std::size_t t = 0; t < nt; ++t) {
        const auto &a = in.positions[static_cast<std::size_t>(in.triangles[t][0])],
                   &b = in.positions[static_cast<std::size_t>(in.triangles[t][1])],
                   &c = in.positions[static_cast<std::size_t>(in.triangles[t][2])];
        centroid[t] = K::Point_3((a[0] + b[0] + c[0]) / 3, (a[1] + b[1] + c[1]) / 3, (a[2] + b[2] + c[2]) / 3);
    }
    std::vector<std::int64_t> via(nt, -1); // the half-edge through which a triangle was reached
    std::uint32_t generation = 0;
    const std::size_t budget = std::max<std::size_t>(1u << 14, 64 * nt / std::max<std::size_t>(mesh.faces.size(), 1));
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
        const auto& face = mesh.faces[f];
        if (face.size() != 4) continue; // reported as NotQuad
        bool ok = true;
        std::array<double, 3> centre{0, 0, 0};
        for (int v : face) {
            if (v < 0 || static_cast<std::size_t>(v) >= loc.size() || !loc[static_cast<std::size_t>(v)].ok) ok = false;
            else
                for (int d = 0; d < 3; ++d) centre[d] += 0.25 * mesh.positions[static_cast<std::size_t>(v)][d];
        }
        if (!ok) continue; // its vertices are reported already
        // Each corner's triangle in turn (then the surface point under the centroid) anchors the
        // chart: a path from an anchor that sits on a singularity, or inside a fold-over next to
        // one, may pass either way round it and turn the other corners about it. The face passes
        // when one anchor shows a unit cell.
        std::array<std::array<std::int64_t, 2>, 4> g{}, first{};
        std::uint32_t first_anchor = 0;
        bool through_fold = false, through_singular = false;
        auto transport = [&](std::uint32_t tc) {
            bool ok = true;
            if (++generation == 0) {
                std::fill(stamp.begin(), stamp.end(), 0);
                generation = 1;
            }
            std::array<std::int64_t, 4> reached{-1, -1, -1, -1};
            int missing = 4;
            auto visit = [&](std::uint32_t t) {
                for (std::size_t i = 0; i < 4; ++i) {
                    if (reached[i] >= 0) continue;
                    const Located& L = loc[static_cast<std::size_t>(face[i])];
                    bool hit = L.triangle == t;
                    for (int k = 0; k < 3 && !hit && L.on_vertex >= 0; ++k) hit = in.triangles[t][k] == L.on_vertex;
                    if (hit) reached[i] = t, --missing;
                }
            };
            // Dijkstra over triangle centroids: the paths approximate geodesics, so the path to the
            // corner across the cell runs through the cell, not round a singular corner.
            heap.clear();
            best[tc] = 0.0;
            stamp[tc] = generation;
            via[tc] = -1;
            heap.push_back({0.0, tc});
            std::size_t settled = 0;
            while (!heap.empty() && missing > 0 && settled < budget) {
                std::pop_heap(heap.begin(), heap.end(), std::greater<>());
                const auto [d, t] = heap.back();
                heap.pop_back();
                if (d > best[t]) continue;
                ++settled;
                visit(t);
                for (int k = 0; k < 3; ++k) {
                    const std::int64_t o = opposite[3 * t + k];
                    if (o < 0) continue;
                    const auto n = static_cast<std::uint32_t>(o / 3);
                    const double dn = d + std::sqrt(CGAL::squared_distance(centroid[t], centroid[n]));
                    if (stamp[n] == generation && dn >= best[n]) continue;
                    stamp[n] = generation;
                    best[n] = dn;
                    via[n] = o; // entered n through its half-edge o
                    heap.push_back({dn, n});
                    std::push_heap(heap.begin(), heap.end(), std::greater<>());
                }
            }
            for (std::size_t i = 0; i < 4 && ok; ++i) {
                const Located& L = loc[static_cast<std::size_t>(face[i])];
                if (reached[i] < 0) {
                    ok = false;
                    break;
                }
                // The grid point in the reached triangle's chart, then back to the centre's triangle.
                const auto t0 = static_cast<std::uint32_t>(reached[i]);
                auto p = L.grid;
                if (t0 != L.triangle) {
                    int k = 0;
                    while (k < 2 && in.triangles[t0][k] != L.on_vertex) ++k;
                    const auto& u = in.uvs[3 * t0 + static_cast<std::size_t>(k)];
                    p = {static_cast<std::int64_t>(std::nearbyint(u[0])), static_cast<std::int64_t>(std::nearbyint(u[1]))};
                }
                through_fold = through_fold || folded[L.triangle] || folded[tc];
                for (std::uint32_t t = t0; t != tc;) {
                    through_fold = through_fold || folded[t];
                    const auto o = static_cast<std::size_t>(via[t]);
                    through_singular = through_singular ||
                                       singular[static_cast<std::size_t>(in.triangles[o / 3][o % 3])] ||
                                       singular[static_cast<std::size_t>(in.triangles[o / 3][(o % 3 + 1) % 3])];
                    const Transition& T = across[o]; // from t's chart to the chart it was reached from
                    const auto q = rot_i(p, T.r);
                    if (std::llabs(q[0]) >= kFar || std::llabs(q[1]) >= kFar) { // judged as no unit step
                        p = {kFar, kFar};
                        break;
                    }
                    p = {q[0] + T.tx, q[1] + T.ty};
                    t = static_cast<std::uint32_t>(opposite[o] / 3);
                }
                g[i] = p;
            }
            return ok;
        };
        auto is_cell = [](const std::array<std::array<std::int64_t, 2>, 4>& q) {
            for (std::size_t i = 0; i < 4; ++i)
                if (!unit_step(q[i], q[(i + 1) % 4])) return false;
            // Unit steps keep every corner within 2 of the first: the area in differences is exact.
            std::int64_t twice_area = 0;
            for (std::size_t i = 1; i + 1 < 4; ++i) {
                const std::int64_t ax = q[i][0] - q[0][0], ay = q[i][1] - q[0][1];
                const std::int64_t bx = q[i + 1][0] - q[0][0], by = q[i + 1][1] - q[0][1];
                twice_area += ax * by - ay * bx;
            }
            return twice_area == 2;
        };
        // From the anchor at corner i, the paths to corners i - 1 and i + 1 can only turn about
        // corner i or about their own end, which keeps their distance to corner i: so each edge
        // is judged from its own ends, and only the cell's shape depends on the way round.
        bool cell = false, reached_all = false;
        std::array<bool, 4> edge_ok{false, false, false, false}, edge_seen{false, false, false, false};
        for (int attempt = 0; attempt < 5 && !cell; ++attempt) {
            std::uint32_t tc;
            if (attempt < 4) {
                tc = loc[static_cast<std::size_t>(face[static_cast<std::size_t>(attempt)])].triangle;
            } else {
                std::array<double, 2> uvc;
                double dist = 0;
                tc = locate(centre, uvc, dist);
            }
            if (!transport(tc)) continue;
            if (!reached_all) first = g, first_anchor = tc;
            reached_all = true;
            cell = is_cell(g);
            if (attempt < 4) {
                const auto i = static_cast<std::size_t>(attempt);
                for (std::size_t e : {i, (i + 3) % 4}) { // edges (i, i+1) and (i-1, i)
                    const auto &a = g[e], &b = g[(e + 1) % 4];
                    edge_seen[e] = true;
                    edge_ok[e] = edge_ok[e] || unit_step(a, b);
                }
            }
        }
        if (cell) continue;
        // A path across a fold-over, or through the fan of a singular vertex (it passes the
        // singularity on one side, the iso-lines perhaps on the other), does not fix the chart it
        // arrives in: a failure there is undecided, not a violation.
        bool corner_near_fold = false;
        for (int v : face) corner_near_fold = corner_near_fold || near_fold(loc[static_cast<std::size_t>(v)].triangle);
        auto report = [&](std::string msg) {
            if (!through_fold && !through_singular && !corner_near_fold)
                violate(ViolationKind::FaceNotGridCell, std::move(msg), static_cast<std::int64_t>(f));
            else if (r.undecided.size() < 1000)
                r.undecided.push_back({ViolationKind::FaceNotGridCell,
                                       msg + (through_fold       ? " (the paths cross fold-overs of the map)"
                                              : corner_near_fold ? " (a corner lies next to a fold-over of the map)"
                                                                 : " (the paths pass through the fan of a singularity)"),
                                       static_cast<std::int64_t>(f)});
        };
        if (!reached_all) {
            report("face " + std::to_string(f) + ": its corners lie too far apart on the input surface to be one grid cell");
            continue;
        }
        bool edges_ok = true;
        for (std::size_t e = 0; e < 4; ++e)
            if (edge_seen[e] && !edge_ok[e]) {
                edges_ok = false;
                report("face " + std::to_string(f) + ": its edge from vertex " + std::to_string(face[e]) + " to vertex " +
                       std::to_string(face[(e + 1) % 4]) + " does not join neighbouring grid points");
            }
        if (!edges_ok) continue;
        // Every edge is a unit step, but no anchor shows one cell.
        report("face " + std::to_string(f) + ": its corners are the grid points " + point(first[0]) + " " + point(first[1]) +
               " " + point(first[2]) + " " + point(first[3]) + " in the chart of input triangle " +
               std::to_string(first_anchor) + ", not a counter-clockwise unit cell");
    }

    // Coverage: a closed, consistently oriented mesh of positive unit cells covers the map once
    // exactly when it has as many faces as the map has area. Fold-overs can make that impossible;
    // the difference is then reported but not a violation.
    r.coverage_difference = static_cast<std::int64_t>(mesh.faces.size()) - r.input_signed_uv_area_rounded;
    if (r.coverage_difference != 0 && r.map_flipped_triangles == 0)
        violate(ViolationKind::CoverageMismatch,
                std::to_string(mesh.faces.size()) + " faces, but the map (without fold-overs) has area " +
                    std::to_string(r.input_signed_uv_area_rounded),
                -1);
}

} // namespace qex::verify_detail

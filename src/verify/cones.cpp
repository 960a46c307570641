// The map's cones (input vertices joined by edges shorter than the UV tolerance), read from UV
// angle sums, and its fold-over footprints with their co-located dipoles (cones.h).
#include "cones.h"

#include "grid.h"
#include "union_find.h"

#include <algorithm>
#include <cmath>

namespace qex::verify_detail {
namespace {

double signed_angle(const std::array<double, 2>& at, const std::array<double, 2>& a, const std::array<double, 2>& b) {
    const double x1 = a[0] - at[0], y1 = a[1] - at[1], x2 = b[0] - at[0], y2 = b[1] - at[1];
    return std::atan2(x1 * y2 - y1 * x2, x1 * x2 + y1 * y2);
}

bool near_integer(double x, double tol) { return std::abs(x - std::nearbyint(x)) <= tol; }

/// Whether the UV segment pq runs along an integer iso-line (within `tol`).
bool iso_segment(const std::array<double, 2>& p, const std::array<double, 2>& q, double tol) {
    for (int d = 0; d < 2; ++d)
        if (std::abs(p[d] - q[d]) <= tol && near_integer(p[d], tol) && near_integer(q[d], tol)) return true;
    return false;
}

/// Cones: input vertices joined by edges shorter than `tol` in UV, each numbered by its smallest vertex.
void group_cones(const Input& in, double tol, ConeMap& k) {
    const std::size_t nv = in.positions.size();
    UnionFind groups(nv);
    for (std::size_t c = 0; c < 3 * in.triangles.size(); ++c) {
        const auto &p = in.uvs[c], &q = in.uvs[next_corner(c)];
        if (std::max(std::abs(p[0] - q[0]), std::abs(p[1] - q[1])) <= tol)
            groups.unite(in.triangles[c / 3][c % 3], in.triangles[c / 3][(c % 3 + 1) % 3]);
    }
    k.cone_of.assign(nv, -1);
    for (std::size_t v = 0; v < nv; ++v) {
        const auto root = static_cast<std::size_t>(groups.find(static_cast<int>(v)));
        if (k.cone_of[root] < 0) {
            k.cone_of[root] = static_cast<std::int32_t>(k.cones.size());
            k.cones.push_back({});
            k.cones.back().vertex = static_cast<std::int64_t>(v);
        }
        k.cone_of[v] = k.cone_of[root];
    }
}

/// Each cone's angle sum, whether it is interior, folded, and on a boundary along iso-lines.
void sum_angles(const LocatedMap& map, double tol, ConeMap& k) {
    const Input& in = map.in;
    for (std::size_t c = 0; c < 3 * in.triangles.size(); ++c) {
        const auto& tri = in.triangles[c / 3];
        const auto self = static_cast<std::size_t>(k.cone_of[static_cast<std::size_t>(tri[c % 3])]);
        const auto next = static_cast<std::size_t>(k.cone_of[static_cast<std::size_t>(tri[(c % 3 + 1) % 3])]);
        const auto prev = static_cast<std::size_t>(k.cone_of[static_cast<std::size_t>(tri[(c % 3 + 2) % 3])]);
        Cone& x = k.cones[self];
        if (map.edges.partner[c] < 0) { // a boundary edge: both its ends on the boundary
            const bool iso = iso_segment(in.uvs[c], in.uvs[next_corner(c)], tol);
            for (Cone* y : {&x, &k.cones[next]}) y->interior = false, y->iso_boundary = y->iso_boundary && iso;
        }
        if (next == self || prev == self) continue; // collapsed within the cone
        x.quarter_turns += signed_angle(in.uvs[c], in.uvs[next_corner(c)], in.uvs[prev_corner(c)]) / (M_PI / 2);
        x.folded = x.folded || map.fold_over[c / 3];
    }
    // A cone of at most one quarter turn, or of eight or more, is no valence an extractor keeps
    // (a face folded onto itself; a fan wound twice): its fan is read up to whole turns, as a
    // folded one is, and it seeds a footprint.
    for (Cone& x : k.cones) {
        int n = 0;
        if (x.interior && x.valence(n) && (n <= 1 || n >= 8)) x.folded = x.extreme = true;
    }
}

/// Per input vertex its triangles (a counting sort).
struct Fans {
    std::vector<std::size_t> start;
    std::vector<std::uint32_t> tri;
};

Fans vertex_fans(const Input& in) {
    const std::size_t nv = in.positions.size();
    Fans f{std::vector<std::size_t>(nv + 1, 0), {}};
    for (const auto& t : in.triangles)
        for (int v : t) ++f.start[static_cast<std::size_t>(v) + 1];
    for (std::size_t v = 0; v < nv; ++v) f.start[v + 1] += f.start[v];
    f.tri.resize(f.start[nv]);
    std::vector<std::size_t> fill(f.start.begin(), f.start.end() - 1);
    for (std::size_t t = 0; t < in.triangles.size(); ++t)
        for (int v : in.triangles[t]) f.tri[fill[static_cast<std::size_t>(v)]++] = static_cast<std::uint32_t>(t);
    return f;
}

/// The point p of a chart carried by the transition m, in doubles (exact: quarter turns and
/// integer translations below 2^53).
std::array<double, 2> carry(const Transition& m, const std::array<double, 2>& p) {
    const auto q = rotate_quarter(p, m.r);
    return {q[0] + static_cast<double>(m.tx), q[1] + static_cast<double>(m.ty)};
}

/// What the searches for co-located cones share from one singularity to the next: which cones are
/// singular, the queue, and per triangle the search that last reached it (a map of many
/// singularities searches once each).
struct ColocationScratch {
    ColocationScratch(const ConeMap& k, std::size_t triangles) : singular(k.cones.size()), seen_by(triangles, 0) {
        for (std::size_t c = 0; c < k.cones.size(); ++c) singular[c] = k.cones[c].singular();
    }
    std::vector<char> singular;
    std::vector<std::pair<std::size_t, Transition>> queue;
    std::vector<std::size_t> depth;
    std::vector<std::uint32_t> seen_by;
    std::uint32_t search = 0;
};

/// The singular cones within 2 kColocationReach triangle steps of singularity `a` (charted
/// from a triangle of its fan) on a's UV point when charted along the way (within `tol`).
std::vector<std::int32_t> colocated_cones(const LocatedMap& map, const ConeMap& k, const Fans& fans, std::size_t a,
                                          double tol, ColocationScratch& scratch) {
    std::vector<std::int32_t> out;
    const std::size_t t0 = fans.tri[fans.start[a]];
    int corner = 0;
    while (map.in.triangles[t0][static_cast<std::size_t>(corner)] != static_cast<int>(a)) ++corner;
    const auto ua = map.in.uvs[3 * t0 + static_cast<std::size_t>(corner)];
    const std::int32_t ca = k.cone_of[a];
    // Breadth first over triangles, each with the map from its chart to t0's.
    auto& queue = scratch.queue;
    auto& depth = scratch.depth;
    const std::uint32_t search = ++scratch.search;
    queue.assign(1, {t0, Transition{}});
    depth.assign(1, 0);
    scratch.seen_by[t0] = search;
    for (std::size_t q = 0; q < queue.size(); ++q) {
        const auto [t, m] = queue[q];
        for (std::size_t j = 0; j < 3; ++j) {
            const std::int32_t cx = k.cone_of[static_cast<std::size_t>(map.in.triangles[t][j])];
            if (cx != ca && scratch.singular[static_cast<std::size_t>(cx)]) {
                const auto ux = carry(m, map.in.uvs[3 * t + j]);
                if (std::max(std::abs(ux[0] - ua[0]), std::abs(ux[1] - ua[1])) <= tol &&
                    std::find(out.begin(), out.end(), cx) == out.end())
                    out.push_back(cx);
            }
            const std::int64_t o = map.edges.opposite[3 * t + j];
            if (o < 0 || depth[q] >= 2 * kColocationReach) continue;
            const auto u = static_cast<std::size_t>(o / 3);
            Transition mu;
            if (scratch.seen_by[u] == search || !compose(m, map.edges.across[static_cast<std::size_t>(o)], mu))
                continue;
            scratch.seen_by[u] = search;
            queue.push_back({u, mu});
            depth.push_back(depth[q] + 1);
        }
    }
    return out;
}

} // namespace

namespace {

/// Whether a corner UV of the cone's vertices is off the integer grid by more than `tol`.
std::vector<char> off_grid_cones(const Input& in, const ConeMap& k, double tol) {
    std::vector<char> off(k.cones.size(), 0);
    for (std::size_t c = 0; c < in.uvs.size(); ++c) {
        const auto& u = in.uvs[c];
        if (std::max(std::abs(u[0] - std::nearbyint(u[0])), std::abs(u[1] - std::nearbyint(u[1]))) > tol)
            off[static_cast<std::size_t>(k.cone_of[static_cast<std::size_t>(in.triangles[c / 3][c % 3])])] = 1;
    }
    return off;
}

/// The footprints' seeds: the cones on fold triangles, the singularities off the grid, and
/// co-located singularities, with the pairs of those to join.
void seed_footprints(const LocatedMap& map, double tol, ConeMap& k) {
    const Input& in = map.in;
    k.seed.assign(k.cones.size(), 0);
    for (std::size_t t = 0; t < in.triangles.size(); ++t)
        if (map.fold_over[t])
            for (int v : in.triangles[t]) k.seed[static_cast<std::size_t>(k.cone_of[static_cast<std::size_t>(v)])] = 1;
    const Fans fans = vertex_fans(in);
    const std::vector<char> off_grid = off_grid_cones(in, k, tol);
    ColocationScratch scratch(k, in.triangles.size());
    for (std::size_t c = 0; c < k.cones.size(); ++c) {
        const Cone& a = k.cones[c];
        if (!scratch.singular[c]) continue;
        if (off_grid[c] || a.extreme) k.seed[c] = 1;
        for (const std::int32_t x : colocated_cones(map, k, fans, static_cast<std::size_t>(a.vertex), tol, scratch)) {
            k.seed[c] = k.seed[static_cast<std::size_t>(x)] = 1;
            k.links.push_back({static_cast<std::int32_t>(c), x});
        }
    }
}

/// Per triangle: within `cells` (UV, along the surface) of a triangle `source` names: shortest
/// paths over the triangles, each step the distance between two neighbours' UV centroids in one
/// chart, less the two triangles' UV radii (as coverage.cpp's reach of fold-overs).
std::vector<char> triangles_within(const LocatedMap& map, const std::vector<char>& source, double cells) {
    const Input& in = map.in;
    const std::size_t nt = in.triangles.size();
    std::vector<std::array<double, 2>> centre(nt, {0, 0});
    std::vector<double> radius(nt, 0.0), dist(nt, HUGE_VAL);
    std::vector<std::pair<double, std::uint32_t>> heap;
    for (std::size_t t = 0; t < nt; ++t) {
        for (std::size_t j = 0; j < 3; ++j)
            for (int d = 0; d < 2; ++d) centre[t][d] += in.uvs[3 * t + j][d] / 3;
        for (std::size_t j = 0; j < 3; ++j)
            radius[t] = std::max(radius[t],
                                 std::hypot(in.uvs[3 * t + j][0] - centre[t][0], in.uvs[3 * t + j][1] - centre[t][1]));
        if (source[t]) dist[t] = -radius[t], heap.push_back({dist[t], static_cast<std::uint32_t>(t)});
    }
    std::make_heap(heap.begin(), heap.end(), std::greater<>());
    while (!heap.empty()) {
        std::pop_heap(heap.begin(), heap.end(), std::greater<>());
        const auto [d, t] = heap.back();
        heap.pop_back();
        if (d > dist[t] || d - radius[t] > cells) continue;
        for (std::size_t j = 0; j < 3; ++j) {
            const std::int64_t o = map.edges.opposite[3 * t + j], across = map.edges.partner[3 * t + j];
            if (across < 0) continue;
            const auto n = static_cast<std::size_t>(across / 3);
            double step = 0; // across an edge without a transition, no step at all
            if (o >= 0) {
                const auto q = carry(map.edges.across[static_cast<std::size_t>(o)], centre[n]);
                step = std::hypot(q[0] - centre[t][0], q[1] - centre[t][1]);
            }
            const double dn = d + (std::isfinite(step) ? step : 0.0);
            if (dn < dist[n])
                dist[n] = dn, heap.push_back({dn, static_cast<std::uint32_t>(n)}),
                std::push_heap(heap.begin(), heap.end(), std::greater<>());
        }
    }
    std::vector<char> within(nt, 0);
    for (std::size_t t = 0; t < nt; ++t) within[t] = dist[t] - radius[t] <= cells;
    return within;
}

/// Per cone: in a footprint, i.e. a seed, or on a triangle within `cells` (UV) of the fans of
/// the cones `grow` names.
std::vector<char> footprint_cones(const LocatedMap& map, const ConeMap& k, const std::vector<char>& grow,
                                  double cells) {
    std::vector<char> in_fp = k.seed;
    if (cells <= 0) return in_fp;
    const Input& in = map.in;
    std::vector<char> source(in.triangles.size(), 0);
    for (std::size_t t = 0; t < in.triangles.size(); ++t)
        for (int v : in.triangles[t])
            source[t] = source[t] || grow[static_cast<std::size_t>(k.cone_of[static_cast<std::size_t>(v)])];
    const std::vector<char> within = triangles_within(map, source, cells);
    for (std::size_t t = 0; t < in.triangles.size(); ++t)
        if (within[t])
            for (int v : in.triangles[t]) in_fp[static_cast<std::size_t>(k.cone_of[static_cast<std::size_t>(v)])] = 1;
    return in_fp;
}

/// The footprints of the cones `in_fp` names: grouped where they share a triangle or are
/// linked; their triangles (a corner in them), area and first fold triangle.
void group_footprints(const LocatedMap& map, const std::vector<char>& in_fp, ConeMap& k) {
    const Input& in = map.in;
    const std::size_t nc = k.cones.size(), nt = in.triangles.size();
    UnionFind groups(nc);
    for (std::size_t t = 0; t < nt; ++t) {
        std::int32_t first = -1;
        for (int v : in.triangles[t]) {
            const std::int32_t c = k.cone_of[static_cast<std::size_t>(v)];
            if (in_fp[static_cast<std::size_t>(c)]) first < 0 ? void(first = c) : groups.unite(c, first);
        }
    }
    for (const auto& l : k.links) groups.unite(l[0], l[1]);
    std::vector<std::int32_t> index_of_root(nc, -1);
    k.footprints.clear();
    k.footprint_of_triangle.assign(nt, -1);
    for (std::size_t c = 0; c < nc; ++c) {
        k.cones[c].footprint = -1;
        if (!in_fp[c]) continue;
        std::int32_t& slot = index_of_root[static_cast<std::size_t>(groups.find(static_cast<int>(c)))];
        if (slot < 0) slot = static_cast<std::int32_t>(k.footprints.size()), k.footprints.emplace_back();
        k.cones[c].footprint = slot;
    }
    for (std::size_t t = 0; t < nt; ++t) {
        std::int32_t f = -1;
        for (int v : in.triangles[t])
            f = std::max(f, k.cones[static_cast<std::size_t>(k.cone_of[static_cast<std::size_t>(v)])].footprint);
        if (f < 0) continue;
        k.footprint_of_triangle[t] = f;
        Footprint& fp = k.footprints[static_cast<std::size_t>(f)];
        const auto &a = in.uvs[3 * t], &b = in.uvs[3 * t + 1], &c = in.uvs[3 * t + 2];
        ++fp.triangles;
        fp.uv_area += 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
        if (fp.first_triangle < 0 || (map.fold_over[t] && !map.fold_over[static_cast<std::size_t>(fp.first_triangle)]))
            fp.first_triangle = static_cast<std::int64_t>(t);
    }
}

/// Per footprint: the sum of its interior cones' turns, and the fold triangles' correction.
void footprint_turns(const LocatedMap& map, ConeMap& k) {
    for (const Cone& x : k.cones)
        if (x.footprint >= 0 && x.interior)
            k.footprints[static_cast<std::size_t>(x.footprint)].cone_turns += x.quarter_turns - 4;
    const Input& in = map.in;
    for (std::size_t t = 0; t < in.triangles.size(); ++t) {
        if (!map.fold_over[t] || k.footprint_of_triangle[t] < 0) continue;
        const auto& tri = in.triangles[t];
        const std::int32_t c0 = k.cone_of[static_cast<std::size_t>(tri[0])],
                           c1 = k.cone_of[static_cast<std::size_t>(tri[1])],
                           c2 = k.cone_of[static_cast<std::size_t>(tri[2])];
        if (c0 == c1 || c1 == c2 || c0 == c2) continue; // collapsed: no triangle of a fold-free map
        double sum = 0;
        for (std::size_t j = 0; j < 3; ++j)
            sum += signed_angle(in.uvs[3 * t + j], in.uvs[3 * t + (j + 1) % 3], in.uvs[3 * t + (j + 2) % 3]);
        k.footprints[static_cast<std::size_t>(k.footprint_of_triangle[t])].correction += 2 - sum / (M_PI / 2);
    }
}

} // namespace

ConeMap map_cones(const LocatedMap& map, double tol) {
    ConeMap k;
    group_cones(map.in, tol, k);
    sum_angles(map, tol, k);
    seed_footprints(map, tol, k);
    regroup_footprints(map, k, std::vector<char>(k.cones.size(), 0), 0);
    return k;
}

void regroup_footprints(const LocatedMap& map, ConeMap& k, const std::vector<char>& grow, double cells) {
    group_footprints(map, footprint_cones(map, k, grow, cells), k);
    footprint_turns(map, k);
}

} // namespace qex::verify_detail

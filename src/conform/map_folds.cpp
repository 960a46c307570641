// Large fold-overs through the charts (see map_generators.h): vertices, patches and fans moved
// by one displacement turned into each chart.
#include "map_generators.h"
#include "extract/grid_automorphism.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

namespace qex::gen {

/// `a` turned by r quarter turns (the extractor's grid automorphisms turn so too).
inline std::array<double, 2> rot(const std::array<double, 2>& a, int r) {
    return detail::GridAutomorphism::rotate(a, r);
}

// ============================================================================ large fold-overs

namespace {

using Uv = std::array<double, 2>;

Uv sub(const Uv& a, const Uv& b) { return {a[0] - b[0], a[1] - b[1]}; }
Uv add(const Uv& a, const Uv& b) { return {a[0] + b[0], a[1] + b[1]}; }
std::size_t next_corner(std::size_t c) { return c - c % 3 + (c + 1) % 3; }
std::size_t prev_corner(std::size_t c) { return c - c % 3 + (c + 2) % 3; }
int vertex_at(const Input& in, std::size_t c) { return in.triangles[c / 3][c % 3]; }

/// The corners (3f + k) of each vertex, in triangle order.
std::vector<std::vector<std::size_t>> vertex_corners(const Input& in) {
    std::vector<std::vector<std::size_t>> out(in.positions.size());
    const std::size_t corners = std::min(3 * in.triangles.size(), in.uvs.size());
    for (std::size_t c = 0; c < corners; ++c) {
        const int v = vertex_at(in, c);
        if (v >= 0 && v < static_cast<int>(out.size())) out[static_cast<std::size_t>(v)].push_back(c);
    }
    return out;
}

/// The quarter turns r that map the edge vector e nearest to e2, or -1 when either has no length,
/// is not finite, or no turn maps it within half its length.
int nearest_turn(const Uv& e, const Uv& e2) {
    const double len = std::max(std::hypot(e[0], e[1]), std::hypot(e2[0], e2[1]));
    if (!std::isfinite(len) || std::hypot(e[0], e[1]) == 0 || std::hypot(e2[0], e2[1]) == 0) return -1;
    int best = -1;
    double best_distance = 0.5 * len;
    for (int r = 0; r < 4; ++r) {
        const Uv d = sub(rot(e, r), e2);
        const double distance = std::hypot(d[0], d[1]);
        if (distance < best_distance) best = r, best_distance = distance;
    }
    return best;
}

/// The signed UV angle of corner c.
double corner_angle(const Input& in, std::size_t c) {
    const Uv a = sub(in.uvs[next_corner(c)], in.uvs[c]), b = sub(in.uvs[prev_corner(c)], in.uvs[c]);
    return std::atan2(a[0] * b[1] - a[1] * b[0], a[0] * b[0] + a[1] * b[1]);
}

/// A vertex's fan, counter-clockwise from its corner in its first triangle.
struct Fan {
    std::vector<std::size_t> corners;
    std::vector<int> turns; ///< quarter turns from the first corner's chart to each corner's
    bool closed = false;    ///< interior: the walk came back to its start over every corner once
    int holonomy = 0;       ///< quarter turns (mod 4) the charts compose to around the vertex
    double angle = 0.0;     ///< signed UV angle sum
    /// The UV angle sum in quarter turns (4: regular; 0: pushed out of its neighbours' polygon).
    long valence() const { return std::lround(angle / (0.5 * M_PI)); }
};

Fan fan_of(const Input& in, const std::vector<std::size_t>& corners) {
    Fan fan;
    if (corners.empty()) return fan;
    std::size_t c = corners[0];
    int turn = 0;
    for (std::size_t step = 0; step < corners.size(); ++step) {
        fan.corners.push_back(c);
        fan.turns.push_back(turn);
        fan.angle += corner_angle(in, c);
        // The next corner counter-clockwise: the one whose next vertex is this one's previous.
        const int b = vertex_at(in, prev_corner(c));
        std::size_t found = c;
        int count = 0;
        for (const std::size_t d : corners)
            if (vertex_at(in, next_corner(d)) == b) found = d, ++count;
        if (count != 1) return fan; // a boundary, or a non-manifold vertex
        const int r =
            nearest_turn(sub(in.uvs[prev_corner(c)], in.uvs[c]), sub(in.uvs[next_corner(found)], in.uvs[found]));
        if (r < 0) return fan;
        turn = (turn + r) & 3;
        c = found;
        if (c == corners[0]) {
            fan.closed = step + 1 == corners.size();
            fan.holonomy = turn;
            return fan;
        }
    }
    return fan;
}

/// Whether displace_vertex_in_charts moves a vertex with this fan.
bool movable(const Fan& fan) { return fan.closed && fan.holonomy == 0 && (fan.valence() == 4 || fan.valence() == 0); }

/// Adds d, given in the chart of fan corner `from`, to every corner, turned into its chart.
void displace_fan(Input& in, const Fan& fan, std::size_t from, const Uv& d) {
    for (std::size_t i = 0; i < fan.corners.size(); ++i)
        in.uvs[fan.corners[i]] = add(in.uvs[fan.corners[i]], rot(d, fan.turns[i] - fan.turns[from]));
}

/// A grid automorphism x -> rot(x, turn) + shift, from the centre's chart to a triangle's.
struct ChartMap {
    int turn = 0;
    Uv shift{0.0, 0.0};
    bool reached = false;
};

} // namespace

std::vector<int> singular_vertices(const Input& in) {
    std::vector<int> out;
    const auto corners = vertex_corners(in);
    for (std::size_t v = 0; v < corners.size(); ++v) {
        const Fan fan = fan_of(in, corners[v]);
        if (fan.closed && (fan.holonomy != 0 || fan.valence() != 4)) out.push_back(static_cast<int>(v));
    }
    return out;
}

std::int64_t displace_vertex_in_charts(Input& in, std::size_t corner, double dx, double dy) {
    if (corner >= std::min(3 * in.triangles.size(), in.uvs.size())) return -1;
    const int v = vertex_at(in, corner);
    if (v < 0 || v >= static_cast<int>(in.positions.size())) return -1;
    const Fan fan = fan_of(in, vertex_corners(in)[static_cast<std::size_t>(v)]);
    if (!movable(fan)) return -1;
    const auto from = std::find(fan.corners.begin(), fan.corners.end(), corner) - fan.corners.begin();
    displace_fan(in, fan, static_cast<std::size_t>(from), {dx, dy});
    return count_flipped(in);
}

std::int64_t fold_patch(Input& in, int centre, int rings, PatchMotion motion, double a, double b) {
    const auto corners = vertex_corners(in);
    if (centre < 0 || centre >= static_cast<int>(corners.size()) || corners[centre].empty()) return -1;
    // The patch: vertices within `rings` edges of the centre, by breadth-first search.
    std::vector<int> ring(corners.size(), -1);
    std::vector<int> patch{centre};
    ring[centre] = 0;
    for (std::size_t i = 0; i < patch.size(); ++i) {
        const int u = patch[i];
        if (ring[u] == rings) continue;
        for (const std::size_t c : corners[u])
            for (const std::size_t w : {next_corner(c), prev_corner(c)})
                if (ring[vertex_at(in, w)] < 0) ring[vertex_at(in, w)] = ring[u] + 1, patch.push_back(vertex_at(in, w));
    }
    // The charts of the triangles around the patch, carried from the centre's first triangle
    // across the edges whose UVs fix a transition.
    std::vector<ChartMap> chart(in.triangles.size());
    std::vector<std::size_t> queue{corners[centre][0] / 3};
    chart[queue[0]].reached = true;
    for (std::size_t i = 0; i < queue.size(); ++i) {
        const std::size_t f = queue[i];
        for (std::size_t k = 0; k < 3; ++k) {
            const std::size_t cp = 3 * f + k, cq = next_corner(cp);
            const int p = vertex_at(in, cp), q = vertex_at(in, cq);
            if (ring[p] < 0 && ring[q] < 0) continue;
            for (const std::size_t d : corners[static_cast<std::size_t>(q)]) {
                const std::size_t g = d / 3;
                if (chart[g].reached || vertex_at(in, next_corner(d)) != p) continue;
                const int r = nearest_turn(sub(in.uvs[cq], in.uvs[cp]), sub(in.uvs[d], in.uvs[next_corner(d)]));
                if (r < 0) continue;
                const Uv t = sub(in.uvs[next_corner(d)], rot(in.uvs[cp], r));
                chart[g] = {(chart[f].turn + r) & 3, add(rot(chart[f].shift, r), t), true};
                queue.push_back(g);
            }
        }
    }
    const Uv o = in.uvs[corners[centre][0]];
    auto moved = [&](const Uv& x, int at) -> Uv {
        const Uv r = sub(x, o);
        switch (motion) {
            case PatchMotion::Translate: return add(x, {a, b});
            case PatchMotion::Twist: {
                const double angle = a * (1.0 - static_cast<double>(at) / (rings + 1));
                return add(o, {std::cos(angle) * r[0] - std::sin(angle) * r[1],
                               std::sin(angle) * r[0] + std::cos(angle) * r[1]});
            }
            case PatchMotion::Mirror: {
                const Uv u{std::cos(a), std::sin(a)};
                const double along = 2 * (u[0] * r[0] + u[1] * r[1]);
                return add(o, {along * u[0] - r[0], along * u[1] - r[1]});
            }
            default: return add(o, {a * r[0], a * r[1]});
        }
    };
    // Every displacement first (from the map as it is), then every move.
    struct Move {
        Fan fan;
        std::size_t from;
        Uv d;
    };
    std::vector<Move> moves;
    for (const int w : patch) {
        Fan fan = fan_of(in, corners[static_cast<std::size_t>(w)]);
        if (!movable(fan)) continue;
        for (std::size_t i = 0; i < fan.corners.size(); ++i) {
            const ChartMap& m = chart[fan.corners[i] / 3];
            if (!m.reached) continue;
            const Uv x = rot(sub(in.uvs[fan.corners[i]], m.shift), -m.turn); // in the centre's chart
            const Uv d = rot(sub(moved(x, ring[w]), x), m.turn);
            const Uv rounded{std::ldexp(std::nearbyint(std::ldexp(d[0], 12)), -12),
                             std::ldexp(std::nearbyint(std::ldexp(d[1], 12)), -12)};
            if (std::isfinite(rounded[0]) && std::isfinite(rounded[1]) && rounded != Uv{0.0, 0.0})
                moves.push_back({std::move(fan), i, rounded});
            break;
        }
    }
    for (const Move& m : moves) displace_fan(in, m.fan, m.from, m.d);
    return moves.empty() ? -1 : count_flipped(in);
}

void squeeze_fan(Input& in, int v, double factor) {
    struct Tri {
        std::size_t f;
        int cv; // v's corner
    };
    std::vector<Tri> fan;
    for (std::size_t f = 0; f < in.triangles.size(); ++f)
        for (int k = 0; k < 3; ++k)
            if (in.triangles[f][k] == v) fan.push_back({f, k});
    // New UVs of the neighbours' corners in v's triangles, in walk order.
    struct Move {
        int w;
        std::array<double, 2> from, to;
    };
    std::vector<Move> moved; // neighbour w's corner UV in one chart -> its new UV
    std::vector<char> done(fan.size(), 0);
    std::size_t t = 0;
    double angle = 0; // developed angle of the current triangle's first neighbour
    for (std::size_t step = 0; step < fan.size(); ++step) {
        done[t] = 1;
        const auto [f, cv] = fan[t];
        const auto& c = in.uvs[3 * f + cv];
        const std::size_t ca = 3 * f + (cv + 1) % 3, cb = 3 * f + (cv + 2) % 3;
        auto dir = [&](std::size_t corner) { return std::atan2(in.uvs[corner][1] - c[1], in.uvs[corner][0] - c[0]); };
        double sweep = dir(cb) - dir(ca);
        while (sweep <= 0) sweep += 2 * M_PI;
        for (const auto& [corner, developed] : {std::pair{ca, angle}, std::pair{cb, angle + sweep}}) {
            const double r = std::hypot(in.uvs[corner][0] - c[0], in.uvs[corner][1] - c[1]);
            const double turned = dir(corner) - developed + developed / factor;
            moved.push_back({in.triangles[corner / 3][corner % 3],
                             in.uvs[corner],
                             {c[0] + r * std::cos(turned), c[1] + r * std::sin(turned)}});
        }
        angle += sweep;
        // The next triangle starts with this one's second neighbour.
        const int b = in.triangles[f][(cv + 2) % 3];
        for (std::size_t u = 0; u < fan.size(); ++u)
            if (!done[u] && in.triangles[fan[u].f][(fan[u].cv + 1) % 3] == b) t = u;
    }
    // The same neighbour in the same chart keeps one new UV (the walk's first assignment).
    std::vector<std::array<double, 2>> out = in.uvs;
    std::vector<char> set(in.uvs.size(), 0);
    for (std::size_t f = 0; f < in.triangles.size(); ++f)
        for (int k = 0; k < 3; ++k) {
            const int w = in.triangles[f][k];
            if (w == v) continue;
            bool neighbour = false;
            for (const Tri& x : fan)
                for (int j = 0; j < 3; ++j) neighbour = neighbour || in.triangles[x.f][j] == w;
            if (!neighbour) continue;
            for (const Move& m : moved)
                if (m.w == w && m.from == in.uvs[3 * f + k] && !set[3 * f + k]) {
                    out[3 * f + k] = m.to;
                    set[3 * f + k] = 1;
                }
        }
    in.uvs = out;
}

} // namespace qex::gen

// Generators of exact integer-grid maps from quad layouts, and the perturbations the tests apply.
#include "map_generators.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <numeric>
#include <tuple>

namespace qex::testing {
namespace {

using Vec3 = std::array<double, 3>;

Vec3 lerp(const Vec3& a, const Vec3& b, double t) {
    return {a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), a[2] + t * (b[2] - a[2])};
}

std::array<double, 2> rot(const std::array<double, 2>& a, int r) {
    switch (r & 3) {
        case 0: return a;
        case 1: return {-a[1], a[0]};
        case 2: return {-a[0], -a[1]};
        default: return {a[1], -a[0]};
    }
}

} // namespace

/// Midpoint vertices shared between the polygons that split an edge.
class Midpoints {
public:
    explicit Midpoints(std::vector<Vec3>& positions) : positions_(positions) {}
    int operator()(int a, int b) {
        const auto key = std::minmax(a, b);
        auto it = ids_.find(key);
        if (it != ids_.end()) return it->second;
        const int id = static_cast<int>(positions_.size());
        positions_.push_back(lerp(positions_[a], positions_[b], 0.5));
        ids_.emplace(key, id);
        return id;
    }

private:
    std::vector<Vec3>& positions_;
    std::map<std::pair<int, int>, int> ids_;
};

QuadLayout split_polygons(const std::string& name, const std::vector<Vec3>& positions,
                          const std::vector<std::vector<int>>& polygons) {
    QuadLayout out{name, positions, {}};
    Midpoints midpoint(out.positions);
    for (const auto& poly : polygons) {
        Vec3 c{0, 0, 0};
        for (int v : poly)
            for (int k = 0; k < 3; ++k) c[k] += positions[v][k] / static_cast<double>(poly.size());
        const int centre = static_cast<int>(out.positions.size());
        out.positions.push_back(c);
        const std::size_t m = poly.size();
        for (std::size_t i = 0; i < m; ++i) {
            const int v = poly[i], next = poly[(i + 1) % m], prev = poly[(i + m - 1) % m];
            out.quads.push_back({v, midpoint(v, next), centre, midpoint(prev, v)});
        }
    }
    return out;
}

QuadLayout torus_layout(int nu, int nv) {
    QuadLayout l{"torus", {}, {}};
    const double R = 3.0, r = 1.0;
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
            const double u = 2 * M_PI * i / nu, v = 2 * M_PI * j / nv;
            l.positions.push_back(
                {(R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u), r * std::sin(v)});
        }
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
            auto id = [&](int a, int b) { return (b % nv) * nu + (a % nu); };
            l.quads.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
        }
    return l;
}

QuadLayout cube_layout() {
    QuadLayout l{"cube", {}, {}};
    for (int i = 0; i < 8; ++i) l.positions.push_back({double(i & 1), double((i >> 1) & 1), double((i >> 2) & 1)});
    // Outward counter-clockwise faces.
    l.quads = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    return l;
}

QuadLayout icosahedron_layout() {
    const double p = (1 + std::sqrt(5.0)) / 2;
    const std::vector<Vec3> v = {{-1, p, 0},  {1, p, 0},  {-1, -p, 0}, {1, -p, 0}, {0, -1, p},  {0, 1, p},
                                 {0, -1, -p}, {0, 1, -p}, {p, 0, -1},  {p, 0, 1},  {-p, 0, -1}, {-p, 0, 1}};
    const std::vector<std::vector<int>> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                             {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                             {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                             {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
    return split_polygons("icosahedron", v, f);
}

QuadLayout prism_layout(int sides) {
    std::vector<Vec3> v;
    for (int z = 0; z < 2; ++z)
        for (int i = 0; i < sides; ++i)
            v.push_back({std::cos(2 * M_PI * i / sides), std::sin(2 * M_PI * i / sides), 1.5 * z});
    std::vector<std::vector<int>> f;
    std::vector<int> bottom, top;
    for (int i = 0; i < sides; ++i) {
        bottom.push_back(sides - 1 - i);
        top.push_back(sides + i);
        f.push_back({i, (i + 1) % sides, sides + (i + 1) % sides, sides + i});
    }
    f.push_back(bottom);
    f.push_back(top);
    return split_polygons("prism" + std::to_string(sides), v, f);
}

QuadLayout disk_layout(int n) {
    QuadLayout l{"disk", {}, {}};
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) l.positions.push_back({double(i), double(j), 0.1 * std::sin(i + 2.0 * j)});
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            auto id = [&](int a, int b) { return b * (n + 1) + a; };
            l.quads.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
        }
    return l;
}

QuadLayout annulus_layout(int nu, int nv) {
    QuadLayout l{"annulus", {}, {}};
    for (int j = 0; j <= nv; ++j)
        for (int i = 0; i < nu; ++i) {
            const double a = 2 * M_PI * i / nu, r = 1.0 + j;
            l.positions.push_back({r * std::cos(a), r * std::sin(a), 0.0});
        }
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
            auto id = [&](int a, int b) { return b * nu + (a % nu); };
            l.quads.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
        }
    return l;
}

Input make_map(const QuadLayout& layout, int n, int k, int diagonals, std::uint32_t seed,
               std::vector<char>* single_chart) {
    Input in;
    std::mt19937 rng(seed);
    std::map<std::tuple<int, int, int>, int> shared; // (kind/vertex, vertex, t) -> vertex id
    auto vertex_id = [&](std::tuple<int, int, int> key, const Vec3& p) {
        auto it = shared.find(key);
        if (it != shared.end()) return it->second;
        const int id = static_cast<int>(in.positions.size());
        in.positions.push_back(p);
        shared.emplace(key, id);
        return id;
    };
    for (std::size_t qi = 0; qi < layout.quads.size(); ++qi) {
        const auto& q = layout.quads[qi];
        const Vec3 &c0 = layout.positions[q[0]], &c1 = layout.positions[q[1]], &c2 = layout.positions[q[2]],
                   &c3 = layout.positions[q[3]];
        std::vector<int> ids((k + 1) * (k + 1));
        for (int b = 0; b <= k; ++b)
            for (int a = 0; a <= k; ++a) {
                const double s = double(a) / k, t = double(b) / k;
                const Vec3 p = lerp(lerp(c0, c1, s), lerp(c3, c2, s), t);
                std::tuple<int, int, int> key{-1, static_cast<int>(qi), b * (k + 1) + a};
                auto on_edge = [&](int from, int to, int pos) {
                    if (pos == 0) return std::tuple<int, int, int>{-2, from, 0};
                    if (pos == k) return std::tuple<int, int, int>{-2, to, 0};
                    return from < to ? std::tuple<int, int, int>{from, to, pos}
                                     : std::tuple<int, int, int>{to, from, k - pos};
                };
                if (b == 0)
                    key = on_edge(q[0], q[1], a);
                else if (a == k)
                    key = on_edge(q[1], q[2], b);
                else if (b == k)
                    key = on_edge(q[2], q[3], k - a);
                else if (a == 0)
                    key = on_edge(q[3], q[0], k - b);
                ids[b * (k + 1) + a] = vertex_id(key, p);
                if (single_chart) {
                    single_chart->resize(in.positions.size(), 0);
                    (*single_chart)[ids[b * (k + 1) + a]] = std::get<0>(key) == -1;
                }
            }
        auto uv = [&](int a, int b) { return std::array<double, 2>{double(a) * n / k, double(b) * n / k}; };
        for (int b = 0; b < k; ++b)
            for (int a = 0; a < k; ++a) {
                const int v00 = ids[b * (k + 1) + a], v10 = ids[b * (k + 1) + a + 1];
                const int v01 = ids[(b + 1) * (k + 1) + a], v11 = ids[(b + 1) * (k + 1) + a + 1];
                const bool flip = diagonals == 1 ? ((a + b) & 1) : diagonals == 2 ? (rng() & 1) : false;
                if (!flip) {
                    in.triangles.push_back({v00, v10, v11});
                    in.uvs.insert(in.uvs.end(), {uv(a, b), uv(a + 1, b), uv(a + 1, b + 1)});
                    in.triangles.push_back({v00, v11, v01});
                    in.uvs.insert(in.uvs.end(), {uv(a, b), uv(a + 1, b + 1), uv(a, b + 1)});
                } else {
                    in.triangles.push_back({v00, v10, v01});
                    in.uvs.insert(in.uvs.end(), {uv(a, b), uv(a + 1, b), uv(a, b + 1)});
                    in.triangles.push_back({v10, v11, v01});
                    in.uvs.insert(in.uvs.end(), {uv(a + 1, b), uv(a + 1, b + 1), uv(a, b + 1)});
                }
            }
    }
    return in;
}

std::int64_t expected_quads(const QuadLayout& layout, int n) {
    return static_cast<std::int64_t>(layout.quads.size()) * n * n;
}

void rechart(Input& in, std::mt19937& rng, std::int64_t max_translation) {
    std::uniform_int_distribution<std::int64_t> t(-max_translation, max_translation);
    for (std::size_t f = 0; f < in.triangles.size(); ++f) {
        const int r = static_cast<int>(rng() & 3);
        const double tx = static_cast<double>(t(rng)), ty = static_cast<double>(t(rng));
        for (int c = 0; c < 3; ++c) {
            const auto p = rot(in.uvs[3 * f + c], r);
            in.uvs[3 * f + c] = {p[0] + tx, p[1] + ty};
        }
    }
}

void shuffle(Input& in, std::mt19937& rng) {
    std::vector<int> perm(in.positions.size());
    std::iota(perm.begin(), perm.end(), 0);
    std::shuffle(perm.begin(), perm.end(), rng);
    std::vector<std::array<double, 3>> pos(in.positions.size());
    for (std::size_t v = 0; v < perm.size(); ++v) pos[perm[v]] = in.positions[v];
    in.positions = pos;
    std::vector<int> forder(in.triangles.size());
    std::iota(forder.begin(), forder.end(), 0);
    std::shuffle(forder.begin(), forder.end(), rng);
    std::vector<std::array<int, 3>> tris;
    std::vector<std::array<double, 2>> uvs;
    for (int f : forder) {
        const int s = static_cast<int>(rng() % 3);
        std::array<int, 3> t{};
        for (int c = 0; c < 3; ++c) {
            t[c] = perm[in.triangles[f][(c + s) % 3]];
            uvs.push_back(in.uvs[3 * f + (c + s) % 3]);
        }
        tris.push_back(t);
    }
    in.triangles = tris;
    in.uvs = uvs;
    for (auto& e : in.feature_edges)
        for (int& v : e)
            if (v >= 0 && v < static_cast<int>(perm.size())) v = perm[v];
    if (!in.valences.empty()) {
        std::vector<int> val(in.valences.size());
        for (std::size_t v = 0; v < perm.size(); ++v) val[perm[v]] = in.valences[v];
        in.valences = val;
    }
}

void translate(Input& in, std::int64_t dx, std::int64_t dy) {
    for (auto& uv : in.uvs) uv = {uv[0] + static_cast<double>(dx), uv[1] + static_cast<double>(dy)};
}

void rotate(Input& in, int r) {
    for (auto& uv : in.uvs) uv = rot(uv, r);
}

void add_noise(Input& in, double eps, std::mt19937& rng) {
    std::uniform_real_distribution<double> d(-eps, eps);
    for (auto& uv : in.uvs) uv = {uv[0] + d(rng), uv[1] + d(rng)};
}

std::int64_t displace_vertex(Input& in, int vertex, double dx, double dy) {
    std::vector<std::size_t> corners;
    for (std::size_t f = 0; f < in.triangles.size(); ++f)
        for (int c = 0; c < 3; ++c)
            if (in.triangles[f][c] == vertex) corners.push_back(3 * f + c);
    for (std::size_t c : corners)
        if (in.uvs[c] != in.uvs[corners[0]]) return -1; // on a chart boundary: not supported
    for (std::size_t c : corners) in.uvs[c] = {in.uvs[c][0] + dx, in.uvs[c][1] + dy};
    return count_flipped(in);
}

Input subdivide(const Input& in) {
    Input out;
    out.positions = in.positions;
    Midpoints midpoint(out.positions);
    auto half = [](const std::array<double, 2>& a, const std::array<double, 2>& b) {
        return std::array<double, 2>{0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])};
    };
    for (std::size_t f = 0; f < in.triangles.size(); ++f) {
        const auto& t = in.triangles[f];
        const auto* uv = &in.uvs[3 * f];
        const int m01 = midpoint(t[0], t[1]), m12 = midpoint(t[1], t[2]), m20 = midpoint(t[2], t[0]);
        const auto u01 = half(uv[0], uv[1]), u12 = half(uv[1], uv[2]), u20 = half(uv[2], uv[0]);
        out.triangles.insert(out.triangles.end(),
                             {{t[0], m01, m20}, {m01, t[1], m12}, {m20, m12, t[2]}, {m01, m12, m20}});
        out.uvs.insert(out.uvs.end(), {uv[0], u01, u20, u01, uv[1], u12, u20, u12, uv[2], u01, u12, u20});
    }
    return out;
}

std::string to_obj(const Input& in) {
    std::string out = "# integer-grid map generated by qex's test generators\n";
    char line[128];
    for (const auto& p : in.positions) {
        std::snprintf(line, sizeof line, "v %.17g %.17g %.17g\n", p[0], p[1], p[2]);
        out += line;
    }
    for (const auto& t : in.uvs) {
        std::snprintf(line, sizeof line, "vt %.17g %.17g\n", t[0], t[1]);
        out += line;
    }
    for (std::size_t f = 0; f < in.triangles.size(); ++f) {
        std::snprintf(line, sizeof line, "f %d/%zu %d/%zu %d/%zu\n", in.triangles[f][0] + 1, 3 * f + 1,
                      in.triangles[f][1] + 1, 3 * f + 2, in.triangles[f][2] + 1, 3 * f + 3);
        out += line;
    }
    return out;
}

std::int64_t count_flipped(const Input& in) {
    std::int64_t n = 0;
    for (std::size_t f = 0; f < in.triangles.size(); ++f) {
        const auto &a = in.uvs[3 * f], &b = in.uvs[3 * f + 1], &c = in.uvs[3 * f + 2];
        n += (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]) < 0;
    }
    return n;
}

namespace {
void split_triangle(Input& in, int f, const std::array<double, 2> uv) { // by value: in.uvs grows below
    const auto t = in.triangles[f];
    const std::array<std::array<double, 2>, 3> u{in.uvs[3 * f], in.uvs[3 * f + 1], in.uvs[3 * f + 2]};
    const int w = static_cast<int>(in.positions.size());
    Vec3 c{0, 0, 0};
    for (int k = 0; k < 3; ++k)
        for (int d = 0; d < 3; ++d) c[d] += in.positions[t[k]][d] / 3.0;
    in.positions.push_back(c);
    in.triangles[f] = {t[0], t[1], w};
    in.uvs[3 * f + 2] = uv;
    in.triangles.push_back({t[1], t[2], w});
    in.uvs.insert(in.uvs.end(), {u[1], u[2], uv});
    in.triangles.push_back({t[2], t[0], w});
    in.uvs.insert(in.uvs.end(), {u[2], u[0], uv});
}
} // namespace

void insert_collapsed_edge(Input& in, int f, int corner) { split_triangle(in, f, in.uvs[3 * f + corner]); }

void insert_zero_area_triangle(Input& in, int f, int corner) {
    const auto& a = in.uvs[3 * f + corner];
    const auto& b = in.uvs[3 * f + (corner + 1) % 3];
    split_triangle(in, f, {0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])});
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

} // namespace qex::testing

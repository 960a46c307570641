// Generators of exact integer-grid maps from quad layouts, and the perturbations the tests apply.
#include "map_generators.h"
#include "extract/grid_automorphism.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <numeric>
#include <tuple>

namespace qex::gen {
namespace {

using Vec3 = std::array<double, 3>;

Vec3 lerp(const Vec3& a, const Vec3& b, double t) {
    return {a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), a[2] + t * (b[2] - a[2])};
}

/// `a` turned by r quarter turns (the extractor's grid automorphisms turn so too).
inline std::array<double, 2> rot(const std::array<double, 2>& a, int r) {
    return detail::GridAutomorphism::rotate(a, r);
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

} // namespace qex::gen

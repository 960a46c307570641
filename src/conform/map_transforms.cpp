// Transforms of integer-grid maps that keep the induced quad mesh (see map_transforms.h).
#include "map_transforms.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <map>
#include <numeric>
#include <random>
#include <sstream>
#include <utility>
#include <vector>

namespace qex::gen::transforms {
namespace {

using Uv = std::array<double, 2>;

// === exact arithmetic checks

/// a + b, and whether the sum was rounded (Knuth's TwoSum: the error term is exact).
double add(double a, double b, bool& rounded) {
    const double s = a + b;
    const double bb = s - a;
    const double err = (a - (s - bb)) + (b - bb);
    rounded = err != 0.0 || !std::isfinite(s);
    return s;
}

/// a * b, and whether the product was rounded (fma gives the exact error of the product).
double mul(double a, double b, bool& rounded) {
    const double p = a * b;
    rounded = std::fma(a, b, -p) != 0.0 || !std::isfinite(p);
    return p;
}

// === random numbers (std::mt19937_64 is the same sequence on every platform; the standard's
// distributions are not, so draws and shuffles are done here)

/// Uniform in [0, n) for small n (the bias of the modulo is below 2^-50).
std::uint64_t below(std::mt19937_64& rng, std::uint64_t n) { return rng() % n; }

/// Uniform in [lo, hi].
std::int64_t between(std::mt19937_64& rng, std::int64_t lo, std::int64_t hi) {
    return lo + static_cast<std::int64_t>(below(rng, static_cast<std::uint64_t>(hi - lo) + 1));
}

/// A uniformly random permutation of 0..n-1 (Fisher-Yates).
std::vector<int> permutation(std::mt19937_64& rng, std::size_t n) {
    std::vector<int> p(n);
    std::iota(p.begin(), p.end(), 0);
    for (std::size_t i = n; i > 1; --i) std::swap(p[i - 1], p[below(rng, i)]);
    return p;
}

/// x rotated by r quarter turns counter-clockwise (exact: swaps and negations).
Uv rotate(const Uv& x, int r) {
    switch (r & 3) {
        case 0: return x;
        case 1: return {-x[1], x[0]};
        case 2: return {-x[0], -x[1]};
        default: return {x[1], -x[0]};
    }
}

/// x + t, counting the rounded coordinates into `rounded`.
Uv shift(const Uv& x, double tx, double ty, std::int64_t& rounded) {
    bool ru = false, rv = false;
    const Uv y{add(x[0], tx, ru), add(x[1], ty, rv)};
    rounded += ru + rv;
    return y;
}

} // namespace

// === the transforms

std::int64_t scale_uvs(Input& in, std::int64_t k) {
    const auto kd = static_cast<double>(k);
    std::int64_t rounded = 0;
    for (Uv& uv : in.uvs)
        for (double& x : uv) {
            bool r = false;
            x = mul(x, kd, r);
            rounded += r;
        }
    return rounded;
}

std::int64_t translate_uvs(Input& in, std::int64_t tx, std::int64_t ty) {
    std::int64_t rounded = 0;
    for (Uv& uv : in.uvs) uv = shift(uv, static_cast<double>(tx), static_cast<double>(ty), rounded);
    return rounded;
}

std::int64_t rechart(Input& in, std::uint64_t seed, std::int64_t max_translation) {
    std::mt19937_64 rng(seed);
    std::int64_t rounded = 0;
    for (std::size_t f = 0; f < in.triangles.size(); ++f) {
        const int r = static_cast<int>(below(rng, 4));
        const auto tx = static_cast<double>(between(rng, -max_translation, max_translation));
        const auto ty = static_cast<double>(between(rng, -max_translation, max_translation));
        for (std::size_t c = 3 * f; c < 3 * f + 3; ++c) in.uvs[c] = shift(rotate(in.uvs[c], r), tx, ty, rounded);
    }
    return rounded;
}

void shuffle(Input& in, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    const std::vector<int> renumber = permutation(rng, in.positions.size()); // old vertex -> new
    const std::vector<int> order = permutation(rng, in.triangles.size());    // new triangle -> old
    Input out;
    out.positions.resize(in.positions.size());
    for (std::size_t v = 0; v < in.positions.size(); ++v) out.positions[renumber[v]] = in.positions[v];
    if (!in.valences.empty()) {
        out.valences.resize(in.valences.size());
        for (std::size_t v = 0; v < in.valences.size(); ++v) out.valences[renumber[v]] = in.valences[v];
    }
    for (int f : order) {
        const std::size_t s = below(rng, 3);
        std::array<int, 3> t{};
        for (std::size_t c = 0; c < 3; ++c) {
            t[c] = renumber[in.triangles[f][(c + s) % 3]];
            out.uvs.push_back(in.uvs[3 * static_cast<std::size_t>(f) + (c + s) % 3]);
        }
        out.triangles.push_back(t);
    }
    for (int e : permutation(rng, in.feature_edges.size())) {
        const auto& fe = in.feature_edges[e];
        out.feature_edges.push_back({renumber[fe[0]], renumber[fe[1]]});
    }
    in = std::move(out);
}

Input subdivide(const Input& in) {
    Input out;
    out.positions = in.positions;
    out.valences = in.valences;
    std::map<std::pair<int, int>, int> midpoints;
    auto midpoint = [&](int a, int b) {
        const auto [it, added] = midpoints.emplace(std::minmax(a, b), static_cast<int>(out.positions.size()));
        if (added) {
            const auto &p = in.positions[a], &q = in.positions[b];
            out.positions.push_back({(p[0] + q[0]) / 2, (p[1] + q[1]) / 2, (p[2] + q[2]) / 2});
            if (!out.valences.empty()) out.valences.push_back(4);
        }
        return it->second;
    };
    auto half = [](const Uv& a, const Uv& b) { return Uv{(a[0] + b[0]) / 2, (a[1] + b[1]) / 2}; };
    for (std::size_t f = 0; f < in.triangles.size(); ++f) {
        const auto& t = in.triangles[f];
        const Uv* uv = &in.uvs[3 * f];
        const int m01 = midpoint(t[0], t[1]), m12 = midpoint(t[1], t[2]), m20 = midpoint(t[2], t[0]);
        const Uv u01 = half(uv[0], uv[1]), u12 = half(uv[1], uv[2]), u20 = half(uv[2], uv[0]);
        out.triangles.insert(out.triangles.end(),
                             {{t[0], m01, m20}, {m01, t[1], m12}, {m20, m12, t[2]}, {m01, m12, m20}});
        out.uvs.insert(out.uvs.end(), {uv[0], u01, u20, u01, uv[1], u12, u20, u12, uv[2], u01, u12, u20});
    }
    for (const auto& e : in.feature_edges) {
        const auto it = midpoints.find(std::minmax(e[0], e[1]));
        if (it == midpoints.end()) { // not an edge of the mesh: kept, for validate() to reject
            out.feature_edges.push_back(e);
            continue;
        }
        out.feature_edges.push_back({e[0], it->second});
        out.feature_edges.push_back({it->second, e[1]});
    }
    return out;
}

std::string apply(Input& in, const std::string& ops, std::int64_t* rounded) {
    std::vector<std::string> words;
    std::istringstream split(ops);
    for (std::string w; split >> w;) words.push_back(w);
    std::size_t i = 0;
    // The next word as an integer, if it is one (then it is consumed).
    auto integer = [&](std::int64_t& x) {
        if (i >= words.size()) return false;
        const std::string& w = words[i];
        const auto [end, ec] = std::from_chars(w.data(), w.data() + w.size(), x);
        if (ec != std::errc() || end != w.data() + w.size()) return false;
        ++i;
        return true;
    };
    std::int64_t count = 0;
    while (i < words.size()) {
        const std::string op = words[i++];
        std::int64_t a = 0, b = 0;
        if (op == "scale") {
            if (!integer(a) || a < 1) return "scale needs an integer K >= 1";
            count += scale_uvs(in, a);
        } else if (op == "translate") {
            if (!integer(a) || !integer(b)) return "translate needs two integers TX TY";
            count += translate_uvs(in, a, b);
        } else if (op == "rechart") {
            if (!integer(a)) return "rechart needs a SEED";
            if (!integer(b)) b = 16; // the largest translation T is optional
            if (b < 0) return "rechart: T must be >= 0";
            count += rechart(in, static_cast<std::uint64_t>(a), b);
        } else if (op == "shuffle") {
            if (!integer(a)) return "shuffle needs a SEED";
            shuffle(in, static_cast<std::uint64_t>(a));
        } else if (op == "subdivide") {
            in = subdivide(in);
        } else {
            return "unknown transform '" + op + "' (scale, translate, rechart, shuffle, subdivide)";
        }
    }
    if (rounded) *rounded += count;
    return {};
}

} // namespace qex::gen::transforms

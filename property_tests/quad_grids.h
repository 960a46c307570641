// Test-only quad meshes for the layout (layout_test.cpp, fuzz/fuzz_layout.cpp): a grid of quads,
// flat, a cylinder or a torus, with faces left out. Every interior vertex is regular; the holes
// give boundary corners, concave corners, annuli and patches that wrap round the torus.
#pragma once

#include "qex/mesh.h"

#include <cmath>
#include <vector>

namespace qex::testing {

/// A w x h grid (w, h >= 3 where periodic), periodic in u and/or v, without the faces i + w * j
/// where keep[i + w * j] is 0 (keep empty or short: the rest kept). Positions are distinct.
inline QuadMesh quad_grid(int w, int h, bool wrap_u, bool wrap_v, const std::vector<char>& keep = {}) {
    QuadMesh m;
    const int nu = wrap_u ? w : w + 1, nv = wrap_v ? h : h + 1;
    const double pi = std::acos(-1.0);
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
            const double t = 2 * pi * i / w, p = 2 * pi * j / h;
            if (wrap_u && wrap_v)
                m.positions.push_back({(3 + std::cos(p)) * std::cos(t), (3 + std::cos(p)) * std::sin(t), std::sin(p)});
            else if (wrap_u)
                m.positions.push_back({std::cos(t), std::sin(t), double(j)});
            else if (wrap_v)
                m.positions.push_back({double(i), std::cos(p), std::sin(p)});
            else
                m.positions.push_back({double(i), double(j), 0.0});
        }
    const auto id = [&](int i, int j) { return (j % nv) * nu + i % nu; };
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i)
            if (static_cast<std::size_t>(i + w * j) >= keep.size() || keep[i + w * j])
                m.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
    // Drop the vertices no face uses (numbered in order).
    std::vector<int> used(m.positions.size(), -1);
    int n = 0;
    for (const auto& f : m.faces)
        for (const int v : f) used[v] = 0;
    std::vector<std::array<double, 3>> kept;
    for (std::size_t v = 0; v < used.size(); ++v)
        if (used[v] == 0) {
            used[v] = n++;
            kept.push_back(m.positions[v]);
        }
    for (auto& f : m.faces)
        for (int& v : f) v = used[v];
    m.positions = kept;
    return m;
}

} // namespace qex::testing

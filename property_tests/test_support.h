// Shared helpers of the tests: run an extraction and judge it with the checker.
#pragma once

#include "map_generators.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace qex::testing {

/// Extracts and requires a valid mesh; returns the result for further assertions.
inline Result extract_valid(const Input& in, const Options& opt = {}) {
    Result r = extract(in, opt);
    EXPECT_TRUE(r.ok()) << to_string(r.error.code) << ": " << r.error.message;
    const VerifyResult v = verify(in, r.mesh);
    EXPECT_TRUE(v.valid) << (v.violations.empty() ? std::string() : v.violations[0].message);
    for (const auto& f : r.mesh.faces) EXPECT_EQ(f.size(), 4u);
    return r;
}

/// A comparable summary of a mesh: per face the sorted rounded positions of its corners.
inline std::vector<std::vector<std::array<long long, 3>>> signature(const QuadMesh& m) {
    std::vector<std::vector<std::array<long long, 3>>> out;
    for (const auto& f : m.faces) {
        std::vector<std::array<long long, 3>> face;
        for (int v : f) {
            const auto& p = m.positions[v];
            face.push_back({std::llround(p[0] * 1e6), std::llround(p[1] * 1e6), std::llround(p[2] * 1e6)});
        }
        std::sort(face.begin(), face.end());
        out.push_back(face);
    }
    std::sort(out.begin(), out.end());
    return out;
}

/// Same combinatorics and positions within `tol`: each vertex of a matched to its nearest in b.
inline bool same_mesh(const QuadMesh& a, const QuadMesh& b, double tol) {
    if (a.positions.size() != b.positions.size() || a.faces.size() != b.faces.size()) return false;
    std::vector<int> match(a.positions.size(), -1);
    for (std::size_t i = 0; i < a.positions.size(); ++i) {
        double best = tol;
        for (std::size_t j = 0; j < b.positions.size(); ++j) {
            double d = 0;
            for (int k = 0; k < 3; ++k) d = std::max(d, std::abs(a.positions[i][k] - b.positions[j][k]));
            if (d < best) {
                best = d;
                match[i] = static_cast<int>(j);
            }
        }
        if (match[i] < 0) return false;
    }
    auto canon = [](std::vector<int> f) {
        std::rotate(f.begin(), std::min_element(f.begin(), f.end()), f.end());
        return f;
    };
    std::vector<std::vector<int>> fa, fb;
    for (const auto& f : a.faces) {
        std::vector<int> g;
        for (int v : f) g.push_back(match[v]);
        fa.push_back(canon(g));
    }
    for (const auto& f : b.faces) fb.push_back(canon(f));
    std::sort(fa.begin(), fa.end());
    std::sort(fb.begin(), fb.end());
    return fa == fb;
}

} // namespace qex::testing

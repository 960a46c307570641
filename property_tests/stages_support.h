// Helpers of the stage tests (stages_test.cpp, stages_holes_test.cpp, stages_mend_test.cpp): a
// map sanitized, and quad meshes with faces dropped, compared and laid out for the holes' stages.
#pragma once

#include "ladder/ladder.h"
#include "pipeline.h"
#include "test_support.h"
#include "transform_checks.h"
#include <climits>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <algorithm>
#include <random>

namespace qex::testing {

/// The map sanitized (stages transitions, valences, sanitize), its transitions computed again.
inline detail::TriMesh sanitized(const Input& in) {
    detail::TriMesh m = detail::make_mesh(in);
    EXPECT_EQ(detail::build_topology(m, "test").code, ErrorCode::None);
    Report rep;
    detail::compute_transitions(m);
    detail::count_valences(m);
    EXPECT_EQ(detail::sanitize(m, {}, {}, rep).code, ErrorCode::None);
    detail::compute_transitions(m);
    return m;
}
/// Not for a temporary input: the mesh reads its 3D positions from the input it was made from,
/// and would outlive it (regions_test once read a freed input this way).
detail::TriMesh sanitized(Input&&) = delete;

/// `mesh` without the faces listed (face_uvs kept in step).
inline QuadMesh without_faces(const QuadMesh& mesh, std::vector<std::size_t> drop) {
    QuadMesh out = mesh;
    std::sort(drop.rbegin(), drop.rend());
    for (const std::size_t f : drop) {
        out.faces.erase(out.faces.begin() + static_cast<std::ptrdiff_t>(f));
        out.face_uvs.erase(out.face_uvs.begin() + static_cast<std::ptrdiff_t>(f));
    }
    return out;
}

/// The faces of `mesh`, each turned to start at its smallest vertex, sorted.
inline std::vector<std::vector<int>> face_set(const QuadMesh& mesh) {
    std::vector<std::vector<int>> faces = mesh.faces;
    for (auto& f : faces) std::rotate(f.begin(), std::min_element(f.begin(), f.end()), f.end());
    std::sort(faces.begin(), faces.end());
    return faces;
}

/// Per vertex of `mesh`, the faces round it, in face order.
inline std::vector<std::vector<std::size_t>> faces_around(const QuadMesh& mesh) {
    std::vector<std::vector<std::size_t>> around(mesh.positions.size());
    for (std::size_t f = 0; f < mesh.faces.size(); ++f)
        for (const int v : mesh.faces[f]) around[static_cast<std::size_t>(v)].push_back(f);
    return around;
}

/// A torus, an icosahedron (valence-5 singularities) and a disk (a boundary), each with its map
/// (3 quads per layout edge, on the grid) and its valid mesh.
struct LayoutMesh {
    QuadLayout layout;
    Input in;
    QuadMesh mesh;
};

inline std::vector<LayoutMesh> layout_meshes() {
    std::vector<LayoutMesh> out;
    for (const QuadLayout& layout : {torus_layout(), icosahedron_layout(), disk_layout(3)}) {
        Input in = make_map(layout, 3, 3);
        QuadMesh mesh = extract_valid(in).mesh;
        out.push_back({layout, std::move(in), std::move(mesh)});
    }
    return out;
}

/// The first vertex with four faces whose faces' corners all have four faces too (away from
/// singularities and the boundary), given the faces round each vertex; SIZE_MAX if none.
inline std::size_t inner_vertex(const QuadMesh& mesh, const std::vector<std::vector<std::size_t>>& around) {
    for (std::size_t v = 0; v < around.size(); ++v) {
        bool inner = around[v].size() == 4;
        for (const std::size_t f : around[v])
            for (const int u : mesh.faces[f]) inner = inner && around[static_cast<std::size_t>(u)].size() == 4;
        if (inner) return v;
    }
    return SIZE_MAX;
}

/// `mesh`'s positions and faces alone (no provenance), its vertices no face uses left out.
inline QuadMesh compacted(const QuadMesh& mesh) {
    QuadMesh bare;
    std::vector<int> index(mesh.positions.size(), -1);
    for (const auto& f : mesh.faces) {
        bare.faces.push_back(f);
        for (int& v : bare.faces.back()) {
            int& i = index[static_cast<std::size_t>(v)];
            if (i < 0) {
                i = static_cast<int>(bare.positions.size());
                bare.positions.push_back(mesh.positions[static_cast<std::size_t>(v)]);
            }
            v = i;
        }
    }
    return bare;
}

/// Whether `mesh`'s faces, without its provenance, make an all-quad, manifold, consistently
/// oriented surface of the input's topology (the checker's first part, locating nothing), its
/// vertices no face uses left out.
inline bool topology_kept(const Input& in, const QuadMesh& mesh) {
    VerifyOptions topology_only;
    topology_only.locate = false;
    return verify(in, compacted(mesh), topology_only).valid;
}

/// The rim a HoleFilled explanation names (its output vertices, in order).
inline std::vector<int> named_rim(const Defect& d) {
    std::vector<int> rim;
    std::istringstream named(d.message.substr(d.message.find("output vertices ") + 16));
    for (int v = 0; named >> v;) rim.push_back(v);
    return rim;
}

/// Over the vertices of `filled`'s patch (the faces past those of `holed`), the sum of the
/// differences between their face counts and four.
inline int patch_difference(const QuadMesh& holed, const QuadMesh& filled) {
    std::map<int, int> faces;
    for (std::size_t f = holed.faces.size(); f < filled.faces.size(); ++f)
        for (const int v : filled.faces[f]) faces[v] = 0;
    for (const auto& f : filled.faces)
        for (const int v : f)
            if (faces.count(v)) ++faces[v];
    int sum = 0;
    for (const auto& [v, n] : faces) sum += std::abs(n - 4);
    return sum;
}

/// By brute force, the least sum of differences from four of the face counts of the rim `filled`
/// names, over every quadrangulation of it (every quad (i, a, b, j) on a side (i, j), recursively).
inline int least_difference(const QuadMesh& holed, const Defect& filled) {
    const std::vector<int> rim = named_rim(filled);
    const int n = static_cast<int>(rim.size());
    std::vector<int> corners(static_cast<std::size_t>(n), 0);
    for (const auto& f : holed.faces)
        for (const int v : f)
            for (int i = 0; i < n; ++i) corners[static_cast<std::size_t>(i)] += v == rim[static_cast<std::size_t>(i)];
    int best = INT_MAX;
    std::vector<int> added(static_cast<std::size_t>(n), 0);
    std::vector<std::pair<int, int>> pending{{0, n - 1}};
    std::function<void()> search = [&] {
        if (pending.empty()) {
            int sum = 0;
            for (int i = 0; i < n; ++i)
                sum += std::abs(corners[static_cast<std::size_t>(i)] + added[static_cast<std::size_t>(i)] - 4);
            best = std::min(best, sum);
            return;
        }
        const auto [i, j] = pending.back();
        pending.pop_back();
        if (j - i == 1) {
            search();
        } else {
            for (int a = i + 1; a < j; a += 2)
                for (int b = a + 1; b < j; b += 2) {
                    for (const int v : {i, a, b, j}) ++added[static_cast<std::size_t>(v)];
                    pending.insert(pending.end(), {{i, a}, {a, b}, {b, j}});
                    search();
                    pending.resize(pending.size() - 3);
                    for (const int v : {i, a, b, j}) --added[static_cast<std::size_t>(v)];
                }
        }
        pending.emplace_back(i, j);
    };
    search();
    return best;
}

} // namespace qex::testing

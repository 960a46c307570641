// Canonical output order: vertices sorted by position, each face rotated to start at its smallest
// vertex with local UVs relative to that corner (and turned so its first edge runs along +u), faces sorted by their vertex lists. Positions are
// computed order-independently upstream, so any vertex, face or corner order of the input gives
// the identical mesh.
#include "parallel.h"
#include "pipeline.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstddef>
#include <numeric>

namespace qex::detail {

namespace {

/// Sorts `v` by `less`, a total order (so the result is unique): on two threads, each half
/// sorted on its own and the halves merged, from 2^16 elements.
template <class T, class Less>
void sort_total(std::vector<T>& v, Less less, int threads) {
    if (!run_parallel(threads, static_cast<std::int64_t>(v.size()))) {
        std::sort(v.begin(), v.end(), less);
        return;
    }
    const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
    for_parts(2, 2, 2, [&](int half, std::int64_t, std::int64_t) {
        std::sort(half == 0 ? v.begin() : mid, half == 0 ? mid : v.end(), less);
    });
    std::vector<T> merged(v.size());
    std::merge(v.begin(), mid, mid, v.end(), merged.begin(), less);
    v.swap(merged);
}

/// Output vertices by position (ties by index).
std::vector<int> vertex_order(const QuadMesh& mesh, int threads) {
    // Sorted as keys that carry their positions: comparisons then read no other memory.
    struct Key {
        std::array<double, 3> p;
        int index;
    };
    std::vector<Key> keys(mesh.positions.size());
    for (std::size_t i = 0; i < keys.size(); ++i) keys[i] = {mesh.positions[i], static_cast<int>(i)};
    sort_total(
        keys,
        [](const Key& a, const Key& b) {
            if (a.p != b.p) return a.p < b.p;
            return a.index < b.index;
        },
        threads);
    std::vector<int> order(keys.size());
    for (std::size_t i = 0; i < keys.size(); ++i) order[i] = keys[i].index;
    return order;
}

/// Renumbers each face's vertices by `rank` and rotates it to start at its smallest vertex,
/// with local UVs relative to that corner and turned so the first edge runs along +u.
void normalize_faces(FaceWalks& faces, const std::vector<int>& rank) {
    for (std::size_t f = 0; f < faces.size(); ++f) {
        const auto b = static_cast<std::ptrdiff_t>(faces.first[f]), e = static_cast<std::ptrdiff_t>(faces.first[f + 1]);
        const auto face = faces.qv.begin() + b, face_end = faces.qv.begin() + e;
        const auto uv = faces.uv.begin() + b, uv_end = faces.uv.begin() + e;
        const std::size_t n = faces.first[f + 1] - faces.first[f];
        for (auto v = face; v != face_end; ++v) *v = rank[static_cast<std::size_t>(*v)];
        const auto first = std::min_element(face, face_end) - face;
        std::rotate(face, face + first, face_end);
        std::rotate(uv, uv + first, uv_end);
        // Local UVs relative to the first corner, turned so the first non-zero edge points along
        // +u (or into the first quadrant): independent of the chart the walk started in.
        const IPoint o = n == 0 ? IPoint{0, 0} : uv[0];
        for (auto x = uv; x != uv_end; ++x) *x = {(*x)[0] - o[0], (*x)[1] - o[1]};
        for (std::size_t k = 1; k < n; ++k) {
            auto e1 = IPoint{uv[k][0] - uv[k - 1][0], uv[k][1] - uv[k - 1][1]};
            if (e1[0] == 0 && e1[1] == 0) continue;
            int turns = 0; // quarter turns counter-clockwise, (u, v) -> (-v, u), until u > 0 and v >= 0
            while (!(e1[0] > 0 && e1[1] >= 0)) e1 = {-e1[1], e1[0]}, ++turns;
            for (int t = 0; t < turns; ++t)
                for (auto x = uv; x != uv_end; ++x) *x = {-(*x)[1], (*x)[0]};
            break;
        }
    }
}

/// Faces in the order of their vertex lists (as std::vector's operator< orders them). The first
/// four entries, padded with -1, are compared in place; longer faces that tie on them are
/// compared in full.
std::vector<int> face_order(const FaceWalks& faces, int threads) {
    struct FaceKey {
        std::array<int, 4> head;
        int face;
    };
    std::vector<FaceKey> fkeys(faces.size());
    for (std::size_t f = 0; f < faces.size(); ++f) {
        fkeys[f] = {{-1, -1, -1, -1}, static_cast<int>(f)};
        for (std::size_t k = 0; k < 4 && faces.first[f] + k < faces.first[f + 1]; ++k)
            fkeys[f].head[k] = faces.qv[faces.first[f] + k];
    }
    sort_total(
        fkeys,
        [&](const FaceKey& a, const FaceKey& b) {
            for (std::size_t k = 0; k < 4; ++k)
                if (a.head[k] != b.head[k]) return a.head[k] < b.head[k];
            const auto fa = static_cast<std::size_t>(a.face), fb = static_cast<std::size_t>(b.face);
            const std::size_t na = faces.first[fa + 1] - faces.first[fa], nb = faces.first[fb + 1] - faces.first[fb];
            if (na > 4 || nb > 4) {
                const int* x = faces.qv.data() + faces.first[fa];
                const int* y = faces.qv.data() + faces.first[fb];
                if (na != nb || !std::equal(x, x + na, y)) return std::lexicographical_compare(x, x + na, y, y + nb);
            }
            return a.face < b.face;
        },
        threads);
    std::vector<int> order(faces.size());
    for (std::size_t i = 0; i < fkeys.size(); ++i) order[i] = fkeys[i].face;
    return order;
}

/// Sets the mesh's faces from `faces`, face order[i] as face i. The faces' vectors are allocated
/// in output order, the vertex lists first, so what reads them in order (the checker, the
/// writers, their release) walks memory in order.
void fill_faces(QuadMesh& mesh, const FaceWalks& faces, const std::vector<int>& order) {
    mesh.faces.clear();
    mesh.face_uvs.clear();
    mesh.faces.reserve(order.size());
    mesh.face_uvs.reserve(order.size());
    for (const int f : order) {
        const auto i = static_cast<std::size_t>(f);
        mesh.faces.emplace_back(faces.qv.begin() + static_cast<std::ptrdiff_t>(faces.first[i]),
                                faces.qv.begin() + static_cast<std::ptrdiff_t>(faces.first[i + 1]));
    }
    for (const int f : order) {
        const auto i = static_cast<std::size_t>(f);
        mesh.face_uvs.emplace_back(faces.uv.begin() + static_cast<std::ptrdiff_t>(faces.first[i]),
                                   faces.uv.begin() + static_cast<std::ptrdiff_t>(faces.first[i + 1]));
    }
}

} // namespace

void set_faces(QuadMesh& mesh, const FaceWalks& faces) {
    std::vector<int> order(faces.size());
    std::iota(order.begin(), order.end(), 0);
    fill_faces(mesh, faces, order);
}

std::vector<int> canonicalize(QuadMesh& mesh, FaceWalks faces, int threads) {
    std::vector<int> rank;
    {
        const std::vector<int> order = vertex_order(mesh, threads);
        rank.resize(order.size());
        for (std::size_t i = 0; i < order.size(); ++i) rank[order[i]] = static_cast<int>(i);
        std::vector<std::array<double, 3>> positions;
        std::vector<Provenance> provenance;
        positions.reserve(order.size());
        provenance.reserve(order.size());
        for (int i : order) {
            positions.push_back(mesh.positions[i]);
            provenance.push_back(mesh.provenance[i]);
        }
        mesh.positions.swap(positions);
        mesh.provenance.swap(provenance);
    }
    normalize_faces(faces, rank);
    const std::vector<int> order = face_order(faces, threads);
    std::vector<int> new_index(faces.size());
    for (std::size_t i = 0; i < order.size(); ++i) new_index[static_cast<std::size_t>(order[i])] = static_cast<int>(i);
    fill_faces(mesh, faces, order);
    return new_index;
}

} // namespace qex::detail

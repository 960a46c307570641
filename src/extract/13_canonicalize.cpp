// Canonical output order: vertices sorted by position, each face rotated to start at its smallest
// vertex with local UVs relative to that corner (and turned so its first edge runs along +u), faces sorted by their vertex lists. Positions are
// computed order-independently upstream, so any vertex, face or corner order of the input gives
// the identical mesh.
#include "pipeline.h"

#include <algorithm>
#include <numeric>

namespace qex::detail {

namespace {

/// Output vertices by position (ties by index).
std::vector<int> vertex_order(const QuadMesh& mesh) {
    std::vector<int> order(mesh.positions.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int b) {
        if (mesh.positions[a] != mesh.positions[b]) return mesh.positions[a] < mesh.positions[b];
        return a < b;
    });
    return order;
}

/// Renumbers each face's vertices by `rank` and rotates it to start at its smallest vertex,
/// with local UVs relative to that corner and turned so the first edge runs along +u.
void normalize_faces(QuadMesh& mesh, const std::vector<int>& rank) {
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
        auto& face = mesh.faces[f];
        auto& uv = mesh.face_uvs[f];
        for (int& v : face) v = rank[v];
        const auto first = std::min_element(face.begin(), face.end()) - face.begin();
        std::rotate(face.begin(), face.begin() + first, face.end());
        std::rotate(uv.begin(), uv.begin() + first, uv.end());
        // Local UVs relative to the first corner, turned so the first non-zero edge points along
        // +u (or into the first quadrant): independent of the chart the walk started in.
        const auto o = uv.empty() ? std::array<std::int64_t, 2>{0, 0} : uv[0];
        for (auto& x : uv) x = {x[0] - o[0], x[1] - o[1]};
        for (std::size_t k = 1; k < uv.size(); ++k) {
            auto e = std::array<std::int64_t, 2>{uv[k][0] - uv[k - 1][0], uv[k][1] - uv[k - 1][1]};
            if (e[0] == 0 && e[1] == 0) continue;
            int turns = 0; // quarter turns counter-clockwise, (u, v) -> (-v, u), until u > 0 and v >= 0
            while (!(e[0] > 0 && e[1] >= 0)) e = {-e[1], e[0]}, ++turns;
            for (int t = 0; t < turns; ++t)
                for (auto& x : uv) x = {-x[1], x[0]};
            break;
        }
    }
}

/// Faces in the order of their vertex lists (as std::vector's operator< orders them). The first
/// four entries, padded with -1, are compared in place; longer faces that tie on them are
/// compared in full.
std::vector<int> face_order(const QuadMesh& mesh) {
    struct FaceKey {
        std::array<int, 4> head;
        int face;
    };
    std::vector<FaceKey> fkeys(mesh.faces.size());
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
        fkeys[f] = {{-1, -1, -1, -1}, static_cast<int>(f)};
        for (std::size_t k = 0; k < 4 && k < mesh.faces[f].size(); ++k) fkeys[f].head[k] = mesh.faces[f][k];
    }
    std::sort(fkeys.begin(), fkeys.end(), [&](const FaceKey& a, const FaceKey& b) {
        if (a.head != b.head) return a.head < b.head;
        const auto &fa = mesh.faces[static_cast<std::size_t>(a.face)],
                   &fb = mesh.faces[static_cast<std::size_t>(b.face)];
        if (fa.size() > 4 || fb.size() > 4)
            if (fa != fb) return fa < fb;
        return a.face < b.face;
    });
    std::vector<int> order(mesh.faces.size());
    for (std::size_t i = 0; i < fkeys.size(); ++i) order[i] = fkeys[i].face;
    return order;
}

} // namespace

std::vector<int> canonicalize(QuadMesh& mesh) {
    const std::vector<int> order = vertex_order(mesh);
    std::vector<int> rank(order.size());
    for (std::size_t i = 0; i < order.size(); ++i) rank[order[i]] = static_cast<int>(i);
    QuadMesh out;
    out.positions.reserve(order.size());
    out.provenance.reserve(order.size());
    for (int i : order) {
        out.positions.push_back(mesh.positions[i]);
        out.provenance.push_back(mesh.provenance[i]);
    }
    normalize_faces(mesh, rank);
    std::vector<int> new_index(mesh.faces.size());
    out.faces.reserve(mesh.faces.size());
    out.face_uvs.reserve(mesh.faces.size());
    for (int f : face_order(mesh)) {
        new_index[f] = static_cast<int>(out.faces.size());
        out.faces.push_back(std::move(mesh.faces[f]));
        out.face_uvs.push_back(std::move(mesh.face_uvs[f]));
    }
    out.map_uvs = std::move(mesh.map_uvs);
    out.map_repaired = std::move(mesh.map_repaired);
    mesh = std::move(out);
    return new_index;
}

} // namespace qex::detail

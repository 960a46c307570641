// Stage close_holes (not in the paper): a rung's mesh that the checker rejects may have holes
// where face walks did not close (next to a fold-over, two traces claimed one q-port, and the
// walks round the edge that lost its trace ran open). Each hole away from the input's boundary,
// whose rim is a simple loop of the mesh's own vertices, is laid out in the grid from the
// quarter turns the faces round each rim vertex leave it (a regular vertex has four). Where the
// layout closes once round a set of unit cells whose corners all lie on the rim, those cells are
// the faces the walks lost, and they are added. The result is only a candidate: the caller keeps
// it only if the checker then accepts the mesh, against the map it carries and against the given
// map alone.
#include "ladder.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>

namespace qex::detail {
namespace {

std::uint64_t edge_key(int a, int b) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

/// Whether a mesh vertex lies on the input's boundary, by its provenance and the input's own
/// topology (`g`, from build_topology: a boundary half-edge has no opposite). Unknown: true.
bool on_input_boundary(const TriMesh& g, const Provenance& p) {
    if (p.element < 0) return true;
    switch (p.kind) {
        case QVertexKind::Vertex: return p.element >= g.num_vertices || g.on_boundary[p.element] != 0;
        case QVertexKind::Edge:
            return p.element >= g.num_faces() || p.local_edge < 0 || p.local_edge > 2 ||
                   g.opp[3 * p.element + p.local_edge] < 0;
        case QVertexKind::Face: return false;
    }
    return true;
}

/// Per input vertex, the quarter turns its fan winds in the map the mesh carries (the signed
/// angles of its corners summed): the faces a vertex of the mesh on it may have, a
/// singularity's valence. -1 where a triangle of the fan was collapsed away (NaN in the map).
std::vector<int> fan_quarter_turns(const Input& input, const std::vector<std::array<double, 2>>& map) {
    std::vector<double> sum(input.positions.size(), 0.0);
    std::vector<char> lost(input.positions.size(), 0);
    for (std::size_t f = 0; f < input.triangles.size() && 3 * f + 2 < map.size(); ++f)
        for (std::size_t k = 0; k < 3; ++k) {
            const auto v = static_cast<std::size_t>(input.triangles[f][k]);
            const auto &a = map[3 * f + k], &b = map[3 * f + (k + 1) % 3], &c = map[3 * f + (k + 2) % 3];
            const double ux = b[0] - a[0], uy = b[1] - a[1], wx = c[0] - a[0], wy = c[1] - a[1];
            const double angle = std::atan2(ux * wy - uy * wx, ux * wx + uy * wy);
            if (std::isfinite(angle))
                sum[v] += angle;
            else
                lost[v] = 1;
        }
    std::vector<int> turns(sum.size(), -1);
    for (std::size_t v = 0; v < sum.size(); ++v)
        if (!lost[v]) turns[v] = static_cast<int>(std::lround(sum[v] / (0.5 * M_PI)));
    return turns;
}

/// The unit cells a hole's rim encloses, laid out in the grid, as faces of rim vertices; empty
/// if the rim does not close once round cells whose corners are all rim vertices.
std::vector<std::vector<int>> cells_inside(const std::vector<int>& rim, const std::vector<int>& corners,
                                           const std::vector<int>& quarter_turns) {
    // Walking the rim with the hole on the left, a vertex of q quarter turns (four, or a
    // singularity's valence) whose faces take c of them leaves the hole q - c, and the walk turns
    // left by 2 - (q - c) quarter turns there.
    static constexpr std::int64_t kStep[4][2] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
    const std::size_t n = rim.size();
    std::vector<std::array<std::int64_t, 2>> at(n);
    std::map<std::array<std::int64_t, 2>, int> vertex_at;
    std::int64_t x = 0, y = 0;
    int dir = 0, turning = 0;
    for (std::size_t i = 0; i < n; ++i) {
        at[i] = {x, y};
        if (!vertex_at.emplace(at[i], rim[i]).second) return {}; // the rim meets itself
        x += kStep[dir][0];
        y += kStep[dir][1];
        const auto next = static_cast<std::size_t>(rim[(i + 1) % n]);
        const int left = quarter_turns[next] - corners[next];
        if (left < 1) return {};
        const int turn = 2 - left;
        turning += turn;
        dir = ((dir + turn) % 4 + 4) % 4;
    }
    if (x != 0 || y != 0 || dir != 0 || turning != 4) return {};
    std::int64_t x0 = 0, x1 = 0, y0 = 0, y1 = 0;
    for (const auto& p : at)
        x0 = std::min(x0, p[0]), x1 = std::max(x1, p[0]), y0 = std::min(y0, p[1]), y1 = std::max(y1, p[1]);
    std::vector<std::vector<int>> cells;
    for (std::int64_t cy = y0; cy < y1; ++cy)
        for (std::int64_t cx = x0; cx < x1; ++cx) {
            // Winding of the rim round the cell's centre: its vertical edges right of the centre.
            int winding = 0;
            for (std::size_t i = 0; i < n; ++i) {
                const auto &p = at[i], &q = at[(i + 1) % n];
                if (p[0] != q[0] || p[0] <= cx) continue;
                if (std::min(p[1], q[1]) == cy) winding += q[1] > p[1] ? 1 : -1;
            }
            if (winding == 0) continue;
            if (winding != 1) return {};
            std::vector<int> face;
            for (const auto& c : {std::array<std::int64_t, 2>{cx, cy}, {cx + 1, cy}, {cx + 1, cy + 1}, {cx, cy + 1}}) {
                const auto it = vertex_at.find(c);
                if (it == vertex_at.end()) return {}; // a grid point inside the hole: no vertex for it
                face.push_back(it->second);
            }
            cells.push_back(std::move(face));
        }
    return cells;
}

} // namespace

Holes find_holes(const Input& input, const QuadMesh& mesh, std::size_t max_rim) {
    Holes holes;
    if (mesh.provenance.size() != mesh.positions.size()) return holes;
    const auto nv = mesh.positions.size();
    std::vector<std::uint64_t> half; // the faces' half-edges, sorted
    half.reserve(4 * mesh.faces.size());
    std::vector<int> corners(nv, 0);
    for (const auto& f : mesh.faces) {
        if (f.size() != 4) return holes; // only holes in an all-quad mesh
        for (std::size_t i = 0; i < 4; ++i) {
            if (f[i] < 0 || static_cast<std::size_t>(f[i]) >= nv) return holes;
            half.push_back(edge_key(f[i], f[(i + 1) % 4]));
            ++corners[static_cast<std::size_t>(f[i])];
        }
    }
    std::sort(half.begin(), half.end());
    if (std::adjacent_find(half.begin(), half.end()) != half.end()) return holes; // not manifold
    // The hole's rim runs against the faces' boundary edges: b -> a for a face's a -> b.
    std::vector<int> rim_next(nv, -1);
    std::vector<char> pinched(nv, 0);
    for (const auto& f : mesh.faces)
        for (std::size_t i = 0; i < 4; ++i) {
            const int a = f[i], b = f[(i + 1) % 4];
            if (std::binary_search(half.begin(), half.end(), edge_key(b, a))) continue;
            if (rim_next[static_cast<std::size_t>(b)] >= 0) pinched[static_cast<std::size_t>(b)] = 1;
            rim_next[static_cast<std::size_t>(b)] = a;
        }
    // The rims first, then the input's topology and fan turns only if one is found: a mesh whose
    // face walks left no hole (a closed mesh, or one open only along the input's boundary) is the
    // common case, and building the input's topology took most of the mending's time.
    std::vector<char> seen(nv, 0);
    for (std::size_t start = 0; start < nv; ++start) {
        if (rim_next[start] < 0 || seen[start]) continue;
        std::vector<int> rim;
        bool simple = true;
        for (int v = static_cast<int>(start); !seen[static_cast<std::size_t>(v)];
             v = rim_next[static_cast<std::size_t>(v)]) {
            seen[static_cast<std::size_t>(v)] = 1;
            rim.push_back(v);
            simple = simple && !pinched[static_cast<std::size_t>(v)] && rim_next[static_cast<std::size_t>(v)] >= 0;
            if (rim_next[static_cast<std::size_t>(v)] < 0) break;
        }
        if (simple && rim.size() >= 4 && rim.size() <= max_rim &&
            rim_next[static_cast<std::size_t>(rim.back())] == rim[0])
            holes.rims.push_back(std::move(rim));
    }
    holes.wound.assign(nv, 4);
    holes.corners = std::move(corners);
    holes.half = std::move(half);
    if (holes.rims.empty()) return holes;
    TriMesh g = make_mesh(input);
    if (build_topology(g, "input").code != ErrorCode::None) return Holes{};
    // A rim along the input's boundary is the surface's own edge, no hole.
    const auto on_boundary = [&](const std::vector<int>& rim) {
        return std::any_of(rim.begin(), rim.end(),
                           [&](int v) { return on_input_boundary(g, mesh.provenance[static_cast<std::size_t>(v)]); });
    };
    holes.rims.erase(std::remove_if(holes.rims.begin(), holes.rims.end(), on_boundary), holes.rims.end());
    if (holes.rims.empty()) return holes;
    // Every vertex has four quarter turns, or a vertex on an input vertex has as many as that
    // vertex's fan winds: a singularity's valence, unless a fold-over left in its fan changes the
    // count.
    const std::vector<int> fan_turns = fan_quarter_turns(input, mesh.map_uvs);
    for (std::size_t v = 0; v < nv; ++v) {
        const Provenance& p = mesh.provenance[v];
        if (p.kind == QVertexKind::Vertex && p.element >= 0 && static_cast<std::size_t>(p.element) < fan_turns.size() &&
            fan_turns[static_cast<std::size_t>(p.element)] > 0)
            holes.wound[v] = fan_turns[static_cast<std::size_t>(p.element)];
    }
    return holes;
}

std::string rim_description(const std::vector<int>& rim) {
    std::string through;
    for (const int v : rim) through += " " + std::to_string(v);
    return "its rim through output vertices" + through;
}

Defect patch_hole(QuadMesh& mesh, const std::vector<int>& rim, const std::vector<std::vector<int>>& faces,
                  DefectKind kind, const std::string& what) {
    for (const auto& face : faces) {
        mesh.faces.push_back(face);
        mesh.face_uvs.push_back({{0, 0}, {1, 0}, {1, 1}, {0, 1}});
    }
    const Provenance& p = mesh.provenance[static_cast<std::size_t>(rim[0])];
    return {kind, what, p.chart_triangle, -1, {p.grid[0], p.grid[1]}, std::nullopt};
}

std::vector<char> close_rims(const Holes& holes, QuadMesh& mesh, bool wound_first, std::vector<Defect>& done) {
    std::vector<char> closed(holes.rims.size(), 0);
    // One reading of the rim vertices' quarter turns is tried first, the other where a rim does
    // not close with it.
    const std::vector<int> regular(holes.corners.size(), 4);
    const std::vector<int>& first = wound_first ? holes.wound : regular;
    const std::vector<int>& second = wound_first ? regular : holes.wound;
    for (std::size_t r = 0; r < holes.rims.size(); ++r) {
        const std::vector<int>& rim = holes.rims[r];
        std::vector<std::vector<int>> cells = cells_inside(rim, holes.corners, first);
        if (cells.empty()) cells = cells_inside(rim, holes.corners, second);
        if (cells.empty()) continue;
        closed[r] = 1;
        done.push_back(patch_hole(mesh, rim, cells, DefectKind::HoleClosed,
                                  "a hole the face walks left (" + rim_description(rim) + ") was closed by " +
                                      std::to_string(cells.size()) + " unit cell" + (cells.size() == 1 ? "" : "s") +
                                      " of the grid, laid out from the faces round its rim (the face walks that ran "
                                      "open there stay listed among the defects)"));
    }
    return closed;
}

std::vector<Defect> close_holes(const Input& input, QuadMesh& mesh, bool wound_first) {
    std::vector<Defect> done;
    (void)close_rims(find_holes(input, mesh), mesh, wound_first, done);
    return done;
}

} // namespace qex::detail

// Collapse of edges that have zero length in the parameter domain (Section 3), so that every
// remaining edge determines its transition function. Original 3D positions stay in the corners.
// An edge is collapsed only where the link condition holds (the endpoints share no neighbour
// besides the edge's opposite vertices); otherwise the collapse would pinch the surface, and the
// edge is kept: compute_transitions then derives its rotation from the fan of an endpoint.
#include "pipeline.h"
#include "union_find.h"

#include <algorithm>
#include <iterator>
#include <string>

namespace qex::detail {
namespace {

/// Whether some edge has zero length in the parameter domain.
bool has_zero_length_edge(const TriMesh& m) {
    bool any = false;
    for (int h = 0; h < 3 * m.num_faces() && !any; ++h) any = m.uv[h] == m.uv[TriMesh::next(h)];
    return any;
}

/// The vertices glued so far (union-find over the mesh's vertices), the triangles around each
/// representative vertex, and whether a triangle is still alive.
class Gluing {
public:
    explicit Gluing(const TriMesh& m);
    /// The representative of corner k of triangle f.
    int corner_of(int f, int k) { return sets_.find(m_.tri[f][k]); }
    bool dead(int f) const { return dead_[f] != 0; }
    /// Collapses every zero-length edge whose collapse keeps the surface a manifold; returns how many.
    std::int64_t collapse_all();

private:
    /// The representatives adjacent to representative v through live triangles, sorted.
    void neighbours(int v, std::vector<int>& out);
    /// Whether the edge (a, b) passes the link condition.
    bool link_condition(int a, int b);
    /// Glues b into a; triangles holding both die.
    void glue(int b, int a);

    /// A vertex's position, the canonical key of what survives a collapse.
    const std::array<double, 3>& position(int v) const { return vpos_[static_cast<std::size_t>(v)]; }

    const TriMesh& m_;
    UnionFind sets_;
    std::vector<std::array<double, 3>> vpos_;
    std::vector<std::vector<int>> faces_of_;
    std::vector<char> dead_;
    std::vector<int> na_, nb_, common_, opposite_; // scratch
};

Gluing::Gluing(const TriMesh& m) : m_(m), sets_(static_cast<std::size_t>(m.num_vertices)) {
    faces_of_.resize(m.num_vertices);
    // A vertex glued by an earlier round of collapses has corners of several input vertices: its
    // own input vertex (the survivor's) is the one that counts.
    vpos_.resize(static_cast<std::size_t>(m.num_vertices));
    for (int v = 0; v < m.num_vertices; ++v) vpos_[static_cast<std::size_t>(v)] = m.vertex_pos(v);
    for (int f = 0; f < m.num_faces(); ++f)
        for (int k = 0; k < 3; ++k) faces_of_[m.tri[f][k]].push_back(f);
    dead_.assign(m.num_faces(), 0);
}

void Gluing::neighbours(int v, std::vector<int>& out) {
    out.clear();
    for (int f : faces_of_[v]) {
        if (dead_[f]) continue;
        for (int k = 0; k < 3; ++k)
            if (const int w = corner_of(f, k); w != v) out.push_back(w);
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
}

bool Gluing::link_condition(int a, int b) {
    neighbours(a, na_);
    neighbours(b, nb_);
    common_.clear();
    std::set_intersection(na_.begin(), na_.end(), nb_.begin(), nb_.end(), std::back_inserter(common_));
    // The opposite vertices: third corners of the live triangles holding a and b.
    opposite_.clear();
    for (int g : faces_of_[a]) {
        if (dead_[g]) continue;
        int has_b = 0, other = -1;
        for (int k = 0; k < 3; ++k) {
            const int w = corner_of(g, k);
            if (w == b)
                has_b = 1;
            else if (w != a)
                other = w;
        }
        if (has_b && other >= 0) opposite_.push_back(other);
    }
    std::sort(opposite_.begin(), opposite_.end());
    return common_ == opposite_;
}

void Gluing::glue(int b, int a) {
    sets_.attach(b, a);
    for (int g : faces_of_[b]) {
        faces_of_[a].push_back(g);
        int count_ab = 0;
        for (int k = 0; k < 3; ++k) count_ab += corner_of(g, k) == a;
        if (count_ab > 1) dead_[g] = 1;
    }
    faces_of_[b].clear();
}

std::int64_t Gluing::collapse_all() {
    std::int64_t collapsed = 0;
    // The zero-length edges in an order that does not depend on the input's (by their end
    // points' positions): where collapses compete for the link condition, and which end
    // survives (the one with the smaller position), are then the same for any input order.
    using Key = std::array<std::array<double, 3>, 2>;
    std::vector<std::pair<Key, int>> edges;
    for (int h = 0; h < 3 * m_.num_faces(); ++h)
        if (m_.uv[h] == m_.uv[TriMesh::next(h)]) {
            const auto &p = position(m_.origin(h)), &q = position(m_.target(h));
            edges.push_back({p < q ? Key{p, q} : Key{q, p}, h});
        }
    std::sort(edges.begin(), edges.end());
    // A collapse the link condition refuses may become possible after others: passes repeat
    // until one collapses nothing.
    for (bool changed = !edges.empty(); changed;) {
        changed = false;
        for (const auto& [key, h] : edges) {
            const int f = TriMesh::face(h);
            if (dead_[f]) continue;
            int a = sets_.find(m_.origin(h)), b = sets_.find(m_.target(h));
            if (a == b) continue;
            if (!link_condition(a, b)) continue; // the collapse would pinch the surface
            if (position(b) < position(a) || (position(b) == position(a) && b < a)) std::swap(a, b);
            glue(b, a);
            ++collapsed;
            changed = true;
        }
    }
    return collapsed;
}

/// The mesh of m's live triangles over the glued vertices, numbered in order of first use; the
/// connectivity is not built.
TriMesh reindexed(const TriMesh& m, Gluing& gluing) {
    std::vector<int> new_id(m.num_vertices, -1);
    int nv = 0;
    TriMesh out;
    for (int f = 0; f < m.num_faces(); ++f) {
        if (gluing.dead(f)) continue;
        std::array<int, 3> t{};
        for (int k = 0; k < 3; ++k) {
            const int v = gluing.corner_of(f, k);
            if (new_id[v] < 0) {
                new_id[v] = nv++;
                out.input_vertex.push_back(m.input_vertex[v]);
            }
            t[k] = new_id[v];
            out.uv.push_back(m.uv[3 * f + k]);
            out.corner_vertex.push_back(m.corner_vertex[3 * f + k]);
        }
        out.tri.push_back(t);
        out.input_triangle.push_back(m.input_triangle[f]);
    }
    out.num_vertices = nv;
    out.positions = m.positions;
    out.threads = m.threads;
    return out;
}

} // namespace

Error collapse(TriMesh& m, std::int64_t& collapsed) {
    collapsed = 0;
    if (!has_zero_length_edge(m)) return {};
    Gluing gluing(m);
    collapsed = gluing.collapse_all();
    if (collapsed == 0) return {};
    TriMesh out = reindexed(m, gluing);
    if (out.tri.empty()) return {ErrorCode::CollapseFailed, "every triangle is degenerate in the parameter domain", -1};
    m = std::move(out);
    Error e = build_topology(m, "after collapsing UV-degenerate edges");
    if (e.code != ErrorCode::None) e.code = ErrorCode::CollapseFailed;
    return e;
}

} // namespace qex::detail

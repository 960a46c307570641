// The repair's co-located dipoles: found breadth first from a folded singularity, merged by
// changing the transitions along the path between them, and undone unless re-embedded
// (dipoles.h).
#include "extract/repair/dipoles.h"

#include <algorithm>
#include <string>
#include <utility>

namespace qex::detail::repair_impl {
namespace {

/// Most edges between the two singularities of a co-located dipole.
constexpr int kDipoleReach = 8;

/// The composition of v's fan transitions, walked clockwise from corner `start` round to it:
/// maps start's chart to itself.
GridAutomorphism fan_holonomy(const TriMesh& m, int start) {
    GridAutomorphism g;
    int h = start;
    for (int n = 0; n < m.fan_size[m.origin(start)]; ++n) {
        g = m.map.transition[h].after(g);
        h = m.cw(h);
        if (h < 0) break;
    }
    return g;
}

/// Whether v is an interior singularity next to a flipped or degenerate triangle.
bool folded_singularity(const TriMesh& m, int v) {
    if (!m.map.singular[v] || m.on_boundary[v] || m.fan_start[v] < 0) return false;
    for (int h = m.fan_start[v], n = 0; h >= 0 && n < m.fan_size[v]; h = m.cw(h), ++n)
        if (!positive(m, TriMesh::face(h))) return true;
    return false;
}

/// Per vertex, what the breadth-first search of find_colocated_dipole reached: the half-edge from
/// its parent and its depth (-1: not reached), in the caller's per-vertex scratch (all -1, left
/// so). Flat arrays, not a hash map: a search visits a few hundred vertices, and the map's lookups
/// were most of the dipole search's time.
struct Reached {
    std::vector<int>& from;
    std::vector<int>& depth;
    std::vector<int> list;
    bool has(int v) const { return depth[static_cast<std::size_t>(v)] >= 0; }
    void set(int v, int h, int d) {
        list.push_back(v);
        from[static_cast<std::size_t>(v)] = h, depth[static_cast<std::size_t>(v)] = d;
    }
    /// Forgets every vertex reached (all -1 again).
    void clear() {
        for (const int v : list) from[static_cast<std::size_t>(v)] = depth[static_cast<std::size_t>(v)] = -1;
        list.clear();
    }
};

/// Two singularities of opposite turns whose valences sum to two regular vertices' (5 and 3, 6
/// and 2), on one grid point when charted along a short path of regular vertices between them:
/// no injective map keeps both, as the path would have zero length. Solver rounding makes
/// them, snapping a dipole's two cones onto one grid point with a fold between them. The paper
/// lets fold-overs spanning singularities merge them (Section 7, Figure 6); here the merge is
/// explicit: the path's transitions are changed so that both become regular (each vertex on
/// the path keeps its fan closed), and the repair then re-embeds the region as a disk. Found
/// breadth first from `a` over `pinned`-free vertices; true with the path in `merge`.
bool find_colocated_dipole(const TriMesh& m, int a, const std::vector<char>& pinned, Reached& parent,
                           DipoleMerge& merge) {
    const int ta = fan_turn(m, a);
    if (ta <= 0) return false;
    // From a canonical corner of a's fan, so that the path found depends neither on the input's
    // order nor on its charts: every other vertex's fan is walked from the corner it is reached by.
    const int first = fan_in_3d_order(m, a)[0];
    const Point2 ua = m.uv[first];
    // Per reached vertex (`parent`, cleared on return): the half-edge from its parent and its
    // depth; per queued vertex, the corner it was reached by and the map from a's chart to that
    // corner's.
    struct Clear {
        Reached& r;
        ~Clear() { r.clear(); }
    } clear{parent};
    std::vector<std::pair<int, GridAutomorphism>> queue{{first, GridAutomorphism{}}};
    parent.set(a, -1, 0);
    for (std::size_t q = 0; q < queue.size(); ++q) {
        const int start = queue[q].first;
        const int w = m.origin(start);
        const int depth = parent.depth[static_cast<std::size_t>(w)];
        if (depth >= kDipoleReach) continue;
        GridAutomorphism g = queue[q].second;
        for (int h = start, n = 0; h >= 0 && n < m.fan_size[w]; ++n) {
            const int c = TriMesh::next(h), x = m.origin(c);
            if (!parent.has(x)) {
                parent.set(x, h, depth + 1);
                if (m.map.singular[x] && !m.on_boundary[x] && x != a) {
                    const int tx = fan_turn(m, x);
                    if (tx > 0 && ((ta + tx) & 3) == 0 && m.map.valence[a] + m.map.valence[x] == 8 &&
                        g.inverse()(m.uv[c]) == ua) {
                        merge.a = a, merge.b = x;
                        merge.valences = {m.map.valence[a], m.map.valence[x]};
                        merge.winding_valences = {m.map.winding_valence[a], m.map.winding_valence[x]};
                        for (int y = x; y != a; y = m.origin(parent.from[static_cast<std::size_t>(y)]))
                            merge.path.push_back(parent.from[static_cast<std::size_t>(y)]);
                        std::reverse(merge.path.begin(), merge.path.end());
                        return true;
                    }
                } else if (!pinned[x]) {
                    queue.push_back({c, g});
                }
            }
            g = m.map.transition[h].after(g);
            h = m.cw(h);
        }
    }
    return false;
}

/// The path's transitions as they were before merge_dipole (its edges are distinct: any order).
void restore_path_transitions(TriMesh& m, const DipoleMerge& merge) {
    for (std::size_t i = 0; i < merge.old.size(); ++i) {
        m.map.transition.set(static_cast<std::size_t>(merge.path[i]), merge.old[i]);
        m.map.transition.set(static_cast<std::size_t>(m.opp[merge.path[i]]), merge.old[i].inverse());
    }
}

/// Changes the path's transitions so that every fan along it closes: a's, each regular vertex's
/// on the way, and (the pair being a dipole on one grid point) b's. False, with nothing changed,
/// when b's does not.
bool merge_dipole(TriMesh& m, DipoleMerge& merge) {
    for (const int e : merge.path) {
        merge.old.push_back(m.map.transition[e]);
        const GridAutomorphism fixed = fan_holonomy(m, m.cw(e)).inverse().after(m.map.transition[e]);
        m.map.transition.set(static_cast<std::size_t>(e), fixed);
        m.map.transition.set(static_cast<std::size_t>(m.opp[e]), fixed.inverse());
    }
    bool closed = true;
    for (const int e : merge.path) closed = closed && fan_holonomy(m, e).is_identity();
    closed = closed && fan_holonomy(m, m.opp[merge.path.back()]).is_identity();
    if (!closed) {
        restore_path_transitions(m, merge);
        return false;
    }
    for (const int v : {merge.a, merge.b}) {
        m.map.singular[v] = 0;
        m.map.valence[v] = m.map.winding_valence[v] = 4;
    }
    return true;
}

/// Whether the re-embedding made the path's UVs agree with its new transitions (every fan along
/// it was re-embedded); otherwise the merge is undone.
bool dipole_embedded(const TriMesh& m, const DipoleMerge& merge) {
    for (const int e : merge.path) {
        const GridAutomorphism& g = m.map.transition[e];
        const int o = m.opp[e];
        if (g(m.uv[e]) != m.uv[TriMesh::next(o)] || g(m.uv[TriMesh::next(e)]) != m.uv[o]) return false;
    }
    return true;
}

/// Undoes merge_dipole: the path's old transitions, and the two singularities' valences.
void unmerge_dipole(TriMesh& m, const DipoleMerge& merge) {
    restore_path_transitions(m, merge);
    m.map.singular[merge.a] = m.map.singular[merge.b] = 1;
    m.map.valence[merge.a] = merge.valences[0];
    m.map.valence[merge.b] = merge.valences[1];
    m.map.winding_valence[merge.a] = merge.winding_valences[0];
    m.map.winding_valence[merge.b] = merge.winding_valences[1];
}

} // namespace

std::vector<DipoleMerge> merge_colocated_dipoles(TriMesh& m, const std::vector<char>& pinned, std::vector<int>& scratch_a,
                                                 std::vector<int>& scratch_b) {
    std::vector<DipoleMerge> merges;
    std::vector<std::pair<VertexKey, int>> cones;
    for (int v = 0; v < m.num_vertices; ++v)
        if (folded_singularity(m, v)) cones.push_back({vertex_key(m, v), v});
    std::sort(cones.begin(), cones.end());
    if (cones.empty()) return merges;
    Reached reached{scratch_a, scratch_b, {}};
    for (const auto& kv : cones) {
        DipoleMerge d;
        if (m.map.singular[kv.second] && find_colocated_dipole(m, kv.second, pinned, reached, d) && merge_dipole(m, d))
            merges.push_back(std::move(d));
    }
    return merges;
}

bool merge_reembedded(const TriMesh& m, const DipoleMerge& d, const std::vector<char>& reembedded) {
    bool all = reembedded[d.b] != 0;
    for (const int e : d.path) all = all && reembedded[m.origin(e)];
    return all && dipole_embedded(m, d);
}

void settle_merges(TriMesh& m, const std::vector<DipoleMerge>& merges, const std::vector<char>& reembedded,
                   Report& report) {
    // Undone in reverse order (a later path may run along an earlier one's edges).
    for (std::size_t k = merges.size(); k-- > 0;)
        if (!merge_reembedded(m, merges[k], reembedded)) unmerge_dipole(m, merges[k]);
    for (const DipoleMerge& d : merges) {
        if (m.map.singular[d.a]) continue; // undone
        report.explanations.push_back(
            {DefectKind::SingularitiesMerged,
             "the singularities at input vertices " + std::to_string(m.input_vertex[d.a]) + " (valence " +
                 std::to_string(d.valences[0]) + ") and " + std::to_string(m.input_vertex[d.b]) + " (valence " +
                 std::to_string(d.valences[1]) + ") lie on one grid point with " + std::to_string(d.path.size() - 1) +
                 " vertices between them, which no fold-free map allows: they were merged into regular vertices "
                 "(the transitions of the " +
                 std::to_string(d.path.size()) + " edges between them changed) and the fold re-embedded",
             m.input_triangle[TriMesh::face(m.fan_start[d.a])],
             -1,
             {0, 0},
             std::nullopt});
    }
}

std::vector<std::pair<int, GridAutomorphism>> transitions_before_merges(const TriMesh& m,
                                                                        const std::vector<DipoleMerge>& merges) {
    std::vector<std::pair<int, GridAutomorphism>> before;
    for (const DipoleMerge& d : merges)
        for (std::size_t i = 0; i < d.path.size(); ++i) {
            before.push_back({d.path[i], d.old[i]});
            before.push_back({m.opp[d.path[i]], d.old[i].inverse()});
        }
    // By half-edge, the first of each kept (a stable sort keeps the merges' order among equals).
    std::stable_sort(before.begin(), before.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    before.erase(std::unique(before.begin(), before.end(), [](const auto& x, const auto& y) { return x.first == y.first; }),
                 before.end());
    return before;
}

MergesState merges_state(const TriMesh& m, const std::vector<DipoleMerge>& merges) {
    MergesState state;
    for (const DipoleMerge& d : merges) {
        for (const int e : d.path)
            state.transitions.push_back(m.map.transition[e]), state.transitions.push_back(m.map.transition[m.opp[e]]);
        for (const int v : {d.a, d.b})
            state.vertex.insert(state.vertex.end(), {m.map.singular[v], m.map.valence[v], m.map.winding_valence[v]});
    }
    return state;
}

void restore_merges(TriMesh& m, const std::vector<DipoleMerge>& merges, const MergesState& state) {
    std::size_t t = 0, k = 0;
    for (const DipoleMerge& d : merges) {
        for (const int e : d.path) {
            m.map.transition.set(static_cast<std::size_t>(e), state.transitions[t++]);
            m.map.transition.set(static_cast<std::size_t>(m.opp[e]), state.transitions[t++]);
        }
        for (const int v : {d.a, d.b}) {
            m.map.singular[v] = static_cast<char>(state.vertex[k++]);
            m.map.valence[v] = state.vertex[k++];
            m.map.winding_valence[v] = state.vertex[k++];
        }
    }
}

} // namespace qex::detail::repair_impl

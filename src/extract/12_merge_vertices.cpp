// Recovery of lost q-edges (Section 5.5), vertex merging (Algorithm 7) and face simplification.
// Fold-overs make the face walks visit clones of one q-vertex; within a face the clones share
// local UVs. Merging them leaves quads plus 2-gons and 1-gons (collapsed), and, where a singularity
// lost ports, faces that pass a vertex twice: those are split at it.
#include "pipeline.h"
#include "union_find.h"

#include <algorithm>
#include <numeric>
#include <string>

namespace qex::detail {
namespace {

struct Corner {
    int v;
    IPoint uv;
};
using Loop = std::vector<Corner>;

/// Rotates a closed walk to its canonical start (canonical_start), so that the choices below
/// (which lost edge to recover, where to split) do not depend on where the walk started. Only
/// the start moves: the local UVs keep their chart, and their equalities are what counts.
void rotate_canonically(const QState& q, Loop& l) {
    std::vector<int> qv(l.size());
    for (std::size_t i = 0; i < l.size(); ++i) qv[i] = l[i].v;
    const std::size_t s = canonical_start(q, qv.data(), qv.size());
    std::rotate(l.begin(), l.begin() + static_cast<std::ptrdiff_t>(s), l.end());
}

/// Splits a closed walk at positions i < j into walk[i..j] and walk[j..end] + walk[0..i].
void split(const Loop& loop, std::size_t i, std::size_t j, Loop& first, Loop& second) {
    first.assign(loop.begin() + static_cast<std::ptrdiff_t>(i), loop.begin() + static_cast<std::ptrdiff_t>(j) + 1);
    second.assign(loop.begin() + static_cast<std::ptrdiff_t>(j), loop.end());
    second.insert(second.end(), loop.begin(), loop.begin() + static_cast<std::ptrdiff_t>(i) + 1);
}

/// Whether a walk visits every vertex once.
bool visits_distinct(const Loop& loop) {
    bool distinct = true;
    for (std::size_t i = 0; i < loop.size() && distinct; ++i)
        for (std::size_t j = i + 1; j < loop.size() && distinct; ++j) distinct = loop[i].v != loop[j].v;
    return distinct;
}

/// Removes repeated consecutive vertices and spikes (x y x) until there are none left (or one corner).
void remove_repeats_and_spikes(Loop& l) {
    bool changed = true;
    while (changed && l.size() > 1) {
        changed = false;
        for (std::size_t i = 0; i < l.size() && l.size() > 1; ++i) {
            const std::size_t n = l.size(), j = (i + 1) % n;
            if (l[i].v == l[j].v) {
                l.erase(l.begin() + static_cast<std::ptrdiff_t>(j));
                changed = true;
                break;
            }
            if (n > 2 && l[i].v == l[(i + 2) % n].v) { // spike i -> j -> i: drop j and the return
                const std::size_t k = (i + 2) % n;
                std::size_t hi = std::max(j, k), lo = std::min(j, k);
                l.erase(l.begin() + static_cast<std::ptrdiff_t>(hi));
                l.erase(l.begin() + static_cast<std::ptrdiff_t>(lo));
                changed = true;
                break;
            }
        }
    }
}

/// Splits a walk at the first vertex it visits twice into two walks, pushed onto `work`;
/// false if it visits no vertex twice.
bool split_at_repeat(const Loop& l, std::vector<Loop>& work) {
    for (std::size_t i = 0; i < l.size(); ++i)
        for (std::size_t j = i + 1; j < l.size(); ++j)
            if (l[i].v == l[j].v) {
                Loop a, b;
                split(l, i, j, a, b);
                a.pop_back(); // the closing copy of the shared vertex
                b.pop_back();
                work.push_back(std::move(a));
                work.push_back(std::move(b));
                return true;
            }
    return false;
}

/// Removes repeated consecutive vertices and spikes (x y x); splits walks visiting a vertex twice.
void simplify(const QState& q, Loop loop, std::vector<Loop>& out) {
    // Most faces visit distinct vertices and are kept as they are.
    if (visits_distinct(loop)) {
        if (loop.size() < 3) rotate_canonically(q, loop); // its first corner names it (explain_collapsed)
        out.push_back(std::move(loop));
        return;
    }
    std::vector<Loop> work{std::move(loop)};
    while (!work.empty()) {
        Loop l = std::move(work.back());
        work.pop_back();
        remove_repeats_and_spikes(l);
        rotate_canonically(q, l);
        if (!split_at_repeat(l, work)) out.push_back(std::move(l));
    }
}

/// Twice the signed area enclosed by the local UVs of a walk, taken relative to its first corner
/// and accumulated in 128 bits: broken maps give walks whose local UVs lie 2^40 apart.
__int128 twice_area(const Loop& l) {
    __int128 a = 0;
    const IPoint& o = l[0].uv;
    for (std::size_t i = 1; i + 1 < l.size(); ++i) {
        const __int128 px = l[i].uv[0] - o[0], py = l[i].uv[1] - o[1];
        const __int128 qx = l[i + 1].uv[0] - o[0], qy = l[i + 1].uv[1] - o[1];
        a += px * qy - py * qx;
    }
    return a;
}

/// Whether q-vertex v has fewer ports than its expected valence: it lost ports (Section 5.5).
bool missing_ports(const TriMesh& m, const QVertex& v) {
    int expected = 4;
    if (v.kind == QVertexKind::Vertex) {
        if (m.on_boundary[v.element]) return false;
        // Valences 1 and 2 do not occur in cross fields of practical maps: such a count means
        // a fold-over took a full turn from a valence 5 or 6 singularity (Figure 2 (d)).
        if (m.map.singular[v.element])
            for (expected = m.map.valence[v.element]; expected < 3;) expected += 4;
    } else if (v.kind == QVertexKind::Edge && m.opp[v.element] < 0) {
        return false;
    }
    return v.num_ports < expected;
}

/// The face walks as loops; releases `faces` (its copy is no longer needed).
std::vector<Loop> take_loops(FaceWalks& faces) {
    std::vector<Loop> loops;
    loops.reserve(faces.size());
    for (std::size_t f = 0; f < faces.size(); ++f) {
        Loop l(faces.first[f + 1] - faces.first[f]);
        for (std::size_t i = 0; i < l.size(); ++i) l[i] = {faces.qv[faces.first[f] + i], faces.uv[faces.first[f] + i]};
        loops.push_back(std::move(l));
    }
    faces = FaceWalks{}; // copied: released now, not at the end
    return loops;
}

/// Splits l between two non-adjacent corners with equal local UVs into parts a and b that each
/// enclose at least one unit square; on pass 0 only at a corner whose q-vertex lost ports.
bool split_lost_edge(const TriMesh& m, const QState& q, const Loop& l, int pass, Loop& a, Loop& b) {
    for (std::size_t i = 0; i < l.size(); ++i) {
        if (pass == 0 && !missing_ports(m, q.qvertices[l[i].v])) continue;
        for (std::size_t j = 0; j < l.size(); ++j) {
            const std::size_t n = l.size();
            if (j == i || j == (i + 1) % n || i == (j + 1) % n || !(l[j].uv == l[i].uv)) continue;
            // Both parts keep both ends: the ends share local UVs and merge below.
            split(l, std::min(i, j), std::max(i, j), a, b);
            if (twice_area(a) < 2 || twice_area(b) < 2) continue;
            return true;
        }
    }
    return false;
}

/// 1. Recover lost q-edges. A face walk whose local UVs enclose an area of two unit squares or
///    more went around a singularity that lost ports (Figure 5 (a)); it is split between two corners
///    with equal local UVs so that every part covers at least one square. Following the paper,
///    a q-vertex with missing ports is the preferred end of the new q-edge.
std::vector<Loop> recover_lost_edges(const TriMesh& m, const QState& q, FaceWalks& faces, const Options& opt,
                                     Report& report) {
    std::vector<Loop> work = take_loops(faces), loops;
    loops.reserve(work.size());
    Loop a, b;
    while (!work.empty()) {
        Loop l = std::move(work.back());
        work.pop_back();
        bool was_split = false;
        if (opt.recover_lost_edges && l.size() > 4 && twice_area(l) >= 4) {
            rotate_canonically(q, l);
            for (int pass = 0; pass < 2 && !was_split; ++pass) was_split = split_lost_edge(m, q, l, pass, a, b);
        }
        if (was_split) {
            work.push_back(std::move(a));
            work.push_back(std::move(b));
            ++report.recovered_edges;
        } else {
            loops.push_back(std::move(l));
        }
    }
    return loops;
}

/// 2. Merge q-vertices sharing local UVs within a face (Algorithm 7): the smallest in canonical
///    order (qvertex_less) represents.
void merge_clones(const QState& q, const std::vector<Loop>& loops, UnionFind& sets, Report& report) {
    for (const Loop& l : loops)
        for (std::size_t i = 0; i < l.size(); ++i)
            for (std::size_t j = i + 1; j < l.size(); ++j)
                if (l[i].uv == l[j].uv && l[i].v != l[j].v) {
                    int a = sets.find(l[i].v), b = sets.find(l[j].v);
                    if (a != b) {
                        if (qvertex_less(q, b, a)) std::swap(a, b);
                        sets.attach(b, a);
                        ++report.merged_qvertices;
                    }
                }
}

/// The explanation of a face that collapsed to the 1- or 2-gon p.
void explain_collapsed(const TriMesh& m, const QState& q, const Loop& p, Report& report) {
    const QVertex& v = q.qvertices[p[0].v];
    report.explanations.push_back({DefectKind::FaceCollapsed,
                                   "a face collapsed to a " + std::to_string(p.size()) + "-gon at grid point (" +
                                       std::to_string(v.grid[0]) + ", " + std::to_string(v.grid[1]) +
                                       ") of input triangle " + std::to_string(m.input_triangle[v.chart]),
                                   m.input_triangle[v.chart],
                                   -1,
                                   {v.grid[0], v.grid[1]},
                                   std::nullopt});
}

/// 3. Simplify faces, on the merged q-vertices; drops (and counts) those left with fewer than 3
///    corners. Releases `loops`.
std::vector<Loop> simplify_faces(const TriMesh& m, const QState& q, std::vector<Loop>& loops, UnionFind& sets,
                                 Report& report) {
    std::vector<Loop> simple;
    simple.reserve(loops.size());
    std::vector<Loop> parts;
    for (Loop& l : loops) {
        for (Corner& c : l) c.v = sets.find(c.v);
        parts.clear();
        simplify(q, std::move(l), parts);
        for (Loop& p : parts) {
            if (p.size() < 3) {
                ++report.collapsed_faces;
                if (!p.empty()) explain_collapsed(m, q, p, report);
                continue;
            }
            simple.push_back(std::move(p));
        }
    }
    std::vector<Loop>().swap(loops);
    return simple;
}

/// The faces' vertex cycles, each rotated to start at its smallest vertex, in one arena: key i is
/// cycle[first[i] .. first[i+1]), ordered by length, then lexicographically.
class CycleKeys {
public:
    explicit CycleKeys(const std::vector<Loop>& faces) {
        cycle_.reserve(4 * faces.size());
        first_.reserve(faces.size() + 1);
        for (const Loop& l : faces) {
            std::size_t m0 = 0;
            for (std::size_t k = 1; k < l.size(); ++k)
                if (l[k].v < l[m0].v) m0 = k;
            for (std::size_t k = 0; k < l.size(); ++k) cycle_.push_back(l[(m0 + k) % l.size()].v);
            first_.push_back(cycle_.size());
        }
    }
    const int* key(std::size_t i) const { return cycle_.data() + first_[i]; }
    std::size_t size(std::size_t i) const { return first_[i + 1] - first_[i]; }
    static bool less(const int* a, std::size_t na, const int* b, std::size_t nb) {
        if (na != nb) return na < nb;
        return std::lexicographical_compare(a, a + na, b, b + nb);
    }
    /// The faces' indices sorted by key, equal keys by index.
    std::vector<std::size_t> sorted() const {
        std::vector<std::size_t> order(first_.size() - 1);
        std::iota(order.begin(), order.end(), std::size_t{0});
        std::sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) {
            if (less(key(x), size(x), key(y), size(y))) return true;
            if (less(key(y), size(y), key(x), size(x))) return false;
            return x < y;
        });
        return order;
    }

private:
    std::vector<int> cycle_;
    std::vector<std::size_t> first_{0};
};

/// Removes the faces marked in `drop`, keeping the others' order.
void erase_dropped(std::vector<Loop>& simple, const std::vector<char>& drop) {
    std::vector<Loop> kept;
    kept.reserve(simple.size());
    for (std::size_t i = 0; i < simple.size(); ++i)
        if (!drop[i]) kept.push_back(std::move(simple[i]));
    simple.swap(kept);
}

/// The explanation of a face and its reverse cancelled, near the first corner of `face`.
void explain_ghosts(const TriMesh& m, const QState& q, const Loop& face, Report& report) {
    const QVertex& v = q.qvertices[face[0].v];
    report.explanations.push_back({DefectKind::GhostFacesCancelled,
                                   "a face and its reverse cancelled near grid point (" + std::to_string(v.grid[0]) +
                                       ", " + std::to_string(v.grid[1]) + ") of input triangle " +
                                       std::to_string(m.input_triangle[v.chart]),
                                   m.input_triangle[v.chart],
                                   -1,
                                   {v.grid[0], v.grid[1]},
                                   std::nullopt});
}

/// 4. Cancel ghost faces (Figure 2 (c)): a face and its reverse cover the same quad once
///    positively and once through a fold-over; together they cover nothing. Faces are keyed
///    by their vertex cycle rotated to the smallest vertex; one sort pairs keys with reverses.
void cancel_ghost_faces(const TriMesh& m, const QState& q, std::vector<Loop>& simple, Report& report) {
    const CycleKeys keys(simple);
    const std::vector<std::size_t> order = keys.sorted();
    std::vector<char> drop(simple.size(), 0);
    std::vector<int> rev;
    // A face's reverse has its length and starts at its smallest vertex: it lies in the face's
    // group, the run of `order` whose keys share both, and is found there by binary search (a
    // group can be large: many faces of one length at a vertex of high valence).
    std::size_t group_begin = 0, group_end = 0;
    for (std::size_t at = 0; at < order.size(); ++at) {
        const std::size_t i = order[at];
        const int* key = keys.key(i);
        const std::size_t n = keys.size(i);
        if (at == group_end) {
            group_begin = at;
            for (group_end = at + 1; group_end < order.size(); ++group_end) {
                const std::size_t x = order[group_end];
                if (keys.size(x) != n || keys.key(x)[0] != key[0]) break;
            }
        }
        if (drop[i]) continue;
        // The reverse cycle, rotated to start at the same (smallest) vertex.
        rev.assign(1, key[0]);
        for (std::size_t j = n - 1; j >= 1; --j) rev.push_back(key[j]);
        if (std::equal(rev.begin(), rev.end(), key)) continue;
        // The first face of the group (in key order) whose key is `rev` and that is not dropped.
        const auto group_first = order.begin() + static_cast<std::ptrdiff_t>(group_begin);
        const auto group_last = order.begin() + static_cast<std::ptrdiff_t>(group_end);
        auto it = std::lower_bound(group_first, group_last, rev, [&](std::size_t x, const std::vector<int>& r) {
            return CycleKeys::less(keys.key(x), n, r.data(), n);
        });
        std::size_t match = order.size();
        for (; it != group_last && std::equal(rev.begin(), rev.end(), keys.key(*it)); ++it)
            if (!drop[*it]) {
                match = *it;
                break;
            }
        if (match == order.size()) continue;
        drop[i] = drop[match] = 1;
        report.ghost_faces_cancelled += 2;
        explain_ghosts(m, q, simple[i], report);
    }
    erase_dropped(simple, drop);
}

/// The explanation of a clockwise face and a near-reverse cancelled, their odd corners merged.
void explain_near_ghosts(const TriMesh& m, const QState& q, const Loop& face, Report& report) {
    const QVertex& v = q.qvertices[face[0].v];
    report.explanations.push_back({DefectKind::GhostFacesCancelled,
                                   "a face walked clockwise over a fold-over and a face with its other three corners "
                                   "in reverse order cancelled near grid point (" +
                                       std::to_string(v.grid[0]) + ", " + std::to_string(v.grid[1]) +
                                       ") of input triangle " + std::to_string(m.input_triangle[v.chart]) +
                                       "; their fourth corners, clones of one grid point on two sheets, merged",
                                   m.input_triangle[v.chart],
                                   -1,
                                   {v.grid[0], v.grid[1]},
                                   std::nullopt});
}

/// 5. Cancel near-ghost pairs. A quad whose local UVs run clockwise was walked over a
///    fold-over's reversed sheet. When another quad has its corners in reverse order but one,
///    the two cover one cell once each way, as a ghost pair does; their odd corners are clones
///    of one grid point that no walk met together (they lie on two sheets). The clones are
///    merged and both faces cancelled, unless the clones share a face (the merge would leave a
///    corner twice in it). The partner runs counter-clockwise (two clockwise faces with three
///    corners in common are mirror images across an edge, their fourth corners two grid
///    points). A clockwise face may have two partners, and two clockwise faces one: the face
///    with the fewest partners left is matched first, so that none is left without one where
///    the matching allows. Ties go by the faces' corners in canonical order (qvertex_less, by
///    position), so the input's order does not matter.
void cancel_near_ghosts(const TriMesh& m, const QState& q, std::vector<Loop>& simple, UnionFind& sets, Report& report) {
    std::vector<std::size_t> clockwise;
    for (std::size_t i = 0; i < simple.size(); ++i)
        if (simple[i].size() == 4 && twice_area(simple[i]) < 0) clockwise.push_back(i);
    if (clockwise.empty()) return;
    std::vector<std::vector<std::size_t>> at(q.qvertices.size()); // the faces at each vertex
    for (std::size_t i = 0; i < simple.size(); ++i)
        for (const Corner& c : simple[i]) at[static_cast<std::size_t>(c.v)].push_back(i);
    // A face's corners from its canonically smallest, compared corner by corner (qvertex_less).
    const auto face_less = [&](std::size_t x, std::size_t y) {
        const Loop &fx = simple[x], &fy = simple[y];
        if (fx.size() != fy.size()) return fx.size() < fy.size();
        const auto start = [&](const Loop& l) {
            std::size_t s0 = 0;
            for (std::size_t k = 1; k < l.size(); ++k)
                if (qvertex_less(q, l[k].v, l[s0].v)) s0 = k;
            return s0;
        };
        const std::size_t sx = start(fx), sy = start(fy);
        for (std::size_t k = 0; k < fx.size(); ++k) {
            const int u = fx[(sx + k) % fx.size()].v, w = fy[(sy + k) % fy.size()].v;
            if (u != w) return qvertex_less(q, u, w);
        }
        return false;
    };
    std::sort(clockwise.begin(), clockwise.end(), face_less);
    std::vector<char> drop(simple.size(), 0);
    const auto holds = [&](std::size_t f, int v) {
        return std::any_of(simple[f].begin(), simple[f].end(), [v](const Corner& c) { return c.v == v; });
    };
    struct Partner {
        std::size_t face;
        int odd_a, odd_b; // the odd corners of the clockwise face and of the partner
    };
    // The partners of clockwise face a: each shares three corners, so one of a's first two.
    const auto partners = [&](std::size_t a, std::vector<Partner>& out) {
        out.clear();
        const Loop& fa = simple[a];
        for (int k0 = 0; k0 < 2; ++k0)
            for (const std::size_t b : at[static_cast<std::size_t>(fa[static_cast<std::size_t>(k0)].v)]) {
                // The partner runs counter-clockwise: two clockwise faces with three corners in
                // common are mirror images across an edge, their fourth corners two grid points.
                if (b == a || drop[b] || simple[b].size() != 4 || twice_area(simple[b]) <= 0) continue;
                if (std::any_of(out.begin(), out.end(), [b](const Partner& p) { return p.face == b; })) continue;
                const Loop& fb = simple[b];
                for (std::size_t s = 0; s < 4; ++s) {
                    int mismatches = 0, x = -1, y = -1;
                    for (std::size_t k = 0; k < 4; ++k) {
                        const int rb = fb[(s + 4 - k) % 4].v; // fb reversed, from corner s
                        if (rb != fa[k].v) ++mismatches, x = fa[k].v, y = rb;
                    }
                    if (mismatches != 1) continue;
                    bool apart = true;
                    for (const std::size_t f : at[static_cast<std::size_t>(x)])
                        apart = apart && (f == a || drop[f] || !holds(f, y));
                    if (apart) out.push_back({b, x, y});
                    break;
                }
            }
    };
    // Fewest partners first costs a pass over the clockwise faces per match: beyond this many,
    // they are taken in canonical order only.
    constexpr std::size_t kMatchedByCount = 256;
    const bool by_count = clockwise.size() <= kMatchedByCount;
    std::vector<Partner> options, best_options;
    for (std::size_t next = 0;;) {
        std::size_t a = simple.size();
        if (by_count) {
            std::size_t fewest = SIZE_MAX;
            for (const std::size_t c : clockwise) {
                if (drop[c]) continue;
                partners(c, options);
                if (!options.empty() && options.size() < fewest) fewest = options.size(), a = c, best_options = options;
            }
        } else {
            for (; next < clockwise.size() && a == simple.size(); ++next) {
                if (drop[clockwise[next]]) continue;
                partners(clockwise[next], best_options);
                if (!best_options.empty()) a = clockwise[next];
            }
        }
        if (a == simple.size()) break;
        const Partner p =
            *std::min_element(best_options.begin(), best_options.end(),
                              [&](const Partner& x, const Partner& y) { return face_less(x.face, y.face); });
        int keep = p.odd_a, gone = p.odd_b;
        if (qvertex_less(q, gone, keep)) std::swap(keep, gone);
        sets.attach(gone, keep);
        ++report.merged_qvertices;
        for (const std::size_t f : at[static_cast<std::size_t>(gone)]) {
            for (Corner& c : simple[f])
                if (c.v == gone) c.v = keep;
            at[static_cast<std::size_t>(keep)].push_back(f);
        }
        drop[a] = drop[p.face] = 1;
        report.ghost_faces_cancelled += 2;
        report.near_ghost_faces_cancelled += 2;
        explain_near_ghosts(m, q, simple[a], report);
    }
    erase_dropped(simple, drop);
}

/// Per class of merged clones (indexed by its representative): the clone the output vertex takes
/// (`chosen`) and the class's size (`count`). Every clone is an image of the same grid point; the
/// output takes one clone's position and provenance, so the vertex lies on the input surface
/// exactly where its provenance says: a clone on an input vertex first (a singularity stays on
/// its vertex, not on a fold-over next to it), then on an edge, then inside a triangle; among
/// equals the first in 3D order, whatever the input order.
void choose_clones(const QState& q, UnionFind& sets, std::vector<int>& chosen, std::vector<int>& count) {
    const int nq = static_cast<int>(q.qvertices.size());
    std::vector<std::pair<int, int>> by_rep(nq);
    for (int i = 0; i < nq; ++i) by_rep[i] = {sets.find(i), i};
    std::sort(by_rep.begin(), by_rep.end(), [&](const auto& a, const auto& b) {
        if (a.first != b.first) return a.first < b.first;
        const QVertex &x = q.qvertices[a.second], &y = q.qvertices[b.second];
        if (x.kind != y.kind) return x.kind < y.kind;
        return x.position < y.position;
    });
    chosen.assign(nq, -1);
    count.assign(nq, 0);
    for (const auto& [r, i] : by_rep) {
        if (chosen[r] < 0) chosen[r] = i;
        ++count[r];
    }
}

/// The provenance of an output vertex at q-vertex v, standing for `merged` clones.
Provenance provenance_of(const TriMesh& m, const QVertex& v, int merged) {
    Provenance pr;
    pr.kind = v.kind;
    pr.chart_triangle = m.input_triangle[v.chart];
    pr.grid = {v.grid[0], v.grid[1]};
    pr.merged = merged;
    pr.barycentric = v.barycentric;
    if (v.kind == QVertexKind::Vertex) {
        pr.element = m.input_vertex[v.element];
        // The chart: its fan's first triangle in 3D order (triangle_less), not the fan's start in
        // the input's order; the grid point carried there through the fan's transitions.
        const int vx = v.element;
        int best = m.fan_start[vx];
        GridAutomorphism to_h, to_best;
        for (int h = m.fan_start[vx], n = 0; h >= 0 && n < m.fan_size[vx]; ++n) {
            if (triangle_less(m, TriMesh::face(h), TriMesh::face(best))) best = h, to_best = to_h;
            const int next = m.cw(h);
            if (next < 0) break;
            to_h = m.map.transition[h].after(to_h);
            h = next;
        }
        if (best != m.fan_start[vx]) {
            const IPoint g = to_best(v.grid);
            pr.chart_triangle = m.input_triangle[TriMesh::face(best)];
            pr.grid = {g[0], g[1]};
            pr.barycentric = {0.0, 0.0, 0.0};
            pr.barycentric[static_cast<std::size_t>(best % 3)] = 1.0;
        }
    } else if (v.kind == QVertexKind::Edge) {
        pr.element = m.input_triangle[TriMesh::face(v.element)];
        pr.local_edge = v.element % 3;
    } else {
        pr.element = m.input_triangle[v.element];
    }
    return pr;
}

/// Reports output face number `face` (from walk l) as a polygon of `corners` corners, not a quad.
void report_non_quad(const TriMesh& m, const QState& q, const Loop& l, std::size_t corners, std::size_t face,
                     Report& report) {
    ++report.non_quad_faces;
    const QVertex& v = q.qvertices[l[0].v];
    report.defects.push_back({DefectKind::NonQuadFace,
                              std::to_string(corners) + "-gon near grid point (" + std::to_string(v.grid[0]) + ", " +
                                  std::to_string(v.grid[1]) + ") of input triangle " +
                                  std::to_string(m.input_triangle[v.chart]),
                              m.input_triangle[v.chart],
                              static_cast<std::int64_t>(face),
                              {v.grid[0], v.grid[1]},
                              std::nullopt});
}

/// 5. Output: one vertex per class of merged clones (choose_clones), numbered in the order the
///    faces first use them; the faces with their local UVs, flat (merge_vertices).
FaceWalks write_output(const TriMesh& m, const QState& q, const std::vector<Loop>& simple, UnionFind& sets,
                       QuadMesh& out, Report& report) {
    const int nq = static_cast<int>(q.qvertices.size());
    std::vector<int> chosen, count;
    choose_clones(q, sets, chosen, count);
    std::vector<int> out_id(nq, -1);
    out = QuadMesh{};
    // Reserved at a bound (a vertex per q-vertex): capacity left untouched costs no memory, where
    // growing by doubling touched up to twice the mesh's size.
    out.positions.reserve(static_cast<std::size_t>(nq));
    out.provenance.reserve(static_cast<std::size_t>(nq));
    FaceWalks faces;
    std::size_t corners = 0;
    for (const Loop& l : simple) corners += l.size();
    faces.first.reserve(simple.size() + 1);
    faces.qv.reserve(corners);
    faces.uv.reserve(corners);
    for (const Loop& l : simple) {
        for (const Corner& c : l) {
            if (out_id[c.v] < 0) {
                out_id[c.v] = static_cast<int>(out.positions.size());
                const QVertex& v = q.qvertices[chosen[c.v] >= 0 ? chosen[c.v] : c.v];
                out.positions.push_back(v.position);
                out.provenance.push_back(provenance_of(m, v, count[c.v]));
            }
            faces.qv.push_back(out_id[c.v]);
            faces.uv.push_back(c.uv);
        }
        if (l.size() != 4) report_non_quad(m, q, l, l.size(), faces.size(), report);
        faces.first.push_back(faces.qv.size());
    }
    return faces;
}

} // namespace

FaceWalks merge_vertices(const TriMesh& m, const QState& q, FaceWalks faces, const Options& opt, QuadMesh& out,
                         Report& report) {
    std::vector<Loop> loops = recover_lost_edges(m, q, faces, opt, report);
    UnionFind sets(q.qvertices.size());
    if (opt.merge_vertices) merge_clones(q, loops, sets, report);
    std::vector<Loop> simple = simplify_faces(m, q, loops, sets, report);
    cancel_ghost_faces(m, q, simple, report);
    if (opt.merge_vertices) cancel_near_ghosts(m, q, simple, sets, report);
    return write_output(m, q, simple, sets, out, report);
}

} // namespace qex::detail

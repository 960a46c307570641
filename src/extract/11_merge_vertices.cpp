// Recovery of lost q-edges (Section 5.5), vertex merging (Algorithm 7) and face simplification.
// Fold-overs make the face walks visit clones of one q-vertex; within a face the clones share
// local UVs. Merging them leaves quads plus 2-gons and 1-gons (collapsed), and, where a singularity
// lost ports, faces that pass a vertex twice: those are split at it. Ghost and near-ghost faces
// are cancelled in between (11_cancel_ghosts.cpp).
#include "merge_loops.h"

#include <algorithm>
#include <string>

namespace qex::detail {
namespace {

using merging::Corner;
using merging::Loop;
using merging::twice_area;

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
    merging::cancel_ghost_faces(m, q, simple, report);
    if (opt.merge_vertices) merging::cancel_near_ghosts(m, q, simple, sets, report);
    return write_output(m, q, simple, sets, out, report);
}

} // namespace qex::detail

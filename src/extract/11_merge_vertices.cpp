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


/// Splits a closed walk at positions i < j into walk[i..j] and walk[j..end] + walk[0..i].
void split(const Loop& loop, std::size_t i, std::size_t j, Loop& first, Loop& second) {
    first.assign(loop.begin() + static_cast<std::ptrdiff_t>(i), loop.begin() + static_cast<std::ptrdiff_t>(j) + 1);
    second.assign(loop.begin() + static_cast<std::ptrdiff_t>(j), loop.end());
    second.insert(second.end(), loop.begin(), loop.begin() + static_cast<std::ptrdiff_t>(i) + 1);
}

/// Removes repeated consecutive vertices and spikes (x y x); splits walks visiting a vertex twice.
void simplify(Loop loop, std::vector<Loop>& out) {
    // Most faces visit distinct vertices and are kept as they are.
    bool distinct = true;
    for (std::size_t i = 0; i < loop.size() && distinct; ++i)
        for (std::size_t j = i + 1; j < loop.size() && distinct; ++j) distinct = loop[i].v != loop[j].v;
    if (distinct) {
        out.push_back(std::move(loop));
        return;
    }
    std::vector<Loop> work{std::move(loop)};
    while (!work.empty()) {
        Loop l = std::move(work.back());
        work.pop_back();
        bool changed = true;
        while (changed && l.size() > 1) {
            changed = false;
            for (std::size_t i = 0; i < l.size() && l.size() > 1; ++i) {
                const std::size_t n = l.size(), j = (i + 1) % n;
                if (l[i].v == l[j].v) { l.erase(l.begin() + static_cast<std::ptrdiff_t>(j)); changed = true; break; }
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
        bool was_split = false;
        for (std::size_t i = 0; i < l.size() && !was_split; ++i)
            for (std::size_t j = i + 1; j < l.size() && !was_split; ++j)
                if (l[i].v == l[j].v) {
                    Loop a, b;
                    split(l, i, j, a, b);
                    a.pop_back(); // the closing copy of the shared vertex
                    b.pop_back();
                    work.push_back(std::move(a));
                    work.push_back(std::move(b));
                    was_split = true;
                }
        if (!was_split) out.push_back(std::move(l));
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

} // namespace

void merge_vertices(const TriMesh& m, const QState& q, FaceWalks faces, const Options& opt,
                        QuadMesh& out, Report& report) {
    const int nq = static_cast<int>(q.qvertices.size());
    // Expected valence of each q-vertex, to find those that lost ports (Section 5.5).
    auto missing_ports = [&](int i) {
        const QVertex& v = q.qvertices[i];
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
    };

    // 1. Recover lost q-edges. A face walk whose local UVs wind around more than one unit square
    //    enclosed a singularity that lost ports (Figure 5 (a)); it is split between two corners
    //    with equal local UVs so that every part covers at least one square. Following the paper,
    //    a q-vertex with missing ports is the preferred end of the new q-edge.
    std::vector<Loop> loops;
    {
        std::vector<Loop> work;
        work.reserve(faces.size());
        for (std::size_t f = 0; f < faces.size(); ++f) {
            Loop l(faces.first[f + 1] - faces.first[f]);
            for (std::size_t i = 0; i < l.size(); ++i) l[i] = {faces.qv[faces.first[f] + i], faces.uv[faces.first[f] + i]};
            work.push_back(std::move(l));
        }
        faces = FaceWalks{}; // copied: released now, not at the end
        Loop a, b;
        while (!work.empty()) {
            Loop l = std::move(work.back());
            work.pop_back();
            bool was_split = false;
            if (opt.recover_lost_edges && l.size() > 4 && twice_area(l) >= 4)
                for (int pass = 0; pass < 2 && !was_split; ++pass)
                    for (std::size_t i = 0; i < l.size() && !was_split; ++i) {
                        if (pass == 0 && !missing_ports(l[i].v)) continue;
                        for (std::size_t j = 0; j < l.size() && !was_split; ++j) {
                            const std::size_t n = l.size();
                            if (j == i || j == (i + 1) % n || i == (j + 1) % n || !(l[j].uv == l[i].uv)) continue;
                            // Both parts keep both ends: the ends share local UVs and merge below.
                            split(l, std::min(i, j), std::max(i, j), a, b);
                            if (twice_area(a) < 2 || twice_area(b) < 2) continue;
                            work.push_back(std::move(a));
                            work.push_back(std::move(b));
                            ++report.recovered_edges;
                            was_split = true;
                        }
                    }
            if (!was_split) loops.push_back(std::move(l));
        }
    }

    // 2. Merge q-vertices sharing local UVs within a face (Algorithm 7).
    UnionFind sets(static_cast<std::size_t>(nq));
    if (opt.merge_vertices)
        for (const Loop& l : loops)
            for (std::size_t i = 0; i < l.size(); ++i)
                for (std::size_t j = i + 1; j < l.size(); ++j)
                    if (l[i].uv == l[j].uv && l[i].v != l[j].v) {
                        const int a = sets.find(l[i].v), b = sets.find(l[j].v);
                        if (a != b) { sets.attach(std::max(a, b), std::min(a, b)); ++report.merged_qvertices; }
                    }

    // 3. Simplify faces.
    std::vector<Loop> simple;
    simple.reserve(loops.size());
    std::vector<Loop> parts;
    for (Loop& l : loops) {
        for (Corner& c : l) c.v = sets.find(c.v);
        parts.clear();
        simplify(std::move(l), parts);
        for (Loop& p : parts) {
            if (p.size() < 3) {
                ++report.collapsed_faces;
                if (!p.empty()) {
                    const QVertex& v = q.qvertices[p[0].v];
                    report.explanations.push_back({DefectKind::FaceCollapsed,
                                                   "a face collapsed to a " + std::to_string(p.size()) +
                                                       "-gon at grid point (" + std::to_string(v.grid[0]) + ", " +
                                                       std::to_string(v.grid[1]) + ") of input triangle " +
                                                       std::to_string(m.input_triangle[v.chart]),
                                                   m.input_triangle[v.chart], -1, {v.grid[0], v.grid[1]}, std::nullopt});
                }
                continue;
            }
            simple.push_back(std::move(p));
        }
    }
    std::vector<Loop>().swap(loops);

    // 4. Cancel ghost faces (Figure 2 (c)): a face and its reverse cover the same quad once
    //    positively and once through a fold-over; together they cover nothing. Faces are keyed
    //    by their vertex cycle rotated to the smallest vertex; one sort pairs keys with reverses.
    {
        // Keys in one arena: key i is cycle[first[i] .. first[i+1]), ordered by length, then
        // lexicographically.
        std::vector<int> cycle;
        std::vector<std::size_t> first{0};
        cycle.reserve(4 * simple.size());
        first.reserve(simple.size() + 1);
        for (const Loop& l : simple) {
            std::size_t m0 = 0;
            for (std::size_t k = 1; k < l.size(); ++k)
                if (l[k].v < l[m0].v) m0 = k;
            for (std::size_t k = 0; k < l.size(); ++k) cycle.push_back(l[(m0 + k) % l.size()].v);
            first.push_back(cycle.size());
        }
        auto key_less = [&](const int* a, std::size_t na, const int* b, std::size_t nb) {
            if (na != nb) return na < nb;
            return std::lexicographical_compare(a, a + na, b, b + nb);
        };
        auto key_of = [&](std::size_t i) { return cycle.data() + first[i]; };
        auto size_of = [&](std::size_t i) { return first[i + 1] - first[i]; };
        std::vector<std::size_t> order(simple.size());
        std::iota(order.begin(), order.end(), std::size_t{0});
        std::sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) {
            if (key_less(key_of(x), size_of(x), key_of(y), size_of(y))) return true;
            if (key_less(key_of(y), size_of(y), key_of(x), size_of(x))) return false;
            return x < y;
        });
        std::vector<char> drop(simple.size(), 0);
        std::vector<int> rev;
        for (std::size_t k = 0; k < order.size(); ++k) {
            const std::size_t i = order[k];
            if (drop[i]) continue;
            // The reverse cycle, rotated to start at the same (smallest) vertex.
            const int* key = key_of(i);
            const std::size_t n = size_of(i);
            rev.assign(1, key[0]);
            for (std::size_t j = n - 1; j >= 1; --j) rev.push_back(key[j]);
            if (std::equal(rev.begin(), rev.end(), key)) continue;
            // The first reverse not yet paired.
            auto it = std::lower_bound(order.begin(), order.end(), std::size_t{0}, [&](std::size_t x, std::size_t) {
                return key_less(key_of(x), size_of(x), rev.data(), rev.size());
            });
            auto is_rev = [&](std::size_t x) { return size_of(x) == n && std::equal(rev.begin(), rev.end(), key_of(x)); };
            while (it != order.end() && is_rev(*it) && drop[*it]) ++it;
            if (it == order.end() || !is_rev(*it)) continue;
            drop[i] = drop[*it] = 1;
            report.ghost_faces_cancelled += 2;
            const QVertex& v = q.qvertices[simple[i][0].v];
            report.explanations.push_back({DefectKind::GhostFacesCancelled,
                                           "a face and its reverse cancelled near grid point (" +
                                               std::to_string(v.grid[0]) + ", " + std::to_string(v.grid[1]) +
                                               ") of input triangle " + std::to_string(m.input_triangle[v.chart]),
                                           m.input_triangle[v.chart], -1, {v.grid[0], v.grid[1]}, std::nullopt});
        }
        std::vector<Loop> kept;
        kept.reserve(simple.size());
        for (std::size_t i = 0; i < simple.size(); ++i)
            if (!drop[i]) kept.push_back(std::move(simple[i]));
        simple.swap(kept);
    }

    // 5. Output: one vertex per class of merged clones. Every clone is an image of the same grid
    // point; the output takes one clone's position and provenance, so the vertex lies on the
    // input surface exactly where its provenance says: a clone on an input vertex first (a
    // singularity stays on its vertex, not on a fold-over next to it), then on an edge, then
    // inside a triangle; among equals the first in 3D order, whatever the input order.
    std::vector<std::pair<int, int>> by_rep(nq);
    for (int i = 0; i < nq; ++i) by_rep[i] = {sets.find(i), i};
    std::sort(by_rep.begin(), by_rep.end(), [&](const auto& a, const auto& b) {
        if (a.first != b.first) return a.first < b.first;
        const QVertex &x = q.qvertices[a.second], &y = q.qvertices[b.second];
        if (x.kind != y.kind) return x.kind < y.kind;
        return x.position < y.position;
    });
    std::vector<int> chosen(nq, -1), count(nq, 0);
    for (const auto& [r, i] : by_rep) {
        if (chosen[r] < 0) chosen[r] = i;
        ++count[r];
    }
    std::vector<int> out_id(nq, -1);
    out = QuadMesh{};
    for (const Loop& l : simple) {
        std::vector<int> face;
        std::vector<std::array<std::int64_t, 2>> uvs;
        face.reserve(l.size());
        uvs.reserve(l.size());
        for (const Corner& c : l) {
            if (out_id[c.v] < 0) {
                out_id[c.v] = static_cast<int>(out.positions.size());
                const QVertex& v = q.qvertices[chosen[c.v] >= 0 ? chosen[c.v] : c.v];
                out.positions.push_back(v.position);
                Provenance pr;
                pr.kind = v.kind;
                pr.chart_triangle = m.input_triangle[v.chart];
                pr.grid = {v.grid[0], v.grid[1]};
                pr.merged = count[c.v];
                pr.barycentric = v.barycentric;
                if (v.kind == QVertexKind::Vertex) {
                    pr.element = m.input_vertex[v.element];
                } else if (v.kind == QVertexKind::Edge) {
                    pr.element = m.input_triangle[TriMesh::face(v.element)];
                    pr.local_edge = v.element % 3;
                } else {
                    pr.element = m.input_triangle[v.element];
                }
                out.provenance.push_back(pr);
            }
            face.push_back(out_id[c.v]);
            uvs.push_back({c.uv[0], c.uv[1]});
        }
        if (face.size() != 4) {
            ++report.non_quad_faces;
            const QVertex& v = q.qvertices[l[0].v];
            report.defects.push_back({DefectKind::NonQuadFace,
                                      std::to_string(face.size()) + "-gon near grid point (" +
                                          std::to_string(v.grid[0]) + ", " + std::to_string(v.grid[1]) +
                                          ") of input triangle " + std::to_string(m.input_triangle[v.chart]),
                                      m.input_triangle[v.chart], static_cast<std::int64_t>(out.faces.size()),
                                      {v.grid[0], v.grid[1]}, std::nullopt});
        }
        out.faces.push_back(std::move(face));
        out.face_uvs.push_back(std::move(uvs));
    }
}

} // namespace qex::detail

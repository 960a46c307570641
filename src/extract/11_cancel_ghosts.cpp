// Ghost faces (Figure 2 (c)) and near-ghost faces of merge_vertices (stage 12), cancelled after
// simplification: a face and its reverse cover one quad once each way, through a fold-over, and
// together cover nothing; a clockwise quad and a quad with three of its corners in reverse order
// do the same, once their odd corners (clones of one grid point on two sheets) are merged.
#include "merge_loops.h"

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <string>

namespace qex::detail::merging {
namespace {

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

/// A clockwise quad's partner: a counter-clockwise quad with the clockwise one's corners in
/// reverse order but one.
struct Partner {
    std::size_t face;
    int odd_a, odd_b; // the odd corners of the clockwise face and of the partner
};

/// The faces as the near-ghost matching sees them: the faces at each vertex, the faces dropped
/// so far, and the canonical order of faces.
class NearGhosts {
public:
    NearGhosts(const QState& q, std::vector<Loop>& simple)
        : q_(q), simple_(simple), at_(q.qvertices.size()), drop_(simple.size(), 0) {
        for (std::size_t i = 0; i < simple.size(); ++i)
            for (const Corner& c : simple[i]) at_[static_cast<std::size_t>(c.v)].push_back(i);
    }

    /// A face's corners from its canonically smallest, compared corner by corner (qvertex_less).
    bool face_less(std::size_t x, std::size_t y) const {
        const Loop &fx = simple_[x], &fy = simple_[y];
        if (fx.size() != fy.size()) return fx.size() < fy.size();
        const auto start = [&](const Loop& l) {
            std::size_t s0 = 0;
            for (std::size_t k = 1; k < l.size(); ++k)
                if (qvertex_less(q_, l[k].v, l[s0].v)) s0 = k;
            return s0;
        };
        const std::size_t sx = start(fx), sy = start(fy);
        for (std::size_t k = 0; k < fx.size(); ++k) {
            const int u = fx[(sx + k) % fx.size()].v, w = fy[(sy + k) % fy.size()].v;
            if (u != w) return qvertex_less(q_, u, w);
        }
        return false;
    }

    /// The partners of clockwise face a: each shares three corners, so one of a's first two.
    void partners(std::size_t a, std::vector<Partner>& out) const {
        out.clear();
        const Loop& fa = simple_[a];
        for (int k0 = 0; k0 < 2; ++k0)
            for (const std::size_t b : at_[static_cast<std::size_t>(fa[static_cast<std::size_t>(k0)].v)]) {
                // The partner runs counter-clockwise: two clockwise faces with three corners in
                // common are mirror images across an edge, their fourth corners two grid points.
                if (b == a || drop_[b] || simple_[b].size() != 4 || twice_area(simple_[b]) <= 0) continue;
                if (std::any_of(out.begin(), out.end(), [b](const Partner& p) { return p.face == b; })) continue;
                const Loop& fb = simple_[b];
                for (std::size_t s = 0; s < 4; ++s) {
                    int mismatches = 0, x = -1, y = -1;
                    for (std::size_t k = 0; k < 4; ++k) {
                        const int rb = fb[(s + 4 - k) % 4].v; // fb reversed, from corner s
                        if (rb != fa[k].v) ++mismatches, x = fa[k].v, y = rb;
                    }
                    if (mismatches != 1) continue;
                    bool apart = true;
                    for (const std::size_t f : at_[static_cast<std::size_t>(x)])
                        apart = apart && (f == a || drop_[f] || !holds(f, y));
                    if (apart) out.push_back({b, x, y});
                    break;
                }
            }
    }

    /// The clockwise face with the fewest partners left (the first in `clockwise` among equals),
    /// its partners in `best`; simple.size() if none has one. `options` is scratch.
    std::size_t fewest_partners(const std::vector<std::size_t>& clockwise, std::vector<Partner>& options,
                                std::vector<Partner>& best) const {
        std::size_t a = simple_.size();
        std::size_t fewest = SIZE_MAX;
        for (const std::size_t c : clockwise) {
            if (drop_[c]) continue;
            partners(c, options);
            if (!options.empty() && options.size() < fewest) fewest = options.size(), a = c, best = options;
        }
        return a;
    }

    /// The first clockwise face from `clockwise[next]` on with a partner left, its partners in
    /// `best`; `next` moves past it. simple.size() if none has one.
    std::size_t next_with_partners(const std::vector<std::size_t>& clockwise, std::size_t& next,
                                   std::vector<Partner>& best) const {
        std::size_t a = simple_.size();
        for (; next < clockwise.size() && a == simple_.size(); ++next) {
            if (drop_[clockwise[next]]) continue;
            partners(clockwise[next], best);
            if (!best.empty()) a = clockwise[next];
        }
        return a;
    }

    /// Merges the odd corners of clockwise face a and its partner p (the canonically smaller
    /// represents) and drops both faces.
    void cancel(std::size_t a, const Partner& p, UnionFind& sets, Report& report) {
        int keep = p.odd_a, gone = p.odd_b;
        if (qvertex_less(q_, gone, keep)) std::swap(keep, gone);
        sets.attach(gone, keep);
        ++report.merged_qvertices;
        for (const std::size_t f : at_[static_cast<std::size_t>(gone)]) {
            for (Corner& c : simple_[f])
                if (c.v == gone) c.v = keep;
            at_[static_cast<std::size_t>(keep)].push_back(f);
        }
        drop_[a] = drop_[p.face] = 1;
        report.ghost_faces_cancelled += 2;
        report.near_ghost_faces_cancelled += 2;
    }

    const std::vector<char>& dropped() const { return drop_; }

private:
    /// Whether face f has a corner at q-vertex v.
    bool holds(std::size_t f, int v) const {
        return std::any_of(simple_[f].begin(), simple_[f].end(), [v](const Corner& c) { return c.v == v; });
    }

    const QState& q_;
    std::vector<Loop>& simple_;
    std::vector<std::vector<std::size_t>> at_; ///< the faces at each vertex
    std::vector<char> drop_;
};

} // namespace

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
    NearGhosts g(q, simple);
    std::sort(clockwise.begin(), clockwise.end(), [&](std::size_t x, std::size_t y) { return g.face_less(x, y); });
    // Fewest partners first costs a pass over the clockwise faces per match: beyond this many,
    // they are taken in canonical order only.
    constexpr std::size_t kMatchedByCount = 256;
    const bool by_count = clockwise.size() <= kMatchedByCount;
    std::vector<Partner> options, best_options;
    for (std::size_t next = 0;;) {
        const std::size_t a = by_count ? g.fewest_partners(clockwise, options, best_options)
                                       : g.next_with_partners(clockwise, next, best_options);
        if (a == simple.size()) break;
        const Partner p =
            *std::min_element(best_options.begin(), best_options.end(),
                              [&](const Partner& x, const Partner& y) { return g.face_less(x.face, y.face); });
        g.cancel(a, p, sets, report);
        explain_near_ghosts(m, q, simple[a], report);
    }
    erase_dropped(simple, g.dropped());
}

} // namespace qex::detail::merging

// The patches and their shapes (patches.h).
#include "patches.h"

#include <algorithm>
#include <array>
#include <numeric>

namespace qex::layout {
namespace {

std::array<int, 4> face_key(const QuadTopology& t, int f) {
    std::array<int, 4> k{};
    for (int i = 0; i < 4; ++i) k[i] = t.rank[t.mesh->faces[f][i]];
    std::sort(k.begin(), k.end());
    return k;
}

/// One boundary loop of the patch: its half-edges in order (counter-clockwise round the patch)
/// and the patch's faces at the vertex each ends at (1: a corner, 2: a side, more: concave).
struct Loop {
    std::vector<int> halfedges, sector;
};

Loop walk_loop(const QuadTopology& t, const std::vector<char>& is_layout, int h0) {
    Loop loop;
    int h = h0;
    do {
        int o = QuadTopology::next(h), s = 1;
        while (!is_layout[o] && s <= t.faces) {
            o = QuadTopology::next(t.twin[o]);
            ++s;
        }
        loop.halfedges.push_back(h);
        loop.sector.push_back(s);
        h = o;
    } while (h != h0 && static_cast<int>(loop.halfedges.size()) <= 4 * t.faces);
    return loop;
}

/// A rectangle's corners (counter-clockwise from the first in the vertex order) and size.
bool rectangle_size(const QuadTopology& t, const Loop& loop, int faces, Patch& p) {
    std::vector<int> at; // loop positions of the corners
    for (std::size_t i = 0; i < loop.sector.size(); ++i)
        if (loop.sector[i] == 1) at.push_back(static_cast<int>(i));
    // The first corner in the vertex order (then by the next: a patch may have one vertex as two corners).
    const auto key = [&](int j) {
        return std::make_pair(t.rank[t.to(loop.halfedges[at[j]])], t.rank[t.to(loop.halfedges[at[(j + 1) % 4]])]);
    };
    int first = 0;
    for (int j = 1; j < 4; ++j)
        if (key(j) < key(first)) first = j;
    const int n = static_cast<int>(loop.halfedges.size());
    std::array<int, 4> side{};
    for (int j = 0; j < 4; ++j) {
        const int a = at[(first + j) % 4], b = at[(first + j + 1) % 4];
        p.corners[j] = t.to(loop.halfedges[a]);
        side[j] = ((b - a) % n + n) % n;
    }
    p.u = side[0];
    p.v = side[1];
    return side[0] == side[2] && side[1] == side[3] && static_cast<long long>(p.u) * p.v == faces;
}

/// A torus: the length of the grid line from its first vertex towards that vertex's first neighbour.
bool torus_size(const QuadTopology& t, const std::vector<int>& faces, Patch& p) {
    int x = t.mesh->faces[faces[0]][0];
    for (const int f : faces)
        for (const int v : t.mesh->faces[f])
            if (t.rank[v] < t.rank[x]) x = v;
    int o0 = t.fan[t.fan_begin[x]];
    for (int k = t.fan_begin[x]; k < t.fan_begin[x + 1]; ++k)
        if (t.rank[t.to(t.fan[k])] < t.rank[t.to(o0)]) o0 = t.fan[k];
    int o = o0, u = 0;
    do {
        ++u;
        o = t.straight(o);
    } while (o != o0 && o >= 0 && u <= 4 * t.faces);
    p.kind = PatchKind::Torus;
    p.u = u;
    p.v = u > 0 ? static_cast<int>(faces.size()) / u : 0;
    return o == o0 && static_cast<long long>(p.u) * p.v == static_cast<long long>(faces.size());
}

/// Whether a patch's boundary half-edge has the patch on its other side too.
bool glued_to_itself(const QuadTopology& t, const std::vector<int>& face_patch, const std::vector<int>& halfedges,
                     int p) {
    for (const int h : halfedges)
        if (t.twin[h] >= 0 && face_patch[t.twin[h] / 4] == p) return true;
    return false;
}

/// A rectangle glued to itself along a separatrix (its sides A and C one line): a cut from the
/// middle of a side that is not glued (B or D, 2 edges or longer) across to the other, parallel to
/// the glued sides, leaves A and C in two patches. The side whose middle vertex is first in the
/// vertex order; none if the free sides are 1 edge long.
std::vector<int> split_cut(const QuadTopology& t, const std::vector<int>& face_patch, const Loop& loop, int p) {
    std::vector<int> at;
    for (std::size_t i = 0; i < loop.sector.size(); ++i)
        if (loop.sector[i] == 1) at.push_back(static_cast<int>(i));
    const int n = static_cast<int>(loop.halfedges.size());
    int best = -1;
    for (int j = 0; j < 4; ++j) {
        const int len = ((at[(j + 1) % 4] - at[j]) % n + n) % n;
        std::vector<int> side;
        for (int i = 1; i <= len; ++i) side.push_back(loop.halfedges[(at[j] + i) % n]);
        if (len < 2 || glued_to_itself(t, face_patch, side, p)) continue;
        const int middle = side[len / 2 - 1]; // arrives at the side's middle vertex
        if (best < 0 || t.rank[t.to(middle)] < t.rank[t.to(best)]) best = middle;
    }
    if (best < 0) return {};
    return {QuadTopology::next(best)};
}

} // namespace

std::vector<std::vector<int>> number_patches(const QuadTopology& t, const std::vector<char>& is_layout,
                                             std::vector<int>& face_patch) {
    face_patch.assign(t.faces, -1);
    std::vector<std::vector<int>> comps;
    std::vector<int> stack;
    for (int f0 = 0; f0 < t.faces; ++f0) {
        if (face_patch[f0] >= 0) continue;
        const int id = static_cast<int>(comps.size());
        comps.emplace_back();
        face_patch[f0] = id;
        stack.push_back(f0);
        while (!stack.empty()) {
            const int f = stack.back();
            stack.pop_back();
            comps[id].push_back(f);
            for (int k = 0; k < 4; ++k) {
                const int h = 4 * f + k;
                if (is_layout[h] || t.twin[h] < 0 || face_patch[t.twin[h] / 4] >= 0) continue;
                face_patch[t.twin[h] / 4] = id;
                stack.push_back(t.twin[h] / 4);
            }
        }
    }
    std::vector<std::array<int, 4>> key(comps.size());
    for (std::size_t c = 0; c < comps.size(); ++c) {
        key[c] = face_key(t, comps[c][0]);
        for (const int f : comps[c]) key[c] = std::min(key[c], face_key(t, f));
    }
    std::vector<int> order(comps.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int b) { return key[a] < key[b]; });
    std::vector<std::vector<int>> out(comps.size());
    for (std::size_t i = 0; i < order.size(); ++i) {
        out[i] = std::move(comps[order[i]]);
        std::sort(out[i].begin(), out[i].end());
        for (const int f : out[i]) face_patch[f] = static_cast<int>(i);
    }
    return out;
}

PatchShape analyse_patch(const QuadTopology& t, const std::vector<char>& is_layout, const std::vector<int>& face_patch,
                         const std::vector<int>& faces, std::vector<int>& stamp) {
    PatchShape s;
    s.patch.faces = faces;
    const int p = face_patch[faces[0]];
    long long vertices = 0, twice_edges = 0;
    std::vector<int> starts; // its boundary half-edges
    for (const int f : faces)
        for (int k = 0; k < 4; ++k) {
            const int v = t.mesh->faces[f][k], h = 4 * f + k;
            if (stamp[v] != 2 * p && stamp[v] != 2 * p + 1) {
                stamp[v] = 2 * p;
                ++vertices;
            }
            const bool inside = t.twin[h] >= 0 && face_patch[t.twin[h] / 4] == p;
            twice_edges += inside && !is_layout[h] ? 1 : 2; // a separatrix inside: an edge each side
            if (is_layout[h]) starts.push_back(h);
        }
    std::vector<Loop> loops;
    std::vector<char> seen(starts.size(), 0);
    int corners = 0, concave = 0, pinched = 0; // pinched: a vertex the boundary passes more than once
    for (std::size_t i = 0; i < starts.size(); ++i) {
        if (seen[i]) continue;
        loops.push_back(walk_loop(t, is_layout, starts[i]));
        for (std::size_t j = 0; j < loops.back().halfedges.size(); ++j) {
            const int h = loops.back().halfedges[j];
            const auto at = std::lower_bound(starts.begin(), starts.end(), h);
            if (at != starts.end() && *at == h) seen[at - starts.begin()] = 1;
            corners += loops.back().sector[j] == 1;
            concave += loops.back().sector[j] > 2;
            const int v = t.to(h);
            pinched += stamp[v] == 2 * p + 1;
            stamp[v] = 2 * p + 1;
        }
    }
    // Of the patch as a surface: a vertex its boundary passes twice is two vertices of it.
    const long long euler = vertices + pinched - twice_edges / 2 + static_cast<long long>(faces.size());
    const std::string what = std::to_string(loops.size()) + " boundary loops, euler characteristic " +
                             std::to_string(euler) + ", " + std::to_string(corners) + " corners, " +
                             std::to_string(concave) + " concave corners, " + std::to_string(pinched) + " pinches";
    if (loops.size() == 1 && euler == 1 && corners == 4 && concave == 0) {
        s.ok = rectangle_size(t, loops[0], static_cast<int>(faces.size()), s.patch);
        if (!s.ok)
            s.problem = "a disk with 4 corners whose sides (" + std::to_string(s.patch.u) + " x " +
                        std::to_string(s.patch.v) + ") do not match its faces";
        if (s.ok && glued_to_itself(t, face_patch, loops[0].halfedges, p)) {
            s.ok = false;
            s.needs_cut = true;
            s.cuts = split_cut(t, face_patch, loops[0], p);
            s.problem = "a rectangle glued to itself along a separatrix" +
                        std::string(s.cuts.empty() ? " and one face wide across it" : "");
            s.needs_cut = !s.cuts.empty();
        }
    } else if (loops.empty() && euler == 0) {
        s.ok = torus_size(t, faces, s.patch);
        if (!s.ok) s.problem = "a torus whose grid lines do not close evenly";
    } else if (loops.size() == 2 && euler == 0 && corners == 0 && concave == 0) {
        s.needs_cut = true;
        std::size_t loop = 0, at = 0;
        for (std::size_t l = 0; l < loops.size(); ++l)
            for (std::size_t i = 0; i < loops[l].halfedges.size(); ++i)
                if (t.rank[t.to(loops[l].halfedges[i])] < t.rank[t.to(loops[loop].halfedges[at])]) {
                    loop = l;
                    at = i;
                }
        const std::vector<int>& hs = loops[loop].halfedges;
        s.cuts = {QuadTopology::next(hs[at]), QuadTopology::next(hs[(at + hs.size() / 2) % hs.size()])};
        s.problem = "an annulus without corners";
    } else {
        s.problem = "not a rectangle: " + what;
    }
    return s;
}

std::vector<PatchAdjacency> patch_adjacency(const QuadTopology& t, const std::vector<int>& face_patch) {
    std::vector<std::pair<int, int>> pairs;
    for (int h = 0; h < 4 * t.faces; ++h) {
        const int g = t.twin[h];
        if (g < h) continue;
        const int a = face_patch[h / 4], b = face_patch[g / 4];
        if (a != b) pairs.emplace_back(std::min(a, b), std::max(a, b));
    }
    std::sort(pairs.begin(), pairs.end());
    std::vector<PatchAdjacency> out;
    for (const auto& [a, b] : pairs) {
        if (out.empty() || out.back().a != a || out.back().b != b) out.push_back({a, b, 0});
        ++out.back().shared_edges;
    }
    return out;
}

} // namespace qex::layout

// Stage fill_holes (not in the paper): the last resort for a mesh that no rung at any scale made
// valid. Where a fold-over's singularities stay at their grid points, a map can leave a hole that
// close_holes cannot close: its rim lays out in no grid, the fans of its rim vertices winding too
// little or too much for the quarter turns a flat patch of cells needs (decimated-knight_miq_18 at
// x2: ten rim vertices past singularities of valence 6, 5 and 6 whose folded fans wind 0 to 2
// quarter turns, round a flipped triangle between three singularities). No mesh that follows the
// map exists there, so no face can follow it: the hole is filled with quads that join its rim
// vertices, and the checker decides whether the map leaves that region undecided (a fold-over
// judged on the surface) or requires cells there, which such quads do not give.
#include "ladder.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdlib>

namespace qex::detail {
namespace {

std::uint64_t half_edge(int a, int b) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

/// The best quadrangulation of one rim (a polygon of an even number of vertices, positions 0 to
/// n - 1 on the rim) by diagonals, none an edge of the mesh: the one whose rim vertices' face
/// counts come nearest their quarter turns (the sum of the differences), then with the shortest
/// diagonals (squared, in space), the first of the dynamic programme's order among equals.
/// Exact, by a dynamic programme over the polygons a side (i, j), i < j, cuts off: the quad
/// (i, a, b, j) on that side leaves the polygons on (i, a), (a, b) and (b, j), and every vertex
/// strictly inside (i, j) takes all its faces there, so its difference is settled there; a
/// polygon's table holds, per count of faces at its ends i and j, the best cost of its inside.
class RimQuadrangulation {
public:
    RimQuadrangulation(const std::vector<int>& rim, const Holes& holes, const QuadMesh& mesh)
        : rim_(rim),
          holes_(holes),
          mesh_(mesh),
          n_(static_cast<int>(rim.size())),
          counts_(n_ / 2 + 1),
          table_(static_cast<std::size_t>(n_ * n_)),
          reached_(static_cast<std::size_t>(n_ * n_)) {}

    /// The best quadrangulation's quads, as rim vertices in rim order; empty if there is none.
    std::vector<std::vector<int>> best() {
        for (int length = 1; length < n_; length += 2)
            for (int i = 0; i + length < n_; ++i) solve(i, i + length);
        const std::vector<Entry>& top = at(0, n_ - 1);
        int chosen = -1;
        Cost best;
        for (int k = 0; k < static_cast<int>(top.size()); ++k) {
            if (!top[static_cast<std::size_t>(k)].set) continue;
            Cost c = top[static_cast<std::size_t>(k)].cost;
            c.deviation += difference(0, k / counts_) + difference(n_ - 1, k % counts_);
            if (chosen < 0 || better(c, best)) chosen = k, best = c;
        }
        std::vector<std::vector<int>> faces;
        if (chosen >= 0) emit(0, n_ - 1, chosen / counts_, chosen % counts_, faces);
        return faces;
    }

private:
    struct Cost {
        std::int64_t deviation = 0;
        double length = 0.0;
    };
    static bool better(const Cost& x, const Cost& y) {
        return x.deviation < y.deviation || (x.deviation == y.deviation && x.length < y.length);
    }
    /// A polygon's best inside for counts (fi, fj) of faces at its ends: its cost, its side's quad
    /// (i, a, b, j), and the counts its three polygons take at their ends.
    struct Entry {
        bool set = false;
        Cost cost;
        int a = -1, b = -1;
        int ia = 0, ai = 0, ab = 0, ba = 0, bj = 0, jb = 0;
    };

    std::vector<Entry>& at(int i, int j) { return table_[static_cast<std::size_t>(i * n_ + j)]; }

    bool rim_side(int i, int j) const { return j - i == 1 || (i == 0 && j == n_ - 1); }

    /// Whether positions i < j may be joined: a side of the rim, or a diagonal that is no edge of
    /// the mesh (the mesh would not stay manifold).
    bool joinable(int i, int j) const {
        if (rim_side(i, j)) return true;
        const int a = rim_[static_cast<std::size_t>(i)], b = rim_[static_cast<std::size_t>(j)];
        const auto& half = holes_.half;
        return !std::binary_search(half.begin(), half.end(), half_edge(a, b)) &&
               !std::binary_search(half.begin(), half.end(), half_edge(b, a));
    }

    /// The squared length of the diagonal (i, j) in space; 0 for a side of the rim.
    double length2(int i, int j) const {
        if (rim_side(i, j)) return 0.0;
        const auto& p = mesh_.positions[static_cast<std::size_t>(rim_[static_cast<std::size_t>(i)])];
        const auto& q = mesh_.positions[static_cast<std::size_t>(rim_[static_cast<std::size_t>(j)])];
        return (p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]);
    }

    /// How far rim position i's face count, with `added` faces of the patch, is from its quarter turns.
    std::int64_t difference(int i, int added) const {
        const auto v = static_cast<std::size_t>(rim_[static_cast<std::size_t>(i)]);
        return std::abs(holes_.corners[v] + added - holes_.wound[v]);
    }

    /// The table of the polygon on (i, j), from those of the shorter ones.
    void solve(int i, int j) {
        std::vector<Entry>& out = at(i, j);
        out.assign(static_cast<std::size_t>(counts_ * counts_), Entry{});
        if (j - i == 1) {
            out[0].set = true;
            set_of(i, j).push_back(0);
            return;
        }
        const int cells = counts_ * counts_;
        std::vector<Cost> partial(static_cast<std::size_t>(cells));
        std::vector<std::array<int, 2>> from(static_cast<std::size_t>(cells));
        std::vector<char> reached(static_cast<std::size_t>(cells));
        for (int a = i + 1; a < j; a += 2)
            for (int b = a + 1; b < j; b += 2) {
                if (!joinable(i, a) || !joinable(a, b) || !joinable(b, j)) continue;
                const std::vector<int>&left = set_of(i, a), &middle = set_of(a, b), &right = set_of(b, j);
                // The polygons on (i, a) and (a, b) joined first: a's faces are all there (the
                // quad's and theirs), so per (count at i, count at b) only the best pair stays.
                std::fill(reached.begin(), reached.end(), 0);
                for (const int l : left)
                    for (const int m : middle) {
                        const int key = (l / counts_) * counts_ + m % counts_;
                        Cost c = sum(entry(i, a, l).cost, entry(a, b, m).cost);
                        c.deviation += difference(a, 1 + l % counts_ + m / counts_);
                        if (reached[static_cast<std::size_t>(key)] &&
                            !better(c, partial[static_cast<std::size_t>(key)]))
                            continue;
                        reached[static_cast<std::size_t>(key)] = 1;
                        partial[static_cast<std::size_t>(key)] = c;
                        from[static_cast<std::size_t>(key)] = {l, m};
                    }
                const double diagonals = length2(i, a) + length2(a, b) + length2(b, j);
                for (int key = 0; key < cells; ++key) {
                    if (!reached[static_cast<std::size_t>(key)]) continue;
                    for (const int r : right) {
                        const int fi = 1 + key / counts_, fj = 1 + r % counts_;
                        if (fi >= counts_ || fj >= counts_) continue;
                        Cost c = sum(partial[static_cast<std::size_t>(key)], entry(b, j, r).cost);
                        c.deviation += difference(b, 1 + key % counts_ + r / counts_);
                        c.length += diagonals;
                        Entry& e = out[static_cast<std::size_t>(fi * counts_ + fj)];
                        if (e.set && !better(c, e.cost)) continue;
                        const auto [l, m] = from[static_cast<std::size_t>(key)];
                        e = {true,        c,           a,           b,           l / counts_,
                             l % counts_, m / counts_, m % counts_, r / counts_, r % counts_};
                    }
                }
            }
        for (int k = 0; k < cells; ++k)
            if (out[static_cast<std::size_t>(k)].set) set_of(i, j).push_back(k);
    }

    static Cost sum(const Cost& x, const Cost& y) { return {x.deviation + y.deviation, x.length + y.length}; }
    const Entry& entry(int i, int j, int k) { return at(i, j)[static_cast<std::size_t>(k)]; }
    /// The counts the polygon on (i, j) can take, as indices into its table.
    std::vector<int>& set_of(int i, int j) { return reached_[static_cast<std::size_t>(i * n_ + j)]; }

    /// Appends the quads of the polygon on (i, j) with counts (fi, fj) at its ends, as rim vertices.
    void emit(int i, int j, int fi, int fj, std::vector<std::vector<int>>& faces) {
        if (j - i == 1) return;
        const Entry e = at(i, j)[static_cast<std::size_t>(fi * counts_ + fj)];
        faces.push_back({rim_[static_cast<std::size_t>(i)], rim_[static_cast<std::size_t>(e.a)],
                         rim_[static_cast<std::size_t>(e.b)], rim_[static_cast<std::size_t>(j)]});
        emit(i, e.a, e.ia, e.ai, faces);
        emit(e.a, e.b, e.ab, e.ba, faces);
        emit(e.b, j, e.bj, e.jb, faces);
    }

    const std::vector<int>& rim_;
    const Holes& holes_;
    const QuadMesh& mesh_;
    const int n_;
    const int counts_;                      ///< the face counts a polygon's end can take: 0 to n / 2
    std::vector<std::vector<Entry>> table_; ///< per polygon (i, j), i * n + j: counts -> best
    std::vector<std::vector<int>> reached_; ///< per polygon: the counts it can take (set entries)
};

} // namespace

std::vector<Defect> fill_holes(const Input& input, QuadMesh& mesh, bool wound_first) {
    // The holes whose rims lay out round cells of their vertices are closed by those cells first.
    const Holes holes = find_holes(input, mesh, kMaxFilledRim);
    std::vector<Defect> done;
    const std::vector<char> closed = close_rims(holes, mesh, wound_first, done);
    for (std::size_t r = 0; r < holes.rims.size(); ++r) {
        const std::vector<int>& rim = holes.rims[r];
        if (closed[r] || rim.size() % 2 != 0) continue; // a patch of quads without new vertices has an even rim
        const std::vector<std::vector<int>> faces = RimQuadrangulation(rim, holes, mesh).best();
        if (faces.empty()) continue;
        done.push_back(patch_hole(mesh, rim, faces, DefectKind::HoleFilled,
                                  "a hole the face walks left (" + rim_description(rim) +
                                      ") is closed by no cells of the grid (its rim lays out in none from the faces "
                                      "round it, or round a grid point with no vertex): it was filled with " +
                                      std::to_string(faces.size()) + " quad" + (faces.size() == 1 ? "" : "s") +
                                      " joining rim vertices, which follow no cells of the map, and the checker "
                                      "accepted the mesh so"));
    }
    return done;
}

} // namespace qex::detail

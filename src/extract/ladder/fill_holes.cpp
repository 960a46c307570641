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
#include <cstdint>
#include <cstdlib>
#include <limits>

namespace qex::detail {
namespace {

std::uint64_t half_edge(int a, int b) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

/// The quadrangulations of one rim (a polygon of an even number of vertices) by diagonals, none
/// an edge of the mesh: each split of a side (i, j) of the polygon (positions on the rim, i < j)
/// into the quad (i, a, b, j) and the three polygons it leaves, searched depth first; the best by
/// (valence deviation, squared diagonal length), the first found among equals.
class RimQuadrangulation {
public:
    RimQuadrangulation(const std::vector<int>& rim, const Holes& holes, const QuadMesh& mesh)
        : rim_(rim), holes_(holes), mesh_(mesh), n_(static_cast<int>(rim.size())) {}

    /// The best quadrangulation's quads, as rim vertices in rim order; empty if there is none.
    std::vector<std::vector<int>> best() {
        std::vector<std::pair<int, int>> pending{{0, n_ - 1}};
        search(pending);
        std::vector<std::vector<int>> faces;
        for (const auto& q : best_)
            faces.push_back({rim_[static_cast<std::size_t>(q[0])], rim_[static_cast<std::size_t>(q[1])],
                             rim_[static_cast<std::size_t>(q[2])], rim_[static_cast<std::size_t>(q[3])]});
        return faces;
    }

private:
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

    double length2(int i, int j) const {
        const auto& p = mesh_.positions[static_cast<std::size_t>(rim_[static_cast<std::size_t>(i)])];
        const auto& q = mesh_.positions[static_cast<std::size_t>(rim_[static_cast<std::size_t>(j)])];
        return (p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]);
    }

    void search(std::vector<std::pair<int, int>>& pending) {
        // Past the budget, of quadrangulations or of steps (diagonals that are edges of the mesh can
        // leave most branches without one): the best found so far stands.
        if (judged_ >= kMaxJudged || ++steps_ > kMaxSteps) return;
        if (pending.empty()) return judge();
        const auto [i, j] = pending.back();
        pending.pop_back();
        if (j - i == 1) {
            search(pending);
        } else {
            for (int a = i + 1; a < j; a += 2)
                for (int b = a + 1; b < j; b += 2) {
                    if (!joinable(i, a) || !joinable(a, b) || !joinable(b, j)) continue;
                    quads_.push_back({i, a, b, j});
                    pending.insert(pending.end(), {{i, a}, {a, b}, {b, j}});
                    search(pending);
                    pending.resize(pending.size() - 3);
                    quads_.pop_back();
                }
        }
        pending.emplace_back(i, j);
    }

    /// The rim vertices' face counts against their quarter turns, then the diagonals' lengths.
    void judge() {
        ++judged_;
        std::vector<int> faces(static_cast<std::size_t>(n_), 0);
        double diagonals = 0.0;
        for (const auto& q : quads_)
            for (std::size_t k = 0; k < 4; ++k) {
                ++faces[static_cast<std::size_t>(q[k])];
                const int a = std::min(q[k], q[(k + 1) % 4]), b = std::max(q[k], q[(k + 1) % 4]);
                if (!rim_side(a, b)) diagonals += 0.5 * length2(a, b); // each diagonal is a side of two quads
            }
        std::int64_t deviation = 0;
        for (int i = 0; i < n_; ++i) {
            const auto v = static_cast<std::size_t>(rim_[static_cast<std::size_t>(i)]);
            deviation += std::abs(holes_.corners[v] + faces[static_cast<std::size_t>(i)] - holes_.wound[v]);
        }
        if (best_.empty() || deviation < best_deviation_ ||
            (deviation == best_deviation_ && diagonals < best_diagonals_)) {
            best_ = quads_;
            best_deviation_ = deviation;
            best_diagonals_ = diagonals;
        }
    }

    const std::vector<int>& rim_;
    const Holes& holes_;
    const QuadMesh& mesh_;
    const int n_;
    std::vector<std::array<int, 4>> quads_, best_;
    std::int64_t best_deviation_ = 0;
    /// The quadrangulations judged, and the most judged: all of them up to 18 rim vertices
    /// (43,263), the first of the search's order beyond (20 have 246,675).
    static constexpr std::size_t kMaxJudged = 100'000;
    /// The search's steps, and the most taken (the 43,263 of 18 rim vertices take about 580,000).
    static constexpr std::size_t kMaxSteps = 2'000'000;
    std::size_t judged_ = 0, steps_ = 0;
    double best_diagonals_ = std::numeric_limits<double>::infinity();
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

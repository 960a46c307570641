// The repair's retry with cone fans opened: a singularity's fan that a fold closed is laid out
// over its angle and kept open by a barrier while the region is untangled again (open_cones.h).
#include "extract/repair/open_cones.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <system_error>
#include <unordered_map>
#include <utility>

namespace qex::detail::repair_impl {
namespace {

/// A singularity whose fan a fold closed: one run of flipped or degenerate triangles (or none, the
/// fan squeezed), which the untangler tends to open by winding a neighbour twice instead (the
/// cone then a turn short). Lays the run's inner rim vertices (all free; the run grown by
/// positive triangles beside it) out evenly, clockwise from the run's first rim vertex, over the
/// angle that the cone's target leaves the run, each at its distance from the cone. The cone's
/// fan is then positive and winds by its target, and its triangles are added to `barrier` (the
/// untangler keeps them positive, so the cone keeps its winding). False for a fan with several
/// runs, a fixed inner rim vertex, or no room for the run (its angle not between 0 and pi per
/// triangle), with nothing moved; or, after moving, when the cone still does not wind by its
/// target (the caller restores the UVs it had before).
bool open_cone_fan(TriMesh& m, const Region& r, const RegionMarks& marks,
                   const std::unordered_map<int, std::size_t>& slot, int cone, std::vector<int>& barrier) {
    // From a canonical corner: the sums and the choices below depend neither on the input's
    // order nor on its charts.
    std::vector<int> fan = fan_in_3d_order(m, cone);
    const std::size_t n = fan.size();
    std::size_t start = n;
    for (std::size_t i = 0; i < n && start == n; ++i)
        if (positive(m, TriMesh::face(fan[i]))) start = i;
    if (start == n) return false;
    std::rotate(fan.begin(), fan.begin() + static_cast<std::ptrdiff_t>(start), fan.end());
    std::size_t first = n, length = 0;
    int runs = 0;
    double kept = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        const bool bad = !positive(m, TriMesh::face(fan[i]));
        if (!bad) {
            kept += corner_angle(m, fan[i]);
            continue;
        }
        if (i == 0 || positive(m, TriMesh::face(fan[i - 1]))) ++runs, first = i;
        ++length;
    }
    if (runs > 1) return false;
    if (runs == 0) { // a squeezed fan, all positive (Figure 2 (d)): all but its first triangle open
        first = 1;
        length = n - 1;
        kept = corner_angle(m, fan[0]);
    }
    // The run takes in positive triangles beside it, alternately after and before it, until it
    // has at most a quarter turn per triangle (a run of one cannot open by more than half a
    // turn, and near-flat triangles are a poor start).
    double span = marks.target(m, cone) - kept;
    for (bool after = true; span > 0.5 * M_PI * static_cast<double>(length) && length + 1 < n; after = !after) {
        if (after && first + length < n) {
            span += corner_angle(m, fan[first + length]);
        } else if (first > 0) {
            span += corner_angle(m, fan[--first]);
        } else {
            span += corner_angle(m, fan[first + length]);
        }
        ++length;
    }
    if (length < 2 || !(span > 0.0 && span < M_PI * static_cast<double>(length))) return false;
    // In the chart of the run's first triangle: the cone, and the direction of its first rim vertex.
    int h = fan[first];
    const Vec2 c = m.uv[h], p = m.uv[TriMesh::prev(h)];
    const double phi = std::atan2(p[1] - c[1], p[0] - c[0]);
    GridAutomorphism to_h; // the first triangle's chart -> h's
    std::vector<std::pair<std::size_t, Vec2>> moves;
    for (std::size_t i = 1; i < length; ++i) {
        const int rim = TriMesh::next(h);
        const auto it = slot.find(m.origin(rim));
        if (it == slot.end()) return false;
        const double radius = std::hypot(m.uv[rim][0] - m.uv[h][0], m.uv[rim][1] - m.uv[h][1]);
        const double angle = phi - span * static_cast<double>(i) / static_cast<double>(length);
        const Vec2 at = to_h(Vec2{c[0] + radius * std::cos(angle), c[1] + radius * std::sin(angle)});
        const FreeFan& f = r.fans[it->second];
        const auto k = static_cast<std::size_t>(std::find(f.corners.begin(), f.corners.end(), rim) - f.corners.begin());
        moves.push_back({it->second, f.to_c[k].inverse()(at)});
        to_h = m.map.transition[h].after(to_h);
        h = m.cw(h);
    }
    for (const auto& [i, x] : moves) place(m, r.fans[i], x);
    if (winding_excess(m, cone, marks) != 0) return false;
    for (const int c : fan) barrier.push_back(TriMesh::face(c));
    return true;
}

/// The region's interior singularities that wind short of their targets at m's UVs.
std::vector<int> short_cones_of(const TriMesh& m, const RegionMarks& marks) {
    std::vector<int> cones;
    for (const int v : marks.fixed)
        if (m.map.singular[v] && !m.on_boundary[v] && winding_excess(m, v, marks) < 0) cones.push_back(v);
    return cones;
}

} // namespace

bool untangle_with_open_cones(TriMesh& m, const Region& r, const RegionMarks& marks, const std::vector<Point2>& before,
                              Workspace& work, int patience) {
    restore_region_uvs(m, r, before);
    std::vector<int> short_cones = short_cones_of(m, marks);
    if (short_cones.empty()) return false;
    // Neighbouring cones may share rim vertices: opened in an order that does not depend on the input's.
    std::sort(short_cones.begin(), short_cones.end(),
              [&](int a, int b) { return vertex_key(m, a) < vertex_key(m, b); });
    std::unordered_map<int, std::size_t> slot;
    for (std::size_t k = 0; k < r.fans.size(); ++k) slot[r.fans[k].vertex] = k;
    // Each cone is opened on top of the ones before it, and kept only if every barrier triangle
    // so far is still positive and every cone opened so far still winds by its target (cones
    // can share rim vertices): the barrier must start positive.
    std::vector<int> barrier, opened;
    for (const int cone : short_cones) {
        const std::vector<Point2> snapshot = region_uvs(m, r);
        const std::size_t kept = barrier.size();
        bool ok = open_cone_fan(m, r, marks, slot, cone, barrier);
        for (std::size_t k = 0; ok && k < barrier.size(); ++k) ok = positive(m, barrier[k]);
        for (std::size_t k = 0; ok && k < opened.size(); ++k) ok = winding_excess(m, opened[k], marks) == 0;
        if (ok) {
            opened.push_back(cone);
            continue;
        }
        barrier.resize(kept);
        restore_region_uvs(m, r, snapshot);
    }
    std::sort(barrier.begin(), barrier.end());
    barrier.erase(std::unique(barrier.begin(), barrier.end()), barrier.end());
    return !barrier.empty() && untangle_region(m, r, work, patience, barrier) && windings_kept(m, r, marks);
}

bool RetryBeside::start(const TriMesh& m, const Region& r, const RegionMarks& marks, const std::vector<Point2>& before,
                        int patience) {
    stop();
    if (short_cones_of(m, marks).empty()) return false;
    // The copy takes what the retry reads and the repair changes: UVs and the map's state.
    shadow_.uv = m.uv;
    shadow_.map = m.map;
    stop_ = false;
    repaired_ = false;
    thrown_ = nullptr;
    try {
        thread_ = std::thread([this, &r, &marks, &before, patience] {
            try {
                repaired_ = untangle_with_open_cones(shadow_, r, marks, before, work_, patience);
            } catch (...) { thrown_ = std::current_exception(); }
        });
    } catch (const std::system_error&) {
        return false; // no thread: the retry runs after the first try, as without one
    }
    return true;
}

bool RetryBeside::take(TriMesh& m, const Region& r) {
    if (thread_.joinable()) thread_.join();
    if (thrown_) std::rethrow_exception(std::exchange(thrown_, nullptr));
    if (repaired_) restore_region_uvs(m, r, region_uvs(shadow_, r));
    return repaired_;
}

void RetryBeside::stop() {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
    thrown_ = nullptr;
}

} // namespace qex::detail::repair_impl

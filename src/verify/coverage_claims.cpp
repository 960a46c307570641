// The coverage check's claims (coverage.h): each vertex claims its grid point in every input
// triangle within the claim reach of it, found by a walk from the triangle it was located in and a
// flood across the edges near the point; the claims sorted by triangle and grid point, the mesh's
// faces around each vertex, and the lookups the required cells make in them.
#include "coverage.h"
#include "parallel.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace qex::verify_detail::coverage {

Coverage::Coverage(const LocatedMap& map, const QuadMesh& mesh, const std::vector<Located>& loc,
                   const std::vector<char>& far_from_folds, double uv_tolerance, int threads)
    : map_(map),
      in_(map.in),
      mesh_(mesh),
      loc_(loc),
      far_(far_from_folds),
      claim_reach_(std::max(kClaimReach, uv_tolerance)),
      threads_(threads) {
    // The faces at each vertex (the located mode runs only when every index is in range); a
    // quad with the three corners that follow the vertex, any other polygon with none (-1).
    const std::size_t nv = mesh.positions.size();
    face_start_.assign(nv + 1, 0);
    for (const auto& f : mesh.faces)
        for (int v : f) ++face_start_[static_cast<std::size_t>(v) + 1];
    for (std::size_t v = 0; v < nv; ++v) face_start_[v + 1] += face_start_[v];
    around_.resize(face_start_[nv]);
    std::vector<std::uint32_t> fill(face_start_.begin(), face_start_.end() - 1);
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
        const auto& q = mesh.faces[f];
        for (std::size_t k = 0; k < q.size(); ++k)
            around_[fill[static_cast<std::size_t>(q[k])]++] = {
                static_cast<std::int32_t>(f),
                q.size() == 4 ? std::array<std::int32_t, 3>{q[(k + 1) % 4], q[(k + 2) % 4], q[(k + 3) % 4]}
                              : std::array<std::int32_t, 3>{-1, -1, -1}};
    }
}

std::array<P2, 3> Coverage::uv(std::uint32_t t, const P2& origin) const { return corner_uvs(in_, t, origin); }

bool Coverage::walk_to(std::uint32_t& t, GridPoint& p) const {
    for (int step = 0; step < kWalkSteps; ++step) {
        const P2 origin{static_cast<double>(p[0]), static_cast<double>(p[1])};
        const std::array<P2, 3> q = uv(t, origin);
        if (triangle_distance({0, 0}, q) <= claim_reach_) return true;
        // Across the edge the point lies farthest beyond (in the triangle's orientation).
        const double area = cross(q[0], q[1], q[2]);
        int best = -1;
        double beyond = 0;
        for (int k = 0; k < 3; ++k) {
            const P2 &a = q[static_cast<std::size_t>(k)], &b = q[static_cast<std::size_t>((k + 1) % 3)];
            const double len = norm(b[0] - a[0], b[1] - a[1]);
            const double s = len > 0 ? -cross(a, b, {0, 0}) / len * (area < 0 ? -1 : 1) : 0;
            if (s > beyond) beyond = s, best = k;
        }
        if (best < 0) return false;
        const std::size_t c = 3 * t + static_cast<std::size_t>(best);
        const std::int64_t o = map_.edges.opposite[c];
        if (o < 0 || map_.fold_over[static_cast<std::size_t>(o / 3)]) return false;
        p = map_point(map_.edges.across[c], p);
        if (std::abs(static_cast<double>(p[0])) > kFarGrid || std::abs(static_cast<double>(p[1])) > kFarGrid)
            return false;
        t = static_cast<std::uint32_t>(o / 3);
    }
    return false;
}

void Coverage::reach_from(std::uint32_t t, const P2& x, Scratch& scratch) const {
    scratch.next();
    auto& reach = scratch.reach;
    reach.assign(1, {t, x});
    scratch.stamp[t] = scratch.generation;
    for (std::size_t head = 0; head < reach.size() && reach.size() < kClaimTriangles; ++head) {
        const auto [s, q] = reach[head];
        const std::array<P2, 3> here = uv(s, q);
        for (std::size_t k = 0; k < 3; ++k) {
            // Only across an edge near the point (the charts on its two sides disagree by less
            // than the reach): the triangle beyond holds no point farther from it.
            if (segment_distance({0, 0}, here[k], here[(k + 1) % 3]) > 2 * claim_reach_) continue;
            const std::size_t c = 3 * s + k;
            const std::int64_t o = map_.edges.opposite[c];
            if (o < 0) continue;
            const auto n = static_cast<std::uint32_t>(o / 3);
            if (scratch.stamp[n] == scratch.generation || map_.fold_over[n]) continue;
            const Transition& m = map_.edges.across[c];
            const P2 r = rotate_quarter(q, m.r);
            const P2 qn{r[0] + static_cast<double>(m.tx), r[1] + static_cast<double>(m.ty)};
            if (!(std::abs(qn[0]) < kFarGrid && std::abs(qn[1]) < kFarGrid)) continue;
            if (triangle_distance({0, 0}, uv(n, qn)) > claim_reach_) continue;
            scratch.stamp[n] = scratch.generation;
            reach.push_back({n, qn});
        }
    }
}

Key Coverage::canonical(const Key& k, Scratch& scratch) const {
    reach_from(k.triangle, {static_cast<double>(k.p[0]), static_cast<double>(k.p[1])}, scratch);
    Key best = k;
    for (const auto& [n, q] : scratch.reach)
        best = std::min(best, Key{n, {static_cast<std::int64_t>(q[0]), static_cast<std::int64_t>(q[1])}});
    return best;
}

void Coverage::claim_grid_points() {
    // Each thread its vertices' claims (their order does not matter: they are sorted below).
    const auto nv = static_cast<std::int64_t>(loc_.size());
    const int threads = run_parallel(threads_, nv) ? threads_ : 1;
    std::vector<std::vector<Claim>> part(static_cast<std::size_t>(threads));
    share_chunks(threads, nv, 4096, [&](std::size_t me, const auto& next) {
        Scratch scratch(in_.triangles.size());
        std::vector<Claim>& mine = part[me];
        for (std::int64_t from = 0, to = 0; next(from, to);)
            for (std::int64_t vi = from; vi < to; ++vi) {
                const Located& L = loc_[static_cast<std::size_t>(vi)];
                if (!L.ok && !L.undecided) continue; // off the surface or off the grid: it claims nothing
                // Its grid point; one its precision cannot place, every grid point it may be on.
                for (int du = -L.spread; du <= L.spread; ++du)
                    for (int dv = -L.spread; dv <= L.spread; ++dv) {
                        std::uint32_t t = L.triangle;
                        GridPoint p{L.grid[0] + du, L.grid[1] + dv};
                        if (map_.fold_over[t] || !walk_to(t, p)) continue;
                        reach_from(t, {static_cast<double>(p[0]), static_cast<double>(p[1])}, scratch);
                        for (const auto& [n, q] : scratch.reach)
                            mine.push_back({{static_cast<std::int64_t>(q[0]), static_cast<std::int64_t>(q[1])},
                                            n,
                                            static_cast<std::int32_t>(vi)});
                    }
            }
    });
    // By triangle (a counting pass over the threads' claims), then each triangle's by grid point
    // and vertex.
    const std::size_t nt = in_.triangles.size();
    claimed_.assign(nt + 1, 0);
    for (const auto& p : part)
        for (const Claim& c : p) ++claimed_[c.triangle + 1];
    for (std::size_t t = 0; t < nt; ++t) claimed_[t + 1] += claimed_[t];
    claims_.resize(claimed_[nt]);
    std::vector<std::size_t> fill(claimed_.begin(), claimed_.end() - 1);
    for (auto& p : part) {
        for (const Claim& c : p) claims_[fill[c.triangle]++] = c;
        std::vector<Claim>().swap(p);
    }
    for (std::size_t t = 0; t < nt; ++t)
        std::sort(claims_.begin() + static_cast<std::ptrdiff_t>(claimed_[t]),
                  claims_.begin() + static_cast<std::ptrdiff_t>(claimed_[t + 1]));
}

std::pair<const Claim*, const Claim*> Coverage::claims_at(const Key& k) const {
    const Claim* from = claims_.data() + claimed_[k.triangle];
    const Claim* to = claims_.data() + claimed_[k.triangle + 1];
    return std::equal_range(from, to, Claim{k.p, k.triangle, 0},
                            [](const Claim& a, const Claim& b) { return a.p < b.p; });
}

std::int64_t Coverage::face_at(const std::array<std::pair<const Claim*, const Claim*>, 4>& at) const {
    auto claimed = [&](std::size_t i, int v) {
        for (const Claim* c = at[i].first; c != at[i].second; ++c)
            if (c->vertex == v) return true;
        return false;
    };
    for (const Claim* c = at[0].first; c != at[0].second; ++c) {
        const auto v = static_cast<std::size_t>(c->vertex);
        for (std::size_t i = face_start_[v]; i < face_start_[v + 1]; ++i) {
            const Around& a = around_[i];
            if (claimed(1, a.next[0]) && claimed(2, a.next[1]) && claimed(3, a.next[2])) return a.face;
        }
    }
    return -1;
}

} // namespace qex::verify_detail::coverage

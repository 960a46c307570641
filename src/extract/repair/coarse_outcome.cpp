// The outcome of the repair on the coarse triangulation, named on the given one: the triangles
// it changed, the fold-overs left grouped on the given mesh with the coarse ones' reasons, and
// the proofs with their triangles (coarse.h).
#include "extract/repair/coarse.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

namespace qex::detail::repair_impl {
namespace {

/// The coarse triangle that holds fine triangle f (its centroid, in its plane), among those at
/// its corners.
int host_of(const TriMesh& m, const CoarseMap& cm, int f) {
    const TriMesh& c = cm.mesh;
    Vec3 centre{0.0, 0.0, 0.0};
    for (int k = 0; k < 3; ++k)
        for (int d = 0; d < 3; ++d) centre[d] += m.pos(3 * f + k)[d] / 3.0;
    std::vector<int> near;
    for (const int u : m.tri[f]) {
        if (cm.host[u] >= 0) {
            const int t = cm.host[u];
            near.push_back(t);
            for (int k = 0; k < 3; ++k)
                if (c.opp[3 * t + k] >= 0) near.push_back(TriMesh::face(c.opp[3 * t + k]));
        } else {
            for (int h = c.fan_start[u], n = 0; h >= 0 && n < c.fan_size[u]; h = c.cw(h), ++n)
                near.push_back(TriMesh::face(h));
        }
    }
    int best = -1;
    double low = -1e300;
    for (const int t : near) {
        const std::array<Vec3, 3> q{c.pos(3 * t), c.pos(3 * t + 1), c.pos(3 * t + 2)};
        std::array<double, 3> l{};
        if (!barycentric3(q[0], q[1], q[2], centre, l)) continue;
        const double worst = std::min({l[0], l[1], l[2]});
        if (worst > low && in_plane(q, centre)) low = worst, best = t;
    }
    return best;
}

/// Which fine triangles a coarse one holds, asked for only where a fold-over is left or a proof
/// names a triangle: those round its corners and round the vertices it holds whose centroid it holds.
class Hosts {
public:
    Hosts(const TriMesh& m, const CoarseMap& cm) : m_(m), cm_(cm), start_(cm.mesh.num_faces() + 1, 0) {
        for (const int t : cm.host)
            if (t >= 0) ++start_[t + 1];
        for (std::size_t t = 1; t < start_.size(); ++t) start_[t] += start_[t - 1];
        inside_.resize(start_.back());
        std::vector<int> at(start_.begin(), start_.end() - 1);
        for (int v = 0; v < m.num_vertices; ++v)
            if (cm.host[v] >= 0) inside_[at[cm.host[v]]++] = v;
    }
    int of(int f) const { return host_of(m_, cm_, f); }
    std::vector<int> held(int t) const {
        std::vector<int> ends(cm_.mesh.tri[t].begin(), cm_.mesh.tri[t].end()), out;
        ends.insert(ends.end(), inside_.begin() + start_[t], inside_.begin() + start_[t + 1]);
        for (const int v : ends)
            for (int h = m_.fan_start[v], n = 0; h >= 0 && n < m_.fan_size[v]; h = m_.cw(h), ++n)
                if (of(TriMesh::face(h)) == t) out.push_back(TriMesh::face(h));
        std::sort(out.begin(), out.end());
        out.erase(std::unique(out.begin(), out.end()), out.end());
        return out;
    }

private:
    const TriMesh& m_;
    const CoarseMap& cm_;
    std::vector<int> start_, inside_; ///< per coarse triangle, the vertices it holds
};

/// The fine triangle of smallest input index among those coarse triangle t holds, else -1.
int first_held(const TriMesh& m, const Hosts& h, int t) {
    int best = -1;
    for (const int f : h.held(t))
        if (best < 0 || m.input_triangle[f] < m.input_triangle[best]) best = f;
    return best;
}

/// A proof of the coarse repair named on m: its triangles are those of m the coarse ones hold
/// (vertices keep their numbers). False if one holds none.
bool fine_proof(const TriMesh& m, const Hosts& h, RepairOutcome::Proof& p) {
    if (p.kind == DefectKind::RimShortOfSingularity) return true;
    if (p.kind == DefectKind::FoldPinnedBySingularities) {
        int pick = -1;
        for (const int f : h.held(p.element))
            if (pick < 0 || (!positive(m, f) && positive(m, pick))) pick = f;
        p.element = pick;
        return pick >= 0;
    }
    if (p.element >= 0) p.element = first_held(m, h, p.element);
    std::vector<int> faces;
    for (const int t : p.faces) {
        const std::vector<int> held = h.held(t);
        faces.insert(faces.end(), held.begin(), held.end());
    }
    std::sort(faces.begin(), faces.end());
    p.faces = std::move(faces);
    return p.element >= 0;
}

} // namespace

/// The coarse repair's outcome named on m (its UVs written back; `sanitized` its UVs before):
/// the triangles whose UVs changed and their groups, the fold-overs left (grouped on m, each with
/// the reason of the coarse fold-over that holds it) and the proofs; updates face_sign.
RepairOutcome fine_outcome(TriMesh& m, const std::vector<Point2>& sanitized, const CoarseMap& cm,
                           const RepairOutcome& coarse) {
    RepairOutcome out;
    std::vector<int> bad;
    for (int f = 0; f < m.num_faces(); ++f) {
        bool changed = false;
        for (int k = 0; k < 3; ++k) changed = changed || m.uv[3 * f + k] != sanitized[3 * f + k];
        if (changed) out.repaired_faces.push_back(f);
        m.map.face_sign[f] = static_cast<signed char>(sign(orient2d(m.uv[3 * f], m.uv[3 * f + 1], m.uv[3 * f + 2])));
        if (m.map.face_sign[f] <= 0) bad.push_back(f);
    }
    out.regions_repaired = static_cast<std::int64_t>(triangle_groups(m, out.repaired_faces).size());
    if (bad.empty() && coarse.proofs.empty()) return out;
    const Hosts h(m, cm);
    std::vector<int> group_of(static_cast<std::size_t>(cm.mesh.num_faces()), -1);
    for (std::size_t g = 0; g < coarse.unrepaired.size(); ++g)
        for (const int t : coarse.unrepaired[g].triangles) group_of[t] = static_cast<int>(g);
    for (auto& group : triangle_groups(m, bad)) {
        std::string why = "the repair on the map's coarsest triangulation left it";
        for (const int f : group) {
            const int t = h.of(f);
            if (t >= 0 && group_of[t] >= 0) {
                why = coarse.unrepaired[static_cast<std::size_t>(group_of[t])].why;
                break;
            }
        }
        out.unrepaired.push_back({std::move(group), why});
    }
    for (RepairOutcome::Proof p : coarse.proofs)
        if (fine_proof(m, h, p)) out.proofs.push_back(std::move(p));
    return out;
}

/// The fine vertices `near` names, as coarse ones: a vertex the coarse triangulation does without
/// by the corners of the triangle that holds it.
std::vector<int> coarse_near(const CoarseMap& cm, const std::vector<int>& near) {
    std::vector<int> out;
    for (const int v : near) {
        if (cm.host[v] < 0) {
            out.push_back(v);
            continue;
        }
        for (const int u : cm.mesh.tri[cm.host[v]]) out.push_back(u);
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

} // namespace qex::detail::repair_impl

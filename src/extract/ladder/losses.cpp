// Which of a rung's lost faces a proof backs: each explanation that removed faces is matched to
// the fold-over the repair left nearest it, and says whether a proof shows that no fold-free map
// of that fold-over's region exists, or the repair failed there (rungs.h).
#include "rungs.h"

#include <algorithm>
#include <string>

namespace qex::detail {
namespace {

/// How far from a lost face a fold-over may lie to be its cause: the repair's largest ring.
constexpr int kReach = 8;

bool removes_faces(DefectKind k) {
    return k == DefectKind::FaceCollapsed || k == DefectKind::GhostFacesCancelled ||
           k == DefectKind::BoundaryFaceDiscarded;
}

/// The fold-overs left nearest triangle t (fewest rings of vertices from its corners, up to
/// kReach), in `found`; `distance` is per-vertex scratch (all -1 before and after).
void nearest_folds(const TriMesh& m, const FoldsLeft& folds, int t, std::vector<int>& distance,
                   std::vector<int>& found) {
    std::vector<int> frontier(m.tri[t].begin(), m.tri[t].end()), next, touched;
    for (const int v : frontier) distance[v] = 0, touched.push_back(v);
    for (int d = 0; d <= kReach && found.empty() && !frontier.empty(); ++d) {
        next.clear();
        for (const int v : frontier)
            for (int c = m.fan_start[v], k = 0; c >= 0 && k < m.fan_size[v]; c = m.cw(c), ++k) {
                const int g = folds.group_of[static_cast<std::size_t>(TriMesh::face(c))];
                if (g >= 0 && std::find(found.begin(), found.end(), g) == found.end()) found.push_back(g);
                for (const int u : m.tri[TriMesh::face(c)])
                    if (distance[u] < 0) distance[u] = d + 1, next.push_back(u), touched.push_back(u);
            }
        frontier.swap(next);
    }
    for (const int v : touched) distance[v] = -1;
}

} // namespace

FoldsLeft folds_left(const TriMesh& m, const RepairOutcome& outcome) {
    FoldsLeft folds;
    folds.group_of.assign(static_cast<std::size_t>(m.num_faces()), -1);
    for (std::size_t g = 0; g < outcome.unrepaired.size(); ++g) {
        const RepairOutcome::Unrepaired& u = outcome.unrepaired[g];
        int first = m.input_triangle[u.triangles[0]];
        for (const int f : u.triangles) {
            folds.group_of[static_cast<std::size_t>(f)] = static_cast<int>(g);
            first = std::min(first, m.input_triangle[f]);
        }
        folds.first.push_back(first);
        folds.proved.push_back(u.proved ? 1 : 0);
    }
    return folds;
}

void name_losses(const TriMesh& m, const FoldsLeft& folds, Report& report) {
    if (folds.group_of.empty()) return; // the rung did not repair
    std::vector<int> working, distance(static_cast<std::size_t>(m.num_vertices), -1), found;
    for (int f = 0; f < m.num_faces(); ++f) {
        const auto t = static_cast<std::size_t>(m.input_triangle[f]);
        if (working.size() <= t) working.resize(t + 1, -1);
        working[t] = f;
    }
    for (Defect& d : report.explanations) {
        if (!removes_faces(d.kind)) continue;
        found.clear();
        const auto t = static_cast<std::size_t>(d.input_element);
        if (d.input_element >= 0 && t < working.size() && working[t] >= 0)
            nearest_folds(m, folds, working[t], distance, found);
        // Several at one distance: proved only if every one is, named by the smallest input
        // triangle, so that neither depends on the order they were met in.
        bool proved = !found.empty();
        int first = -1;
        for (const int g : found) {
            proved = proved && folds.proved[static_cast<std::size_t>(g)];
            const int f = folds.first[static_cast<std::size_t>(g)];
            first = first < 0 ? f : std::min(first, f);
        }
        if (found.empty())
            d.message += "; no fold-over the repair left lies within " + std::to_string(kReach) + " rings of it";
        else if (proved)
            d.message += "; next to the fold-over from input triangle " + std::to_string(first) +
                         ", which a proof listed before it shows no fold-free map of its region has";
        else
            d.message += "; next to the fold-over from input triangle " + std::to_string(first) +
                         ", which the repair did not re-embed (nothing proves that no fold-free map of it exists)";
        ++(proved ? report.losses_proved : report.losses_not_proved);
    }
}

} // namespace qex::detail

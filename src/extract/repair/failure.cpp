// The repair's failure reports: a failed attempt at a region described and put in words, the
// failures kept per vertex, and the explanations of the fold-overs left (failure.h).
#include "extract/repair/failure.h"
#include "extract/repair/repair.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

namespace qex::detail {
namespace repair_impl {

namespace {

/// A number of quarter turns for a message: to two decimals, whole ones without.
std::string quarter_turns(double q) {
    char text[32];
    if (std::abs(q - std::nearbyint(q)) < 0.005)
        std::snprintf(text, sizeof text, "%.0f", q);
    else
        std::snprintf(text, sizeof text, "%.2f", q);
    return text;
}

} // namespace

std::string RegionFailure::text() const {
    const std::string where = "within " + std::to_string(radius) + " rings (a region of " +
                              std::to_string(free_vertices) + " free vertices, " + std::to_string(triangles) +
                              " triangles, " + std::to_string(singularities) + " singularities inside):";
    switch (why) {
        case Why::TooLarge: return where + " the region is larger than the repair attempts";
        case Why::AreaNotPositive:
            return where +
                   " the region's signed UV area is not positive: no orientation-preserving map of it "
                   "exists";
        case Why::NoRoom:
            if (!proof)
                return where +
                       " the angles its fixed vertices leave the region admit no embedding (Gauss-Bonnet, or "
                       "whole turns missing among several singularities)";
            if (cone >= 0)
                return where + " input vertex " + std::to_string(vertex) + " leaves it " + quarter_turns(amount) +
                       " quarter turns for " + std::to_string(corners) +
                       " corners, which positive triangles cannot fill (between 0 and 2 per corner)";
            return where + " the angles its fixed vertices leave it miss " + quarter_turns(amount) +
                   " quarter turns of the 2 per triangle that positive triangles take, among " +
                   std::to_string(singularities) + " singularities inside (Gauss-Bonnet)";
        case Why::RimShort:
            return where + " its rim turns " + std::to_string(winds) +
                   " quarter turns about the grid point of input vertex " + std::to_string(vertex) +
                   " (a singularity of valence " + std::to_string(target) +
                   ", which needs as many): with the singularity at its grid point, no fold-free map of "
                   "the region exists";
        case Why::Inverted:
            return where + " the untangler left " + std::to_string(inverted) +
                   " of its triangles inverted (the first: input triangle " + std::to_string(triangle) + ")";
        case Why::Winding:
            if (vertex < 0)
                return where + " every triangle was made positive, but a vertex winds otherwise than it must";
            return where + " every triangle was made positive, but input vertex " + std::to_string(vertex) +
                   (singular ? " (a singularity of valence " + std::to_string(target) + ")"
                             : " (a regular vertex, 4 quarter turns)") +
                   " winds " + std::to_string(winds) + " quarter turns";
    }
    return where;
}

RegionFailure describe_failure(const TriMesh& m, const Region& r, const RegionMarks& marks, bool admitted, int radius) {
    RegionFailure f;
    f.radius = radius;
    f.free_vertices = r.fans.size();
    f.triangles = r.faces.size();
    for (const int v : marks.fixed) {
        double inside = 0.0, outside = 0.0;
        int corners = 0;
        fan_angles(m, v, marks, inside, outside, corners);
        f.singularities += m.map.singular[v] && !m.on_boundary[v] && corners == m.fan_size[v];
    }
    double area2 = 0.0, magnitude = 0.0;
    for (const int t : r.faces) {
        const Vec2 &a = m.uv[3 * t], &b = m.uv[3 * t + 1], &c = m.uv[3 * t + 2];
        const double p1 = (b[0] - a[0]) * (c[1] - a[1]), p2 = (b[1] - a[1]) * (c[0] - a[0]);
        area2 += p1 - p2;
        magnitude += std::abs(p1) + std::abs(p2);
        if (!positive(m, t)) {
            ++f.inverted;
            if (f.triangle < 0 || m.input_triangle[t] < f.triangle) f.triangle = m.input_triangle[t];
        }
        if (f.first_face < 0 || m.input_triangle[t] < m.input_triangle[f.first_face]) f.first_face = t;
    }
    if (!(area2 > 0.0)) {
        f.why = RegionFailure::Why::AreaNotPositive;
        f.amount = 0.5 * area2;
        // Moving free vertices keeps the sum (each one's fan has its rim fixed): a proof where
        // the sum is clear of its rounding (each product within a few units in the last place,
        // the sum of n terms within n).
        const double eps = std::numeric_limits<double>::epsilon();
        f.proof = area2 < -(static_cast<double>(r.faces.size()) + 8.0) * eps * magnitude;
        if (f.proof) f.faces = r.faces;
    } else if (!admitted && marks.rim_cone >= 0) {
        f.why = RegionFailure::Why::RimShort;
        f.proof = true;
        f.vertex = m.input_vertex[marks.rim_cone];
        f.cone = marks.rim_cone;
        f.singular = true;
        f.winds = static_cast<int>(std::lround(marks.rim_angle / (0.5 * M_PI)));
        f.target = static_cast<int>(std::lround(marks.target(m, marks.rim_cone) / (0.5 * M_PI)));
    } else if (!admitted) {
        f.why = RegionFailure::Why::NoRoom;
        f.proof = marks.room_proved;
        if (marks.room_vertex >= 0) {
            f.cone = marks.room_vertex;
            f.vertex = m.input_vertex[marks.room_vertex];
            f.amount = marks.room_left / (0.5 * M_PI);
            f.corners = marks.room_corners;
        } else {
            f.amount = marks.room_missing / (0.5 * M_PI);
        }
    } else if (f.inverted > 0) {
        f.why = RegionFailure::Why::Inverted;
    } else {
        f.why = RegionFailure::Why::Winding;
        // The first vertex (free ones in the region's canonical order, then fixed ones) that
        // winds otherwise than it must.
        std::vector<int> order;
        for (const FreeFan& fan : r.fans) order.push_back(fan.vertex);
        order.insert(order.end(), marks.fixed.begin(), marks.fixed.end());
        for (const int v : order) {
            if (m.on_boundary[v] || winding_excess(m, v, marks) == 0) continue;
            double inside = 0.0, outside = 0.0;
            int corners = 0;
            fan_angles(m, v, marks, inside, outside, corners);
            f.vertex = m.input_vertex[v];
            f.singular = m.map.singular[v] != 0;
            f.winds = static_cast<int>(std::lround((inside + outside) / (0.5 * M_PI)));
            f.target = static_cast<int>(std::lround(marks.target(m, v) / (0.5 * M_PI)));
            break;
        }
    }
    return f;
}

void FailureLog::record(const Region& r, const RegionFailure& f) {
    for (const FreeFan& fan : r.fans) {
        failure_of[fan.vertex] = static_cast<int>(failures.size());
        if (f.proof && f.why == RegionFailure::Why::RimShort) proof_of[fan.vertex] = static_cast<int>(failures.size());
        // A refusal proves the fold stays only while no larger region was admitted: a later
        // failure of another kind takes it back.
        room_proof_of[fan.vertex] =
            f.proof && f.why != RegionFailure::Why::RimShort ? static_cast<int>(failures.size()) : -1;
    }
    failures.push_back(f);
}

std::string FailureLog::reason(const TriMesh& m, const std::vector<int>& group) const {
    // The latest attempt at a region that held one of its vertices (the largest radius).
    int last = -1, proof = -1;
    for (const int f : group)
        for (const int v : m.tri[f]) last = std::max(last, failure_of[v]), proof = std::max(proof, proof_of[v]);
    std::string why =
        "no orientation-preserving re-embedding that keeps every vertex's winding (once round a regular "
        "vertex, a singularity's valence round it) was found: " +
        (last >= 0 ? failures[static_cast<std::size_t>(last)].text() : std::string("no region held it"));
    if (proof >= 0 && proof != last) why += "; and before, " + failures[static_cast<std::size_t>(proof)].text();
    return why;
}

void FailureLog::proofs(const TriMesh& m, const std::vector<int>& group, std::vector<char>& seen,
                        std::vector<int>& out) const {
    seen.resize(failures.size(), 0);
    for (const std::vector<int>* of : {&proof_of, &room_proof_of})
        for (const int f : group)
            for (const int v : m.tri[f]) {
                const int p = (*of)[v];
                if (p < 0 || seen[static_cast<std::size_t>(p)]) continue;
                seen[static_cast<std::size_t>(p)] = 1;
                out.push_back(p);
            }
}

namespace {

std::array<std::int64_t, 2> grid_point(const Point2& uv) { return {std::llround(uv[0]), std::llround(uv[1])}; }

} // namespace

Defect proof_explanation(const TriMesh& m, const RepairOutcome::Proof& p) {
    if (p.kind == DefectKind::RimShortOfSingularity) {
        const int h = m.fan_start[p.element]; // its first corner, as SingularitiesMerged names one
        const int t = m.input_triangle[TriMesh::face(h)];
        const std::array<std::int64_t, 2> g = grid_point(m.uv[h]);
        return {DefectKind::RimShortOfSingularity,
                "the singularity at input vertex " + std::to_string(m.input_vertex[p.element]) + " (grid point (" +
                    std::to_string(g[0]) + ", " + std::to_string(g[1]) + ") of input triangle " + std::to_string(t) +
                    ") needs " + std::to_string(p.target) +
                    " quarter turns round it, but the rim of the fold-over's "
                    "region round it (within " +
                    std::to_string(p.radius) + " rings, " + std::to_string(p.triangles) + " triangles) turns " +
                    std::to_string(p.winds) +
                    " about its grid point, fewer: no fold-free map of the region with its rim as the map gives it "
                    "keeps the singularity at its grid point",
                t,
                -1,
                g,
                std::nullopt};
    }
    if (p.kind == DefectKind::AnglesLeaveNoRoom || p.kind == DefectKind::RegionAreaNotPositive) {
        const int t = p.element;
        const std::string region = "the region of the fold-over's repair within " + std::to_string(p.radius) +
                                   " rings (" + std::to_string(p.triangles) + " triangles, " +
                                   std::to_string(p.singularities) + " singularities inside, from input triangle " +
                                   std::to_string(m.input_triangle[t]) + ")";
        std::string why;
        if (p.kind == DefectKind::RegionAreaNotPositive) {
            double area = 0.0; // on m's map: a refinement reusing the repair names it at its scale
            for (const int f : p.faces) {
                const Point2 &a = m.uv[3 * f], &b = m.uv[3 * f + 1], &c = m.uv[3 * f + 2];
                area += 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
            }
            why = region + " has a signed UV area of " + std::to_string(area) +
                  ", which moving its free vertices does not change: no map of it with its rim and singularities "
                  "as the map gives them is fold-free";
        } else if (p.vertex >= 0)
            why = "input vertex " + std::to_string(m.input_vertex[p.vertex]) + " (" +
                  (m.map.singular[p.vertex]
                       ? "a singularity of valence " + std::to_string(m.map.valence[p.vertex]) + " as the map counts it"
                       : std::string("a regular vertex")) +
                  ") leaves " + region + " " + quarter_turns(p.amount) + " quarter turns for " +
                  std::to_string(p.corners) +
                  " corners, besides the angles of its triangles outside the region: positive triangles give "
                  "each corner between 0 and 2, so no fold-free map of the region keeps the vertex's winding";
        else
            why = "the angles the fixed vertices of " + region + " leave it miss " + quarter_turns(p.amount) +
                  " quarter turns of the 2 per triangle that positive triangles take (Gauss-Bonnet): no fold-free "
                  "map of the region keeps every vertex's winding with the singularities' valences as the map "
                  "counts them";
        return {p.kind, why, m.input_triangle[t], -1, grid_point(m.uv[3 * t]), std::nullopt};
    }
    const int t = p.element;
    const Point2 &a = m.uv[3 * t], &b = m.uv[3 * t + 1], &c = m.uv[3 * t + 2];
    const double area = 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
    std::string corners;
    for (int k = 0; k < 3; ++k)
        corners += (k == 0   ? ""
                    : k == 1 ? ", "
                             : " and ") +
                   std::to_string(m.input_vertex[m.tri[t][k]]) + " (valence " +
                   std::to_string(m.map.valence[m.tri[t][k]]) + ")";
    return {DefectKind::FoldPinnedBySingularities,
            "input triangle " + std::to_string(m.input_triangle[t]) + " is flipped (UV area " + std::to_string(area) +
                ") and its three corners are singularities, at input vertices " + corners +
                ": singularities stay at their grid points, so no fold-free map removes this fold",
            m.input_triangle[t],
            -1,
            grid_point(a),
            std::nullopt};
}

} // namespace repair_impl

void explain_unrepaired(const TriMesh& m, const RepairOutcome& outcome, Report& report) {
    for (const RepairOutcome::Proof& p : outcome.proofs)
        report.explanations.push_back(repair_impl::proof_explanation(m, p));
    for (const RepairOutcome::Unrepaired& u : outcome.unrepaired) {
        int first = m.input_triangle[u.triangles[0]];
        double area = 0.0;
        for (const int f : u.triangles) {
            first = std::min(first, m.input_triangle[f]);
            const Point2 &a = m.uv[3 * f], &b = m.uv[3 * f + 1], &c = m.uv[3 * f + 2];
            area += 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
        }
        report.explanations.push_back({DefectKind::FoldOverNotRepaired,
                                       "a fold-over of " + std::to_string(u.triangles.size()) +
                                           " flipped or degenerate triangles (UV area " + std::to_string(area) +
                                           ", from input triangle " + std::to_string(first) +
                                           ") stays as the map gives it: " + u.why,
                                       first,
                                       -1,
                                       {0, 0},
                                       std::nullopt});
    }
}

} // namespace qex::detail

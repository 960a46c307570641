// Transition functions between adjacent charts (Section 3.1): the rotation that best maps one
// chart's copy of the shared edge onto the other's, then the rounded integer translation.
//
// The copies' positions come first. Where exactly one rotation relates them by a grid transition
// up to solver noise (and every other misses by far more), that rotation is the edge's, whatever
// its direction says: noise on an edge shorter than itself (a collapsed triangle subdivided, then
// perturbed) can point its copies any way. Where several do (copies on a point that quarter or
// half turns about a grid point, cell centre or edge midpoint fix), the choices below are made
// among those.
//
// An edge whose two copies differ by about as much as the edge is long (solver noise on an edge
// that is nearly degenerate in the parameter domain) does not determine its rotation by its
// direction. Such an edge takes the rotation that closes the fan of one of its ends with the
// other edges' transitions: noise never creates a singularity. Only when neither end has a
// closed fan of determined edges does the nearest rotation stand.
#include "pipeline.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace qex::detail {
namespace {

/// Bounds closing_rotation's walk round a fan (corners stepped over). The walk ends at `skip` or
/// at the boundary within the fan's size (build_topology checked the fans), so this is only a
/// guard against walking forever; a fan of more corners would count as open.
constexpr int kMaxClosingWalk = 1 << 16;

/// Edges shorter than a triangle's longest edge by more than this factor count as short (dipoles).
constexpr double kShortEdgeFactor = 8;

/// The maximum norm.
double norm_inf(const Point2& p) { return std::max(std::abs(p[0]), std::abs(p[1])); }

/// The length (maximum norm) of the UV edge of half-edge c.
double uv_edge_length(const TriMesh& m, int c) {
    const Point2 &p = m.uv[c], &q = m.uv[TriMesh::next(c)];
    return norm_inf({q[0] - p[0], q[1] - p[1]});
}

/// The transition of rotation r from face(h)'s chart to face(opp h)'s with the rounded integer
/// translation that best maps h's copy of the edge onto the opposite copy.
GridAutomorphism fitted_transition(const TriMesh& m, int h, int r) {
    const int o = m.opp[h];
    // In face(h) the edge runs a -> b; in face(o) it runs b -> a.
    const Point2& a = m.uv[h];
    const Point2& b = m.uv[TriMesh::next(h)];
    const Point2& a2 = m.uv[TriMesh::next(o)];
    const Point2& b2 = m.uv[o];
    const Point2 ra = GridAutomorphism::rotate(a, r), rb = GridAutomorphism::rotate(b, r);
    GridAutomorphism g;
    g.r = r;
    g.tx = static_cast<std::int64_t>(std::llround(0.5 * ((a2[0] - ra[0]) + (b2[0] - rb[0]))));
    g.ty = static_cast<std::int64_t>(std::llround(0.5 * ((a2[1] - ra[1]) + (b2[1] - rb[1]))));
    return g;
}

/// How far transition g leaves half-edge h's copies of the edge from the opposite copies
/// (inf-norm, the worse end): the seam check's measure.
double seam_offset(const TriMesh& m, int h, const GridAutomorphism& g) {
    const int o = m.opp[h];
    const Point2 ga = g(m.uv[h]), gb = g(m.uv[TriMesh::next(h)]);
    const Point2 &a2 = m.uv[TriMesh::next(o)], &b2 = m.uv[o];
    return std::max(norm_inf({ga[0] - a2[0], ga[1] - a2[1]}), norm_inf({gb[0] - b2[0], gb[1] - b2[1]}));
}

/// solver_noise_bound for the four copies of interior half-edge h's ends (their largest
/// coordinate), with the mesh's noise_scale.
double seam_noise_bound(const TriMesh& m, int h) {
    const int o = m.opp[h];
    const double magnitude = std::max(
        {norm_inf(m.uv[h]), norm_inf(m.uv[TriMesh::next(h)]), norm_inf(m.uv[o]), norm_inf(m.uv[TriMesh::next(o)])});
    return solver_noise_bound(magnitude, m.noise_scale);
}

/// Sets the transition of interior half-edge h to fitted_transition(m, h, r); its opposite
/// gets the inverse.
void set_transition(TriMesh& m, int h, int r) {
    const GridAutomorphism g = fitted_transition(m, h, r);
    m.map.transition.set(static_cast<std::size_t>(h), g);
    m.map.transition.set(static_cast<std::size_t>(m.opp[h]), g.inverse());
}

/// Per triangle: its longest UV edge (for the dipole pass).
std::vector<double> longest_edges(const TriMesh& m) {
    std::vector<double> longest(static_cast<std::size_t>(m.num_faces()));
    const int parts = m.parts(3 * m.num_faces());
    for_parts(parts, parts, m.num_faces(), [&](int, std::int64_t begin, std::int64_t end) {
        for (auto f = static_cast<int>(begin); f < end; ++f)
            longest[static_cast<std::size_t>(f)] =
                std::max({uv_edge_length(m, 3 * f), uv_edge_length(m, 3 * f + 1), uv_edge_length(m, 3 * f + 2)});
    });
    return longest;
}

/// A rotation is ruled out only where it misses by more than this many noise bounds: noise a
/// little above the bound must not leave a wrong rotation fitting alone.
constexpr double kClearOfNoise = 4;

/// What the positions of half-edge h's copies say of its rotation.
struct ByPosition {
    /// Bit r: the transition of rotation r relates the copies up to kClearOfNoise times solver
    /// noise (solver_noise_bound, as the seam check): r is not ruled out. 0 when every one is.
    unsigned fits = 0;
    /// The one rotation not ruled out, when it relates the copies up to solver noise itself;
    /// else -1.
    int unique = -1;
    /// Whether rotation r is allowed: one not ruled out, or any when all are.
    bool allows(int r) const { return fits == 0 || ((fits >> r) & 1u) != 0; }
};

/// What the positions of half-edge h's copies say of its rotation. A rotation whose copies' edge
/// vectors (d rotated, d2) differ by more than twice kClearOfNoise noise bounds is ruled out
/// without its fit: the ends' offsets differ by R^r d - d2 whatever the translation, so the worse
/// end is off by at least half of it. The margin covers the rounding of this bound and of
/// seam_offset, so the same rotations are ruled out as by the fit; it spares almost every edge
/// the fit of its three wrong rotations.
ByPosition by_position(const TriMesh& m, int h) {
    const int o = m.opp[h];
    const Point2 &a = m.uv[h], &b = m.uv[TriMesh::next(h)];
    const Point2 &a2 = m.uv[TriMesh::next(o)], &b2 = m.uv[o];
    const double magnitude = std::max({norm_inf(a), norm_inf(b), norm_inf(a2), norm_inf(b2)});
    const double bound = solver_noise_bound(magnitude, m.noise_scale); // seam_noise_bound
    constexpr double eps = std::numeric_limits<double>::epsilon();
    const double margin = 2 * kClearOfNoise * bound + 16 * eps * (magnitude + 1);
    const Point2 d{b[0] - a[0], b[1] - a[1]}, d2{b2[0] - a2[0], b2[1] - a2[1]};
    ByPosition out;
    int within_noise = -1;
    for (int r = 0; r < 4; ++r) {
        const Point2 rd = GridAutomorphism::rotate(d, r);
        if (0.5 * norm_inf({rd[0] - d2[0], rd[1] - d2[1]}) > margin) continue;
        const double off = seam_offset(m, h, fitted_transition(m, h, r));
        if (off <= kClearOfNoise * bound) out.fits |= 1u << r;
        if (off <= bound) within_noise = r;
    }
    if (within_noise >= 0 && out.fits == 1u << within_noise) out.unique = within_noise;
    return out;
}

/// The rotation r (quarter turns) among those `allowed` whose R90^r e is closest to e2 (largest
/// dot product; the first such r on ties).
int nearest_rotation(const Point2& e, const Point2& e2, const ByPosition& allowed = {}) {
    int best = -1;
    double best_dot = -HUGE_VAL;
    for (int r = 0; r < 4; ++r) {
        if (!allowed.allows(r)) continue;
        const Point2 re = GridAutomorphism::rotate(e, r);
        const double dot = re[0] * e2[0] + re[1] * e2[1];
        if (best < 0 || dot > best_dot) {
            best_dot = dot;
            best = r;
        }
    }
    return best;
}

/// What the first pass lists, each in index order: undetermined edges, and short edges with
/// their lengths.
struct Listed {
    std::vector<int> undetermined;
    std::vector<std::pair<double, int>> short_edges;
};

/// The first pass at half-edge h: a boundary half-edge gets the identity (it is never read); an
/// interior edge is visited at its smaller half-edge, writing only its own two entries, seen
/// from its canonical half-edge: the rotation its copies' positions single out (ByPosition), else
/// the nearest rotation among those they allow; listed in `mine` if undetermined or short
/// (never when its positions singled its rotation out). An edge with a missing UV (a collapsed
/// triangle's) gets the identity both ways and is undetermined but not listed.
void first_pass_edge(TriMesh& m, int h, const std::vector<double>& longest, std::vector<char>& determined,
                     Listed& mine) {
    const int o = m.opp[h];
    if (o < 0) {
        m.map.transition.set(static_cast<std::size_t>(h), GridAutomorphism{});
        return;
    }
    if (o < h) return; // set as the inverse of o
    // Seen from the canonical half-edge, so that neither the input's numbering nor float
    // rounding on the two sides decides (a tie between two directions, 45 degrees apart,
    // resolves to the first rotation from that side).
    const int c = canonical_half_edge(m, h), co = m.opp[c];
    const Point2& a = m.uv[c];
    const Point2& b = m.uv[TriMesh::next(c)];
    const Point2& a2 = m.uv[TriMesh::next(co)];
    const Point2& b2 = m.uv[co];
    const Point2 e{b[0] - a[0], b[1] - a[1]};
    const Point2 e2{b2[0] - a2[0], b2[1] - a2[1]};
    if (!std::isfinite(e[0] + e[1] + e2[0] + e2[1] + a[0] + a[1] + a2[0] + a2[1])) {
        m.map.transition.set(static_cast<std::size_t>(h), GridAutomorphism{});
        m.map.transition.set(static_cast<std::size_t>(o), GridAutomorphism{});
        determined[h] = determined[o] = 0;
        return;
    }
    const ByPosition position = by_position(m, c);
    if (position.unique >= 0) {
        set_transition(m, c, position.unique);
        return;
    }
    const int best = nearest_rotation(e, e2, position);
    set_transition(m, c, best);
    const Point2 re = GridAutomorphism::rotate(e, best);
    // Determined: the rotated copies differ by less than half the shorter one's length.
    if (!(2 * norm_inf({re[0] - e2[0], re[1] - e2[1]}) < std::min(norm_inf(e), norm_inf(e2)))) {
        determined[h] = determined[o] = 0;
        mine.undetermined.push_back(h);
    }
    const double l = std::max(norm_inf(e), norm_inf(e2));
    const double longest_h = longest[static_cast<std::size_t>(TriMesh::face(h))];
    const double longest_o = longest[static_cast<std::size_t>(TriMesh::face(o))];
    if (kShortEdgeFactor * l < std::max(longest_h, longest_o)) mine.short_edges.push_back({l, h});
}

/// The first pass over every half-edge (first_pass_edge). Each part lists its range's edges;
/// joined in part order, the lists are in index order, as a serial pass makes them.
Listed first_pass(TriMesh& m, std::vector<char>& determined) {
    const int nh = 3 * m.num_faces();
    const std::vector<double> longest = longest_edges(m);
    const int parts = m.parts(nh);
    std::vector<Listed> listed(static_cast<std::size_t>(parts));
    for_parts(parts, parts, nh, [&](int part, std::int64_t begin, std::int64_t end) {
        for (auto h = static_cast<int>(begin); h < end; ++h)
            first_pass_edge(m, h, longest, determined, listed[static_cast<std::size_t>(part)]);
    });
    Listed all = std::move(listed[0]);
    for (std::size_t part = 1; part < listed.size(); ++part) {
        const Listed& mine = listed[part];
        all.undetermined.insert(all.undetermined.end(), mine.undetermined.begin(), mine.undetermined.end());
        all.short_edges.insert(all.short_edges.end(), mine.short_edges.begin(), mine.short_edges.end());
    }
    return all;
}

/// The rotation (quarter turns) that closes the fan round the origin of corner `start` when the
/// edge of half-edge `skip` is crossed last; -1 if the fan is open or crosses an undetermined edge.
/// The walk goes from face(opp[skip]) round the shared vertex to face(skip).
int closing_rotation(const TriMesh& m, const std::vector<char>& determined, int skip, int start) {
    int turns = 0;
    int c = start;
    for (int guard = 0; guard < kMaxClosingWalk; ++guard) {
        if (c == skip) return (4 - (turns & 3)) & 3;
        const int o = m.opp[c];
        if (o < 0 || !determined[c]) return -1;
        turns += m.map.transition[c].r;
        c = TriMesh::next(o);
    }
    return -1;
}

/// Undetermined edges: the rotation that closes the fan round the edge's end with the smaller 3D
/// position (canonical_half_edge; a: corner h in face(h), corner next(o) in face(o)), else its
/// other end, if the copies' positions allow it; else the nearest stands. When both fans close but disagree, which end is tried
/// first decides, so it must not be the input's order. Each edge's walks cross determined edges
/// only, so the order of the edges does not matter.
void settle_undetermined(TriMesh& m, const std::vector<char>& determined, const std::vector<int>& undetermined) {
    for (const int listed : undetermined) {
        const int h = canonical_half_edge(m, listed);
        const int o = m.opp[h];
        int r = closing_rotation(m, determined, h, TriMesh::next(o));
        if (r < 0) {
            const int rb = closing_rotation(m, determined, o, TriMesh::next(h)); // o's rotation
            if (rb >= 0) r = (4 - rb) & 3;
        }
        if (r >= 0 && by_position(m, h).allows(r)) set_transition(m, h, r);
    }
}

/// Dipoles: noise can still turn a short edge by a quarter, which puts singularities of
/// opposite index on its two ends. A short edge whose ends turn by opposite amounts takes the
/// rotation that makes both regular, if its copies' positions allow it (an edge whose positions
/// single its rotation out is not listed as short). Shortest edges first, edges of one length by their ends'
/// 3D positions, so the outcome does not depend on the input's order.
void fix_dipoles(TriMesh& m, std::vector<std::pair<double, int>>& short_edges) {
    // The turn of each short edge's ends, walked when first needed (-2: not yet walked).
    std::vector<int> turns(static_cast<std::size_t>(m.num_vertices), -2);
    auto turn = [&](int v) -> int& {
        int& t = turns[static_cast<std::size_t>(v)];
        if (t == -2) t = fan_turn(m, v);
        return t;
    };
    using Ends = std::array<std::array<double, 3>, 2>;
    const auto ends = [&](int h) {
        const auto &a = m.vertex_pos(m.origin(h)), &b = m.vertex_pos(m.target(h));
        return a < b ? Ends{a, b} : Ends{b, a};
    };
    std::sort(short_edges.begin(), short_edges.end(), [&](const auto& x, const auto& y) {
        if (x.first != y.first) return x.first < y.first;
        const Ends ex = ends(x.second), ey = ends(y.second);
        return ex != ey ? ex < ey : x.second < y.second; // two edges at the same points: index order
    });
    for (const auto& [l, h] : short_edges) {
        int &ta = turn(m.origin(h)), &tb = turn(m.target(h));
        if (ta <= 0 || tb <= 0 || ((ta + tb) & 3) != 0) continue; // regular, open, or not opposite
        const int delta = (4 - ta) & 3;                           // a's walk crosses h, b's walk crosses opp(h)
        const int r = (m.map.transition[h].r + delta) & 3;
        if (!by_position(m, h).allows(r)) continue; // the copies' positions rule it out
        set_transition(m, h, r);
        ta = 0;
        tb = 0;
    }
}

} // namespace

int fan_turn(const TriMesh& m, int v) {
    if (m.fan_start[v] < 0 || m.on_boundary[v]) return -1;
    int c = m.fan_start[v], sum = 0, n = 0;
    do {
        sum += m.map.transition[c].r;
        c = m.cw(c);
    } while (c >= 0 && c != m.fan_start[v] && ++n <= m.fan_size[v]);
    return c == m.fan_start[v] ? sum & 3 : -1;
}

void compute_transitions(TriMesh& m) {
    const int nh = 3 * m.num_faces();
    m.map.transition.allocate(static_cast<std::size_t>(nh));
    std::vector<char> determined(nh, 1);
    Listed listed = first_pass(m, determined);
    settle_undetermined(m, determined, listed.undetermined);
    if (listed.short_edges.empty()) return;
    fix_dipoles(m, listed.short_edges);
}

namespace {

/// Whether interior half-edge h (checked from its smaller side) is a seam whose transition maps
/// its copies onto each other only up to more than solver noise.
bool off_seam(const TriMesh& m, int h) {
    const int o = m.opp[h];
    if (o < h) return false; // boundary, or checked from the other side
    return !(seam_offset(m, h, m.map.transition[static_cast<std::size_t>(h)]) <= seam_noise_bound(m, h));
}

/// The seams off_seam finds, in half-edge order (each part lists its range's; `first_only`: a
/// part stops at its first, and only the first part's that has one counts).
std::vector<int> off_seams(const TriMesh& m, bool first_only) {
    const int nh = 3 * m.num_faces();
    const int parts = m.parts(nh);
    std::vector<std::vector<int>> found(static_cast<std::size_t>(parts));
    for_parts(parts, parts, nh, [&](int part, std::int64_t begin, std::int64_t end) {
        std::vector<int>& mine = found[static_cast<std::size_t>(part)];
        for (auto h = static_cast<int>(begin); h < end && !(first_only && !mine.empty()); ++h)
            if (off_seam(m, h)) mine.push_back(h);
    });
    std::vector<int> all;
    for (const std::vector<int>& mine : found) {
        all.insert(all.end(), mine.begin(), mine.end());
        if (first_only && !all.empty()) break;
    }
    return all;
}

} // namespace

Error check_seams(const TriMesh& m, SeamPolicy policy, Report& report) {
    if (policy == SeamPolicy::Trusted) return {};
    for (const int h : off_seams(m, policy == SeamPolicy::Checked)) {
        const int o = m.opp[h];
        const GridAutomorphism& g = m.map.transition[static_cast<std::size_t>(h)];
        const double off = seam_offset(m, h, g);
        char what[160];
        std::snprintf(what, sizeof what, "%.3g cells off (rotation %d quarter turns, translation (%lld, %lld))", off,
                      g.r, static_cast<long long>(g.tx), static_cast<long long>(g.ty));
        const std::string seam = "the seam edge between input vertices " + std::to_string(m.input_vertex[m.origin(h)]) +
                                 " and " + std::to_string(m.input_vertex[m.target(h)]) + " (input triangles " +
                                 std::to_string(m.input_triangle[TriMesh::face(h)]) + " and " +
                                 std::to_string(m.input_triangle[TriMesh::face(o)]) + ")";
        if (policy == SeamPolicy::Rounded) {
            report.explanations.push_back({DefectKind::SeamRounded,
                                           seam + " was rounded to the nearest grid transition, " + what,
                                           m.input_triangle[TriMesh::face(h)],
                                           -1,
                                           {0, 0},
                                           std::nullopt});
            continue;
        }
        return {ErrorCode::InconsistentMap,
                seam + " has UV copies that no grid transition relates: the nearest is " + what +
                    "; an integer-grid map's charts differ by a rotation by quarter turns and an integer "
                    "translation (Options::round_inconsistent_seams, --round-seams, rounds them instead)",
                m.input_triangle[TriMesh::face(h)]};
    }
    return {};
}

} // namespace qex::detail

// The located mode's singularity match: every irregular vertex of the mesh sits on a singularity
// of the map with the matching valence, and every singularity of the map carries such a vertex.
// Decided everywhere, fold-over regions included: a repair (qex's) moves no singularity in 3D,
// and no valid extraction of the map can move one. A rotated edge makes two vertices of valence
// 3 and two of valence 5 at regular points of the map: caught wherever it lies.
//
// The map's valences are read from its UV angle sums: a vertex whose fan's corner angles sum to
// n quarter turns has valence n. Input vertices joined by an edge shorter than the UV tolerance
// are one cone (an extractor collapses such edges): its fan is the triangles with one corner in
// it. Where that fan holds a flipped or degenerate triangle, the sum is known modulo a whole
// turn only (a vertex pushed across its fan winds zero times; a repair corrects it by whole
// turns): the valence must then match modulo 4. On the boundary, where the input's boundary runs
// along iso-lines, a boundary vertex of the mesh has as many faces as the corner's quarter turns.
#include "cones.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace qex::verify_detail {
namespace {

/// Per mesh vertex (indices valid): its faces, and whether it is on the mesh's boundary (an
/// edge of one face side).
struct MeshValences {
    std::vector<int> faces;
    std::vector<char> boundary;
};

MeshValences mesh_valences(const QuadMesh& mesh) {
    MeshValences m{std::vector<int>(mesh.positions.size(), 0), std::vector<char>(mesh.positions.size(), 0)};
    std::vector<std::uint64_t> keys;
    for (const auto& face : mesh.faces)
        for (std::size_t i = 0; i < face.size(); ++i) {
            ++m.faces[static_cast<std::size_t>(face[i])];
            const auto a = static_cast<std::uint32_t>(face[i]),
                       b = static_cast<std::uint32_t>(face[(i + 1) % face.size()]);
            keys.push_back(static_cast<std::uint64_t>(std::min(a, b)) << 32 | std::max(a, b));
        }
    std::sort(keys.begin(), keys.end());
    for (std::size_t i = 0, j = 0; i < keys.size(); i = j) {
        j = i;
        while (j < keys.size() && keys[j] == keys[i]) ++j;
        if (j - i == 1) m.boundary[keys[i] >> 32] = m.boundary[keys[i] & 0xffffffffu] = 1;
    }
    return m;
}

/// A boundary vertex of the mesh at no input vertex: on an input boundary edge of its triangle
/// that runs along an iso-line through its grid point (then a straight boundary: 2 faces).
bool on_iso_boundary_edge(const LocatedMap& map, const Located& L, double tol) {
    const auto on_integer = [tol](double x) { return std::abs(x - std::nearbyint(x)) <= tol; };
    const std::size_t t = L.triangle;
    for (std::size_t k = 0; k < 3; ++k) {
        const std::size_t c = 3 * t + k;
        if (map.edges.partner[c] >= 0) continue;
        const auto &p = map.in.uvs[c], &q = map.in.uvs[next_corner(c)];
        int d = 0; // the constant coordinate
        while (d < 2 && !(std::abs(p[d] - q[d]) <= tol && on_integer(p[d]) && on_integer(q[d]))) ++d;
        if (d == 2) continue;
        const double lo = std::min(p[1 - d], q[1 - d]) - tol, hi = std::max(p[1 - d], q[1 - d]) + tol;
        const double along = static_cast<double>(L.grid[static_cast<std::size_t>(1 - d)]);
        if (static_cast<double>(L.grid[static_cast<std::size_t>(d)]) == std::nearbyint(p[d]) && along >= lo &&
            along <= hi)
            return true;
    }
    return false;
}

std::string valence_words(int n, bool modulo) {
    return modulo ? "angle sum of " + std::to_string(n) +
                        " quarter turns (a valence modulo 4: a fold-over lies in its fan)"
                  : "valence " + std::to_string(n);
}

} // namespace

namespace {

/// What the map says a mesh vertex's valence must be: `n` faces, or none (`judged` false).
struct Expected {
    bool judged = false;
    int n = 4;
    const Cone* cone = nullptr; ///< the cone it sits on, if any
    std::string where;
};

Expected expected_valence(const LocatedMap& map, const ConeMap& k, const Located& L, bool mesh_boundary, double tol) {
    Expected e;
    if (L.on_vertex >= 0) {
        e.cone = &k.cones[static_cast<std::size_t>(k.cone_of[static_cast<std::size_t>(L.on_vertex)])];
        const Cone& x = *e.cone;
        if (x.interior != !mesh_boundary || !x.valence(e.n)) return e;
        if (mesh_boundary && !(x.iso_boundary && !x.folded)) return e;
        e.judged = true;
        e.where = (mesh_boundary ? "a boundary corner of " : std::string(x.singular() ? "a singularity of " : "")) +
                  valence_words(e.n, x.folded) + " at input vertex " + std::to_string(L.on_vertex);
        return e;
    }
    if (mesh_boundary) {
        e.judged = on_iso_boundary_edge(map, L, tol);
        e.n = 2;
        e.where = "a straight boundary along an iso-line of input triangle " + std::to_string(L.triangle);
        return e;
    }
    e.judged = true;
    e.where = "a regular point of input triangle " + std::to_string(L.triangle);
    return e;
}

} // namespace

namespace {

/// Where a finding lies on the map: the cone of the input vertex it sits on, or its triangle.
struct Spot {
    std::int32_t cone = -1;
    std::uint32_t triangle = 0;
    /// The footprint it lies in (a cone's, or a triangle's when on no input vertex), or -1.
    std::int32_t footprint(const ConeMap& k) const {
        return cone >= 0 ? k.cones[static_cast<std::size_t>(cone)].footprint : k.footprint_of_triangle[triangle];
    }
};

/// What the vertex and cone loops found: mismatches, not yet judged against the footprints; the
/// mesh's interior vertices of valence other than 4 (their faces - 4 in `turns`).
struct Findings {
    std::vector<std::pair<Violation, Spot>> pending;
    std::vector<std::pair<int, Spot>> irregular;
    std::vector<char> carried;   ///< per cone: a vertex of the mesh lies on it
    std::vector<char> undecided; ///< per input triangle: in a footprint whose mismatches are undecided
};

/// Marks the triangles of the footprints `which` names undecided.
void mark_undecided(const ConeMap& k, const std::vector<char>& which, Findings& f) {
    for (std::size_t t = 0; t < f.undecided.size(); ++t)
        if (k.footprint_of_triangle[t] >= 0 && which[static_cast<std::size_t>(k.footprint_of_triangle[t])])
            f.undecided[t] = 1;
}

void judge_vertices(const LocatedMap& map, const ConeMap& k, const QuadMesh& mesh, const std::vector<Located>& loc,
                    double tol, VerifyResult& r, Findings& f) {
    const MeshValences m = mesh_valences(mesh);
    for (std::size_t v = 0; v < loc.size(); ++v) {
        const Located& L = loc[v];
        if (m.faces[v] == 0 || !(L.ok || L.surface_only) || L.undecided) continue;
        const bool boundary = m.boundary[v] != 0;
        const Expected e = expected_valence(map, k, L, boundary, tol);
        const Spot spot{e.cone ? static_cast<std::int32_t>(e.cone - k.cones.data()) : -1, L.triangle};
        if (e.cone) f.carried[static_cast<std::size_t>(spot.cone)] = 1;
        if (!boundary && m.faces[v] != 4) ++r.irregular_vertices, f.irregular.push_back({m.faces[v] - 4, spot});
        if (!e.judged) continue;
        ++r.valences_judged;
        if (e.cone ? e.cone->matches(m.faces[v], e.n) : m.faces[v] == e.n) continue;
        f.pending.push_back({{ViolationKind::ValenceMismatch,
                              std::string(boundary ? "boundary " : "") + "vertex " + std::to_string(v) + " has " +
                                  std::to_string(m.faces[v]) + " faces; the map has " + e.where,
                              static_cast<std::int64_t>(v)},
                             spot});
    }
}

void judge_cones(const ConeMap& k, VerifyResult& r, Findings& f) {
    for (std::size_t c = 0; c < k.cones.size(); ++c) {
        const Cone& x = k.cones[c];
        int n = 0;
        const bool singular = x.singular(), corner = x.boundary_corner();
        r.map_cones += singular;
        if (x.interior && !x.valence(n)) ++r.unread_cones;
        if (!(singular || corner) || f.carried[c]) continue;
        f.pending.push_back({{ViolationKind::SingularityNotCarried,
                              std::string(singular ? "the map's singularity of " : "the map's boundary corner of ") +
                                  valence_words(n, x.folded) + " at input vertex " + std::to_string(x.vertex) +
                                  " carries no vertex of the mesh",
                              x.vertex},
                             Spot{static_cast<std::int32_t>(c), 0}});
    }
}

/// Per footprint: how many quarter turns of irregularity the mesh has there beyond the map's
/// singularities and what the folds may add: the sum of |faces - 4| over its irregular vertices,
/// less the sum of |valence - 4| over its singular cones (the smallest a folded cone's residue
/// allows), less kFoldTurns per folded singularity (at least kFoldTurns in all). A fold may merge
/// or move singularities, and leaving it as the map gives it makes dipoles next to its cones
/// (qex's outputs of heavily folded maps: up to 16 quarter turns in a footprint of 9000
/// triangles); a rotated edge adds four quarter turns.
constexpr std::int64_t kFoldTurns = 2;

std::vector<std::int64_t> excess_turns(const ConeMap& k, const Findings& f) {
    std::vector<std::int64_t> excess(k.footprints.size(), 0), folded(k.footprints.size(), 0);
    for (const auto& [turns, spot] : f.irregular)
        if (const std::int32_t fp = spot.footprint(k); fp >= 0) excess[static_cast<std::size_t>(fp)] += std::abs(turns);
    for (const Cone& x : k.cones) {
        int n = 0;
        if (x.footprint < 0 || !x.singular() || !x.valence(n)) continue;
        const int residue = ((n - 4) % 4 + 4) % 4;
        excess[static_cast<std::size_t>(x.footprint)] -= x.folded ? std::min(residue, 4 - residue) : std::abs(n - 4);
        folded[static_cast<std::size_t>(x.footprint)] += x.folded;
    }
    for (std::size_t i = 0; i < excess.size(); ++i) excess[i] -= kFoldTurns * std::max<std::int64_t>(1, folded[i]);
    return excess;
}

/// One round over the footprints: those whose mismatches the mesh's valences explain by their
/// sum (Gauss-Bonnet on the footprint: a fold may merge or move singularities within it) have
/// them listed as undecided; the cones of the others are marked in `grow`. Returns the
/// mismatches left.
std::vector<std::pair<Violation, Spot>> explain_by_sums(const ConeMap& k, Findings& f, VerifyResult& r,
                                                        std::vector<char>& grow) {
    const std::size_t nf = k.footprints.size();
    std::vector<std::int64_t> mesh_turns(nf, 0);
    std::vector<char> has(nf, 0);
    for (const auto& [turns, spot] : f.irregular)
        if (const std::int32_t fp = spot.footprint(k); fp >= 0) mesh_turns[static_cast<std::size_t>(fp)] += turns;
    for (const auto& p : f.pending)
        if (const std::int32_t fp = p.second.footprint(k); fp >= 0) has[static_cast<std::size_t>(fp)] = 1;
    std::vector<char> sums(nf, 0);
    const std::vector<std::int64_t> excess = excess_turns(k, f);
    for (std::size_t i = 0; i < nf; ++i) {
        if (!has[i]) continue;
        const double want = k.footprints[i].cone_turns + k.footprints[i].correction, n = std::nearbyint(want);
        sums[i] = std::abs(want - n) <= kQuarterTurnSlack && static_cast<double>(mesh_turns[i]) == n && excess[i] <= 0;
        r.undecided_footprints += sums[i];
    }
    mark_undecided(k, sums, f);
    std::fill(grow.begin(), grow.end(), 0);
    for (std::size_t c = 0; c < k.cones.size(); ++c)
        if (k.cones[c].footprint >= 0 && has[static_cast<std::size_t>(k.cones[c].footprint)] &&
            !sums[static_cast<std::size_t>(k.cones[c].footprint)])
            grow[c] = 1;
    std::vector<std::pair<Violation, Spot>> left;
    for (auto& p : f.pending) {
        const std::int32_t fp = p.second.footprint(k);
        if (fp < 0 || !sums[static_cast<std::size_t>(fp)]) {
            left.push_back(std::move(p));
            continue;
        }
        const Footprint& x = k.footprints[static_cast<std::size_t>(fp)];
        add_capped(r.undecided, p.first.kind,
                   p.first.message + "; in the fold-over footprint of input triangle " +
                       std::to_string(x.first_triangle) + " (" + std::to_string(x.triangles) +
                       " triangles), where the mesh's valences sum as the map's",
                   p.first.element);
    }
    return left;
}

/// The mesh's sum of (faces - 4) over its interior vertices in footprint `fp`.
std::int64_t mesh_turns_in(const ConeMap& k, const Findings& f, std::int32_t fp) {
    std::int64_t sum = 0;
    for (const auto& [turns, spot] : f.irregular) sum += spot.footprint(k) == fp ? turns : 0;
    return sum;
}

std::string num(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.2f", x);
    return buf;
}

} // namespace

void check_singularities(const LocatedMap& map, const QuadMesh& mesh, const std::vector<Located>& loc, double tol,
                         VerifyResult& r, std::vector<Violation>& out) {
    ConeMap k = map_cones(map, tol);
    Findings f{{}, {}, std::vector<char>(k.cones.size(), 0), std::vector<char>(map.in.triangles.size(), 0)};
    judge_vertices(map, k, mesh, loc, tol, r, f);
    judge_cones(k, r, f);
    // The footprints whose sums do not explain their mismatches grow by a ring at a time: an
    // extractor that leaves a fold as the map gives it may move a singularity out of it.
    std::vector<char> grow(k.cones.size(), 0);
    for (int round = 0; round <= kFootprintGrowth && !f.pending.empty(); ++round) {
        if (round > 0) regroup_footprints(map, k, grow, round * kFootprintStep);
        f.pending = explain_by_sums(k, f, r, grow);
    }
    // What is left inside a footprint grown to its limit is undecided too, unless the mesh is
    // more irregular there than the map: the map folds over too much there to tell where its
    // singularities go (on coarse maps, a footprint may hold most of the surface, or reach its
    // boundary, where the sums do not apply).
    std::vector<char> counted(k.footprints.size(), 0);
    const std::vector<std::int64_t> excess = excess_turns(k, f);
    for (auto& p : f.pending) {
        const std::int32_t fp = p.second.footprint(k);
        if (fp < 0) {
            add_capped(out, p.first.kind, std::move(p.first.message), p.first.element);
            continue;
        }
        const Footprint& x = k.footprints[static_cast<std::size_t>(fp)];
        const std::int64_t more = excess[static_cast<std::size_t>(fp)];
        add_capped(more > 0 ? out : r.undecided, p.first.kind,
                   p.first.message + "; in the fold-over footprint of input triangle " +
                       std::to_string(x.first_triangle) + " (" + std::to_string(x.triangles) +
                       " triangles), whose valences the mesh sums to " + std::to_string(mesh_turns_in(k, f, fp)) +
                       " quarter turns beyond regular, the map to " + num(x.cone_turns + x.correction) + ", with " +
                       std::to_string(more) + " quarter turns of irregularity beyond the map's and its folds'",
                   p.first.element);
        if (more > 0) continue;
        r.undecided_footprints += !counted[static_cast<std::size_t>(fp)];
        counted[static_cast<std::size_t>(fp)] = 1;
    }
    mark_undecided(k, counted, f);
    // The undecided share: the triangles of the footprints whose mismatches went undecided.
    for (std::size_t t = 0; t < f.undecided.size(); ++t) {
        if (!f.undecided[t]) continue;
        const auto &a = map.in.uvs[3 * t], &b = map.in.uvs[3 * t + 1], &c = map.in.uvs[3 * t + 2];
        ++r.undecided_triangles;
        r.undecided_uv_area += 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
    }
}

} // namespace qex::verify_detail

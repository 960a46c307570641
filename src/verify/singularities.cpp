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
// along iso-lines, a boundary vertex of the mesh has as many faces as the corner's quarter turns,
// less those of the cells round its grid point that the input's boundary cuts (a notch inside a
// cell): an extractor discards such partial faces, as the paper does.
#include "cones.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <tuple>

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

/// Where the input's boundary cuts cells round a grid point of the boundary (BoundaryCells), which
/// the extractor may leave without their faces (coverage does not require them either). Read only
/// where a boundary vertex has fewer faces than its corner, or a corner carries no vertex: few.
class Cuts {
public:
    Cuts(const LocatedMap& map, const std::vector<Located>& loc, double tol) : map_(map), loc_(loc), tol_(tol) {}

    /// Boundary vertex v has `faces` < n faces, n the corner's quarter turns: explained where the
    /// map has n cells round its grid point, at most as many faces are missing as cells are cut,
    /// and no other vertex lies on the grid point (a vertex split into copies along a slit from
    /// the boundary leaves each copy fewer faces too).
    bool explain(std::size_t v, int faces, int n) {
        const Located& L = loc_[v];
        const CellsRound c = round(L.triangle, L.grid);
        return c.read && c.cells == n && faces >= n - c.cut && alone(v, c);
    }

    /// Corner x of n quarter turns carries no vertex: explained where its n cells are all cut.
    bool explain_uncarried(const Cone& x, int n) {
        if (first_corner_.empty()) {
            first_corner_.assign(map_.in.positions.size(), SIZE_MAX);
            for (std::size_t c = 3 * map_.in.triangles.size(); c-- > 0;)
                first_corner_[static_cast<std::size_t>(map_.in.triangles[c / 3][c % 3])] = c;
        }
        const std::size_t c = first_corner_[static_cast<std::size_t>(x.vertex)];
        if (c == SIZE_MAX) return false;
        const auto& uv = map_.in.uvs[c];
        const GridPoint g{static_cast<std::int64_t>(std::nearbyint(uv[0])),
                          static_cast<std::int64_t>(std::nearbyint(uv[1]))};
        if (!(std::abs(uv[0] - static_cast<double>(g[0])) <= tol_ &&
              std::abs(uv[1] - static_cast<double>(g[1])) <= tol_))
            return false;
        const CellsRound r = round(static_cast<std::uint32_t>(c / 3), g);
        return r.read && r.cells == n && r.cut == n;
    }

private:
    CellsRound round(std::uint32_t t, const GridPoint& g) {
        if (!cells_) cells_ = std::make_unique<BoundaryCells>(map_, tol_);
        return cells_->round(t, g);
    }

    /// No vertex but v lies on the grid point (in the chart of any triangle near it).
    bool alone(std::size_t v, const CellsRound& c) {
        if (!indexed_) {
            for (std::size_t w = 0; w < loc_.size(); ++w)
                if (loc_[w].ok || loc_[w].surface_only || loc_[w].undecided)
                    on_.push_back({loc_[w].triangle, loc_[w].grid, w});
            std::sort(on_.begin(), on_.end());
            indexed_ = true;
        }
        for (const auto& [t, g] : c.at)
            for (auto it = std::lower_bound(on_.begin(), on_.end(), std::make_tuple(t, g, std::size_t{0}));
                 it != on_.end() && std::get<0>(*it) == t && std::get<1>(*it) == g; ++it)
                if (std::get<2>(*it) != v) return false;
        return true;
    }

    const LocatedMap& map_;
    const std::vector<Located>& loc_;
    double tol_;
    std::unique_ptr<BoundaryCells> cells_;
    std::vector<std::size_t> first_corner_; ///< per input vertex its first corner (when first asked)
    /// The located vertices by triangle and grid point (when first asked).
    std::vector<std::tuple<std::uint32_t, GridPoint, std::size_t>> on_;
    bool indexed_ = false;
};

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
                    double tol, Cuts& cuts, VerifyResult& r, Findings& f) {
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
        if (boundary && m.faces[v] < e.n && cuts.explain(v, m.faces[v], e.n)) continue; // cut cells' faces
        f.pending.push_back({{ViolationKind::ValenceMismatch,
                              std::string(boundary ? "boundary " : "") + "vertex " + std::to_string(v) + " has " +
                                  std::to_string(m.faces[v]) + " faces; the map has " + e.where,
                              static_cast<std::int64_t>(v)},
                             spot});
    }
}

void judge_cones(const ConeMap& k, Cuts& cuts, VerifyResult& r, Findings& f) {
    for (std::size_t c = 0; c < k.cones.size(); ++c) {
        const Cone& x = k.cones[c];
        int n = 0;
        const bool read = x.valence(n), singular = x.singular(), corner = x.boundary_corner();
        r.map_cones += singular;
        if (x.interior && !read) ++r.unread_cones;
        if (!(singular || corner) || f.carried[c]) continue;
        if (corner && cuts.explain_uncarried(x, n)) continue; // every cell round it cut: no face there
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
    Cuts cuts(map, loc, tol);
    judge_vertices(map, k, mesh, loc, tol, cuts, r, f);
    judge_cones(k, cuts, r, f);
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

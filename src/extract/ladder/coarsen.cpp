// Coarsening: users make quads smaller by multiplying a map's UVs by K, and a fold-over then
// covers K^2 times more cells, more than the repair may re-embed. When no rung gives a valid mesh
// at the map's own scale (or its mesh has more quads than the map's area) and the map is twice
// an integer-grid map laid from some grid point, the ladder runs on the map halved (then / 4, ...),
// and the first valid mesh there is split back onto the given map (split_onto_map), where it
// must pass the checker.
#include "ladder.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

namespace qex::detail {

// ============================================================================ divisible maps

bool map_divisible_by(const TriMesh& m, const std::vector<std::array<int, 2>>& features, std::int64_t k,
                      IPoint& origin) {
    const auto residue = [k](double x, std::int64_t& r) {
        if (!(std::abs(x) < 0x1p52) || x != std::floor(x)) return false;
        r = ((static_cast<std::int64_t>(x) % k) + k) % k;
        return true;
    };
    // The origin's residues, per coordinate: fixed by the first singularity or iso-line met;
    // every other must agree.
    std::array<std::int64_t, 2> o{-1, -1};
    const auto agree = [&](int d, double x) {
        std::int64_t r = 0;
        if (!residue(x, r)) return false;
        if (o[static_cast<std::size_t>(d)] < 0) o[static_cast<std::size_t>(d)] = r;
        return o[static_cast<std::size_t>(d)] == r;
    };
    for (int v = 0; v < m.num_vertices; ++v)
        if ((m.map.singular[v] || (!m.on_boundary[v] && m.map.valence[v] != 4)) && m.fan_start[v] >= 0) {
            const Point2& u = m.uv[m.fan_start[v]];
            if (!agree(0, u[0]) || !agree(1, u[1])) return false;
        }
    std::vector<std::array<int, 2>> feature_set;
    for (const auto& e : features) feature_set.push_back({std::min(e[0], e[1]), std::max(e[0], e[1])});
    std::sort(feature_set.begin(), feature_set.end());
    // Every transition u -> R u + t between charts, with u = k u' + origin in both, must be one
    // of the coarse grid: R origin + t - origin a multiple of k. A translation must be one
    // anyway; the turning ones, each once (by their residues), decide an origin that neither a
    // singularity nor an iso-line fixed: the first that suits them all.
    std::vector<std::array<std::int64_t, 3>> turning;
    for (int h = 0; h < 3 * m.num_faces(); ++h) {
        if (m.opp[h] >= 0) {
            const GridAutomorphism& t = m.map.transition[h];
            const std::int64_t tx = ((t.tx % k) + k) % k, ty = ((t.ty % k) + k) % k;
            if (t.r == 0 && (tx != 0 || ty != 0)) return false;
            if (t.r != 0) turning.push_back({t.r, tx, ty});
        }
        const int a = m.input_vertex[m.origin(h)], b = m.input_vertex[m.target(h)];
        const bool feature = std::binary_search(feature_set.begin(), feature_set.end(),
                                                std::array<int, 2>{std::min(a, b), std::max(a, b)});
        if (m.opp[h] >= 0 && !feature) continue;
        // A boundary or feature edge on an iso-line of the coarse grid (one on none would lose
        // the cells it cuts at the coarse scale, K - 1 rows of them).
        const Point2 &p = m.uv[h], &q = m.uv[TriMesh::next(h)];
        bool on_line = false;
        for (int d = 0; d < 2 && !on_line; ++d) on_line = p[d] == q[d] && agree(d, p[d]);
        if (!on_line) return false;
    }
    std::sort(turning.begin(), turning.end());
    turning.erase(std::unique(turning.begin(), turning.end()), turning.end());
    const auto suits = [&](const IPoint& c) {
        for (const auto& [r, tx, ty] : turning) {
            const IPoint image = GridAutomorphism{static_cast<int>(r), tx, ty}(c);
            if ((image[0] - c[0]) % k != 0 || (image[1] - c[1]) % k != 0) return false;
        }
        return true;
    };
    // Residues a free coordinate may take (all of them, up to a bound on the search).
    const std::int64_t free_span = k <= 64 ? k : 1;
    for (std::int64_t x = o[0] >= 0 ? o[0] : 0; x < (o[0] >= 0 ? o[0] + 1 : free_span); ++x)
        for (std::int64_t y = o[1] >= 0 ? o[1] : 0; y < (o[1] >= 0 ? o[1] + 1 : free_span); ++y)
            if (suits({x, y})) {
                origin = {x, y};
                return true;
            }
    return false;
}

namespace {

// ============================================================================ the ladder on the map halved

/// How far (relative to the map's largest coordinate, at least 1) sanitizing the map at the
/// coarse scale may leave a corner from the given map's sanitized value: truncation to another
/// power of two.
constexpr double kTruncationSpread = 0x1p-40;

/// Per factor k = 2, 4, ... up to Options::max_coarsening (bounded as grid_scale is: 2^20) while
/// the sanitized map m is k times an integer-grid map: the grid point the coarse grid is laid
/// from (its origin).
std::vector<IPoint> coarse_origins(const TriMesh& m, const Input& input, const Options& options) {
    const int most = std::min(options.max_coarsening, 1 << 20);
    std::vector<IPoint> origins;
    const std::vector<std::array<int, 2>> features = feature_edges(m, input, options);
    IPoint origin{0, 0};
    for (int k = 2; k <= most && map_divisible_by(m, features, k, origin); k *= 2) origins.push_back(origin);
    return origins;
}

/// How far sanitizing the map at a coarse scale may leave a corner from the given map's
/// sanitized value `given`. Sanitizing truncates a fan to a power of two set by its largest
/// coordinate, in any chart: the bound is taken from the map's largest.
double truncation_spread(const std::vector<std::array<double, 2>>& given) {
    double largest = 1.0;
    for (const auto& uv : given)
        if (!std::isnan(uv[0])) largest = std::max({largest, std::abs(uv[0]), std::abs(uv[1])});
    return kTruncationSpread * largest;
}

/// The input with its map at the coarse scale: u = k u' + o, from the sanitized map `given`
/// (whose values, truncated, move to the origin exactly, where the given ones could round), then
/// divided by a power of two (exact). Corners of triangles collapsed away keep the given UVs,
/// moved and divided alike.
void divide_map(const Input& input, const std::vector<std::array<double, 2>>& given, int k, const IPoint& o,
                Input& coarse) {
    const double inverse = 1.0 / k;
    for (std::size_t c = 0; c < coarse.uvs.size(); ++c) {
        const std::array<double, 2>& u = std::isnan(given[c][0]) ? input.uvs[c] : given[c];
        coarse.uvs[c] = {(u[0] - static_cast<double>(o[0])) * inverse, (u[1] - static_cast<double>(o[1])) * inverse};
    }
}

/// Whether the sanitized map of the coarse mesh, times k plus o (`map`), is the given map's
/// outside what its repair changed: the same triangles collapsed away, and no corner moved beyond
/// `spread` (moved to another origin, a fan's values can be truncated a few units in the last
/// place otherwise; a snapped singularity or a rounded seam moves by far more).
bool same_sanitized_map(const QuadMesh& coarse, const std::vector<std::array<double, 2>>& map,
                        const std::vector<std::array<double, 2>>& given, double spread) {
    std::vector<char> repaired(map.size() / 3, 0);
    for (const std::int32_t t : coarse.map_repaired)
        if (t >= 0 && static_cast<std::size_t>(t) < repaired.size()) repaired[static_cast<std::size_t>(t)] = 1;
    bool same = map.size() == given.size();
    for (std::size_t c = 0; c < map.size() && same; ++c) {
        if (repaired[c / 3]) continue;
        same = std::isnan(map[c][0]) == std::isnan(given[c][0]);
        for (int d = 0; d < 2 && same && !std::isnan(map[c][0]); ++d)
            same = std::abs(map[c][d] - given[c][d]) <= spread;
    }
    return same;
}

/// The valid mesh of the map at the coarse scale (`attempt`) split k x k onto the given map, into
/// `split`, and the checker's verdict on it in `check` (not valid if it could not be split):
/// stages place_on_given_map and check, timed in the attempt's report.
void split_and_check(const Input& input, const Options& options, const std::vector<std::array<double, 2>>& given,
                     double spread, int k, const IPoint& o, Result& attempt, QuadMesh& split, VerifyResult& check) {
    // Its sanitized map must be the given map's, moved and divided, outside what its repair
    // changed (same_sanitized_map). The mesh carries this map, which the checker verifies exactly.
    std::vector<std::array<double, 2>> map = attempt.mesh.map_uvs;
    for (auto& uv : map) uv = {k * uv[0] + static_cast<double>(o[0]), k * uv[1] + static_cast<double>(o[1])};
    const bool same = same_sanitized_map(attempt.mesh, map, given, spread);
    StageTimer timer(attempt.report);
    if (same && split_onto_map(input, map, attempt.mesh, k, o, split)) {
        timer.done(Stage::place_on_given_map);
        VerifyOptions verify_options;
        verify_options.threads = options.threads;
        check = verify(input, split, verify_options);
        if (check.valid) {
            // Its faces' local UVs are the split's own making, and provenance mode takes them
            // as given: the mesh must also pass the oracle that judges it against the given
            // map alone, as `qex check --param` does (fold-over regions judged on the
            // surface), or everywhere if it came from a relaxed rung (which must hold on the
            // given map everywhere, as judge() requires at any scale).
            const std::vector<Violation> located =
                located_violations(input, split, verify_options, !relaxed_rung(attempt.report.rung));
            check.violations.insert(check.violations.end(), located.begin(), located.end());
            check.valid = check.violations.empty();
        }
        timer.done(Stage::check);
    }
}

/// Makes `attempt`, its mesh replaced by `split` (accepted: `check`), the result of coarsening by
/// k from o, with the explanation of why the map at its own scale (`result`) gave way to it.
void take_coarsened(QuadMesh&& split, VerifyResult&& check, int k, const IPoint& o, Result& attempt, Result& result) {
    attempt.mesh = std::move(split);
    attempt.check = std::move(check);
    attempt.report.coarsening = k;
    attempt.report.signed_uv_area *= static_cast<double>(k) * k; // the given map's, as the quads are
    attempt.report.check_violations = 0;
    const std::string f = std::to_string(k);
    attempt.report.explanations.insert(
        attempt.report.explanations.begin(),
        scale_explanation(DefectKind::MapCoarsened, result,
                          "the map with its UVs divided by " + f + " (from grid point (" + std::to_string(o[0]) + ", " +
                              std::to_string(o[1]) +
                              ")) is an integer-grid map too (its sanitized map is this one's, so divided), "
                              "and gives one: each of its quads is split into " +
                              f + " x " + f + ", every new vertex on its grid point of this map"));
    attempt.report.stage_seconds = std::move(result.report.stage_seconds);
    result = std::move(attempt);
}

} // namespace

bool over_covered(const Result& r) {
    return static_cast<double>(r.mesh.faces.size()) > static_cast<double>(std::llround(r.report.signed_uv_area));
}

bool extract_coarsened(const Input& input, const Options& options, Result& result) {
    TriMesh m;
    if (!sanitize_as_given(input, options, m, result.report)) return false;
    const std::vector<IPoint> origins = coarse_origins(m, input, options);
    if (origins.empty()) return false;
    const std::vector<std::array<double, 2>> given = take_map(m, input);
    const double spread = truncation_spread(given);
    Input coarse = input;
    for (std::size_t i = 0; i < origins.size(); ++i) {
        const int k = 2 << i;
        const IPoint o = origins[i];
        divide_map(input, given, k, o, coarse);
        StageTimer::hook_scale = 1;
        Result attempt = extract_at_scale(coarse, options);
        if (!attempt.ok() || !attempt.check.valid) {
            add_stage_seconds(attempt.report, result.report);
            if (!attempt.ok()) return false;
            continue;
        }
        QuadMesh split;
        VerifyResult check;
        split_and_check(input, options, given, spread, k, o, attempt, split, check);
        add_stage_seconds(attempt.report, result.report);
        if (!check.valid) continue;
        take_coarsened(std::move(split), std::move(check), k, o, attempt, result);
        return true;
    }
    return false;
}

} // namespace qex::detail

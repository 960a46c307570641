// The extraction driver: the fallback ladder, and for each rung the pipeline's stages in the
// order of the stage table (pipeline.h), each timed under its own name.
#include "pipeline.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <limits>
#include <string>

namespace qex::detail {

// ============================================================================ timing

thread_local const std::function<void(const char*, int)>* StageTimer::hook = nullptr;
thread_local int StageTimer::hook_scale = 1;

StageTimer::StageTimer(Report& report) : report_(report), last_(std::chrono::steady_clock::now()) {}

void StageTimer::done(Stage stage) {
    const auto now = std::chrono::steady_clock::now();
    const double seconds = std::chrono::duration<double>(now - last_).count();
    last_ = now;
    const char* name = stage_name(stage);
    if (hook) (*hook)(name, hook_scale);
    for (auto& [label, total] : report_.stage_seconds)
        if (label == name) {
            total += seconds;
            return;
        }
    report_.stage_seconds.emplace_back(name, seconds);
}

// ============================================================================ sanitization rounds

Error sanitize_until_stable(TriMesh& m, const Input& input, const std::vector<std::array<int, 2>>& features,
                            Report& report, StageTimer& timer, int max_rounds, SeamPolicy seams) {
    // Branch points (r = 0 singularities) are decided by angles. Without given valences they are
    // snapped only once the truncated map's degenerate edges are collapsed: before, a noisy
    // sliver next to a vertex can add a full turn to its angle sum.
    bool branch_points = !input.valences.empty();
    for (int round = 0;; ++round) {
        compute_transitions(m);
        if (round == 0)
            if (Error e = check_seams(m, seams, report); e.code != ErrorCode::None) return e;
        timer.done(Stage::compute_transitions);
        count_valences(m);
        timer.done(Stage::count_valences);
        std::int64_t deferred = 0;
        if (Error e = sanitize(m, input.valences, features, report, branch_points, &deferred);
            e.code != ErrorCode::None)
            return e;
        timer.done(Stage::sanitize);
        // The last round ends on a sanitized map: a collapse after it would leave the map
        // state of the old connectivity (degenerate edges left over are handled downstream).
        if (round == max_rounds) return {};
        std::int64_t collapsed = 0;
        if (Error e = collapse(m, collapsed); e.code != ErrorCode::None) return e;
        timer.done(Stage::collapse);
        report.collapsed_edges += collapsed;
        if (collapsed == 0) {
            if (branch_points || deferred == 0) return {};
            branch_points = true; // one more pass, now on the collapsed map
        }
    }
}

// ============================================================================ coarsening

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

// ============================================================================ one rung

/// The fallback ladder. Each rung re-runs the pipeline from the validated, collapsed mesh.
struct Rung {
    const char* name;
    bool repair;        ///< stage repair runs (certified: the mesh carries the repaired map)
    int untangle_rings; ///< > 0: stage untangle relaxes the map first (uncertified)
    int untangle_iterations;
};
constexpr Rung kLadder[] = {
    // 1. The sanitized map with its fold-over regions re-embedded (certified), then the paper's method.
    {"repaired", true, 0, 0},
    // 2. The paper's method, and its local handling of fold-overs, on the map as given.
    {"as-given", false, 0, 0},
    // 3, 4. Last resorts without a certificate: relax the folded regions (one ring, then three),
    // extract, and move the mesh back onto the given map, where the checker must accept it.
    {"untangled-1", false, 1, 30},
    {"untangled-3", false, 3, 100},
};

/// Whether the rung named `name` (Report::rung) relaxed the map: a last resort.
bool relaxed_rung(const std::string& name) {
    for (const Rung& r : kLadder)
        if (name == r.name) return r.untangle_rings > 0;
    return false;
}

/// The feature edges to snap: the input's, and every boundary edge with Options::snap_boundary.
std::vector<std::array<int, 2>> feature_edges(const TriMesh& m, const Input& input, const Options& options) {
    std::vector<std::array<int, 2>> features = input.feature_edges;
    if (options.snap_boundary)
        for (int h = 0; h < 3 * m.num_faces(); ++h)
            if (m.opp[h] < 0) features.push_back({m.input_vertex[m.origin(h)], m.input_vertex[m.target(h)]});
    return features;
}

/// What the sanitized map tells the report: flipped and degenerate triangles, signed UV area.
void report_map(const TriMesh& m, Report& report) {
    double area2 = 0.0;
    for (int f = 0; f < m.num_faces(); ++f) {
        report.flipped_triangles += m.map.face_sign[f] < 0;
        report.degenerate_triangles += m.map.face_sign[f] == 0;
        const auto &a = m.uv[3 * f], &b = m.uv[3 * f + 1], &c = m.uv[3 * f + 2];
        area2 += (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    }
    report.signed_uv_area = 0.5 * area2;
}

/// Refinement stops short of this many quads: a map with many quads is not too coarse, and
/// refining it would only multiply the cost.
constexpr double kMaxRefinedQuads = 200'000;

/// The sanitized map before stage repair and after it, with what the repair reported: kept from
/// the map at its own scale for its refinements. Refining multiplies the UVs by a power of two,
/// exactly, and leaves the repair's problem as it was (the same triangles, rims and
/// singularities), so the repair is not run again where the refined map's sanitized state is
/// exactly the kept one times the factor.
struct RepairMemo {
    bool filled = false;
    // Before the repair: connectivity, UVs and map state.
    std::vector<std::array<int, 3>> tri;
    std::vector<int> input_triangle, input_vertex, corner_vertex;
    std::vector<Point2> sanitized;
    std::vector<GridAutomorphism> transitions;
    std::vector<char> singular;
    std::vector<int> valence, winding_valence;
    // After it.
    std::vector<Point2> repaired;
    std::vector<GridAutomorphism> repaired_transitions;
    std::vector<char> repaired_singular;
    std::vector<int> repaired_valence, repaired_winding_valence;
    RepairOutcome outcome;
    std::vector<Defect> explanations; ///< the ones the repair added (merged singularities)
};

/// One attempt at the ladder: the map's own scale, or a refinement of it.
struct AtScale {
    /// The UVs times this power of two (1: the map as given).
    std::int64_t factor = 1;
    /// The map at its own scale passed check_seams: its solver noise, multiplied with it, can
    /// exceed the check's bound and is noise still, so a refinement's seams are trusted.
    bool seams_checked = false;
    /// Factor 1: filled by the repair, if one runs. Larger: the repair it holds is taken, times
    /// the factor, where it applies (RepairMemo).
    RepairMemo* memo = nullptr;
};

/// The transitions of every half-edge of m.
std::vector<GridAutomorphism> all_transitions(const TriMesh& m) {
    std::vector<GridAutomorphism> out(m.map.transition.size());
    for (std::size_t h = 0; h < out.size(); ++h) out[h] = m.map.transition[h];
    return out;
}

/// A UV of the map at its own scale, `factor` times (exact for a power of two; NaN stays NaN).
Point2 times(const Point2& u, std::int64_t factor) {
    const auto k = static_cast<double>(factor);
    return {k * u[0], k * u[1]};
}

/// A transition of the map at its own scale, in the map `factor` times it.
GridAutomorphism times(const GridAutomorphism& g, std::int64_t factor) { return {g.r, factor * g.tx, factor * g.ty}; }

/// Whether m's sanitized state is exactly the memo's times `factor`.
bool memo_applies(const TriMesh& m, const RepairMemo& memo, std::int64_t factor) {
    if (!memo.filled || m.tri != memo.tri || m.input_triangle != memo.input_triangle ||
        m.input_vertex != memo.input_vertex || m.corner_vertex != memo.corner_vertex ||
        m.uv.size() != memo.sanitized.size() || m.map.singular != memo.singular || m.map.valence != memo.valence ||
        m.map.winding_valence != memo.winding_valence || m.map.transition.size() != memo.transitions.size())
        return false;
    for (std::size_t c = 0; c < m.uv.size(); ++c) {
        const Point2 u = times(memo.sanitized[c], factor);
        for (int d = 0; d < 2; ++d)
            if (m.uv[c][d] != u[d] && !(std::isnan(m.uv[c][d]) && std::isnan(u[d]))) return false;
    }
    for (std::size_t h = 0; h < memo.transitions.size(); ++h)
        if (!(m.map.transition[h] == times(memo.transitions[h], factor))) return false;
    return true;
}

/// Stage repair on the sanitized map m, or its result at the map's own scale taken from
/// `scale.memo` (see RepairMemo), which the repair at that scale fills.
RepairOutcome repair_at_scale(TriMesh& m, const std::vector<std::array<int, 2>>& features, bool valences_given,
                              const AtScale& scale, Report& report) {
    RepairMemo* memo = scale.memo;
    if (memo && scale.factor > 1 && memo_applies(m, *memo, scale.factor)) {
        for (std::size_t c = 0; c < m.uv.size(); ++c) m.uv[c] = times(memo->repaired[c], scale.factor);
        for (std::size_t h = 0; h < memo->repaired_transitions.size(); ++h)
            m.map.transition.set(h, times(memo->repaired_transitions[h], scale.factor));
        m.map.singular = memo->repaired_singular;
        m.map.valence = memo->repaired_valence;
        m.map.winding_valence = memo->repaired_winding_valence;
        m.map.face_sign = triangle_signs(m);
        report.explanations.insert(report.explanations.end(), memo->explanations.begin(), memo->explanations.end());
        return memo->outcome;
    }
    // No refinement can follow when doubling the map takes it past kMaxRefinedQuads.
    if (!memo || scale.factor != 1 || std::abs(report.signed_uv_area) * 4 > kMaxRefinedQuads)
        return repair(m, features, valences_given, report);
    *memo = RepairMemo{};
    memo->tri = m.tri;
    memo->input_triangle = m.input_triangle;
    memo->input_vertex = m.input_vertex;
    memo->corner_vertex = m.corner_vertex;
    memo->sanitized = m.uv;
    memo->transitions = all_transitions(m);
    memo->singular = m.map.singular;
    memo->valence = m.map.valence;
    memo->winding_valence = m.map.winding_valence;
    const std::size_t explained = report.explanations.size();
    RepairOutcome outcome = repair(m, features, valences_given, report);
    memo->repaired = m.uv;
    memo->repaired_transitions = all_transitions(m);
    memo->repaired_singular = m.map.singular;
    memo->repaired_valence = m.map.valence;
    memo->repaired_winding_valence = m.map.winding_valence;
    memo->outcome = outcome;
    memo->explanations.assign(report.explanations.begin() + static_cast<std::ptrdiff_t>(explained),
                              report.explanations.end());
    memo->filled = true;
    return outcome;
}

/// Stages untangle (last resorts) to repair: the map, ready for extraction. `repaired_faces`: the
/// triangles whose UVs the repair changed. `scale`: the attempt's refinement factor (solver
/// noise is that many times the map's own) and the repair kept for its refinements.
Error prepare_map(TriMesh& m, const Input& input, const Options& options, const Rung& rung, Report& report,
                  StageTimer& timer, std::vector<int>& repaired_faces, const AtScale& scale = {}) {
    m.noise_scale = static_cast<double>(scale.factor);
    if (rung.untangle_rings > 0) {
        compute_transitions(m);
        count_valences(m);
        (void)untangle(m, rung.untangle_rings, rung.untangle_iterations);
        timer.done(Stage::untangle);
    }
    const std::vector<std::array<int, 2>> features = feature_edges(m, input, options);
    const SeamPolicy seams = rung.untangle_rings > 0 || scale.seams_checked ? SeamPolicy::Trusted
                             : options.round_inconsistent_seams             ? SeamPolicy::Rounded
                                                                            : SeamPolicy::Checked;
    if (Error e = sanitize_until_stable(m, input, features, report, timer, kMaxSanitizeRounds, seams);
        e.code != ErrorCode::None)
        return e;
    count_valences(m, true); // on the sanitized map, for lost-edge detection at singularities
    if (!input.valences.empty())
        for (int v = 0; v < m.num_vertices; ++v) m.map.valence[v] = input.valences[m.input_vertex[v]];
    timer.done(Stage::count_valences);
    report_map(m, report);
    timer.done(Stage::sanitize);
    if (rung.repair && report.flipped_triangles + report.degenerate_triangles > 0) {
        RepairOutcome outcome = repair_at_scale(m, features, !input.valences.empty(), scale, report);
        explain_unrepaired(m, outcome, report);
        report.repaired_regions = outcome.regions_repaired;
        report.unrepaired_regions = static_cast<std::int64_t>(outcome.unrepaired.size());
        report.repaired_triangles = static_cast<std::int64_t>(outcome.repaired_faces.size());
        for (int f = 0; f < m.num_faces(); ++f) report.flipped_after_repair += m.map.face_sign[f] <= 0;
        repaired_faces = std::move(outcome.repaired_faces);
        timer.done(Stage::repair);
    } else {
        report.flipped_after_repair = report.flipped_triangles + report.degenerate_triangles;
    }
    return {};
}

/// Why a q-vertex found no q-port, from the triangles it lies on: on a vertex, its fan and how
/// many of them are flipped or degenerate; on an edge or in a triangle, whether they are all
/// degenerate.
std::string portless_why(const TriMesh& m, const QVertex& v) {
    const auto sign = [&](int f) { return m.map.face_sign[static_cast<std::size_t>(f)]; };
    if (v.kind == QVertexKind::Vertex) {
        int triangles = 0, flipped = 0, degenerate = 0;
        for (int h = m.fan_start[v.element], k = 0; h >= 0 && k < m.fan_size[v.element]; h = m.cw(h), ++k) {
            ++triangles;
            flipped += sign(TriMesh::face(h)) < 0;
            degenerate += sign(TriMesh::face(h)) == 0;
        }
        return "on input vertex " + std::to_string(m.input_vertex[v.element]) + ", whose fan of " +
               std::to_string(triangles) + " triangles (" + std::to_string(flipped) + " flipped, " +
               std::to_string(degenerate) + " degenerate) starts no iso-line";
    }
    const int f = v.kind == QVertexKind::Edge ? TriMesh::face(v.element) : v.element;
    const int o = v.kind == QVertexKind::Edge ? m.opp[v.element] : -1;
    const bool degenerate = sign(f) == 0 && (o < 0 || sign(TriMesh::face(o)) == 0);
    return std::string(v.kind == QVertexKind::Edge ? "on an edge" : "inside a triangle") +
           (degenerate ? " of degenerate triangles only" : " whose triangles start no iso-line");
}

/// Geometry extraction (Section 4): stages generate_qvertices and enumerate_ports.
Error extract_geometry(const TriMesh& m, const Options& options, QState& q, Report& report, StageTimer& timer) {
    if (Error e = generate_qvertices(m, options, q); e.code != ErrorCode::None) return e;
    for (const auto& v : q.qvertices) {
        report.qvertices_on_vertices += v.kind == QVertexKind::Vertex;
        report.qvertices_on_edges += v.kind == QVertexKind::Edge;
        report.qvertices_in_faces += v.kind == QVertexKind::Face;
    }
    timer.done(Stage::generate_qvertices);
    enumerate_ports(m, q);
    report.ports = static_cast<std::int64_t>(q.ports.size());
    for (const QVertex& v : q.qvertices)
        if (v.num_ports == 0)
            report.defects.push_back({DefectKind::PortlessQVertex,
                                      "the q-vertex at grid point (" + std::to_string(v.grid[0]) + ", " +
                                          std::to_string(v.grid[1]) + ") has no q-port: " + portless_why(m, v),
                                      m.input_triangle[v.chart],
                                      -1,
                                      {v.grid[0], v.grid[1]},
                                      std::nullopt});
    timer.done(Stage::enumerate_ports);
    return {};
}

/// Connectivity extraction (Section 5): stages trace_ports, extract_faces and merge_vertices.
/// Returns the output faces, flat (merge_vertices).
FaceWalks extract_connectivity(const TriMesh& m, const Options& options, QState& q, QuadMesh& mesh, Report& report,
                               StageTimer& timer) {
    trace_ports(m, options, q, report);
    timer.done(Stage::trace_ports);
    FaceWalks faces = extract_faces(m, q, report);
    timer.done(Stage::extract_faces);
    // Merging needs the q-vertices only: the ports and traces (two thirds of the q-state on
    // maps with many quads) are released first.
    std::vector<Port>().swap(q.ports);
    std::vector<Connection>().swap(q.connections);
    std::vector<char>().swap(q.into_boundary);
    std::vector<int>().swap(q.edge_first);
    std::vector<int>().swap(q.face_first);
    FaceWalks out = merge_vertices(m, q, std::move(faces), options, mesh, report);
    timer.done(Stage::merge_vertices);
    return out;
}

/// The sanitized map, per input corner, for the checker (NaN for triangles collapsed away).
/// Only the map and the triangle numbering of the working mesh are still needed: the rest is
/// released first, and when no triangle was collapsed away the map is handed over uncopied.
std::vector<std::array<double, 2>> take_map(TriMesh& m, const Input& input) {
    std::vector<Point2> uv = std::move(m.uv);
    std::vector<int> input_triangle = std::move(m.input_triangle);
    m = TriMesh{};
    bool same_numbering = input_triangle.size() == input.triangles.size();
    for (std::size_t f = 0; f < input_triangle.size() && same_numbering; ++f)
        same_numbering = input_triangle[f] == static_cast<int>(f);
    if (same_numbering) return uv;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    std::vector<std::array<double, 2>> map(input.uvs.size(), {nan, nan});
    for (std::size_t f = 0; f < input_triangle.size(); ++f)
        for (std::size_t k = 0; k < 3; ++k) map[3 * static_cast<std::size_t>(input_triangle[f]) + k] = uv[3 * f + k];
    return map;
}

/// One rung on the validated, collapsed mesh `m`, up to stage canonicalize. Returns false on an
/// input error (in result.error), which no rung can help.
bool run_rung(TriMesh m, const Input& input, const Options& options, const Rung& rung, Result& result,
              const AtScale& scale) {
    Report& report = result.report;
    StageTimer timer(report);
    std::vector<int> repaired_faces;
    if ((result.error = prepare_map(m, input, options, rung, report, timer, repaired_faces, scale)).code !=
        ErrorCode::None)
        return false;
    std::vector<std::int32_t> certificate; // the repaired triangles, by input index
    for (const int f : repaired_faces) certificate.push_back(m.input_triangle[f]);
    std::sort(certificate.begin(), certificate.end());
    if (rung.repair && repaired_faces.empty()) report.rung = "as-given"; // nothing to repair: the map as given
    QState q;
    if ((result.error = extract_geometry(m, options, q, report, timer)).code != ErrorCode::None) return false;
    FaceWalks faces = extract_connectivity(m, options, q, result.mesh, report, timer);
    q = QState{};
    result.mesh.map_uvs = take_map(m, input);
    result.mesh.map_repaired = std::move(certificate);
    if (options.canonical_order) {
        const std::vector<int> new_index = canonicalize(result.mesh, std::move(faces), thread_count(options.threads));
        for (Defect& d : report.defects)
            if (d.output_face >= 0) d.output_face = new_index[static_cast<std::size_t>(d.output_face)];
    } else {
        set_faces(result.mesh, faces);
    }
    timer.done(Stage::canonicalize);
    return true;
}

/// The violations of `mesh` judged without its provenance against the given map, as
/// `qex check --param` judges any extractor's mesh (fold-over regions on the surface only, or not).
std::vector<Violation> located_violations(const Input& input, const QuadMesh& mesh, VerifyOptions options,
                                          bool fold_regions) {
    QuadMesh bare;
    bare.positions = mesh.positions;
    bare.faces = mesh.faces;
    options.fold_regions = fold_regions;
    return verify(input, bare, options).violations;
}

/// Whether the checker accepts `mesh` against the map it carries, and the oracle without
/// provenance against the given map too (fold-over regions judged on the surface, or everywhere
/// after a relaxed rung), as `qex check --param` would; its verdict in `check`.
bool accepted(const Input& input, const QuadMesh& mesh, bool relaxed, const VerifyOptions& verify_options,
              VerifyResult& check) {
    check = verify(input, mesh, verify_options);
    return check.valid && located_violations(input, mesh, verify_options, !relaxed).empty();
}

/// Keeps `mended` (with `explanations` for what was done to it) as the attempt's mesh.
void keep(QuadMesh&& mended, VerifyResult&& check, std::vector<Defect>&& explanations, Result& attempt) {
    attempt.mesh = std::move(mended);
    attempt.check = std::move(check);
    for (Defect& d : explanations) attempt.report.explanations.push_back(std::move(d));
}

/// Stage close_holes, on a mesh the checker rejected: the holes its face walks left, closed by the
/// grid cells their rims enclose. Kept (with `done`, what was done to `mesh` before) only if it
/// is then accepted(). `mesh` is read only before the result is kept, so it may be attempt.mesh.
bool close_holes_if_accepted(const Input& input, const QuadMesh& mesh, bool relaxed,
                             const VerifyOptions& verify_options, const std::vector<Defect>& done, Result& attempt) {
    // Rim vertices read as regular first; then, if that is rejected, as their fans wind (a
    // valence-3 and a valence-5 vertex on one rim cancel in the first reading).
    std::vector<std::vector<int>> first_faces; // the first reading's result, not judged twice
    for (const bool wound_first : {false, true}) {
        QuadMesh closed = mesh;
        std::vector<Defect> explanations = close_holes(input, closed, wound_first);
        if (explanations.empty() || (wound_first && closed.faces == first_faces)) continue;
        if (!wound_first) first_faces = closed.faces;
        VerifyResult check;
        if (!accepted(input, closed, relaxed, verify_options, check)) continue;
        explanations.insert(explanations.begin(), done.begin(), done.end());
        keep(std::move(closed), std::move(check), std::move(explanations), attempt);
        return true;
    }
    return false;
}

/// Stages separate_sheets and close_holes, on a mesh the checker rejected. Where the checker
/// found an edge of more than two face sides, the edges that join sheets of a fold-over are cut
/// (of an edge's ends, the smaller first where the order is free, then the larger); each such
/// mesh is kept if it is accepted(), or once its holes are closed too. Else the holes of the mesh
/// as it is are closed (close_holes_if_accepted).
void mend_if_accepted(const Input& input, bool relaxed, const VerifyOptions& verify_options, StageTimer& timer,
                      Result& attempt) {
    const bool joined = std::any_of(attempt.check.violations.begin(), attempt.check.violations.end(),
                                    [](const Violation& v) { return v.kind == ViolationKind::NonManifoldEdge; });
    for (const bool larger_end_first : {false, true}) {
        if (!joined) break;
        QuadMesh separated = attempt.mesh;
        std::vector<Defect> explanations = separate_sheets(input, separated, larger_end_first);
        timer.done(Stage::separate_sheets);
        if (explanations.empty()) continue;
        VerifyResult check;
        const bool ok = accepted(input, separated, relaxed, verify_options, check);
        timer.done(Stage::separate_sheets);
        if (ok) {
            keep(std::move(separated), std::move(check), std::move(explanations), attempt);
            return;
        }
        const bool closed = close_holes_if_accepted(input, separated, relaxed, verify_options, explanations, attempt);
        timer.done(Stage::close_holes);
        if (closed) return;
    }
    (void)close_holes_if_accepted(input, attempt.mesh, relaxed, verify_options, {}, attempt);
    timer.done(Stage::close_holes);
}

/// Stages place_on_given_map (last resorts) and check: the checker's verdict on the rung's mesh,
/// against the map it carries (with the repair's certificate, which the checker verifies on its
/// own). A relaxed rung's mesh is moved onto the given map and must pass there.
void judge(const Input& input, const Options& options, const Rung& rung,
           const std::vector<std::array<double, 2>>& given_map, Result& attempt) {
    StageTimer timer(attempt.report);
    const bool relaxed = rung.untangle_rings > 0;
    if (relaxed && !given_map.empty()) {
        // Every vertex moves onto its grid point in the given (sanitized) map, so the mesh is
        // judged against that map.
        attempt.report.unplaced_vertices = place_on_given_map(input, given_map, attempt.mesh);
        timer.done(Stage::place_on_given_map);
    }
    VerifyOptions verify_options;
    verify_options.threads = options.threads;
    attempt.check = verify(input, attempt.mesh, verify_options);
    timer.done(Stage::check);
    if (!attempt.check.valid) mend_if_accepted(input, relaxed, verify_options, timer, attempt);
    if (relaxed && attempt.check.valid) {
        // And it must pass the oracle that judges it against the given map alone (as
        // `qex check` would), everywhere, or the rung is rejected.
        for (const Violation& v : located_violations(input, attempt.mesh, verify_options, false))
            attempt.check.violations.push_back(
                {v.kind, v.message + " (against the given map; this rung relaxed it)", v.element});
        attempt.check.valid = attempt.check.violations.empty();
    } else if (attempt.check.valid && attempt.report.near_ghost_faces_cancelled > 0) {
        // Merged clones of two sheets take one clone's place: the faces round it must still join
        // neighbouring grid points on the given map, as `qex check --param` judges (fold-over
        // regions on the surface only).
        for (const Violation& v : located_violations(input, attempt.mesh, verify_options, true))
            attempt.check.violations.push_back(
                {v.kind, v.message + " (against the given map, without provenance; clones of two sheets were merged)",
                 v.element});
        attempt.check.valid = attempt.check.violations.empty();
    }
    attempt.report.check_violations = static_cast<std::int64_t>(attempt.check.violations.size());
    timer.done(Stage::check);
}

/// A fresh result for rung `r`, with what stages validate and collapse reported, and the stage
/// times so far (the rungs before it included).
Result start_attempt(const Report& prepared, int r, int tried) {
    Result attempt;
    Report& report = attempt.report;
    report.input_vertices = prepared.input_vertices;
    report.input_triangles = prepared.input_triangles;
    report.stage_seconds = prepared.stage_seconds;
    report.collapsed_edges = prepared.collapsed_edges;
    report.rung = kLadder[r].name;
    report.rungs_tried = tried;
    return attempt;
}

/// Stages validate and collapse (Section 3): the input's, before any rung changes the map.
Error prepare_mesh(const Input& input, const Options& options, TriMesh& m, Report& report) {
    StageTimer timer(report);
    if (Error e = validate(input, thread_count(options.threads), m); e.code != ErrorCode::None) return e;
    timer.done(Stage::validate);
    if (Error e = collapse(m, report.collapsed_edges); e.code != ErrorCode::None) return e;
    timer.done(Stage::collapse);
    return {};
}

/// The whole ladder on `input` at its own scale (`scale`: which attempt this is).
Result extract_at_scale(const Input& input, const Options& options, const AtScale& scale = {}) {
    Result prepared;
    prepared.report.input_vertices = static_cast<std::int64_t>(input.positions.size());
    prepared.report.input_triangles = static_cast<std::int64_t>(input.triangles.size());
    TriMesh m;
    if ((prepared.error = prepare_mesh(input, options, m, prepared.report)).code != ErrorCode::None) return prepared;
    // The ladder: the first rung whose output the checker accepts wins; if none does, the rung
    // with the fewest violations is returned, its defects and violations in the report.
    const int first = options.repair_fold_overs ? 0 : 1;
    const int rungs = options.fallback_ladder ? static_cast<int>(std::size(kLadder)) : first + 1;
    Result best;
    std::size_t best_violations = SIZE_MAX;
    std::vector<std::array<double, 2>> given_map; // the as-given rung's sanitized map
    for (int r = first; r < rungs; ++r) {
        // The first rung takes the prepared mesh; a later rung (rarely needed) prepares it again
        // rather than every run paying for a copy. Preparing succeeded once, so it does again.
        // Its time, like every rung's, is added to the stages' totals.
        if (r > first) {
            Report again;
            again.stage_seconds = std::move(prepared.report.stage_seconds);
            (void)prepare_mesh(input, options, m, again);
            prepared.report.stage_seconds = std::move(again.stage_seconds);
        }
        Result attempt = start_attempt(prepared.report, r, r - first + 1);
        if (!run_rung(std::move(m), input, options, kLadder[r], attempt, scale)) return attempt;
        judge(input, options, kLadder[r], given_map, attempt);
        prepared.report.stage_seconds = attempt.report.stage_seconds; // this rung's and all before
        if (attempt.check.valid) return attempt;
        // A repair that changed nothing had the map as given: the next rung would repeat it.
        const bool as_given = kLadder[r].untangle_rings == 0 && attempt.report.repaired_triangles == 0;
        if (as_given) given_map = attempt.mesh.map_uvs;
        // The further rungs change only flipped or degenerate regions: without any, they would
        // repeat this one.
        const bool another_map = attempt.report.flipped_triangles + attempt.report.degenerate_triangles > 0;
        if (attempt.check.violations.size() < best_violations) {
            best_violations = attempt.check.violations.size();
            best = std::move(attempt);
        }
        best.report.rungs_tried = r - first + 1;
        if (!another_map) break;
        if (kLadder[r].repair && as_given) ++r; // skip the as-given rung
    }
    best.report.stage_seconds = std::move(prepared.report.stage_seconds);
    // No rung gave a valid mesh: locate every violation on the input through the provenance.
    locate_violations(input, best);
    return best;
}

/// Adds `from`'s stage times to `to`'s, stage by stage.
void add_stage_seconds(const Report& from, Report& to) {
    for (const auto& [name, seconds] : from.stage_seconds) {
        const std::string& stage = name; // clang before 16 cannot capture a structured binding
        auto it = std::find_if(to.stage_seconds.begin(), to.stage_seconds.end(),
                               [&](const auto& entry) { return entry.first == stage; });
        if (it == to.stage_seconds.end())
            to.stage_seconds.emplace_back(name, seconds);
        else
            it->second += seconds;
    }
}

/// The explanation of a mesh extracted at another scale: what failed at the map's own scale,
/// and where, then `how`.
Defect scale_explanation(DefectKind kind, const Result& at_scale_one, const std::string& how) {
    Defect d{kind, "", -1, -1, {0, 0}, std::nullopt};
    if (at_scale_one.check.valid) { // over_covered
        d.message = "the mesh at the map's own scale is valid but has " +
                    std::to_string(at_scale_one.mesh.faces.size()) + " quads for a signed UV area of " +
                    std::to_string(std::llround(at_scale_one.report.signed_uv_area)) +
                    " (faces on two sheets of a fold-over cover some cells twice); this mesh is closer to the "
                    "area: " +
                    how;
        return d;
    }
    std::string what = std::to_string(at_scale_one.check.violations.size()) + " checker violations";
    if (!at_scale_one.report.defects.empty()) {
        const Defect& first = at_scale_one.report.defects.front();
        d.input_element = first.input_element;
        d.grid = first.grid;
        what += "; the first: " + first.message;
    }
    d.message = "the map gives no valid quad mesh at its own scale (" + what + "); " + how;
    return d;
}

/// What a refined attempt that gave no valid mesh failed by: the first of its checker
/// violations as located on the input (else its first defect).
Defect refinement_failure(const Result& refined, std::int64_t scale) {
    const std::string k = std::to_string(scale);
    const std::vector<Defect>& defects = refined.report.defects;
    const auto located = std::find_if(defects.begin(), defects.end(),
                                      [](const Defect& d) { return d.kind == DefectKind::CheckerViolation; });
    const Defect* first = located != defects.end() ? &*located : defects.empty() ? nullptr : &defects.front();
    Defect d{DefectKind::RefinementFailed, "", first ? first->input_element : -1, -1, {0, 0}, std::nullopt};
    d.message = "the map with its UVs multiplied by " + k + " gives no valid mesh either (" +
                std::to_string(refined.check.violations.size()) + " checker violations" +
                (first ? "; the first: " + first->message : std::string()) + ")";
    return d;
}

/// The explanation of a refined mesh.
Defect refinement_explanation(const Result& at_scale_one, int scale) {
    const std::string k = std::to_string(scale);
    return scale_explanation(DefectKind::MapRefined, at_scale_one,
                             "the mesh is extracted on the map with its UVs multiplied by " + k +
                                 ", so each quad of the map's own size is " + k + " x " + k + " quads");
}

// ============================================================================ the ladder on the map halved

/// The map as given, sanitized (stages validate and collapse, then sanitize's rounds), in `m`.
bool sanitize_as_given(const Input& input, const Options& options, TriMesh& m, Report& report) {
    Report own;
    if (prepare_mesh(input, options, m, own).code != ErrorCode::None) return false;
    StageTimer timer(own);
    std::vector<int> unused;
    const bool ok = prepare_map(m, input, options, kLadder[1], own, timer, unused).code == ErrorCode::None;
    add_stage_seconds(own, report);
    return ok;
}

/// How far (relative to the map's largest coordinate, at least 1) sanitizing the map at the
/// coarse scale may leave a corner from the given map's sanitized value: truncation to another
/// power of two.
constexpr double kTruncationSpread = 0x1p-40;

/// Whether a valid mesh at the map's own scale has more quads than the map's signed UV area.
bool over_covered(const Result& r) {
    return static_cast<double>(r.mesh.faces.size()) > static_cast<double>(std::llround(r.report.signed_uv_area));
}

/// Coarsening (Options::max_coarsening), after the map at its own scale gave `result`, invalid
/// (or valid but over_covered):
/// the ladder on the map with its UVs divided by 2, 4, ... while that is an integer-grid map, and
/// the first valid mesh there split back onto the given map. Replaces `result` and returns true
/// when that mesh passes the checker against the given map.
bool extract_coarsened(const Input& input, const Options& options, Result& result) {
    TriMesh m;
    if (!sanitize_as_given(input, options, m, result.report)) return false;
    // Powers of two up to the option (bounded as grid_scale is: 2^20).
    const int most = std::min(options.max_coarsening, 1 << 20);
    // Per factor k = 2, 4, ...: the grid point the coarse grid is laid from (its origin).
    std::vector<IPoint> origins;
    {
        const std::vector<std::array<int, 2>> features = feature_edges(m, input, options);
        IPoint origin{0, 0};
        for (int k = 2; k <= most && map_divisible_by(m, features, k, origin); k *= 2) origins.push_back(origin);
    }
    if (origins.empty()) return false;
    const std::vector<std::array<double, 2>> given = take_map(m, input);
    // Sanitizing truncates a fan to a power of two set by its largest coordinate, in any chart:
    // the bound is taken from the map's largest.
    double largest = 1.0;
    for (const auto& uv : given)
        if (!std::isnan(uv[0])) largest = std::max({largest, std::abs(uv[0]), std::abs(uv[1])});
    const double spread = kTruncationSpread * largest;
    Input coarse = input;
    for (std::size_t i = 0; i < origins.size(); ++i) {
        const int k = 2 << i;
        const IPoint o = origins[i];
        // u = k u' + o, from the sanitized map (whose values, truncated, move to the origin
        // exactly, where the given ones could round), then divided by a power of two (exact).
        // Corners of triangles collapsed away keep the given UVs, moved and divided alike.
        const double inverse = 1.0 / k;
        for (std::size_t c = 0; c < coarse.uvs.size(); ++c) {
            const std::array<double, 2>& u = std::isnan(given[c][0]) ? input.uvs[c] : given[c];
            coarse.uvs[c] = {(u[0] - static_cast<double>(o[0])) * inverse,
                             (u[1] - static_cast<double>(o[1])) * inverse};
        }
        StageTimer::hook_scale = 1;
        Result attempt = extract_at_scale(coarse, options);
        if (!attempt.ok() || !attempt.check.valid) {
            add_stage_seconds(attempt.report, result.report);
            if (!attempt.ok()) return false;
            continue;
        }
        // Its sanitized map must be the given map's, moved and divided, outside what its repair
        // changed: the same triangles collapsed away, and no corner moved beyond the truncation
        // sanitizing does (moved to another origin, a fan's values can be truncated a few units
        // in the last place otherwise; a snapped singularity or a rounded seam moves by far more).
        // The mesh carries this map, which the checker verifies exactly.
        std::vector<std::array<double, 2>> map = attempt.mesh.map_uvs;
        for (auto& uv : map) uv = {k * uv[0] + static_cast<double>(o[0]), k * uv[1] + static_cast<double>(o[1])};
        std::vector<char> repaired(map.size() / 3, 0);
        for (const std::int32_t t : attempt.mesh.map_repaired)
            if (t >= 0 && static_cast<std::size_t>(t) < repaired.size()) repaired[static_cast<std::size_t>(t)] = 1;
        bool same = map.size() == given.size();
        for (std::size_t c = 0; c < map.size() && same; ++c) {
            if (repaired[c / 3]) continue;
            same = std::isnan(map[c][0]) == std::isnan(given[c][0]);
            for (int d = 0; d < 2 && same && !std::isnan(map[c][0]); ++d)
                same = std::abs(map[c][d] - given[c][d]) <= spread;
        }
        StageTimer timer(attempt.report);
        QuadMesh split;
        VerifyResult check;
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
        add_stage_seconds(attempt.report, result.report);
        if (!check.valid) continue;
        attempt.mesh = std::move(split);
        attempt.check = std::move(check);
        attempt.report.coarsening = k;
        attempt.report.signed_uv_area *= static_cast<double>(k) * k; // the given map's, as the quads are
        attempt.report.check_violations = 0;
        const std::string f = std::to_string(k);
        attempt.report.explanations.insert(
            attempt.report.explanations.begin(),
            scale_explanation(DefectKind::MapCoarsened, result,
                              "the map with its UVs divided by " + f + " (from grid point (" + std::to_string(o[0]) +
                                  ", " + std::to_string(o[1]) +
                                  ")) is an integer-grid map too (its sanitized map is this one's, so divided), "
                                  "and gives one: each of its quads is split into " +
                                  f + " x " + f + ", every new vertex on its grid point of this map"));
        attempt.report.stage_seconds = std::move(result.report.stage_seconds);
        result = std::move(attempt);
        return true;
    }
    return false;
}

} // namespace
} // namespace qex::detail

namespace qex {

Result extract(const Input& input, const Options& options) {
    using namespace detail;
    // The progress hook, for this thread and this call only.
    struct Hook {
        explicit Hook(const Options& o) {
            StageTimer::hook = o.on_stage ? &o.on_stage : nullptr;
            StageTimer::hook_scale = 1;
        }
        ~Hook() { StageTimer::hook = nullptr; }
    } hook(options);
    // The repair at the map's own scale, kept for its refinements (if any can run).
    RepairMemo memo;
    const bool may_refine = options.fallback_ladder && options.max_refinement >= 2;
    Result result = extract_at_scale(input, options, AtScale{1, false, may_refine ? &memo : nullptr});
    if (!result.ok() || !options.fallback_ladder) return result;
    if (result.check.valid) {
        // More quads than the signed area: faces on two sheets of a fold-over cover some cells
        // twice (a pleat the checker, judging fold-over regions on the surface, lets pass). The
        // coarsened map's mesh is taken instead if its count is closer to the area.
        if (options.max_coarsening < 2 || !over_covered(result)) return result;
        Result coarse = result;
        if (!extract_coarsened(input, options, coarse)) return result;
        const double area = result.report.signed_uv_area;
        const auto off = [area](const Result& r) { return std::abs(static_cast<double>(r.mesh.faces.size()) - area); };
        return off(coarse) < off(result) ? coarse : result;
    }
    if (options.max_coarsening >= 2 && extract_coarsened(input, options, result)) return result;
    if (options.max_refinement < 2) return result;
    // Refinement: the map at twice, four times, ... its scale. Multiplying by two is exact; a map
    // that would leave the range integer transitions need comes back as an input error, and ends
    // the refinement with the scale-1 result.
    Input scaled = input;
    std::vector<Defect> failed; // per refinement tried
    for (int scale = 2; scale <= options.max_refinement; scale *= 2) {
        if (std::abs(result.report.signed_uv_area) * scale * scale > kMaxRefinedQuads) break;
        for (auto& uv : scaled.uvs) uv = {2.0 * uv[0], 2.0 * uv[1]};
        StageTimer::hook_scale = scale;
        // The map at scale 1 passed the seam check (or this would not run).
        Result refined = extract_at_scale(scaled, options, AtScale{scale, true, &memo});
        ++result.report.refinements_tried;
        add_stage_seconds(refined.report, result.report);
        if (!refined.ok()) break;
        if (refined.check.valid) {
            refined.mesh.grid_scale = scale;
            refined.report.grid_scale = scale;
            refined.report.refinements_tried = result.report.refinements_tried;
            refined.report.stage_seconds = std::move(result.report.stage_seconds);
            refined.report.explanations.insert(refined.report.explanations.begin(),
                                               refinement_explanation(result, scale));
            // Seams rounded at scale 1 (Options::round_inconsistent_seams) are the refined map's
            // too, rounded there without a check: their explanations carry over.
            for (const Defect& d : result.report.explanations)
                if (d.kind == DefectKind::SeamRounded) refined.report.explanations.push_back(d);
            return refined;
        }
        failed.push_back(refinement_failure(refined, scale));
    }
    result.report.explanations.insert(result.report.explanations.end(), failed.begin(), failed.end());
    return result;
}

} // namespace qex

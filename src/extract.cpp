// The extraction driver: runs the pipeline stages in the order of the paper and times them.
#include "pipeline.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <iterator>
#include <limits>
#include <numeric>
#include <string>

namespace qex {
namespace {

class StageTimer {
public:
    explicit StageTimer(Report& r) : report_(r), last_(std::chrono::steady_clock::now()) {}
    void done(const char* stage) {
        const auto now = std::chrono::steady_clock::now();
        report_.stage_seconds.emplace_back(stage, std::chrono::duration<double>(now - last_).count());
        last_ = now;
    }

private:
    Report& report_;
    std::chrono::steady_clock::time_point last_;
};

/// Returns, per old face index, its new index.
std::vector<int> canonicalize(QuadMesh& mesh) {
    const std::size_t nv = mesh.positions.size();
    std::vector<int> order(nv);
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int b) {
        if (mesh.positions[a] != mesh.positions[b]) return mesh.positions[a] < mesh.positions[b];
        return a < b;
    });
    std::vector<int> rank(nv);
    for (std::size_t i = 0; i < nv; ++i) rank[order[i]] = static_cast<int>(i);
    QuadMesh out;
    out.positions.reserve(nv);
    out.provenance.reserve(nv);
    for (int i : order) {
        out.positions.push_back(mesh.positions[i]);
        out.provenance.push_back(mesh.provenance[i]);
    }
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
        auto& face = mesh.faces[f];
        auto& uv = mesh.face_uvs[f];
        for (int& v : face) v = rank[v];
        const auto first = std::min_element(face.begin(), face.end()) - face.begin();
        std::rotate(face.begin(), face.begin() + first, face.end());
        std::rotate(uv.begin(), uv.begin() + first, uv.end());
        // Local UVs relative to the first corner: independent of the chart the walk started in.
        const auto o = uv.empty() ? std::array<std::int64_t, 2>{0, 0} : uv[0];
        for (auto& x : uv) x = {x[0] - o[0], x[1] - o[1]};
    }
    // Faces in the order of their vertex lists (as std::vector's operator< orders them). The
    // first four entries, padded with -1, are compared in place; longer faces that tie on them
    // are compared in full.
    struct FaceKey {
        std::array<int, 4> head;
        int face;
    };
    std::vector<FaceKey> fkeys(mesh.faces.size());
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
        fkeys[f] = {{-1, -1, -1, -1}, static_cast<int>(f)};
        for (std::size_t k = 0; k < 4 && k < mesh.faces[f].size(); ++k) fkeys[f].head[k] = mesh.faces[f][k];
    }
    std::sort(fkeys.begin(), fkeys.end(), [&](const FaceKey& a, const FaceKey& b) {
        if (a.head != b.head) return a.head < b.head;
        const auto &fa = mesh.faces[static_cast<std::size_t>(a.face)], &fb = mesh.faces[static_cast<std::size_t>(b.face)];
        if (fa.size() > 4 || fb.size() > 4)
            if (fa != fb) return fa < fb;
        return a.face < b.face;
    });
    std::vector<int> forder(mesh.faces.size());
    for (std::size_t i = 0; i < fkeys.size(); ++i) forder[i] = fkeys[i].face;
    std::vector<int> new_index(mesh.faces.size());
    out.faces.reserve(mesh.faces.size());
    out.face_uvs.reserve(mesh.faces.size());
    for (int f : forder) {
        new_index[f] = static_cast<int>(out.faces.size());
        out.faces.push_back(std::move(mesh.faces[f]));
        out.face_uvs.push_back(std::move(mesh.face_uvs[f]));
    }
    out.map_uvs = std::move(mesh.map_uvs);
    mesh = std::move(out);
    return new_index;
}

} // namespace

Error validate(const Input& input) {
    if (Error e = detail::validate_input_values(input); e.code != ErrorCode::None) return e;
    detail::TriMesh m = detail::make_mesh(input);
    return detail::build_topology(m, "input");
}

namespace {

/// Where the output leaves the input surface bare: the input vertex farthest from every output
/// vertex, and that distance in median output edge lengths. A lost handle or a hole shows up as
/// a bare region. A uniform grid of cells one median edge wide holds the output vertices, and
/// each input vertex searches up to 4 rings of cells around its own.
std::pair<int, double> barest_input_vertex(const Input& input, const QuadMesh& mesh) {
    std::vector<double> lengths;
    for (const auto& f : mesh.faces)
        for (std::size_t i = 0; i < f.size(); ++i) {
            const auto &a = mesh.positions[static_cast<std::size_t>(f[i])],
                       &b = mesh.positions[static_cast<std::size_t>(f[(i + 1) % f.size()])];
            lengths.push_back(std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2])));
        }
    if (lengths.empty() || mesh.positions.empty()) return {-1, 0.0};
    std::nth_element(lengths.begin(), lengths.begin() + static_cast<std::ptrdiff_t>(lengths.size() / 2), lengths.end());
    const double cell = lengths[lengths.size() / 2];
    if (!(cell > 0) || !std::isfinite(cell)) return {-1, 0.0};
    auto key = [&](const std::array<double, 3>& p, int dx, int dy, int dz) {
        const auto c = [&](double x, int d) { return static_cast<std::int64_t>(std::floor(x / cell)) + d; };
        return std::array<std::int64_t, 3>{c(p[0], dx), c(p[1], dy), c(p[2], dz)};
    };
    std::vector<std::pair<std::array<std::int64_t, 3>, int>> grid;
    grid.reserve(mesh.positions.size());
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) grid.push_back({key(mesh.positions[i], 0, 0, 0), static_cast<int>(i)});
    std::sort(grid.begin(), grid.end());
    const int rings = 4;
    int worst = -1;
    double worst_d = -1;
    for (std::size_t v = 0; v < input.positions.size(); ++v) {
        const auto& p = input.positions[v];
        double best = HUGE_VAL;
        for (int dx = -rings; dx <= rings; ++dx)
            for (int dy = -rings; dy <= rings; ++dy)
                for (int dz = -rings; dz <= rings; ++dz) {
                    const auto k = key(p, dx, dy, dz);
                    auto it = std::lower_bound(grid.begin(), grid.end(), std::make_pair(k, -1));
                    for (; it != grid.end() && it->first == k; ++it) {
                        const auto& q = mesh.positions[static_cast<std::size_t>(it->second)];
                        best = std::min(best, std::sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
                                                        (p[2] - q[2]) * (p[2] - q[2])));
                    }
                }
        best = std::min(best, (rings + 1) * cell); // beyond the searched rings
        if (best > worst_d) worst_d = best, worst = static_cast<int>(v);
    }
    return {worst, worst_d / cell};
}

/// The fallback ladder. Each rung re-runs the pipeline from the validated mesh.
struct Rung {
    const char* name;
    int untangle_rings;      ///< 0: the map as given
    int untangle_iterations;
};
constexpr Rung kLadder[] = {
    // 1. The paper's method on the map as given.
    {"as-given", 0, 0},
    // 2. Fold-overs defeated the local handling: relax the folded regions (one ring around them).
    {"untangled-1", 1, 30},
    // 3. Still invalid: relax wider regions for longer.
    {"untangled-3", 3, 100},
};

/// Runs sanitization and extraction on `m` (validated, collapsed). Returns false on an input error.
bool run_pipeline(detail::TriMesh m, const Input& input, const Options& options, const Rung& rung,
                  Result& result) {
    Report& report = result.report;
    StageTimer timer(report);
    std::vector<std::array<int, 2>> features = input.feature_edges;
    if (options.snap_boundary)
        for (int h = 0; h < 3 * m.num_faces(); ++h)
            if (m.opp[h] < 0) features.push_back({m.input_vertex[m.origin(h)], m.input_vertex[m.target(h)]});
    std::int64_t collapsed = 0;
    if (rung.untangle_rings > 0) {
        detail::compute_transitions(m);
        detail::count_valences(m);
        report.flipped_after_untangling = detail::untangle_fold_overs(m, rung.untangle_rings, rung.untangle_iterations);
        timer.done("untangle");
    }
    // Branch points (r = 0 singularities) are decided by angles. Without given valences they are
    // snapped only once the truncated map's degenerate edges are collapsed: before, a noisy
    // sliver next to a vertex can add a full turn to its angle sum.
    bool branch_points = !input.valences.empty();
    for (int round = 0;; ++round) {
        detail::compute_transitions(m);
        detail::count_valences(m);
        std::int64_t deferred = 0;
        if ((result.error = detail::sanitize(m, input.valences, features, report, branch_points, &deferred)).code !=
            ErrorCode::None)
            return false;
        if ((result.error = detail::collapse_degenerate_edges(m, collapsed)).code != ErrorCode::None) return false;
        report.collapsed_edges += collapsed;
        if (round == 8) break;
        if (collapsed == 0) {
            if (branch_points || deferred == 0) break;
            branch_points = true; // one more pass, now on the collapsed map
        }
    }
    detail::count_valences(m, true); // on the sanitized map, for lost-edge detection at singularities
    if (!input.valences.empty())
        for (int v = 0; v < m.num_vertices; ++v) m.valence[v] = input.valences[m.input_vertex[v]];
    for (int f = 0; f < m.num_faces(); ++f) {
        report.flipped_triangles += m.face_sign[f] < 0;
        report.degenerate_triangles += m.face_sign[f] == 0;
    }
    {
        double area2 = 0.0;
        for (int f = 0; f < m.num_faces(); ++f) {
            const auto &a = m.uv[3 * f], &b = m.uv[3 * f + 1], &c = m.uv[3 * f + 2];
            area2 += (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        }
        report.signed_uv_area = 0.5 * area2;
    }
    timer.done("sanitize");

    // Geometry extraction (Section 4).
    detail::QState q;
    if ((result.error = detail::generate_qvertices(m, options, q)).code != ErrorCode::None) return false;
    for (const auto& v : q.qvertices) {
        report.qvertices_on_vertices += v.kind == QVertexKind::Vertex;
        report.qvertices_on_edges += v.kind == QVertexKind::Edge;
        report.qvertices_in_faces += v.kind == QVertexKind::Face;
    }
    timer.done("generate_qvertices");
    detail::enumerate_ports(m, q);
    report.ports = static_cast<std::int64_t>(q.ports.size());
    for (std::size_t i = 0; i < q.qvertices.size(); ++i)
        if (q.qvertices[i].num_ports == 0)
            report.defects.push_back({DefectKind::PortlessQVertex,
                                      "the q-vertex at grid point (" + std::to_string(q.qvertices[i].grid[0]) + ", " +
                                          std::to_string(q.qvertices[i].grid[1]) +
                                          ") lies only on degenerate triangles and has no q-port",
                                      m.input_triangle[q.qvertices[i].chart], -1,
                                      {q.qvertices[i].grid[0], q.qvertices[i].grid[1]}});
    timer.done("enumerate_ports");

    // Connectivity extraction (Section 5).
    detail::trace_ports(m, options, q, report);
    timer.done("trace_ports");
    auto faces = detail::extract_faces(m, q, report);
    timer.done("extract_faces");
    // Merging needs the q-vertices only: the ports and traces (two thirds of the q-state on
    // maps with many quads) are released first.
    std::vector<detail::Port>().swap(q.ports);
    std::vector<detail::Connection>().swap(q.connections);
    std::vector<char>().swap(q.dangling);
    std::vector<int>().swap(q.edge_first);
    std::vector<int>().swap(q.face_first);
    detail::merge_and_simplify(m, q, std::move(faces), options, result.mesh, report);
    q = detail::QState{};
    // The sanitized map, per input corner, for the checker. Only the map and the triangle
    // numbering of the working mesh are still needed: the rest is released first, and when no
    // triangle was collapsed away the map is handed over without a copy.
    std::vector<detail::Point2> uv = std::move(m.uv);
    std::vector<int> input_triangle = std::move(m.input_triangle);
    m = detail::TriMesh{};
    bool same_numbering = input_triangle.size() == input.triangles.size();
    for (std::size_t f = 0; f < input_triangle.size() && same_numbering; ++f)
        same_numbering = input_triangle[f] == static_cast<int>(f);
    if (same_numbering) {
        result.mesh.map_uvs = std::move(uv);
    } else {
        const double nan = std::numeric_limits<double>::quiet_NaN();
        result.mesh.map_uvs.assign(input.uvs.size(), {nan, nan});
        for (std::size_t f = 0; f < input_triangle.size(); ++f)
            for (std::size_t k = 0; k < 3; ++k)
                result.mesh.map_uvs[3 * static_cast<std::size_t>(input_triangle[f]) + k] = uv[3 * f + k];
    }
    if (options.canonical_order) {
        const std::vector<int> new_index = canonicalize(result.mesh);
        for (Defect& d : report.defects)
            if (d.output_face >= 0) d.output_face = new_index[d.output_face];
    }
    timer.done("merge_vertices");
    return true;
}

} // namespace

Result extract(const Input& input, const Options& options) {
    Result result;
    Report& report = result.report;
    StageTimer timer(report);
    report.input_vertices = static_cast<std::int64_t>(input.positions.size());
    report.input_triangles = static_cast<std::int64_t>(input.triangles.size());

    if ((result.error = detail::validate_input_values(input)).code != ErrorCode::None) return result;
    detail::TriMesh m = detail::make_mesh(input);
    m.threads = detail::thread_count(options.threads);
    if ((result.error = detail::build_topology(m, "input")).code != ErrorCode::None) return result;
    timer.done("validate");
    // Collapse of UV-degenerate edges (Section 3): the input's, before any rung changes the map.
    std::int64_t collapsed = 0;
    if ((result.error = detail::collapse_degenerate_edges(m, collapsed)).code != ErrorCode::None) return result;
    timer.done("collapse");

    // The ladder: the first rung whose output the checker accepts wins; if none does, the rung
    // with the fewest violations is returned, its defects and violations in the report.
    const int rungs = options.fallback_ladder ? static_cast<int>(std::size(kLadder)) : 1;
    Result best;
    std::size_t best_violations = SIZE_MAX;
    std::vector<std::array<double, 2>> given_map; // the first rung's sanitized map
    for (int r = 0; r < rungs; ++r) {
        Result attempt;
        attempt.report.input_vertices = report.input_vertices;
        attempt.report.input_triangles = report.input_triangles;
        attempt.report.stage_seconds = report.stage_seconds;
        attempt.report.collapsed_edges = collapsed;
        attempt.report.rung = kLadder[r].name;
        attempt.report.rungs_tried = r + 1;
        // The first rung takes the prepared mesh; a later rung (rarely needed) prepares it again
        // rather than every run paying for a copy.
        if (r > 0) {
            m = detail::make_mesh(input);
            m.threads = detail::thread_count(options.threads);
            (void)detail::build_topology(m, "input");         // succeeded above
            (void)detail::collapse_degenerate_edges(m, collapsed); // likewise
        }
        if (!run_pipeline(std::move(m), input, options, kLadder[r], attempt))
            return attempt; // input error: no rung helps
        if (kLadder[r].untangle_rings > 0 && !given_map.empty()) {
            // A relaxed map is not the given one: every vertex moves onto its grid point in the
            // given (sanitized) map, so the mesh is judged against that map.
            attempt.report.unplaced_vertices = detail::place_on_given_map(input, given_map, attempt.mesh);
        }
        VerifyOptions verify_options;
        verify_options.threads = options.threads;
        attempt.check = verify(input, attempt.mesh, verify_options);
        if (kLadder[r].untangle_rings > 0 && attempt.check.valid) {
            // And it must pass the oracle that judges it against the given map alone (as
            // `qex check` would), or the rung is rejected.
            QuadMesh bare;
            bare.positions = attempt.mesh.positions;
            bare.faces = attempt.mesh.faces;
            const VerifyResult located = verify(input, bare, verify_options);
            for (const Violation& v : located.violations)
                attempt.check.violations.push_back({v.kind, v.message + " (against the given map; this rung relaxed it)", v.element});
            attempt.check.valid = attempt.check.violations.empty();
        }
        attempt.report.check_violations = static_cast<std::int64_t>(attempt.check.violations.size());
        if (attempt.check.valid) return attempt;
        if (r == 0) given_map = attempt.mesh.map_uvs; // only a failed first rung needs it
        // Untangling moves only vertices near flipped or degenerate triangles: without any,
        // the further rungs would repeat this one.
        const bool untangling_can_help = attempt.report.flipped_triangles + attempt.report.degenerate_triangles > 0;
        if (attempt.check.violations.size() < best_violations) {
            best_violations = attempt.check.violations.size();
            best = std::move(attempt);
        }
        best.report.rungs_tried = r + 1;
        if (!untangling_can_help) break;
    }
    // No rung gave a valid mesh: locate every violation on the input through the provenance.
    for (const Violation& v : best.check.violations) {
        Defect d{DefectKind::CheckerViolation, std::string(to_string(v.kind)) + ": " + v.message, -1, -1, {0, 0}};
        int vertex = -1;
        const bool per_face = v.kind == ViolationKind::NotQuad || v.kind == ViolationKind::RepeatedVertex ||
                              v.kind == ViolationKind::InconsistentOrientation ||
                              v.kind == ViolationKind::LocalUvNotUnitSquare;
        if (per_face && v.element >= 0 && v.element < static_cast<std::int64_t>(best.mesh.faces.size())) {
            d.output_face = v.element;
            if (!best.mesh.faces[v.element].empty()) vertex = best.mesh.faces[v.element][0];
        } else if (v.kind == ViolationKind::NonManifoldVertex) {
            vertex = static_cast<int>(v.element);
        } else if ((v.kind == ViolationKind::EulerMismatch || v.kind == ViolationKind::BoundaryMismatch ||
                    v.kind == ViolationKind::ComponentMismatch) &&
                   !best.report.explanations.empty()) {
            // A global defect has no single place; the places where faces were removed are where
            // the topology can have changed.
            d.message += " (faces were removed at " + std::to_string(best.report.explanations.size()) +
                         " places, listed in explanations; the first is near grid point (" +
                         std::to_string(best.report.explanations[0].grid[0]) + ", " +
                         std::to_string(best.report.explanations[0].grid[1]) + ") of input triangle " +
                         std::to_string(best.report.explanations[0].input_element) + ")";
            d.input_element = best.report.explanations[0].input_element;
            d.grid = best.report.explanations[0].grid;
        }
        if (v.kind == ViolationKind::EulerMismatch || v.kind == ViolationKind::BoundaryMismatch ||
            v.kind == ViolationKind::ComponentMismatch) {
            const auto [bare, distance] = barest_input_vertex(input, best.mesh);
            if (bare >= 0) {
                char figure[32];
                std::snprintf(figure, sizeof figure, "%.1f", distance);
                d.message += "; the input surface farthest from the output is at input vertex " + std::to_string(bare) +
                             ", " + figure + " median edge lengths from every output vertex";
            }
        }
        if (vertex >= 0 && vertex < static_cast<int>(best.mesh.provenance.size())) {
            const Provenance& p = best.mesh.provenance[vertex];
            d.input_element = p.chart_triangle;
            d.grid = p.grid;
            d.message += " (near grid point (" + std::to_string(p.grid[0]) + ", " + std::to_string(p.grid[1]) +
                         ") of input triangle " + std::to_string(p.chart_triangle) + ")";
        }
        best.report.defects.push_back(std::move(d));
    }
    return best;
}

} // namespace qex

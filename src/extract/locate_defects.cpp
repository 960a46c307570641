// Where a rejected mesh is wrong: every checker violation becomes a defect that keeps the
// violation's kind and names the output face, the input triangle and the grid point it is near.
// A global violation (Euler characteristic, boundary loops, components) names where faces were
// removed and the input vertex farthest from the output, where a lost handle or a hole shows.
#include "pipeline.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace qex::detail {
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

bool is_global(ViolationKind k) {
    return k == ViolationKind::EulerMismatch || k == ViolationKind::BoundaryMismatch ||
           k == ViolationKind::ComponentMismatch;
}

/// Whether the checker's `element` of a violation of this kind is an output face.
bool is_per_face(ViolationKind k) {
    return k == ViolationKind::NotQuad || k == ViolationKind::RepeatedVertex ||
           k == ViolationKind::InconsistentOrientation || k == ViolationKind::LocalUvNotUnitSquare;
}

/// A global defect has no single place; the places where faces were removed are where the
/// topology can have changed, and the barest input vertex is where the output is missing.
void describe_global(const Input& input, const Result& result, Defect& d) {
    const auto& explanations = result.report.explanations;
    if (!explanations.empty()) {
        d.message += " (faces were removed at " + std::to_string(explanations.size()) +
                     " places, listed in explanations; the first is near grid point (" +
                     std::to_string(explanations[0].grid[0]) + ", " + std::to_string(explanations[0].grid[1]) +
                     ") of input triangle " + std::to_string(explanations[0].input_element) + ")";
        d.input_element = explanations[0].input_element;
        d.grid = explanations[0].grid;
    }
    const auto [bare, distance] = barest_input_vertex(input, result.mesh);
    if (bare >= 0) {
        char figure[32];
        std::snprintf(figure, sizeof figure, "%.1f", distance);
        d.message += "; the input surface farthest from the output is at input vertex " + std::to_string(bare) +
                     ", " + figure + " median edge lengths from every output vertex";
    }
}

} // namespace

void locate_violations(const Input& input, Result& result) {
    const QuadMesh& mesh = result.mesh;
    for (const Violation& v : result.check.violations) {
        Defect d{DefectKind::CheckerViolation, v.message, -1, -1, {0, 0}, v.kind};
        int vertex = -1;
        if (is_per_face(v.kind) && v.element >= 0 && v.element < static_cast<std::int64_t>(mesh.faces.size())) {
            d.output_face = v.element;
            if (!mesh.faces[static_cast<std::size_t>(v.element)].empty())
                vertex = mesh.faces[static_cast<std::size_t>(v.element)][0];
        } else if (v.kind == ViolationKind::NonManifoldVertex) {
            vertex = static_cast<int>(v.element);
        } else if (is_global(v.kind)) {
            describe_global(input, result, d);
        }
        if (vertex >= 0 && vertex < static_cast<int>(mesh.provenance.size())) {
            const Provenance& p = mesh.provenance[static_cast<std::size_t>(vertex)];
            d.input_element = p.chart_triangle;
            d.grid = p.grid;
            d.message += " (near grid point (" + std::to_string(p.grid[0]) + ", " + std::to_string(p.grid[1]) +
                         ") of input triangle " + std::to_string(p.chart_triangle) + ")";
        }
        result.report.defects.push_back(std::move(d));
    }
}

} // namespace qex::detail

// Helpers of the metamorphic tests (map_transforms.h): the real maps of ../shared by name, a
// tolerant comparison of two quad meshes, and one-line summaries for failure messages.
#pragma once

#include "qex/qex.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <numeric>
#include <sstream>
#include <string>
#include <vector>

namespace qex::testing {

/// Reads QEX_SHARED_DIR/meshes/<folder>/<name>_param.obj. "" on success, else why not (the
/// caller skips: the real maps are not part of the repository).
inline std::string read_real_map(const std::string& folder, const std::string& name, Input& in) {
    const std::filesystem::path path =
        std::filesystem::path(QEX_SHARED_DIR) / "meshes" / folder / (name + "_param.obj");
    if (!std::filesystem::exists(path)) return "no " + path.string();
    if (const IoError e = read_obj(path.string(), in); !e.ok()) return path.string() + ": " + e.message;
    return {};
}

/// The first `n` violations, one per line, and how many there are in all.
inline std::string violations_text(const std::vector<Violation>& violations, std::size_t n = 3) {
    std::ostringstream out;
    out << violations.size() << " violations";
    for (std::size_t i = 0; i < std::min(n, violations.size()); ++i)
        out << "\n  " << to_string(violations[i].kind) << ": " << violations[i].message;
    return out.str();
}

/// One line about an extraction: quads, area, and what the fold-overs and the repair did.
inline std::string summary(const Result& r, const VerifyResult& v) {
    std::ostringstream out;
    out << r.mesh.faces.size() << " quads, signed UV area " << v.input_signed_uv_area_rounded << ", "
        << r.report.flipped_triangles << " flipped, " << r.report.repaired_regions << " regions repaired, "
        << r.report.unrepaired_regions << " unrepaired, " << r.report.explanations.size() << " explanations, rung "
        << r.report.rung;
    return out.str();
}

/// The diagonal of the bounding box of `positions`.
inline double bbox_diagonal(const std::vector<std::array<double, 3>>& positions) {
    if (positions.empty()) return 0.0;
    std::array<double, 3> lo = positions[0], hi = positions[0];
    for (const auto& p : positions)
        for (int k = 0; k < 3; ++k) {
            lo[k] = std::min(lo[k], p[k]);
            hi[k] = std::max(hi[k], p[k]);
        }
    return std::hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
}

/// "" when the positions are the same doubles in the same order, else the first that differs and
/// the largest difference.
inline std::string position_difference(const std::vector<std::array<double, 3>>& a,
                                       const std::vector<std::array<double, 3>>& b) {
    std::ostringstream out;
    if (a.size() != b.size()) {
        out << a.size() << " positions against " << b.size();
        return out.str();
    }
    std::int64_t first = -1, differing = 0;
    double largest = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        if (a[i] == b[i]) continue;
        if (first < 0) first = static_cast<std::int64_t>(i);
        ++differing;
        for (int k = 0; k < 3; ++k) largest = std::max(largest, std::abs(a[i][k] - b[i][k]));
    }
    if (first < 0) return {};
    const auto &p = a[static_cast<std::size_t>(first)], &q = b[static_cast<std::size_t>(first)];
    out.precision(17);
    out << differing << " positions differ, by up to " << largest << "; the first, vertex " << first << ": (" << p[0]
        << ", " << p[1] << ", " << p[2] << ") against (" << q[0] << ", " << q[1] << ", " << q[2] << ")";
    return out.str();
}

/// "" when `a` and `b` have as many vertices and faces, every vertex i of `a` has its own vertex
/// of `b` within its tolerance (`wide[i]` ? `wide_tol` : `tol`; inf-norm), and the faces are the
/// same under that matching (up to the rotation of each face, and up to which of b's vertices
/// within `tol` of each other a vertex is); else the first difference. `wide` may be empty.
inline std::string mesh_difference(const QuadMesh& a, const QuadMesh& b, double tol, double wide_tol,
                                   const std::vector<char>& wide) {
    std::ostringstream out;
    if (a.positions.size() != b.positions.size()) {
        out << a.positions.size() << " vertices against " << b.positions.size();
        return out.str();
    }
    if (a.faces.size() != b.faces.size()) {
        out << a.faces.size() << " faces against " << b.faces.size();
        return out.str();
    }
    // b's vertices by x; each vertex of a takes the nearest unmatched one within the window.
    std::vector<int> by_x(b.positions.size());
    std::iota(by_x.begin(), by_x.end(), 0);
    std::sort(by_x.begin(), by_x.end(), [&](int i, int j) { return b.positions[i] < b.positions[j]; });
    std::vector<int> match(a.positions.size(), -1);
    std::vector<char> taken(b.positions.size(), 0);
    for (std::size_t i = 0; i < a.positions.size(); ++i) {
        const auto& p = a.positions[i];
        const double own = i < wide.size() && wide[i] ? std::max(tol, wide_tol) : tol;
        auto it = std::lower_bound(by_x.begin(), by_x.end(), p[0] - own,
                                   [&](int j, double x) { return b.positions[j][0] < x; });
        double best = own;
        for (; it != by_x.end() && b.positions[*it][0] <= p[0] + own; ++it) {
            if (taken[*it]) continue;
            double d = 0.0;
            for (int k = 0; k < 3; ++k) d = std::max(d, std::abs(p[k] - b.positions[*it][k]));
            if (d <= best) {
                best = d;
                match[i] = *it;
            }
        }
        if (match[i] < 0) {
            double nearest = INFINITY;
            for (const auto& q : b.positions) {
                double d = 0.0;
                for (int k = 0; k < 3; ++k) d = std::max(d, std::abs(p[k] - q[k]));
                nearest = std::min(nearest, d);
            }
            out.precision(17);
            out << "vertex " << i << " at (" << p[0] << ", " << p[1] << ", " << p[2] << ") has no counterpart within "
                << own << " (the nearest is " << nearest << " away)";
            return out.str();
        }
        taken[match[i]] = 1;
    }
    // Vertices of b within tol of each other (a fold-over's sheets can meet at one surface point,
    // stage separate_sheets) cannot be told apart by position: they stand for the first of them.
    std::vector<int> alias(b.positions.size());
    std::iota(alias.begin(), alias.end(), 0);
    for (std::size_t n = 0; n < by_x.size(); ++n)
        for (std::size_t m = n + 1; m < by_x.size() && b.positions[by_x[m]][0] <= b.positions[by_x[n]][0] + tol; ++m) {
            double d = 0.0;
            for (int k = 0; k < 3; ++k) d = std::max(d, std::abs(b.positions[by_x[n]][k] - b.positions[by_x[m]][k]));
            if (d <= tol) alias[by_x[m]] = alias[by_x[n]];
        }
    auto canonical = [&](std::vector<int> f) {
        for (int& v : f) v = v >= 0 ? alias[v] : v;
        std::rotate(f.begin(), std::min_element(f.begin(), f.end()), f.end());
        return f;
    };
    std::vector<std::vector<int>> fa, fb;
    for (const auto& f : a.faces) {
        std::vector<int> g;
        for (int v : f) g.push_back(v >= 0 && v < static_cast<int>(match.size()) ? match[v] : -1);
        fa.push_back(canonical(g));
    }
    for (const auto& f : b.faces) fb.push_back(canonical(f));
    std::sort(fa.begin(), fa.end());
    std::sort(fb.begin(), fb.end());
    const auto diff = std::mismatch(fa.begin(), fa.end(), fb.begin());
    if (diff.first != fa.end()) {
        out << "the faces differ under the vertex matching: face (";
        for (int v : *diff.first) out << " " << v;
        out << " ) of the first against (";
        for (int v : *diff.second) out << " " << v;
        out << " ) of the second";
        return out.str();
    }
    return {};
}

/// As above with one tolerance for every vertex.
inline std::string mesh_difference(const QuadMesh& a, const QuadMesh& b, double tol) {
    return mesh_difference(a, b, tol, tol, {});
}

/// The median length of the mesh's edges (each face side once per face).
inline double median_edge_length(const QuadMesh& m) {
    std::vector<double> lengths;
    for (const auto& f : m.faces)
        for (std::size_t k = 0; k < f.size(); ++k) {
            const auto &p = m.positions[static_cast<std::size_t>(f[k])],
                       &q = m.positions[static_cast<std::size_t>(f[(k + 1) % f.size()])];
            lengths.push_back(std::hypot(p[0] - q[0], p[1] - q[1], p[2] - q[2]));
        }
    if (lengths.empty()) return 0.0;
    std::nth_element(lengths.begin(), lengths.begin() + static_cast<std::ptrdiff_t>(lengths.size() / 2), lengths.end());
    return lengths[lengths.size() / 2];
}

/// Per vertex of `m`: placed by a repaired region (on an input triangle of the certificate, in
/// `m`'s or in `other`'s). Input vertices keep their positions, so they are never placed by one.
inline std::vector<char> placed_by_repair(const QuadMesh& m, const QuadMesh& other) {
    std::vector<char> repaired, out(m.positions.size(), 0);
    for (const QuadMesh* q : {&m, &other})
        for (const std::int32_t t : q->map_repaired) {
            if (static_cast<std::size_t>(t) >= repaired.size()) repaired.resize(static_cast<std::size_t>(t) + 1, 0);
            repaired[static_cast<std::size_t>(t)] = 1;
        }
    for (std::size_t i = 0; i < m.provenance.size() && i < out.size(); ++i) {
        const Provenance& p = m.provenance[i];
        const auto t = static_cast<std::size_t>(p.element);
        out[i] = p.kind != QVertexKind::Vertex && p.element >= 0 && t < repaired.size() && repaired[t];
    }
    return out;
}

} // namespace qex::testing

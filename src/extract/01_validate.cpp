// Stage validate: the raw input's values (sizes, indices, finiteness, magnitudes, isolated
// vertices, given valences and feature edges), then the working mesh and its topology (manifold,
// consistently oriented).
#include "pipeline.h"

#include <cmath>
#include <initializer_list>
#include <string>
#include <vector>

namespace qex::detail {
namespace {
/// 2^52: every coordinate must stay below it in magnitude; beyond it integer translations are not exact.
constexpr double kMaxCoordinate = 4503599627370496.0;
/// The largest valence a vertex may be given.
constexpr int kMaxValence = 1000;

/// An error of code `c` about `element` (-1: the input as a whole).
Error make(ErrorCode c, std::string msg, std::int64_t element) { return Error{c, std::move(msg), element}; }

/// The name of 3D coordinate k.
const char* axis_name(int k) { return k == 0 ? "x" : k == 1 ? "y" : "z"; }

/// Some triangles, few enough elements for 32-bit indices, and three UVs per triangle.
Error check_sizes(const Input& in) {
    const std::int64_t nv = static_cast<std::int64_t>(in.positions.size());
    const std::int64_t nf = static_cast<std::int64_t>(in.triangles.size());
    if (nf == 0) return make(ErrorCode::EmptyMesh, "the mesh has no triangles", -1);
    if (nv >= (std::int64_t{1} << 30) || nf >= (std::int64_t{1} << 29))
        return make(ErrorCode::MapTooLarge, "the mesh has too many elements for 32-bit indices", -1);
    if (in.uvs.size() != 3 * in.triangles.size())
        return make(
            ErrorCode::UvCountMismatch,
            "expected " + std::to_string(3 * nf) + " corner UVs (3 per triangle), got " + std::to_string(in.uvs.size()),
            -1);
    return {};
}

/// Every vertex coordinate finite and below 2^52 in magnitude.
Error check_positions(const Input& in) {
    const std::int64_t nv = static_cast<std::int64_t>(in.positions.size());
    for (std::int64_t v = 0; v < nv; ++v)
        for (int k = 0; k < 3; ++k) {
            const double x = in.positions[v][k];
            if (!std::isfinite(x))
                return make(ErrorCode::NonFiniteValue,
                            "vertex " + std::to_string(v) + " has a non-finite " + axis_name(k) + " coordinate", v);
            if (std::abs(x) >= kMaxCoordinate)
                return make(ErrorCode::CoordinateTooLarge,
                            "vertex " + std::to_string(v) + " has |" + axis_name(k) + "| >= 2^52", v);
        }
    return {};
}

/// Every corner UV finite and below 2^52 in magnitude.
Error check_uvs(const Input& in) {
    const std::int64_t nf = static_cast<std::int64_t>(in.triangles.size());
    for (std::int64_t c = 0; c < 3 * nf; ++c)
        for (int k = 0; k < 2; ++k) {
            const double x = in.uvs[c][k];
            if (!std::isfinite(x))
                return make(
                    ErrorCode::NonFiniteValue,
                    "triangle " + std::to_string(c / 3) + " corner " + std::to_string(c % 3) + " has a non-finite UV",
                    c / 3);
            if (std::abs(x) >= kMaxCoordinate)
                return make(ErrorCode::CoordinateTooLarge,
                            "triangle " + std::to_string(c / 3) + " corner " + std::to_string(c % 3) +
                                " has a UV coordinate with magnitude >= 2^52",
                            c / 3);
        }
    return {};
}

/// Triangle indices in range and pairwise distinct; every vertex used by some triangle.
Error check_triangles(const Input& in) {
    const std::int64_t nv = static_cast<std::int64_t>(in.positions.size());
    const std::int64_t nf = static_cast<std::int64_t>(in.triangles.size());
    std::vector<char> used(static_cast<std::size_t>(nv), 0);
    for (std::int64_t f = 0; f < nf; ++f) {
        const auto& t = in.triangles[f];
        for (int k = 0; k < 3; ++k) {
            if (t[k] < 0 || t[k] >= nv)
                return make(ErrorCode::IndexOutOfRange,
                            "triangle " + std::to_string(f) + " refers to vertex " + std::to_string(t[k]) +
                                " but there are " + std::to_string(nv) + " vertices",
                            f);
            used[t[k]] = 1;
        }
        if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0])
            return make(ErrorCode::DegenerateTriangle,
                        "triangle " + std::to_string(f) + " uses vertex " +
                            std::to_string(t[0] == t[1] || t[0] == t[2] ? t[0] : t[1]) + " twice",
                        f);
    }
    for (std::int64_t v = 0; v < nv; ++v)
        if (!used[v])
            return make(ErrorCode::IsolatedVertex, "vertex " + std::to_string(v) + " is used by no triangle", v);
    return {};
}

/// Given valences (if any): one per vertex, each in 0..kMaxValence.
Error check_valences(const Input& in) {
    const std::int64_t nv = static_cast<std::int64_t>(in.positions.size());
    if (!in.valences.empty() && static_cast<std::int64_t>(in.valences.size()) != nv)
        return make(ErrorCode::ValenceCountMismatch,
                    "expected " + std::to_string(nv) + " valences, got " + std::to_string(in.valences.size()), -1);
    for (std::size_t i = 0; i < in.valences.size(); ++i)
        if (in.valences[i] < 0 || in.valences[i] > kMaxValence)
            return make(ErrorCode::ValenceCountMismatch,
                        "vertex " + std::to_string(i) + " has an implausible valence " + std::to_string(in.valences[i]),
                        static_cast<std::int64_t>(i));
    return {};
}

/// Every feature edge joins two distinct vertices in range.
Error check_feature_edges(const Input& in) {
    const std::int64_t nv = static_cast<std::int64_t>(in.positions.size());
    for (std::size_t i = 0; i < in.feature_edges.size(); ++i) {
        const auto& e = in.feature_edges[i];
        if (e[0] < 0 || e[0] >= nv || e[1] < 0 || e[1] >= nv || e[0] == e[1])
            return make(ErrorCode::BadFeatureEdge, "feature edge " + std::to_string(i) + " has invalid vertices",
                        static_cast<std::int64_t>(i));
    }
    return {};
}
} // namespace

Error validate_input_values(const Input& in) {
    // In this order: the first failing check's error is reported.
    for (Error (*check)(const Input&) :
         {check_sizes, check_positions, check_uvs, check_triangles, check_valences, check_feature_edges})
        if (Error e = check(in); e.code != ErrorCode::None) return e;
    return {};
}

Error validate(const Input& in, int threads, TriMesh& m) {
    if (Error e = validate_input_values(in); e.code != ErrorCode::None) return e;
    m = make_mesh(in);
    m.threads = threads;
    return build_topology(m, "input");
}

} // namespace qex::detail

namespace qex {

Error validate(const Input& input) {
    detail::TriMesh m;
    return detail::validate(input, 1, m);
}

} // namespace qex

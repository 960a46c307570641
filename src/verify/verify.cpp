// The checker: judges a polygon mesh against the input map with its own code (nothing from the
// extraction pipeline). Its decisions are exact: on integers (128-bit for the local UVs'
// differences), and on doubles with CGAL's exact predicates and rationals or exact sums
// (TwoSum); only the located mode, which judges meshes from elsewhere, rounds with its two
// tolerances. This file is the entry: the mesh's own checks, its topology against the input's
// (topology.cpp), the input's signed area (signed_area.cpp), then the mesh's map and provenance
// (map_check.cpp) or, without provenance, the located mode (check_located.cpp).
#include "checker.h"
#include "parallel.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <string>

namespace qex {
namespace verify_detail {
namespace {

/// Faces: four vertices each, indices in range, no vertex twice. Returns whether every index is
/// in range.
bool check_faces(const QuadMesh& mesh, std::vector<Violation>& out) {
    const std::size_t nv = mesh.positions.size();
    bool indices_ok = true;
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
        const auto& face = mesh.faces[f];
        if (face.size() != 4)
            add_capped(out, ViolationKind::NotQuad,
                       "face " + std::to_string(f) + " has " + std::to_string(face.size()) + " vertices",
                       static_cast<std::int64_t>(f));
        for (std::size_t i = 0; i < face.size(); ++i) {
            if (face[i] < 0 || static_cast<std::size_t>(face[i]) >= nv) {
                indices_ok = false;
                out.push_back({ViolationKind::BadIndex,
                               "face " + std::to_string(f) + " refers to vertex " + std::to_string(face[i]),
                               static_cast<std::int64_t>(f)});
            }
            for (std::size_t j = i + 1; j < face.size(); ++j)
                if (face[i] == face[j])
                    add_capped(out, ViolationKind::RepeatedVertex,
                               "face " + std::to_string(f) + " uses vertex " + std::to_string(face[i]) + " twice",
                               static_cast<std::int64_t>(f));
        }
    }
    return indices_ok;
}

/// Positions: every coordinate finite.
void check_positions(const QuadMesh& mesh, std::vector<Violation>& out) {
    for (std::size_t v = 0; v < mesh.positions.size(); ++v)
        for (double x : mesh.positions[v])
            if (!std::isfinite(x)) {
                out.push_back({ViolationKind::NonFinitePosition,
                               "vertex " + std::to_string(v) + " has a non-finite position",
                               static_cast<std::int64_t>(v)});
                break;
            }
}

/// A counter-clockwise unit grid cell: every side one unit step along an axis, and each step a
/// quarter turn to the left of the one before (then the four close the cell and enclose area 1).
/// Decided on 128-bit integer differences, exactly.
bool unit_square_ccw(const std::vector<std::array<std::int64_t, 2>>& uv) {
    if (uv.size() != 4) return false;
    std::array<std::array<__int128, 2>, 4> step;
    for (std::size_t i = 0; i < 4; ++i) {
        const auto &a = uv[i], &b = uv[(i + 1) % 4];
        step[i] = {static_cast<__int128>(b[0]) - a[0], static_cast<__int128>(b[1]) - a[1]};
        const __int128 manhattan =
            (step[i][0] < 0 ? -step[i][0] : step[i][0]) + (step[i][1] < 0 ? -step[i][1] : step[i][1]);
        if (manhattan != 1) return false;
    }
    for (std::size_t i = 0; i < 4; ++i) {
        const auto &d = step[i], &e = step[(i + 1) % 4];
        if (e[0] != -d[1] || e[1] != d[0]) return false;
    }
    return true;
}

/// Local UVs (when every face has them): each quad's are a counter-clockwise unit square.
void check_local_uvs(const QuadMesh& mesh, std::vector<Violation>& out) {
    if (mesh.face_uvs.size() != mesh.faces.size()) return;
    for (std::size_t f = 0; f < mesh.faces.size(); ++f)
        if (mesh.faces[f].size() == 4 && !unit_square_ccw(mesh.face_uvs[f]))
            add_capped(out, ViolationKind::LocalUvNotUnitSquare,
                       "the local UVs of face " + std::to_string(f) + " are not a counter-clockwise unit square",
                       static_cast<std::int64_t>(f));
}

/// More face corners (mesh or input) than the checker's 32-bit tables hold.
bool too_large(const Input& input, const QuadMesh& mesh) {
    std::size_t total_corners = 0;
    for (const auto& face : mesh.faces) total_corners += face.size();
    return total_corners > static_cast<std::size_t>(INT32_MAX) ||
           3 * input.triangles.size() > static_cast<std::size_t>(INT32_MAX);
}

/// The mesh's topology (its indices valid) into `r`; its violations, and vertices no face uses.
void check_mesh_topology(const QuadMesh& mesh, int threads, VerifyResult& r, std::vector<Violation>& out) {
    const std::size_t nv = mesh.positions.size();
    std::vector<std::size_t> offset(mesh.faces.size() + 1, 0);
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) offset[f + 1] = offset[f] + mesh.faces[f].size();
    std::vector<int> corners;
    corners.reserve(offset.back()); // grown by doubling, it touched and copied up to twice that
    for (const auto& face : mesh.faces) corners.insert(corners.end(), face.begin(), face.end());
    const Topology t = analyse(nv, offset, corners, &out, threads);
    r.faces = t.faces;
    r.vertices = t.vertices;
    r.edges = t.edges;
    r.boundary_loops = t.boundary_loops;
    r.components = t.components;
    r.euler = t.euler();
    if (static_cast<std::int64_t>(nv) == t.vertices) return;
    // Each vertex no face uses, by name.
    std::vector<char> used(nv, 0);
    for (int v : corners) used[static_cast<std::size_t>(v)] = 1;
    const std::string count = std::to_string(static_cast<std::int64_t>(nv) - t.vertices);
    for (std::size_t v = 0; v < nv; ++v)
        if (!used[v])
            add_capped(out, ViolationKind::UnreferencedVertex,
                       "vertex " + std::to_string(v) + " is used by no face (" + count + " such vertices)",
                       static_cast<std::int64_t>(v));
}

/// The distance (model units) within which a mesh vertex counts as on the input's boundary,
/// for naming holes: the located mode's tolerances, or the same computed here.
double boundary_tolerance(const Input& input, const QuadMesh& mesh, const VerifyOptions& opt, const VerifyResult& r) {
    if (r.located) return r.surface_tolerance + r.max_rounding_tolerance;
    double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL}, norm = 0;
    for (const auto& x : input.positions)
        for (int d = 0; d < 3; ++d) lo[d] = std::min(lo[d], x[d]), hi[d] = std::max(hi[d], x[d]);
    for (const auto& x : mesh.positions) norm = std::max(norm, std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]));
    double diag2 = 0;
    for (int d = 0; d < 3; ++d) diag2 += hi[d] > lo[d] ? (hi[d] - lo[d]) * (hi[d] - lo[d]) : 0;
    const double rounding = opt.position_digits > 0 ? 0.5 * std::pow(10.0, 1 - opt.position_digits) : 0.0;
    return opt.distance_tolerance * std::sqrt(diag2) + rounding * norm;
}

} // namespace

/// The input's topology, for the comparison and the map check (PreparedInput holds one):
/// found when its indices are in range (the input's own problems are validation's to name).
struct InputTopology {
    bool indices_ok = false;
    EdgePairs pairs;
    std::vector<char> single_fan;
    std::int64_t euler = 0, boundary_loops = 0, components = 0;
};

InputTopology analyse_input(const Input& input, int threads) {
    InputTopology it;
    it.indices_ok = true;
    std::vector<std::size_t> tri_offset(input.triangles.size() + 1);
    std::vector<int> tri_corners;
    tri_corners.reserve(3 * input.triangles.size());
    for (std::size_t f = 0; f < input.triangles.size(); ++f) {
        tri_offset[f + 1] = 3 * (f + 1);
        for (int v : input.triangles[f]) {
            it.indices_ok = it.indices_ok && v >= 0 && static_cast<std::size_t>(v) < input.positions.size();
            tri_corners.push_back(v);
        }
    }
    if (!it.indices_ok) return it;
    const Topology ti =
        analyse(input.positions.size(), tri_offset, tri_corners, nullptr, threads, &it.pairs, &it.single_fan);
    it.euler = ti.euler();
    it.boundary_loops = ti.boundary_loops;
    it.components = ti.components;
    return it;
}

} // namespace verify_detail

struct PreparedInput::Analysis {
    verify_detail::InputTopology topology;
};

namespace verify_detail {
namespace {

/// The mesh's Euler characteristic, boundary loops and components against the input's.
void compare_topology(const VerifyResult& r, std::vector<Violation>& out) {
    if (r.euler != r.input_euler)
        out.push_back(
            {ViolationKind::EulerMismatch,
             "Euler characteristic " + std::to_string(r.euler) + ", input has " + std::to_string(r.input_euler), -1});
    if (r.boundary_loops != r.input_boundary_loops)
        out.push_back(
            {ViolationKind::BoundaryMismatch,
             std::to_string(r.boundary_loops) + " boundary loops, input has " + std::to_string(r.input_boundary_loops),
             -1});
    if (r.components != r.input_components)
        out.push_back({ViolationKind::ComponentMismatch,
                       std::to_string(r.components) + " components, input has " + std::to_string(r.input_components),
                       -1});
}

} // namespace
} // namespace verify_detail

namespace verify_detail {
namespace {

/// The input's topology: the prepared one where it describes this input, else found into `own`
/// (not when the input's UVs are not 3 per triangle: nothing is judged against it then).
const InputTopology& input_topology(const Input& input, const VerifyOptions& options, int threads,
                                    InputTopology& own) {
    if (options.prepared && options.prepared->describes(input)) return options.prepared->analysis().topology;
    if (input.uvs.size() == 3 * input.triangles.size()) own = analyse_input(input, threads);
    return own;
}

/// verify(), with the map's solver noise multiplied by `noise_scale` (a refined mesh's map).
VerifyResult verify_at(const Input& input, const QuadMesh& mesh, const VerifyOptions& options, double noise_scale) {
    if (mesh.grid_scale != 1) {
        // A refined mesh is judged against the input map with its UVs multiplied by the scale, a
        // power of two, so the product is exact (or overflows to Inf, which the map check rejects).
        if (mesh.grid_scale < 2 || mesh.grid_scale > (1 << 20) || (mesh.grid_scale & (mesh.grid_scale - 1)) != 0) {
            VerifyResult bad;
            bad.violations.push_back(
                {ViolationKind::MapNotIntegerGrid,
                 "grid scale " + std::to_string(mesh.grid_scale) + " is not a power of two between 1 and 2^20", -1});
            return bad;
        }
        Input scaled = input;
        for (auto& uv : scaled.uvs) uv = {uv[0] * mesh.grid_scale, uv[1] * mesh.grid_scale};
        QuadMesh at_scale = mesh; // the same mesh, judged at its own scale
        at_scale.grid_scale = 1;
        return verify_at(scaled, at_scale, options, static_cast<double>(mesh.grid_scale));
    }
    VerifyResult r;
    auto& out = r.violations;
    const int threads = thread_count(options.threads);
    if (mesh.faces.empty()) out.push_back({ViolationKind::EmptyMesh, "the mesh has no faces", -1});
    const bool indices_ok = check_faces(mesh, out);
    check_positions(mesh, out);
    check_local_uvs(mesh, out);
    if (too_large(input, mesh)) {
        out.push_back({ViolationKind::TooLarge,
                       "more than 2^31 - 1 face corners (mesh or input): beyond the checker's tables", -1});
        r.valid = false;
        return r;
    }
    if (indices_ok) check_mesh_topology(mesh, threads, r, out);
    // The input's topology and exact signed UV area.
    InputTopology own;
    const InputTopology& it = input_topology(input, options, threads, own);
    const bool input_ok = it.indices_ok && input.uvs.size() == 3 * input.triangles.size();
    if (input_ok) {
        r.input_euler = it.euler;
        r.input_triangles = static_cast<std::int64_t>(input.triangles.size());
        r.input_boundary_loops = it.boundary_loops;
        r.input_components = it.components;
        signed_uv_area(input, r);
        if (indices_ok && !mesh.faces.empty()) compare_topology(r, out);
    }
    if (input_ok && !mesh.map_uvs.empty()) {
        if (mesh.map_uvs.size() != input.uvs.size())
            out.push_back({ViolationKind::MapNotIntegerGrid,
                           "the mesh's map has " + std::to_string(mesh.map_uvs.size()) + " corner UVs, the input " +
                               std::to_string(input.uvs.size()),
                           -1});
        else
            check_map(input, mesh, it.pairs, it.single_fan, threads, r, out);
    }
    if (mesh.map_uvs.empty() && !mesh.map_repaired.empty())
        out.push_back({ViolationKind::RepairNotCertified, "the mesh lists repaired triangles but carries no map", -1});
    PlaceContext places;
    places.indices_ok = indices_ok;
    if (input_ok && indices_ok && options.locate && mesh.provenance.empty() && !input.triangles.empty())
        check_located(input, mesh, options, r, out, &places.located_triangle, &places.closest_triangle, noise_scale);
    if (input_ok) places.boundary_tolerance = boundary_tolerance(input, mesh, options, r);
    // Holes (a mesh without boundary loops has none), and in located mode missing components.
    if (input_ok && indices_ok && !mesh.faces.empty() && (r.boundary_loops > 0 || !places.located_triangle.empty()))
        check_holes(input, mesh, r.boundary_loops > 0, places.boundary_tolerance, places.closest_triangle,
                    places.located_triangle, out);
    r.valid = out.empty();
    if (input_ok) place_violations(input, mesh, places, r);
    return r;
}

} // namespace
} // namespace verify_detail

VerifyResult verify(const Input& input, const QuadMesh& mesh, const VerifyOptions& options) {
    // Every point lies within 0.5 of a grid point: a UV tolerance above 1 says no more than 1 does,
    // and one that is NaN or negative holds no point. Taken so here, for every caller (the CLI, the
    // bindings, C++), the coverage search never grows with it.
    VerifyOptions o = options;
    o.uv_tolerance = o.uv_tolerance >= 0 ? std::min(o.uv_tolerance, 1.0) : 0.0;
    if (o.strict_map) o.fold_regions = false;
    VerifyResult r = verify_detail::verify_at(input, mesh, o, 1.0);
    if (o.strict_map && !r.undecided.empty()) { // strict: nothing is left undecided
        r.violations.insert(r.violations.end(), r.undecided.begin(), r.undecided.end());
        r.undecided.clear();
        r.valid = false;
    }
    return r;
}

// ============================================================================ PreparedInput

namespace {

std::unique_ptr<const PreparedInput::Analysis> analysed(const Input& input, int threads) {
    auto a = std::make_unique<PreparedInput::Analysis>();
    // Beyond the checker's 32-bit tables verify() judges nothing against the input.
    if (3 * input.triangles.size() <= static_cast<std::size_t>(INT32_MAX))
        a->topology = verify_detail::analyse_input(input, verify_detail::thread_count(threads));
    return a;
}

} // namespace

PreparedInput::PreparedInput(const Input& input, int threads)
    : triangles_(&input.triangles), vertices_(input.positions.size()), analysis_(analysed(input, threads)) {}

PreparedInput::~PreparedInput() = default;

bool PreparedInput::describes(const Input& input) const {
    return input.positions.size() == vertices_ && (&input.triangles == triangles_ || input.triangles == *triangles_);
}

} // namespace qex

// The C API (qex/qex_c.h) over qex::extract and qex::check_mesh: arguments checked, every
// exception caught, the result's arrays flattened once into the handle, which owns them.
#include "qex/qex_c.h"

#include "qex/check.h"
#include "qex/qex.h"
#include "qex/report.h"

#include <chrono>
#include <cstddef>
#include <cstring>
#include <limits>
#include <memory>
#include <new>
#include <string>
#include <vector>

struct qex_result {
    bool ok = false;
    bool valid = false;
    std::string error;
    std::string error_code;
    std::vector<std::int32_t> quads;
    std::vector<double> positions;
    std::vector<std::int64_t> face_uvs;
    std::string report_json = "{}";
};

struct qex_verdict {
    bool ok = false;
    bool valid = false;
    std::string error;
    std::string error_code;
    std::string json = "{}";
};

namespace {

// The result of a call the library refused before extracting; NULL if even that cannot be had.
qex_result* refused(const char* code, const std::string& message) {
    try {
        auto* r = new qex_result;
        r->error_code = code;
        r->error = message;
        return r;
    } catch (...) { return nullptr; }
}

// Copies the options the caller's struct_size covers over the defaults.
qex::Options to_options(const qex_options* o, int64_t num_vertices, std::vector<int>& valences) {
    qex::Options options;
    if (!o) return options;
    qex_options c;
    qex_options_init_size(&c, sizeof c);
    std::memcpy(&c, o, o->struct_size < sizeof c ? o->struct_size : sizeof c);
    options.threads = c.threads;
    options.repair_fold_overs = c.repair_fold_overs != 0;
    options.fallback_ladder = c.fallback_ladder != 0;
    options.snap_boundary = c.snap_boundary != 0;
    options.canonical_order = c.canonical_order != 0;
    options.max_qvertices = c.max_qvertices;
    if (o->struct_size >= offsetof(qex_options, valences) + sizeof c.valences && c.valences)
        valences.assign(c.valences, c.valences + num_vertices);
    options.best_effort = c.best_effort != 0; // the default where the caller's struct ends before it
    options.fill_holes = c.fill_holes != 0;
    return options;
}

/// The map's arrays as an Input (counts and pointers checked by the caller).
qex::Input to_input(const double* positions, int64_t num_vertices, const int32_t* triangles, int64_t num_triangles,
                    const double* corner_uvs) {
    qex::Input in;
    in.positions.resize(static_cast<std::size_t>(num_vertices));
    for (std::size_t i = 0; i < in.positions.size(); ++i)
        in.positions[i] = {positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]};
    in.triangles.resize(static_cast<std::size_t>(num_triangles));
    in.uvs.resize(3 * in.triangles.size());
    for (std::size_t f = 0; f < in.triangles.size(); ++f) {
        in.triangles[f] = {triangles[3 * f], triangles[3 * f + 1], triangles[3 * f + 2]};
        for (std::size_t k = 0; k < 3; ++k)
            in.uvs[3 * f + k] = {corner_uvs[6 * f + 2 * k], corner_uvs[6 * f + 2 * k + 1]};
    }
    return in;
}

qex_result* run(const double* positions, int64_t num_vertices, const int32_t* triangles, int64_t num_triangles,
                const double* corner_uvs, const qex_options* options) {
    constexpr int64_t kMax = std::numeric_limits<int>::max() / 3;
    if (num_vertices < 0 || num_vertices > kMax)
        return refused("InvalidArgument", "num_vertices " + std::to_string(num_vertices) + " is out of range");
    if (num_triangles < 0 || num_triangles > kMax)
        return refused("InvalidArgument", "num_triangles " + std::to_string(num_triangles) + " is out of range");
    if ((num_vertices > 0 && !positions) || (num_triangles > 0 && (!triangles || !corner_uvs)))
        return refused("InvalidArgument", "positions, triangles and corner_uvs must not be NULL");
    if (options && options->struct_size < sizeof(size_t))
        return refused("InvalidArgument", "qex_options.struct_size is not set (call qex_options_init)");
    qex::Input in = to_input(positions, num_vertices, triangles, num_triangles, corner_uvs);
    const qex::Options opts = to_options(options, num_vertices, in.valences);

    const auto t0 = std::chrono::steady_clock::now();
    const qex::Result result = qex::extract(in, opts);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

    auto r = std::make_unique<qex_result>();
    r->ok = result.ok();
    r->error_code = qex::to_string(result.error.code);
    r->error = result.error.message;
    if (!r->ok) return r.release();
    r->valid = result.check.valid;
    const qex::QuadMesh& m = result.mesh;
    r->positions.reserve(3 * m.positions.size());
    for (const auto& p : m.positions) r->positions.insert(r->positions.end(), p.begin(), p.end());
    for (std::size_t f = 0; f < m.faces.size(); ++f) {
        if (m.faces[f].size() != 4) continue; // only in a mesh the checker rejected
        for (int v : m.faces[f]) r->quads.push_back(v);
        const bool has_uv = f < m.face_uvs.size() && m.face_uvs[f].size() == 4;
        for (std::size_t k = 0; k < 4; ++k) {
            r->face_uvs.push_back(has_uv ? m.face_uvs[f][k][0] : 0);
            r->face_uvs.push_back(has_uv ? m.face_uvs[f][k][1] : 0);
        }
    }
    r->report_json = qex::report_json(result, 0.0, seconds);
    return r.release();
}

qex_verdict* refused_check(const char* code, const std::string& message) {
    try {
        auto* v = new qex_verdict;
        v->error_code = code;
        v->error = message;
        return v;
    } catch (...) { return nullptr; }
}

qex_verdict* run_check(const double* positions, int64_t num_vertices, const int32_t* triangles, int64_t num_triangles,
                       const double* corner_uvs, const double* quad_positions, int64_t num_quad_vertices,
                       const int32_t* quads, int64_t num_quads, int grid_scale, const char* certificate_path) {
    constexpr int64_t kMax = std::numeric_limits<int>::max() / 4;
    if (num_vertices < 0 || num_vertices > kMax || num_triangles < 0 || num_triangles > kMax || num_quad_vertices < 0 ||
        num_quad_vertices > kMax || num_quads < 0 || num_quads > kMax)
        return refused_check("InvalidArgument", "a count is out of range");
    if ((num_vertices > 0 && !positions) || (num_triangles > 0 && (!triangles || !corner_uvs)) ||
        (num_quad_vertices > 0 && !quad_positions) || (num_quads > 0 && !quads))
        return refused_check("InvalidArgument", "an array with a positive count must not be NULL");
    if (grid_scale < 1 || grid_scale > 64 || (grid_scale & (grid_scale - 1)) != 0)
        return refused_check("InvalidArgument", "grid_scale must be 1, 2, 4, 8, 16, 32 or 64");
    qex::Certificate certificate;
    if (certificate_path) {
        if (const qex::IoError e = qex::read_certificate(certificate_path, certificate); !e.ok())
            return refused_check(e.code == qex::IoError::Code::CannotOpen ? "CannotOpen" : "MalformedFile",
                                 std::string(certificate_path) + ": " + e.message);
    }
    const qex::Input in = to_input(positions, num_vertices, triangles, num_triangles, corner_uvs);
    qex::QuadMesh mesh;
    mesh.positions.resize(static_cast<std::size_t>(num_quad_vertices));
    for (std::size_t i = 0; i < mesh.positions.size(); ++i)
        mesh.positions[i] = {quad_positions[3 * i], quad_positions[3 * i + 1], quad_positions[3 * i + 2]};
    mesh.faces.resize(static_cast<std::size_t>(num_quads));
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) mesh.faces[f].assign(quads + 4 * f, quads + 4 * f + 4);
    // The oracle's one entry (qex/check.h), as `qex check` and Python's qex.check judge.
    const qex::MeshCheck c =
        certificate_path ? qex::check_mesh(in, mesh, certificate) : qex::check_mesh(in, mesh, grid_scale);
    auto v = std::make_unique<qex_verdict>();
    v->ok = c.map_ok();
    v->error_code = qex::to_string(c.error.code);
    v->error = c.error.message;
    if (!v->ok) return v.release();
    v->valid = c.verdict.valid;
    // With the quality figures, as `qex check --json` prints the verdict.
    v->json = qex::verify_json(c.verdict, qex::mesh_quality(in, mesh));
    return v.release();
}

} // namespace

extern "C" {

/// run_check with every exception turned into a refused verdict (nothing escapes the C API).
static qex_verdict* guarded_check(const double* positions, int64_t num_vertices, const int32_t* triangles,
                                  int64_t num_triangles, const double* corner_uvs, const double* quad_positions,
                                  int64_t num_quad_vertices, const int32_t* quads, int64_t num_quads, int grid_scale,
                                  const char* certificate_path) {
    try {
        return run_check(positions, num_vertices, triangles, num_triangles, corner_uvs, quad_positions,
                         num_quad_vertices, quads, num_quads, grid_scale, certificate_path);
    } catch (const std::bad_alloc&) {
        return refused_check("OutOfMemory", "out of memory");
    } catch (const std::exception& e) { return refused_check("InternalError", e.what()); } catch (...) {
        return refused_check("InternalError", "unknown exception");
    }
}

qex_verdict* qex_check(const double* positions, int64_t num_vertices, const int32_t* triangles, int64_t num_triangles,
                       const double* corner_uvs, const double* quad_positions, int64_t num_quad_vertices,
                       const int32_t* quads, int64_t num_quads, int grid_scale) {
    return guarded_check(positions, num_vertices, triangles, num_triangles, corner_uvs, quad_positions,
                         num_quad_vertices, quads, num_quads, grid_scale, nullptr);
}

qex_verdict* qex_check_certificate(const double* positions, int64_t num_vertices, const int32_t* triangles,
                                   int64_t num_triangles, const double* corner_uvs, const double* quad_positions,
                                   int64_t num_quad_vertices, const int32_t* quads, int64_t num_quads,
                                   const char* certificate_path) {
    if (!certificate_path) return refused_check("InvalidArgument", "certificate_path must not be NULL");
    return guarded_check(positions, num_vertices, triangles, num_triangles, corner_uvs, quad_positions,
                         num_quad_vertices, quads, num_quads, 1, certificate_path);
}

int qex_verdict_ok(const qex_verdict* v) { return v && v->ok; }
int qex_verdict_valid(const qex_verdict* v) { return v && v->valid; }
const char* qex_verdict_error(const qex_verdict* v) { return v ? v->error.c_str() : "out of memory"; }
const char* qex_verdict_error_code(const qex_verdict* v) { return v ? v->error_code.c_str() : "OutOfMemory"; }
const char* qex_verdict_json(const qex_verdict* v) { return v ? v->json.c_str() : "{}"; }
void qex_verdict_free(qex_verdict* v) { delete v; }

void qex_options_init_size(qex_options* options, size_t struct_size) {
    if (!options || struct_size < sizeof(size_t)) return;
    const qex::Options d;
    qex_options o{};
    o.struct_size = struct_size < sizeof o ? struct_size : sizeof o;
    o.threads = d.threads;
    o.repair_fold_overs = d.repair_fold_overs;
    o.fallback_ladder = d.fallback_ladder;
    o.snap_boundary = d.snap_boundary;
    o.canonical_order = d.canonical_order;
    o.max_qvertices = d.max_qvertices;
    o.valences = nullptr;
    o.best_effort = d.best_effort;
    o.fill_holes = d.fill_holes;
    std::memcpy(options, &o, o.struct_size);
    options->struct_size = struct_size;
}

qex_result* qex_extract(const double* positions, int64_t num_vertices, const int32_t* triangles, int64_t num_triangles,
                        const double* corner_uvs, const qex_options* options) {
    try {
        return run(positions, num_vertices, triangles, num_triangles, corner_uvs, options);
    } catch (const std::bad_alloc&) {
        return refused("OutOfMemory", "out of memory");
    } catch (const std::exception& e) { return refused("InternalError", e.what()); } catch (...) {
        return refused("InternalError", "unknown exception");
    }
}

int qex_result_ok(const qex_result* r) { return r && r->ok; }
int qex_result_valid(const qex_result* r) { return r && r->valid; }
const char* qex_result_error(const qex_result* r) { return r ? r->error.c_str() : "out of memory"; }
const char* qex_result_error_code(const qex_result* r) { return r ? r->error_code.c_str() : "OutOfMemory"; }
int64_t qex_result_num_quads(const qex_result* r) { return r ? static_cast<int64_t>(r->quads.size() / 4) : 0; }
const int32_t* qex_result_quads(const qex_result* r) { return r && !r->quads.empty() ? r->quads.data() : nullptr; }
int64_t qex_result_num_vertices(const qex_result* r) { return r ? static_cast<int64_t>(r->positions.size() / 3) : 0; }
const double* qex_result_positions(const qex_result* r) {
    return r && !r->positions.empty() ? r->positions.data() : nullptr;
}
const int64_t* qex_result_face_uvs(const qex_result* r) {
    return r && !r->face_uvs.empty() ? r->face_uvs.data() : nullptr;
}
const char* qex_result_report_json(const qex_result* r) { return r ? r->report_json.c_str() : "{}"; }
void qex_result_free(qex_result* r) { delete r; }

} // extern "C"

/* qex C API: quad mesh extraction for programs in C and for other languages through a C ABI
 * (ctypes, cffi, FFI of Rust/Julia/C#, ...). C99, in the shared library libqex_c.
 *
 *   qex_result* r = qex_extract(positions, nv, triangles, nt, corner_uvs, NULL);
 *   if (!qex_result_ok(r))         fprintf(stderr, "%s\n", qex_result_error(r));
 *   else if (qex_result_valid(r))  use qex_result_quads(r), qex_result_positions(r) ...
 *   qex_result_free(r);
 *
 * No function aborts, prints or throws: bad input (NULL pointers, negative counts, indices out of
 * range, NaN, a mesh or map the extractor rejects) comes back in the result's error message,
 * which names the element at fault. Every returned pointer is owned by the result and lives until
 * qex_result_free(). qex_extract returns NULL only when memory for the result itself runs out;
 * every accessor accepts NULL (and returns 0, NULL or an empty string).
 */
#ifndef QEX_QEX_C_H
#define QEX_QEX_C_H

#include <stddef.h>
#include <stdint.h>

#if defined(_WIN32)
#define QEX_C_API __declspec(dllexport)
#elif defined(__GNUC__)
#define QEX_C_API __attribute__((visibility("default")))
#else
#define QEX_C_API
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* The version of this header's ABI: qex_options may grow at its end, never change. */
#define QEX_C_API_VERSION 1

/* Options of one extraction. Fill with qex_options_init(), which sets struct_size to the size the
 * caller was compiled with; the library reads only the fields that size covers, so a program built
 * against an older header keeps working with a newer library. */
typedef struct qex_options {
    size_t struct_size;      /* sizeof(qex_options) as the caller knows it */
    int threads;             /* threads for the parallel loops: 0 every core, 1 serial (same output) */
    int repair_fold_overs;   /* re-embed flipped regions before extraction (default 1: certified; 0 is
                                `qex extract --no-repair`: fast, uncertified) */
    int fallback_ladder;     /* retry on the map as given when the repaired map fails (default 1) */
    int snap_boundary;       /* snap every boundary edge to its closest integer iso-line (default 0) */
    int canonical_order;     /* sort output vertices and faces canonically (default 1) */
    int64_t max_qvertices;   /* refuse maps that need more output vertices (default 10,000,000) */
    const int32_t* valences; /* optional: num_vertices cross-field valences (4 regular), or NULL */
    int best_effort;         /* no valid mesh: return the attempt closest to valid (default 0); still invalid */
    int fill_holes;          /* last resort: fill holes no grid cells close from their rims (default 1; HoleFilled) */
} qex_options;

typedef struct qex_result qex_result; /* opaque */

/* Fills the first `struct_size` bytes of *options with the defaults (those of qex::Options) and
 * sets options->struct_size = struct_size: a library newer than the caller's header writes no
 * further than the caller's struct. */
QEX_C_API void qex_options_init_size(qex_options* options, size_t struct_size);

/* The defaults, with struct_size = sizeof(qex_options) as the caller is compiled. */
static inline void qex_options_init(qex_options* options) { qex_options_init_size(options, sizeof(qex_options)); }

/* Extracts the quad mesh of a triangle mesh carrying an integer-grid map. positions: 3 doubles
 * per vertex; triangles: 3 vertex indices per triangle (counter-clockwise); corner_uvs: 6 doubles
 * per triangle, (u, v) of its corners in order. options: NULL for the defaults. */
QEX_C_API qex_result* qex_extract(const double* positions, int64_t num_vertices, const int32_t* triangles,
                                  int64_t num_triangles, const double* corner_uvs /* 6 per triangle */,
                                  const qex_options* options /* NULL: defaults */);

QEX_C_API int qex_result_ok(const qex_result* result);    /* 1: the input was accepted */
QEX_C_API int qex_result_valid(const qex_result* result); /* 1: the checker accepted the mesh */
/* Why the input was rejected (the element named), or "" when it was accepted. */
QEX_C_API const char* qex_result_error(const qex_result* result);
/* The qex::ErrorCode's name ("None", "NonManifoldEdge", ...; "InvalidArgument" for a NULL
 * pointer or a count out of range, "OutOfMemory"). */
QEX_C_API const char* qex_result_error_code(const qex_result* result);
QEX_C_API int64_t qex_result_num_quads(const qex_result* result);
QEX_C_API const int32_t* qex_result_quads(const qex_result* result); /* 4 per quad, counter-clockwise */
QEX_C_API int64_t qex_result_num_vertices(const qex_result* result);
QEX_C_API const double* qex_result_positions(const qex_result* result); /* 3 per vertex */
/* Per quad corner, the integer local UV (u, v): 8 per quad, a counter-clockwise unit square. */
QEX_C_API const int64_t* qex_result_face_uvs(const qex_result* result);
/* The report as JSON: the document `qex extract --report` writes ("{}" for rejected input). */
QEX_C_API const char* qex_result_report_json(const qex_result* result);
QEX_C_API void qex_result_free(qex_result* result);

/* The oracle: judges any extractor's quad mesh against a map, with the same code path and
 * defaults as `qex check --param MAP MESH --grid-scale K` (and Python's qex.check, `qex draw
 * --quads`): the map as for qex_extract; quad_positions 3 doubles per vertex, quads 4 vertex
 * indices per face (counter-clockwise); grid_scale 1, or the power of two (up to 64) the mesh was
 * refined by. */
typedef struct qex_verdict qex_verdict; /* opaque */
QEX_C_API qex_verdict* qex_check(const double* positions, int64_t num_vertices, const int32_t* triangles,
                                 int64_t num_triangles, const double* corner_uvs /* 6 per triangle */,
                                 const double* quad_positions, int64_t num_quad_vertices, const int32_t* quads,
                                 int64_t num_quads, int grid_scale);
/* The same, judged on qex's certificate (`qex check --param MAP MESH --certificate CERT`): the
 * certificate file `qex extract --certificate` wrote is checked against the map and the mesh
 * judged on the repaired map it holds, at its grid scale. An unreadable or malformed file is
 * refused (error codes "CannotOpen", "MalformedFile"); one that does not hold gives
 * CertificateMismatch violations. */
QEX_C_API qex_verdict* qex_check_certificate(const double* positions, int64_t num_vertices, const int32_t* triangles,
                                             int64_t num_triangles, const double* corner_uvs,
                                             const double* quad_positions, int64_t num_quad_vertices,
                                             const int32_t* quads, int64_t num_quads, const char* certificate_path);
QEX_C_API int qex_verdict_ok(const qex_verdict* verdict);    /* 1: the map was accepted (else an error) */
QEX_C_API int qex_verdict_valid(const qex_verdict* verdict); /* 1: the checker accepted the mesh */
/* Why the map or the call was refused, or "" (qex_result_error_code's names in error_code). */
QEX_C_API const char* qex_verdict_error(const qex_verdict* verdict);
QEX_C_API const char* qex_verdict_error_code(const qex_verdict* verdict);
/* The verdict as JSON, the document `qex check --json` prints, the mesh's quality figures under
 * "quality" (qex/quality.h) ("{}" when the map was refused). */
QEX_C_API const char* qex_verdict_json(const qex_verdict* verdict);
QEX_C_API void qex_verdict_free(qex_verdict* verdict);

#ifdef __cplusplus
}
#endif

#endif /* QEX_QEX_C_H */

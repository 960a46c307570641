/* A C99 program using the C API (qex/qex_c.h): refused inputs first (each comes back with a
 * message, nothing aborts), then a flat 2x2 square, then the map of an OBJ file given as argv[1]
 * (its quad count must be argv[2] when given). ctest builds it with the C compiler, once plain
 * and once under AddressSanitizer (leaks fail that run); the install_consumer test links it
 * against the installed library. Exit code 0: every check passed. */
#include <qex/qex_c.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int failures = 0;

#define CHECK(cond)                                                                  \
    do {                                                                             \
        if (!(cond)) {                                                               \
            fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, __LINE__, #cond); \
            ++failures;                                                              \
        }                                                                            \
    } while (0)

/* Extraction must refuse the input: not ok, not valid, an error message, no mesh. */
static void expect_refused(const char* what, qex_result* r, const char* code) {
    CHECK(r != NULL);
    CHECK(!qex_result_ok(r));
    CHECK(!qex_result_valid(r));
    CHECK(strlen(qex_result_error(r)) > 0);
    CHECK(qex_result_num_quads(r) == 0 && qex_result_quads(r) == NULL);
    CHECK(qex_result_num_vertices(r) == 0 && qex_result_positions(r) == NULL);
    if (code && strcmp(qex_result_error_code(r), code) != 0) {
        fprintf(stderr, "%s: code %s, expected %s\n", what, qex_result_error_code(r), code);
        ++failures;
    }
    printf("refused %s: %s: %s\n", what, qex_result_error_code(r), qex_result_error(r));
    qex_result_free(r);
}

/* The mesh of an accepted map: valid, indices in range, positions finite, the report JSON. */
static void expect_valid(const char* what, qex_result* r, long long quads) {
    int64_t q, nv, i;
    const int32_t* f;
    const double* p;
    CHECK(qex_result_ok(r));
    CHECK(qex_result_valid(r));
    CHECK(strcmp(qex_result_error(r), "") == 0);
    q = qex_result_num_quads(r);
    nv = qex_result_num_vertices(r);
    f = qex_result_quads(r);
    p = qex_result_positions(r);
    CHECK(q > 0 && f != NULL && nv > 0 && p != NULL && qex_result_face_uvs(r) != NULL);
    if (quads >= 0 && q != quads) {
        fprintf(stderr, "%s: %lld quads, expected %lld\n", what, (long long)q, quads);
        ++failures;
    }
    for (i = 0; f && i < 4 * q; ++i) CHECK(f[i] >= 0 && f[i] < nv);
    for (i = 0; p && i < 3 * nv; ++i) CHECK(isfinite(p[i]));
    CHECK(strstr(qex_result_report_json(r), "\"rung\"") != NULL);
    CHECK(strstr(qex_result_report_json(r), "\"check\"") != NULL);
    printf("%s: %lld quads, %lld vertices\n", what, (long long)q, (long long)nv);
    qex_result_free(r);
}

/* A minimal reader of the OBJ maps: v x y z, vt u v, f a/ta b/tb c/tc (1-based). */
static int read_map(const char* path, double** pos, int64_t* nv, int32_t** tri, int64_t* nt, double** uv) {
    FILE* in = fopen(path, "r");
    char line[512];
    double* vt = NULL;
    int64_t nvt = 0, cap_v = 0, cap_vt = 0, cap_t = 0;
    *pos = NULL, *tri = NULL, *uv = NULL, *nv = 0, *nt = 0;
    if (!in) return 0;
    while (fgets(line, sizeof line, in)) {
        double x, y, z;
        long a, b, c, ta, tb, tc;
        if (sscanf(line, "v %lf %lf %lf", &x, &y, &z) == 3) {
            if (*nv == cap_v) *pos = realloc(*pos, (size_t)(cap_v = 2 * cap_v + 64) * 3 * sizeof(double));
            (*pos)[3 * *nv] = x, (*pos)[3 * *nv + 1] = y, (*pos)[3 * *nv + 2] = z, ++*nv;
        } else if (sscanf(line, "vt %lf %lf", &x, &y) == 2) {
            if (nvt == cap_vt) vt = realloc(vt, (size_t)(cap_vt = 2 * cap_vt + 64) * 2 * sizeof(double));
            vt[2 * nvt] = x, vt[2 * nvt + 1] = y, ++nvt;
        } else if (sscanf(line, "f %ld/%ld %ld/%ld %ld/%ld", &a, &ta, &b, &tb, &c, &tc) == 6) {
            long t[3], k;
            t[0] = ta, t[1] = tb, t[2] = tc;
            if (*nt == cap_t) {
                cap_t = 2 * cap_t + 64;
                *tri = realloc(*tri, (size_t)cap_t * 3 * sizeof(int32_t));
                *uv = realloc(*uv, (size_t)cap_t * 6 * sizeof(double));
            }
            (*tri)[3 * *nt] = (int32_t)(a - 1), (*tri)[3 * *nt + 1] = (int32_t)(b - 1),
                       (*tri)[3 * *nt + 2] = (int32_t)(c - 1);
            for (k = 0; k < 3; ++k) {
                int ok = t[k] >= 1 && t[k] <= nvt;
                (*uv)[6 * *nt + 2 * k] = ok ? vt[2 * (t[k] - 1)] : NAN;
                (*uv)[6 * *nt + 2 * k + 1] = ok ? vt[2 * (t[k] - 1) + 1] : NAN;
            }
            ++*nt;
        }
    }
    free(vt);
    fclose(in);
    return *nt > 0;
}

int main(int argc, char** argv) {
    /* A flat 2x2 square in the plane z = 0, its UVs its coordinates: 4 quads. */
    const double square[] = {0, 0, 0, 2, 0, 0, 2, 2, 0, 0, 2, 0};
    const int32_t two[] = {0, 1, 2, 0, 2, 3};
    const double square_uv[] = {0, 0, 2, 0, 2, 2, 0, 0, 2, 2, 0, 2};
    const int32_t out_of_range[] = {0, 1, 7, 0, 2, 3};
    const int32_t fan[] = {0, 1, 2, 0, 2, 3, 2, 0, 1}; /* edge 0-1 (and 1-2, 2-0) used too often */
    const double fan_uv[] = {0, 0, 2, 0, 2, 2, 0, 0, 2, 2, 0, 2, 2, 2, 0, 0, 2, 0};
    double nan_uv[12];
    qex_options options;

    /* Accessors and free accept NULL. */
    CHECK(!qex_result_ok(NULL) && !qex_result_valid(NULL) && qex_result_num_quads(NULL) == 0);
    CHECK(qex_result_quads(NULL) == NULL && qex_result_positions(NULL) == NULL);
    CHECK(strcmp(qex_result_report_json(NULL), "{}") == 0 && strlen(qex_result_error(NULL)) > 0);
    qex_result_free(NULL);
    qex_options_init(NULL);

    expect_refused("NULL arrays", qex_extract(NULL, 4, NULL, 2, NULL, NULL), "InvalidArgument");
    expect_refused("negative count", qex_extract(square, -1, two, 2, square_uv, NULL), "InvalidArgument");
    expect_refused("huge count", qex_extract(square, (int64_t)1 << 40, two, 2, square_uv, NULL), "InvalidArgument");
    /* Counts at the edges of 32 and 64 bits: refused before any array is read. */
    expect_refused("2^31 vertices", qex_extract(square, (int64_t)1 << 31, two, 2, square_uv, NULL), "InvalidArgument");
    expect_refused("2^31 - 1 triangles", qex_extract(square, 4, two, INT32_MAX, square_uv, NULL), "InvalidArgument");
    expect_refused("2^63 - 1 vertices", qex_extract(square, INT64_MAX, two, 2, square_uv, NULL), "InvalidArgument");
    expect_refused("-2^63 triangles", qex_extract(square, 4, two, INT64_MIN, square_uv, NULL), "InvalidArgument");
    expect_refused("no triangles", qex_extract(square, 4, two, 0, square_uv, NULL), "EmptyMesh");
    expect_refused("index out of range", qex_extract(square, 4, out_of_range, 2, square_uv, NULL), "IndexOutOfRange");
    memcpy(nan_uv, square_uv, sizeof nan_uv);
    nan_uv[7] = NAN;
    expect_refused("NaN uv", qex_extract(square, 4, two, 2, nan_uv, NULL), "NonFiniteValue");
    expect_refused("non-manifold", qex_extract(square, 4, fan, 3, fan_uv, NULL), NULL);
    qex_options_init(&options);
    options.struct_size = 0;
    expect_refused("options without struct_size", qex_extract(square, 4, two, 2, square_uv, &options),
                   "InvalidArgument");

    expect_valid("square, default options", qex_extract(square, 4, two, 2, square_uv, NULL), 4);
    qex_options_init(&options);
    options.threads = 1;
    expect_valid("square, one thread", qex_extract(square, 4, two, 2, square_uv, &options), 4);
    /* A caller built against a header whose options ended before max_qvertices: initialising
     * writes no further, and extraction reads no further. */
    options.max_qvertices = 1;
    options.valences = (const int32_t*)(uintptr_t)8; /* reading it would crash */
    qex_options_init_size(&options, offsetof(qex_options, max_qvertices));
    CHECK(options.max_qvertices == 1 && options.threads == 0 &&
          options.struct_size == offsetof(qex_options, max_qvertices));
    options.threads = 1;
    expect_valid("square, older options struct", qex_extract(square, 4, two, 2, square_uv, &options), 4);
    qex_options_init(&options);
    options.max_qvertices = 1;
    expect_refused("max_qvertices 1", qex_extract(square, 4, two, 2, square_uv, &options), "MapTooLarge");
    /* best_effort (off by default) and fill_holes (on by default, the last resort) change nothing
     * for a map with a valid mesh, either way; a caller whose struct ends before one gets its
     * default, the library reading nothing past the struct. */
#define CHECK_FLAG_OPTION(FIELD, DEFAULT)                                                                           \
    do {                                                                                                            \
        qex_options_init(&options);                                                                                 \
        CHECK(options.FIELD == (DEFAULT));                                                                          \
        options.FIELD = !(DEFAULT);                                                                                 \
        expect_valid("square, " #FIELD " not its default", qex_extract(square, 4, two, 2, square_uv, &options), 4); \
        options.FIELD = 7; /* past the caller's struct: not read */                                                 \
        qex_options_init_size(&options, offsetof(qex_options, FIELD));                                              \
        CHECK(options.FIELD == 7);                                                                                  \
        expect_valid("square, options without " #FIELD, qex_extract(square, 4, two, 2, square_uv, &options), 4);    \
    } while (0)
    CHECK_FLAG_OPTION(best_effort, 0);
    CHECK_FLAG_OPTION(fill_holes, 1);
#undef CHECK_FLAG_OPTION

    if (argc >= 2) {
        double *pos, *uv;
        int32_t* tri;
        int64_t nv, nt;
        if (!read_map(argv[1], &pos, &nv, &tri, &nt, &uv)) {
            fprintf(stderr, "cannot read %s\n", argv[1]);
            ++failures;
        } else {
            expect_valid(argv[1], qex_extract(pos, nv, tri, nt, uv, NULL), argc >= 3 ? atoll(argv[2]) : -1);
        }
        free(pos), free(tri), free(uv);
    }
    printf("%s\n", failures ? "FAILED" : "OK");
    return failures ? 1 : 0;
}

// Structure-aware: the bytes choose a generated integer-grid map and a sequence of perturbations,
// then run extraction and the exact checker. Perturbations the paper handles (charts, order,
// translation, rotation, collapsed edges, noise, on a boundary only when snapped, and feature
// edges that lie on iso-lines) must give a valid mesh whose quad count is the map's signed UV
// area, exactly; any others must give a clean error or a consistent result
// (property_tests/result_checks.h: the verdict is the checker's run again, the checker defects are
// its violations kind for kind, every defect names a place).
#include "fuzz_input.h"
#include "map_generators.h"
#include "result_checks.h"

#include <cmath>
#include <limits>
#include <string>

using namespace qex;
using namespace qex::testing;

namespace {

/// The generated map and what the perturbations did to it.
struct Case {
    const QuadLayout* layout = nullptr;
    int n = 1, k = 1; ///< grid quads and lattice steps per layout edge
    Input in;
    /// Only perturbations the paper handles, after which the exact result is required. Noise on
    /// a boundary is handled once snapped (Options::snap_boundary), and a feature edge only
    /// when it lies on an integer iso-line: snapping any other edge moves the map. A collapsed
    /// edge is handled while its UV length is zero: noise makes it a short edge, whose triangles
    /// the sanitization can flip (corpus/fuzz_extract/merged/b45659e8..., a cube's singular
    /// corner: the output is invalid, with located defects).
    bool benign = true;
    bool noise = false, collapsed = false;
};

/// Whether the edge from corner k of triangle f lies on an integer iso-line of its chart.
bool on_iso_line(const Input& in, int f, int k) {
    const auto &a = in.uvs[3 * static_cast<std::size_t>(f) + static_cast<std::size_t>(k)],
               &b = in.uvs[3 * static_cast<std::size_t>(f) + static_cast<std::size_t>((k + 1) % 3)];
    return (a[0] == b[0] && std::floor(a[0]) == a[0]) || (a[1] == b[1] && std::floor(a[1]) == a[1]);
}

/// Applies the perturbation `op` the bytes choose next. The bytes are read left to right, each
/// into a variable of its own (the order of a call's arguments is unspecified: gcc's replay must
/// read what clang's libFuzzer wrote).
void perturb(fuzz::Bytes& b, int op, std::vector<char>& single_chart, std::mt19937& rng, Case& c) {
    Input& in = c.in;
    const int n = c.n, k = c.k;
    const int nf = static_cast<int>(in.triangles.size()), nv = static_cast<int>(in.positions.size());
    switch (op) {
        case 0: rechart(in, rng, 1 << b.range(0, 20)); break;
        case 1: shuffle(in, rng); break;
        case 2: {
            const int x = b.range(0, 40), y = b.range(0, 40);
            translate(in, std::int64_t{1} << x, -(std::int64_t{1} << y));
            break;
        }
        case 3: rotate(in, b.range(0, 3)); break;
        case 4:
            add_noise(in, std::ldexp(1.0, -b.range(20, 50)), rng);
            c.noise = true;
            c.benign = c.benign && !c.collapsed;
            break;
        case 5: { // fold-over at a single-chart vertex
            const int v = b.range(0, nv - 1);
            if (v < static_cast<int>(single_chart.size()) && single_chart[v]) {
                const double dx = b.unit() * n / k * 1.5, dy = b.unit() * n / k * 1.5;
                displace_vertex(in, v, dx, dy);
                c.benign = false;
            }
            break;
        }
        case 6:
        case 7: { // a collapsed edge (handled), or a zero-area triangle (see KnownFailures)
            const int f = b.range(0, nf - 1), corner = b.range(0, 2);
            if (op == 6)
                insert_collapsed_edge(in, f, corner), c.collapsed = true;
            else
                insert_zero_area_triangle(in, f, corner), c.benign = false;
            single_chart.push_back(0);
            in.valences.clear();
            break;
        }
        case 8:
            in.uvs[b.range(0, 3 * nf - 1)][b.range(0, 1)] =
                (b.byte() & 1) ? std::numeric_limits<double>::quiet_NaN() : std::numeric_limits<double>::infinity();
            c.benign = false;
            break;
        case 9:
            in.triangles.push_back(in.triangles[b.range(0, nf - 1)]);
            in.uvs.resize(3 * in.triangles.size());
            c.benign = false;
            break;
        case 11: { // a feature edge: an edge of the mesh, or (rarely) an arbitrary pair
            const int f = b.range(0, nf - 1), corner = b.range(0, 2);
            if (b.byte() < 240) {
                in.feature_edges.push_back({in.triangles[f][corner], in.triangles[f][(corner + 1) % 3]});
                c.benign = c.benign && on_iso_line(in, f, corner);
            } else {
                in.feature_edges.push_back({b.range(-1, nv), b.range(-1, nv)}), c.benign = false;
            }
            break;
        }
        case 12: { // valences given by the caller: 4 everywhere except a few, possibly wrong
            in.valences.assign(in.positions.size(), 4);
            for (int i = b.range(0, 4); i > 0; --i) in.valences[b.range(0, nv - 1)] = b.range(0, 9);
            c.benign = false; // a wrong valence moves a vertex onto a grid point
            break;
        }
        default: {
            const int f = b.range(0, nf - 1);
            in.triangles.erase(in.triangles.begin() + f);
            in.uvs.erase(in.uvs.begin() + 3 * f, in.uvs.begin() + 3 * f + 3);
            c.benign = false;
            break;
        }
    }
}

/// The oracle for other extractors (no provenance): on a fold-free map it must agree with the
/// exact checker, and on a damaged copy of the mesh it must not crash.
void check_without_provenance(fuzz::Bytes& b, const Case& c, const Options& opt, const Result& r, bool valid) {
    QuadMesh bare = r.mesh;
    bare.provenance.clear();
    bare.map_uvs.clear();
    bare.face_uvs.clear();
    const VerifyResult located = verify(c.in, bare);
    // (Snapped features and boundaries move the map, and explained deficits leave cells uncovered.)
    if (c.benign && c.in.feature_edges.empty() && !opt.snap_boundary && valid && r.report.explanations.empty() &&
        !located.valid)
        fuzz::fail("the oracle without provenance rejects a valid mesh of a fold-free map");
    for (int ops = b.range(0, 3); ops > 0 && !b.empty() && !bare.faces.empty(); --ops) {
        auto& face = bare.faces[b.range(0, static_cast<int>(bare.faces.size()) - 1)];
        if (face.size() < 2) continue;
        switch (b.range(0, 3)) {
            case 0: std::swap(face[0], face[b.range(1, static_cast<int>(face.size()) - 1)]); break;
            case 1:
                face[b.range(0, static_cast<int>(face.size()) - 1)] =
                    b.range(-1, static_cast<int>(bare.positions.size()));
                break;
            case 2:
                bare.positions[b.range(0, static_cast<int>(bare.positions.size()) - 1)][b.range(0, 2)] +=
                    b.unit() - 0.5;
                break;
            default: face.pop_back(); break;
        }
    }
    (void)verify(c.in, bare);
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    fuzz::Bytes b(data, size);
    const QuadLayout layouts[] = {torus_layout(),  cube_layout(),  icosahedron_layout(),
                                  prism_layout(8), disk_layout(2), annulus_layout()};
    Case c;
    c.layout = &layouts[b.range(0, 5)];
    c.n = b.range(1, 3);
    c.k = b.range(1, 5);
    std::vector<char> single_chart;
    const int diagonals = b.range(0, 2);
    const std::uint32_t seed = b.u32();
    c.in = make_map(*c.layout, c.n, c.k, diagonals, seed, &single_chart);
    std::mt19937 rng(b.u32());
    for (int ops = b.range(0, 6); ops > 0 && !b.empty(); --ops) perturb(b, b.range(0, 12), single_chart, rng, c);
    Options opt;
    opt.max_qvertices = 200000;
    opt.snap_boundary = b.byte() & 1;
    const Result r = extract(c.in, opt);
    if (!r.ok()) {
        if (c.benign) fuzz::fail(std::string("a generated map is valid input: ") + r.error.message);
        if (r.error.message.empty()) fuzz::fail("an error without a message");
        return 0;
    }
    const VerifyResult v = verify(c.in, r.mesh);
    if (const std::string why = result_inconsistency(c.in, r, &v); !why.empty()) fuzz::fail(why);
    const bool exact_expected = c.benign && (!c.noise || v.input_boundary_loops == 0 || opt.snap_boundary);
    const auto quads = static_cast<std::int64_t>(r.mesh.faces.size());
    const std::int64_t generated = expected_quads(*c.layout, c.n);
    if (exact_expected && (!v.valid || quads != v.input_signed_uv_area_rounded || quads != generated))
        fuzz::fail(std::string(v.valid ? "valid" : "invalid") + " mesh of " + std::to_string(quads) +
                   " quads on a map of area " + std::to_string(v.input_signed_uv_area_rounded) +
                   " (generated: " + std::to_string(generated) + ")");
    check_without_provenance(b, c, opt, r, v.valid);
    return 0;
}

// Structure-aware: the bytes choose a generated integer-grid map and a sequence of perturbations,
// then run extraction and the exact checker. Perturbations the paper handles must give a valid
// mesh with the map's area; any others must give a valid mesh or reported defects.
#include "fuzz_input.h"
#include "map_generators.h"

#include <cmath>
#include <cstdlib>
#include <limits>

using namespace qex;
using namespace qex::testing;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    fuzz::Bytes b(data, size);
    const QuadLayout layouts[] = {torus_layout(), cube_layout(), icosahedron_layout(), prism_layout(8),
                                  disk_layout(2), annulus_layout()};
    const QuadLayout& layout = layouts[b.range(0, 5)];
    const int n = b.range(1, 3), k = b.range(1, 5);
    std::vector<char> single_chart;
    Input in = make_map(layout, n, k, b.range(0, 2), b.u32(), &single_chart);
    std::mt19937 rng(b.u32());
    bool benign = true; // only perturbations after which the exact result is required
    for (int ops = b.range(0, 6); ops > 0 && !b.empty(); --ops) {
        const int nf = static_cast<int>(in.triangles.size()), nv = static_cast<int>(in.positions.size());
        switch (b.range(0, 12)) {
            case 0: rechart(in, rng, 1 << b.range(0, 20)); break;
            case 1: shuffle(in, rng); break;
            case 2: translate(in, std::int64_t{1} << b.range(0, 40), -(std::int64_t{1} << b.range(0, 40))); break;
            case 3: rotate(in, b.range(0, 3)); break;
            case 4: add_noise(in, std::ldexp(1.0, -b.range(20, 50)), rng); break;
            case 5: { // fold-over at a single-chart vertex
                const int v = b.range(0, nv - 1);
                if (v < static_cast<int>(single_chart.size()) && single_chart[v]) {
                    displace_vertex(in, v, b.unit() * n / k * 1.5, b.unit() * n / k * 1.5);
                    benign = false;
                }
                break;
            }
            case 6: insert_collapsed_edge(in, b.range(0, nf - 1), b.range(0, 2)); single_chart.push_back(0); in.valences.clear(); break;
            case 7: insert_zero_area_triangle(in, b.range(0, nf - 1), b.range(0, 2)); single_chart.push_back(0); in.valences.clear(); benign = false; break;
            case 8: in.uvs[b.range(0, 3 * nf - 1)][b.range(0, 1)] = (b.byte() & 1) ? std::numeric_limits<double>::quiet_NaN() : std::numeric_limits<double>::infinity(); benign = false; break;
            case 9: in.triangles.push_back(in.triangles[b.range(0, nf - 1)]); in.uvs.resize(3 * in.triangles.size()); benign = false; break;
            case 11: { // a feature edge: an edge of the mesh, or (rarely) an arbitrary pair
                const int f = b.range(0, nf - 1), k = b.range(0, 2);
                if (b.byte() < 240) in.feature_edges.push_back({in.triangles[f][k], in.triangles[f][(k + 1) % 3]});
                else in.feature_edges.push_back({b.range(-1, nv), b.range(-1, nv)}), benign = false;
                break;
            }
            case 12: { // valences given by the caller: 4 everywhere except a few, possibly wrong
                in.valences.assign(in.positions.size(), 4);
                for (int i = b.range(0, 4); i > 0; --i) in.valences[b.range(0, nv - 1)] = b.range(0, 9);
                benign = false; // a wrong valence moves a vertex onto a grid point
                break;
            }
            default: {
                const int f = b.range(0, nf - 1);
                in.triangles.erase(in.triangles.begin() + f);
                in.uvs.erase(in.uvs.begin() + 3 * f, in.uvs.begin() + 3 * f + 3);
                benign = false;
                break;
            }
        }
    }
    Options opt;
    opt.max_qvertices = 200000;
    opt.snap_boundary = b.byte() & 1;
    const Result r = extract(in, opt);
    if (!r.ok()) {
        if (benign || r.error.message.empty()) std::abort(); // a generated map is valid input
        return 0;
    }
    const VerifyResult v = verify(in, r.mesh);
    if (!v.valid && r.report.defects.empty()) std::abort();
    // The oracle for other extractors (no provenance): on a fold-free map it must agree, and on
    // a damaged copy of the mesh it must not crash.
    QuadMesh bare = r.mesh;
    bare.provenance.clear();
    bare.map_uvs.clear();
    bare.face_uvs.clear();
    const VerifyResult located = verify(in, bare);
    // (Snapped features and boundaries move the map, and explained deficits leave cells uncovered.)
    if (benign && in.feature_edges.empty() && !opt.snap_boundary && v.valid && r.report.explanations.empty() &&
        !located.valid)
        std::abort();
    for (int ops = b.range(0, 3); ops > 0 && !b.empty() && !bare.faces.empty(); --ops) {
        auto& face = bare.faces[b.range(0, static_cast<int>(bare.faces.size()) - 1)];
        if (face.size() < 2) continue;
        switch (b.range(0, 3)) {
            case 0: std::swap(face[0], face[b.range(1, static_cast<int>(face.size()) - 1)]); break;
            case 1: face[b.range(0, static_cast<int>(face.size()) - 1)] = b.range(-1, static_cast<int>(bare.positions.size())); break;
            case 2: bare.positions[b.range(0, static_cast<int>(bare.positions.size()) - 1)][b.range(0, 2)] += b.unit() - 0.5; break;
            default: face.pop_back(); break;
        }
    }
    (void)verify(in, bare);
    return 0;
}

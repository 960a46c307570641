// qex_broken_extractor MODE IN.obj OUT.obj: qex's extraction (the library), its output broken
// on purpose in one way, for the test of `qex conform`'s outcomes (cli_conform_test.py). MODE:
//   none          the valid mesh (exact)
//   drop_face     the first face left out                      (invalid_exit_0)
//   rotate_edge   an edge between two quads rotated             (invalid_exit_0)
//   move_vertex   a vertex moved half an edge                   (invalid_exit_0)
//   one_triangle  a single triangle written                     (invalid_exit_0)
//   no_write      exit 0 without writing                        (no_output)
//   empty         exit 0 with an empty file                     (no_output)
//   crash         ends by SIGSEGV                               (crash)
//   hang          never ends                                    (timeout)
//   wrong_map     the valid mesh of the map with its UVs x 3    (invalid_exit_0)
//                 (no grid scale 2^j refines a grid of thirds: the wrong map at every scale)
//   refined       the valid mesh of the map with its UVs x 2, as qex extract refines: valid at
//                 grid scale 2 (wrong_count on a known case, valid on a user's map)
#include "qex/qex.h"

#include <csignal>
#include <cstdio>
#include <fstream>
#include <map>
#include <string>
#include <unistd.h>

namespace {

/// Rotates the first interior edge u-v between faces f = (u, v, f2, f3) and g = (v, u, g2, g3)
/// within their hexagon: the faces become (f3, u, g2, g3) and (g3, v, f2, f3).
bool rotate_edge(qex::QuadMesh& m) {
    std::map<std::pair<int, int>, std::pair<std::size_t, int>> half; // (from, to) -> face, corner
    for (std::size_t f = 0; f < m.faces.size(); ++f)
        for (int c = 0; c < 4 && m.faces[f].size() == 4; ++c) half[{m.faces[f][c], m.faces[f][(c + 1) % 4]}] = {f, c};
    for (const auto& [e, fc] : half) {
        const auto twin = half.find({e.second, e.first});
        if (twin == half.end()) continue;
        const auto& F = m.faces[fc.first];
        const auto& G = m.faces[twin->second.first];
        const int c = fc.second, d = twin->second.second;
        const int u = F[c], v = F[(c + 1) % 4], f2 = F[(c + 2) % 4], f3 = F[(c + 3) % 4];
        const int g2 = G[(d + 2) % 4], g3 = G[(d + 3) % 4];
        m.faces[fc.first] = {f3, u, g2, g3};
        m.faces[twin->second.first] = {g3, v, f2, f3};
        return true;
    }
    return false;
}

int write(const std::string& path, const qex::QuadMesh& mesh) { return qex::write_obj(path, mesh, 1).ok() ? 0 : 2; }

} // namespace

int main(int argc, char** argv) {
    if (argc != 4) {
        std::fprintf(stderr, "usage: qex_broken_extractor MODE IN.obj OUT.obj\n");
        return 1;
    }
    const std::string mode = argv[1], in_path = argv[2], out_path = argv[3];
    if (mode == "crash") std::raise(SIGSEGV);
    if (mode == "hang")
        for (;;) pause();
    if (mode == "no_write") return 0;
    if (mode == "empty") return std::ofstream(out_path) ? 0 : 2;
    qex::Input input;
    if (const qex::IoError e = qex::read_obj(in_path, input, 1); !e.ok()) {
        std::fprintf(stderr, "qex_broken_extractor: %s\n", e.message.c_str());
        return 3;
    }
    if (mode == "wrong_map" || mode == "refined") {
        const double k = mode == "refined" ? 2 : 3;
        for (auto& uv : input.uvs) uv = {k * uv[0], k * uv[1]};
    }
    qex::Options options;
    options.threads = 1;
    qex::Result r = qex::extract(input, options);
    if (!r.ok() || !r.check.valid) return 5;
    qex::QuadMesh& m = r.mesh;
    m.face_uvs.clear(); // local UVs would no longer match the broken faces
    if (mode == "drop_face")
        m.faces.erase(m.faces.begin());
    else if (mode == "rotate_edge" && !rotate_edge(m))
        return 6;
    else if (mode == "move_vertex") {
        const auto& f = m.faces[0];
        auto& p = m.positions[f[0]];
        const auto& q = m.positions[f[1]];
        for (int k = 0; k < 3; ++k) p[k] += 0.5 * (q[k] - p[k]);
    } else if (mode == "one_triangle") {
        m.faces = {{m.faces[0][0], m.faces[0][1], m.faces[0][2]}};
    }
    return write(out_path, m);
}

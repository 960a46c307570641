// Bytes as a quad grid (plane, cylinder or torus) with faces left out, feature edges and one face
// reversed or cut to a triangle at will (property_tests/quad_grids.h): the layout must be refused
// with a reason, or be one its independent check accepts with patch sizes that add up to the face
// count. The check is then run on a mutated copy of the layout and must not crash.
#include "fuzz_input.h"
#include "quad_grids.h"

#include "qex/layout.h"

#include <algorithm>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    qex::fuzz::Bytes in(data, size);
    const int w = in.range(3, 12), h = in.range(3, 12), kind = in.byte() % 4;
    std::vector<char> keep(w * h, 1);
    for (int k = in.byte() % 24; k > 0; --k) keep[in.byte() % keep.size()] = 0;
    qex::QuadMesh mesh = qex::testing::quad_grid(w, h, kind & 1, kind & 2, keep);
    if (mesh.faces.empty()) return 0;
    const std::uint8_t damage = in.byte();
    auto& f0 = mesh.faces[in.byte() % mesh.faces.size()];
    if (damage == 1) std::reverse(f0.begin(), f0.end());
    if (damage == 2) f0.pop_back();
    qex::LayoutOptions options;
    for (int k = in.byte() % 6; k > 0; --k) { // a face's edge, or (rarely) any pair
        const auto& f = mesh.faces[in.byte() % mesh.faces.size()];
        const int c = in.byte() % 4;
        options.feature_edges.push_back({f[c % f.size()], f[(c + 1) % f.size()]});
    }
    const qex::Layout l = qex::extract_layout(mesh, options);
    if (!l.valid) {
        if (l.error.empty()) qex::fuzz::fail("an invalid layout without a reason");
        return 0;
    }
    long long area = 0;
    for (const qex::Patch& p : l.patches) area += static_cast<long long>(p.u) * p.v;
    if (area != static_cast<long long>(mesh.faces.size())) qex::fuzz::fail("patch sizes do not add up to the faces");
    if (!qex::check_layout(mesh, l, options).empty()) qex::fuzz::fail("a valid layout the check rejects");
    qex::Layout bad = l; // the check must judge nonsense without crashing
    const std::uint8_t what = in.byte();
    if (!bad.separatrices.empty()) bad.separatrices[what % bad.separatrices.size()].vertices.push_back(in.byte() - 128);
    if (!bad.patches.empty()) bad.patches[what % bad.patches.size()].u += in.byte() % 3 - 1;
    if (what & 1) bad.face_patch[what % bad.face_patch.size()] = in.byte() - 128;
    if (what & 2 && !bad.patches.empty()) bad.patches[0].corners[what % 4] = in.byte() - 128;
    qex::check_layout(mesh, bad, options);
    return 0;
}

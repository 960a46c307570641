// Raw doubles as the UVs of a small fixed mesh through the preprocessing: either a clean error, or
// the sanitization's invariants hold exactly (transitions map corners bit for bit, fans close).
#include "fuzz_input.h"
#include "map_generators.h"
#include "pipeline.h"

using namespace qex;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const Input base = testing::make_map(testing::torus_layout(3, 3), 1, 2);
    fuzz::Bytes b(data, size);
    Input in = base;
    const bool raw = b.byte() & 1;
    for (auto& uv : in.uvs)
        for (double& x : uv) {
            if (b.empty()) break;
            x = raw ? b.raw_double() : x + b.unit() * 0.3;
        }
    if (detail::validate_input_values(in).code != ErrorCode::None) return 0;
    detail::TriMesh m = detail::make_mesh(in);
    if (detail::build_topology(m, "fuzz").code != ErrorCode::None) fuzz::fail("the fixed mesh's topology was rejected");
    std::int64_t collapsed = 0;
    if (detail::collapse(m, collapsed).code != ErrorCode::None) return 0;
    detail::compute_transitions(m);
    detail::count_valences(m);
    Report report;
    if (detail::sanitize(m, {}, {}, report).code != ErrorCode::None) return 0;
    for (int h = 0; h < 3 * m.num_faces(); ++h) {
        const int o = m.opp[h];
        if (o < 0) continue;
        if (!(m.map.transition[o] == m.map.transition[h].inverse()))
            fuzz::fail("opposite transitions are not inverses");
        // Exactness holds while coordinates stay below 2^52 (validated).
        if (m.map.transition[h](m.uv[h]) != m.uv[detail::TriMesh::next(o)])
            fuzz::fail("a transition does not map an edge's first corner exactly");
        if (m.map.transition[h](m.uv[detail::TriMesh::next(h)]) != m.uv[o])
            fuzz::fail("a transition does not map an edge's second corner exactly");
    }
    return 0;
}

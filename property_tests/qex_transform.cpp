// qex_transform IN.obj OUT.obj OPS...: writes a transformed copy of an OBJ map (map_transforms.h),
// e.g. `qex_transform duck.obj duck_x8.obj scale 8 rechart 1 shuffle 2`. Transforms apply in the
// order given: scale K, translate TX TY, rechart SEED [T], shuffle SEED, subdivide.
// Exit codes: 0 written, 1 usage, 2 cannot read or write. Prints how many UV coordinates a scale
// or translation rounded (0: the new map is exact).
#include "map_generators.h"
#include "map_transforms.h"

#include <cstdio>
#include <fstream>
#include <string>

int main(int argc, char** argv) {
    if (argc < 3) {
        std::fprintf(stderr,
                     "usage: %s IN.obj OUT.obj [scale K | translate TX TY | rechart SEED [T] | "
                     "shuffle SEED | subdivide]...\n",
                     argv[0]);
        return 1;
    }
    qex::Input in;
    if (const qex::IoError e = qex::read_obj(argv[1], in); !e.ok()) {
        std::fprintf(stderr, "%s: %s\n", argv[1], e.message.c_str());
        return 2;
    }
    std::string ops;
    for (int i = 3; i < argc; ++i) ops += std::string(argv[i]) + " ";
    const auto flipped_before = qex::testing::count_flipped(in);
    std::int64_t rounded = 0;
    if (const std::string why = qex::testing::transforms::apply(in, ops, &rounded); !why.empty()) {
        std::fprintf(stderr, "%s\n", why.c_str());
        return 1;
    }
    std::ofstream out(argv[2], std::ios::binary);
    out << qex::testing::to_obj(in);
    out.close();
    if (!out) {
        std::fprintf(stderr, "%s: cannot write\n", argv[2]);
        return 2;
    }
    std::fprintf(stderr, "%zu triangles, flipped %lld before, %lld after, %lld UV coordinates rounded\n",
                 in.triangles.size(), static_cast<long long>(flipped_before),
                 static_cast<long long>(qex::testing::count_flipped(in)), static_cast<long long>(rounded));
    return 0;
}

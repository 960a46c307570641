// Extracts a map with the installed library and judges the mesh with the installed checker.
#include <qex/qex.h>

#include <cstdio>

int main(int argc, char** argv) {
    if (argc != 2) return 2;
    qex::Input in;
    if (const qex::IoError e = qex::read_obj(argv[1], in); !e.ok()) {
        std::fprintf(stderr, "%s\n", e.message.c_str());
        return 3;
    }
    const qex::Result r = qex::extract(in);
    if (!r.ok()) return 4;
    const qex::VerifyResult v = qex::verify(in, r.mesh);
    std::printf("%zu quads, %s\n", r.mesh.faces.size(), v.valid ? "valid" : "invalid");
    return v.valid && !r.mesh.faces.empty() ? 0 : 5;
}

// Links qex::verify alone: a unit square made of two triangles, and a quad mesh of it that
// the checker must accept, then one with a reversed face that it must reject.
#include <qex/verify.h>

#include <cstdio>

int main() {
    qex::Input in;
    in.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    in.triangles = {{0, 1, 2}, {0, 2, 3}};
    in.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 0}, {1, 1}, {0, 1}};
    qex::QuadMesh quad;
    quad.positions = in.positions;
    quad.faces = {{0, 1, 2, 3}};
    const bool accepted = qex::verify(in, quad).valid;
    quad.faces = {{0, 3, 2, 1}};
    const bool rejected = !qex::verify(in, quad).valid;
    std::printf("accepted %d, rejected %d\n", accepted, rejected);
    return accepted && rejected ? 0 : 1;
}

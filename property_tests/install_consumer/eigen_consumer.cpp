// Uses the installed qex/eigen.h: a map read as arrays in libigl's conventions (V, F, TC, FTC),
// extracted, and the mesh copied out as QV, QF.
#include <qex/eigen.h>

#include <cstdio>

int main(int argc, char** argv) {
    if (argc != 2) return 2;
    qex::Input obj;
    if (!qex::read_obj(argv[1], obj).ok()) return 3;
    Eigen::MatrixXd V(obj.positions.size(), 3), TC(obj.uvs.size(), 2);
    Eigen::MatrixXi F(obj.triangles.size(), 3), FTC(obj.triangles.size(), 3);
    for (std::size_t i = 0; i < obj.positions.size(); ++i)
        V.row(i) << obj.positions[i][0], obj.positions[i][1], obj.positions[i][2];
    for (std::size_t f = 0; f < obj.triangles.size(); ++f)
        for (int k = 0; k < 3; ++k) {
            F(f, k) = obj.triangles[f][k];
            FTC(f, k) = static_cast<int>(3 * f + k);
            TC.row(3 * f + k) << obj.uvs[3 * f + k][0], obj.uvs[3 * f + k][1];
        }
    const qex::Result r = qex::extract(qex::from_eigen(V, F, TC, FTC));
    Eigen::MatrixXd QV;
    Eigen::MatrixXi QF;
    qex::to_eigen(r.mesh, QV, QF);
    std::printf("eigen: %ld quads, %ld vertices, %s\n", static_cast<long>(QF.rows()), static_cast<long>(QV.rows()),
                r.check.valid ? "valid" : "invalid");
    return r.ok() && r.check.valid && QF.rows() == static_cast<Eigen::Index>(r.mesh.faces.size()) ? 0 : 1;
}

// qex/eigen.h against Debian's Eigen: libigl-style arrays in (V, F, TC, FTC, with shared UVs
// indexed per corner), the same Input and the same mesh as the OBJ path, and the mesh out as QV, QF.
#include <qex/eigen.h>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <string>
#include <utility>

#ifndef QEX_SHARED_DIR
#define QEX_SHARED_DIR "../shared"
#endif
#ifndef QEX_CORPUS_DIR
#define QEX_CORPUS_DIR "corpus"
#endif

namespace {

using RowMajorXd = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using IndicesX3 = Eigen::Matrix<long long, Eigen::Dynamic, 3>;

/// The Input as libigl holds it: TC the distinct UVs, FTC the corners' indices into TC.
struct Arrays {
    Eigen::MatrixXd V;
    Eigen::MatrixXi F;
    RowMajorXd TC;
    IndicesX3 FTC;
};

Arrays to_arrays(const qex::Input& in) {
    Arrays a;
    a.V.resize(static_cast<Eigen::Index>(in.positions.size()), 3);
    for (std::size_t i = 0; i < in.positions.size(); ++i)
        for (int c = 0; c < 3; ++c) a.V(static_cast<Eigen::Index>(i), c) = in.positions[i][c];
    a.F.resize(static_cast<Eigen::Index>(in.triangles.size()), 3);
    a.FTC.resize(a.F.rows(), 3);
    std::map<std::pair<double, double>, long long> index;
    std::vector<std::array<double, 2>> tc;
    for (std::size_t f = 0; f < in.triangles.size(); ++f)
        for (int k = 0; k < 3; ++k) {
            a.F(static_cast<Eigen::Index>(f), k) = in.triangles[f][k];
            const auto& uv = in.uvs[3 * f + k];
            const auto [it, added] = index.emplace(std::make_pair(uv[0], uv[1]), static_cast<long long>(tc.size()));
            if (added) tc.push_back(uv);
            a.FTC(static_cast<Eigen::Index>(f), k) = it->second;
        }
    a.TC.resize(static_cast<Eigen::Index>(tc.size()), 2);
    for (std::size_t t = 0; t < tc.size(); ++t)
        for (int c = 0; c < 2; ++c) a.TC(static_cast<Eigen::Index>(t), c) = tc[t][c];
    return a;
}

/// Bitwise the same map.
void expect_same_input(const qex::Input& a, const qex::Input& b) {
    EXPECT_EQ(a.positions, b.positions);
    EXPECT_EQ(a.triangles, b.triangles);
    ASSERT_EQ(a.uvs.size(), b.uvs.size());
    for (std::size_t i = 0; i < a.uvs.size(); ++i) ASSERT_EQ(a.uvs[i], b.uvs[i]) << "corner " << i;
}

/// Reads `path`, goes through the arrays, and requires the mesh of the OBJ path, as QV and QF too.
void round_trip(const std::string& path) {
    qex::Input obj;
    const qex::IoError e = qex::read_obj(path, obj);
    ASSERT_TRUE(e.ok()) << e.message;
    const Arrays a = to_arrays(obj);
    ASSERT_LT(a.TC.rows(), static_cast<Eigen::Index>(obj.uvs.size())) << "the test means to share UVs";
    const qex::Input in = qex::from_eigen(a.V, a.F, a.TC, a.FTC);
    expect_same_input(obj, in);

    const qex::Result want = qex::extract(obj);
    const qex::Result got = qex::extract(in);
    ASSERT_TRUE(got.ok()) << got.error.message;
    EXPECT_EQ(got.check.valid, want.check.valid);
    EXPECT_EQ(got.mesh.positions, want.mesh.positions);
    EXPECT_EQ(got.mesh.faces, want.mesh.faces);

    Eigen::MatrixXd QV;
    Eigen::MatrixXi QF;
    qex::to_eigen(got.mesh, QV, QF);
    ASSERT_EQ(QV.rows(), static_cast<Eigen::Index>(got.mesh.positions.size()));
    ASSERT_EQ(QF.rows(), static_cast<Eigen::Index>(got.mesh.faces.size()));
    ASSERT_EQ(QF.cols(), 4);
    for (Eigen::Index f = 0; f < QF.rows(); ++f)
        for (Eigen::Index c = 0; c < 4; ++c) EXPECT_EQ(QF(f, c), got.mesh.faces[f][c]);
    for (Eigen::Index v = 0; v < QV.rows(); ++v)
        for (Eigen::Index c = 0; c < 3; ++c) EXPECT_EQ(QV(v, c), got.mesh.positions[v][c]);
}

TEST(Eigen, SampleMapSameAsObjPath) { round_trip(QEX_CORPUS_DIR "/fuzz_obj/valid/cube_n3_k4.obj"); }

TEST(Eigen, PaperMapSameAsObjPath) {
    const std::string path = QEX_SHARED_DIR "/meshes/paper/duck_miq_4_param.obj";
    if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is absent (the shared maps beside the checkout)";
    round_trip(path);
}

TEST(Eigen, ExpressionsAndPerVertexUvs) {
    // A flat 2x2 square given as expressions (a block, a cast), TC per vertex with FTC = F.
    Eigen::Matrix<double, 4, 3> V;
    V << 0, 0, 0, 2, 0, 0, 2, 2, 0, 0, 2, 0;
    Eigen::Matrix<int, 2, 3> F;
    F << 0, 1, 2, 0, 2, 3;
    const qex::Input in = qex::from_eigen(V.cast<float>(), F, V.leftCols<2>(), F);
    const qex::Result r = qex::extract(in);
    ASSERT_TRUE(r.ok()) << r.error.message;
    EXPECT_TRUE(r.check.valid);
    Eigen::Matrix<float, Eigen::Dynamic, 3> QV;
    Eigen::Matrix<int, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> QF;
    qex::to_eigen(r.mesh, QV, QF);
    EXPECT_EQ(QF.rows(), 4);
    EXPECT_EQ(QV.rows(), 9);
}

TEST(Eigen, BadArraysAreRejectedByExtract) {
    Eigen::MatrixXd V(4, 3);
    V << 0, 0, 0, 2, 0, 0, 2, 2, 0, 0, 2, 0;
    Eigen::MatrixXi F(2, 3);
    F << 0, 1, 2, 0, 2, 3;
    Eigen::MatrixXd TC = V.leftCols(2);
    // Wrong shapes: an empty Input.
    EXPECT_EQ(qex::extract(qex::from_eigen(V.leftCols(2), F, TC, F)).error.code, qex::ErrorCode::EmptyMesh);
    EXPECT_EQ(qex::extract(qex::from_eigen(V, F, TC, F.topRows(1))).error.code, qex::ErrorCode::EmptyMesh);
    // A UV index out of range: a NaN corner, named by extract().
    Eigen::MatrixXi FTC = F;
    FTC(1, 2) = 99;
    EXPECT_EQ(qex::extract(qex::from_eigen(V, F, TC, FTC)).error.code, qex::ErrorCode::NonFiniteValue);
    Eigen::MatrixXi G = F;
    G(0, 1) = 4;
    EXPECT_EQ(qex::extract(qex::from_eigen(V, G, TC, F)).error.code, qex::ErrorCode::IndexOutOfRange);
}

} // namespace

// qex <-> Eigen arrays in libigl's conventions (header-only; needs Eigen 3). For programs that
// keep their meshes as libigl does: V (#V x 3) positions, F (#F x 3) triangles, TC (#TC x 2) UVs
// and FTC (#F x 3) per-corner indices into TC, so that corner k of triangle f has UV TC.row(FTC(f, k)).
//
//   qex::Result r = qex::extract(qex::from_eigen(V, F, TC, FTC));
//   Eigen::MatrixXd QV; Eigen::MatrixXi QF;
//   qex::to_eigen(r.mesh, QV, QF);
#pragma once

#include "qex/qex.h"

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <limits>

namespace qex {

/// Builds a qex::Input from libigl-style arrays. Shapes are not asserted: rows of F or FTC with
/// fewer than 3 columns, or an FTC with fewer rows than F, give an empty Input (which extract()
/// rejects as EmptyMesh); indices are copied as they are, so extract() names any out of range.
/// @param[in] V   #V by 3 vertex positions (any floating or integer scalar)
/// @param[in] F   #F by 3 triangles, indices into V, counter-clockwise
/// @param[in] TC  #TC by 2 parameter coordinates
/// @param[in] FTC #F by 3 indices into TC, one per triangle corner (libigl's FTC, or F itself
///                when TC holds one UV per vertex)
template <class DerivedV, class DerivedF, class DerivedTC, class DerivedFTC>
Input from_eigen(const Eigen::MatrixBase<DerivedV>& V, const Eigen::MatrixBase<DerivedF>& F,
                 const Eigen::MatrixBase<DerivedTC>& TC, const Eigen::MatrixBase<DerivedFTC>& FTC) {
    Input in;
    if (V.cols() != 3 || F.cols() != 3 || TC.cols() != 2 || FTC.cols() != 3 || FTC.rows() != F.rows()) return in;
    in.positions.resize(static_cast<std::size_t>(V.rows()));
    for (Eigen::Index i = 0; i < V.rows(); ++i)
        in.positions[static_cast<std::size_t>(i)] = {static_cast<double>(V(i, 0)), static_cast<double>(V(i, 1)),
                                                     static_cast<double>(V(i, 2))};
    in.triangles.resize(static_cast<std::size_t>(F.rows()));
    in.uvs.resize(3 * in.triangles.size());
    for (Eigen::Index f = 0; f < F.rows(); ++f) {
        const auto fi = static_cast<std::size_t>(f);
        for (Eigen::Index k = 0; k < 3; ++k) {
            in.triangles[fi][static_cast<std::size_t>(k)] = static_cast<int>(F(f, k));
            const auto t = static_cast<Eigen::Index>(FTC(f, k));
            // A UV index out of range would read outside TC: the corner gets a NaN UV instead,
            // which extract() rejects naming the triangle.
            const bool in_range = t >= 0 && t < TC.rows();
            const double nan = std::numeric_limits<double>::quiet_NaN();
            in.uvs[3 * fi + static_cast<std::size_t>(k)] = {in_range ? static_cast<double>(TC(t, 0)) : nan,
                                                            in_range ? static_cast<double>(TC(t, 1)) : nan};
        }
    }
    return in;
}

/// Copies a quad mesh into libigl-style arrays. Faces with other than 4 corners (only in a mesh
/// the checker rejected) are left out.
/// @param[in]  mesh the extracted mesh (qex::Result::mesh)
/// @param[out] QV   #QV by 3 vertex positions
/// @param[out] QF   #QF by 4 quads, indices into QV, counter-clockwise
template <class DerivedQV, class DerivedQF>
void to_eigen(const QuadMesh& mesh, Eigen::PlainObjectBase<DerivedQV>& QV, Eigen::PlainObjectBase<DerivedQF>& QF) {
    using SV = typename DerivedQV::Scalar;
    using SF = typename DerivedQF::Scalar;
    QV.resize(static_cast<Eigen::Index>(mesh.positions.size()), 3);
    for (std::size_t i = 0; i < mesh.positions.size(); ++i)
        for (Eigen::Index c = 0; c < 3; ++c)
            QV(static_cast<Eigen::Index>(i), c) = static_cast<SV>(mesh.positions[i][static_cast<std::size_t>(c)]);
    Eigen::Index quads = 0;
    for (const auto& f : mesh.faces) quads += f.size() == 4 ? 1 : 0;
    QF.resize(quads, 4);
    Eigen::Index row = 0;
    for (const auto& f : mesh.faces) {
        if (f.size() != 4) continue;
        for (Eigen::Index c = 0; c < 4; ++c) QF(row, c) = static_cast<SF>(f[static_cast<std::size_t>(c)]);
        ++row;
    }
}

} // namespace qex

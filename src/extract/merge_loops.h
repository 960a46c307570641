// The face walks of merge_vertices (stage 12) as loops of corners, shared by the stage's two
// files: 11_merge_vertices.cpp (lost-edge recovery, clone merging, simplification, output) and
// 11_cancel_ghosts.cpp (ghost and near-ghost faces cancelled).
#pragma once

#include "pipeline.h"
#include "union_find.h"

#include <vector>

namespace qex::detail::merging {

/// A corner of a face walk: its q-vertex and its local UV.
struct Corner {
    int v;
    IPoint uv;
};
using Loop = std::vector<Corner>;

/// Twice the signed area enclosed by the local UVs of a walk, taken relative to its first corner
/// and accumulated in 128 bits: broken maps give walks whose local UVs lie 2^40 apart.
inline __int128 twice_area(const Loop& l) {
    __int128 a = 0;
    const IPoint& o = l[0].uv;
    for (std::size_t i = 1; i + 1 < l.size(); ++i) {
        const __int128 px = l[i].uv[0] - o[0], py = l[i].uv[1] - o[1];
        const __int128 qx = l[i + 1].uv[0] - o[0], qy = l[i + 1].uv[1] - o[1];
        a += px * qy - py * qx;
    }
    return a;
}

/// 4. Removes the pairs of a face and its reverse from `simple` (11_cancel_ghosts.cpp).
void cancel_ghost_faces(const TriMesh& m, const QState& q, std::vector<Loop>& simple, Report& report);
/// 5. Removes the pairs of a clockwise quad and a quad with three of its corners in reverse
///    order, merging their odd corners in `sets` (11_cancel_ghosts.cpp).
void cancel_near_ghosts(const TriMesh& m, const QState& q, std::vector<Loop>& simple, UnionFind& sets, Report& report);

} // namespace qex::detail::merging

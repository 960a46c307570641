// The located mode's face check: a face's corners, each located in some input triangle, are
// carried into the chart of one anchor triangle along the input's transitions (a shortest-path
// search over the triangles), and there must be the corners of one counter-clockwise unit grid
// cell. The search's distances choose the paths; the grid points are compared as integers.
// This header is the check's room: the judge of one face and what it finds, whose search and
// reports live in face_cells.cpp and whose corridors (an edge's homotopy class) in
// face_corridor.cpp. Only these files include it.
#pragma once

#include "checker.h"

#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace qex::verify_detail::face_cells {

/// A face's four corners as grid points in one chart.
using Quad = std::array<GridPoint, 4>;

/// What the anchors of one face showed: whether one showed a unit cell; the first anchor that
/// reached all four corners and the grid points there; per edge (i, i+1), whether an anchor at
/// one of its ends judged it, and whether one saw a unit step.
struct Anchors {
    bool cell = false, reached_all = false;
    Quad first{};
    std::uint32_t first_anchor = 0;
    std::array<bool, 4> edge_ok{false, false, false, false}, edge_seen{false, false, false, false};
};

/// The corridor of a face's edge (a, b): the triangles within kCorridor |ab| of the segment ab,
/// reached from a's triangle. Where the transitions compose to the same map along every path
/// inside it (checked edge by edge), no fold-over lies in it and no cone but at a or b (whose
/// fans are cut: turning about an end keeps the distance to it), carrying b's grid point
/// through it gives one answer, the one along any iso-line from a to b inside it: a path
/// homotopic to the edge. A correct mesh's edge is a unit iso-line whose arc stays within
/// kCorridor of its chord (an arc up to twice as long as its chord does).
constexpr double kCorridor = 0.5;
/// Triangles a corridor holds at most (beyond: not certified).
constexpr std::size_t kCorridorBudget = 1u << 14;

/// An edge carried through its corridor: b's grid point in the chart of a's triangle, and the
/// map from the chart b was read in to that chart.
struct Edge {
    GridPoint b{0, 0};
    Transition m;
    bool b_on_cone = false;
};

/// Judges the faces one by one; keeps the search's scratch between them.
class FaceJudge {
public:
    FaceJudge(const LocatedMap& map, const QuadMesh& mesh, const std::vector<Located>& loc);
    /// Face f: passes, or appends its violation (or undecided check).
    void judge(std::size_t f, VerifyResult& r, std::vector<Violation>& out);

private:
    /// Each corner's triangle in turn, then the triangle under the face's centre.
    Anchors try_anchors(const std::vector<int>& face, const std::array<double, 3>& centre);
    /// All four corners carried into the chart of anchor tc (into g_); false when the search
    /// does not reach them all.
    bool transport(const std::vector<int>& face, std::uint32_t tc);
    /// The triangle where the search from tc reached each corner, or -1.
    std::array<std::int64_t, 4> search(const std::vector<int>& face, std::uint32_t tc);
    /// The grid point of the located vertex L, read in triangle t0, carried back to tc along the search's path.
    GridPoint carry(const Located& L, std::uint32_t t0, std::uint32_t tc);
    /// Reports the failure of face f: a violation when `certified` and no path or corner
    /// touched a fold-over or a singular fan, else undecided.
    void report(std::size_t f, const std::string& msg, bool certified, VerifyResult& r,
                std::vector<Violation>& out) const;
    /// Reports each edge of face f that the anchors judged and saw no unit step on, nor its
    /// corridor certified as one (`along`, `certified`); returns whether there was none.
    bool report_edges(std::size_t f, const Anchors& a, const std::array<Edge, 4>& along,
                      const std::array<bool, 4>& certified, VerifyResult& r, std::vector<Violation>& out) const;
    /// A fold-over shares a vertex with triangle t.
    bool near_fold(std::uint32_t t) const;

    // --- the corridors (face_corridor.cpp)
    /// Carries vertex b's grid point into the chart of vertex a's triangle through the corridor
    /// of the edge (a, b) (see kCorridor): false when the corridor does not certify one answer.
    bool along_edge(int a, int b, Edge& e);
    /// Floods the corridor of the segment from pa to pb (radius rho) from triangle t0, each triangle's map to
    /// t0's chart into to_start_, never across an edge at the cones cone_a and cone_b (-1: none);
    /// false when it meets a fold-over, a crossing without a known transition or two maps that
    /// disagree, or grows beyond kCorridorBudget.
    bool flood_corridor(std::uint32_t t0, const std::array<double, 3>& pa, const std::array<double, 3>& pb, double rho,
                        std::int64_t cone_a, std::int64_t cone_b);
    /// b's grid point carried into the corridor's start chart: read in b's own triangle, or for
    /// b on the cone cone_b (-1: not), in the first triangle of its fan the corridor reached;
    /// false when the corridor did not reach it.
    bool read_end(const Located& B, std::int64_t cone_b, Edge& e) const;
    /// The corridor's triangles: within kCorridor |ab| of the segment ab (a superset: by centroid
    /// distance less the triangle's radius).
    bool in_corridor(std::uint32_t t, const std::array<double, 3>& a, const std::array<double, 3>& b, double rho) const;

    const LocatedMap& map_;
    const Input& in_;
    const QuadMesh& mesh_;
    const std::vector<Located>& loc_;
    std::vector<double> step_;      ///< per half-edge: the distance between the centroids across it
    std::vector<char> fold_vertex_; ///< per input vertex: a corner of a fold-over
    std::size_t budget_;            ///< triangles a search settles at most
    // The search's scratch: triangles stamped with the current generation were reached.
    std::vector<std::uint32_t> stamp_;
    std::vector<double> best_;
    std::vector<std::int64_t> via_; ///< the half-edge through which a triangle was reached
    std::vector<std::pair<double, std::uint32_t>> heap_;
    std::uint32_t generation_ = 0;
    // The corridors' scratch: per triangle its generation, and the map from its chart to the
    // chart of the corridor's start.
    std::vector<std::array<double, 3>> centre_;
    std::vector<double> radius_; ///< per triangle: the largest distance from its centroid to a corner
    std::vector<std::uint32_t> cstamp_;
    std::vector<Transition> to_start_;
    std::vector<std::uint32_t> queue_;
    std::uint32_t cgeneration_ = 0;
    // The face being judged: its corners in the last anchor's chart, and whether any anchor's
    // paths (or a corner) touched a fold-over or a singular fan.
    Quad g_{};
    bool corner_near_fold_ = false, through_fold_ = false, through_singular_ = false;
    bool corner_in_region_ = false; ///< a corner lies in a fold-over region (judged on the surface only)
    /// A search settled its budget of triangles before reaching every corner: the corners may
    /// still be one cell apart across many small triangles, so that is undecided, not a violation.
    bool out_of_budget_ = false;
};

} // namespace qex::verify_detail::face_cells

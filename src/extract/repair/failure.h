// The repair's failure reports (inside the subsystem only; its door is repair.h): what the last
// attempt at a region found, and per vertex the attempts that failed, for the report of the
// fold-overs the repair leaves (failure.cpp).
#pragma once

#include "extract/repair/certificates.h"
#include "extract/repair/repair.h"
#include "qex/extract.h"

#include <cstdint>
#include <string>
#include <vector>

namespace qex::detail::repair_impl {

/// What the last attempt at a region found, for the report of the fold-overs it leaves.
struct RegionFailure {
    enum class Why : std::uint8_t { TooLarge, AreaNotPositive, NoRoom, RimShort, Inverted, Winding };
    Why why = Why::NoRoom;
    int radius = 0;
    std::size_t free_vertices = 0, triangles = 0;
    int singularities = 0; ///< fixed singular vertices whose whole fan is in the region
    int inverted = 0;      ///< Inverted: triangles left inverted, the first (by input index) of them
    int triangle = -1;
    int vertex = -1; ///< Winding: the input vertex that winds wrongly, its winding and target
    int cone = -1;   ///< RimShort: the singularity (working vertex) whose angle the rim misses; NoRoom: below
    int winds = 0, target = 0;
    bool singular = false;
    /// Whether the failure proves that the region has no re-embedding that keeps every winding
    /// (RimShort; AreaNotPositive and NoRoom where the room certificate's figures prove it).
    bool proof = false;
    /// The region's triangle of smallest input index (working index), where a proof of the
    /// region is placed.
    int first_face = -1;
    /// AreaNotPositive: the region's signed UV area. NoRoom: with `cone` a fixed vertex (working
    /// index, `vertex` its input vertex), the angle its fixed triangles leave the region in
    /// quarter turns, for `corners` region corners; with `cone` -1, the quarter turns the angles
    /// the fixed vertices leave miss of half a turn per triangle.
    double amount = 0.0;
    int corners = 0;
    /// AreaNotPositive, proved: the region's triangles (working indices), so that its area is
    /// named on the map of the scale extracted.
    std::vector<int> faces;

    /// The failure in words, for the report.
    std::string text() const;
};

/// Why an attempt at region r failed (`admitted`: it passed admits_embedding), from its UVs as
/// the attempt left them (the first one: the open-cone retry starts again from the given UVs).
RegionFailure describe_failure(const TriMesh& m, const Region& r, const RegionMarks& marks, bool admitted, int radius);

/// The failed attempts, and per free vertex the last of them at a region that held it.
struct FailureLog {
    explicit FailureLog(std::size_t vertices)
        : failure_of(vertices, -1), proof_of(vertices, -1), room_proof_of(vertices, -1) {}

    std::vector<RegionFailure> failures;
    /// Per free vertex, the last failed attempt at a region that held it (an index into failures).
    std::vector<int> failure_of;
    /// Per free vertex, the last region that held it and was proved to have no re-embedding (a
    /// rim short of its singularity's angle): a larger region's failure does not undo the proof.
    std::vector<int> proof_of;
    /// Per free vertex, the last region that held it and that the room certificate proved to have
    /// none (AreaNotPositive, NoRoom with its figures), kept beside proof_of.
    std::vector<int> room_proof_of;

    /// Records f as the latest failed attempt at r's free vertices.
    void record(const Region& r, const RegionFailure& f);
    /// Why the fold-over of the triangles in `group` was not repaired: the latest attempt at a
    /// region that held one of its vertices, and an earlier proof that none exists.
    std::string reason(const TriMesh& m, const std::vector<int>& group) const;
    /// The proofs (rims short of their singularity's angle, then regions the room certificate
    /// refuses) that hold for the fold-over of the triangles in `group`: the failures' indices,
    /// each once in `seen` (per failure, scratch).
    void proofs(const TriMesh& m, const std::vector<int>& group, std::vector<char>& seen, std::vector<int>& out) const;
};

/// The explanation a proof gives, named on m's map (its grid point and area at m's scale).
Defect proof_explanation(const TriMesh& m, const RepairOutcome::Proof& p);

} // namespace qex::detail::repair_impl

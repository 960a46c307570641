// Stage repair, the subsystem's only door: certified re-embedding of fold-over regions (not in
// the paper). What goes in, what comes out and what is certified: README.md beside this header.
#pragma once

#include "extract/grid_automorphism.h"
#include "qex/extract.h"

#include <array>
#include <functional>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace qex::detail {

struct TriMesh;

/// What stage repair did: the triangles whose UVs it changed (working indices, sorted), and the
/// fold-over regions it could not repair within its budget (explain_unrepaired names them).
struct RepairOutcome {
    std::vector<int> repaired_faces;
    std::int64_t regions_repaired = 0;
    /// A fold-over left as the map gives it: its triangles (working indices), why, and whether a
    /// proof in `proofs` backs it (otherwise the repair failed there: its untangler, its budget).
    struct Unrepaired {
        std::vector<int> triangles;
        std::string why;
        bool proved = false;
    };
    std::vector<Unrepaired> unrepaired;
    /// What proves that a fold-over left stays with the singularities at their grid points, each
    /// once, in the order of `unrepaired`: a rim short of its singularity's angle
    /// (RimShortOfSingularity: `element` the singularity, working vertex), a flipped triangle
    /// between three singularities (FoldPinnedBySingularities: `element` the triangle), or a
    /// region the room certificate proves has no fold-free map (AnglesLeaveNoRoom,
    /// RegionAreaNotPositive: `element` its triangle of smallest input index). Kept as their
    /// sources, so that a refinement reusing this outcome names them on its own map.
    struct Proof {
        DefectKind kind;
        int element = -1;
        int winds = 0, target = 0; ///< RimShortOfSingularity: quarter turns of the rim, and needed
        int radius = 0;            ///< the region (not FoldPinnedBySingularities): its rings and triangles
        std::size_t triangles = 0;
        /// AnglesLeaveNoRoom: the fixed vertex (working index; -1 for the angles' sum), and the
        /// quarter turns it leaves the region for `corners` corners, or the quarter turns the sum
        /// misses among `singularities` singularities inside; RegionAreaNotPositive: the area where
        /// repaired (named from `faces` on the map of the scale extracted).
        int vertex = -1, corners = 0, singularities = 0;
        double amount = 0.0;
        std::vector<int> faces; ///< RegionAreaNotPositive: the region's triangles (working indices)
    };
    std::vector<Proof> proofs;
    /// Whether the map changed after the look before the last ring (LookBeforeLastRing): true
    /// when no look was taken. When false the map is the one the look was shown.
    bool changed_after_look = true;
    /// The half-edges whose transitions a dipole merge changed (kept or undone), each once, with
    /// the transition the sanitized map gave it: with these, a copy of the map's transitions after
    /// the repair tells those before it.
    std::vector<std::pair<int, GridAutomorphism>> transitions_before;
};

/// Whether explanations of this kind are proofs the repair names (RepairOutcome::Proof).
inline bool is_proof(DefectKind k) {
    return k == DefectKind::RimShortOfSingularity || k == DefectKind::FoldPinnedBySingularities ||
           k == DefectKind::AnglesLeaveNoRoom || k == DefectKind::RegionAreaNotPositive;
}

/// The proofs first, then one explanation (FoldOverNotRepaired) per fold-over the repair left,
/// with its UV area and places in m (the map of the scale being extracted).
void explain_unrepaired(const TriMesh& m, const RepairOutcome& outcome, Report& report);

/// Stage repair: re-embeds the regions of flipped and degenerate triangles (UV area <= 0) of the
/// sanitized map. Each region's free vertices (interior, regular, not on a feature) move so
/// that every triangle around them is positively oriented, decided exactly; singular,
/// boundary and feature vertices and everything outside the regions keep their sanitized UVs
/// bit for bit, and the transitions stay as they are, but for co-located dipoles next to a fold,
/// which are merged first (the transitions of a path between them change; named in
/// report.explanations, and undone unless their region is re-embedded). A region that does not
/// untangle grows and is tried again, up to a budget; past it, its UVs are restored and the
/// paper's local handling takes over there (named in report.explanations). Updates
/// MapState::face_sign, and the valences of singularities it corrects or merges. Regions that
/// share no vertex are attempted on up to `threads` threads (0: every core), with the same
/// result for any count.
///
/// `look`, if given, is asked before the last ring radius, when fold-overs are left, with the map
/// as the repair would leave it there (the dipole merges that do not stand undone) and the
/// outcome so far: `enough` stops the repair there (the mesh of that map is as good as the last
/// ring could make it); otherwise, with `near` given, the last ring attempts only the fold-overs
/// within its radius of those vertices (where that mesh lost quads), else all of them.
///
/// `sanitized`, if given, is m's UVs as they are (a copy the caller keeps anyway): the repair
/// compares with it instead of copying them itself (15 MB on a 315K-triangle map).
struct RepairLook {
    bool enough = false;
    std::vector<int> near;
};
using LookBeforeLastRing = std::function<RepairLook(const TriMesh&, const RepairOutcome&)>;
RepairOutcome repair(TriMesh& m, const std::vector<std::array<int, 2>>& feature_edges, bool valences_given, int threads,
                     Report& report, const LookBeforeLastRing& look = {},
                     const std::vector<std::array<double, 2>>* sanitized = nullptr);

} // namespace qex::detail

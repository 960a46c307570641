// Stage repair: certified re-embedding of fold-over regions (not in the paper, whose handling of
// fold-overs is local and assumes a fold covers a small part of a cell).
//
// A region is a connected set of free vertices (interior, regular, off the features) near
// flipped or degenerate triangles; its triangles are those around its free vertices, and its
// other vertices (singular, boundary, feature, or outside) stay fixed. The free vertices move to
// minimise an energy that penalises inverted triangles through a regularised determinant, the
// regularisation shrinking as the triangles untangle (the foldover-free energy of Garanzha et
// al. 2021, minimised here with L-BFGS over the region's free vertices). Each vertex lives in the
// chart of one of its corners and is written to the others through the exact transitions after
// truncation (as sanitize does), so transitions and singularities are untouched. A region is
// attempted only when its fixed vertices leave room for an embedding (their angles,
// Gauss-Bonnet), and counts as repaired only when every one of its triangles is positively
// oriented by the exact predicate and every vertex winds as it must (positive triangles can
// still wind twice round a vertex while a singularity beside it is a turn short); otherwise its
// UVs are restored bit for bit, it grows, and it is tried again, up to a budget. What the
// untangler leaves inverted is moved vertex by vertex into the kernel of its link where it has
// one. Where the untangler wound a region wrongly round its singularities, the region is tried
// once more from its given UVs, with the fans of the singularities that wind short there opened
// (laid out over their angles) and kept open by a barrier.
//
// Before the last ring, the caller may look at the map as it stands and stop the repair there, or
// send the last ring only where that map's mesh lost quads (LookBeforeLastRing, RepairLook).
//
// The one change to transitions and singularities: before the regions are grown, co-located
// dipoles (two singularities of opposite index on one grid point, which no fold-free map allows)
// are merged into regular vertices, each merge named in the report and undone unless the repair
// re-embeds it.
//
// This file is the stage's driver; the subsystem's files are listed in README.md beside it.
#include "extract/repair/repair.h"

#include "extract/repair/dipoles.h"
#include "extract/repair/failure.h"
#include "extract/repair/open_cones.h"
#include "extract/repair/regions.h"
#include "extract/repair/solver.h"
#include "extract/parallel.h"
#include "extract/union_find.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <functional>
#include <iterator>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace qex::detail {
namespace repair_impl {
namespace {

// ============================================================================ budget

/// Ring radii around the fold-overs, one attempt each.
constexpr int kRingRadii[] = {1, 2, 4, 8};
/// Larger regions are not attempted (their repair would cost more than the extraction).
constexpr std::size_t kMaxRegionVertices = std::size_t{1} << 17;
/// The regions of a ring radius are attempted on several threads only past this many triangles
/// in all (fewer cost less than starting a thread).
constexpr std::size_t kParallelMinTriangles = 512;
/// A region's retry runs beside its first try (RetryBeside) from this many triangles: below, the
/// first try takes less than the copy of the map and the thread cost.
constexpr std::size_t kRetryBesideMinTriangles = 256;

// ============================================================================ the attempts

/// What one attempt at a region works in (one per thread): the untangler's scratch and the marks
/// the certificates read.
struct Scratch {
    explicit Scratch(const TriMesh& m) : work(m) { marks.size_for(m); }
    Workspace work;
    RegionMarks marks; // its members by name: an aggregate list would silently fill `cone`
};

/// What the attempts at regions share, across regions and rings: the breadth-first scratch, the
/// attempts' scratch (one per thread, made when needed), and per vertex what happened so far.
struct Attempts {
    Attempts(const TriMesh& m, int threads)
        : threads(threads),
          distance(static_cast<std::size_t>(m.num_vertices), -1),
          label(distance.size(), -1),
          reembedded(static_cast<std::size_t>(m.num_vertices), 0),
          log(static_cast<std::size_t>(m.num_vertices)) {
        scratch.emplace_back(m);
    }

    int threads;
    std::vector<int> distance, label;
    std::vector<Scratch> scratch;
    /// The retry beside the first try, for regions attempted one at a time (made when needed).
    std::unique_ptr<RetryBeside> beside;
    /// Per vertex: re-embedded by a certified region (a dipole merge stands only if its path was).
    std::vector<char> reembedded;
    FailureLog log;
};

/// The regions of the free vertices within `radius` rings of the seed triangles, in an order
/// that does not depend on the input's; `distance` and `label` are per-vertex scratch. An admitted
/// attempt makes its fans: attempts move only their own free vertices, in no other region's triangle.
std::vector<Region> regions_within(const TriMesh& m, const std::vector<int>& seeds_faces, int radius,
                                   const std::vector<char>& pinned, std::vector<int>& distance,
                                   std::vector<int>& label) {
    std::vector<int> seeds;
    for (const int f : seeds_faces)
        for (const int v : m.tri[f]) seeds.push_back(v);
    std::vector<int> free;
    for (const int v : ring_neighbourhood(m, seeds, radius, distance))
        if (!pinned[v]) free.push_back(v);
    std::sort(free.begin(), free.end());
    // Regions share fixed vertices, whose windings the certificate reads: they are taken in
    // an order that does not depend on the input's (their smallest vertex key first).
    std::vector<Region> regions = find_regions(m, free, label);
    std::sort(regions.begin(), regions.end(), [&](const Region& a, const Region& b) {
        return vertex_key(m, a.fans[0].vertex) < vertex_key(m, b.fans[0].vertex);
    });
    return regions;
}

/// One attempt at region r: admitted by the room certificate, untangled, and certified by the
/// winding certificate (once more with cone fans opened where that is what failed); then
/// relaxed. Nothing when repaired (its free vertices marked in `reembedded`); otherwise its UVs
/// are restored and its failure returned. It reads and writes only r's triangles and the fans of
/// their vertices. With `beside` (regions attempted one at a time, threads to spare), a large
/// region's retry runs beside its first try: the same outcome, sooner.
std::optional<RegionFailure> attempt_region(TriMesh& m, Region& r, int radius, bool valences_given, Scratch& a,
                                            std::vector<char>& reembedded,
                                            std::unique_ptr<RetryBeside>* beside = nullptr) {
    if (r.fans.size() > kMaxRegionVertices) {
        RegionFailure f;
        f.why = RegionFailure::Why::TooLarge;
        f.radius = radius;
        f.free_vertices = r.fans.size();
        f.triangles = r.faces.size();
        return f;
    }
    RegionMarks& marks = a.marks;
    marks.mark(m, r);
    bool repaired = false;
    const bool admitted = admits_embedding(m, r, valences_given, marks);
    RegionFailure failure; // what the first attempt left, if it failed (the retry starts over)
    std::vector<Point2> before; // r's UVs before the attempt (none moved where it is refused)
    if (admitted) {
        make_fans(m, r);
        before = region_uvs(m, r);
        const int patience =
            radius == kRingRadii[std::size(kRingRadii) - 1] ? kPatienceAtLastRing : kPatienceBeforeLastRing;
        RetryBeside* ahead = nullptr;
        if (beside && r.faces.size() >= kRetryBesideMinTriangles) {
            if (!*beside) *beside = std::make_unique<RetryBeside>(m);
            if ((*beside)->start(m, r, marks, before, patience)) ahead = beside->get();
        }
        struct StopAtExit { // the retry reads this attempt's locals: it ends before they do
            RetryBeside* b;
            ~StopAtExit() {
                if (b) b->stop();
            }
        } stop_at_exit{ahead};
        const bool untangled = untangle_region(m, r, a.work, patience);
        repaired = untangled && windings_kept(m, r, marks);
        if (!repaired) failure = describe_failure(m, r, marks, true, radius);
        // Once more with cone fans opened, where that is what failed: the untangler wound
        // the region wrongly round its singularities, or Gauss-Bonnet corrected some.
        if (!repaired && (untangled || marks.cone >= 0))
            repaired = ahead ? ahead->take(m, r) : untangle_with_open_cones(m, r, marks, before, a.work, patience);
    } else {
        failure = describe_failure(m, r, marks, false, radius);
    }
    if (repaired) {
        polish_region(m, r, a.work, marks);
        for (const FreeFan& fan : r.fans) reembedded[fan.vertex] = 1;
    }
    // A corrected singularity winds by the angle Gauss-Bonnet gave it: that is its valence.
    if (repaired && marks.cone >= 0)
        m.map.valence[marks.cone] = m.map.winding_valence[marks.cone] =
            static_cast<int>(std::lround(marks.cone_angle / (0.5 * M_PI)));
    marks.clear(r);
    if (repaired) return std::nullopt;
    if (admitted) restore_region_uvs(m, r, before);
    return failure;
}

/// The regions in groups that share no vertex with each other (union-find over the vertices of
/// their triangles): an attempt reads only its region's triangles and the fans of their
/// vertices, so groups are independent, and within one the regions are taken in their order.
/// Largest groups first (by triangles), to balance the threads; `owner` is per-vertex scratch
/// (all -1 before and after).
std::vector<std::vector<std::size_t>> independent_groups(const TriMesh& m, const std::vector<Region>& regions,
                                                         std::vector<int>& owner) {
    UnionFind sets(regions.size());
    for (std::size_t i = 0; i < regions.size(); ++i)
        for (const int f : regions[i].faces)
            for (const int v : m.tri[f]) {
                int& o = owner[static_cast<std::size_t>(v)];
                if (o < 0) o = static_cast<int>(i);
                const int x = sets.find(o), y = sets.find(static_cast<int>(i));
                if (x != y) sets.attach(std::max(x, y), std::min(x, y));
            }
    for (const Region& r : regions)
        for (const int f : r.faces)
            for (const int v : m.tri[f]) owner[static_cast<std::size_t>(v)] = -1;
    std::vector<std::vector<std::size_t>> groups(regions.size());
    std::vector<std::size_t> size(regions.size(), 0);
    for (std::size_t i = 0; i < regions.size(); ++i) {
        const auto g = static_cast<std::size_t>(sets.find(static_cast<int>(i)));
        groups[g].push_back(i);
        size[g] += regions[i].faces.size();
    }
    std::vector<std::size_t> order;
    for (std::size_t g = 0; g < groups.size(); ++g)
        if (!groups[g].empty()) order.push_back(g);
    std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) { return size[x] > size[y]; });
    std::vector<std::vector<std::size_t>> out;
    for (const std::size_t g : order) out.push_back(std::move(groups[g]));
    return out;
}

/// The attempts at every region of one ring radius: independent groups on the threads, each
/// group's regions in their order, and the failures recorded in the regions' order, so the
/// outcome is the serial one for any thread count. How many regions were repaired.
std::size_t attempt_regions(TriMesh& m, std::vector<Region>& regions, int radius, bool valences_given,
                            Attempts& a) {
    std::vector<std::optional<RegionFailure>> failed(regions.size());
    std::size_t triangles = 0;
    for (const Region& r : regions) triangles += r.faces.size();
    // The groups only when threads could share them.
    const std::vector<std::vector<std::size_t>> groups =
        a.threads > 1 && regions.size() > 1 && triangles >= kParallelMinTriangles
            ? independent_groups(m, regions, a.label)
            : std::vector<std::vector<std::size_t>>{};
    const int threads = std::min(a.threads, static_cast<int>(groups.size()));
    if (threads > 1) {
        // Plain threads, not OpenMP: a few per repair, and none left spinning when the library
        // runs inside its users' parallel jobs. Each takes the next group (largest first).
        while (a.scratch.size() < static_cast<std::size_t>(threads)) a.scratch.emplace_back(m);
        for (Scratch& s : a.scratch) s.work.beside = false; // the threads are the groups'
        std::atomic<std::size_t> next{0};
        std::vector<std::exception_ptr> thrown(static_cast<std::size_t>(threads));
        const auto work = [&](std::size_t t) {
            try {
                for (std::size_t g = next++; g < groups.size(); g = next++)
                    for (const std::size_t i : groups[g])
                        failed[i] = attempt_region(m, regions[i], radius, valences_given, a.scratch[t], a.reembedded);
            } catch (...) {
                thrown[t] = std::current_exception();
                next = groups.size();
            }
        };
        run_workers(static_cast<std::size_t>(threads), work, thrown);
    } else {
        a.scratch[0].work.beside = a.threads > 1;
        for (std::size_t i = 0; i < regions.size(); ++i)
            failed[i] = attempt_region(m, regions[i], radius, valences_given, a.scratch[0], a.reembedded,
                                       a.threads > 1 ? &a.beside : nullptr);
    }
    std::size_t repaired = 0;
    for (std::size_t i = 0; i < regions.size(); ++i)
        if (failed[i])
            a.log.record(regions[i], *failed[i]);
        else
            ++repaired;
    return repaired;
}

/// Keeps the seed triangles with a vertex within `radius` rings of the `near` vertices: those
/// whose regions at that radius reach them. `distance` is per-vertex scratch.
void keep_near(const TriMesh& m, const std::vector<int>& near, int radius, std::vector<int>& seeds_faces,
               std::vector<int>& distance) {
    std::vector<char> reached(static_cast<std::size_t>(m.num_vertices), 0);
    for (const int v : ring_neighbourhood(m, near, radius, distance)) reached[static_cast<std::size_t>(v)] = 1;
    const auto far = [&](int f) {
        for (const int v : m.tri[f])
            if (reached[static_cast<std::size_t>(v)]) return false;
        return true;
    };
    seeds_faces.erase(std::remove_if(seeds_faces.begin(), seeds_faces.end(), far), seeds_faces.end());
}

/// Attempts the regions round the fold-overs (`seeds_faces`) and the paths of the dipole merges
/// that do not stand yet, ring radius by ring radius; leaves in `seeds_faces` and `stuck` the
/// flipped or degenerate triangles that remain. Returns whether a region was repaired after the
/// look (true when none was taken): otherwise the map is as the look saw it.
bool grow_regions(TriMesh& m, const std::vector<char>& pinned, bool valences_given,
                  const std::vector<DipoleMerge>& merges, std::vector<int>& seeds_faces, std::vector<int>& stuck,
                  Attempts& a, const std::function<RepairLook()>& look) {
    bool looked = false;
    for (const int radius : kRingRadii) {
        if (seeds_faces.empty()) break;
        RepairLook seen;
        if (radius == kRingRadii[std::size(kRingRadii) - 1] && look) {
            looked = true;
            if ((seen = look()).enough) return false;
        }
        std::vector<int> seeds = seeds_faces; // the flipped and degenerate triangles, and then:
        for (const DipoleMerge& d : merges)
            if (!merge_reembedded(m, d, a.reembedded))
                for (const int e : d.path) seeds.push_back(TriMesh::face(e));
        if (!seen.near.empty()) keep_near(m, seen.near, radius, seeds, a.distance);
        if (seeds.empty()) break;
        std::vector<Region> regions = regions_within(m, seeds, radius, pinned, a.distance, a.label);
        const std::size_t repaired = attempt_regions(m, regions, radius, valences_given, a);
        // An attempt leaves its region's triangles positive or restores them bit for bit, so the
        // triangles left are among those before it: bad_triangles() would find these (a scan of
        // every triangle took 2 ms a ring on a 315K-triangle map).
        const auto now_positive = [&](int f) { return positive(m, f); };
        seeds_faces.erase(std::remove_if(seeds_faces.begin(), seeds_faces.end(), now_positive), seeds_faces.end());
        stuck.erase(std::remove_if(stuck.begin(), stuck.end(), now_positive), stuck.end());
        if (looked) return repaired > 0;
    }
    return !looked;
}

/// Whether failure f is named as a proof (outcome_of): a rim short of its singularity's angle,
/// or a room certificate's refusal with figures that prove it.
bool names_proof(const TriMesh& m, const RegionFailure& f) {
    return (f.why == RegionFailure::Why::RimShort && f.winds < f.target && m.fan_start[f.cone] >= 0) ||
           ((f.why == RegionFailure::Why::NoRoom || f.why == RegionFailure::Why::AreaNotPositive) && f.first_face >= 0);
}

/// Whether a proof named for some fold-over holds for the one of `group` (a vertex of it was in a
/// region so proved, as FailureLog::proofs finds them, whichever fold-over names it first).
bool backed_by_proof(const TriMesh& m, const FailureLog& log, const std::vector<int>& group) {
    for (const std::vector<int>* of : {&log.proof_of, &log.room_proof_of})
        for (const int f : group)
            for (const int v : m.tri[f])
                if (const int p = (*of)[static_cast<std::size_t>(v)];
                    p >= 0 && names_proof(m, log.failures[static_cast<std::size_t>(p)]))
                    return true;
    return false;
}

/// The proof a failure names (names_proof), each field by name.
RepairOutcome::Proof proof_of(const RegionFailure& f) {
    RepairOutcome::Proof p{};
    p.kind = DefectKind::RegionAreaNotPositive;
    p.radius = f.radius, p.triangles = f.triangles;
    if (f.why == RegionFailure::Why::RimShort) {
        p.kind = DefectKind::RimShortOfSingularity;
        p.element = f.cone, p.winds = f.winds, p.target = f.target;
        return p;
    }
    p.element = f.first_face, p.singularities = f.singularities, p.amount = f.amount;
    if (f.why == RegionFailure::Why::NoRoom) {
        p.kind = DefectKind::AnglesLeaveNoRoom;
        p.vertex = f.cone, p.corners = f.corners;
    } else {
        p.faces = f.faces;
    }
    return p;
}

/// A flipped triangle whose corners are all singularities: none of them moves.
RepairOutcome::Proof pinned_proof(int face) {
    RepairOutcome::Proof p{};
    p.kind = DefectKind::FoldPinnedBySingularities;
    p.element = face;
    return p;
}

/// The stage's outcome: the certificate's region (every triangle whose UVs differ from the
/// sanitized map) and how many groups it forms, and the fold-overs left, each with why; updates
/// MapState::face_sign.
RepairOutcome outcome_of(TriMesh& m, const std::vector<Point2>& sanitized, const std::vector<int>& stuck,
                         const std::vector<int>& seeds_faces, const FailureLog& log) {
    RepairOutcome out;
    // The certificate's region: every triangle whose UVs differ from the sanitized map.
    for (int f = 0; f < m.num_faces(); ++f) {
        bool changed = false;
        for (int k = 0; k < 3; ++k) changed = changed || m.uv[3 * f + k] != sanitized[3 * f + k];
        if (changed) out.repaired_faces.push_back(f);
        m.map.face_sign[f] = static_cast<signed char>(sign(orient2d(m.uv[3 * f], m.uv[3 * f + 1], m.uv[3 * f + 2])));
    }
    out.regions_repaired = static_cast<std::int64_t>(triangle_groups(m, out.repaired_faces).size());
    for (auto& group : triangle_groups(m, stuck)) {
        // A flipped triangle between three singularities: none of its corners moves.
        const std::size_t before = out.proofs.size();
        for (const int f : group)
            if (m.map.face_sign[f] < 0 && m.map.singular[m.tri[f][0]] && m.map.singular[m.tri[f][1]] &&
                m.map.singular[m.tri[f][2]])
                out.proofs.push_back(pinned_proof(f));
        out.unrepaired.push_back({std::move(group),
                                  "all its corners are singular, boundary or feature vertices, which stay fixed",
                                  out.proofs.size() > before});
    }
    std::vector<char> seen;
    for (const auto& group : triangle_groups(m, seeds_faces)) {
        std::vector<int> proved;
        log.proofs(m, group, seen, proved);
        // A rim that turns about the grid point by fewer quarter turns than the singularity needs:
        // in a fold-free map of the region it turns by the angle and a full turn more for each
        // other preimage of the point inside (a rim turning more proves nothing).
        for (const int p : proved) {
            const RegionFailure& f = log.failures[static_cast<std::size_t>(p)];
            if (!names_proof(m, f)) continue;
            out.proofs.push_back(proof_of(f));
        }
        out.unrepaired.push_back({group, log.reason(m, group), backed_by_proof(m, log, group)});
    }
    return out;
}

} // namespace
} // namespace repair_impl

RepairOutcome repair(TriMesh& m, const std::vector<std::array<int, 2>>& feature_edges, bool valences_given, int threads,
                     Report& report, const LookBeforeLastRing& look, const std::vector<Point2>* given) {
    using namespace repair_impl;
    std::vector<int> seeds_faces, stuck;
    std::vector<char> pinned = pinned_vertices(m, feature_edges);
    bad_triangles(m, pinned, seeds_faces, stuck);
    if (seeds_faces.empty() && stuck.empty()) return RepairOutcome{};
    Attempts attempts(m, thread_count(threads));
    // Co-located dipoles next to the fold-overs are merged first (their vertices become free),
    // in an order that does not depend on the input's; not against the user's valences.
    std::vector<DipoleMerge> merges;
    if (!valences_given) merges = merge_colocated_dipoles(m, pinned, attempts.distance, attempts.label);
    if (!merges.empty()) { // merged vertices are free now (the merges change no UV: no sign)
        pinned = pinned_vertices(m, feature_edges);
        split_again(m, pinned, seeds_faces, stuck);
    }
    // The merges change transitions, never UVs: m's UVs are still the sanitized ones.
    std::vector<Point2> own;
    if (!given) own = m.uv;
    const std::vector<Point2>& sanitized = given ? *given : own;
    std::function<RepairLook()> before_last;
    if (look)
        before_last = [&] {
            // The map as the repair would leave it here (the merges that do not stand undone), and
            // as it was if the repair goes on.
            const MergesState merged = merges_state(m, merges);
            Report scratch;
            settle_merges(m, merges, attempts.reembedded, scratch);
            RepairLook seen = look(m, outcome_of(m, sanitized, stuck, seeds_faces, attempts.log));
            if (!seen.enough) restore_merges(m, merges, merged);
            return seen;
        };
    const bool changed = grow_regions(m, pinned, valences_given, merges, seeds_faces, stuck, attempts, before_last);
    settle_merges(m, merges, attempts.reembedded, report);
    RepairOutcome out = outcome_of(m, sanitized, stuck, seeds_faces, attempts.log);
    out.changed_after_look = changed;
    out.transitions_before = transitions_before_merges(m, merges);
    return out;
}

} // namespace qex::detail

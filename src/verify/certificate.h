// The certificate's check (certificate.cpp, certificate_charts.cpp): a room of the checker
// behind checker.h. certificate.cpp checks the surface, the moved UVs, the orientations and the
// windings, and judges the mesh on the certificate; certificate_charts.cpp compares its charts
// and singularities with the given map's.
#pragma once

#include "checker.h"

#include <cstdint>
#include <string>
#include <vector>

namespace qex::verify_detail {

using UVs = std::vector<std::array<double, 2>>;

/// Appends a CertificateMismatch naming input triangle `t` (-1: none) and its other places.
inline void mismatch(std::vector<Violation>& out, const std::string& message, std::int64_t t,
                     std::vector<Place> places = {}) {
    if (out.size() >= kMaxListed) return;
    if (t >= 0) places.insert(places.begin(), Place{PlaceKind::InputTriangle, {t}});
    out.push_back({ViolationKind::CertificateMismatch, "certificate: " + message, t, std::move(places)});
}

/// The certificate's charts against the given map's (`given`: its UVs times the grid scale;
/// `U`: the certificate's; `listed` and `collapsed` per triangle, certificate.cpp). A repair
/// may express a listed triangle's UVs in another chart, and may cancel singularities of the
/// given map against each other inside its listed triangles (qex's repair merges a dipole a
/// fold-over holds into regular vertices), and nothing else:
/// - across every edge with an unlisted side whose transition the given map determines
///   (input_edges with `tol`), the certificate's is the same grid automorphism, exactly, up to
///   the chart of its listed side (if any; found breadth first from the unlisted triangles);
/// - every vertex whose fan turns in both maps turns as in the given map, except a singularity
///   of the given map the certificate makes regular at a listed triangle: in a region of listed
///   triangles (sharing vertices) on a fold of the given map (`folded`, per vertex: its fan
///   holds a flipped or degenerate triangle), where the located mode's footprints do not match
///   singularities one by one either, any may go; in a region without fold, those it makes
///   regular must cancel, their turns summing to whole turns (a dipole);
/// - a region that cancels none is charted as given up to a chart per triangle inside too:
///   across each of its edges the certificate's transition is g_o G g_t^-1 for the given G.
/// Returns per input vertex whether it is a singularity of the given map the certificate cancels.
/// `given_sums`: per input vertex its angle sum in the given map (angle_sums), which gives the
/// turns of a fan whose transitions the given map does not determine (an edge too short to read).
std::vector<char> check_charts(const Input& given, const UVs& U, const std::vector<char>& listed,
                               const std::vector<char>& collapsed, const std::vector<char>& folded,
                               const std::vector<double>& given_sums, double tol, std::vector<Violation>& out);

/// Per input vertex the sum of its corners' signed angles (signed_angle) in the UVs `U`.
std::vector<double> angle_sums(const Input& in, const UVs& U);

} // namespace qex::verify_detail

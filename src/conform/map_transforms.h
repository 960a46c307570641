// Transforms of an integer-grid map that keep the quad mesh it induces, for metamorphic tests on
// any map (the real OBJ maps included): scaling the UVs by an integer, integer translation,
// per-triangle re-charting by grid automorphisms, reordering, 1-to-4 subdivision.
//
// Unlike the perturbations of map_generators.h these carry `valences` and `feature_edges` along,
// draw their random numbers from std::mt19937_64 alone (the same result on every platform for a
// seed), and report where double arithmetic rounded a UV.
#pragma once

#include "qex/mesh.h"

#include <cstdint>
#include <string>

namespace qex::gen::transforms {

/// Multiplies every UV by `k` >= 1: the map of k^2 times the quads. Returns the number of UV
/// coordinates whose product was rounded (0: the scaled map is exact). Powers of two are exact
/// for every finite UV short of overflow.
std::int64_t scale_uvs(Input& in, std::int64_t k);

/// Adds the integer vector (tx, ty) to every UV. Returns the number of UV coordinates whose sum
/// was rounded (a noisy UV loses low bits where the sum needs a larger exponent).
std::int64_t translate_uvs(Input& in, std::int64_t tx, std::int64_t ty);

/// Re-charts every triangle by its own random grid automorphism x -> R90^r x + t, r in 0..3,
/// t in [-max_translation, max_translation]^2 integer: every edge becomes a cut. Returns the
/// number of UV coordinates whose translation was rounded.
std::int64_t rechart(Input& in, std::uint64_t seed, std::int64_t max_translation = 16);

/// Renumbers the vertices, reorders the triangles and rotates the corners of each triangle
/// cyclically, all at random; valences follow their vertices, feature edges their endpoints
/// (and the feature-edge list is reordered too). Exact: the map itself is unchanged.
void shuffle(Input& in, std::uint64_t seed);

/// 1-to-4 midpoint subdivision: each edge gets its midpoint (a shared vertex, position (p+q)/2),
/// and each triangle's corner UVs the midpoints (a+b)/2 of its own corners' UVs, so the map is
/// the same up to the rounding of (a+b)/2. New vertices have valence 4; a feature edge becomes
/// its two halves.
Input subdivide(const Input& in);

/// Applies the transforms named in `ops` in order: "scale K", "translate TX TY", "rechart SEED
/// [T]", "shuffle SEED", "subdivide". Returns "" or what is wrong with `ops` (then `in` is
/// partly transformed). `rounded` (if given) accumulates the transforms' rounded coordinates.
std::string apply(Input& in, const std::string& ops, std::int64_t* rounded = nullptr);

} // namespace qex::gen::transforms

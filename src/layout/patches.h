// The patches the separatrices cut a quad mesh into (patches.cpp): faces joined across every edge
// that is neither a separatrix nor a cut, numbered canonically; each patch's shape (a rectangle
// with its corners and size, a torus, an annulus still to cut, or what else it is); the patches'
// adjacency. Private to src/layout/.
#pragma once

#include "quad_topology.h"

#include <string>
#include <vector>

namespace qex::layout {

struct PatchShape {
    Patch patch;
    bool ok = false; ///< a rectangle or a torus
    /// An annulus (two boundary loops without corners), or a rectangle glued to itself along a
    /// separatrix: to be cut along `cuts`, the outgoing half-edges the cuts start along. An
    /// annulus is cut twice, from its first boundary vertex and from the vertex half way round
    /// that loop, so that each piece is a rectangle embedded in the mesh.
    bool needs_cut = false;
    std::vector<int> cuts;
    std::string problem; ///< why it is neither
};

/// Numbers the patches (canonically: by their first face in the vertex order) into `face_patch`;
/// `is_layout` marks the half-edges on separatrices and cuts. Returns each patch's faces.
std::vector<std::vector<int>> number_patches(const QuadTopology& topo, const std::vector<char>& is_layout,
                                             std::vector<int>& face_patch);

/// The shape of the patch with faces `faces` (increasing); `stamp` is scratch (per vertex, -1 initially).
PatchShape analyse_patch(const QuadTopology& topo, const std::vector<char>& is_layout,
                         const std::vector<int>& face_patch, const std::vector<int>& faces, std::vector<int>& stamp);

/// The pairs of patches that share mesh edges, sorted.
std::vector<PatchAdjacency> patch_adjacency(const QuadTopology& topo, const std::vector<int>& face_patch);

} // namespace qex::layout

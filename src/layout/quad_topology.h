// The half-edges of a quad mesh for the layout's tracing: half-edge 4f+k runs from corner k of
// face f to corner k+1; each vertex's fan of outgoing half-edges in turning order; the cut edges
// (boundary and features); the canonical vertex order. Private to src/layout/ (the independent
// check, check_layout.cpp, does not use it).
#pragma once

#include "qex/layout.h"

#include <string>
#include <vector>

namespace qex::layout {

struct QuadTopology {
    const QuadMesh* mesh = nullptr;
    int vertices = 0, faces = 0;
    std::vector<int> twin;      ///< per half-edge; -1 on the boundary
    std::vector<char> cut;      ///< per half-edge: a boundary or feature edge
    std::vector<int> fan_begin; ///< per vertex + 1: its range in `fan`
    std::vector<int> fan;       ///< outgoing half-edges, each the rot() of the one before
    std::vector<char> boundary; ///< per vertex: on the boundary
    std::vector<char> feature;  ///< per vertex: on a feature edge
    std::vector<int> rank;      ///< per vertex: its place in the canonical order (position, index)

    int from(int h) const { return mesh->faces[h / 4][h % 4]; }
    int to(int h) const { return mesh->faces[h / 4][(h + 1) % 4]; }
    static int next(int h) { return h / 4 * 4 + (h + 1) % 4; }
    static int prev(int h) { return h / 4 * 4 + (h + 3) % 4; }
    /// The next outgoing half-edge round from(o), or -1 at the boundary.
    int rot(int o) const { return twin[prev(o)]; }
    /// The outgoing half-edge straight on from the one arriving along h, at a regular vertex.
    int straight(int h) const { return rot(rot(twin[h])); }
    int valence(int v) const { return fan_begin[v + 1] - fan_begin[v]; }
    bool on_cut(int v) const { return boundary[v] || feature[v]; }
};

/// What a vertex starts: whether it is special, and the outgoing half-edges to trace from it.
struct VertexSpokes {
    bool special = false;
    std::vector<int> traces;
};

/// Builds the topology; returns "" or why the mesh has no layout (not all quads, an index out of
/// range, a non-manifold or inconsistently oriented edge or vertex, a bad feature edge).
std::string build_topology(const QuadMesh& mesh, const LayoutOptions& options, QuadTopology& topo);

/// The vertex's sectors (its faces between cut edges): special if one is not 2 faces (or, with no
/// cut, if it has other than 4); the interior edges of those sectors are traced.
VertexSpokes spokes(const QuadTopology& topo, int v);

} // namespace qex::layout

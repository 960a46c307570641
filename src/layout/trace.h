// The motorcycle graph of a quad mesh's separatrices (trace.cpp): every separatrix is traced at
// once, one mesh edge per step in canonical order, and stops at a special vertex, the boundary or
// a feature, or where a separatrix passed first (a T-junction); two that meet head-on along one
// grid line are joined. Private to src/layout/.
#pragma once

#include "quad_topology.h"

#include <vector>

namespace qex::layout {

struct Trace {
    std::vector<int> path; ///< vertices so far
    int next = -1;         ///< the outgoing half-edge it moves along next
    SeparatrixStart start = SeparatrixStart::IrregularVertex;
    SeparatrixEnd end = SeparatrixEnd::SpecialVertex;
    bool active = true;
    bool dropped = false; ///< its first edge was another's (traced from the other end), or it was joined into one
};

struct Motorcycles {
    std::vector<Trace> traces;
    std::vector<int> owner;      ///< per vertex: the trace that passed through it first, or -1
    std::vector<int> owner_prev; ///< per vertex: the vertex that trace came from
    std::vector<char> used;      ///< per half-edge: on a trace
};

/// Adds a trace from `from` along the outgoing half-edge `h`.
void add_trace(Motorcycles& m, int from, int h, SeparatrixStart start);

/// Runs every active trace to its end, in steps of one edge, the traces in their order.
void run(const QuadTopology& topo, Motorcycles& m);

} // namespace qex::layout

// The motorcycle graph (trace.h). Each step moves every active trace by one edge, in the order of
// the traces (canonical: by their start, then their first edge, in the canonical vertex order), so
// the result depends on nothing else. A trace claims each regular vertex it enters first; one that
// enters a claimed vertex stops there (a T-junction), unless the claim is the head of a trace
// coming the other way along the same grid line: then the two are joined (met head-on). Every
// vertex is claimed once, so all traces end within #vertices steps: a grid line that would wind
// round the surface for ever stops where it meets itself.
#include "trace.h"

#include <algorithm>

namespace qex::layout {
namespace {

SeparatrixEnd end_at(const QuadTopology& t, const std::vector<char>& special, int x) {
    if (special[x]) return SeparatrixEnd::SpecialVertex;
    return t.boundary[x] ? SeparatrixEnd::Boundary : SeparatrixEnd::Feature;
}

/// Moves trace i by one edge; `special` marks the special vertices.
void advance(const QuadTopology& t, const std::vector<char>& special, Motorcycles& m, int i) {
    Trace& me = m.traces[i];
    const int h = me.next, x = t.to(h), cur = t.from(h);
    if (m.used[h]) { // its first edge is a separatrix traced from the other end already
        me.active = false;
        me.dropped = true;
        return;
    }
    m.used[h] = 1;
    if (t.twin[h] >= 0) m.used[t.twin[h]] = 1;
    if (t.on_cut(x) || special[x]) {
        me.path.push_back(x);
        me.end = end_at(t, special, x);
        me.active = false;
        return;
    }
    const int on = t.straight(h);
    if (m.owner[x] < 0) {
        m.owner[x] = i;
        m.owner_prev[x] = cur;
        me.path.push_back(x);
        me.next = on;
        return;
    }
    Trace& other = m.traces[m.owner[x]];
    me.active = false;
    if (other.active && other.path.back() == x && m.owner_prev[x] == t.to(on)) {
        me.path.insert(me.path.end(), other.path.rbegin(), other.path.rend()); // joined: one grid line
        me.end = SeparatrixEnd::HeadOn;
        other.active = false;
        other.dropped = true;
        return;
    }
    me.path.push_back(x);
    me.end = SeparatrixEnd::Separatrix;
}

} // namespace

void add_trace(Motorcycles& m, int from, int h, SeparatrixStart start) {
    Trace t;
    t.path.push_back(from);
    t.next = h;
    t.start = start;
    m.traces.push_back(std::move(t));
}

void run(const QuadTopology& t, Motorcycles& m) {
    std::vector<char> special(t.vertices, 0);
    for (int v = 0; v < t.vertices; ++v) special[v] = t.on_cut(v) || t.valence(v) != 4 ? spokes(t, v).special : 0;
    if (m.owner.empty()) {
        m.owner.assign(t.vertices, -1);
        m.owner_prev.assign(t.vertices, -1);
        m.used.assign(4 * static_cast<std::size_t>(t.faces), 0);
    }
    std::vector<int> active;
    for (int i = 0; i < static_cast<int>(m.traces.size()); ++i)
        if (m.traces[i].active) active.push_back(i);
    while (!active.empty()) {
        for (const int i : active)
            if (m.traces[i].active) advance(t, special, m, i);
        active.erase(std::remove_if(active.begin(), active.end(), [&](int i) { return !m.traces[i].active; }),
                     active.end());
    }
}

} // namespace qex::layout

// Q-port tracing (Algorithm 5): each port's iso-line is followed across triangles, transitions and
// orientation flips until it reaches the next integer grid point, where the opposite port is
// found. All decisions are exact orientation tests on the sanitized map.
#include "pipeline.h"

#include <algorithm>
#include <array>
#include <string>
#include <utility>
#include <vector>

namespace qex::detail {
namespace {

/// How many ends of half-edge h lie on the closed segment [a, b].
int vertices_on_segment(const TriMesh& m, int h, const Point2& a, const Point2& b) {
    return static_cast<int>(on_segment(m.uv[h], a, b)) + static_cast<int>(on_segment(m.uv[TriMesh::next(h)], a, b));
}

/// The edge of face f (other than `entry`) through which segment (a, b] leaves it (PICKNEXTEDGE).
/// Of two candidates the paper takes the one incident to fewer vertices on the segment; an edge
/// the segment runs along ranks last, so a trace along a boundary edge is not mistaken for one
/// leaving the surface there. Ties go to the edge with the smaller 3D end points, not to the
/// input's corner order.
int pick_next_edge(const TriMesh& m, int f, int entry, const Point2& a, const Point2& b) {
    int best = -1, best_rank = 100;
    auto edge_key = [&](int h) {
        const auto &p = m.pos(h), &q = m.pos(TriMesh::next(h));
        return p < q ? std::array<std::array<double, 3>, 2>{p, q} : std::array<std::array<double, 3>, 2>{q, p};
    };
    for (int k = 0; k < 3; ++k) {
        const int h = 3 * f + k;
        if (h == entry || !segment_hits_half_open(m.uv[h], m.uv[TriMesh::next(h)], a, b)) continue;
        const int on = vertices_on_segment(m, h, a, b);
        const bool along = orient2d(a, b, m.uv[h]) == Orientation::Collinear &&
                           orient2d(a, b, m.uv[TriMesh::next(h)]) == Orientation::Collinear;
        const int rank = on + (along ? 10 : 0);
        if (rank < best_rank || (rank == best_rank && edge_key(h) < edge_key(best))) {
            best = h;
            best_rank = rank;
        }
    }
    return best;
}

/// The q-vertex at grid point b in the closed triangle f, or -1.
int qvertex_at(const TriMesh& m, const QState& q, int f, const IPoint& b) {
    const Point2 pb = to_point(b);
    for (int k = 0; k < 3; ++k)
        if (m.uv[3 * f + k] == pb) return q.vertex_qvertex[m.tri[f][k]];
    for (int k = 0; k < 3; ++k) {
        const int h = 3 * f + k;
        if (!on_segment(pb, m.uv[h], m.uv[TriMesh::next(h)])) continue;
        const int canon = canonical_half_edge(m, h);
        const IPoint bc = canon == h ? b : m.map.transition[h](b);
        // An edge's q-vertices ascend along its longer axis in its canonical chart (one per
        // coordinate there), as generate_qvertices walks it: a binary search.
        const Point2 &ea = m.uv[canon], &eb = m.uv[TriMesh::next(canon)];
        const int ax = std::abs(eb[0] - ea[0]) >= std::abs(eb[1] - ea[1]) ? 0 : 1;
        const auto first = q.qvertices.begin() + q.edge_first[canon],
                   last = q.qvertices.begin() + q.edge_first[canon + 1];
        const auto it =
            std::lower_bound(first, last, bc[ax], [ax](const QVertex& v, std::int64_t x) { return v.grid[ax] < x; });
        return it != last && it->grid == bc ? static_cast<int>(it - q.qvertices.begin()) : -1;
    }
    // A triangle's q-vertices ascend by (u, v), as generate_qvertices scans it (u outer): a binary
    // search, where a scan cost the square of the q-vertices on maps with large triangles. It
    // halves the range without a branch on the comparison, which a trace cannot predict.
    const QVertex* base = q.qvertices.data() + q.face_first[f];
    const QVertex* const last = q.qvertices.data() + q.face_first[f + 1];
    auto less = [&b](const QVertex& v) {
        return static_cast<int>(v.grid[0] < b[0]) |
               (static_cast<int>(v.grid[0] == b[0]) & static_cast<int>(v.grid[1] < b[1]));
    };
    for (std::ptrdiff_t len = last - base; len > 1;) {
        const std::ptrdiff_t half = len / 2;
        base += half * less(base[half - 1]);
        len -= half;
    }
    if (base != last && less(*base)) ++base; // the first q-vertex not below b
    return base != last && base->grid == b ? static_cast<int>(base - q.qvertices.data()) : -1;
}

/// The port of q-vertex qv in corner `corner` with direction dir, or -1.
int port_at(const QState& q, int qv, int corner, int dir) {
    const QVertex& v = q.qvertices[qv];
    for (int p = v.first_port; p < v.first_port + v.num_ports; ++p)
        if (q.ports[p].corner == corner && q.ports[p].dir == dir) return p;
    return -1;
}

/// matching_port for a vertex-q-vertex: tries the corner of f at the vertex, then the fan's corners
/// clockwise and counter-clockwise in lockstep; the nearest corner wins (clockwise first).
int vertex_matching_port(const TriMesh& m, const QState& q, int qv, int f, int dir, GridAutomorphism& to_port) {
    const int v = q.qvertices[qv].element;
    int start = -1;
    for (int k = 0; k < 3; ++k)
        if (m.tri[f][k] == v) start = 3 * f + k;
    if (start < 0) return -1;
    if (const int p = port_at(q, qv, start, dir); p >= 0) return p;
    int cw = start, ccw = start;
    GridAutomorphism gcw, gccw;
    const int n = m.fan_size[v];
    for (int step = 1; step < n && (cw >= 0 || ccw >= 0); ++step) {
        if (cw >= 0) {
            gcw = m.map.transition[cw].after(gcw);
            cw = m.cw(cw);
            if (cw >= 0)
                if (const int p = port_at(q, qv, cw, gcw.rotate_dir(dir)); p >= 0) {
                    to_port = gcw;
                    return p;
                }
        }
        if (ccw >= 0) {
            const int prev = TriMesh::prev(ccw);
            if (m.opp[prev] >= 0) {
                gccw = m.map.transition[prev].after(gccw);
                ccw = m.opp[prev];
                if (const int p = port_at(q, qv, ccw, gccw.rotate_dir(dir)); p >= 0) {
                    to_port = gccw;
                    return p;
                }
            } else {
                ccw = -1;
            }
        }
    }
    return -1;
}

/// The port of q-vertex qv that points in direction dir of face f's chart; `to_port` receives the
/// transition from f's chart to the port's chart. Searches the fan outwards from f.
int matching_port(const TriMesh& m, const QState& q, int qv, int f, int dir, GridAutomorphism& to_port) {
    const QVertex& v = q.qvertices[qv];
    to_port = GridAutomorphism{};
    switch (v.kind) {
        case QVertexKind::Face: return port_at(q, qv, 3 * f, dir);
        case QVertexKind::Edge: {
            const int h = v.element, o = m.opp[h];
            const int here = TriMesh::face(h) == f ? h : o, there = here == h ? o : h;
            if (const int p = port_at(q, qv, here, dir); p >= 0) return p;
            if (there < 0) return -1;
            to_port = m.map.transition[here];
            return port_at(q, qv, there, to_port.rotate_dir(dir));
        }
        case QVertexKind::Vertex: return vertex_matching_port(m, q, qv, f, dir, to_port);
    }
    return -1;
}

/// Appends a defect at grid point `grid` in the chart of input triangle `element`.
void add_defect(Report& r, DefectKind kind, std::string msg, std::int64_t element, const IPoint& grid) {
    r.defects.push_back({kind, std::move(msg), element, -1, {grid[0], grid[1]}, std::nullopt});
}

/// "the iso-line from grid point (x, y)", the start of the tracing defects' messages.
std::string iso_line_from(const IPoint& grid) {
    return "the iso-line from grid point (" + std::to_string(grid[0]) + ", " + std::to_string(grid[1]) + ")";
}

/// Where a trace stopped: in triangle f, with the iso-line's direction and its segment's end b in
/// f's chart, and g from the chart of the port's triangle to f's.
struct TraceEnd {
    int f;
    int dir;
    IPoint b;
    GridAutomorphism g;
    bool arrived = false;  ///< b lies in the closed triangle f
    bool boundary = false; ///< the iso-line left the surface through a boundary edge
    bool folded = false;   ///< it crossed a flipped or degenerate triangle
};

/// The sign of the cross product of (n - p) and the axis direction d: exact, by comparisons.
int cross_sign(const Point2& p, const Point2& n, const IPoint& d) {
    auto sign = [](double x, double y) { return (x > y) - (x < y); };
    return d[0] != 0 ? -static_cast<int>(d[0]) * sign(n[1], p[1]) : static_cast<int>(d[1]) * sign(n[0], p[0]);
}

/// Segment (a, b] leaves triangle f through boundary half-edge h. Where it meets h only at an
/// end v, it has not left the surface: it passes v. The fan of v is walked from f away from h to
/// the first triangle whose corner at v holds the iso-line's direction (closed, exact). Returns
/// the half-edge through which that triangle is entered, and `g` the transition from f's chart to
/// its chart; -1 where the iso-line leaves the surface at v, or a fold-over is met first.
int past_boundary_vertex(const TriMesh& m, int h, int dir, const Point2& a, const Point2& b, GridAutomorphism& g) {
    const int hn = TriMesh::next(h);
    const bool at_origin = m.uv[h] != a && on_segment(m.uv[h], a, b);
    const bool at_target = m.uv[hn] != a && on_segment(m.uv[hn], a, b);
    if (at_origin == at_target) return -1; // no end on (a, b], or the segment runs along h
    // e: f's other edge at v; an edge that ends at v has a twin that starts there, and back.
    int e = at_origin ? TriMesh::prev(h) : hn;
    const int v = m.tri[TriMesh::face(h)][(at_origin ? h : hn) % 3];
    g = GridAutomorphism{};
    for (int step = 0; step < m.fan_size[v]; ++step) {
        const int o = m.opp[e];
        if (o < 0) return -1;
        g = m.map.transition[e].after(g);
        dir = m.map.transition[e].rotate_dir(dir);
        if (m.map.face_sign[TriMesh::face(o)] <= 0) return -1;
        const int c = at_origin ? o : TriMesh::next(o); // the corner at v
        const IPoint d = unit_dir(dir);
        if (cross_sign(m.uv[c], m.uv[TriMesh::next(c)], d) >= 0 && cross_sign(m.uv[c], m.uv[TriMesh::prev(c)], d) <= 0)
            return o;
        e = at_origin ? TriMesh::prev(o) : TriMesh::next(o);
    }
    return -1;
}

/// Follows a port's iso-line across triangles, transitions and orientation flips until its next
/// grid point lies in the current triangle, it leaves the surface, or it cannot be followed.
TraceEnd follow_iso_line(const TriMesh& m, const Options& opt, const Port& port, Report& report) {
    TraceEnd end{TriMesh::face(port.corner), port.dir, {}, {}};
    int entry = -1;
    int s = m.map.face_sign[end.f];
    end.folded = s <= 0;
    IPoint a = port.grid;
    end.b = {a[0] + unit_dir(end.dir)[0], a[1] + unit_dir(end.dir)[1]};
    for (std::int64_t step = 0; step < opt.max_trace_steps; ++step) {
        const int f = end.f;
        const Point2 pa = to_point(a), pb = to_point(end.b);
        if (in_closed_triangle(pb, m.uv[3 * f], m.uv[3 * f + 1], m.uv[3 * f + 2])) {
            end.arrived = true;
            break;
        }
        const int h = pick_next_edge(m, f, entry, pa, pb);
        if (h < 0) break;
        int o = m.opp[h];
        GridAutomorphism t = o >= 0 ? m.map.transition[h] : GridAutomorphism{};
        if (o < 0 && (s <= 0 || (o = past_boundary_vertex(m, h, end.dir, pa, pb, t)) < 0)) {
            end.boundary = true;
            break;
        }
        end.g = t.after(end.g);
        a = t(a);
        end.b = t(end.b);
        end.dir = t.rotate_dir(end.dir);
        end.f = TriMesh::face(o);
        entry = o;
        const int s2 = m.map.face_sign[end.f];
        end.folded = end.folded || s2 <= 0;
        if (s2 != 0 && s2 != s) { // orientation flip: the iso-line runs backwards in this chart
            std::swap(a, end.b);
            end.dir = (end.dir + 2) & 3;
            s = s2;
            ++report.orientation_flips_crossed;
        }
    }
    return end;
}

/// The port pointing back where the iso-line arrived (-1 if none); `to_port` receives the
/// transition from the chart of the arrival triangle to that port's.
int arrival_port(const TriMesh& m, const QState& q, const TraceEnd& end, GridAutomorphism& to_port) {
    const int target = qvertex_at(m, q, end.f, end.b);
    return target < 0 ? -1 : matching_port(m, q, target, end.f, (end.dir + 2) & 3, to_port);
}

/// Connects port p to the port pointing back where its iso-line arrived, or reports why it cannot.
void connect(const TriMesh& m, QState& q, int p, const TraceEnd& end, Report& report) {
    const Port& port = q.ports[p];
    const std::int64_t where = m.input_triangle[end.f];
    GridAutomorphism to_port;
    const int p2 = arrival_port(m, q, end, to_port);
    if (p2 < 0) {
        add_defect(report, DefectKind::UnmatchedPort,
                   iso_line_from(port.grid) + " arrived at (" + std::to_string(end.b[0]) + ", " +
                       std::to_string(end.b[1]) + ") where no q-port points back",
                   where, end.b);
        return;
    }
    if (p2 == p || q.connections[p2].to >= 0 || q.into_boundary[p2]) {
        add_defect(report, DefectKind::PortConflict,
                   iso_line_from(port.grid) + " arrived at a q-port that is already connected", where, end.b);
        return;
    }
    const GridAutomorphism total = to_port.after(end.g);
    q.connections[p] = {p2, total};
    q.connections[p2] = {p, total.inverse()};
    ++report.traces_connected;
}

} // namespace

TriangleKey triangle_key(const TriMesh& m, int f) {
    // The smallest of the three rotations (two corners at one point tie on the first position).
    TriangleKey best{};
    for (int c = 3 * f; c < 3 * f + 3; ++c) {
        const TriangleKey key{m.pos(c), m.pos(TriMesh::next(c)), m.pos(TriMesh::prev(c))};
        if (c == 3 * f || key_less(key, best)) best = key;
    }
    return best;
}

bool triangle_less(const TriMesh& m, int f, int g) { return key_less(triangle_key(m, f), triangle_key(m, g)); }

int canonical_half_edge(const TriMesh& m, int h) {
    const int o = m.opp[h];
    if (o < 0) return h;
    // The half-edge that runs from the end with the smaller position; a vertex glued by collapses
    // is at its own input vertex on both sides. (Two vertices at one point: index order.)
    const auto &from = m.vertex_pos(m.origin(h)), &to = m.vertex_pos(m.target(h));
    if (from != to) return from < to ? h : o;
    return std::min(h, o);
}

bool port_less(const TriMesh& m, const QState& q, int a, int b) {
    const Port &x = q.ports[static_cast<std::size_t>(a)], &y = q.ports[static_cast<std::size_t>(b)];
    if (x.qvertex != y.qvertex) return qvertex_less(q, x.qvertex, y.qvertex);
    const int fx = TriMesh::face(x.corner), fy = TriMesh::face(y.corner);
    if (fx != fy) return triangle_less(m, fx, fy);
    return x.dir < y.dir;
}

void trace_ports(const TriMesh& m, const Options& opt, QState& q, Report& report) {
    const int np = static_cast<int>(q.ports.size());
    q.connections.assign(np, Connection{});
    q.into_boundary.assign(np, 0);
    // Two iso-lines may arrive at one port (through fold-overs, mostly): the first to arrive would
    // win, and so the input's order would decide. Instead, iso-lines through fold-overs, and every
    // port some iso-line contests (with all that arrive at it), are settled after the rest, in
    // canonical port order. The others connect in pairs whose order does not matter.
    std::vector<char> contested(static_cast<std::size_t>(np), 0);
    std::vector<int> later;
    auto settle = [&](int p, const TraceEnd& end) {
        const Port& port = q.ports[p];
        if (end.boundary) {
            q.into_boundary[p] = 1;
            ++report.traces_into_boundary;
        } else if (!end.arrived) {
            ++report.traces_failed;
            add_defect(report, DefectKind::TraceFailed, iso_line_from(port.grid) + " could not be followed",
                       m.input_triangle[end.f], port.grid);
        } else {
            connect(m, q, p, end, report);
        }
    };
    for (int p = 0; p < np; ++p) {
        if (q.connections[p].to >= 0 || q.into_boundary[p] || contested[p]) continue;
        ++report.traces;
        const TraceEnd end = follow_iso_line(m, opt, q.ports[p], report);
        if (end.folded) {
            later.push_back(p);
            continue;
        }
        GridAutomorphism to_port;
        const int p2 = end.arrived && !end.boundary ? arrival_port(m, q, end, to_port) : -1;
        if (p2 >= 0 && p2 != p && (contested[p2] || q.connections[p2].to >= 0)) {
            // Contested: p, p2 and whatever p2 was connected to wait for the canonical pass.
            for (const int x : {p, p2, q.connections[p2].to})
                if (x >= 0) contested[x] = 1, later.push_back(x);
            if (const int p4 = q.connections[p2].to; p4 >= 0) {
                q.connections[p2] = q.connections[p4] = Connection{};
                --report.traces_connected;
            }
            continue;
        }
        settle(p, end);
    }
    std::sort(later.begin(), later.end(), [&](int a, int b) { return port_less(m, q, a, b); });
    later.erase(std::unique(later.begin(), later.end()), later.end());
    // First the pairs whose iso-lines arrive at each other (both ends agree), then the rest in
    // canonical order, the first to arrive at a port winning it.
    std::vector<TraceEnd> ends(later.size());
    std::vector<int> target(later.size(), -1);
    std::vector<int> slot(later.empty() ? 0 : static_cast<std::size_t>(np), -1); // read only for later ports
    for (std::size_t i = 0; i < later.size(); ++i) {
        const int p = later[i];
        slot[static_cast<std::size_t>(p)] = static_cast<int>(i);
        if (q.connections[p].to >= 0 || q.into_boundary[p]) continue;
        ++report.traces;
        ends[i] = follow_iso_line(m, opt, q.ports[p], report);
        GridAutomorphism to_port;
        if (ends[i].arrived && !ends[i].boundary) target[i] = arrival_port(m, q, ends[i], to_port);
    }
    auto free_port = [&](int p) { return q.connections[p].to < 0 && !q.into_boundary[p]; };
    for (std::size_t i = 0; i < later.size(); ++i) {
        const int p = later[i], p2 = target[i];
        if (p2 < 0 || p2 == p || !free_port(p) || !free_port(p2)) continue;
        const int j = slot[static_cast<std::size_t>(p2)];
        if (j >= 0 && target[static_cast<std::size_t>(j)] == p) settle(p, ends[i]);
    }
    for (std::size_t i = 0; i < later.size(); ++i)
        if (free_port(later[i])) settle(later[i], ends[i]);
}

} // namespace qex::detail

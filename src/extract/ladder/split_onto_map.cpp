// A coarse mesh split back onto the map it was coarsened from (coarsening, coarsen.cpp): every
// quad of the mesh extracted from the map divided by k becomes k x k quads. A quad's cell is
// searched for on the fine map only inside its open box, so the search cannot wind round a
// singularity at a corner into another sheet; every new vertex lies on a preimage of its grid
// point, one where no vertex lies yet and near the cell where there is one.
#include "chart_search.h"
#include "ladder.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <set>

namespace qex::detail {
namespace {

// ============================================================================ a quad's cell

/// The triangles a provenance's grid point is on, each with the transition from the chart of
/// its triangle `chart_triangle` to its own: that triangle; with the neighbour across the edge;
/// or the vertex's whole fan, walked clockwise. Empty if a triangle of it was collapsed away.
std::vector<std::pair<int, GridAutomorphism>> triangles_at(const TriMesh& g, const Provenance& p) {
    std::vector<std::pair<int, GridAutomorphism>> at;
    const int t0 = p.chart_triangle;
    if (p.kind == QVertexKind::Face) return {{t0, GridAutomorphism{}}};
    if (p.kind == QVertexKind::Edge) {
        const int h = 3 * t0 + p.local_edge, o = g.opp[h];
        at.push_back({t0, GridAutomorphism{}});
        if (o >= 0) at.push_back({TriMesh::face(o), g.map.transition[h]});
        return at;
    }
    // The fan from its first corner, then re-based on t0's chart.
    const int v = p.element;
    GridAutomorphism to_h, to_t0;
    bool seen = false;
    for (int h = g.fan_start[v], n = 0; h >= 0 && n < g.fan_size[v]; h = g.cw(h), ++n) {
        if (!std::isfinite(g.uv[h][0])) return {};
        at.push_back({TriMesh::face(h), to_h});
        if (TriMesh::face(h) == t0 && !seen) to_t0 = to_h, seen = true;
        to_h = g.map.transition[h].after(to_h);
    }
    if (!seen) return {};
    const GridAutomorphism back = to_t0.inverse();
    for (auto& [t, to] : at) to = to.after(back);
    // In an order that does not depend on the input's (fan_start does).
    std::sort(at.begin(), at.end(), [&](const auto& x, const auto& y) { return triangle_less(g, x.first, y.first); });
    return at;
}

/// Where the cell search has a corner of the cell (provenance p, its triangles `at`:
/// triangles_at): 1 when grid point q (seeds' chart) is on the corner's vertex, edge or
/// triangle, at its grid point there; -1 when the search holds one of
/// those triangles with q elsewhere; 0 when it holds none (a fold can keep a corner's own
/// triangles out of the cell).
int corner_found(const ChartSearch& search, const Provenance& p,
                 const std::vector<std::pair<int, GridAutomorphism>>& at, const IPoint& q) {
    const IPoint expected{p.grid[0], p.grid[1]};
    int found = 0;
    for (const auto& [t, to] : at)
        if (search.listed(t)) {
            if (search.to(t)(q) == to(expected)) return 1;
            found = -1;
        }
    return found;
}

/// A coarse face's cell on the given map: the triangles it covers (listed by `search`), and how
/// its local frame lies in their chart.
struct CellFrame {
    std::array<int, 4> corners; ///< the face's vertices, from the corner the frame is anchored at
    IPoint origin, e1, e2;      ///< that corner's grid point (times k), the sides' unit steps
    int turn = 0;               ///< quarter turns from the face's local frame to the chart
    int start = -1;             ///< a triangle the search started from, and the transition
    GridAutomorphism to_start;  ///< from the chart of the points to its chart
    /// Grid point (i, j) of the split cell (0..k each), in the chart of the search's start.
    IPoint point(int i, int j) const {
        const IPoint off = GridAutomorphism::rotate(IPoint{i * e1[0] + j * e2[0], i * e1[1] + j * e2[1]}, turn);
        return {origin[0] + off[0], origin[1] + off[1]};
    }
};

/// Finds face f's cell anchored at its corner `a`, for splitting it into k x k: the start and
/// quarter turn under which the cell's triangles hold the most of its other corners where the
/// coarse mesh has them, and none elsewhere. On success, `search` lists that cell.
bool find_cell(const TriMesh& g, const std::vector<Provenance>& provenance, const std::vector<int>& face,
               const std::vector<std::array<std::int64_t, 2>>& uv, int a, int k, ChartSearch& search,
               CellFrame& frame) {
    for (int i = 0; i < 4; ++i)
        frame.corners[static_cast<std::size_t>(i)] = face[static_cast<std::size_t>((a + i) % 4)];
    const auto at = [&](int i) { return uv[static_cast<std::size_t>((a + i) % 4)]; };
    frame.e1 = {at(1)[0] - at(0)[0], at(1)[1] - at(0)[1]};
    frame.e2 = {at(3)[0] - at(0)[0], at(3)[1] - at(0)[1]};
    const Provenance& p0 = provenance[static_cast<std::size_t>(frame.corners[0])];
    frame.origin = {p0.grid[0], p0.grid[1]};
    // Where the search starts: the triangle of the corner (with the neighbour across its edge);
    // on a vertex, each triangle of its fan on its own (their charts, walked round a
    // singularity, differ by its turn: together they would mix two sheets of the cell).
    const std::vector<std::pair<int, GridAutomorphism>> around = triangles_at(g, p0);
    std::vector<std::vector<std::pair<int, GridAutomorphism>>> starts;
    if (p0.kind == QVertexKind::Vertex)
        for (const auto& seed : around) starts.push_back({seed});
    else if (!around.empty())
        starts.push_back(around);
    const auto run = [&](std::size_t start, int r) {
        frame.turn = r;
        const IPoint lo = frame.point(0, 0), hi = frame.point(k, k);
        return search.cell(starts[start], {std::min(lo[0], hi[0]), std::min(lo[1], hi[1])},
                           {std::max(lo[0], hi[0]), std::max(lo[1], hi[1])}) &&
               !search.triangles().empty();
    };
    // Where the other corners are (their triangles, with transitions), walked once.
    std::array<std::vector<std::pair<int, GridAutomorphism>>, 3> corner_at;
    for (std::size_t j = 0; j < 3; ++j)
        corner_at[j] = triangles_at(g, provenance[static_cast<std::size_t>(frame.corners[j + 1])]);
    int best = 0, turn = -1;
    std::size_t from = 0;
    for (std::size_t start = 0; start < starts.size(); ++start)
        for (int r = 0; r < 4; ++r) {
            if (!run(start, r)) continue;
            int matched = 0;
            bool contradicted = false;
            const std::array<std::pair<int, int>, 3> ij{{{k, 0}, {k, k}, {0, k}}};
            for (std::size_t j = 0; j < 3; ++j) {
                const Provenance& pj = provenance[static_cast<std::size_t>(frame.corners[j + 1])];
                const int found = corner_found(search, pj, corner_at[j], frame.point(ij[j].first, ij[j].second));
                matched += found > 0;
                contradicted = contradicted || found < 0;
            }
            // Starts in one sector find the same cell (their charts differ by the singularity's
            // turn about the corner, and so do their quarter turns): the first is taken.
            if (!contradicted && matched > best) best = matched, turn = r, from = start;
        }
    if (turn < 0 || !run(from, turn)) return false;
    frame.start = starts[from][0].first;
    frame.to_start = starts[from][0].second;
    return true;
}

// ============================================================================ one split

/// The preimages of a grid point a split has met so far: the first, and the first free one.
struct Candidates {
    std::optional<Provenance> first, free_one;
};

/// A coarse mesh's quads split k x k onto the map `g`, face by face, into `out`: what the split
/// carries from one face to the next (which grid points have vertices, and the sides split).
class Splitter {
public:
    Splitter(const Input& input, const TriMesh& g, int k, QuadMesh& out)
        : input_(input),
          g_(g),
          k_(k),
          out_(out),
          search_(g),
          wide_(g),
          slots_(static_cast<std::size_t>((k + 1) * (k + 1))) {}

    /// The coarse vertices, on the same elements: their grid points times k, from the origin.
    /// False if one has no triangle of the map.
    bool place_coarse_vertices(const QuadMesh& coarse, const IPoint& origin) {
        for (std::size_t v = 0; v < coarse.positions.size(); ++v) {
            const Provenance& p = coarse.provenance[v];
            if (p.chart_triangle < 0 || p.chart_triangle >= g_.num_faces()) return false;
            out_.provenance.push_back(located(input_, g_, p.chart_triangle,
                                              {p.grid[0] * k_ + origin[0], p.grid[1] * k_ + origin[1]}, p.merged));
            out_.positions.push_back(position_of(input_, out_.provenance.back()));
        }
        // Where vertices lie (a new vertex takes a preimage where none lies yet, if it has one).
        placed_.insert(out_.positions.begin(), out_.positions.end());
        return true;
    }

    /// A quad of the coarse mesh (its vertices and local UVs), split k x k: false if it has no
    /// cell on the map or a grid point of it no preimage.
    bool split_face(const std::vector<int>& face, const std::vector<std::array<std::int64_t, 2>>& uv) {
        CellFrame frame;
        if (!find_frame(face, uv, frame)) return false;
        const std::array<int, 4>& c = frame.corners;
        // A free preimage is taken only near the cell: within twice its corners' spread of
        // their mean (a grid point found round a singularity can lie across the surface).
        const Neighbourhood cell(out_.positions, c);
        slot(0, 0) = c[0], slot(k_, 0) = c[1], slot(k_, k_) = c[2], slot(0, k_) = c[3];
        if (!split_sides(frame, cell)) return false;
        for (int j = 1; j < k_; ++j)
            for (int i = 1; i < k_; ++i)
                if ((slot(i, j) = place(frame, cell, i, j)) < 0) return false;
        add_faces(frame);
        return true;
    }

private:
    /// The face's cell (find_cell), anchored at a corner inside a triangle if it has one, else on
    /// an edge, else on a vertex (the fewer triangles round the anchor, the fewer starts).
    bool find_frame(const std::vector<int>& face, const std::vector<std::array<std::int64_t, 2>>& uv,
                    CellFrame& frame) {
        std::array<int, 4> anchors{0, 1, 2, 3};
        std::stable_sort(anchors.begin(), anchors.end(), [&](int x, int y) {
            const auto rank = [](QVertexKind kind) {
                return kind == QVertexKind::Face ? 0 : kind == QVertexKind::Edge ? 1 : 2;
            };
            return rank(out_.provenance[static_cast<std::size_t>(face[static_cast<std::size_t>(x)])].kind) <
                   rank(out_.provenance[static_cast<std::size_t>(face[static_cast<std::size_t>(y)])].kind);
        });
        bool found = false;
        for (std::size_t n = 0; n < 4 && !found; ++n)
            found = find_cell(g_, out_.provenance, face, uv, anchors[n], k_, search_, frame);
        return found;
    }

    /// Offers preimage p of the grid point being placed: the first one met, and the first free
    /// one (where no vertex lies yet, near the cell). True when p is free: the search ends.
    bool offer(Provenance p, const Neighbourhood& cell, Candidates& found) const {
        if (!found.first) found.first = p;
        const std::array<double, 3> x = position_of(input_, p);
        if (placed_.count(x) || !cell.near(x)) return false;
        found.free_one = std::move(p);
        return true;
    }

    /// A fold can cut the cell's triangles in parts: the one that holds q is not reached inside
    /// the cell. The preimages of q (in the chart of triangle s0: `from`) an unbounded search
    /// from s0 finds, offered until a free one is.
    void search_beyond(int s0, const IPoint& from, const Neighbourhood& cell, Candidates& found) {
        for (const auto& [u, at_u] : wide_.find_all(s0, from))
            if (offer(located(input_, g_, u, at_u, 1), cell, found)) return;
    }

    /// The vertex at grid point (i, j) of the cell, appended: on a preimage of it inside the cell
    /// where no vertex lies yet (a fold-over can give the grid point several, one another sheet's,
    /// where a vertex is), else the first found. Its index, or -1 if none is found.
    int place(const CellFrame& frame, const Neighbourhood& cell, int i, int j) {
        const IPoint q = frame.point(i, j);
        Candidates found;
        for (const int t : search_.holders(q))
            if (offer(located(input_, g_, t, search_.to(t)(q), 1), cell, found)) break;
        // Searched for from the start, unbounded, then from the cell's triangles. Once some
        // preimage is known, a free one is looked for from at most four more starts (each search
        // lists up to 4096 triangles: a cell of a thousand triangles with no free preimage would
        // otherwise cost a hundred searches per vertex).
        if (!found.free_one) search_beyond(frame.start, frame.to_start(q), cell, found);
        for (std::size_t n = 0, tries = 0;
             !found.free_one && n < search_.triangles().size() && (!found.first || tries < 4);
             n += 8, tries += found.first ? 1 : 0)
            search_beyond(search_.triangles()[n], search_.to(search_.triangles()[n])(q), cell, found);
        if (!found.first) return -1;
        out_.provenance.push_back(found.free_one ? *found.free_one : *found.first);
        out_.positions.push_back(position_of(input_, out_.provenance.back()));
        placed_.insert(out_.positions.back());
        return static_cast<int>(out_.positions.size()) - 1;
    }

    /// The new vertices on the cell's four sides: a side split before (by the face across it)
    /// gives its vertices again, else they are placed. False if one has no preimage.
    bool split_sides(const CellFrame& frame, const Neighbourhood& cell) {
        const std::array<int, 4>& c = frame.corners;
        // The sides, each from its first corner to its second, and the (i, j) of step s along it.
        const std::array<std::array<int, 2>, 4> ends{{{c[0], c[1]}, {c[1], c[2]}, {c[3], c[2]}, {c[0], c[3]}}};
        const int k = k_;
        const auto step = [k](int side, int s) {
            return side == 0   ? std::pair{s, 0}
                   : side == 1 ? std::pair{k, s}
                   : side == 2 ? std::pair{s, k}
                               : std::pair{0, s};
        };
        for (int side = 0; side < 4; ++side) {
            const int a = ends[static_cast<std::size_t>(side)][0], b = ends[static_cast<std::size_t>(side)][1];
            const auto key = std::minmax(a, b);
            // A side's new vertices are numbered from its smaller corner, so the face across it
            // finds them in that order.
            const auto it = side_first_.find(key);
            if (it != side_first_.end()) {
                for (int s = 1; s < k; ++s) {
                    const auto [i, j] = step(side, s);
                    slot(i, j) = it->second + (a < b ? s : k - s) - 1;
                }
                continue;
            }
            side_first_.emplace(key, static_cast<int>(out_.positions.size()));
            for (int t = 1; t < k; ++t) {
                const auto [i, j] = step(side, a < b ? t : k - t);
                if ((slot(i, j) = place(frame, cell, i, j)) < 0) return false;
            }
        }
        return true;
    }

    /// The cell's k x k quads, with their local UVs in the face's frame.
    void add_faces(const CellFrame& frame) {
        for (int j = 0; j < k_; ++j)
            for (int i = 0; i < k_; ++i) {
                out_.faces.push_back({slot(i, j), slot(i + 1, j), slot(i + 1, j + 1), slot(i, j + 1)});
                std::vector<std::array<std::int64_t, 2>> local;
                for (const auto& [di, dj] : {std::pair{0, 0}, std::pair{1, 0}, std::pair{1, 1}, std::pair{0, 1}})
                    local.push_back({(i + di) * frame.e1[0] + (j + dj) * frame.e2[0],
                                     (i + di) * frame.e1[1] + (j + dj) * frame.e2[1]});
                out_.face_uvs.push_back(std::move(local));
            }
    }

    /// The vertex at (i, j), 0..k each, of the split cell.
    int& slot(int i, int j) { return slots_[static_cast<std::size_t>(j * (k_ + 1) + i)]; }

    const Input& input_;
    const TriMesh& g_;
    const int k_;
    QuadMesh& out_;
    ChartSearch search_, wide_;
    std::set<std::array<double, 3>> placed_;
    /// Per coarse edge (its vertices, smaller first): the first of its k - 1 new vertices,
    /// numbered from the smaller vertex on.
    std::map<std::pair<int, int>, int> side_first_;
    std::vector<int> slots_;
};

} // namespace

bool split_onto_map(const Input& input, const std::vector<std::array<double, 2>>& map, const QuadMesh& coarse, int k,
                    const IPoint& origin, QuadMesh& out) {
    TriMesh g = make_mesh(input);
    if (build_topology(g, "input").code != ErrorCode::None) return false;
    g.uv = map;
    compute_transitions(g);
    const auto nv = coarse.positions.size();
    if (coarse.provenance.size() != nv || coarse.face_uvs.size() != coarse.faces.size() || k < 2) return false;
    out = QuadMesh{};
    out.map_uvs = map;
    out.map_repaired = coarse.map_repaired;
    out.provenance.reserve(nv);
    Splitter split(input, g, k, out);
    if (!split.place_coarse_vertices(coarse, origin)) return false;
    for (std::size_t f = 0; f < coarse.faces.size(); ++f) {
        if (coarse.faces[f].size() != 4 || coarse.face_uvs[f].size() != 4) return false;
        if (!split.split_face(coarse.faces[f], coarse.face_uvs[f])) return false;
    }
    return true;
}

} // namespace qex::detail

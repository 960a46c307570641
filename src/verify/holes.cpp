// Holes and missing components: every boundary loop of the mesh that runs along no boundary of
// the input is a hole (Hole: its loop, its faces, the input triangles under it), and in located
// mode every component of the input no vertex lies on is missing (MissingComponent). A loop runs
// along an input boundary loop when each of its vertices lies within a cell of it (the input's
// boundary off the iso-lines leaves a staircase up to a cell inside it: twice the diagonal of
// the vertex's largest face, plus the distance tolerance), and each input loop keeps only the
// mesh loop that runs closest along it: a quad dropped next to the boundary is a hole too.
#include "checker.h"
#include "union_find.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace qex::verify_detail {

using Index = std::int64_t;

/// The mesh's boundary loops (sides without a twin: the reverse side, the edge's only other), each
/// with the faces whose sides it follows. A vertex with several boundary sides continues along
/// the first unused one.
Boundary boundary_loops(const QuadMesh& mesh) {
    // The sides, keyed by their undirected edge: a side alone in its key is a boundary side.
    struct Side {
        std::uint64_t key;
        int from, to;
        Index face;
    };
    std::vector<Side> sides;
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
        const auto& face = mesh.faces[f];
        for (std::size_t i = 0; i < face.size(); ++i) {
            const auto a = static_cast<std::uint32_t>(face[i]),
                       b = static_cast<std::uint32_t>(face[(i + 1) % face.size()]);
            sides.push_back({static_cast<std::uint64_t>(std::min(a, b)) << 32 | std::max(a, b), face[i],
                             face[(i + 1) % face.size()], static_cast<Index>(f)});
        }
    }
    std::sort(sides.begin(), sides.end(),
              [](const Side& x, const Side& y) { return x.key != y.key ? x.key < y.key : x.face < y.face; });
    std::vector<Side> open;
    for (std::size_t i = 0, j = 0; i < sides.size(); i = j) {
        j = i;
        while (j < sides.size() && sides[j].key == sides[i].key) ++j;
        // As the topology counts them: a side has a twin only when its edge has exactly two
        // sides, in opposite directions.
        const bool twins = j - i == 2 && sides[i].from == sides[i + 1].to && sides[i].to == sides[i + 1].from &&
                           sides[i].from != sides[i].to;
        if (!twins)
            for (std::size_t k = i; k < j; ++k) open.push_back(sides[k]);
    }
    std::sort(open.begin(), open.end(),
              [](const Side& x, const Side& y) { return x.from != y.from ? x.from < y.from : x.face < y.face; });
    std::vector<char> used(open.size(), 0);
    auto first_from = [&](int v) -> std::size_t {
        auto it = std::lower_bound(open.begin(), open.end(), v, [](const Side& s, int x) { return s.from < x; });
        for (; it != open.end() && it->from == v; ++it)
            if (!used[static_cast<std::size_t>(it - open.begin())]) return static_cast<std::size_t>(it - open.begin());
        return open.size();
    };
    Boundary b;
    for (std::size_t s0 = 0; s0 < open.size(); ++s0) {
        if (used[s0]) continue;
        std::vector<Index> loop, faces;
        for (std::size_t s = s0; s < open.size(); s = first_from(open[s].to)) {
            used[s] = 1;
            loop.push_back(open[s].from);
            faces.push_back(open[s].face);
            if (open[s].to == open[s0].from) break;
        }
        std::sort(faces.begin(), faces.end());
        faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
        b.loops.push_back(std::move(loop));
        b.faces.push_back(std::move(faces));
    }
    return b;
}

/// The squared distance from x to the segment ab.
double segment_distance2(const std::array<double, 3>& x, const std::array<double, 3>& a,
                         const std::array<double, 3>& b) {
    double ab[3], ax[3], len2 = 0, dot = 0;
    for (int d = 0; d < 3; ++d) ab[d] = b[d] - a[d], ax[d] = x[d] - a[d], len2 += ab[d] * ab[d], dot += ab[d] * ax[d];
    const double t = len2 > 0 ? std::clamp(dot / len2, 0.0, 1.0) : 0.0;
    double d2 = 0;
    for (int d = 0; d < 3; ++d) d2 += (ax[d] - t * ab[d]) * (ax[d] - t * ab[d]);
    return d2;
}

/// The input's boundary edges (edges of one triangle side), in the order of their (smaller end,
/// larger end): the sides bucketed by their smaller end (a counting sort; the indices are the
/// input's, checked), each bucket, a vertex's few sides, sorted by the larger.
std::vector<std::array<int, 2>> input_boundary_edges(const Input& in) {
    std::vector<std::size_t> start(in.positions.size() + 1, 0);
    const auto low = [](const std::array<int, 3>& t, int k) { return std::min(t[k], t[(k + 1) % 3]); };
    for (const auto& t : in.triangles)
        for (int k = 0; k < 3; ++k) ++start[static_cast<std::size_t>(low(t, k)) + 1];
    for (std::size_t v = 0; v + 1 < start.size(); ++v) start[v + 1] += start[v];
    std::vector<std::array<int, 2>> sides(3 * in.triangles.size());
    std::vector<std::size_t> fill(start.begin(), start.end() - 1);
    for (const auto& t : in.triangles)
        for (int k = 0; k < 3; ++k) sides[fill[static_cast<std::size_t>(low(t, k))]++] = {t[k], t[(k + 1) % 3]};
    const auto high = [](const std::array<int, 2>& e) { return std::max(e[0], e[1]); };
    std::vector<std::array<int, 2>> out;
    for (std::size_t v = 0; v + 1 < start.size(); ++v) {
        const auto first = sides.begin() + static_cast<std::ptrdiff_t>(start[v]);
        const auto last = sides.begin() + static_cast<std::ptrdiff_t>(start[v + 1]);
        std::sort(first, last, [&](const auto& a, const auto& b) { return high(a) < high(b); });
        for (auto i = first, j = first; i != last; i = j) {
            while (j != last && high(*j) == high(*i)) ++j;
            if (j - i == 1) out.push_back(*i);
        }
    }
    return out;
}

/// Per input component (by triangles sharing vertices) with no located vertex: its first triangle.
std::vector<Index> empty_input_components(const Input& in, const std::vector<std::int64_t>& located_triangle) {
    UnionFind uf(in.positions.size());
    for (const auto& t : in.triangles) uf.unite(t[1], t[0]), uf.unite(t[2], t[0]);
    std::vector<char> hosts(in.positions.size(), 0), listed(in.positions.size(), 0);
    for (const std::int64_t t : located_triangle)
        if (t >= 0) hosts[static_cast<std::size_t>(uf.find(in.triangles[static_cast<std::size_t>(t)][0]))] = 1;
    std::vector<Index> out;
    for (std::size_t t = 0; t < in.triangles.size(); ++t) {
        const auto root = static_cast<std::size_t>(uf.find(in.triangles[t][0]));
        if (!hosts[root] && !listed[root]) listed[root] = 1, out.push_back(static_cast<Index>(t));
    }
    return out;
}

namespace {

/// Per vertex the farthest other corner of its faces (a cell's diagonal, on a quad mesh).
std::vector<double> cell_reach(const QuadMesh& mesh) {
    std::vector<double> reach(mesh.positions.size(), 0.0);
    for (const auto& face : mesh.faces)
        for (const int a : face)
            for (const int b : face) {
                const auto &p = mesh.positions[static_cast<std::size_t>(a)],
                           &q = mesh.positions[static_cast<std::size_t>(b)];
                const double d = std::sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
                                           (p[2] - q[2]) * (p[2] - q[2]));
                if (std::isfinite(d))
                    reach[static_cast<std::size_t>(a)] = std::max(reach[static_cast<std::size_t>(a)], d);
            }
    return reach;
}

/// The input's boundary edges grouped into loops (by shared vertices), each with the edges of
/// the triangles of zero UV area joined to it through vertices: the map covers no cell there, so
/// a mesh that follows it runs along their far side (a boundary corner whose vertex shares its UV
/// with an interior one is cut off by the mesh's boundary). A degenerate triangle touching two
/// loops joins both; loops are not merged through it.
std::vector<std::vector<std::array<int, 2>>> input_loops(const Input& in) {
    const auto edges = input_boundary_edges(in);
    UnionFind uf(in.positions.size());
    for (const auto& e : edges) uf.unite(e[0], e[1]);
    std::vector<std::int64_t> slot(in.positions.size(), -1), loop_of(in.positions.size(), -1);
    std::vector<std::vector<std::array<int, 2>>> loops;
    for (const auto& e : edges) {
        auto& s = slot[static_cast<std::size_t>(uf.find(e[0]))];
        if (s < 0) s = static_cast<std::int64_t>(loops.size()), loops.emplace_back();
        loops[static_cast<std::size_t>(s)].push_back(e);
        loop_of[static_cast<std::size_t>(e[0])] = loop_of[static_cast<std::size_t>(e[1])] = s;
    }
    // To their closure through degenerate triangles: a worklist of labelled vertices, each
    // degenerate triangle at one joining its loop once (a pass over all triangles per step of a
    // chain of them would be quadratic).
    const std::vector<char> degenerate = uv_degenerate_triangles(in);
    std::vector<std::vector<std::size_t>> at(in.positions.size()); // degenerate triangles per vertex
    for (std::size_t f = 0; f < in.triangles.size(); ++f)
        if (degenerate[f])
            for (const int v : in.triangles[f]) at[static_cast<std::size_t>(v)].push_back(f);
    std::vector<std::vector<std::int64_t>> joined(in.triangles.size()); // per triangle, the loops it joined
    std::vector<int> work;
    for (std::size_t v = 0; v < in.positions.size(); ++v)
        if (loop_of[v] >= 0 && !at[v].empty()) work.push_back(static_cast<int>(v));
    for (std::size_t i = 0; i < work.size(); ++i) {
        const std::int64_t l = loop_of[static_cast<std::size_t>(work[i])];
        for (const std::size_t f : at[static_cast<std::size_t>(work[i])]) {
            if (std::find(joined[f].begin(), joined[f].end(), l) != joined[f].end()) continue;
            joined[f].push_back(l);
            const auto& t = in.triangles[f];
            for (int k = 0; k < 3; ++k) loops[static_cast<std::size_t>(l)].push_back({t[k], t[(k + 1) % 3]});
            for (const int w : t)
                if (loop_of[static_cast<std::size_t>(w)] < 0) loop_of[static_cast<std::size_t>(w)] = l, work.push_back(w);
        }
    }
    return loops;
}

} // namespace

std::vector<std::size_t> find_holes(const Input& in, const QuadMesh& mesh, const Boundary& b, double tol) {
    std::vector<std::size_t> holes;
    const auto loops = input_loops(in);
    std::size_t work = 0;
    for (const auto& l : b.loops) work += l.size();
    if (static_cast<double>(work) * static_cast<double>(3 * in.triangles.size()) > 5e8) return holes; // not decided
    const std::vector<double> reach = cell_reach(mesh);
    // Per input loop the mesh loop that runs closest along it (the largest distance of a vertex).
    std::vector<double> best(loops.size(), HUGE_VAL);
    std::vector<std::int64_t> kept_by(loops.size(), -1);
    for (std::size_t l = 0; l < b.loops.size(); ++l)
        for (std::size_t i = 0; i < loops.size(); ++i) {
            double far = 0;
            bool along = true;
            for (const Index v : b.loops[l]) {
                const auto& x = mesh.positions[static_cast<std::size_t>(v)];
                double d2 = HUGE_VAL;
                for (const auto& e : loops[i])
                    d2 = std::min(d2, segment_distance2(x, in.positions[static_cast<std::size_t>(e[0])],
                                                        in.positions[static_cast<std::size_t>(e[1])]));
                const double d = std::sqrt(d2);
                far = std::max(far, d);
                along = along && d <= tol + 2 * reach[static_cast<std::size_t>(v)];
                if (!along) break;
            }
            if (along && far < best[i]) best[i] = far, kept_by[i] = static_cast<std::int64_t>(l);
        }
    for (std::size_t l = 0; l < b.loops.size(); ++l)
        if (std::find(kept_by.begin(), kept_by.end(), static_cast<std::int64_t>(l)) == kept_by.end())
            holes.push_back(l);
    return holes;
}

void check_holes(const Input& in, const QuadMesh& mesh, bool has_boundary, double tol,
                 const std::vector<std::int64_t>& closest_triangle, const std::vector<std::int64_t>& located_triangle,
                 std::vector<Violation>& out) {
    const Boundary b = has_boundary ? boundary_loops(mesh) : Boundary{};
    for (const std::size_t l : b.loops.empty() ? std::vector<std::size_t>{} : find_holes(in, mesh, b, tol)) {
        const auto& loop = b.loops[l];
        std::vector<Index> under;
        for (const Index v : loop) {
            const std::int64_t t = static_cast<std::size_t>(v) < closest_triangle.size()
                                       ? closest_triangle[static_cast<std::size_t>(v)]
                                       : -1;
            if (t >= 0 && std::find(under.begin(), under.end(), t) == under.end()) under.push_back(t);
        }
        std::string through;
        for (std::size_t i = 0; i < loop.size() && i < 8; ++i) through += (i ? " " : "") + std::to_string(loop[i]);
        Violation x{
            ViolationKind::Hole,
            "the boundary loop of " + std::to_string(loop.size()) + " vertices through " + through +
                (loop.size() > 8 ? " ..." : "") + " runs along no boundary of the input" +
                (under.empty() ? std::string() : " (a hole at input triangle " + std::to_string(under[0]) + ")"),
            loop[0],
            {{PlaceKind::Loop, loop}, {PlaceKind::Face, b.faces[l]}}};
        if (!under.empty()) x.places.push_back({PlaceKind::InputTriangle, under});
        if (out.size() < kMaxListed) out.push_back(std::move(x));
    }
    if (located_triangle.empty()) return;
    for (const Index t : empty_input_components(in, located_triangle))
        add_capped(out, ViolationKind::MissingComponent,
                   "the input's component of triangle " + std::to_string(t) + " carries no vertex of the mesh", t);
}

} // namespace qex::verify_detail

// qex::check_layout: the independent check of a quad layout. It sees only the public headers and
// shares no code with the tracing (quad_topology, trace, patches): its own edge table, its own
// notion of a regular vertex (the faces round a vertex joined across uncut edges, corner by
// corner: every group of 4 without a cut, of 2 with one), and the patches judged as sub-complexes
// (Euler characteristic, boundary loops, corners counted by faces, sides walked).
#include "qex/layout.h"

#include <algorithm>
#include <cstdint>
#include <map>
#include <numeric>
#include <unordered_map>

namespace qex {
namespace {

struct Find {
    std::vector<int> up;
    explicit Find(int n) : up(n) { std::iota(up.begin(), up.end(), 0); }
    int root(int x) {
        while (up[x] != x) x = up[x] = up[up[x]];
        return x;
    }
    void join(int a, int b) { up[root(a)] = root(b); }
};

/// The mesh as the check sees it: edges with their faces, cuts, and which vertices are regular.
struct Judge {
    const QuadMesh& mesh;
    std::vector<std::array<int, 2>> edge_ends, edge_faces; ///< faces: -1 where none
    std::vector<int> corner_edge;                          ///< per face corner 4f+k: the edge to corner k+1
    std::vector<int> star_begin;                           ///< per vertex + 1: its range in `star`
    std::vector<std::pair<int, int>> star;                 ///< (neighbour, edge)
    std::vector<char> edge_cut, edge_layout;               ///< boundary or feature; and cut or separatrix
    std::vector<char> boundary, feature, special;          ///< per vertex
    explicit Judge(const QuadMesh& m) : mesh(m) {}

    int find_edge(int a, int b) const {
        for (int i = star_begin[a]; i < star_begin[a + 1]; ++i)
            if (star[i].first == b) return star[i].second;
        return -1;
    }
    bool cut(int v) const { return boundary[v] || feature[v]; }
};

/// The edges, each with its faces: the face corners bucketed by the smaller vertex of their edge.
std::string build_edge_table(Judge& j) {
    const auto& faces = j.mesh.faces;
    const int nv = static_cast<int>(j.mesh.positions.size());
    std::vector<int> begin(nv + 1, 0);
    for (std::size_t f = 0; f < faces.size(); ++f) {
        if (faces[f].size() != 4) return "face " + std::to_string(f) + " is not a quad";
        for (int k = 0; k < 4; ++k) {
            const int a = faces[f][k], b = faces[f][(k + 1) % 4];
            if (a < 0 || b < 0 || a >= nv || b >= nv || a == b) return "face " + std::to_string(f) + " has a bad index";
            ++begin[std::min(a, b) + 1];
        }
    }
    std::partial_sum(begin.begin(), begin.end(), begin.begin());
    std::vector<int> corners(4 * faces.size()), fill(begin.begin(), begin.end() - 1);
    const auto ends = [&](int c) {
        const int a = faces[c / 4][c % 4], b = faces[c / 4][(c + 1) % 4];
        return std::make_pair(std::min(a, b), std::max(a, b));
    };
    for (int c = 0; c < static_cast<int>(corners.size()); ++c) corners[fill[ends(c).first]++] = c;
    j.corner_edge.assign(corners.size(), -1);
    for (int v = 0; v < nv; ++v)
        for (int i = begin[v]; i < begin[v + 1]; ++i) {
            const int c = corners[i];
            if (j.corner_edge[c] >= 0) continue;
            const int e = static_cast<int>(j.edge_faces.size());
            j.edge_ends.push_back({v, ends(c).second});
            j.edge_faces.push_back({c / 4, -1});
            j.corner_edge[c] = e;
            for (int k = i + 1; k < begin[v + 1]; ++k) {
                const int d = corners[k];
                if (ends(d).second != ends(c).second) continue;
                if (j.edge_faces[e][1] >= 0)
                    return "an edge of face " + std::to_string(d / 4) + " has more than two faces";
                j.edge_faces[e][1] = d / 4;
                j.corner_edge[d] = e;
            }
        }
    j.star_begin.assign(nv + 1, 0);
    for (const auto& [a, b] : j.edge_ends) ++j.star_begin[a + 1], ++j.star_begin[b + 1];
    std::partial_sum(j.star_begin.begin(), j.star_begin.end(), j.star_begin.begin());
    j.star.resize(2 * j.edge_ends.size());
    std::vector<int> at(j.star_begin.begin(), j.star_begin.end() - 1);
    for (int e = 0; e < static_cast<int>(j.edge_ends.size()); ++e) {
        const auto [a, b] = j.edge_ends[e];
        j.star[at[a]++] = {b, e};
        j.star[at[b]++] = {a, e};
    }
    return "";
}

std::string build_edges(Judge& j, const LayoutOptions& options) {
    if (std::string e = build_edge_table(j); !e.empty()) return e;
    const int nv = static_cast<int>(j.mesh.positions.size());
    j.edge_cut.assign(j.edge_faces.size(), 0);
    j.boundary.assign(nv, 0);
    j.feature.assign(nv, 0);
    for (std::size_t e = 0; e < j.edge_faces.size(); ++e)
        if (j.edge_faces[e][1] < 0) {
            j.edge_cut[e] = 1;
            j.boundary[j.edge_ends[e][0]] = j.boundary[j.edge_ends[e][1]] = 1;
        }
    for (const auto& fe : options.feature_edges) {
        const int e = fe[0] >= 0 && fe[0] < nv && fe[1] >= 0 && fe[1] < nv ? j.find_edge(fe[0], fe[1]) : -1;
        if (e < 0) return "a feature edge is not an edge of the mesh";
        j.edge_cut[e] = 1;
        j.feature[fe[0]] = j.feature[fe[1]] = 1;
    }
    j.edge_layout = j.edge_cut;
    return "";
}

/// The face corners joined across every interior mesh edge that `blocked` does not mark: a group
/// per vertex and side of the blocked edges round it.
Find corner_groups(const Judge& j, const std::vector<char>& blocked) {
    const auto& faces = j.mesh.faces;
    Find groups(static_cast<int>(4 * faces.size()));
    const auto corner = [&](int f, int v) {
        for (int k = 0; k < 4; ++k)
            if (faces[f][k] == v) return 4 * f + k;
        return -1;
    };
    for (std::size_t e = 0; e < j.edge_faces.size(); ++e) {
        const auto [f, g] = j.edge_faces[e];
        if (g < 0 || blocked[e]) continue;
        for (const int v : j.edge_ends[e]) groups.join(corner(f, v), corner(g, v));
    }
    return groups;
}

/// Regular vertices: the face corners at a vertex joined across its uncut edges form one group of
/// 4 (no cut at the vertex) or groups of 2 (a cut).
void find_special(Judge& j) {
    const auto& faces = j.mesh.faces;
    Find groups = corner_groups(j, j.edge_cut);
    std::vector<int> size(4 * faces.size(), 0), corners(j.mesh.positions.size(), 0);
    for (int c = 0; c < static_cast<int>(size.size()); ++c) ++size[groups.root(c)];
    j.special.assign(j.mesh.positions.size(), 0);
    for (int c = 0; c < static_cast<int>(size.size()); ++c) {
        const int v = faces[c / 4][c % 4], s = size[groups.root(c)];
        ++corners[v];
        if (s != (j.cut(v) ? 2 : 4)) j.special[v] = 1;
    }
}

/// The separatrices: along uncut mesh edges, no edge twice, straight through regular vertices,
/// from a special vertex (or a cut's boundary vertex) to where their end says.
std::string check_separatrices(Judge& j, const Layout& layout) {
    const int nv = static_cast<int>(j.mesh.positions.size());
    std::vector<char> inner(nv, 0);
    for (std::size_t s = 0; s < layout.separatrices.size(); ++s) {
        const auto& p = layout.separatrices[s].vertices;
        const std::string name = "separatrix " + std::to_string(s);
        if (p.size() < 2) return name + " has fewer than 2 vertices";
        for (const int v : p)
            if (v < 0 || v >= nv) return name + " has a bad vertex index";
        for (std::size_t i = 0; i + 1 < p.size(); ++i) {
            const int e = j.find_edge(p[i], p[i + 1]);
            if (e < 0) return name + " leaves the mesh edges at vertex " + std::to_string(p[i]);
            if (j.edge_layout[e])
                return name + " runs along a cut or another separatrix at vertex " + std::to_string(p[i]);
            j.edge_layout[e] = 1;
        }
        for (std::size_t i = 1; i + 1 < p.size(); ++i) {
            const auto a = j.edge_faces[j.find_edge(p[i - 1], p[i])], b = j.edge_faces[j.find_edge(p[i], p[i + 1])];
            const bool turns = a[0] == b[0] || a[0] == b[1] || a[1] == b[0] || a[1] == b[1];
            if (j.special[p[i]] || j.cut(p[i]) || turns)
                return name + " does not run straight through a regular vertex at " + std::to_string(p[i]);
            inner[p[i]] = 1;
        }
    }
    for (std::size_t s = 0; s < layout.separatrices.size(); ++s) {
        const Separatrix& x = layout.separatrices[s];
        const int a = x.vertices.front(), z = x.vertices.back();
        bool start = false, end = false;
        switch (x.start) {
            case SeparatrixStart::IrregularVertex: start = j.special[a] && !j.cut(a); break;
            case SeparatrixStart::BoundaryVertex: start = j.special[a] && j.boundary[a]; break;
            case SeparatrixStart::FeatureVertex: start = j.special[a] && j.feature[a] && !j.boundary[a]; break;
            case SeparatrixStart::Cut: start = !j.special[a] && (j.cut(a) || inner[a]); break;
        }
        switch (x.end) {
            case SeparatrixEnd::SpecialVertex:
            case SeparatrixEnd::HeadOn: end = j.special[z]; break;
            case SeparatrixEnd::Boundary: end = !j.special[z] && j.boundary[z]; break;
            case SeparatrixEnd::Feature: end = !j.special[z] && j.feature[z] && !j.boundary[z]; break;
            case SeparatrixEnd::Separatrix: end = !j.special[z] && !j.cut(z) && inner[z]; break;
        }
        if (!start) return "separatrix " + std::to_string(s) + " does not start as " + to_string(x.start) + " says";
        if (!end) return "separatrix " + std::to_string(s) + " does not end as " + to_string(x.end) + " says";
    }
    return "";
}

/// The patches cover the mesh, each one piece, joined to others only across layout edges.
std::string check_cover(const Judge& j, const Layout& layout) {
    const int nf = static_cast<int>(j.mesh.faces.size()), np = static_cast<int>(layout.patches.size());
    if (static_cast<int>(layout.face_patch.size()) != nf) return "face_patch does not name a patch per face";
    std::vector<std::vector<int>> members(np);
    for (int f = 0; f < nf; ++f) {
        if (layout.face_patch[f] < 0 || layout.face_patch[f] >= np)
            return "face " + std::to_string(f) + " has no patch";
        members[layout.face_patch[f]].push_back(f);
    }
    Find pieces(nf);
    for (std::size_t e = 0; e < j.edge_faces.size(); ++e) {
        const auto [f, g] = j.edge_faces[e];
        if (g < 0) continue;
        const bool apart = layout.face_patch[f] != layout.face_patch[g];
        if (apart && !j.edge_layout[e])
            return "faces " + std::to_string(f) + " and " + std::to_string(g) +
                   " are in different patches across an edge on no separatrix";
        if (!apart && j.edge_layout[e])
            return "a separatrix or cut runs inside patch " + std::to_string(layout.face_patch[f]);
        if (!apart) pieces.join(f, g);
    }
    for (int p = 0; p < np; ++p) {
        if (members[p].empty() || members[p] != layout.patches[p].faces)
            return "patch " + std::to_string(p) + " does not list the faces face_patch gives it";
        for (const int f : members[p])
            if (pieces.root(f) != pieces.root(members[p][0])) return "patch " + std::to_string(p) + " is not one piece";
    }
    return "";
}

/// The face corners joined across the edges on no separatrix or cut: the vertices of the patches
/// as surfaces (a vertex a patch's boundary passes twice is two of them).
Find patch_vertices(const Judge& j) { return corner_groups(j, j.edge_layout); }

/// Per face-corner group (its root): faces, its vertex, the next group along the patch's boundary
/// (-1: none); reset after each patch.
struct Groups {
    Find find;
    std::vector<int> faces_at, vertex, next;
    explicit Groups(Find f)
        : find(std::move(f)), faces_at(find.up.size(), 0), vertex(find.up.size(), -1), next(find.up.size(), -1) {}
};

/// Walks a rectangle's boundary from a corner at corners[0]: sides u, v, u, v to corners[1..3, 0],
/// and nothing else on the boundary (`rim` groups in all).
bool sides_match(const Patch& patch, const Groups& gs, int start, std::size_t rim) {
    const int sides[4] = {patch.u, patch.v, patch.u, patch.v};
    int g = start;
    std::size_t walked = 0;
    for (int s = 0; s < 4; ++s) {
        for (int i = 0; i < sides[s]; ++i, ++walked) {
            if (gs.next[g] < 0 || walked > rim) return false;
            g = gs.next[g];
        }
        if (gs.vertex[g] != patch.corners[(s + 1) % 4]) return false;
    }
    return g == start && walked == rim;
}

/// One patch as a surface (its corners joined across its inner edges): a disk with one boundary
/// loop, 4 corners (1 face) and otherwise sides (2 faces), regular vertices inside, sides u, v,
/// u, v from corners[0] on, u * v faces; or a torus: a closed component of regular vertices.
std::string check_patch(const Judge& j, Groups& gs, const Layout& layout, int p) {
    const Patch& patch = layout.patches[p];
    const std::string name = "patch " + std::to_string(p);
    std::vector<int> touched;
    long long twice_edges = 0;
    std::size_t rim = 0;
    for (const int f : patch.faces)
        for (int k = 0; k < 4; ++k) {
            const int g = gs.find.root(4 * f + k);
            if (gs.faces_at[g]++ == 0) touched.push_back(g);
            gs.vertex[g] = j.mesh.faces[f][k];
            const bool on_rim = j.edge_layout[j.corner_edge[4 * f + k]] != 0;
            twice_edges += on_rim ? 2 : 1;
            if (!on_rim) continue;
            if (gs.next[g] >= 0)
                return name + " has a boundary that branches at vertex " + std::to_string(gs.vertex[g]);
            gs.next[g] = gs.find.root(4 * f + (k + 1) % 4);
            ++rim;
        }
    const long long euler =
        static_cast<long long>(touched.size()) - twice_edges / 2 + static_cast<long long>(patch.faces.size());
    std::vector<int> corners, starts;
    std::string problem;
    for (const int g : touched) {
        const int v = gs.vertex[g], n = gs.faces_at[g];
        const bool on_rim = gs.next[g] >= 0;
        if (!on_rim && (n != 4 || j.special[v] || j.cut(v)))
            problem = name + " has an irregular vertex inside: " + std::to_string(v);
        if (on_rim && n > 2) problem = name + " has a concave corner at vertex " + std::to_string(v);
        if (on_rim && n == 1) corners.push_back(v);
        if (on_rim && n == 1 && v == patch.corners[0]) starts.push_back(g);
    }
    if (static_cast<long long>(patch.u) * patch.v != static_cast<long long>(patch.faces.size()) || patch.u < 1)
        problem = name + " has " + std::to_string(patch.faces.size()) + " faces, not u * v";
    else if (patch.kind == PatchKind::Torus && (rim != 0 || euler != 0))
        problem = name + " is no closed torus component";
    else if (patch.kind == PatchKind::Rectangle && (euler != 1 || corners.size() != 4))
        problem = name + " is not a disk with 4 corners";
    std::sort(corners.begin(), corners.end());
    std::array<int, 4> given = patch.corners;
    std::sort(given.begin(), given.end());
    if (problem.empty() && patch.kind == PatchKind::Rectangle) {
        if (!std::equal(corners.begin(), corners.end(), given.begin()))
            problem = name + " does not name its corners";
        else if (std::none_of(starts.begin(), starts.end(), [&](int g) { return sides_match(patch, gs, g, rim); }))
            problem = name + "'s boundary is not one loop of sides u, v, u, v from corners[0]";
    }
    for (const int g : touched) gs.faces_at[g] = 0, gs.vertex[g] = -1, gs.next[g] = -1;
    return problem;
}

std::string check_adjacency(const Judge& j, const Layout& layout) {
    std::map<std::pair<int, int>, int> shared;
    for (const auto& [f, g] : j.edge_faces)
        if (g >= 0 && layout.face_patch[f] != layout.face_patch[g])
            ++shared[std::minmax(layout.face_patch[f], layout.face_patch[g])];
    if (shared.size() != layout.adjacency.size()) return "the adjacency lists other pairs of patches";
    std::size_t i = 0;
    for (const auto& [ab, n] : shared) {
        const PatchAdjacency& x = layout.adjacency[i++];
        if (x.a != ab.first || x.b != ab.second || x.shared_edges != n)
            return "the adjacency of patches " + std::to_string(ab.first) + " and " + std::to_string(ab.second) +
                   " is wrong";
    }
    return "";
}

} // namespace

std::string check_layout(const QuadMesh& mesh, const Layout& layout, const LayoutOptions& options) {
    Judge j(mesh);
    if (std::string e = build_edges(j, options); !e.empty()) return e;
    find_special(j);
    std::vector<int> special;
    for (int v = 0; v < static_cast<int>(j.special.size()); ++v)
        if (j.special[v]) special.push_back(v);
    if (special != layout.special_vertices) return "the special vertices are not the mesh's";
    if (std::string e = check_separatrices(j, layout); !e.empty()) return e;
    if (std::string e = check_cover(j, layout); !e.empty()) return e;
    Groups groups(patch_vertices(j));
    for (int p = 0; p < static_cast<int>(layout.patches.size()); ++p)
        if (std::string e = check_patch(j, groups, layout, p); !e.empty()) return e;
    return check_adjacency(j, layout);
}

} // namespace qex

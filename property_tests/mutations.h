// Meshes broken the way real extractors break them, made from a correct quad mesh, and what the
// checker must say of them (checker_mutations_test.cpp on generated maps, and
// checker_precision_test.cpp on qex's outputs of the real maps).
#pragma once

#include "map_generators.h"
#include "qex/qex.h"

#include <algorithm>
#include <cstdint>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace qex::testing {

/// Mutation sites a face apart: each claims its faces and every face at their vertices.
class Sites {
public:
    explicit Sites(const QuadMesh& m) : faces_of_(m.positions.size()), taken_(m.faces.size(), 0) {
        for (std::size_t f = 0; f < m.faces.size(); ++f)
            for (int v : m.faces[f]) faces_of_[static_cast<std::size_t>(v)].push_back(f);
    }
    /// Claims the faces at `vertices` if none is claimed yet.
    bool claim(const std::vector<int>& vertices) {
        for (int v : vertices)
            for (std::size_t f : faces_of_[static_cast<std::size_t>(v)])
                if (taken_[f]) return false;
        for (int v : vertices)
            for (std::size_t f : faces_of_[static_cast<std::size_t>(v)]) taken_[f] = 1;
        return true;
    }
    /// Claims every face at v, claimed or not.
    void block(int v) {
        for (std::size_t f : faces_of_[static_cast<std::size_t>(v)]) taken_[f] = 1;
    }
    const std::vector<std::size_t>& faces_at(int v) const { return faces_of_[static_cast<std::size_t>(v)]; }

private:
    std::vector<std::vector<std::size_t>> faces_of_;
    std::vector<char> taken_;
};

/// The mesh as another extractor would write it: positions and faces only.
inline QuadMesh bare(const QuadMesh& m) {
    QuadMesh b;
    b.positions = m.positions;
    b.faces = m.faces;
    return b;
}

/// How many violations of kind `k` the verdict holds.
inline std::size_t count(const VerifyResult& v, ViolationKind k) {
    std::size_t n = 0;
    for (const Violation& x : v.violations) n += x.kind == k;
    return n;
}

/// A generated map and qex's mesh of it, bare: the correct mesh the mutations start from.
struct MutationCase {
    const char* name;
    Input in;
    QuadMesh good;
};

inline MutationCase make_case(const char* name, Input in) {
    MutationCase c{name, std::move(in), {}};
    c.good = bare(extract(c.in).mesh);
    return c;
}

/// The checker tests' maps: a torus (no singularities: every face failure is decided), a cube
/// (cones) and an annulus (boundary), each with qex's own mesh.
inline std::vector<MutationCase> standard_cases() {
    std::vector<MutationCase> out;
    out.push_back(make_case("torus", make_map(torus_layout(), 3, 2)));
    out.push_back(make_case("cube", make_map(cube_layout(), 3, 3)));
    out.push_back(make_case("annulus", make_map(annulus_layout(), 3, 3)));
    return out;
}

/// Whether a violation of kind `k` has a place of kind `pk` whose indices include all of `want`.
inline bool names(const VerifyResult& v, ViolationKind k, PlaceKind pk, const std::vector<std::int64_t>& want) {
    for (const Violation& x : v.violations) {
        if (x.kind != k) continue;
        for (const Place& p : x.places) {
            if (p.kind != pk) continue;
            const std::set<std::int64_t> have(p.indices.begin(), p.indices.end());
            if (std::all_of(want.begin(), want.end(), [&](std::int64_t i) { return have.count(i) > 0; })) return true;
        }
    }
    return false;
}

/// Whether face f is named as no grid cell, as a violation or (with `undecided`) an undecided check.
inline bool names_face(const VerifyResult& v, std::int64_t f, bool undecided) {
    for (const auto* list : {&v.violations, &v.undecided})
        for (const Violation& x : *list)
            if (x.kind == ViolationKind::FaceNotGridCell && x.element == f && (list == &v.violations || undecided))
                return true;
    return false;
}

/// Whether a violation in `list` names one of `vertices` or `faces` (its element or a place).
inline bool named(const std::vector<Violation>& list, const std::set<std::int64_t>& vertices,
                  const std::set<std::int64_t>& faces) {
    for (const Violation& x : list) {
        const ViolationElement e = element_kind(x.kind);
        if ((e == ViolationElement::OutputVertex && vertices.count(x.element)) ||
            (e == ViolationElement::OutputFace && faces.count(x.element)))
            return true;
        for (const Place& p : x.places) {
            const auto& in = p.kind == PlaceKind::Face ? faces : vertices;
            if (p.kind != PlaceKind::Vertex && p.kind != PlaceKind::Loop && p.kind != PlaceKind::Face) continue;
            for (const std::int64_t i : p.indices)
                if (in.count(i)) return true;
        }
    }
    return false;
}

/// "" when every violation names at least one non-empty place; else the first that does not.
inline std::string unplaced(const VerifyResult& v) {
    for (const Violation& x : v.violations)
        if (x.places.empty() || x.places.front().indices.empty())
            return std::string(to_string(x.kind)) + ": " + x.message;
    return {};
}

inline std::string first_message(const VerifyResult& v) { return v.violations.empty() ? "" : v.violations[0].message; }

/// Two faces sharing an edge (a, b): a -> b in f (the first from face `start` on), b -> a in g.
struct SharedEdge {
    std::size_t f = 0, g = 0;
    int a = -1, b = -1;
};
inline SharedEdge shared_edge(const QuadMesh& m, std::size_t start) {
    std::vector<std::vector<std::size_t>> faces_of(m.positions.size());
    for (std::size_t f = 0; f < m.faces.size(); ++f)
        for (int v : m.faces[f]) faces_of[static_cast<std::size_t>(v)].push_back(f);
    for (std::size_t f = start; f < m.faces.size(); ++f)
        for (std::size_t i = 0; i < 4; ++i) {
            const int a = m.faces[f][i], b = m.faces[f][(i + 1) % 4];
            for (std::size_t g : faces_of[static_cast<std::size_t>(a)]) {
                if (g == f) continue;
                for (std::size_t j = 0; j < 4; ++j)
                    if (m.faces[g][j] == b && m.faces[g][(j + 1) % 4] == a) return {f, g, a, b};
            }
        }
    return {};
}

/// The first face from `start` on (cyclically) none of whose vertices is on the mesh's boundary;
/// m.faces.size() when there is none.
inline std::size_t interior_face(const QuadMesh& m, std::size_t start) {
    std::set<std::pair<int, int>> sides;
    for (const auto& f : m.faces)
        for (std::size_t i = 0; i < f.size(); ++i) sides.insert({f[i], f[(i + 1) % f.size()]});
    std::set<int> boundary;
    for (const auto& s : sides)
        if (!sides.count({s.second, s.first})) boundary.insert(s.first), boundary.insert(s.second);
    for (std::size_t k = 0; k < m.faces.size(); ++k) {
        const std::size_t f = (start + k) % m.faces.size();
        if (std::none_of(m.faces[f].begin(), m.faces[f].end(), [&](int v) { return boundary.count(v) > 0; })) return f;
    }
    return start;
}

/// Replaces vertex b by a in every face.
inline void merge_into(QuadMesh& m, int b, int a) {
    for (auto& face : m.faces)
        for (int& x : face)
            if (x == b) x = a;
}

/// Rotates the edge shared by faces e.f and e.g: the hexagon around it, split by the other diagonal.
inline void rotate_edge(QuadMesh& m, const SharedEdge& e) {
    auto from = [](std::vector<int> face, int v) {
        std::rotate(face.begin(), std::find(face.begin(), face.end(), v), face.end());
        return face;
    };
    // f = (a, b, x, y), g = (b, a, z, w): around the hexagon a -> z -> w -> b -> x -> y.
    const std::vector<int> f = from(m.faces[e.f], e.a), g = from(m.faces[e.g], e.b);
    const std::vector<int> hex{f[0], g[2], g[3], f[1], f[2], f[3]};
    m.faces[e.f] = {hex[1], hex[2], hex[3], hex[4]};
    m.faces[e.g] = {hex[4], hex[5], hex[0], hex[1]};
}

/// The vertices of the two faces of e in `good` (each once when e is rotatable).
inline std::vector<int> edge_site(const QuadMesh& good, const SharedEdge& e) {
    std::vector<int> site(good.faces[e.f].begin(), good.faces[e.f].end());
    site.insert(site.end(), good.faces[e.g].begin(), good.faces[e.g].end());
    return site;
}

/// Rotates e in m (a copy of `good`, mutated so far only at sites `sites` claimed) when its
/// faces lie a face apart from those sites, claiming it: mutants that can be judged together.
inline bool rotate_apart(Sites& sites, const QuadMesh& good, QuadMesh& m, const SharedEdge& e) {
    if (!sites.claim(edge_site(good, e))) return false;
    rotate_edge(m, e);
    return true;
}

} // namespace qex::testing

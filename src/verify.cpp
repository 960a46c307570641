// The checker: judges a polygon mesh against the input map with its own code (nothing from the
// extraction pipeline) and exact rational arithmetic (CGAL) wherever a number is compared.
#include "qex/qex.h"

#include <CGAL/Exact_rational.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>
#include <unordered_map>

namespace qex {
namespace {

using Rational = CGAL::Exact_rational;

struct Topology {
    std::int64_t vertices = 0, edges = 0, faces = 0, boundary_loops = 0, components = 0;
    std::int64_t euler() const { return vertices - edges + faces; }
};

int find(std::vector<int>& parent, int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
}

std::uint64_t key(int a, int b) { return static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32 | static_cast<std::uint32_t>(b); }

/// Topology of a polygon mesh with valid indices; appends violations when `out` is given.
Topology analyse(std::size_t num_vertices, const std::vector<std::vector<int>>& faces, std::vector<Violation>* out) {
    Topology t;
    auto violate = [&](ViolationKind k, std::string msg, std::int64_t e) {
        if (out && out->size() < 1000) out->push_back({k, std::move(msg), e});
    };
    // Directed edges: (a, b) -> face; detect duplicates (misorientation or non-manifold).
    std::unordered_map<std::uint64_t, int> directed;
    directed.reserve(faces.size() * 4);
    std::vector<char> referenced(num_vertices, 0);
    std::vector<int> parent(num_vertices);
    std::iota(parent.begin(), parent.end(), 0);
    for (std::size_t f = 0; f < faces.size(); ++f) {
        const auto& face = faces[f];
        for (std::size_t i = 0; i < face.size(); ++i) {
            const int a = face[i], b = face[(i + 1) % face.size()];
            referenced[a] = 1;
            parent[find(parent, a)] = find(parent, b);
            if (!directed.emplace(key(a, b), static_cast<int>(f)).second)
                violate(ViolationKind::InconsistentOrientation,
                        "edge (" + std::to_string(a) + ", " + std::to_string(b) + ") is traversed twice in the same direction",
                        static_cast<std::int64_t>(f));
        }
    }
    // Undirected edges and boundary half-edges.
    std::unordered_map<int, std::vector<int>> boundary_out; // vertex -> targets of boundary half-edges
    for (const auto& [k, f] : directed) {
        const int a = static_cast<int>(k >> 32), b = static_cast<int>(k & 0xffffffffu);
        if (directed.count(key(b, a))) {
            if (a < b) ++t.edges;
        } else {
            ++t.edges;
            boundary_out[a].push_back(b);
        }
    }
    // Non-manifold vertices: more than one boundary fan, or fans that do not cover all corners.
    std::vector<int> corners(num_vertices, 0);
    for (const auto& face : faces)
        for (int v : face) ++corners[v];
    for (const auto& [v, targets] : boundary_out)
        if (targets.size() > 1)
            violate(ViolationKind::NonManifoldVertex,
                    "vertex " + std::to_string(v) + " has " + std::to_string(targets.size()) + " boundary fans", v);
    {
        // Walk each vertex's fan: from corner (f, i) at v, cross the edge (v, next) to the face holding (next, v).
        std::vector<int> first_face(num_vertices, -1), first_pos(num_vertices, -1);
        std::unordered_map<std::uint64_t, std::pair<int, int>> incoming; // (prev, v) -> (face, position of v)
        incoming.reserve(directed.size());
        for (std::size_t f = 0; f < faces.size(); ++f)
            for (std::size_t i = 0; i < faces[f].size(); ++i) {
                const auto& face = faces[f];
                const int v = face[i], prev = face[(i + face.size() - 1) % face.size()];
                incoming[key(prev, v)] = {static_cast<int>(f), static_cast<int>(i)};
                if (first_face[v] < 0 || directed.count(key(v, prev)) == 0) { first_face[v] = static_cast<int>(f); first_pos[v] = static_cast<int>(i); }
            }
        for (std::size_t v = 0; v < num_vertices; ++v) {
            if (first_face[v] < 0) continue;
            int f = first_face[v], i = first_pos[v], seen = 0;
            do {
                ++seen;
                const auto& face = faces[f];
                const int next = face[(i + 1) % face.size()];
                const auto it = incoming.find(key(next, static_cast<int>(v)));
                if (it == incoming.end()) break;
                f = it->second.first;
                i = it->second.second;
            } while ((f != first_face[v] || i != first_pos[v]) && seen <= corners[v]);
            if (seen != corners[v])
                violate(ViolationKind::NonManifoldVertex,
                        "the faces around vertex " + std::to_string(v) + " do not form a single fan", static_cast<std::int64_t>(v));
        }
    }
    // Boundary loops: follow boundary half-edges.
    std::unordered_map<int, char> used;
    for (const auto& [v, targets] : boundary_out) {
        if (used[v]) continue;
        ++t.boundary_loops;
        int x = v;
        for (std::size_t guard = 0; guard <= boundary_out.size() && !used[x]; ++guard) {
            used[x] = 1;
            const auto it = boundary_out.find(x);
            if (it == boundary_out.end()) break;
            x = it->second.front();
        }
    }
    for (std::size_t v = 0; v < num_vertices; ++v) {
        if (!referenced[v]) continue;
        ++t.vertices;
        if (find(parent, static_cast<int>(v)) == static_cast<int>(v)) ++t.components;
    }
    t.faces = static_cast<std::int64_t>(faces.size());
    return t;
}

/// Twice the signed area of a polygon, exactly.
Rational twice_area(const std::vector<std::array<std::int64_t, 2>>& p) {
    Rational a = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const auto& x = p[i];
        const auto& y = p[(i + 1) % p.size()];
        a += Rational(static_cast<double>(x[0])) * Rational(static_cast<double>(y[1])) -
             Rational(static_cast<double>(x[1])) * Rational(static_cast<double>(y[0]));
    }
    return a;
}

bool unit_square_ccw(const std::vector<std::array<std::int64_t, 2>>& uv) {
    if (uv.size() != 4) return false;
    for (std::size_t i = 0; i < 4; ++i) {
        const auto& a = uv[i];
        const auto& b = uv[(i + 1) % 4];
        if (std::abs(a[0] - b[0]) + std::abs(a[1] - b[1]) != 1) return false;
    }
    return twice_area(uv) == Rational(2);
}

} // namespace

VerifyResult verify(const Input& input, const QuadMesh& mesh) {
    VerifyResult r;
    auto& out = r.violations;
    const std::size_t nv = mesh.positions.size();
    if (mesh.faces.empty()) out.push_back({ViolationKind::EmptyMesh, "the mesh has no faces", -1});
    bool indices_ok = true;
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
        const auto& face = mesh.faces[f];
        if (face.size() != 4 && out.size() < 1000)
            out.push_back({ViolationKind::NotQuad, "face " + std::to_string(f) + " has " + std::to_string(face.size()) + " vertices",
                           static_cast<std::int64_t>(f)});
        for (std::size_t i = 0; i < face.size(); ++i) {
            if (face[i] < 0 || static_cast<std::size_t>(face[i]) >= nv) {
                indices_ok = false;
                out.push_back({ViolationKind::BadIndex, "face " + std::to_string(f) + " refers to vertex " + std::to_string(face[i]),
                               static_cast<std::int64_t>(f)});
            }
            for (std::size_t j = i + 1; j < face.size(); ++j)
                if (face[i] == face[j] && out.size() < 1000)
                    out.push_back({ViolationKind::RepeatedVertex, "face " + std::to_string(f) + " uses vertex " + std::to_string(face[i]) + " twice",
                                   static_cast<std::int64_t>(f)});
        }
    }
    for (std::size_t v = 0; v < nv; ++v)
        for (double x : mesh.positions[v])
            if (!std::isfinite(x)) {
                out.push_back({ViolationKind::NonFinitePosition, "vertex " + std::to_string(v) + " has a non-finite position",
                               static_cast<std::int64_t>(v)});
                break;
            }
    if (mesh.face_uvs.size() == mesh.faces.size())
        for (std::size_t f = 0; f < mesh.faces.size(); ++f)
            if (mesh.faces[f].size() == 4 && !unit_square_ccw(mesh.face_uvs[f]) && out.size() < 1000)
                out.push_back({ViolationKind::LocalUvNotUnitSquare,
                               "the local UVs of face " + std::to_string(f) + " are not a counter-clockwise unit square",
                               static_cast<std::int64_t>(f)});
    if (indices_ok) {
        const Topology t = analyse(nv, mesh.faces, &out);
        r.faces = t.faces;
        r.vertices = t.vertices;
        r.edges = t.edges;
        r.boundary_loops = t.boundary_loops;
        r.components = t.components;
        r.euler = t.euler();
        if (static_cast<std::int64_t>(nv) != t.vertices)
            out.push_back({ViolationKind::UnreferencedVertex,
                           std::to_string(static_cast<std::int64_t>(nv) - t.vertices) + " vertices are used by no face", -1});
    }
    // The input's topology and exact signed UV area.
    bool input_ok = input.uvs.size() == 3 * input.triangles.size();
    std::vector<std::vector<int>> tris;
    tris.reserve(input.triangles.size());
    for (const auto& t : input.triangles) {
        for (int v : t) input_ok = input_ok && v >= 0 && static_cast<std::size_t>(v) < input.positions.size();
        tris.push_back({t[0], t[1], t[2]});
    }
    if (input_ok) {
        const Topology ti = analyse(input.positions.size(), tris, nullptr);
        r.input_euler = ti.euler();
        r.input_boundary_loops = ti.boundary_loops;
        r.input_components = ti.components;
        // Signed UV area: a double sum with a rigorous error bound decides the rounding; exact
        // rationals are used only when the bound does not.
        double approx = 0.0, bound = 0.0;
        bool finite = true;
        for (std::size_t f = 0; f < input.triangles.size(); ++f) {
            const auto &a = input.uvs[3 * f], &b = input.uvs[3 * f + 1], &c = input.uvs[3 * f + 2];
            const double t = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
            finite = finite && std::isfinite(t);
            approx += t;
            bound += std::abs(b[0] - a[0]) * std::abs(c[1] - a[1]) + std::abs(b[1] - a[1]) * std::abs(c[0] - a[0]) +
                     std::abs(approx);
        }
        bound *= 8 * std::numeric_limits<double>::epsilon();
        approx *= 0.5;
        bound *= 0.5;
        const double nearest = std::nearbyint(approx);
        if (finite && std::abs(approx - nearest) + bound < 0.5) {
            r.input_signed_uv_area_rounded = static_cast<std::int64_t>(nearest);
        } else if (finite) {
            Rational area = 0;
            for (std::size_t f = 0; f < input.triangles.size(); ++f) {
                const auto &a = input.uvs[3 * f], &b = input.uvs[3 * f + 1], &c = input.uvs[3 * f + 2];
                area += (Rational(b[0]) - Rational(a[0])) * (Rational(c[1]) - Rational(a[1])) -
                        (Rational(b[1]) - Rational(a[1])) * (Rational(c[0]) - Rational(a[0]));
            }
            area /= 2;
            approx = CGAL::to_double(area);
            // Round half away from zero, decided exactly.
            Rational lo = Rational(std::floor(approx));
            while (lo > area) lo -= 1;
            while (lo + 1 <= area) lo += 1;
            const Rational frac = area - lo;
            r.input_signed_uv_area_rounded = static_cast<std::int64_t>(CGAL::to_double(lo)) + (frac >= Rational(1, 2) ? 1 : 0);
        }
        r.input_signed_uv_area = std::to_string(approx);
        if (indices_ok && !mesh.faces.empty()) {
            if (r.euler != r.input_euler)
                out.push_back({ViolationKind::EulerMismatch,
                               "Euler characteristic " + std::to_string(r.euler) + ", input has " + std::to_string(r.input_euler), -1});
            if (r.boundary_loops != r.input_boundary_loops)
                out.push_back({ViolationKind::BoundaryMismatch,
                               std::to_string(r.boundary_loops) + " boundary loops, input has " + std::to_string(r.input_boundary_loops), -1});
            if (r.components != r.input_components)
                out.push_back({ViolationKind::ComponentMismatch,
                               std::to_string(r.components) + " components, input has " + std::to_string(r.input_components), -1});
        }
    }
    r.valid = out.empty();
    return r;
}

} // namespace qex

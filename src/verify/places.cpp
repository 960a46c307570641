// Where the violations are: every violation that names an element gets it as a place, and the
// violations of the whole mesh (boundary loops, components, Euler characteristic, coverage) get
// their candidates: each hole's boundary loop and the faces around it, each extra component's
// faces, the input components no vertex lies on, and for the Euler characteristic and the
// coverage the places of the local violations that change them. Only violations already found
// get places: nothing here decides a verdict.
#include "checker.h"
#include "union_find.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace qex::verify_detail {
namespace {

/// Candidates listed per violation at most (each a place).
constexpr std::size_t kMaxPlaces = 100;

using Index = std::int64_t;

/// The place that `element` names, by element_kind.
bool element_place(const Violation& v, Place& p) {
    if (v.element < 0) return false;
    switch (element_kind(v.kind)) {
        case ViolationElement::OutputFace: p.kind = PlaceKind::Face; break;
        case ViolationElement::OutputVertex: p.kind = PlaceKind::Vertex; break;
        case ViolationElement::InputVertex: p.kind = PlaceKind::InputVertex; break;
        case ViolationElement::InputTriangle: p.kind = PlaceKind::InputTriangle; break;
        case ViolationElement::None: return false;
    }
    p.indices = {v.element};
    return true;
}

/// The mesh's components as lists of faces, smallest first (ties: by first face).
std::vector<std::vector<Index>> components_by_size(const QuadMesh& mesh) {
    UnionFind uf(mesh.positions.size());
    for (const auto& face : mesh.faces)
        for (std::size_t i = 1; i < face.size(); ++i) uf.unite(face[i], face[0]);
    std::vector<Index> slot(mesh.positions.size(), -1);
    std::vector<std::vector<Index>> comps;
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
        if (mesh.faces[f].empty()) continue;
        const auto root = static_cast<std::size_t>(uf.find(mesh.faces[f][0]));
        if (slot[root] < 0) slot[root] = static_cast<Index>(comps.size()), comps.emplace_back();
        comps[static_cast<std::size_t>(slot[root])].push_back(static_cast<Index>(f));
    }
    std::stable_sort(comps.begin(), comps.end(), [](const auto& a, const auto& b) { return a.size() < b.size(); });
    return comps;
}

/// Located mode: the input triangle of the closest surface point of the violation's output vertex,
/// or of its output face's first corner that has one; -1 otherwise.
Index closest_triangle(const QuadMesh& mesh, const PlaceContext& ctx, const Violation& v) {
    const auto n = static_cast<Index>(ctx.closest_triangle.size());
    if (v.element < 0 || n == 0) return -1;
    if (element_kind(v.kind) == ViolationElement::OutputVertex)
        return v.element < n ? ctx.closest_triangle[static_cast<std::size_t>(v.element)] : -1;
    if (element_kind(v.kind) != ViolationElement::OutputFace || v.element >= static_cast<Index>(mesh.faces.size()))
        return -1;
    for (const int x : mesh.faces[static_cast<std::size_t>(v.element)])
        if (x >= 0 && x < n && ctx.closest_triangle[static_cast<std::size_t>(x)] >= 0)
            return ctx.closest_triangle[static_cast<std::size_t>(x)];
    return -1;
}

void add_place(Violation& v, PlaceKind kind, std::vector<Index> indices) {
    if (v.places.size() < kMaxPlaces && !indices.empty()) v.places.push_back({kind, std::move(indices)});
}

std::string list(const std::vector<Index>& xs, std::size_t most = 12) {
    std::string s;
    for (std::size_t i = 0; i < xs.size() && i < most; ++i) s += (i ? " " : "") + std::to_string(xs[i]);
    if (xs.size() > most) s += " ...";
    return s;
}

/// The candidates of the whole mesh's violations: the holes (the mesh's boundary loops that
/// leave the input's boundary), the components beyond the input's count, the input components no
/// vertex lies on, and the places of the local violations that change the Euler characteristic
/// or the coverage.
struct Candidates {
    Boundary b;
    std::vector<std::size_t> holes; ///< indices into b's loops
    std::vector<std::vector<Index>> extra;
    std::vector<Index> missing;
    std::vector<Place> local;
};

/// Gives every violation (and undecided check) the place its element names, and in located
/// mode, for an output vertex or face, the input triangle where it lies.
void place_elements(const QuadMesh& mesh, const PlaceContext& ctx, VerifyResult& r) {
    for (auto* list_of : {&r.violations, &r.undecided})
        for (Violation& v : *list_of) {
            Place p;
            if (v.places.empty() && element_place(v, p)) v.places.push_back(std::move(p));
            // Where on the input a located vertex or face lies: the closest surface point's triangle.
            const std::int64_t t = closest_triangle(mesh, ctx, v);
            if (t >= 0) v.places.push_back({PlaceKind::InputTriangle, {t}});
        }
}

/// Holes: the mesh's boundary loops that do not run along the input's boundary (find_holes);
/// all of them when every loop runs along it, yet they are too many or too few.
std::vector<std::size_t> hole_loops(const Input& in, const QuadMesh& mesh, const PlaceContext& ctx, const Boundary& b) {
    std::vector<std::size_t> holes = find_holes(in, mesh, b, ctx.boundary_tolerance);
    if (holes.empty())
        for (std::size_t l = 0; l < b.loops.size(); ++l) holes.push_back(l);
    return holes;
}

/// The places of the local violations that change the Euler characteristic or the coverage.
std::vector<Place> local_places(const std::vector<Violation>& out) {
    std::vector<Place> local;
    for (const Violation& v : out)
        if (v.kind == ViolationKind::NonManifoldEdge || v.kind == ViolationKind::NonManifoldVertex ||
            v.kind == ViolationKind::InconsistentOrientation || v.kind == ViolationKind::NotQuad ||
            v.kind == ViolationKind::FaceNotGridCell || v.kind == ViolationKind::RepeatedVertex)
            for (const Place& p : v.places)
                if (local.size() < kMaxPlaces) local.push_back(p);
    return local;
}

/// Located mode: where on the input a hole lies (its loop's vertices' closest triangles).
std::vector<Index> hole_triangles(const PlaceContext& ctx, const std::vector<Index>& loop) {
    std::vector<Index> t;
    for (const Index x : loop)
        if (x < static_cast<Index>(ctx.closest_triangle.size()) &&
            ctx.closest_triangle[static_cast<std::size_t>(x)] >= 0 &&
            std::find(t.begin(), t.end(), ctx.closest_triangle[static_cast<std::size_t>(x)]) == t.end())
            t.push_back(ctx.closest_triangle[static_cast<std::size_t>(x)]);
    return t;
}

/// Adds the holes to v: each one's loop, its faces and where it lies on the input.
void add_holes(Violation& v, const Candidates& c, const PlaceContext& ctx) {
    for (const std::size_t l : c.holes) {
        add_place(v, PlaceKind::Loop, c.b.loops[l]);
        add_place(v, PlaceKind::Face, c.b.faces[l]);
        add_place(v, PlaceKind::InputTriangle, hole_triangles(ctx, c.b.loops[l]));
    }
}

/// Adds the extra components' faces to v, and the input components no vertex lies on.
void add_components(Violation& v, const Candidates& c) {
    for (const auto& faces : c.extra) add_place(v, PlaceKind::Face, faces);
    if (!c.missing.empty()) add_place(v, PlaceKind::InputTriangle, c.missing);
}

/// Gives a violation of the whole mesh its candidates, and says in its message what they are.
void place_global(Violation& v, const Candidates& c, const PlaceContext& ctx) {
    std::string found;
    switch (v.kind) {
        case ViolationKind::BoundaryMismatch:
            add_holes(v, c, ctx);
            if (!c.holes.empty()) found = std::to_string(c.holes.size()) + " off the input's boundary";
            break;
        case ViolationKind::ComponentMismatch:
            add_components(v, c);
            if (!c.extra.empty())
                found = "extra: " + std::to_string(c.extra.size()) + " of " + std::to_string(c.extra.front().size()) +
                        " faces or more";
            if (!c.missing.empty())
                found += (found.empty() ? "" : "; ") + std::string("input components with no vertex at triangles ") +
                         list(c.missing);
            break;
        case ViolationKind::EulerMismatch:
        case ViolationKind::CoverageMismatch:
            add_holes(v, c, ctx);
            add_components(v, c);
            for (const Place& p : c.local) add_place(v, p.kind, p.indices);
            if (!v.places.empty()) found = std::to_string(v.places.size()) + " candidate places";
            break;
        default: break;
    }
    if (v.kind == ViolationKind::BoundaryMismatch && !c.holes.empty())
        found += ": the first through vertices " + list(c.b.loops[c.holes.front()]);
    if (!found.empty()) v.message += " (" + found + ")";
}

} // namespace

void place_violations(const Input& in, const QuadMesh& mesh, const PlaceContext& ctx, VerifyResult& r) {
    auto& out = r.violations;
    place_elements(mesh, ctx, r);
    bool boundary = false, components = false, global = false;
    for (const Violation& v : out) {
        boundary = boundary || v.kind == ViolationKind::BoundaryMismatch || v.kind == ViolationKind::EulerMismatch ||
                   v.kind == ViolationKind::CoverageMismatch;
        components = components || v.kind == ViolationKind::ComponentMismatch || v.kind == ViolationKind::EulerMismatch;
        global = global || element_kind(v.kind) == ViolationElement::None;
    }
    if (!global || !ctx.indices_ok) return;
    Candidates c;
    if (boundary) {
        c.b = boundary_loops(mesh);
        c.holes = hole_loops(in, mesh, ctx, c.b);
    }
    // Components beyond the input's count, smallest first; input components no vertex lies on.
    if (components) {
        auto comps = components_by_size(mesh);
        const auto surplus = static_cast<Index>(comps.size()) - r.input_components;
        for (Index k = 0; k < surplus; ++k) c.extra.push_back(std::move(comps[static_cast<std::size_t>(k)]));
        if (!ctx.located_triangle.empty()) c.missing = empty_input_components(in, ctx.located_triangle);
    }
    c.local = local_places(out);
    for (Violation& v : out) place_global(v, c, ctx);
}

} // namespace qex::verify_detail

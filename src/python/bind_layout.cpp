// The layout room of the binding: the quad layout (qex/layout.h) of an extracted mesh, or of
// any quad mesh given as arrays.
#include "bindings.h"
#include "convert.h"

#include "qex/layout.h"

#include <cstdint>
#include <vector>

namespace qex_python {
namespace {

/// The quad layout (qex/layout.h) as numpy arrays: "face_patch" (F,), "patch_sizes" (P, 2) u and v,
/// "patch_corners" (P, 4), "separatrices" a list of vertex index arrays, "separatrix_ends" their
/// SeparatrixEnd names, "adjacency" (A, 3) patch a, patch b, shared edges, "special_vertices";
/// "valid" and "error" (the independent check's reason when it rejects the layout), "notes".
py::dict layout_of(const qex::QuadMesh& mesh) {
    qex::Layout l;
    {
        py::gil_scoped_release unlocked;
        l = qex::extract_layout(mesh);
    }
    const auto ints = [](const std::vector<int>& v) {
        return py::array_t<std::int64_t>(v.size(), std::vector<std::int64_t>(v.begin(), v.end()).data());
    };
    py::array_t<std::int64_t> sizes({l.patches.size(), std::size_t{2}}), corners({l.patches.size(), std::size_t{4}});
    py::array_t<std::int64_t> adjacency({l.adjacency.size(), std::size_t{3}});
    for (std::size_t p = 0; p < l.patches.size(); ++p) {
        sizes.mutable_at(p, 0) = l.patches[p].u, sizes.mutable_at(p, 1) = l.patches[p].v;
        for (int k = 0; k < 4; ++k) corners.mutable_at(p, k) = l.patches[p].corners[k];
    }
    for (std::size_t i = 0; i < l.adjacency.size(); ++i)
        adjacency.mutable_at(i, 0) = l.adjacency[i].a, adjacency.mutable_at(i, 1) = l.adjacency[i].b,
                                adjacency.mutable_at(i, 2) = l.adjacency[i].shared_edges;
    py::list separatrices, ends;
    for (const qex::Separatrix& x : l.separatrices) {
        separatrices.append(ints(x.vertices));
        ends.append(qex::to_string(x.end));
    }
    py::dict d;
    d["valid"] = l.valid, d["error"] = l.error, d["face_patch"] = ints(l.face_patch), d["patch_sizes"] = sizes;
    d["patch_corners"] = corners, d["separatrices"] = separatrices, d["separatrix_ends"] = ends;
    d["adjacency"] = adjacency, d["special_vertices"] = ints(l.special_vertices), d["notes"] = l.notes;
    return d;
}

constexpr const char* kLayoutDoc = R"doc(The quad layout of an extracted mesh (qex/layout.h), as a dict of numpy arrays:
"face_patch" (F,), "patch_sizes" (P, 2), "patch_corners" (P, 4), "separatrices" (a list of vertex index
arrays), "separatrix_ends", "adjacency" (A, 3: patch a, patch b, shared edges), "special_vertices",
"valid", "error" (why the independent check rejects it), "notes".)doc";

} // namespace

void bind_layout(py::module_& m) {
    m.def("layout", &layout_of, kLayoutDoc, py::arg("mesh"));
    m.def(
        "layout_of_arrays", [](const Doubles& QV, const py::object& QF) { return layout_of(to_mesh(QV, QF)); },
        R"doc(The quad layout of the quad mesh (QV (n, 3) positions, QF (k, 4) faces), as `layout` gives it.)doc",
        py::arg("QV"), py::arg("QF"));
}

} // namespace qex_python

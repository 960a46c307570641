// The extraction room of the binding: QuadMesh, and extract() with its options and the arrays
// of its result. The GIL is released while the library extracts.
#include "bindings.h"
#include "convert.h"

#include "qex/report.h"

#include <chrono>
#include <cstdint>
#include <string>
#include <utility>

namespace qex_python {
namespace {

/// An integer option: a Python int (or numpy integer), not a float (a cast_error: TypeError, as
/// for any other wrong type); one beyond 64 bits is a ValueError.
std::int64_t int64_option(const std::string& k, const py::handle& value) {
    if (PyFloat_Check(value.ptr()) || !PyIndex_Check(value.ptr())) throw py::cast_error();
    const auto i = py::reinterpret_steal<py::object>(PyNumber_Index(value.ptr()));
    if (!i) throw py::error_already_set();
    int overflow = 0;
    const long long x = PyLong_AsLongLongAndOverflow(i.ptr(), &overflow);
    if (overflow != 0)
        throw py::value_error("extract(): option '" + k + "' = " + std::string(py::str(value)) +
                              " does not fit in 64 bits");
    if (x == -1 && PyErr_Occurred()) throw py::error_already_set();
    return x;
}

void set_option(qex::Options& o, const std::string& k, const py::handle& value) {
    if (k == "max_qvertices")
        o.max_qvertices = int64_option(k, value);
    else if (k == "max_trace_steps")
        o.max_trace_steps = int64_option(k, value);
    else if (k == "recover_lost_edges")
        o.recover_lost_edges = value.cast<bool>();
    else if (k == "merge_vertices")
        o.merge_vertices = value.cast<bool>();
    else if (k == "canonical_order")
        o.canonical_order = value.cast<bool>();
    else if (k == "snap_boundary")
        o.snap_boundary = value.cast<bool>();
    else if (k == "repair_fold_overs")
        o.repair_fold_overs = value.cast<bool>();
    else if (k == "fallback_ladder")
        o.fallback_ladder = value.cast<bool>();
    else if (k == "best_effort")
        o.best_effort = value.cast<bool>();
    else if (k == "fill_holes")
        o.fill_holes = value.cast<bool>();
    else
        throw py::type_error("extract() got an unexpected option '" + k + "'");
}

void set_options(qex::Options& o, const py::dict& options) {
    for (const auto& [key, value] : options) {
        const std::string k = py::str(key);
        try {
            set_option(o, k, value);
        } catch (const py::cast_error&) {
            throw py::type_error("extract(): option '" + k + "' cannot be a " +
                                 py::str(py::type::handle_of(value).attr("__name__")).cast<std::string>());
        }
    }
}

/// The mesh's arrays: its quads (k,4), positions (p,3) and face UVs (k,4,2); faces other than
/// quads are left out.
py::dict mesh_arrays(const qex::QuadMesh& m) {
    py::ssize_t quads = 0;
    for (const auto& face : m.faces) quads += face.size() == 4 ? 1 : 0;
    py::array_t<std::int32_t> Q({quads, py::ssize_t{4}});
    py::array_t<std::int64_t> FUV({quads, py::ssize_t{4}, py::ssize_t{2}});
    py::array_t<double> P({static_cast<py::ssize_t>(m.positions.size()), py::ssize_t{3}});
    {
        auto q = Q.mutable_unchecked<2>();
        auto fuv = FUV.mutable_unchecked<3>();
        py::ssize_t row = 0;
        for (std::size_t f = 0; f < m.faces.size(); ++f) {
            if (m.faces[f].size() != 4) continue; // only in a mesh the checker rejected
            const bool uvs = f < m.face_uvs.size() && m.face_uvs[f].size() == 4;
            for (py::ssize_t k = 0; k < 4; ++k) {
                q(row, k) = m.faces[f][k];
                fuv(row, k, 0) = uvs ? m.face_uvs[f][k][0] : 0;
                fuv(row, k, 1) = uvs ? m.face_uvs[f][k][1] : 0;
            }
            ++row;
        }
        auto p = P.mutable_unchecked<2>();
        for (std::size_t i = 0; i < m.positions.size(); ++i)
            for (py::ssize_t c = 0; c < 3; ++c) p(i, c) = m.positions[i][c];
    }
    py::dict out;
    out["quads"] = Q;
    out["positions"] = P;
    out["face_uvs"] = FUV;
    return out;
}

/// The provenance of every output vertex, one array per field.
py::dict provenance_arrays(const qex::QuadMesh& m) {
    const auto n = static_cast<py::ssize_t>(m.provenance.size());
    py::array_t<std::int8_t> kind(n);
    py::array_t<std::int32_t> element(n), local_edge(n), chart(n), merged(n);
    py::array_t<double> bary({n, py::ssize_t{3}});
    py::array_t<std::int64_t> grid({n, py::ssize_t{2}});
    {
        auto k = kind.mutable_unchecked<1>();
        auto e = element.mutable_unchecked<1>();
        auto le = local_edge.mutable_unchecked<1>();
        auto c = chart.mutable_unchecked<1>();
        auto mg = merged.mutable_unchecked<1>();
        auto b = bary.mutable_unchecked<2>();
        auto g = grid.mutable_unchecked<2>();
        for (py::ssize_t i = 0; i < n; ++i) {
            const qex::Provenance& pv = m.provenance[i];
            k(i) = static_cast<std::int8_t>(pv.kind);
            e(i) = pv.element;
            le(i) = pv.local_edge;
            c(i) = pv.chart_triangle;
            mg(i) = pv.merged;
            for (py::ssize_t j = 0; j < 3; ++j) b(i, j) = pv.barycentric[j];
            for (py::ssize_t j = 0; j < 2; ++j) g(i, j) = pv.grid[j];
        }
    }
    py::dict provenance;
    provenance["kind"] = kind;
    provenance["element"] = element;
    provenance["local_edge"] = local_edge;
    provenance["barycentric"] = bary;
    provenance["grid"] = grid;
    provenance["chart_triangle"] = chart;
    provenance["merged"] = merged;
    return provenance;
}

/// What extract() returns to the Python side: the mesh (kept for verify and write_obj) and the
/// arrays and report made of it.
py::dict extract(const Doubles& V, const py::object& F, const Doubles& UV, const py::object& valences,
                 const py::object& feature_edges, int threads, const py::dict& options) {
    qex::Input in = to_input(V, F, UV, valences, feature_edges);
    qex::Options o;
    o.threads = threads;
    set_options(o, options);
    qex::Result r;
    std::string report;
    {
        py::gil_scoped_release unlocked;
        const auto t0 = std::chrono::steady_clock::now();
        r = qex::extract(in, o);
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (r.ok()) report = qex::report_json(r, 0.0, seconds);
    }
    if (!r.ok()) reject(r.error);
    py::dict out = mesh_arrays(r.mesh);
    out["provenance"] = provenance_arrays(r.mesh);
    out["valid"] = r.check.valid;
    out["report_json"] = report;
    out["mesh"] = py::cast(std::move(r.mesh));
    return out;
}

constexpr const char* kExtractDoc = R"doc(Extract the quad mesh of a map (the core of `qex.extract`).

Parameters
----------
V : ndarray of float64, shape (n, 3)
    Vertex positions.
F : ndarray of int64, shape (m, 3)
    Triangles, indices into `V`.
UV : ndarray of float64, shape (3m, 2)
    The UV of each triangle corner, ``UV[3f + k]`` for corner k of triangle f.
valences : ndarray of int64, shape (n,), or None
    The valence per vertex, or None to count them from the map.
feature_edges : ndarray of int64, shape (e, 2), or None
    Vertex pairs of the feature edges.
threads : int
    Threads of the parallel loops (0: every core).
options : dict
    Fields of ``qex::Options`` by name (``max_qvertices``, ``snap_boundary``, ...).

Returns
-------
dict
    ``quads``, ``positions``, ``face_uvs``, ``provenance`` (a dict of arrays), ``valid``,
    ``report_json`` (the report as JSON text) and ``mesh`` (a `QuadMesh`).

Raises
------
ValueError
    Arrays of the wrong shape or dtype, or input the library rejects.
TypeError
    An unknown option, or an option of the wrong type.
)doc";

} // namespace

// QuadMesh comes first: the signatures of the other rooms name it.
void bind_extraction(py::module_& m) {
    py::class_<qex::QuadMesh>(m, "QuadMesh", "The extracted mesh as the library holds it (for verify and write_obj).")
        .def_property_readonly(
            "num_faces", [](const qex::QuadMesh& q) { return q.faces.size(); }, "The number of faces.")
        .def_property_readonly(
            "num_vertices", [](const qex::QuadMesh& q) { return q.positions.size(); }, "The number of vertices.");
    m.def("extract", &extract, kExtractDoc, py::arg("V"), py::arg("F"), py::arg("UV"), py::arg("valences"),
          py::arg("feature_edges"), py::arg("threads"), py::arg("options"));
}

} // namespace qex_python

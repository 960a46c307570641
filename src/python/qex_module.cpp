// The compiled half of the Python package qex (qex._qex): numpy arrays in and out of qex::extract,
// qex::verify and the OBJ files. The Python half (qex/__init__.py) checks dtypes and shapes and
// holds the docstrings; this side checks them again, so that no call from Python can crash the
// interpreter, and releases the GIL while the library works.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "qex/check.h"
#include "qex/layout.h"
#include "qex/qex.h"
#include "qex/report.h"

#include "io/checked_int.h"

#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>

namespace py = pybind11;

namespace {

using Doubles = py::array_t<double, py::array::c_style | py::array::forcecast>;
using Int64s = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>;

// An array's shape must be (rows, cols) (rows any); raises ValueError naming `what` otherwise.
void expect_shape(const py::array& a, py::ssize_t cols, const char* what) {
    if (a.ndim() != 2 || a.shape(1) != cols)
        throw py::value_error(std::string(what) + " must have shape (n, " + std::to_string(cols) + ")");
}

int to_index(std::int64_t x, const char* what) {
    int i = 0;
    if (!qex::io_detail::checked_int(x, i))
        throw py::value_error(std::string(what) + ": " + std::to_string(x) + " does not fit in 32 bits");
    return i;
}

/// `obj` as an int64 array, for indices: an array of integers (or bools), as the Python half
/// requires. Not forcecast from anything else: a float array would be truncated, and its NaN,
/// infinities and values past 2^63 have no int64 at all; a uint64 past 2^63 would wrap.
Int64s integer_array(const py::handle& obj, const char* what) {
    const py::array a = py::array::ensure(obj);
    if (!a) throw py::value_error(std::string(what) + " must be an array of integers");
    const char kind = a.dtype().kind();
    if (a.size() > 0 && kind != 'b' && kind != 'i' && kind != 'u')
        throw py::value_error(std::string(what) + " must hold integers, not " + std::string(py::str(a.dtype())));
    if (kind == 'u' && a.itemsize() == 8) {
        const py::array_t<std::uint64_t, py::array::c_style | py::array::forcecast> u(a);
        const std::uint64_t* x = u.data();
        for (py::ssize_t i = 0; i < u.size(); ++i)
            if (std::int64_t fits = 0; !qex::io_detail::checked_int(x[i], fits))
                throw py::value_error(std::string(what) + ": index " + std::to_string(x[i]) + " is out of range");
    }
    Int64s out = Int64s::ensure(a);
    if (!out) throw py::value_error(std::string(what) + " must be an array of integers");
    return out;
}

/// The Input of arrays V (n,3), F (m,3) and UV (3m,2), valences (n,) or None, feature edges (e,2) or None.
qex::Input to_input(const Doubles& V, const py::object& F_in, const Doubles& UV, const py::object& valences,
                    const py::object& feature_edges) {
    const Int64s F = integer_array(F_in, "F");
    expect_shape(V, 3, "V");
    expect_shape(F, 3, "F");
    expect_shape(UV, 2, "UV");
    if (UV.shape(0) != 3 * F.shape(0))
        throw py::value_error("UV must hold 3 UVs per triangle: " + std::to_string(UV.shape(0)) + " for " +
                              std::to_string(F.shape(0)) + " triangles");
    qex::Input in;
    auto v = V.unchecked<2>();
    auto f = F.unchecked<2>();
    auto uv = UV.unchecked<2>();
    in.positions.resize(static_cast<std::size_t>(V.shape(0)));
    for (py::ssize_t i = 0; i < V.shape(0); ++i) in.positions[i] = {v(i, 0), v(i, 1), v(i, 2)};
    in.triangles.resize(static_cast<std::size_t>(F.shape(0)));
    for (py::ssize_t i = 0; i < F.shape(0); ++i)
        for (py::ssize_t k = 0; k < 3; ++k) in.triangles[i][k] = to_index(f(i, k), "F");
    in.uvs.resize(static_cast<std::size_t>(UV.shape(0)));
    for (py::ssize_t i = 0; i < UV.shape(0); ++i) in.uvs[i] = {uv(i, 0), uv(i, 1)};
    if (!valences.is_none()) {
        const Int64s a = integer_array(valences, "valences");
        if (a.ndim() != 1) throw py::value_error("valences must have shape (n,)");
        auto x = a.unchecked<1>();
        for (py::ssize_t i = 0; i < a.shape(0); ++i) in.valences.push_back(to_index(x(i), "valences"));
    }
    if (!feature_edges.is_none()) {
        const Int64s a = integer_array(feature_edges, "feature_edges");
        expect_shape(a, 2, "feature_edges");
        auto x = a.unchecked<2>();
        for (py::ssize_t i = 0; i < a.shape(0); ++i)
            in.feature_edges.push_back({to_index(x(i, 0), "feature_edges"), to_index(x(i, 1), "feature_edges")});
    }
    return in;
}

/// The mesh of arrays QV (p,3) and QF (k,c): one face per row.
qex::QuadMesh to_mesh(const Doubles& QV, const py::object& QF_in) {
    const Int64s QF = integer_array(QF_in, "QF");
    expect_shape(QV, 3, "QV");
    if (QF.ndim() != 2) throw py::value_error("QF must have shape (k, 4)");
    qex::QuadMesh m;
    auto v = QV.unchecked<2>();
    auto f = QF.unchecked<2>();
    for (py::ssize_t i = 0; i < QV.shape(0); ++i) m.positions.push_back({v(i, 0), v(i, 1), v(i, 2)});
    m.faces.resize(static_cast<std::size_t>(QF.shape(0)));
    for (py::ssize_t i = 0; i < QF.shape(0); ++i)
        for (py::ssize_t k = 0; k < QF.shape(1); ++k) m.faces[i].push_back(to_index(f(i, k), "QF"));
    return m;
}

[[noreturn]] void reject(const qex::Error& e) {
    throw py::value_error(std::string(qex::to_string(e.code)) + ": " + e.message);
}

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

std::string verify(const Doubles& V, const py::object& F, const Doubles& UV, const qex::QuadMesh& mesh, int threads) {
    const qex::Input in = to_input(V, F, UV, py::none(), py::none());
    py::gil_scoped_release unlocked;
    qex::VerifyOptions o;
    o.threads = threads;
    return qex::verify_json(qex::verify(in, mesh, o));
}

[[noreturn]] void raise(const std::string& path, const qex::IoError& e);

std::string check(const Doubles& V, const py::object& F, const Doubles& UV, const Doubles& QV, const py::object& QF,
                  double uv_tolerance, double distance_tolerance, bool locate, int digits, int grid_scale,
                  bool fold_regions, int threads, const std::string& certificate_path) {
    // As the Python half: finite tolerances, the UV one at most a cell (the checker's search
    // for the cells about a triangle grows with it); digits and grid scale as `qex check` takes them.
    if (!(uv_tolerance >= 0 && uv_tolerance <= 1))
        throw py::value_error("uv_tolerance must be a finite number from 0 to 1");
    if (!(distance_tolerance >= 0 && std::isfinite(distance_tolerance)))
        throw py::value_error("distance_tolerance must be a finite number from 0");
    if (digits < 0 || digits > 17) throw py::value_error("digits must be an integer from 0 to 17");
    if (grid_scale < 1 || grid_scale > 64 || (grid_scale & (grid_scale - 1)) != 0)
        throw py::value_error("grid_scale must be 1, 2, 4, 8, 16, 32 or 64");
    if (!certificate_path.empty() && grid_scale != 1)
        throw py::value_error("grid_scale and certificate exclude each other: the certificate carries its grid scale");
    const qex::Input in = to_input(V, F, UV, py::none(), py::none());
    const qex::QuadMesh mesh = to_mesh(QV, QF);
    qex::Certificate certificate;
    if (!certificate_path.empty()) {
        qex::IoError e;
        {
            py::gil_scoped_release unlocked;
            e = qex::read_certificate(certificate_path, certificate);
        }
        if (!e.ok()) raise(certificate_path, e);
    }
    qex::MeshCheck c;
    qex::MeshQuality quality;
    {
        py::gil_scoped_release unlocked;
        // The oracle's one entry (qex/check.h), as `qex check` and the C API judge.
        qex::VerifyOptions o;
        o.uv_tolerance = uv_tolerance;
        o.distance_tolerance = distance_tolerance;
        o.locate = locate;
        o.position_digits = digits;
        o.fold_regions = fold_regions;
        o.threads = threads;
        c = certificate_path.empty() ? qex::check_mesh(in, mesh, grid_scale, o)
                                     : qex::check_mesh(in, mesh, certificate, o);
        if (c.map_ok()) quality = qex::mesh_quality(in, mesh);
    }
    if (!c.map_ok()) reject(c.error);
    return qex::verify_json(c.verdict, quality);
}

[[noreturn]] void raise(const std::string& path, const qex::IoError& e) {
    const std::string message = path + ": " + e.message;
    if (e.code == qex::IoError::Code::CannotOpen || e.code == qex::IoError::Code::CannotWrite) {
        PyErr_SetString(PyExc_OSError, message.c_str());
        throw py::error_already_set();
    }
    throw py::value_error(message);
}

py::array_t<std::int32_t> read_vval(const std::string& path) {
    std::vector<int> valences;
    qex::IoError e;
    {
        py::gil_scoped_release unlocked;
        e = qex::read_vval(path, valences);
    }
    if (!e.ok()) raise(path, e);
    py::array_t<std::int32_t> out(static_cast<py::ssize_t>(valences.size()));
    auto o = out.mutable_unchecked<1>();
    for (py::ssize_t i = 0; i < out.shape(0); ++i) o(i) = valences[static_cast<std::size_t>(i)];
    return out;
}

py::tuple read_obj(const std::string& path, int threads) {
    qex::Input in;
    qex::IoError e;
    {
        py::gil_scoped_release unlocked;
        e = qex::read_obj(path, in, threads);
    }
    if (!e.ok()) raise(path, e);
    const auto nv = static_cast<py::ssize_t>(in.positions.size());
    const auto nf = static_cast<py::ssize_t>(in.triangles.size());
    py::array_t<double> V({nv, py::ssize_t{3}});
    py::array_t<std::int32_t> F({nf, py::ssize_t{3}});
    py::array_t<double> UV({nf, py::ssize_t{3}, py::ssize_t{2}});
    auto v = V.mutable_unchecked<2>();
    auto f = F.mutable_unchecked<2>();
    auto uv = UV.mutable_unchecked<3>();
    for (py::ssize_t i = 0; i < nv; ++i)
        for (py::ssize_t c = 0; c < 3; ++c) v(i, c) = in.positions[i][c];
    for (py::ssize_t i = 0; i < nf; ++i)
        for (py::ssize_t k = 0; k < 3; ++k) {
            f(i, k) = in.triangles[i][k];
            uv(i, k, 0) = in.uvs[3 * i + k][0];
            uv(i, k, 1) = in.uvs[3 * i + k][1];
        }
    return py::make_tuple(V, F, UV);
}

void write_certificate(const Doubles& V, const py::object& F, const Doubles& UV, const qex::QuadMesh& mesh,
                       const std::string& path) {
    const qex::Input in = to_input(V, F, UV, py::none(), py::none());
    if (mesh.map_uvs.size() != in.uvs.size())
        throw py::value_error("the mesh carries no map of these arrays' triangles (extract it from V, F, UV)");
    qex::IoError e;
    {
        py::gil_scoped_release unlocked;
        e = qex::write_certificate(path, qex::make_certificate(in, mesh));
    }
    if (!e.ok()) raise(path, e);
}

void write_obj(const std::string& path, const qex::QuadMesh& mesh) {
    qex::IoError e;
    {
        py::gil_scoped_release unlocked;
        e = qex::write_obj(path, mesh);
    }
    if (!e.ok()) raise(path, e);
}

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

} // namespace

PYBIND11_MODULE(_qex, m) {
    m.doc() =
        "The compiled core of the qex package; use the functions of `qex` itself, which check the "
        "arguments and document them (qex/_qex.pyi holds this module's types).";
    py::class_<qex::QuadMesh>(m, "QuadMesh", "The extracted mesh as the library holds it (for verify and write_obj).")
        .def_property_readonly(
            "num_faces", [](const qex::QuadMesh& q) { return q.faces.size(); }, "The number of faces.")
        .def_property_readonly(
            "num_vertices", [](const qex::QuadMesh& q) { return q.positions.size(); }, "The number of vertices.");
    m.def("extract", &extract, R"doc(Extract the quad mesh of a map (the core of `qex.extract`).

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
)doc",
          py::arg("V"), py::arg("F"), py::arg("UV"), py::arg("valences"), py::arg("feature_edges"), py::arg("threads"),
          py::arg("options"));
    m.def("verify", &verify, R"doc(Judge an extracted mesh against its map (the core of `qex.verify`).

Parameters
----------
V, F, UV : ndarray
    The map, as for `extract`.
mesh : QuadMesh
    The ``mesh`` that `extract` returned.
threads : int
    Threads of the checker (0: every core).

Returns
-------
str
    The verdict as JSON text (``qex check --json``).
)doc",
          py::arg("V"), py::arg("F"), py::arg("UV"), py::arg("mesh"), py::arg("threads"));
    m.def("check", &check, R"doc(Judge any quad mesh against a map (the core of `qex.check`).

Parameters
----------
V, F, UV : ndarray
    The map, as for `extract`.
QV : ndarray of float64, shape (p, 3)
    The mesh's vertices.
QF : ndarray of int64, shape (k, c)
    Its faces, indices into `QV`.
uv_tolerance : float
    Largest UV distance of a vertex to its grid point, from 0 to 1.
distance_tolerance : float
    Largest distance of a vertex to the surface, a fraction of the bounding-box diagonal.
locate : bool
    Locate the vertices on the map (False: the topology only).
digits : int
    The positions may be rounded to this many significant digits (0: exact doubles).
grid_scale : int
    Judge against the map's UVs times this power of two (1 to 64).
fold_regions : bool
    Judge vertices in the map's fold-over regions on the surface only.
threads : int
    Threads of the checker (0: every core).
certificate : str
    A certificate file (`write_certificate`, ``qex extract --certificate``) to judge the mesh on;
    "" for none.

Returns
-------
str
    The verdict as JSON text (``qex check --json``).

Raises
------
ValueError
    Arrays of the wrong shape or dtype, a tolerance out of range, a map the library rejects, a
    malformed certificate, or a certificate with a grid scale other than 1.
OSError
    The certificate cannot be read.
)doc",
          py::arg("V"), py::arg("F"), py::arg("UV"), py::arg("QV"), py::arg("QF"), py::arg("uv_tolerance"),
          py::arg("distance_tolerance"), py::arg("locate"), py::arg("digits"), py::arg("grid_scale"),
          py::arg("fold_regions"), py::arg("threads"), py::arg("certificate"));
    m.def("read_obj", &read_obj, R"doc(Read an OBJ map (the core of `qex.read_obj`).

Parameters
----------
path : str
    The OBJ file.
threads : int
    Threads of the reader (0: every core).

Returns
-------
tuple of ndarray
    ``V`` (n, 3) float64, ``F`` (m, 3) int32 and ``UV`` (m, 3, 2) float64.

Raises
------
OSError
    The file cannot be read.
ValueError
    A malformed file (the message names the line).
)doc",
          py::arg("path"), py::arg("threads"));
    m.def("read_vval", &read_vval, R"doc(Read a VVAL file of valences (the core of `qex.read_vval`).

Parameters
----------
path : str
    The VVAL file.

Returns
-------
ndarray of int32, shape (n,)
    A valence per input vertex.

Raises
------
OSError
    The file cannot be read.
ValueError
    A malformed file (the message names the line).
)doc",
          py::arg("path"));
    m.def("write_obj", &write_obj, R"doc(Write an extracted mesh as OBJ (the core of `qex.write_obj`).

Parameters
----------
path : str
    The file to write (through ``path + ".tmp"``, renamed).
mesh : QuadMesh
    The ``mesh`` that `extract` returned.

Raises
------
OSError
    The file cannot be written.
)doc",
          py::arg("path"), py::arg("mesh"));
    m.def("write_certificate", &write_certificate,
          R"doc(Write an extracted mesh's certificate (the core of `qex.write_certificate`).

Parameters
----------
V, F, UV : ndarray
    The map the mesh was extracted from, as for `extract`.
mesh : QuadMesh
    The ``mesh`` that `extract` returned.
path : str
    The file to write (through ``path + ".tmp"``, renamed).

Raises
------
ValueError
    Arrays of the wrong shape or dtype, or a mesh that carries no map of them.
OSError
    The file cannot be written.
)doc",
          py::arg("V"), py::arg("F"), py::arg("UV"), py::arg("mesh"), py::arg("path"));
    m.def("layout", &layout_of, R"doc(The quad layout of an extracted mesh (qex/layout.h), as a dict of numpy arrays:
"face_patch" (F,), "patch_sizes" (P, 2), "patch_corners" (P, 4), "separatrices" (a list of vertex index
arrays), "separatrix_ends", "adjacency" (A, 3: patch a, patch b, shared edges), "special_vertices",
"valid", "error" (why the independent check rejects it), "notes".)doc",
          py::arg("mesh"));
    m.def(
        "layout_of_arrays", [](const Doubles& QV, const py::object& QF) { return layout_of(to_mesh(QV, QF)); },
        R"doc(The quad layout of the quad mesh (QV (n, 3) positions, QF (k, 4) faces), as `layout` gives it.)doc",
        py::arg("QV"), py::arg("QF"));
}

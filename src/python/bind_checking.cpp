// The checking room of the binding: verify() judges an extracted mesh, check() any quad mesh,
// both against their map. The GIL is released while the checker works.
#include "bindings.h"
#include "convert.h"

#include "qex/check.h"
#include "qex/report.h"

#include <cmath>
#include <string>

namespace qex_python {
namespace {

std::string verify(const Doubles& V, const py::object& F, const Doubles& UV, const qex::QuadMesh& mesh, int threads) {
    const qex::Input in = to_input(V, F, UV, py::none(), py::none());
    py::gil_scoped_release unlocked;
    qex::VerifyOptions o;
    o.threads = threads;
    return qex::verify_json(qex::verify(in, mesh, o));
}

constexpr const char* kVerifyDoc = R"doc(Judge an extracted mesh against its map (the core of `qex.verify`).

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
)doc";

std::string check(const Doubles& V, const py::object& F, const Doubles& UV, const Doubles& QV, const py::object& QF,
                  double uv_tolerance, double distance_tolerance, bool locate, int digits, int grid_scale,
                  bool fold_regions, bool strict_map, int threads, const std::string& certificate_path) {
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
        o.strict_map = strict_map;
        o.threads = threads;
        c = certificate_path.empty() ? qex::check_mesh(in, mesh, grid_scale, o)
                                     : qex::check_mesh(in, mesh, certificate, o);
        if (c.map_ok()) quality = qex::mesh_quality(in, mesh);
    }
    if (!c.map_ok()) reject(c.error);
    return qex::verify_json(c.verdict, quality);
}

constexpr const char* kCheckDoc = R"doc(Judge any quad mesh against a map (the core of `qex.check`).

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
strict_map : bool
    Decide every check against the raw map: what would be undecided is a violation.
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
)doc";

} // namespace

void bind_checking(py::module_& m) {
    m.def("verify", &verify, kVerifyDoc, py::arg("V"), py::arg("F"), py::arg("UV"), py::arg("mesh"),
          py::arg("threads"));
    m.def("check", &check, kCheckDoc, py::arg("V"), py::arg("F"), py::arg("UV"), py::arg("QV"), py::arg("QF"),
          py::arg("uv_tolerance"), py::arg("distance_tolerance"), py::arg("locate"), py::arg("digits"),
          py::arg("grid_scale"), py::arg("fold_regions"), py::arg("strict_map"), py::arg("threads"),
          py::arg("certificate"));
}

} // namespace qex_python

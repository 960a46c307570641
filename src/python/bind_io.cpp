// The I/O room of the binding: OBJ and VVAL files read into arrays, an extracted mesh and its
// certificate written. The GIL is released while a file is read or written.
#include "bindings.h"
#include "convert.h"

#include <cstdint>
#include <string>
#include <vector>

namespace qex_python {
namespace {

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

constexpr const char* kReadVvalDoc = R"doc(Read a VVAL file of valences (the core of `qex.read_vval`).

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
)doc";

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

constexpr const char* kReadObjDoc = R"doc(Read an OBJ map (the core of `qex.read_obj`).

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
)doc";

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

constexpr const char* kWriteCertificateDoc =
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
)doc";

void write_obj(const std::string& path, const qex::QuadMesh& mesh) {
    qex::IoError e;
    {
        py::gil_scoped_release unlocked;
        e = qex::write_obj(path, mesh);
    }
    if (!e.ok()) raise(path, e);
}

constexpr const char* kWriteObjDoc = R"doc(Write an extracted mesh as OBJ (the core of `qex.write_obj`).

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
)doc";

} // namespace

void bind_io(py::module_& m) {
    m.def("read_obj", &read_obj, kReadObjDoc, py::arg("path"), py::arg("threads"));
    m.def("read_vval", &read_vval, kReadVvalDoc, py::arg("path"));
    m.def("write_obj", &write_obj, kWriteObjDoc, py::arg("path"), py::arg("mesh"));
    m.def("write_certificate", &write_certificate, kWriteCertificateDoc, py::arg("V"), py::arg("F"), py::arg("UV"),
          py::arg("mesh"), py::arg("path"));
}

} // namespace qex_python

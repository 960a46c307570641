// The conversions every room shares (convert.h). The Python half checks dtypes and shapes
// first; they are checked again here, as a caller may reach qex._qex directly.
#include "convert.h"

#include "io/checked_int.h"

#include <cstdint>
#include <string>

namespace qex_python {

void expect_shape(const py::array& a, py::ssize_t cols, const char* what) {
    if (a.ndim() != 2 || a.shape(1) != cols)
        throw py::value_error(std::string(what) + " must have shape (n, " + std::to_string(cols) + ")");
}

namespace {

int to_index(std::int64_t x, const char* what) {
    int i = 0;
    if (!qex::io_detail::checked_int(x, i))
        throw py::value_error(std::string(what) + ": " + std::to_string(x) + " does not fit in 32 bits");
    return i;
}

} // namespace

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

[[noreturn]] void raise(const std::string& path, const qex::IoError& e) {
    const std::string message = path + ": " + e.message;
    if (e.code == qex::IoError::Code::CannotOpen || e.code == qex::IoError::Code::CannotWrite) {
        PyErr_SetString(PyExc_OSError, message.c_str());
        throw py::error_already_set();
    }
    throw py::value_error(message);
}

} // namespace qex_python

// What every room of the binding shares (qex_module.cpp lists the rooms): numpy arrays turned
// into qex's types, and qex's errors turned into Python's exceptions. Every array is checked
// here, so that no call from Python can crash the interpreter.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h> // in every room alike: one set of type casters throughout the module

#include "qex/qex.h"

#include <cstdint>
#include <string>

namespace py = pybind11;

namespace qex_python {

using Doubles = py::array_t<double, py::array::c_style | py::array::forcecast>;
using Int64s = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>;

// An array's shape must be (rows, cols) (rows any); raises ValueError naming `what` otherwise.
void expect_shape(const py::array& a, py::ssize_t cols, const char* what);

/// `obj` as an int64 array, for indices: an array of integers (or bools), as the Python half
/// requires. Not forcecast from anything else: a float array would be truncated, and its NaN,
/// infinities and values past 2^63 have no int64 at all; a uint64 past 2^63 would wrap.
Int64s integer_array(const py::handle& obj, const char* what);

/// The Input of arrays V (n,3), F (m,3) and UV (3m,2), valences (n,) or None, feature edges (e,2) or None.
qex::Input to_input(const Doubles& V, const py::object& F_in, const Doubles& UV, const py::object& valences,
                    const py::object& feature_edges);

/// The mesh of arrays QV (p,3) and QF (k,c): one face per row.
qex::QuadMesh to_mesh(const Doubles& QV, const py::object& QF_in);

/// The library's rejection of its input, as a ValueError.
[[noreturn]] void reject(const qex::Error& e);

/// A file's error: an OSError when it cannot be opened or written, a ValueError otherwise.
[[noreturn]] void raise(const std::string& path, const qex::IoError& e);

} // namespace qex_python

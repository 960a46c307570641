// The compiled half of the Python package qex (qex._qex): numpy arrays in and out of qex::extract,
// qex::verify and the OBJ files. The Python half (the modules in qex/) checks dtypes and shapes and
// holds the docstrings; this side checks them again, so that no call from Python can crash the
// interpreter, and releases the GIL while the library works.
//
// The binding is split into rooms by what they bind (bindings.h), each in its own file:
//   convert.h, convert.cpp   arrays to qex's types, qex's errors to Python's exceptions (shared)
//   bind_extraction.cpp      QuadMesh, extract: its options, its result's arrays
//   bind_checking.cpp        verify, check
//   bind_io.cpp              read_obj, read_vval, write_obj, write_certificate
//   bind_layout.cpp          layout, layout_of_arrays
//   bind_conform.cpp         qex.conform's cases, judge and table (qex/conform.h)
#include "bindings.h"

#include <pybind11/pybind11.h>

PYBIND11_MODULE(_qex, m) {
    m.doc() =
        "The compiled core of the qex package; use the functions of `qex` itself, which check the "
        "arguments and document them (qex/_qex.pyi holds this module's types).";
    qex_python::bind_extraction(m);
    qex_python::bind_checking(m);
    qex_python::bind_io(m);
    qex_python::bind_layout(m);
    qex_python::bind_conform(m);
}

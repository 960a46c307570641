// The rooms of the binding, a source file each (bind_<room>.cpp). PYBIND11_MODULE
// (qex_module.cpp) calls them in this order; extraction first, as it registers QuadMesh, whose
// name the other rooms' signatures and docstrings carry.
#pragma once

#include <pybind11/pybind11.h>

namespace qex_python {

void bind_extraction(pybind11::module_& m); // QuadMesh, extract
void bind_checking(pybind11::module_& m);   // verify, check
void bind_io(pybind11::module_& m);         // read_obj, read_vval, write_obj, write_certificate
void bind_layout(pybind11::module_& m);     // layout, layout_of_arrays
void bind_conform(pybind11::module_& m);    // conform_cases, conform_map_text, conform_judge, conform_table

} // namespace qex_python

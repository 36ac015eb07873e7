#pragma once

#include <pybind11/pybind11.h>

// The parts of the `_mimpact` module, each binding one library.
namespace mimpact::python {

void bind_chains(pybind11::module_& module);
void bind_kernel(pybind11::module_& module);
void bind_packings(pybind11::module_& module);

}  // namespace mimpact::python

#include <pybind11/pybind11.h>

#include "bindings.hpp"
#include "mimpact/common/error.hpp"

namespace py = pybind11;

// The compiled part of the Python package `mimpact` (python/mimpact/__init__.py). Bad input
// arrives in Python as ValueError with the library's message, naming the field, the value and
// what is allowed; other failures of a run as RuntimeError.
PYBIND11_MODULE(_mimpact, module) {
  module.doc() = "mimpact: multiple impacts with the LZB model (compiled part)";
  py::register_exception_translator([](std::exception_ptr raised) {
    try {
      if (raised) std::rethrow_exception(raised);
    } catch (const mimpact::InvalidInput& error) {
      PyErr_SetString(PyExc_ValueError, error.what());
    } catch (const mimpact::Error& error) {
      PyErr_SetString(PyExc_RuntimeError, error.what());
    }
  });
  mimpact::python::bind_kernel(module);
  mimpact::python::bind_chains(module);
  mimpact::python::bind_packings(module);
}

// The core's algorithms as functions of the Python module (simplify, chains, compare, packs, octree, LODStrips).
#pragma once

#include <pybind11/pybind11.h>

namespace lodforge::python {

void bind_algorithms(pybind11::module_& m);

}  // namespace lodforge::python

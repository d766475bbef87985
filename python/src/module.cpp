// lodforge._core: the LodForge core for Python (pybind11). The package lodforge re-exports it;
// docs/python.md is the tutorial.
#include "bind_algorithms.h"
#include "py_mesh.h"
#include "py_progress.h"

#include "lodforge/pack/preset_library.h"

#include <pybind11/stl.h>

PYBIND11_MODULE(_core, m) {
    m.doc() = "LodForge core: meshes as NumPy arrays, simplification, LOD chains, packs, octrees, LODStrips.";
    m.attr("__version__") = LODFORGE_VERSION;
    lodforge::python::bind_errors(m);
    lodforge::python::bind_mesh(m);
    lodforge::python::bind_algorithms(m);
    m.def("shipped_presets", &lodforge::shipped_preset_names, "Names of the presets LodForge ships.");
}

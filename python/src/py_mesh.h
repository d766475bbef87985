// lodforge.Mesh: a core Mesh owned by Python, whose arrays NumPy sees without copies.
#pragma once

#include "lodforge/mesh.h"

#include <pybind11/pybind11.h>

#include <memory>
#include <vector>

namespace lodforge::python {

// The Mesh plus the buffers it replaced. Array properties return views into the mesh's vectors whose
// base is the Python object, so a view keeps the mesh alive. Assigning an array of the same length
// copies into the existing buffer (views see the new values); a different length needs a new buffer,
// and the old one is kept here until the mesh dies, so a view taken before stays valid memory.
struct MeshHandle {
    Mesh mesh;
    std::vector<std::shared_ptr<void>> retired;

    MeshHandle() = default;
    explicit MeshHandle(Mesh m) : mesh(std::move(m)) {}
};
using MeshPtr = std::shared_ptr<MeshHandle>;

inline MeshPtr wrap(Mesh mesh) { return std::make_shared<MeshHandle>(std::move(mesh)); }

void bind_mesh(pybind11::module_& m);

}  // namespace lodforge::python

namespace lodforge::python {

// The mesh of a handle after checking what the core assumes of its input (array lengths, index range,
// finite values): arrays assigned from Python may disagree. Throws Error(invalid) naming `what`.
const Mesh& checked(const MeshHandle& handle, const char* what = "mesh");

}  // namespace lodforge::python

#include "py_mesh.h"
#include "py_progress.h"

#include "lodforge/error.h"
#include "lodforge/io/mesh_info.h"
#include "lodforge/io/mesh_io.h"
#include "lodforge/io/mesh_validate.h"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <cstring>
#include <filesystem>
#include <string>

namespace py = pybind11;

namespace lodforge::python {
namespace {

// Element type and width of each per-item struct as NumPy sees it (rows of `Width` scalars).
template <class T> struct Layout;
template <> struct Layout<Vec2f> { using Scalar = float; static constexpr int width = 2; };
template <> struct Layout<Vec3f> { using Scalar = float; static constexpr int width = 3; };
template <> struct Layout<Vec4f> { using Scalar = float; static constexpr int width = 4; };
template <> struct Layout<std::uint32_t> { using Scalar = std::uint32_t; static constexpr int width = 1; };

// A (n, width) view, or (n,) for width 1, of `v`; `base` keeps the owner alive.
template <class T>
py::array view(std::vector<T>& v, py::handle base, int width = Layout<T>::width) {
    using S = typename Layout<T>::Scalar;
    const auto n = static_cast<py::ssize_t>(v.size() * Layout<T>::width / width);
    if (width == 1) return py::array_t<S>({n}, {py::ssize_t(sizeof(S))}, reinterpret_cast<S*>(v.data()), base);
    return py::array_t<S>({n, py::ssize_t(width)}, {py::ssize_t(sizeof(S)) * width, py::ssize_t(sizeof(S))},
                          reinterpret_cast<S*>(v.data()), base);
}

// Copies `value` (any array-like of matching shape, converted) into `v` following MeshHandle's rule.
template <class T>
void assign(MeshHandle& h, std::vector<T>& v, py::handle value, const char* name, int width = Layout<T>::width) {
    using S = typename Layout<T>::Scalar;
    const auto a = py::array_t<S, py::array::c_style | py::array::forcecast>::ensure(value);
    if (!a) throw Error(Error::Kind::argument, std::string("Mesh.") + name + ": expected an array of numbers");
    const bool ok = width == 1 ? a.ndim() == 1 : (a.ndim() == 2 && a.shape(1) == width) || (a.ndim() == 1 && a.size() == 0);
    if (!ok)
        throw Error(Error::Kind::argument, std::string("Mesh.") + name + ": expected shape " +
                                               (width == 1 ? "(n,)" : "(n, " + std::to_string(width) + ")"));
    const std::size_t items = static_cast<std::size_t>(a.size()) * sizeof(S) / sizeof(T);
    if (items != v.size()) {
        if (!v.empty()) h.retired.push_back(std::make_shared<std::vector<T>>(std::move(v)));
        v = std::vector<T>(items);
    }
    if (items) std::memcpy(static_cast<void*>(v.data()), a.data(), items * sizeof(T));
}

template <class T>
void array_property(py::class_<MeshHandle, MeshPtr>& c, const char* name, std::vector<T> Mesh::*member,
                    const char* doc, int width = Layout<T>::width) {
    c.def_property(
        name, [member, width](py::object self) { return view(self.cast<MeshHandle&>().mesh.*member, self, width); },
        [member, name, width](MeshHandle& h, py::handle value) { assign(h, h.mesh.*member, value, name, width); },
        doc);
}

py::dict texture_dict(const TextureRef& t) {
    py::dict d;
    d["path"] = t.path;
    d["embedded"] = !t.bytes.empty();
    d["mime_type"] = t.mime_type;
    d["texcoord_set"] = t.texcoord_set;
    return d;
}

}  // namespace

const Mesh& checked(const MeshHandle& handle, const char* what) {
    const ValidationReport report = validate(handle.mesh);
    for (const ValidationFinding& f : report.findings)
        if (f.severity == ValidationFinding::Severity::error)
            throw Error(Error::Kind::invalid, std::string(what) + ": " + f.message);
    return handle.mesh;
}

void bind_mesh(py::module_& m) {
    py::class_<Material>(m, "Material", "A material (glTF metallic-roughness; MTL and PLY map onto it).")
        .def(py::init<>())
        .def_readwrite("name", &Material::name)
        .def_property("base_color", [](const Material& x) { return std::array<float, 4>{x.base_color.x, x.base_color.y, x.base_color.z, x.base_color.w}; },
                      [](Material& x, std::array<float, 4> c) { x.base_color = {c[0], c[1], c[2], c[3]}; },
                      "Linear RGBA factor.")
        .def_readwrite("metallic", &Material::metallic)
        .def_readwrite("roughness", &Material::roughness)
        .def_readwrite("double_sided", &Material::double_sided)
        .def_property_readonly("base_color_texture", [](const Material& x) { return texture_dict(x.base_color_texture); },
                               "{'path', 'embedded', 'mime_type', 'texcoord_set'}")
        .def("__repr__", [](const Material& x) { return "<lodforge.Material '" + x.name + "'>"; });

    py::class_<MeshHandle, MeshPtr> c(m, "Mesh", R"(A triangle mesh: struct of arrays, one vertex per wedge.

Array properties are NumPy views into the mesh (no copy): positions, normals (n, 3) float32,
colors (n, 4) float32 RGBA in [0, 1], texcoords (a list of (n, 2) float32, one per set), position_ids
(n,) uint32, indices (t, 3) uint32, face_materials (t,) uint32. An absent attribute is an empty
array. Assigning an array copies it in; a view taken before an assignment that changes the length
keeps the old values.)");
    c.def(py::init<>(), "An empty mesh.");
    c.def(py::init([](py::handle positions, py::handle indices) {
              auto h = std::make_shared<MeshHandle>();
              assign(*h, h->mesh.positions, positions, "positions");
              assign(*h, h->mesh.indices, indices, "indices", 3);
              return h;
          }),
          py::arg("positions"), py::arg("indices"), "A mesh from (n, 3) positions and (t, 3) vertex indices.");
    array_property(c, "positions", &Mesh::positions, "(n, 3) float32 view.");
    array_property(c, "normals", &Mesh::normals, "(n, 3) float32 view, or empty.");
    array_property(c, "colors", &Mesh::colors, "(n, 4) float32 RGBA view, or empty.");
    array_property(c, "position_ids", &Mesh::position_ids,
                   "(n,) uint32 view: vertices with equal ids are wedges of one surface point; empty = each its own.");
    array_property(c, "indices", &Mesh::indices, "(t, 3) uint32 view: vertex indices per triangle.", 3);
    array_property(c, "face_materials", &Mesh::face_materials, "(t,) uint32 view: material per triangle, or empty.");
    c.def_property(
        "texcoords",
        [](py::object self) {
            py::list sets;
            for (auto& set : self.cast<MeshHandle&>().mesh.texcoords) sets.append(view(set, self));
            return sets;
        },
        [](MeshHandle& h, py::sequence sets) {
            // Each set keeps its buffer where it can (same rule as the other arrays).
            auto& tc = h.mesh.texcoords;
            while (tc.size() > sets.size()) {
                h.retired.push_back(std::make_shared<std::vector<Vec2f>>(std::move(tc.back())));
                tc.pop_back();
            }
            tc.resize(sets.size());
            for (std::size_t s = 0; s < sets.size(); ++s) assign(h, tc[s], sets[s], "texcoords");
        },
        "List of (n, 2) float32 views, one per texture coordinate set.");
    c.def_property(
        "materials", [](const MeshHandle& h) { return h.mesh.materials; },
        [](MeshHandle& h, std::vector<Material> v) { h.mesh.materials = std::move(v); },
        "The materials (a copy: assign a list to change them).");
    c.def_property(
        "source_dir", [](const MeshHandle& h) { return h.mesh.source_dir; },
        [](MeshHandle& h, std::string v) { h.mesh.source_dir = std::move(v); },
        "Directory relative texture paths are resolved against.");
    c.def_property_readonly("warnings", [](const MeshHandle& h) { return h.mesh.warnings; }, "Importer notes.");
    c.def_property_readonly("vertex_count", [](const MeshHandle& h) { return h.mesh.vertex_count(); },
                            "Vertices (wedges): `wedges` in `lodforge info`.");
    c.def_property_readonly("point_count", [](const MeshHandle& h) { return h.mesh.point_count(); },
                            "Distinct surface points: `vertices` in `lodforge info`.");
    c.def_property_readonly("triangle_count", [](const MeshHandle& h) { return h.mesh.triangle_count(); });
    c.def_property_readonly(
        "bounds",
        [](const MeshHandle& h) {
            const Bounds b = h.mesh.bounds();
            return py::make_tuple(py::make_tuple(b.min.x, b.min.y, b.min.z), py::make_tuple(b.max.x, b.max.y, b.max.z));
        },
        "((min x, y, z), (max x, y, z)).");
    c.def("copy", [](const MeshHandle& h) { return wrap(h.mesh); }, "A deep copy.");
    c.def("__repr__", [](const MeshHandle& h) {
        return "<lodforge.Mesh " + std::to_string(h.mesh.triangle_count()) + " triangles, " +
               std::to_string(h.mesh.vertex_count()) + " vertices>";
    });

    m.def(
        "read_mesh",
        [](const std::filesystem::path& path, bool validate, bool place_every_instance, py::object progress) {
            ReadOptions options;
            options.validate = validate;
            options.place_every_instance = place_every_instance;
            return wrap(run_with_progress(progress, [&](Progress* p) { return read_mesh(path.string(), options, p); }));
        },
        py::arg("path"), py::kw_only(), py::arg("validate") = true, py::arg("place_every_instance") = false,
        py::arg("progress") = py::none(),
        "Reads a .ply, .obj, .gltf or .glb file. Raises lodforge.Error naming the file on any problem.");
    m.def(
        "write_mesh",
        [](const MeshHandle& h, const std::filesystem::path& path, const std::string& ply_encoding, bool normals, bool colors,
           bool texcoords, bool ply_colors_as_uchar, py::object progress) {
            WriteOptions options;
            if (ply_encoding == "binary") options.ply_encoding = PlyEncoding::binary_little_endian;
            else if (ply_encoding == "ascii") options.ply_encoding = PlyEncoding::ascii;
            else if (ply_encoding == "binary_big_endian") options.ply_encoding = PlyEncoding::binary_big_endian;
            else throw Error(Error::Kind::argument, "write_mesh: ply_encoding must be 'binary', 'ascii' or 'binary_big_endian'");
            options.write_normals = normals;
            options.write_colors = colors;
            options.write_texcoords = texcoords;
            options.ply_colors_as_uchar = ply_colors_as_uchar;
            std::vector<std::string> warnings;
            options.warnings = &warnings;
            run_with_progress(progress, [&](Progress* p) {
                write_mesh(checked(h), path.string(), options, p);
                return 0;
            });
            return warnings;
        },
        py::arg("mesh"), py::arg("path"), py::kw_only(), py::arg("ply_encoding") = "binary", py::arg("normals") = true,
        py::arg("colors") = true, py::arg("texcoords") = true, py::arg("ply_colors_as_uchar") = true,
        py::arg("progress") = py::none(),
        "Writes PLY, OBJ (+MTL) or GLB by extension, atomically. Returns what was left out (warnings).");
    m.def(
        "_mesh_info_json",
        [](const MeshHandle& h, const std::string& path) {
            return to_json(mesh_info(h.mesh, path, path.empty() ? "" : format_name(detect_format(path))));
        },
        py::arg("mesh"), py::arg("path") = "");
}

}  // namespace lodforge::python

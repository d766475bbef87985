// glTF 2.0 import (.gltf and .glb) through tinygltf.
//
// tinygltf parses the JSON and loads buffers; images are *not* decoded here (a custom image loader
// keeps embedded bytes and leaves external files as URIs), so a missing texture never fails the load
// and opening is fast; image_decode.cpp decodes on demand. Every accessor read is bounds-checked here,
// because tinygltf does not check accessor ranges against buffer sizes.
//
// Decisions (docs/import-obj-gltf.md): each glTF mesh reachable from the scene is imported once, at the
// world transform of its first instance in depth-first order (further instances share its LODs and
// are not duplicated), so the counts are the stored data; V is flipped (v' = 1 - v) so the Mesh keeps
// the OpenGL/OBJ convention of v pointing up.
#include "lodforge/io/gltf_reader.h"

#include "io/gltf_json_check.h"
#include "lodforge/error.h"
#include "lodforge/io/input_file.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <set>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

namespace lodforge {
namespace fs = std::filesystem;

namespace {

using Mat4 = std::array<double, 16>;  // column-major, as glTF stores it

constexpr Mat4 kIdentity = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

Mat4 multiply(const Mat4& a, const Mat4& b) {
    Mat4 r{};
    for (int c = 0; c < 4; ++c)
        for (int row = 0; row < 4; ++row) {
            double s = 0;
            for (int k = 0; k < 4; ++k) s += a[static_cast<std::size_t>(k * 4 + row)] * b[static_cast<std::size_t>(c * 4 + k)];
            r[static_cast<std::size_t>(c * 4 + row)] = s;
        }
    return r;
}

Mat4 trs_matrix(const tinygltf::Node& node) {
    if (node.matrix.size() == 16) {
        Mat4 m{};
        std::copy(node.matrix.begin(), node.matrix.end(), m.begin());
        return m;
    }
    Mat4 t = kIdentity, r = kIdentity, s = kIdentity;
    if (node.translation.size() == 3) {
        t[12] = node.translation[0];
        t[13] = node.translation[1];
        t[14] = node.translation[2];
    }
    if (node.rotation.size() == 4) {
        const double x = node.rotation[0], y = node.rotation[1], z = node.rotation[2], w = node.rotation[3];
        r = {1 - 2 * (y * y + z * z), 2 * (x * y + z * w),     2 * (x * z - y * w),     0,
             2 * (x * y - z * w),     1 - 2 * (x * x + z * z), 2 * (y * z + x * w),     0,
             2 * (x * z + y * w),     2 * (y * z - x * w),     1 - 2 * (x * x + y * y), 0,
             0,                       0,                       0,                       1};
    }
    if (node.scale.size() == 3) {
        s[0] = node.scale[0];
        s[5] = node.scale[1];
        s[10] = node.scale[2];
    }
    return multiply(t, multiply(r, s));
}

double determinant3(const Mat4& m) {
    return m[0] * (m[5] * m[10] - m[9] * m[6]) - m[4] * (m[1] * m[10] - m[9] * m[2]) +
           m[8] * (m[1] * m[6] - m[5] * m[2]);
}

// Inverse transpose of the upper 3x3 (column-major 3x3 result), for normals.
std::array<double, 9> normal_matrix(const Mat4& m) {
    const double a = m[0], b = m[4], c = m[8];
    const double d = m[1], e = m[5], f = m[9];
    const double g = m[2], h = m[6], i = m[10];
    const double det = determinant3(m);
    if (std::fabs(det) < 1e-300) return {1, 0, 0, 0, 1, 0, 0, 0, 1};
    // Cofactor matrix / det == inverse transpose. Stored column-major: out[col*3 + row].
    const double inv = 1.0 / det;
    return {(e * i - f * h) * inv, -(b * i - c * h) * inv, (b * f - c * e) * inv,
            -(d * i - f * g) * inv, (a * i - c * g) * inv, -(a * f - c * d) * inv,
            (d * h - e * g) * inv, -(a * h - b * g) * inv, (a * e - b * d) * inv};
}

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
    return s;
}

// tinygltf quotes a data URI it cannot decode in full (megabytes of base64 in one error line): the
// payload of every `data:…;base64,` is cut to its first 16 characters.
std::string one_line(const std::string& text) {
    std::string out;
    bool pending = false;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (c == '\n' || c == '\r') {
            pending = !out.empty();
            continue;
        }
        if (pending) out += "; ";
        pending = false;
        out += c;
        if (c == ',' && out.size() >= 7 && out.compare(out.size() - 7, 7, "base64,") == 0) {
            std::size_t end = i + 1;
            while (end < text.size() && (std::isalnum(static_cast<unsigned char>(text[end])) || text[end] == '+' ||
                                         text[end] == '/' || text[end] == '='))
                ++end;
            if (end - (i + 1) > 16) {
                out += text.substr(i + 1, 16) + "… (" + std::to_string(end - (i + 1)) + " characters)";
                i = end - 1;
            }
        }
    }
    return out;
}

std::string url_decode(const std::string& uri) {
    std::string out;
    for (std::size_t i = 0; i < uri.size(); ++i) {
        if (uri[i] == '%' && i + 2 < uri.size() && std::isxdigit(static_cast<unsigned char>(uri[i + 1])) &&
            std::isxdigit(static_cast<unsigned char>(uri[i + 2]))) {
            out += static_cast<char>(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
            i += 2;
        } else {
            out += uri[i];
        }
    }
    return out;
}

std::string sniff_mime(const std::vector<std::uint8_t>& b) {
    if (b.size() >= 4 && b[0] == 0x89 && b[1] == 'P' && b[2] == 'N' && b[3] == 'G') return "image/png";
    if (b.size() >= 3 && b[0] == 0xFF && b[1] == 0xD8 && b[2] == 0xFF) return "image/jpeg";
    return {};
}

// Image "loader" that decodes nothing: embedded images (data URIs) keep their encoded bytes, external
// ones keep their URI, and images in buffer views are read (with bounds checks) by the importer.
bool keep_image_undecoded(tinygltf::Image* image, const int, std::string*, std::string*, int, int,
                          const unsigned char* bytes, int size, void*) {
    image->as_is = true;
    if (image->uri.empty() && image->bufferView < 0 && bytes && size > 0)
        image->image.assign(bytes, bytes + size);
    return true;
}

// tinygltf's file reader, refusing what is not a regular file: a buffer URI naming /dev/zero was read
// until memory ran out, one naming a FIFO blocked forever.
bool read_regular_file(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user) {
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) {
        if (err) *err += "File read error : " + path + " is not a regular file\n";
        return false;
    }
    return tinygltf::ReadWholeFile(out, err, path, user);
}

std::size_t component_size(int type) {
    switch (type) {
        case TINYGLTF_COMPONENT_TYPE_BYTE:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
        case TINYGLTF_COMPONENT_TYPE_SHORT:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
        case TINYGLTF_COMPONENT_TYPE_INT:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
        default: return 0;
    }
}

std::size_t component_count(int type) {
    switch (type) {
        case TINYGLTF_TYPE_SCALAR: return 1;
        case TINYGLTF_TYPE_VEC2: return 2;
        case TINYGLTF_TYPE_VEC3: return 3;
        case TINYGLTF_TYPE_VEC4: return 4;
        default: return 0;  // matrices are never vertex attributes we read
    }
}

template <typename T>
T load(const std::uint8_t* p) {
    T v;
    std::memcpy(&v, p, sizeof v);
    return v;
}

float component_value(const std::uint8_t* p, int type, bool normalized) {
    switch (type) {
        case TINYGLTF_COMPONENT_TYPE_BYTE: {
            const auto v = load<std::int8_t>(p);
            return normalized ? std::max(static_cast<float>(v) / 127.f, -1.f) : static_cast<float>(v);
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: {
            const auto v = load<std::uint8_t>(p);
            return normalized ? static_cast<float>(v) / 255.f : static_cast<float>(v);
        }
        case TINYGLTF_COMPONENT_TYPE_SHORT: {
            const auto v = load<std::int16_t>(p);
            return normalized ? std::max(static_cast<float>(v) / 32767.f, -1.f) : static_cast<float>(v);
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
            const auto v = load<std::uint16_t>(p);
            return normalized ? static_cast<float>(v) / 65535.f : static_cast<float>(v);
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: return static_cast<float>(load<std::uint32_t>(p));
        case TINYGLTF_COMPONENT_TYPE_INT: return static_cast<float>(load<std::int32_t>(p));
        default: return load<float>(p);
    }
}

struct Instance {
    int mesh = -1;
    Mat4 world = kIdentity;
    int node = -1;
};

struct PrimitiveJob {
    int mesh = -1;
    int primitive = -1;
    const Instance* instance = nullptr;
    std::size_t count = 0;         // vertices in its POSITION accessor
    std::size_t base = 0;          // first point of its POSITION accessor in the output
    bool owns_points = true;       // false: an earlier primitive of the same mesh stored this accessor
    bool same_attributes = true;   // when !owns_points: attributes identical to the owner's
};

// Vertex attributes of one primitive, already transformed and converted to the Mesh conventions.
struct PrimitiveData {
    std::vector<Vec3f> positions;
    std::vector<Vec3f> normals;
    std::vector<Vec4f> colors;
    std::vector<std::vector<Vec2f>> texcoords;  // [set], empty set = absent
    std::vector<std::vector<Joints4>> joints;   // [set], empty set = absent (indices into the merged skin)
    std::vector<std::vector<Vec4f>> weights;    // [set], empty set = absent
    std::vector<std::vector<Vec3f>> target_positions, target_normals;  // [target][vertex], morph only
};

// KHR_texture_transform in glTF's UV space (origin top left): uv' = T R S uv, i.e.
// u' = a u + b v + c, v' = d u + e v + f.
struct UvTransform {
    double a = 1, b = 0, c = 0, d = 0, e = 1, f = 0;
    bool operator==(const UvTransform&) const = default;
    bool identity() const { return *this == UvTransform{}; }
};

double number_at(const tinygltf::Value& object, const char* key, int index, double fallback) {
    if (!object.Has(key)) return fallback;
    const tinygltf::Value& v = object.Get(key);
    if (index < 0) return v.IsNumber() ? v.GetNumberAsDouble() : fallback;
    if (!v.IsArray() || static_cast<int>(v.ArrayLen()) <= index || !v.Get(index).IsNumber()) return fallback;
    return v.Get(index).GetNumberAsDouble();
}

class GltfImporter {
public:
    GltfImporter(std::string path, const tinygltf::Model& model, Progress* progress, const GltfReadOptions& options)
        : path_(std::move(path)), model_(model), progress_(progress), options_(options) {}

    Mesh run() {
        check_version();
        check_required_extensions();
        collect_instances();
        collect_primitives();
        if (jobs_.empty()) {
            // Nothing to import would give an empty mesh that every command then fails on far from
            // the cause (or writes an empty file); say here why there is no surface.
            std::size_t skipped = 0;
            for (const std::string& w : mesh_.warnings) skipped += w.find("points/lines skipped") != std::string::npos;
            fail(Error::Kind::invalid, skipped ? "no triangle primitives (" + std::to_string(skipped) +
                                                     " POINTS/LINES primitives skipped; point and line data is not imported)"
                                               : "no triangle geometry: the scene instances no mesh primitive");
        }
        decide_skin();
        convert_materials();
        build();
        if (skinned_) read_skeleton();
        if (options_.morph_targets) read_weights_animation();
        return std::move(mesh_);
    }

private:
    [[noreturn]] void fail(Error::Kind kind, const std::string& what) const { throw_error(kind, path_, what); }

    std::string where(const PrimitiveJob& job) const {
        const auto& m = model_.meshes[static_cast<std::size_t>(job.mesh)];
        return "mesh " + std::to_string(job.mesh) + (m.name.empty() ? "" : " '" + m.name + "'") + " primitive " +
               std::to_string(job.primitive);
    }

    void check_version() const {
        // tinygltf reads a 1.0 file as an empty 2.0 model; refuse it instead of importing nothing.
        const std::string& v = model_.asset.version;
        if (v.empty() || v[0] != '2')
            fail(Error::Kind::unsupported, "glTF version '" + v + "' is not supported (only glTF 2.0)");
    }

    void check_required_extensions() const {
        for (const std::string& ext : model_.extensionsRequired) {
            if (ext == "KHR_mesh_quantization" || ext == "KHR_texture_transform" || ext.rfind("KHR_materials_", 0) == 0)
                continue;
            if (ext == "KHR_draco_mesh_compression" || ext == "EXT_meshopt_compression")
                fail(Error::Kind::unsupported, "compressed geometry (" + ext + ") is not supported; decompress it first "
                                               "(e.g. gltf-transform decompress)");
            fail(Error::Kind::unsupported, "requires the unsupported extension " + ext);
        }
    }

    // Depth-first over the scene; the first node that instances a mesh places it.
    void collect_instances() {
        const std::vector<int> roots = scene_roots();
        std::vector<char> on_path(model_.nodes.size(), 0);
        std::vector<char> mesh_seen(model_.meshes.size(), 0);
        for (int root : roots) visit(root, kIdentity, on_path, mesh_seen);
        for (std::size_t m = 0; m < mesh_seen.size(); ++m) {
            if (mesh_seen[m] < 2 || options_.place_every_instance) continue;
            const std::string& name = model_.meshes[m].name;
            mesh_.warnings.push_back("mesh " + std::to_string(m) + (name.empty() ? "" : " '" + name + "'") +
                                     " is instanced by " + std::to_string(int(mesh_seen[m])) +
                                     " nodes; imported once, at its first placement");
        }
    }

    std::vector<int> scene_roots() const {
        std::vector<int> roots;
        const auto& scenes = model_.scenes;
        if (model_.defaultScene >= 0 && static_cast<std::size_t>(model_.defaultScene) < scenes.size()) {
            roots = scenes[static_cast<std::size_t>(model_.defaultScene)].nodes;
        } else if (!scenes.empty()) {
            for (const auto& scene : scenes) roots.insert(roots.end(), scene.nodes.begin(), scene.nodes.end());
        } else {
            std::vector<char> is_child(model_.nodes.size(), 0);
            for (const auto& node : model_.nodes)
                for (int c : node.children)
                    if (c >= 0 && static_cast<std::size_t>(c) < is_child.size()) is_child[static_cast<std::size_t>(c)] = 1;
            for (std::size_t i = 0; i < model_.nodes.size(); ++i)
                if (!is_child[i]) roots.push_back(static_cast<int>(i));
        }
        return roots;
    }

    // Iterative, so that a hierarchy thousands of nodes deep cannot exhaust the stack.
    void visit(int root, const Mat4& root_parent, std::vector<char>& on_path, std::vector<char>& mesh_seen) {
        struct Frame {
            int node;
            Mat4 world;
            std::size_t next_child = 0;
        };
        std::vector<Frame> stack;
        auto enter = [&](int index, const Mat4& parent) {
            if (index < 0 || static_cast<std::size_t>(index) >= model_.nodes.size())
                fail(Error::Kind::format, "scene refers to node " + std::to_string(index) + " of " +
                                              std::to_string(model_.nodes.size()));
            const auto ui = static_cast<std::size_t>(index);
            if (on_path[ui]) fail(Error::Kind::format, "node hierarchy has a cycle through node " + std::to_string(index));
            const tinygltf::Node& node = model_.nodes[ui];
            const Mat4 world = multiply(parent, local_matrix(index));
            if (node.mesh >= 0) {
                if (static_cast<std::size_t>(node.mesh) >= model_.meshes.size())
                    fail(Error::Kind::format, "node " + std::to_string(index) + " refers to mesh " +
                                                  std::to_string(node.mesh) + " of " + std::to_string(model_.meshes.size()));
                char& seen = mesh_seen[static_cast<std::size_t>(node.mesh)];
                const bool first = seen == 0;
                if (seen < 100) ++seen;  // a count for the note; saturates well inside char
                if (first || options_.place_every_instance) {
                    // A skinned mesh ignores its node's transform (glTF spec); without posing the skin the
                    // mesh-space bind pose is the best geometry we have.
                    instances_.push_back({node.mesh, node.skin >= 0 ? kIdentity : world, index});
                }
            }
            on_path[ui] = 1;
            stack.push_back({index, world});
        };
        enter(root, root_parent);
        while (!stack.empty()) {
            Frame& top = stack.back();
            const auto& children = model_.nodes[static_cast<std::size_t>(top.node)].children;
            if (top.next_child < children.size()) {
                const int child = children[top.next_child++];
                const Mat4 world = top.world;  // `top` may move when the stack grows
                enter(child, world);
            } else {
                on_path[static_cast<std::size_t>(top.node)] = 0;
                stack.pop_back();
            }
        }
    }

    // The node's transform; a matrix or TRS member of the wrong length is an error, not identity.
    Mat4 local_matrix(int index) const {
        const tinygltf::Node& node = model_.nodes[static_cast<std::size_t>(index)];
        auto check = [&](const std::vector<double>& v, std::size_t n, const char* name) {
            if (!v.empty() && v.size() != n)
                fail(Error::Kind::format, "node " + std::to_string(index) + ": '" + name + "' has " +
                                              std::to_string(v.size()) + " numbers, not " + std::to_string(n));
            for (double x : v)
                if (!std::isfinite(x))
                    fail(Error::Kind::format, "node " + std::to_string(index) + ": '" + name + "' is not finite");
        };
        check(node.matrix, 16, "matrix");
        check(node.translation, 3, "translation");
        check(node.rotation, 4, "rotation");
        check(node.scale, 3, "scale");
        return trs_matrix(node);
    }

    int attribute(const tinygltf::Primitive& p, const char* name) const {
        const auto it = p.attributes.find(name);
        return it == p.attributes.end() ? -1 : it->second;
    }

    const tinygltf::Accessor& accessor(int index, const std::string& what) const {
        if (index < 0 || static_cast<std::size_t>(index) >= model_.accessors.size())
            fail(Error::Kind::format, what + " refers to accessor " + std::to_string(index) + " of " +
                                          std::to_string(model_.accessors.size()));
        return model_.accessors[static_cast<std::size_t>(index)];
    }

    void collect_primitives() {
        jobs_.reserve(instances_.size());
        std::size_t points = 0;
        for (const Instance& instance : instances_) {
            const auto& gm = model_.meshes[static_cast<std::size_t>(instance.mesh)];
            std::map<int, std::size_t> owner_of_accessor;  // POSITION accessor → job index (this mesh)
            for (std::size_t p = 0; p < gm.primitives.size(); ++p) {
                const tinygltf::Primitive& prim = gm.primitives[p];
                const int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
                if (mode <= TINYGLTF_MODE_LINE_STRIP) {  // points and lines carry no surface
                    mesh_.warnings.push_back("mesh " + std::to_string(instance.mesh) + " primitive " +
                                             std::to_string(p) + ": points/lines skipped");
                    continue;
                }
                PrimitiveJob job;
                job.mesh = instance.mesh;
                job.primitive = static_cast<int>(p);
                job.instance = &instance;
                if (mode > TINYGLTF_MODE_TRIANGLE_FAN) fail(Error::Kind::format, where(job) + " has unknown mode " + std::to_string(mode));
                const int position = attribute(prim, "POSITION");
                if (position < 0) fail(Error::Kind::format, where(job) + " has no POSITION attribute");
                job.count = accessor(position, where(job) + " POSITION").count;
                check_extent(position, where(job) + " POSITION");
                if (auto it = owner_of_accessor.find(position); it != owner_of_accessor.end()) {
                    const PrimitiveJob& owner = jobs_[it->second];
                    const auto& owner_prim = gm.primitives[static_cast<std::size_t>(owner.primitive)];
                    job.owns_points = false;
                    job.base = owner.base;
                    job.same_attributes = true;
                    for (const char* name : {"NORMAL", "COLOR_0", "TEXCOORD_0", "TEXCOORD_1", "JOINTS_0", "WEIGHTS_0",
                                             "JOINTS_1", "WEIGHTS_1"})
                        job.same_attributes = job.same_attributes && attribute(prim, name) == attribute(owner_prim, name);
                } else {
                    job.base = points;
                    points += job.count;
                    if (points > 0xFFFFFFFEull) fail(Error::Kind::unsupported, "more than 4 billion vertices");
                    owner_of_accessor.emplace(position, jobs_.size());
                }
                has_normals_ = has_normals_ || attribute(prim, "NORMAL") >= 0;
                has_colors_ = has_colors_ || attribute(prim, "COLOR_0") >= 0;
                if (attribute(prim, "TEXCOORD_1") >= 0) texcoord_sets_ = 2;
                else if (attribute(prim, "TEXCOORD_0") >= 0) texcoord_sets_ = std::max<std::size_t>(texcoord_sets_, 1);
                for (std::size_t set = 0;; ++set) {
                    const std::string n = std::to_string(set);
                    if (attribute(prim, ("JOINTS_" + n).c_str()) < 0 || attribute(prim, ("WEIGHTS_" + n).c_str()) < 0) break;
                    joint_sets_ = std::max(joint_sets_, set + 1);
                }
                if (prim.material >= 0 && static_cast<std::size_t>(prim.material) >= model_.materials.size())
                    fail(Error::Kind::format, where(job) + " refers to material " + std::to_string(prim.material) +
                                                  " of " + std::to_string(model_.materials.size()));
                needs_default_material_ = needs_default_material_ || prim.material < 0;
                if (options_.morph_targets) {
                    if (!jobs_.empty() && prim.targets.size() != morph_count_)
                        fail(Error::Kind::unsupported, where(job) + " has " + std::to_string(prim.targets.size()) +
                                                           " morph targets, an earlier primitive " +
                                                           std::to_string(morph_count_) + "; morphing needs the same count");
                    morph_count_ = prim.targets.size();
                    for (const auto& target : prim.targets) morph_normals_ = morph_normals_ || target.count("NORMAL") > 0;
                }
                jobs_.push_back(job);
            }
        }
        point_total_ = points;
    }

    // ---- accessors -------------------------------------------------------------------------------

    // Bounds-checked pointer to `count` elements of `element_size` bytes at `stride`.
    const std::uint8_t* view_data(int view_index, std::size_t offset, std::size_t element_size, std::size_t count,
                                  std::size_t& stride, const std::string& what) const {
        if (view_index < 0 || static_cast<std::size_t>(view_index) >= model_.bufferViews.size())
            fail(Error::Kind::format, what + " refers to bufferView " + std::to_string(view_index) + " of " +
                                          std::to_string(model_.bufferViews.size()));
        const tinygltf::BufferView& view = model_.bufferViews[static_cast<std::size_t>(view_index)];
        if (view.buffer < 0 || static_cast<std::size_t>(view.buffer) >= model_.buffers.size())
            fail(Error::Kind::format, what + ": bufferView " + std::to_string(view_index) + " refers to buffer " +
                                          std::to_string(view.buffer) + " of " + std::to_string(model_.buffers.size()));
        const auto& data = model_.buffers[static_cast<std::size_t>(view.buffer)].data;
        if (view.byteOffset > data.size() || view.byteLength > data.size() - view.byteOffset)
            fail(Error::Kind::format, what + ": bufferView " + std::to_string(view_index) + " (" +
                                          std::to_string(view.byteOffset) + " + " + std::to_string(view.byteLength) +
                                          " bytes) exceeds its buffer of " + std::to_string(data.size()) + " bytes");
        stride = view.byteStride ? view.byteStride : element_size;
        if (stride < element_size)
            fail(Error::Kind::format, what + ": byteStride " + std::to_string(stride) + " is smaller than an element (" +
                                          std::to_string(element_size) + " bytes)");
        if (count > 0) {
            const std::size_t length = view.byteLength;
            if (offset > length || element_size > length - offset ||
                count - 1 > (length - offset - element_size) / stride)
                fail(Error::Kind::format, what + ": " + std::to_string(count) + " elements at offset " +
                                              std::to_string(offset) + " exceed bufferView " + std::to_string(view_index) +
                                              " (" + std::to_string(length) + " bytes)");
        }
        return data.data() + view.byteOffset + offset;
    }

    // Checks that an accessor's elements lie inside its data before anything is allocated for it, so a
    // lying `count` is an error, not a huge allocation. An accessor without a bufferView (all zeros, plus
    // sparse values) has no data to bound it: it may not have more elements than its sparse part or
    // the largest accessor that has data.
    void check_extent(int index, const std::string& what) const {
        const tinygltf::Accessor& a = accessor(index, what);
        const std::size_t element = component_size(a.componentType) * component_count(a.type);
        if (element == 0) return;  // reported with its reason when read
        if (a.sparse.isSparse) check_sparse(a, element, what);
        if (a.bufferView >= 0) {
            std::size_t stride = 0;
            view_data(a.bufferView, a.byteOffset, element, a.count, stride, what);
            return;
        }
        std::size_t limit = a.sparse.isSparse ? static_cast<std::size_t>(a.sparse.count) : 0;
        for (const auto& other : model_.accessors)
            if (other.bufferView >= 0) limit = std::max(limit, other.count);
        if (a.count > limit)
            fail(Error::Kind::format, what + ": " + std::to_string(a.count) + " elements without a bufferView exceed "
                                          "every accessor with data (at most " + std::to_string(limit) + ")");
    }

    // A sparse part is bounded by its accessor and by the bytes its two views hold; checked before
    // anything is allocated for the accessor (a 5 KB file claiming 2e9 sparse values asked for 24 GB).
    void check_sparse(const tinygltf::Accessor& a, std::size_t element, const std::string& what) const {
        if (a.sparse.count < 1 || static_cast<std::size_t>(a.sparse.count) > a.count)
            fail(Error::Kind::format, what + ": sparse count " + std::to_string(a.sparse.count) +
                                          " is outside 1.." + std::to_string(a.count) + " (the accessor's count)");
        if (a.sparse.indices.byteOffset < 0 || a.sparse.values.byteOffset < 0)
            fail(Error::Kind::format, what + ": sparse byteOffset is negative");
        const auto count = static_cast<std::size_t>(a.sparse.count);
        const std::size_t isize = component_size(a.sparse.indices.componentType);
        if (isize == 0 || a.sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_BYTE ||
            a.sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_SHORT ||
            a.sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_INT ||
            a.sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT)
            fail(Error::Kind::format, what + ": sparse indices have an invalid component type");
        std::size_t stride = 0;
        view_data(a.sparse.indices.bufferView, static_cast<std::size_t>(a.sparse.indices.byteOffset), isize, count,
                  stride, what + " sparse indices");
        view_data(a.sparse.values.bufferView, static_cast<std::size_t>(a.sparse.values.byteOffset), element, count,
                  stride, what + " sparse values");
    }

    // All components of an accessor as floats (normalized integers mapped to [0,1] / [-1,1]),
    // sparse substitution applied. `allowed` lists the accepted component counts.
    std::vector<float> read_floats(int index, std::initializer_list<std::size_t> allowed, std::size_t& components,
                                   const std::string& what) const {
        const tinygltf::Accessor& a = accessor(index, what);
        components = component_count(a.type);
        const std::size_t csize = component_size(a.componentType);
        if (csize == 0) fail(Error::Kind::format, what + ": unsupported component type " + std::to_string(a.componentType));
        if (std::find(allowed.begin(), allowed.end(), components) == allowed.end())
            fail(Error::Kind::format, what + ": unexpected accessor type (" + std::to_string(components) + " components)");
        const std::size_t element = csize * components;
        if (a.count > std::numeric_limits<std::uint32_t>::max())
            fail(Error::Kind::unsupported, what + ": accessor with " + std::to_string(a.count) + " elements");
        check_extent(index, what);
        std::vector<float> out(a.count * components, 0.f);
        if (a.bufferView >= 0) {
            std::size_t stride = 0;
            const std::uint8_t* p = view_data(a.bufferView, a.byteOffset, element, a.count, stride, what);
            for (std::size_t i = 0; i < a.count; ++i, p += stride)
                for (std::size_t c = 0; c < components; ++c)
                    out[i * components + c] = component_value(p + c * csize, a.componentType, a.normalized);
        }
        if (a.sparse.isSparse) {
            // check_extent has validated the sparse part.
            const auto count = static_cast<std::size_t>(a.sparse.count);
            const std::size_t isize = component_size(a.sparse.indices.componentType);
            std::size_t istride = 0, vstride = 0;
            const std::uint8_t* ip = view_data(a.sparse.indices.bufferView,
                                               static_cast<std::size_t>(a.sparse.indices.byteOffset), isize, count,
                                               istride, what + " sparse indices");
            const std::uint8_t* vp = view_data(a.sparse.values.bufferView,
                                               static_cast<std::size_t>(a.sparse.values.byteOffset), element, count,
                                               vstride, what + " sparse values");
            // Sparse data is tightly packed regardless of the bufferView's stride.
            for (std::size_t s = 0; s < count; ++s) {
                const auto target = static_cast<std::size_t>(component_value(ip + s * isize, a.sparse.indices.componentType, false));
                if (target >= a.count)
                    fail(Error::Kind::format, what + ": sparse index " + std::to_string(target) + " out of range");
                for (std::size_t c = 0; c < components; ++c)
                    out[target * components + c] =
                        component_value(vp + s * element + c * csize, a.componentType, a.normalized);
            }
        }
        return out;
    }

    std::vector<std::uint32_t> read_indices(int index, const std::string& what) const {
        const tinygltf::Accessor& a = accessor(index, what);
        const int type = a.componentType;
        if (type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
            type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
            fail(Error::Kind::format, what + ": indices must be unsigned byte, short or int");
        if (a.type != TINYGLTF_TYPE_SCALAR) fail(Error::Kind::format, what + ": indices must be scalars");
        if (a.sparse.isSparse || a.bufferView < 0) {
            // Rare but legal: go through the general path (exact for integers below 2^24).
            std::size_t components = 0;
            const std::vector<float> values = read_floats(index, {1}, components, what);
            std::vector<std::uint32_t> out(values.size());
            for (std::size_t i = 0; i < values.size(); ++i) out[i] = static_cast<std::uint32_t>(values[i]);
            return out;
        }
        const std::size_t csize = component_size(type);
        std::size_t stride = 0;
        const std::uint8_t* p = view_data(a.bufferView, a.byteOffset, csize, a.count, stride, what);
        std::vector<std::uint32_t> out(a.count);
        for (std::size_t i = 0; i < a.count; ++i, p += stride) {
            if (csize == 1) out[i] = *p;
            else if (csize == 2) out[i] = load<std::uint16_t>(p);
            else out[i] = load<std::uint32_t>(p);
        }
        return out;
    }

    PrimitiveData load_primitive(const PrimitiveJob& job) const {
        const auto& prim = model_.meshes[static_cast<std::size_t>(job.mesh)].primitives[static_cast<std::size_t>(job.primitive)];
        const std::string at = where(job);
        const Mat4& m = job.instance->world;
        PrimitiveData d;
        std::size_t comps = 0;

        const std::vector<float> pos = read_floats(attribute(prim, "POSITION"), {3}, comps, at + " POSITION");
        d.positions.resize(job.count);
        for (std::size_t i = 0; i < job.count; ++i) {
            const double x = pos[3 * i], y = pos[3 * i + 1], z = pos[3 * i + 2];
            if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
                fail(Error::Kind::invalid, at + " POSITION: vertex " + std::to_string(i) + " is not finite (NaN or infinity)");
            d.positions[i] = {static_cast<float>(m[0] * x + m[4] * y + m[8] * z + m[12]),
                              static_cast<float>(m[1] * x + m[5] * y + m[9] * z + m[13]),
                              static_cast<float>(m[2] * x + m[6] * y + m[10] * z + m[14])};
        }
        auto check_count = [&](const std::vector<float>& values, std::size_t components, const char* name) {
            if (values.size() != job.count * components)
                fail(Error::Kind::format, at + " " + name + " has " + std::to_string(values.size() / components) +
                                              " elements but POSITION has " + std::to_string(job.count));
        };
        if (const int n = attribute(prim, "NORMAL"); n >= 0) {
            const std::vector<float> v = read_floats(n, {3}, comps, at + " NORMAL");
            check_count(v, 3, "NORMAL");
            const std::array<double, 9> nm = normal_matrix(m);
            d.normals.resize(job.count);
            for (std::size_t i = 0; i < job.count; ++i) {
                const double x = v[3 * i], y = v[3 * i + 1], z = v[3 * i + 2];
                double tx = nm[0] * x + nm[3] * y + nm[6] * z;
                double ty = nm[1] * x + nm[4] * y + nm[7] * z;
                double tz = nm[2] * x + nm[5] * y + nm[8] * z;
                const double len = std::sqrt(tx * tx + ty * ty + tz * tz);
                if (len > 0) {
                    tx /= len;
                    ty /= len;
                    tz /= len;
                }
                d.normals[i] = {static_cast<float>(tx), static_cast<float>(ty), static_cast<float>(tz)};
            }
        }
        if (const int c = attribute(prim, "COLOR_0"); c >= 0) {
            const std::vector<float> v = read_floats(c, {3, 4}, comps, at + " COLOR_0");
            check_count(v, comps, "COLOR_0");
            d.colors.resize(job.count);
            for (std::size_t i = 0; i < job.count; ++i)
                d.colors[i] = {v[comps * i], v[comps * i + 1], v[comps * i + 2], comps == 4 ? v[comps * i + 3] : 1.f};
        }
        d.texcoords.resize(texcoord_sets_);
        for (std::size_t set = 0; set < texcoord_sets_; ++set) {
            const std::string name = "TEXCOORD_" + std::to_string(set);
            const int t = attribute(prim, name.c_str());
            if (t < 0) continue;
            const std::vector<float> v = read_floats(t, {2}, comps, at + " " + name);
            check_count(v, 2, name.c_str());
            d.texcoords[set].resize(job.count);
            const UvTransform tf = prim.material >= 0 && static_cast<std::size_t>(prim.material) < material_uv_.size() && set < 2
                                      ? material_uv_[static_cast<std::size_t>(prim.material)][set]
                                      : UvTransform{};
            if (tf.identity()) {
                for (std::size_t i = 0; i < job.count; ++i) d.texcoords[set][i] = {v[2 * i], 1.f - v[2 * i + 1]};
            } else {
                for (std::size_t i = 0; i < job.count; ++i) {
                    const double u = v[2 * i], w = v[2 * i + 1];
                    d.texcoords[set][i] = {static_cast<float>(tf.a * u + tf.b * w + tf.c),
                                           static_cast<float>(1.0 - (tf.d * u + tf.e * w + tf.f))};
                }
            }
        }
        if (skinned_) load_influences(prim, job, at, d);
        if (options_.morph_targets) load_targets(prim, job, at, d);
        return d;
    }

    // JOINTS_n / WEIGHTS_n, joint indices moved into the merged skin (skin_base_).
    void load_influences(const tinygltf::Primitive& prim, const PrimitiveJob& job, const std::string& at,
                         PrimitiveData& d) const {
        const int skin = model_.nodes[static_cast<std::size_t>(job.instance->node)].skin;
        const std::size_t base = skin_base_.at(skin);
        const std::size_t joint_count = model_.skins[static_cast<std::size_t>(skin)].joints.size();
        d.joints.resize(joint_sets_);
        d.weights.resize(joint_sets_);
        std::size_t comps = 0;
        for (std::size_t set = 0; set < joint_sets_; ++set) {
            const std::string jn = "JOINTS_" + std::to_string(set), wn = "WEIGHTS_" + std::to_string(set);
            const int ja = attribute(prim, jn.c_str()), wa = attribute(prim, wn.c_str());
            if (ja < 0 || wa < 0) continue;
            const tinygltf::Accessor& a = accessor(ja, at + " " + jn);
            if (a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
                a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT)
                fail(Error::Kind::format, at + " " + jn + " must be unsigned byte or unsigned short");
            const std::vector<float> j = read_floats(ja, {4}, comps, at + " " + jn);
            const std::vector<float> w = read_floats(wa, {4}, comps, at + " " + wn);
            if (j.size() != 4 * job.count || w.size() != 4 * job.count)
                fail(Error::Kind::format, at + " " + jn + "/" + wn + " element count differs from POSITION's " +
                                              std::to_string(job.count));
            d.joints[set].resize(job.count);
            d.weights[set].resize(job.count);
            for (std::size_t i = 0; i < job.count; ++i) {
                for (std::size_t c = 0; c < 4; ++c) {
                    const auto joint = static_cast<std::size_t>(j[4 * i + c]);
                    const float weight = w[4 * i + c];
                    if (!std::isfinite(weight) || weight < 0)
                        fail(Error::Kind::invalid, at + " " + wn + ": vertex " + std::to_string(i) + " has a negative or non-finite weight");
                    if (joint >= joint_count && weight > 0)
                        fail(Error::Kind::format, at + " " + jn + ": vertex " + std::to_string(i) + " uses joint " +
                                                      std::to_string(joint) + " of " + std::to_string(joint_count));
                    d.joints[set][i][c] = static_cast<std::uint16_t>(joint < joint_count ? base + joint : 0);
                }
                d.weights[set][i] = {w[4 * i], w[4 * i + 1], w[4 * i + 2], w[4 * i + 3]};
            }
        }
    }

    // A mesh is imported skinned when every placed mesh instance is skinned and has JOINTS_0/WEIGHTS_0
    // and no mesh is placed twice (a static part or a second copy would need its own node, which the
    // one-mesh model cannot say). The skins the instances use are concatenated into one (skin_base_).
    void decide_skin() {
        if (joint_sets_ == 0) return;
        const bool all_skinned = std::all_of(instances_.begin(), instances_.end(), [&](const Instance& i) {
            return model_.nodes[static_cast<std::size_t>(i.node)].skin >= 0;
        });
        std::set<int> meshes;
        for (const Instance& i : instances_) meshes.insert(i.mesh);
        const bool copies = meshes.size() < instances_.size();  // place_every_instance placed one mesh twice
        if (!all_skinned || copies) {
            mesh_.warnings.push_back("skin dropped: " + std::string(copies ? "a skinned mesh is placed more than once"
                                                                           : "the scene mixes skinned and static meshes") +
                                     "; imported as a static mesh in the bind pose");
            joint_sets_ = 0;
            return;
        }
        std::size_t joints = 0;
        for (const Instance& i : instances_) {
            const int skin = model_.nodes[static_cast<std::size_t>(i.node)].skin;
            if (static_cast<std::size_t>(skin) >= model_.skins.size())
                fail(Error::Kind::format, "node " + std::to_string(i.node) + " refers to skin " + std::to_string(skin) +
                                              " of " + std::to_string(model_.skins.size()));
            if (skin_base_.count(skin)) continue;
            skin_base_[skin] = joints;
            joints += model_.skins[static_cast<std::size_t>(skin)].joints.size();
        }
        if (joints == 0 || joints > 65535) fail(Error::Kind::unsupported, std::to_string(joints) + " joints (1 to 65535 supported)");
        skinned_ = true;
    }

    // The node hierarchy (every node, same indices, meshes and cameras dropped), the merged skin and
    // every animation channel that moves a node (morph weight channels are not carried).
    void read_skeleton() {
        auto sk = std::make_shared<Skeleton>();
        const std::size_t node_count = model_.nodes.size();
        for (const tinygltf::Node& g : model_.nodes) {
            for (int c : g.children)
                if (c < 0 || static_cast<std::size_t>(c) >= node_count)
                    fail(Error::Kind::format, "node " + std::to_string(sk->nodes.size()) + " has child " +
                                                  std::to_string(c) + " of " + std::to_string(node_count));
            sk->nodes.push_back({g.name, g.children, g.translation, g.rotation, g.scale, g.matrix});
        }
        sk->roots = scene_roots();
        std::vector<std::pair<std::size_t, int>> skins;  // base, skin
        for (const auto& [skin, base] : skin_base_) skins.emplace_back(base, skin);
        std::sort(skins.begin(), skins.end());
        for (const auto& [base, skin] : skins) {
            const tinygltf::Skin& g = model_.skins[static_cast<std::size_t>(skin)];
            const std::string what = "skin " + std::to_string(skin);
            if (sk->skin_name.empty()) sk->skin_name = g.name;
            if (sk->skeleton_root < 0 && g.skeleton >= 0 && static_cast<std::size_t>(g.skeleton) < node_count)
                sk->skeleton_root = g.skeleton;
            for (int j : g.joints) {
                if (j < 0 || static_cast<std::size_t>(j) >= node_count)
                    fail(Error::Kind::format, what + " refers to node " + std::to_string(j) + " of " + std::to_string(node_count));
                sk->joints.push_back(j);
            }
            std::vector<std::array<float, 16>> ibm(g.joints.size());
            for (auto& m : ibm) m = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
            if (g.inverseBindMatrices >= 0) {
                const tinygltf::Accessor& a = accessor(g.inverseBindMatrices, what + " inverseBindMatrices");
                if (a.type != TINYGLTF_TYPE_MAT4 || a.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT ||
                    a.count != g.joints.size() || a.bufferView < 0)
                    fail(Error::Kind::format, what + ": inverseBindMatrices must be one float MAT4 per joint");
                std::size_t stride = 0;
                const std::uint8_t* p = view_data(a.bufferView, a.byteOffset, 64, a.count, stride, what + " inverseBindMatrices");
                for (std::size_t k = 0; k < a.count; ++k, p += stride) std::memcpy(ibm[k].data(), p, 64);
            }
            sk->inverse_bind_matrices.insert(sk->inverse_bind_matrices.end(), ibm.begin(), ibm.end());
        }
        for (std::size_t a = 0; a < model_.animations.size(); ++a) {
            const tinygltf::Animation& g = model_.animations[a];
            Animation anim;
            anim.name = g.name;
            std::map<int, int> sampler_of;  // glTF sampler -> kept sampler
            for (const tinygltf::AnimationChannel& ch : g.channels) {
                if (ch.target_path != "translation" && ch.target_path != "rotation" && ch.target_path != "scale") continue;
                const std::string what = "animation " + std::to_string(a) + " channel to node " + std::to_string(ch.target_node);
                if (ch.target_node < 0 || static_cast<std::size_t>(ch.target_node) >= node_count)
                    fail(Error::Kind::format, what + ": no such node");
                if (ch.sampler < 0 || static_cast<std::size_t>(ch.sampler) >= g.samplers.size())
                    fail(Error::Kind::format, what + " refers to sampler " + std::to_string(ch.sampler) + " of " +
                                                  std::to_string(g.samplers.size()));
                auto [it, inserted] = sampler_of.try_emplace(ch.sampler, static_cast<int>(anim.samplers.size()));
                if (inserted) anim.samplers.push_back(read_sampler(g.samplers[static_cast<std::size_t>(ch.sampler)],
                                                                   ch.target_path == "rotation" ? 4 : 3, what));
                anim.channels.push_back({it->second, ch.target_node, ch.target_path});
            }
            if (!anim.channels.empty()) sk->animations.push_back(std::move(anim));
        }
        mesh_.skeleton = std::move(sk);
    }

    AnimationSampler read_sampler(const tinygltf::AnimationSampler& g, int components, const std::string& what) const {
        AnimationSampler s;
        s.components = components;
        s.interpolation = g.interpolation.empty() ? "LINEAR" : g.interpolation;
        if (s.interpolation != "LINEAR" && s.interpolation != "STEP" && s.interpolation != "CUBICSPLINE")
            fail(Error::Kind::format, what + ": unknown interpolation '" + s.interpolation + "'");
        std::size_t comps = 0;
        s.input = read_floats(g.input, {1}, comps, what + " input");
        s.output = read_floats(g.output, {static_cast<std::size_t>(components)}, comps, what + " output");
        const std::size_t per_key = (s.interpolation == "CUBICSPLINE" ? 3u : 1u) * static_cast<std::size_t>(components);
        if (s.input.empty() || s.output.size() != s.input.size() * per_key)
            fail(Error::Kind::format, what + ": " + std::to_string(s.output.size() / static_cast<std::size_t>(components)) +
                                          " values for " + std::to_string(s.input.size()) + " keys");
        for (std::size_t k = 0; k < s.input.size(); ++k)
            if (!std::isfinite(s.input[k]) || (k > 0 && !(s.input[k] > s.input[k - 1])))
                fail(Error::Kind::format, what + ": key times must increase (key " + std::to_string(k) + ")");
        for (float v : s.output)
            if (!std::isfinite(v)) fail(Error::Kind::format, what + ": a value is not finite");
        return s;
    }

    // Target deltas are directions: the linear part of the world transform, no translation. A normal
    // delta is divided by the length of the transformed (unnormalised) base normal, so that adding it to
    // the stored unit normal keeps the proportions of the file's n + d.
    void load_targets(const tinygltf::Primitive& prim, const PrimitiveJob& job, const std::string& at,
                      PrimitiveData& d) const {
        const Mat4& m = job.instance->world;
        const std::array<double, 9> nm = normal_matrix(m);
        std::vector<float> base_normals;
        std::size_t comps = 0;
        if (const int n = attribute(prim, "NORMAL"); n >= 0) base_normals = read_floats(n, {3}, comps, at + " NORMAL");
        d.target_positions.assign(morph_count_, std::vector<Vec3f>(job.count));
        if (morph_normals_) d.target_normals.assign(morph_count_, std::vector<Vec3f>(job.count));
        for (std::size_t t = 0; t < prim.targets.size(); ++t) {
            const std::string what = at + " target " + std::to_string(t);
            auto read = [&](const char* name) {
                const auto it = prim.targets[t].find(name);
                if (it == prim.targets[t].end()) return std::vector<float>();
                std::vector<float> v = read_floats(it->second, {3}, comps, what + " " + name);
                if (v.size() != 3 * job.count)
                    fail(Error::Kind::format, what + " " + name + " has " + std::to_string(v.size() / 3) +
                                                  " elements but POSITION has " + std::to_string(job.count));
                for (float x : v)
                    if (!std::isfinite(x)) fail(Error::Kind::invalid, what + " " + name + " has a non-finite value");
                return v;
            };
            const std::vector<float> dp = read("POSITION");
            for (std::size_t i = 0; i < job.count && !dp.empty(); ++i) {
                const double x = dp[3 * i], y = dp[3 * i + 1], z = dp[3 * i + 2];
                d.target_positions[t][i] = {static_cast<float>(m[0] * x + m[4] * y + m[8] * z),
                                            static_cast<float>(m[1] * x + m[5] * y + m[9] * z),
                                            static_cast<float>(m[2] * x + m[6] * y + m[10] * z)};
            }
            const std::vector<float> dn = read("NORMAL");
            for (std::size_t i = 0; i < job.count && !dn.empty() && !base_normals.empty(); ++i) {
                auto apply = [&](const float* v) {
                    return std::array<double, 3>{nm[0] * v[0] + nm[3] * v[1] + nm[6] * v[2],
                                                 nm[1] * v[0] + nm[4] * v[1] + nm[7] * v[2],
                                                 nm[2] * v[0] + nm[5] * v[1] + nm[8] * v[2]};
                };
                const auto b = apply(&base_normals[3 * i]);
                const double len = std::sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
                const double inv = len > 0 ? 1.0 / len : 1.0;
                const auto e = apply(&dn[3 * i]);
                d.target_normals[t][i] = {static_cast<float>(e[0] * inv), static_cast<float>(e[1] * inv),
                                          static_cast<float>(e[2] * inv)};
            }
        }
    }

    // Keys of the first weights channel whose node places a morphing mesh.
    void read_weights_animation() {
        GltfMorphTargets& out = *options_.morph_targets;
        if (morph_count_ == 0) return;
        for (const tinygltf::Animation& anim : model_.animations)
            for (const tinygltf::AnimationChannel& ch : anim.channels) {
                if (ch.target_path != "weights") continue;
                const bool placed = std::any_of(instances_.begin(), instances_.end(),
                                                [&](const Instance& i) { return i.node == ch.target_node; });
                if (!placed) continue;
                const std::string what = "animation '" + anim.name + "' weights";
                if (ch.sampler < 0 || static_cast<std::size_t>(ch.sampler) >= anim.samplers.size())
                    fail(Error::Kind::format, what + " refers to sampler " + std::to_string(ch.sampler) + " of " +
                                                  std::to_string(anim.samplers.size()));
                const tinygltf::AnimationSampler& sampler = anim.samplers[static_cast<std::size_t>(ch.sampler)];
                std::size_t comps = 0;
                const std::vector<float> times = read_floats(sampler.input, {1}, comps, what + " input");
                const std::vector<float> values = read_floats(sampler.output, {1}, comps, what + " output");
                const std::string interpolation = sampler.interpolation.empty() ? "LINEAR" : sampler.interpolation;
                const std::size_t per_key = (interpolation == "CUBICSPLINE" ? 3 : 1) * morph_count_;
                if (times.empty() || values.size() != times.size() * per_key)
                    fail(Error::Kind::format, what + ": " + std::to_string(values.size()) + " values for " +
                                                  std::to_string(times.size()) + " keys and " +
                                                  std::to_string(morph_count_) + " targets");
                for (std::size_t k = 0; k < times.size(); ++k) {
                    if (!std::isfinite(times[k]) || (k > 0 && !(times[k] > times[k - 1])))
                        fail(Error::Kind::format, what + ": key times must increase (key " + std::to_string(k) + ")");
                    const std::size_t first = k * per_key + (per_key > morph_count_ ? morph_count_ : 0);
                    out.key_weights.emplace_back(values.begin() + static_cast<std::ptrdiff_t>(first),
                                                 values.begin() + static_cast<std::ptrdiff_t>(first + morph_count_));
                }
                out.key_times = times;
                out.interpolation = interpolation;
                return;
            }
    }

    // Store vertex `i` of `d` at mesh vertex `target` (which already exists).
    void store(const PrimitiveData& d, std::size_t i, std::size_t target) {
        if (GltfMorphTargets* mt = options_.morph_targets) {
            for (std::size_t t = 0; t < mt->position_deltas.size(); ++t) {
                mt->position_deltas[t][target] = d.target_positions[t][i];
                if (!mt->normal_deltas.empty()) mt->normal_deltas[t][target] = d.target_normals[t][i];
            }
        }
        mesh_.positions[target] = d.positions[i];
        if (has_normals_) mesh_.normals[target] = d.normals.empty() ? Vec3f{} : d.normals[i];
        if (has_colors_) mesh_.colors[target] = d.colors.empty() ? Vec4f{1, 1, 1, 1} : d.colors[i];
        for (std::size_t set = 0; set < texcoord_sets_; ++set)
            mesh_.texcoords[set][target] = d.texcoords[set].empty() ? Vec2f{} : d.texcoords[set][i];
        for (std::size_t set = 0; set < mesh_.joints.size(); ++set) {
            mesh_.joints[set][target] = d.joints[set].empty() ? Joints4{0, 0, 0, 0} : d.joints[set][i];
            mesh_.weights[set][target] = d.weights[set].empty() ? Vec4f{} : d.weights[set][i];
        }
    }

    std::size_t append_vertex(std::uint32_t point) {
        const std::size_t v = mesh_.positions.size();
        if (v >= 0xFFFFFFFFull) fail(Error::Kind::unsupported, "more than 4 billion vertices");
        mesh_.positions.emplace_back();
        mesh_.position_ids.push_back(point);
        if (has_normals_) mesh_.normals.emplace_back();
        if (has_colors_) mesh_.colors.emplace_back();
        for (auto& set : mesh_.texcoords) set.emplace_back();
        for (auto& set : mesh_.joints) set.emplace_back();
        for (auto& set : mesh_.weights) set.emplace_back();
        if (GltfMorphTargets* mt = options_.morph_targets) {
            for (auto& t : mt->position_deltas) t.emplace_back();
            for (auto& t : mt->normal_deltas) t.emplace_back();
        }
        return v;
    }

    // Triangles of one primitive in local vertex indices (strips and fans converted).
    std::vector<std::uint32_t> local_triangles(const PrimitiveJob& job) const {
        const auto& prim = model_.meshes[static_cast<std::size_t>(job.mesh)].primitives[static_cast<std::size_t>(job.primitive)];
        const std::string at = where(job);
        std::vector<std::uint32_t> idx;
        if (prim.indices >= 0) {
            idx = read_indices(prim.indices, at + " indices");
        } else {
            idx.resize(job.count);
            for (std::size_t i = 0; i < job.count; ++i) idx[i] = static_cast<std::uint32_t>(i);
        }
        for (std::size_t i = 0; i < idx.size(); ++i)
            if (idx[i] >= job.count)
                fail(Error::Kind::invalid, at + ": index " + std::to_string(idx[i]) + " at position " + std::to_string(i) +
                                               " is out of range (" + std::to_string(job.count) + " vertices)");
        const int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
        if (mode == TINYGLTF_MODE_TRIANGLES) {
            if (idx.size() % 3 != 0)
                fail(Error::Kind::format, at + ": " + std::to_string(idx.size()) + " indices is not a multiple of 3");
            return idx;
        }
        std::vector<std::uint32_t> tri;
        if (idx.size() < 3) return tri;
        tri.reserve(3 * (idx.size() - 2));
        for (std::size_t i = 0; i + 2 < idx.size(); ++i) {
            std::uint32_t a, b, c;
            if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
                a = idx[i];
                b = idx[i + 1 + (i % 2)];
                c = idx[i + 2 - (i % 2)];
                if (a == b || b == c || a == c) continue;  // restart / degenerate joints of a strip
            } else {
                a = idx[i + 1];
                b = idx[i + 2];
                c = idx[0];
            }
            tri.insert(tri.end(), {a, b, c});
        }
        return tri;
    }

    TextureRef texture_ref(int texture, int texcoord, const std::string& what) const {
        TextureRef ref;
        if (texture < 0) return ref;
        if (static_cast<std::size_t>(texture) >= model_.textures.size())
            fail(Error::Kind::format, what + " refers to texture " + std::to_string(texture) + " of " +
                                          std::to_string(model_.textures.size()));
        ref.texcoord_set = std::max(texcoord, 0);
        const int source = model_.textures[static_cast<std::size_t>(texture)].source;
        if (source < 0) return ref;  // image only through an extension (KTX2, WebP): not supported
        if (static_cast<std::size_t>(source) >= model_.images.size())
            fail(Error::Kind::format, what + " refers to image " + std::to_string(source) + " of " +
                                          std::to_string(model_.images.size()));
        const tinygltf::Image& image = model_.images[static_cast<std::size_t>(source)];
        ref.mime_type = image.mimeType;
        if (image.bufferView >= 0) {
            const std::string label = "image " + std::to_string(source);
            if (static_cast<std::size_t>(image.bufferView) >= model_.bufferViews.size())
                fail(Error::Kind::format, label + " refers to bufferView " + std::to_string(image.bufferView) + " of " +
                                              std::to_string(model_.bufferViews.size()));
            const tinygltf::BufferView& view = model_.bufferViews[static_cast<std::size_t>(image.bufferView)];
            if (view.buffer < 0 || static_cast<std::size_t>(view.buffer) >= model_.buffers.size())
                fail(Error::Kind::format, label + ": bufferView refers to a missing buffer");
            const auto& buffer = model_.buffers[static_cast<std::size_t>(view.buffer)].data;
            if (view.byteOffset > buffer.size() || view.byteLength > buffer.size() - view.byteOffset)
                fail(Error::Kind::format, label + ": bufferView exceeds its buffer");
            const auto first = buffer.begin() + static_cast<std::ptrdiff_t>(view.byteOffset);
            ref.bytes.assign(first, first + static_cast<std::ptrdiff_t>(view.byteLength));
        } else if (!image.uri.empty()) {
            ref.path = url_decode(image.uri);
        } else {
            ref.bytes.assign(image.image.begin(), image.image.end());
        }
        if (ref.mime_type.empty() && !ref.bytes.empty()) ref.mime_type = sniff_mime(ref.bytes);
        if (ref.mime_type.empty() && !ref.path.empty()) {
            const std::string ext = lower(fs::path(ref.path).extension().string());
            if (ext == ".png") ref.mime_type = "image/png";
            else if (ext == ".jpg" || ext == ".jpeg") ref.mime_type = "image/jpeg";
        }
        return ref;
    }

    // KHR_texture_transform is baked into the texture coordinates of the primitives using the material
    // (the Mesh and the writers have no per-texture transform). One transform per UV set: when the
    // textures sampling a set disagree, the base colour texture's (first in this order) wins, with a
    // warning. Its `texCoord` override moves the texture to that set.
    void bake_texture_transforms(const tinygltf::Material& g, Material& m, const std::string& what) {
        const auto& pbr = g.pbrMetallicRoughness;
        const std::array<std::pair<const tinygltf::ExtensionMap*, TextureRef*>, 5> infos = {{
            {&pbr.baseColorTexture.extensions, &m.base_color_texture},
            {&pbr.metallicRoughnessTexture.extensions, &m.metallic_roughness_texture},
            {&g.normalTexture.extensions, &m.normal_texture},
            {&g.occlusionTexture.extensions, &m.occlusion_texture},
            {&g.emissiveTexture.extensions, &m.emissive_texture}}};
        std::array<UvTransform, 2> per_set{};
        std::array<bool, 2> claimed{false, false};
        for (const auto& [extensions, ref] : infos) {
            if (ref->empty()) continue;
            UvTransform t;
            if (const auto it = extensions->find("KHR_texture_transform"); it != extensions->end() && it->second.IsObject()) {
                const tinygltf::Value& x = it->second;
                const double r = number_at(x, "rotation", -1, 0), cs = std::cos(r), sn = std::sin(r);
                const double sx = number_at(x, "scale", 0, 1), sy = number_at(x, "scale", 1, 1);
                t = {cs * sx, sn * sy, number_at(x, "offset", 0, 0), -sn * sx, cs * sy, number_at(x, "offset", 1, 0)};
                const double set = number_at(x, "texCoord", -1, ref->texcoord_set);
                if (set >= 0 && set <= 1) ref->texcoord_set = static_cast<int>(set);
            }
            if (ref->texcoord_set < 0 || ref->texcoord_set > 1) continue;
            const auto set = static_cast<std::size_t>(ref->texcoord_set);
            if (!claimed[set]) {
                claimed[set] = true;
                per_set[set] = t;
            } else if (!(per_set[set] == t)) {
                mesh_.warnings.push_back(what + ": textures sampling TEXCOORD_" + std::to_string(set) +
                                         " have different KHR_texture_transforms; the first is applied to all");
            }
        }
        material_uv_.push_back(per_set);
    }

    void convert_materials() {
        for (std::size_t i = 0; i < model_.materials.size(); ++i) {
            const tinygltf::Material& g = model_.materials[i];
            const std::string what = "material " + std::to_string(i);
            Material m;
            m.name = g.name.empty() ? "material_" + std::to_string(i) : g.name;
            const auto& pbr = g.pbrMetallicRoughness;
            if (pbr.baseColorFactor.size() == 4)
                m.base_color = {static_cast<float>(pbr.baseColorFactor[0]), static_cast<float>(pbr.baseColorFactor[1]),
                                static_cast<float>(pbr.baseColorFactor[2]), static_cast<float>(pbr.baseColorFactor[3])};
            m.metallic = static_cast<float>(pbr.metallicFactor);
            m.roughness = static_cast<float>(pbr.roughnessFactor);
            m.base_color_texture = texture_ref(pbr.baseColorTexture.index, pbr.baseColorTexture.texCoord, what);
            m.metallic_roughness_texture =
                texture_ref(pbr.metallicRoughnessTexture.index, pbr.metallicRoughnessTexture.texCoord, what);
            m.normal_texture = texture_ref(g.normalTexture.index, g.normalTexture.texCoord, what);
            m.occlusion_texture = texture_ref(g.occlusionTexture.index, g.occlusionTexture.texCoord, what);
            m.emissive_texture = texture_ref(g.emissiveTexture.index, g.emissiveTexture.texCoord, what);
            bake_texture_transforms(g, m, what);
            if (g.emissiveFactor.size() == 3)
                m.emissive = {static_cast<float>(g.emissiveFactor[0]), static_cast<float>(g.emissiveFactor[1]),
                              static_cast<float>(g.emissiveFactor[2])};
            m.double_sided = g.doubleSided;
            mesh_.materials.push_back(std::move(m));
        }
        if (needs_default_material_) {
            Material m;
            m.name = "default";
            default_material_ = static_cast<std::uint32_t>(mesh_.materials.size());
            mesh_.materials.push_back(std::move(m));
        }
    }

    void build() {
        // Stored points first: every owned POSITION accessor, in scene order.
        mesh_.positions.resize(point_total_);
        mesh_.position_ids.resize(point_total_);
        for (std::size_t i = 0; i < point_total_; ++i) mesh_.position_ids[i] = static_cast<std::uint32_t>(i);
        if (has_normals_) mesh_.normals.assign(point_total_, Vec3f{});
        if (has_colors_) mesh_.colors.assign(point_total_, Vec4f{1, 1, 1, 1});
        mesh_.texcoords.assign(texcoord_sets_, std::vector<Vec2f>(point_total_));
        if (skinned_) {
            mesh_.joints.assign(joint_sets_, std::vector<Joints4>(point_total_, Joints4{0, 0, 0, 0}));
            mesh_.weights.assign(joint_sets_, std::vector<Vec4f>(point_total_));
        }
        if (GltfMorphTargets* mt = options_.morph_targets) {
            mt->position_deltas.assign(morph_count_, std::vector<Vec3f>(point_total_));
            if (morph_normals_ && has_normals_) mt->normal_deltas.assign(morph_count_, std::vector<Vec3f>(point_total_));
            mt->names.assign(morph_count_, std::string());
            mt->default_weights.assign(morph_count_, 0.f);
            if (!instances_.empty()) {
                const auto& gm = model_.meshes[static_cast<std::size_t>(instances_.front().mesh)];
                for (std::size_t t = 0; t < morph_count_ && t < gm.weights.size(); ++t)
                    mt->default_weights[t] = static_cast<float>(gm.weights[t]);
                // Target names: the common "targetNames" extra, else the POSITION accessor's name.
                if (gm.extras.Has("targetNames") && gm.extras.Get("targetNames").IsArray()) {
                    const auto& names = gm.extras.Get("targetNames");
                    for (std::size_t t = 0; t < morph_count_ && t < names.ArrayLen(); ++t)
                        if (names.Get(static_cast<int>(t)).IsString()) mt->names[t] = names.Get(static_cast<int>(t)).Get<std::string>();
                }
                for (std::size_t t = 0; t < morph_count_ && !gm.primitives.empty(); ++t) {
                    if (!mt->names[t].empty() || t >= gm.primitives.front().targets.size()) continue;
                    const auto& target = gm.primitives.front().targets[t];
                    const auto it = target.find("POSITION");
                    if (it != target.end() && it->second >= 0 && static_cast<std::size_t>(it->second) < model_.accessors.size())
                        mt->names[t] = model_.accessors[static_cast<std::size_t>(it->second)].name;
                }
            }
        }

        const double steps = static_cast<double>(std::max<std::size_t>(jobs_.size(), 1)) * 2;
        for (std::size_t j = 0; j < jobs_.size(); ++j) {
            check_progress(progress_, 0.2 + 0.8 * static_cast<double>(j) / steps, "Reading glTF");
            const PrimitiveJob& job = jobs_[j];
            if (!job.owns_points) continue;
            const PrimitiveData d = load_primitive(job);
            for (std::size_t i = 0; i < job.count; ++i) store(d, i, job.base + i);
        }
        // Then triangles; primitives that share a POSITION accessor with different attributes add wedges.
        for (std::size_t j = 0; j < jobs_.size(); ++j) {
            check_progress(progress_, 0.6 + 0.8 * static_cast<double>(j) / steps, "Reading glTF");
            const PrimitiveJob& job = jobs_[j];
            std::vector<std::uint32_t> tri = local_triangles(job);
            const auto& prim = model_.meshes[static_cast<std::size_t>(job.mesh)].primitives[static_cast<std::size_t>(job.primitive)];
            if (job.owns_points || job.same_attributes) {
                for (auto& v : tri) v = static_cast<std::uint32_t>(job.base + v);
            } else {
                const PrimitiveData d = load_primitive(job);
                std::unordered_map<std::uint32_t, std::uint32_t> wedge;
                for (auto& v : tri) {
                    auto [it, inserted] = wedge.try_emplace(v, 0u);
                    if (inserted) {
                        const std::size_t w = append_vertex(static_cast<std::uint32_t>(job.base + v));
                        store(d, v, w);
                        it->second = static_cast<std::uint32_t>(w);
                    }
                    v = it->second;
                }
            }
            if (determinant3(job.instance->world) < 0)
                for (std::size_t t = 0; t + 2 < tri.size(); t += 3) std::swap(tri[t + 1], tri[t + 2]);
            mesh_.indices.insert(mesh_.indices.end(), tri.begin(), tri.end());
            const std::uint32_t material = prim.material >= 0 ? static_cast<std::uint32_t>(prim.material) : default_material_;
            mesh_.face_materials.insert(mesh_.face_materials.end(), tri.size() / 3, material);
        }
        check_progress(progress_, 1.0, "Reading glTF");
    }

    std::string path_;
    const tinygltf::Model& model_;
    Progress* progress_;
    GltfReadOptions options_;
    Mesh mesh_;
    std::vector<Instance> instances_;
    std::vector<PrimitiveJob> jobs_;
    std::size_t point_total_ = 0;
    bool has_normals_ = false;
    bool has_colors_ = false;
    std::size_t texcoord_sets_ = 0;
    std::size_t joint_sets_ = 0;           // JOINTS_n/WEIGHTS_n pairs (the most any primitive has)
    bool skinned_ = false;                 // decide_skin
    std::map<int, std::size_t> skin_base_;  // glTF skin -> its first joint in the merged skin
    std::vector<std::array<UvTransform, 2>> material_uv_;  // [material][set], baked into the UVs
    std::size_t morph_count_ = 0;
    bool morph_normals_ = false;
    bool needs_default_material_ = false;
    std::uint32_t default_material_ = 0;
};

std::vector<unsigned char> read_file(const std::string& path) {
    check_input_file(path, "a glTF file");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw_error(Error::Kind::io, path, "cannot open");
    std::vector<unsigned char> data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in.bad()) throw_error(Error::Kind::io, path, "read error");
    return data;
}

}  // namespace

Mesh read_gltf(const std::string& path, Progress* progress, const GltfReadOptions& options) {
    check_progress(progress, 0.0, "Reading glTF");
    const std::vector<unsigned char> data = read_file(path);
    if (data.size() > std::numeric_limits<unsigned int>::max())
        throw_error(Error::Kind::unsupported, path, "files over 4 GiB are not supported");
    const bool binary = data.size() >= 4 && std::memcmp(data.data(), "glTF", 4) == 0;
    if (!binary && lower(fs::path(path).extension().string()) == ".glb")
        throw_error(Error::Kind::format, path, "not a binary glTF (missing 'glTF' magic)");
    if (binary && data.size() >= 12) {
        // The GLB header states the version and the total length; checking them first turns tinygltf's
        // generic "Invalid glTF binary" (or a silent read of another version) into a reason to act on.
        std::uint32_t version = 0, declared = 0;
        std::memcpy(&version, data.data() + 4, 4);
        std::memcpy(&declared, data.data() + 8, 4);
        if (version != 2)
            throw_error(Error::Kind::unsupported, path,
                        "GLB container version " + std::to_string(version) + " is not supported (only version 2)");
        if (declared > data.size())
            throw_error(Error::Kind::format, path,
                        "truncated GLB: the header announces " + std::to_string(declared) + " bytes, the file has " +
                            std::to_string(data.size()));
    }
    if (!binary) {
        check_gltf_json(path, reinterpret_cast<const char*>(data.data()), data.size());
    } else if (data.size() >= 20) {
        std::uint32_t json_length = 0;
        std::memcpy(&json_length, data.data() + 12, 4);
        if (json_length <= data.size() - 20) check_gltf_json(path, reinterpret_cast<const char*>(data.data()) + 20, json_length);
    }
    const std::string base_dir = fs::path(path).parent_path().string();

    tinygltf::Model model;
    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(keep_image_undecoded, nullptr);
    loader.SetFsCallbacks({&tinygltf::FileExists, &tinygltf::ExpandFilePath, &read_regular_file, &tinygltf::WriteWholeFile, nullptr});
    std::string err, warn;
    bool ok = false;
    try {
        const auto size = static_cast<unsigned int>(data.size());
        ok = binary ? loader.LoadBinaryFromMemory(&model, &err, &warn, data.data(), size, base_dir)
                    : loader.LoadASCIIFromString(&model, &err, &warn, reinterpret_cast<const char*>(data.data()),
                                                 size, base_dir);
    } catch (const std::exception& e) {
        err += e.what();
        ok = false;
    }
    if (!ok) {
        const std::string reason = one_line(err.empty() ? warn : err);
        if (reason.find("File not found") != std::string::npos || reason.find("File read error") != std::string::npos)
            throw_error(Error::Kind::io, path, "a referenced buffer file is missing or unreadable: " + reason);
        if (binary && data.size() < 20) throw_error(Error::Kind::format, path, "truncated GLB (" + reason + ")");
        throw_error(Error::Kind::format, path, "cannot parse glTF: " + (reason.empty() ? "unknown error" : reason));
    }
    check_progress(progress, 0.2, "Reading glTF");
    GltfImporter importer(path, model, progress, options);
    Mesh mesh = importer.run();
    add_warning_lines(mesh, warn);
    std::error_code ec;
    const fs::path dir = fs::path(path).parent_path().empty() ? fs::path(".") : fs::path(path).parent_path();
    const fs::path absolute = fs::absolute(dir, ec);
    mesh.source_dir = ec ? dir.string() : absolute.lexically_normal().string();
    return mesh;
}

}  // namespace lodforge

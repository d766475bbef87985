// glTF 2.0 binary writer for LOD chains.
//
// Follows the glTF 2.0 specification (Khronos, "glTF 2.0 Specification", sections 3.6 binary data
// storage, 3.7 geometry, 3.9 materials, 4.4 GLB file format) and the vendor extension MSFT_lod with
// its MSFT_screencoverage extras (Microsoft, extensions/2.0/Vendor/MSFT_lod). The JSON chunk is built
// with nlohmann::ordered_json (insertion order, shortest round-trip numbers), so the same input always
// gives the same bytes; the GLB container (a 12-byte header and two chunks) is simple enough to write
// here. Everything in the binary chunk starts on a 4-byte boundary.
#include "lodforge/io/gltf_writer.h"

#include "lodforge/io/atomic_file.h"
#include "lodforge/error.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <optional>
#include <tuple>

namespace lodforge {
namespace {

using nlohmann::ordered_json;

constexpr int kFloat = 5126, kUnsignedShort = 5123, kUnsignedInt = 5125, kByte = 5120, kShort = 5122;
constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;

// The vertex arrays of one Mesh, drawn by one or more levels.
struct VertexSource {
    const Mesh* mesh = nullptr;
    // bufferViews of the converted arrays (-1 = absent)
    int position_view = -1, normal_view = -1, color_view = -1;
    std::vector<int> texcoord_views;
    std::vector<int> joint_views, weight_views;  // per JOINTS_n / WEIGHTS_n set
    // accessors already made, by vertex count (levels of a shared buffer use prefixes)
    std::map<std::uint32_t, ordered_json> attributes_by_count;
};

// One level: triangles over a prefix [0, vertex_count) of a source.
struct LevelSpec {
    std::size_t source = 0;
    std::uint32_t vertex_count = 0;
    const std::uint32_t* indices = nullptr;
    std::size_t index_count = 0;
    const std::uint32_t* face_materials = nullptr;  // nullptr: every triangle uses material 0 (if any)
};

bool same_texture(const TextureRef& a, const TextureRef& b) {
    return a.path == b.path && a.bytes == b.bytes && a.mime_type == b.mime_type && a.texcoord_set == b.texcoord_set;
}

bool same_material(const Material& a, const Material& b) {
    return a.name == b.name && a.base_color == b.base_color && a.metallic == b.metallic &&
           a.roughness == b.roughness && a.emissive == b.emissive && a.double_sided == b.double_sided &&
           same_texture(a.base_color_texture, b.base_color_texture) &&
           same_texture(a.normal_texture, b.normal_texture) &&
           same_texture(a.metallic_roughness_texture, b.metallic_roughness_texture) &&
           same_texture(a.occlusion_texture, b.occlusion_texture) &&
           same_texture(a.emissive_texture, b.emissive_texture);
}

std::string sniff_mime(const std::vector<std::uint8_t>& b) {
    if (b.size() >= 8 && b[0] == 0x89 && b[1] == 'P' && b[2] == 'N' && b[3] == 'G') return "image/png";
    if (b.size() >= 3 && b[0] == 0xFF && b[1] == 0xD8 && b[2] == 0xFF) return "image/jpeg";
    return {};
}

class GlbBuilder {
public:
    GlbBuilder(const GlbOptions& options, Progress* progress) : options_(options), progress_(progress) {}

    std::vector<std::uint8_t> build(std::vector<VertexSource> sources, const std::vector<LevelSpec>& levels,
                                    GlbResult* result) {
        sources_ = std::move(sources);
        if (levels.empty()) throw_error(Error::Kind::argument, where_, "no levels to write");
        if (!options_.screen_coverage.empty() && options_.screen_coverage.size() != levels.size())
            throw_error(Error::Kind::argument, where_,
                        "screen_coverage has " + std::to_string(options_.screen_coverage.size()) +
                            " values for " + std::to_string(levels.size()) + " levels");
        for (const VertexSource& s : sources_) check_source(*s.mesh);
        check_skin();
        if (morph_) check_morph();
        if (quantized()) prepare_quantization();

        doc_["asset"] = {{"generator", options_.generator}, {"version", "2.0"}};
        if (levels.size() > 1) doc_["extensionsUsed"] = ordered_json::array({"MSFT_lod"});
        if (quantized()) {
            doc_["extensionsUsed"].push_back("KHR_mesh_quantization");
            doc_["extensionsRequired"] = ordered_json::array({"KHR_mesh_quantization"});
        }
        doc_["scene"] = 0;
        ordered_json scene_nodes = ordered_json::array({0});
        // The skeleton's nodes follow the levels' (node k is level k, as without a skin).
        if (skeleton_)
            for (int root : skeleton_->roots) scene_nodes.push_back(levels.size() + static_cast<std::size_t>(root));
        doc_["scenes"] = ordered_json::array({{{"nodes", scene_nodes}}});

        ordered_json nodes = ordered_json::array();
        ordered_json meshes = ordered_json::array();
        for (std::size_t k = 0; k < levels.size(); ++k) {
            check_progress(progress_, static_cast<double>(k) / static_cast<double>(levels.size()), "writing glb");
            const std::string name = options_.name + "_LOD" + std::to_string(k);
            ordered_json mesh = {{"name", name}, {"primitives", level_primitives(levels[k], k)}};
            if (morph_) add_mesh_weights(mesh);
            meshes.push_back(std::move(mesh));
            ordered_json node = {{"name", name}, {"mesh", k}};
            if (skeleton_) node["skin"] = 0;
            if (quantized()) {
                // The dequantisation of the targets (and so of the base they are added to): uniform,
                // so normals keep their directions (KHR_mesh_quantization).
                node["translation"] = {q_translation_.x, q_translation_.y, q_translation_.z};
                node["scale"] = {q_scale_, q_scale_, q_scale_};
            }
            if (k == 0 && levels.size() > 1) {
                ordered_json ids = ordered_json::array();
                for (std::size_t j = 1; j < levels.size(); ++j) ids.push_back(j);
                node["extensions"] = {{"MSFT_lod", {{"ids", ids}}}};
                if (!options_.screen_coverage.empty())
                    node["extras"] = {{"MSFT_screencoverage", options_.screen_coverage}};
            }
            nodes.push_back(node);
        }
        if (skeleton_) add_skeleton(nodes, levels.size());
        doc_["nodes"] = nodes;
        doc_["meshes"] = meshes;
        if (morph_ && !morph_->key_times.empty()) doc_["animations"] = animation(levels.size());
        if (skeleton_ && !skeleton_->animations.empty()) {
            if (!doc_.contains("animations")) doc_["animations"] = ordered_json::array();
            for (const Animation& a : skeleton_->animations) doc_["animations"].push_back(skeleton_animation(a, levels.size()));
        }
        if (!materials_.empty()) doc_["materials"] = materials_;
        if (!textures_.empty()) {
            doc_["textures"] = textures_;
            doc_["images"] = images_;
            // One sampler: repeat wrapping and trilinear filtering, what the sources assume by default.
            doc_["samplers"] = ordered_json::array({{{"magFilter", 9729}, {"minFilter", 9987},
                                                     {"wrapS", 10497}, {"wrapT", 10497}}});
        }
        doc_["accessors"] = accessors_;
        doc_["bufferViews"] = views_;
        doc_["buffers"] = ordered_json::array({{{"byteLength", bin_.size()}}});
        check_progress(progress_, 1.0, "writing glb");

        std::vector<std::uint8_t> glb = container();
        if (result) {
            result->bytes = glb.size();
            result->levels = levels.size();
            result->primitives = primitives_;
            result->materials = materials_.size();
            result->images = images_.size();
            result->warnings = warnings_;
        }
        return glb;
    }

private:
    void check_source(const Mesh& m) const {
        const std::size_t n = m.vertex_count();
        if (n == 0) throw_error(Error::Kind::invalid, where_, "a level has no vertices");
        if ((m.has_normals() && m.normals.size() != n) || (m.has_colors() && m.colors.size() != n))
            throw_error(Error::Kind::invalid, where_, "attribute array size differs from the vertex count");
        for (const auto& set : m.texcoords)
            if (set.size() != n) throw_error(Error::Kind::invalid, where_, "texcoord set size differs from the vertex count");
        if (m.joints.size() != m.weights.size())
            throw_error(Error::Kind::invalid, where_, "joint and weight set counts differ");
        for (std::size_t s = 0; s < m.joints.size(); ++s)
            if (m.joints[s].size() != n || m.weights[s].size() != n)
                throw_error(Error::Kind::invalid, where_, "joint or weight set size differs from the vertex count");
        for (std::size_t i = 0; i < n; ++i)
            if (!is_finite(m.positions[i]))
                throw_error(Error::Kind::invalid, where_, "vertex " + std::to_string(i) + " has a non-finite position");
    }

    void align(std::size_t to = 4) {
        while (bin_.size() % to) bin_.push_back(0);
    }

    int add_view(const void* data, std::size_t bytes, int target, int stride) {
        align();
        ordered_json view = {{"buffer", 0}, {"byteOffset", bin_.size()}, {"byteLength", bytes}};
        // Several accessors (one per level) read the same vertex views, which glTF only allows with an
        // explicit stride.
        if (stride > 0) view["byteStride"] = stride;
        if (target > 0) view["target"] = target;
        const auto* p = static_cast<const std::uint8_t*>(data);
        bin_.insert(bin_.end(), p, p + bytes);
        views_.push_back(view);
        return static_cast<int>(views_.size()) - 1;
    }

    int add_accessor(ordered_json accessor) {
        accessors_.push_back(std::move(accessor));
        return static_cast<int>(accessors_.size()) - 1;
    }

    template <typename T>
    int add_vertex_view(const std::vector<T>& values) {
        return add_view(values.data(), values.size() * sizeof(T), kArrayBuffer, static_cast<int>(sizeof(T)));
    }

    void write_source(VertexSource& s) {
        const Mesh& m = *s.mesh;
        s.position_view = add_vertex_view(quantized() ? q_base_ : m.positions);
        if (m.has_normals()) {
            // glTF requires unit normals; an unusable one (zero, NaN) gets +Z rather than failing the file.
            std::vector<Vec3f> unit(m.normals.size());
            for (std::size_t i = 0; i < unit.size(); ++i) {
                const Vec3f nrm = m.normals[i];
                const float len = length(nrm);
                unit[i] = (std::isfinite(len) && len > 1e-20f) ? nrm * (1.f / len) : Vec3f{0, 0, 1};
            }
            s.normal_view = add_vertex_view(unit);
        }
        if (m.has_colors()) {
            std::vector<Vec4f> c(m.colors.size());
            auto clamp01 = [](float v) { return std::isfinite(v) ? std::clamp(v, 0.f, 1.f) : 0.f; };
            for (std::size_t i = 0; i < c.size(); ++i)
                c[i] = {clamp01(m.colors[i].x), clamp01(m.colors[i].y), clamp01(m.colors[i].z), clamp01(m.colors[i].w)};
            s.color_view = add_vertex_view(c);
        }
        for (const auto& set : m.texcoords) {
            // The mesh model keeps OBJ's v-up convention (docs/decisions.md); glTF's origin is top-left.
            std::vector<Vec2f> uv(set.size());
            for (std::size_t i = 0; i < uv.size(); ++i) uv[i] = {set[i].x, 1.f - set[i].y};
            s.texcoord_views.push_back(add_vertex_view(uv));
        }
        if (!skeleton_) return;
        for (const auto& set : m.joints) s.joint_views.push_back(add_vertex_view(set));
        for (const auto& set : m.weights) s.weight_views.push_back(add_vertex_view(set));
    }

    const ordered_json& attributes(std::size_t source_index, std::uint32_t count) {
        VertexSource& s = sources_[source_index];
        if (s.position_view < 0) write_source(s);
        if (auto it = s.attributes_by_count.find(count); it != s.attributes_by_count.end()) return it->second;
        const Mesh& m = *s.mesh;
        const std::vector<Vec3f>& positions = quantized() ? q_base_ : m.positions;
        Bounds b;
        for (std::uint32_t i = 0; i < count; ++i) b.add(positions[i]);
        ordered_json attrs;
        attrs["POSITION"] = add_accessor({{"bufferView", s.position_view}, {"componentType", kFloat}, {"count", count},
                                          {"type", "VEC3"}, {"min", {b.min.x, b.min.y, b.min.z}},
                                          {"max", {b.max.x, b.max.y, b.max.z}}});
        if (s.normal_view >= 0)
            attrs["NORMAL"] = add_accessor({{"bufferView", s.normal_view}, {"componentType", kFloat}, {"count", count},
                                            {"type", "VEC3"}});
        for (std::size_t t = 0; t < s.texcoord_views.size(); ++t)
            attrs["TEXCOORD_" + std::to_string(t)] = add_accessor(
                {{"bufferView", s.texcoord_views[t]}, {"componentType", kFloat}, {"count", count}, {"type", "VEC2"}});
        for (std::size_t t = 0; t < s.joint_views.size(); ++t) {
            attrs["JOINTS_" + std::to_string(t)] = add_accessor({{"bufferView", s.joint_views[t]},
                                                                 {"componentType", kUnsignedShort},
                                                                 {"count", count}, {"type", "VEC4"}});
            attrs["WEIGHTS_" + std::to_string(t)] = add_accessor(
                {{"bufferView", s.weight_views[t]}, {"componentType", kFloat}, {"count", count}, {"type", "VEC4"}});
        }
        if (s.color_view >= 0)
            attrs["COLOR_0"] = add_accessor({{"bufferView", s.color_view}, {"componentType", kFloat}, {"count", count},
                                             {"type", "VEC4"}});
        return s.attributes_by_count.emplace(count, std::move(attrs)).first->second;
    }

    int add_indices(const std::vector<std::uint32_t>& indices, std::uint32_t vertex_count) {
        // 16-bit where every index fits below the restart value 65535, which glTF forbids as an index.
        int component = kUnsignedInt;
        if (vertex_count < 65535) {
            std::vector<std::uint16_t> narrow(indices.begin(), indices.end());
            add_view(narrow.data(), narrow.size() * 2, kElementArrayBuffer, 0);
            component = kUnsignedShort;
        } else {
            add_view(indices.data(), indices.size() * 4, kElementArrayBuffer, 0);
        }
        return add_accessor({{"bufferView", static_cast<int>(views_.size()) - 1}, {"componentType", component},
                             {"count", indices.size()}, {"type", "SCALAR"}});
    }

    ordered_json level_primitives(const LevelSpec& level, std::size_t k) {
        const Mesh& m = *sources_[level.source].mesh;
        const std::string label = "level " + std::to_string(k);
        if (level.index_count == 0 || level.index_count % 3 != 0)
            throw_error(Error::Kind::invalid, where_, label + " has no triangles");
        if (level.vertex_count > m.vertex_count())
            throw_error(Error::Kind::invalid, where_, label + " uses more vertices than its buffer has");
        const std::size_t triangles = level.index_count / 3;
        // Triangles grouped by material, in material order, each group in the level's triangle order.
        std::map<std::uint32_t, std::vector<std::uint32_t>> groups;
        const std::uint32_t none = m.materials.empty() ? UINT32_MAX : 0;
        for (std::size_t t = 0; t < triangles; ++t) {
            const std::uint32_t mat = level.face_materials ? level.face_materials[t] : none;
            if (mat != UINT32_MAX && mat >= m.materials.size())
                throw_error(Error::Kind::invalid, where_, label + " triangle " + std::to_string(t) + " uses material " +
                                                              std::to_string(mat) + " of " + std::to_string(m.materials.size()));
            auto& g = groups[mat];
            for (int c = 0; c < 3; ++c) {
                const std::uint32_t v = level.indices[3 * t + static_cast<std::size_t>(c)];
                if (v >= level.vertex_count)
                    throw_error(Error::Kind::invalid, where_, label + " triangle " + std::to_string(t) + " refers to vertex " +
                                                                  std::to_string(v) + " of " + std::to_string(level.vertex_count));
                g.push_back(v);
            }
        }
        ordered_json primitives = ordered_json::array();
        for (const auto& [mat, indices] : groups) {
            ordered_json p;
            p["attributes"] = attributes(level.source, level.vertex_count);
            if (morph_) p["targets"] = targets(level.source, level.vertex_count);
            p["indices"] = add_indices(indices, level.vertex_count);
            if (mat != UINT32_MAX) p["material"] = material(m, mat);
            p["mode"] = 4;
            primitives.push_back(std::move(p));
            ++primitives_;
        }
        return primitives;
    }

    // ---- skin and skeleton animations -------------------------------------------------------------

    // Every level is bound to the skeleton of the first source; all sources must share it (levels
    // change vertices, never joints).
    void check_skin() {
        const Mesh& first = *sources_.front().mesh;
        if (!first.has_skin()) return;
        skeleton_ = first.skeleton.get();
        const std::size_t joints = skeleton_->joints.size(), nodes = skeleton_->nodes.size();
        if (joints == 0 || skeleton_->inverse_bind_matrices.size() != joints)
            throw_error(Error::Kind::invalid, where_, "the skin needs one inverse bind matrix per joint");
        for (int j : skeleton_->joints)
            if (j < 0 || static_cast<std::size_t>(j) >= nodes) throw_error(Error::Kind::invalid, where_, "a joint is not a node");
        for (const VertexSource& s : sources_) {
            const Mesh& m = *s.mesh;
            if (m.skeleton.get() != skeleton_ || m.joints.empty())
                throw_error(Error::Kind::invalid, where_, "levels of one file must share one skeleton");
            for (const auto& set : m.joints)
                for (const Joints4& j : set)
                    for (std::uint16_t i : j)
                        if (i >= joints)
                            throw_error(Error::Kind::invalid, where_, "a vertex uses joint " + std::to_string(i) + " of " +
                                                                          std::to_string(joints));
        }
    }

    // The hierarchy after the level nodes (index + offset) and the one skin over it.
    void add_skeleton(ordered_json& nodes, std::size_t offset) {
        for (const SkeletonNode& n : skeleton_->nodes) {
            ordered_json j;
            if (!n.name.empty()) j["name"] = n.name;
            if (!n.children.empty()) {
                ordered_json children = ordered_json::array();
                for (int c : n.children) children.push_back(offset + static_cast<std::size_t>(c));
                j["children"] = children;
            }
            if (n.matrix.size() == 16) j["matrix"] = n.matrix;
            if (n.translation.size() == 3) j["translation"] = n.translation;
            if (n.rotation.size() == 4) j["rotation"] = n.rotation;
            if (n.scale.size() == 3) j["scale"] = n.scale;
            nodes.push_back(std::move(j));
        }
        const auto& ibm = skeleton_->inverse_bind_matrices;
        const int view = add_view(ibm.data(), ibm.size() * sizeof(ibm[0]), 0, 0);
        ordered_json skin = {{"inverseBindMatrices", add_accessor({{"bufferView", view}, {"componentType", kFloat},
                                                                    {"count", ibm.size()}, {"type", "MAT4"}})}};
        if (skeleton_->skeleton_root >= 0) skin["skeleton"] = offset + static_cast<std::size_t>(skeleton_->skeleton_root);
        ordered_json joints = ordered_json::array();
        for (int j : skeleton_->joints) joints.push_back(offset + static_cast<std::size_t>(j));
        skin["joints"] = joints;
        if (!skeleton_->skin_name.empty()) skin["name"] = skeleton_->skin_name;
        doc_["skins"] = ordered_json::array({skin});
    }

    ordered_json skeleton_animation(const Animation& a, std::size_t offset) {
        ordered_json samplers = ordered_json::array();
        for (const AnimationSampler& s : a.samplers) {
            const int input_view = add_view(s.input.data(), s.input.size() * sizeof(float), 0, 0);
            const int input = add_accessor({{"bufferView", input_view}, {"componentType", kFloat},
                                            {"count", s.input.size()}, {"type", "SCALAR"},
                                            {"min", {s.input.front()}}, {"max", {s.input.back()}}});
            const int output_view = add_view(s.output.data(), s.output.size() * sizeof(float), 0, 0);
            const int output = add_accessor({{"bufferView", output_view}, {"componentType", kFloat},
                                             {"count", s.output.size() / static_cast<std::size_t>(s.components)},
                                             {"type", s.components == 4 ? "VEC4" : "VEC3"}});
            samplers.push_back({{"input", input}, {"interpolation", s.interpolation}, {"output", output}});
        }
        ordered_json channels = ordered_json::array();
        for (const AnimationChannel& c : a.channels)
            channels.push_back({{"sampler", c.sampler},
                                {"target", {{"node", offset + static_cast<std::size_t>(c.node)}, {"path", c.path}}}});
        ordered_json j;
        if (!a.name.empty()) j["name"] = a.name;
        j["samplers"] = samplers;
        j["channels"] = channels;
        return j;
    }

    // ---- materials and images -------------------------------------------------------------------

    int material(const Mesh& m, std::uint32_t index) {
        const Material& mat = m.materials[index];
        const std::size_t sets = m.texcoords.size();
        for (std::size_t i = 0; i < written_materials_.size(); ++i) {
            const auto& [source_dir, texcoord_sets, written] = written_materials_[i];
            if (source_dir == m.source_dir && texcoord_sets == sets && same_material(written, mat))
                return static_cast<int>(i);
        }
        ordered_json j;
        if (!mat.name.empty()) j["name"] = mat.name;
        // glTF bounds every factor to [0, 1]; MTL files (Ke, Kd) may go outside.
        auto unit = [](float v) { return std::isfinite(v) ? std::clamp(v, 0.f, 1.f) : 0.f; };
        ordered_json pbr;
        pbr["baseColorFactor"] = {unit(mat.base_color.x), unit(mat.base_color.y), unit(mat.base_color.z),
                                  unit(mat.base_color.w)};
        if (auto t = texture_info(m, mat.base_color_texture, mat.name, "base colour")) pbr["baseColorTexture"] = *t;
        pbr["metallicFactor"] = unit(mat.metallic);
        pbr["roughnessFactor"] = unit(mat.roughness);
        if (auto t = texture_info(m, mat.metallic_roughness_texture, mat.name, "metallic-roughness"))
            pbr["metallicRoughnessTexture"] = *t;
        j["pbrMetallicRoughness"] = pbr;
        if (auto t = texture_info(m, mat.normal_texture, mat.name, "normal")) j["normalTexture"] = *t;
        if (auto t = texture_info(m, mat.occlusion_texture, mat.name, "occlusion")) j["occlusionTexture"] = *t;
        if (auto t = texture_info(m, mat.emissive_texture, mat.name, "emissive")) j["emissiveTexture"] = *t;
        const Vec3f e{unit(mat.emissive.x), unit(mat.emissive.y), unit(mat.emissive.z)};
        if (!(e == Vec3f{0, 0, 0})) j["emissiveFactor"] = {e.x, e.y, e.z};
        if (mat.double_sided) j["doubleSided"] = true;
        materials_.push_back(std::move(j));
        written_materials_.emplace_back(m.source_dir, sets, mat);
        return static_cast<int>(materials_.size()) - 1;
    }

    std::optional<ordered_json> texture_info(const Mesh& m, const TextureRef& ref, const std::string& material,
                                             const char* slot) {
        if (ref.empty()) return std::nullopt;
        const std::string what = "material '" + material + "' " + slot + " texture";
        if (ref.texcoord_set < 0 || static_cast<std::size_t>(ref.texcoord_set) >= m.texcoords.size()) {
            // A binding to a texcoord set the mesh lacks is invalid glTF; the factors still apply.
            warnings_.push_back(what + " dropped: the mesh has no texture coordinate set " +
                                std::to_string(ref.texcoord_set));
            return std::nullopt;
        }
        const int image = image_index(m, ref, what);
        if (image < 0) return std::nullopt;
        ordered_json info = {{"index", image}};  // texture i samples image i
        if (ref.texcoord_set != 0) info["texCoord"] = ref.texcoord_set;
        return info;
    }

    int image_index(const Mesh& m, const TextureRef& ref, const std::string& what) {
        std::vector<std::uint8_t> bytes;
        std::string name;
        if (!ref.bytes.empty()) {
            bytes = ref.bytes;
            name = ref.path.empty() ? what + " (embedded)" : ref.path;
        } else {
            name = m.resolve_texture_path(ref);
            std::ifstream in(name, std::ios::binary);
            if (in) bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
            if (!in.good() && !in.eof()) bytes.clear();
            if (bytes.empty()) {
                if (!options_.skip_missing_textures)
                    throw_error(Error::Kind::io, name, "cannot read the " + what + " to embed it in the glb");
                warnings_.push_back(name + ": cannot read the " + what + "; written without it");
                return -1;
            }
        }
        const std::string mime = sniff_mime(bytes);
        if (mime.empty())
            throw_error(Error::Kind::unsupported, name,
                        "the " + what + " is neither PNG nor JPEG, the only image formats core glTF allows; "
                                        "convert it first");
        for (std::size_t i = 0; i < image_bytes_.size(); ++i)
            if (image_bytes_[i] == bytes) return static_cast<int>(i);
        const int view = add_view(bytes.data(), bytes.size(), 0, 0);
        images_.push_back({{"bufferView", view}, {"mimeType", mime}});
        textures_.push_back({{"sampler", 0}, {"source", images_.size() - 1}});
        image_bytes_.push_back(std::move(bytes));
        return static_cast<int>(images_.size()) - 1;
    }

    // ---- container --------------------------------------------------------------------------------

    std::vector<std::uint8_t> container() {
        // Names come from file names, which need not be UTF-8 (JSON must be): bad bytes become U+FFFD.
        std::string json = doc_.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
        while (json.size() % 4) json += ' ';  // the JSON chunk is padded with spaces
        align();
        const std::size_t total = 12 + 8 + json.size() + 8 + bin_.size();
        if (total > 0xFFFFFFFFull) throw_error(Error::Kind::unsupported, where_, "the glb would exceed 4 GiB");
        std::vector<std::uint8_t> out;
        out.reserve(total);
        auto u32 = [&out](std::size_t v) {
            const auto x = static_cast<std::uint32_t>(v);
            for (int i = 0; i < 4; ++i) out.push_back(static_cast<std::uint8_t>(x >> (8 * i)));
        };
        u32(0x46546C67);  // "glTF"
        u32(2);
        u32(total);
        u32(json.size());
        u32(0x4E4F534A);  // "JSON"
        out.insert(out.end(), json.begin(), json.end());
        u32(bin_.size());
        u32(0x004E4942);  // "BIN\0"
        out.insert(out.end(), bin_.begin(), bin_.end());
        return out;
    }

    const GlbOptions& options_;
    Progress* progress_;
    std::string where_ = "<glb>";
    std::vector<VertexSource> sources_;
    ordered_json doc_;
    ordered_json accessors_ = ordered_json::array();
    ordered_json views_ = ordered_json::array();
    ordered_json materials_ = ordered_json::array();
    ordered_json textures_ = ordered_json::array();
    ordered_json images_ = ordered_json::array();
    std::vector<std::tuple<std::string, std::size_t, Material>> written_materials_;
    std::vector<std::vector<std::uint8_t>> image_bytes_;
    std::vector<std::uint8_t> bin_;
    std::vector<std::string> warnings_;
    std::size_t primitives_ = 0;

public:
    void set_where(std::string where) { where_ = std::move(where); }
    void set_morph(const GlbMorphTargets* morph) { morph_ = morph; }

private:
    // ---- morph targets (only with set_morph; one vertex source) ----------------------------------

    const GlbMorphTargets* morph_ = nullptr;
    const Skeleton* skeleton_ = nullptr;  // check_skin: the skin every level is bound to, or none
    std::vector<int> target_position_views_, target_normal_views_;
    std::map<std::uint32_t, ordered_json> targets_by_count_;
    // KHR_mesh_quantization (GlbMorphTargets::quantize): p = translation + scale * stored
    Vec3f q_translation_{};
    float q_scale_ = 1.f;
    std::vector<Vec3f> q_base_;                       // base positions in the dequantisation frame
    std::vector<std::vector<std::int16_t>> q_positions_;  // [target][4 * vertex + axis], 4th padding
    std::vector<bool> q_normal_bytes_;                // per target: BYTE normals (else FLOAT)

    bool quantized() const { return morph_ && morph_->quantize; }

    // One uniform scale for every target: the largest displacement component maps to +-32767. The base
    // stays float (written once), expressed in the same frame because the node transform applies to
    // base and deltas alike.
    void prepare_quantization() {
        const GlbMorphTargets& m = *morph_;
        const Mesh& base = *sources_[0].mesh;
        Bounds b;
        for (const Vec3f& p : base.positions) b.add(p);
        q_translation_ = (b.min + b.max) * 0.5f;
        float largest = 0.f;
        for (const auto& d : m.position_deltas)
            for (const Vec3f& v : d) largest = std::max({largest, std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)});
        q_scale_ = largest > 0.f ? largest : 1.f;
        q_base_.resize(base.positions.size());
        for (std::size_t i = 0; i < q_base_.size(); ++i) q_base_[i] = (base.positions[i] - q_translation_) * (1.f / q_scale_);
    }

    void write_quantized_targets() {
        const GlbMorphTargets& m = *morph_;
        auto snorm16 = [](float f) {
            return static_cast<std::int16_t>(std::clamp(std::lround(f * 32767.f), -32767L, 32767L));
        };
        const float inv = 1.f / q_scale_;
        for (const auto& d : m.position_deltas) {
            std::vector<std::int16_t>& q = q_positions_.emplace_back(4 * d.size(), std::int16_t{0});
            for (std::size_t i = 0; i < d.size(); ++i) {
                q[4 * i] = snorm16(d[i].x * inv);
                q[4 * i + 1] = snorm16(d[i].y * inv);
                q[4 * i + 2] = snorm16(d[i].z * inv);
            }
            target_position_views_.push_back(add_view(q.data(), q.size() * 2, kArrayBuffer, 8));
        }
        // Normal displacements outside [-1, 1] cannot be normalized integers; the spec leaves those to
        // FLOAT, decided per target.
        for (const auto& d : m.normal_deltas) {
            bool fits = true;
            for (const Vec3f& v : d) fits = fits && std::fabs(v.x) <= 1.f && std::fabs(v.y) <= 1.f && std::fabs(v.z) <= 1.f;
            q_normal_bytes_.push_back(fits);
            if (!fits) {
                target_normal_views_.push_back(add_vertex_view(d));
                continue;
            }
            std::vector<std::int8_t> q(4 * d.size(), std::int8_t{0});
            auto snorm8 = [](float f) { return static_cast<std::int8_t>(std::clamp(std::lround(f * 127.f), -127L, 127L)); };
            for (std::size_t i = 0; i < d.size(); ++i) {
                q[4 * i] = snorm8(d[i].x);
                q[4 * i + 1] = snorm8(d[i].y);
                q[4 * i + 2] = snorm8(d[i].z);
            }
            target_normal_views_.push_back(add_view(q.data(), q.size(), kArrayBuffer, 4));
        }
    }

    void check_morph() const {
        const GlbMorphTargets& m = *morph_;
        const std::size_t T = m.position_deltas.size();
        if (sources_.size() != 1) throw_error(Error::Kind::invalid, where_, "morph targets need one vertex buffer");
        const std::size_t n = sources_[0].mesh->vertex_count();
        if (T == 0) throw_error(Error::Kind::invalid, where_, "morph export without targets");
        auto check = [&](const std::vector<std::vector<Vec3f>>& deltas, const char* what) {
            for (std::size_t t = 0; t < deltas.size(); ++t) {
                if (deltas[t].size() != n)
                    throw_error(Error::Kind::invalid, where_, std::string("morph target ") + std::to_string(t) + " " + what +
                                                                  " has " + std::to_string(deltas[t].size()) + " values for " +
                                                                  std::to_string(n) + " vertices");
                for (const Vec3f& d : deltas[t])
                    if (!is_finite(d))
                        throw_error(Error::Kind::invalid, where_, std::string("morph target ") + std::to_string(t) + " " +
                                                                      what + " is not finite");
            }
        };
        check(m.position_deltas, "POSITION");
        check(m.normal_deltas, "NORMAL");
        if (!m.normal_deltas.empty() && m.normal_deltas.size() != T)
            throw_error(Error::Kind::invalid, where_, "morph targets: NORMAL and POSITION target counts differ");
        if (!m.names.empty() && m.names.size() != T)
            throw_error(Error::Kind::invalid, where_, "morph targets: name count differs from the target count");
        if (!m.default_weights.empty() && m.default_weights.size() != T)
            throw_error(Error::Kind::invalid, where_, "morph targets: weight count differs from the target count");
        if (m.key_weights.size() != m.key_times.size())
            throw_error(Error::Kind::invalid, where_, "morph animation: key and weight counts differ");
        for (std::size_t k = 0; k < m.key_times.size(); ++k) {
            if (!std::isfinite(m.key_times[k]) || (k > 0 && !(m.key_times[k] > m.key_times[k - 1])) || m.key_times[k] < 0)
                throw_error(Error::Kind::invalid, where_, "morph animation: key times must increase from >= 0");
            if (m.key_weights[k].size() != T)
                throw_error(Error::Kind::invalid, where_, "morph animation: key " + std::to_string(k) + " has " +
                                                              std::to_string(m.key_weights[k].size()) + " weights for " +
                                                              std::to_string(T) + " targets");
            for (float w : m.key_weights[k])
                if (!std::isfinite(w)) throw_error(Error::Kind::invalid, where_, "morph animation: weight is not finite");
        }
        if (m.interpolation != "LINEAR" && m.interpolation != "STEP")
            throw_error(Error::Kind::invalid, where_, "morph animation: interpolation must be LINEAR or STEP");
    }

    const ordered_json& targets(std::size_t source_index, std::uint32_t count) {
        if (auto it = targets_by_count_.find(count); it != targets_by_count_.end()) return it->second;
        (void)source_index;  // one source (check_morph)
        const GlbMorphTargets& m = *morph_;
        if (target_position_views_.empty()) {
            if (quantized()) {
                write_quantized_targets();
            } else {
                for (const auto& d : m.position_deltas) target_position_views_.push_back(add_vertex_view(d));
                for (const auto& d : m.normal_deltas) target_normal_views_.push_back(add_vertex_view(d));
            }
        }
        ordered_json list = ordered_json::array();
        for (std::size_t t = 0; t < m.position_deltas.size(); ++t) {
            ordered_json target;
            if (quantized()) {
                // min/max of an integer accessor are its stored integers, normalized or not (the validator's
                // reading of the spec).
                std::array<int, 3> lo{32767, 32767, 32767}, hi{-32767, -32767, -32767};
                for (std::uint32_t i = 0; i < count; ++i)
                    for (int c = 0; c < 3; ++c) {
                        const int q = q_positions_[t][4 * i + static_cast<std::size_t>(c)];
                        lo[static_cast<std::size_t>(c)] = std::min(lo[static_cast<std::size_t>(c)], q);
                        hi[static_cast<std::size_t>(c)] = std::max(hi[static_cast<std::size_t>(c)], q);
                    }
                target["POSITION"] = add_accessor({{"bufferView", target_position_views_[t]}, {"componentType", kShort},
                                                   {"normalized", true}, {"count", count}, {"type", "VEC3"},
                                                   {"min", lo}, {"max", hi}});
                if (!target_normal_views_.empty()) {
                    if (q_normal_bytes_[t])
                        target["NORMAL"] = add_accessor({{"bufferView", target_normal_views_[t]}, {"componentType", kByte},
                                                         {"normalized", true}, {"count", count}, {"type", "VEC3"}});
                    else
                        target["NORMAL"] = add_accessor({{"bufferView", target_normal_views_[t]},
                                                         {"componentType", kFloat}, {"count", count}, {"type", "VEC3"}});
                }
            } else {
                Bounds b;
                for (std::uint32_t i = 0; i < count; ++i) b.add(m.position_deltas[t][i]);
                target["POSITION"] = add_accessor({{"bufferView", target_position_views_[t]}, {"componentType", kFloat},
                                                   {"count", count}, {"type", "VEC3"}, {"min", {b.min.x, b.min.y, b.min.z}},
                                                   {"max", {b.max.x, b.max.y, b.max.z}}});
                if (!target_normal_views_.empty())
                    target["NORMAL"] = add_accessor({{"bufferView", target_normal_views_[t]}, {"componentType", kFloat},
                                                     {"count", count}, {"type", "VEC3"}});
            }
            list.push_back(std::move(target));
        }
        return targets_by_count_.emplace(count, std::move(list)).first->second;
    }

    void add_mesh_weights(ordered_json& mesh) const {
        const GlbMorphTargets& m = *morph_;
        mesh["weights"] = m.default_weights.empty() ? std::vector<float>(m.position_deltas.size(), 0.f) : m.default_weights;
        if (!m.names.empty()) mesh["extras"] = {{"targetNames", m.names}};
    }

    ordered_json animation(std::size_t levels) {
        const GlbMorphTargets& m = *morph_;
        const int input_view = add_view(m.key_times.data(), m.key_times.size() * sizeof(float), 0, 0);
        const int input = add_accessor({{"bufferView", input_view}, {"componentType", kFloat},
                                        {"count", m.key_times.size()}, {"type", "SCALAR"},
                                        {"min", {m.key_times.front()}}, {"max", {m.key_times.back()}}});
        std::vector<float> weights;
        for (const auto& key : m.key_weights) weights.insert(weights.end(), key.begin(), key.end());
        const int output_view = add_view(weights.data(), weights.size() * sizeof(float), 0, 0);
        const int output = add_accessor({{"bufferView", output_view}, {"componentType", kFloat},
                                         {"count", weights.size()}, {"type", "SCALAR"}});
        ordered_json channels = ordered_json::array();
        for (std::size_t k = 0; k < levels; ++k)
            channels.push_back({{"sampler", 0}, {"target", {{"node", k}, {"path", "weights"}}}});
        ordered_json anim = {{"name", m.animation_name},
                             {"samplers", ordered_json::array({{{"input", input}, {"interpolation", m.interpolation},
                                                                {"output", output}}})},
                             {"channels", channels}};
        return ordered_json::array({anim});
    }
};

std::vector<std::uint8_t> encode_levels(const std::vector<Mesh>& levels, const GlbOptions& options,
                                        GlbResult* result, Progress* progress, const std::string& where) {
    std::vector<VertexSource> sources;
    std::vector<LevelSpec> specs;
    for (std::size_t k = 0; k < levels.size(); ++k) {
        const Mesh& m = levels[k];
        if (!m.face_materials.empty() && m.face_materials.size() != m.triangle_count())
            throw_error(Error::Kind::invalid, where, "level " + std::to_string(k) +
                                                         ": face_materials size differs from the triangle count");
        sources.push_back({.mesh = &m, .position_view = -1, .normal_view = -1, .color_view = -1,
                           .texcoord_views = {}, .joint_views = {}, .weight_views = {}, .attributes_by_count = {}});
        specs.push_back({.source = k, .vertex_count = static_cast<std::uint32_t>(m.vertex_count()),
                         .indices = m.indices.data(), .index_count = m.indices.size(),
                         .face_materials = m.face_materials.empty() ? nullptr : m.face_materials.data()});
    }
    GlbBuilder builder(options, progress);
    builder.set_where(where);
    return builder.build(std::move(sources), specs, result);
}

std::vector<std::uint8_t> encode_shared(const SharedLodBuffers& shared, const GlbOptions& options,
                                        GlbResult* result, Progress* progress, const std::string& where,
                                        const GlbMorphTargets* morph = nullptr) {
    const std::size_t triangles = shared.indices.size() / 3;
    if (!shared.face_materials.empty() && shared.face_materials.size() != triangles)
        throw_error(Error::Kind::invalid, where, "face_materials size differs from the triangle count");
    std::vector<LevelSpec> specs;
    for (std::size_t k = 0; k < shared.levels.size(); ++k) {
        const LodIndexRange& r = shared.levels[k];
        if (r.first_index > shared.indices.size() || r.index_count > shared.indices.size() - r.first_index ||
            r.first_index % 3 != 0)
            throw_error(Error::Kind::invalid, where, "level " + std::to_string(k) + ": index range outside the buffer");
        specs.push_back({.source = 0, .vertex_count = r.vertex_count, .indices = shared.indices.data() + r.first_index,
                         .index_count = r.index_count,
                         .face_materials = shared.face_materials.empty()
                                               ? nullptr
                                               : shared.face_materials.data() + r.first_index / 3});
    }
    std::vector<VertexSource> sources(1);
    sources[0].mesh = &shared.vertices;
    GlbBuilder builder(options, progress);
    builder.set_where(where);
    builder.set_morph(morph);
    return builder.build(std::move(sources), specs, result);
}

GlbResult write_bytes(const std::vector<std::uint8_t>& bytes, GlbResult result, const std::string& path) {
    AtomicFile file(path, true);
    file.stream().write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    file.commit();
    return result;
}

}  // namespace

std::vector<std::uint8_t> encode_glb(const std::vector<Mesh>& levels, const GlbOptions& options, GlbResult* result,
                                     Progress* progress) {
    return encode_levels(levels, options, result, progress, "<glb>");
}

std::vector<std::uint8_t> encode_glb(const SharedLodBuffers& shared, const GlbOptions& options, GlbResult* result,
                                     Progress* progress) {
    return encode_shared(shared, options, result, progress, "<glb>");
}

GlbResult write_glb(const std::vector<Mesh>& levels, const GlbOptions& options, const std::string& path,
                    Progress* progress) {
    GlbResult result;
    const auto bytes = encode_levels(levels, options, &result, progress, path);
    return write_bytes(bytes, std::move(result), path);
}

GlbResult write_glb(const SharedLodBuffers& shared, const GlbOptions& options, const std::string& path,
                    Progress* progress) {
    GlbResult result;
    const auto bytes = encode_shared(shared, options, &result, progress, path);
    return write_bytes(bytes, std::move(result), path);
}

std::vector<std::uint8_t> encode_glb(const SharedLodBuffers& shared, const GlbOptions& options,
                                     const GlbMorphTargets& morph, GlbResult* result, Progress* progress) {
    return encode_shared(shared, options, result, progress, "<glb>", &morph);
}

GlbResult write_glb(const SharedLodBuffers& shared, const GlbOptions& options, const GlbMorphTargets& morph,
                    const std::string& path, Progress* progress) {
    GlbResult result;
    const auto bytes = encode_shared(shared, options, &result, progress, path, &morph);
    return write_bytes(bytes, std::move(result), path);
}

}  // namespace lodforge

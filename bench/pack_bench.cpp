// LOD pack benchmark: where the time of `write_lod_pack` goes (hashing, the chain, measuring, writing),
// and the GLB encoder against tinygltf's writer (TinyGLTF::WriteGltfSceneToStream, binary) encoding the
// same levels over the same shared vertex buffer, in one run.
//
// Per model: seconds of sha256_file, build_lod_chain without and with measurement (the difference is
// the Metro measurement of the levels), encode_glb (median of --reps) and the tinygltf comparator
// (building its Model from the shared buffers plus writing, median of --reps), GLB sizes, and the whole
// write_lod_pack with the default preset (levels 0.5, 0.25, 0.1, 0.03; glb only) into a temp dir.
//
//   lodforge_bench_pack [--models dragon,dragon2,frag] [--reps N]

#include "bench_util.h"
#include "lodforge/io/file_hash.h"
#include "lodforge/io/gltf_writer.h"
#include "lodforge/simplify/lod_chain.h"
#include "lodforge/pack/lod_pack.h"
#include "lodforge/io/mesh_io.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

using namespace lodforge;

namespace {

using Clock = std::chrono::steady_clock;

double seconds(const std::function<void()>& f) {
    const auto t0 = Clock::now();
    f();
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

double median_seconds(int reps, const std::function<void()>& f) {
    std::vector<double> t;
    for (int i = 0; i < reps; ++i) t.push_back(seconds(f));
    std::sort(t.begin(), t.end());
    return t[t.size() / 2];
}

using lodforge::bench::split;

int add_view(tinygltf::Model& m, const void* data, std::size_t bytes, int target, int stride) {
    auto& buffer = m.buffers[0].data;
    while (buffer.size() % 4) buffer.push_back(0);
    tinygltf::BufferView v;
    v.buffer = 0;
    v.byteOffset = buffer.size();
    v.byteLength = bytes;
    v.byteStride = static_cast<std::size_t>(stride);
    v.target = target;
    const auto* p = static_cast<const unsigned char*>(data);
    buffer.insert(buffer.end(), p, p + bytes);
    m.bufferViews.push_back(v);
    return static_cast<int>(m.bufferViews.size()) - 1;
}

int add_accessor(tinygltf::Model& m, int view, int component, std::size_t count, int type) {
    tinygltf::Accessor a;
    a.bufferView = view;
    a.componentType = component;
    a.count = count;
    a.type = type;
    m.accessors.push_back(a);
    return static_cast<int>(m.accessors.size()) - 1;
}

// The same content encode_glb writes for a shared chain (positions with min/max, unit normals,
// flipped UVs, colours, 16/32-bit indices per level, MSFT_lod), built with tinygltf.
std::string tinygltf_glb(const SharedLodBuffers& shared) {
    const Mesh& v = shared.vertices;
    tinygltf::Model m;
    m.asset.version = "2.0";
    m.buffers.resize(1);
    const int pos = add_view(m, v.positions.data(), v.positions.size() * 12, 34962, 12);
    int nrm = -1, col = -1, uv = -1;
    if (v.has_normals()) {
        std::vector<Vec3f> n(v.normals.size());
        for (std::size_t i = 0; i < n.size(); ++i) {
            const float len = length(v.normals[i]);
            n[i] = len > 0 ? v.normals[i] * (1.f / len) : Vec3f{0, 0, 1};
        }
        nrm = add_view(m, n.data(), n.size() * 12, 34962, 12);
    }
    if (v.has_colors()) col = add_view(m, v.colors.data(), v.colors.size() * 16, 34962, 16);
    if (v.has_texcoords()) {
        std::vector<Vec2f> t(v.texcoords[0].size());
        for (std::size_t i = 0; i < t.size(); ++i) t[i] = {v.texcoords[0][i].x, 1.f - v.texcoords[0][i].y};
        uv = add_view(m, t.data(), t.size() * 8, 34962, 8);
    }
    for (std::size_t k = 0; k < shared.levels.size(); ++k) {
        const LodIndexRange& r = shared.levels[k];
        tinygltf::Primitive p;
        const int a = add_accessor(m, pos, TINYGLTF_COMPONENT_TYPE_FLOAT, r.vertex_count, TINYGLTF_TYPE_VEC3);
        Bounds b;
        for (std::uint32_t i = 0; i < r.vertex_count; ++i) b.add(v.positions[i]);
        m.accessors[static_cast<std::size_t>(a)].minValues = {b.min.x, b.min.y, b.min.z};
        m.accessors[static_cast<std::size_t>(a)].maxValues = {b.max.x, b.max.y, b.max.z};
        p.attributes["POSITION"] = a;
        if (nrm >= 0) p.attributes["NORMAL"] = add_accessor(m, nrm, TINYGLTF_COMPONENT_TYPE_FLOAT, r.vertex_count, TINYGLTF_TYPE_VEC3);
        if (col >= 0) p.attributes["COLOR_0"] = add_accessor(m, col, TINYGLTF_COMPONENT_TYPE_FLOAT, r.vertex_count, TINYGLTF_TYPE_VEC4);
        if (uv >= 0) p.attributes["TEXCOORD_0"] = add_accessor(m, uv, TINYGLTF_COMPONENT_TYPE_FLOAT, r.vertex_count, TINYGLTF_TYPE_VEC2);
        const std::uint32_t* idx = shared.indices.data() + r.first_index;
        int view = 0, component = 0;
        if (r.vertex_count < 65535) {
            std::vector<std::uint16_t> narrow(idx, idx + r.index_count);
            view = add_view(m, narrow.data(), narrow.size() * 2, 34963, 0);
            component = TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
        } else {
            view = add_view(m, idx, r.index_count * 4, 34963, 0);
            component = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
        }
        p.indices = add_accessor(m, view, component, r.index_count, TINYGLTF_TYPE_SCALAR);
        p.mode = TINYGLTF_MODE_TRIANGLES;
        tinygltf::Mesh mesh;
        mesh.primitives.push_back(p);
        m.meshes.push_back(mesh);
        tinygltf::Node node;
        node.mesh = static_cast<int>(k);
        m.nodes.push_back(node);
    }
    tinygltf::Value::Array ids;
    for (std::size_t k = 1; k < shared.levels.size(); ++k) ids.emplace_back(static_cast<int>(k));
    tinygltf::Value::Object lod;
    lod["ids"] = tinygltf::Value(ids);
    m.nodes[0].extensions["MSFT_lod"] = tinygltf::Value(lod);
    m.extensionsUsed.push_back("MSFT_lod");
    tinygltf::Scene scene;
    scene.nodes = {0};
    m.scenes.push_back(scene);
    m.defaultScene = 0;
    std::ostringstream out;
    tinygltf::TinyGLTF writer;
    writer.WriteGltfSceneToStream(&m, out, false, true);
    return out.str();
}

}  // namespace

int main(int argc, char** argv) {
    std::string models = "dragon,dragon2,frag";
    int reps = 5;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--models") && i + 1 < argc) models = argv[++i];
        else if (!std::strcmp(argv[i], "--reps") && i + 1 < argc) reps = std::max(1, std::atoi(argv[++i]));
        else {
            std::fprintf(stderr, "usage: lodforge_bench_pack [--models dragon,dragon2,frag] [--reps N]\n");
            return 2;
        }
    }
    const std::string data = LODFORGE_SHARED_DATA;
    auto path_of = [&](const std::string& key) -> std::string {
        if (key == "dragon") return data + "/scan-dragon/dragon_vrip.ply";
        if (key == "dragon2") return data + "/scan-dragon/dragon_vrip_res2.ply";
        if (key == "frag") return data + "/color-open3d-frag115/frag_115.ply";
        return key;
    };
    std::printf("| model | tris | sha256 s | chain s | chain+measure s | encode_glb s | tinygltf s | ratio | glb MB | tinygltf MB | write_lod_pack s |\n");
    std::printf("|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (const std::string& key : split(models)) {
        const std::string path = path_of(key);
        const Mesh mesh = read_mesh(path);
        const double hash_s = seconds([&] { (void)sha256_file(path); });
        LodChainParams p;
        p.levels = lod_levels_from_ratios({0.5f, 0.25f, 0.1f, 0.03f});
        p.measure = false;
        LodChainResult chain;
        const double chain_s = seconds([&] { chain = build_lod_chain(mesh, p); });
        p.measure = true;
        const double measured_s = seconds([&] { (void)build_lod_chain(mesh, p); });
        std::vector<std::uint8_t> ours;
        const double ours_s = median_seconds(reps, [&] { ours = encode_glb(chain.shared, {}); });
        std::string theirs;
        const double theirs_s = median_seconds(reps, [&] { theirs = tinygltf_glb(chain.shared); });
        const auto dir = std::filesystem::temp_directory_path() / ("lodforge-bench-pack-" + std::to_string(::getpid()));
        PackParams pack;
        pack.source_path = path;
        pack.output_dir = dir.string();
        const double pack_s = seconds([&] { (void)write_lod_pack(mesh, pack); });
        std::filesystem::remove_all(dir);
        std::printf("| %s | %zu | %.3f | %.2f | %.2f | %.3f | %.3f | %.2f | %.1f | %.1f | %.2f |\n", key.c_str(),
                    mesh.triangle_count(), hash_s, chain_s, measured_s, ours_s, theirs_s, theirs_s / ours_s,
                    ours.size() / 1e6, theirs.size() / 1e6, pack_s);
        std::fflush(stdout);
    }
    return 0;
}

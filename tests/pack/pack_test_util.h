// Shared by the pack tests: the Khronos validator run on a file, and a GLB split into its JSON and
// binary chunks so tests can check what a loader would see.
#pragma once

#include "support/cli_run.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace lodforge::test {

struct Validation {
    int exit_code = -1;
    nlohmann::json report;  // {errors, warnings, infos, messages, info}
    std::string raw;
};

inline Validation validate_gltf(const std::string& path) {
    Validation v;
    const CliRun run = run_command(std::string(LODFORGE_GLTF_VALIDATE) + " '" + path + "' 2>&1");
    v.exit_code = run.exit_code;
    v.raw = run.out;
    v.report = nlohmann::json::parse(v.raw, nullptr, false);
    return v;
}

// Warnings the validator raises for every LOD pack, explained in docs/pack.md: it does not implement
// the vendor extension MSFT_lod (UNSUPPORTED_EXTENSION, the one warning), and the infos listed below.
inline std::vector<std::string> unexplained_warnings(const Validation& v) {
    std::vector<std::string> out;
    if (!v.report.is_object()) return {"no report: " + v.raw};
    for (const auto& m : v.report["messages"]) {
        const std::string s = m.get<std::string>();
        if (s.rfind("note ", 0) != 0) continue;  // errors are counted separately
        if (s.find("UNSUPPORTED_EXTENSION") != std::string::npos && s.find("MSFT_lod") != std::string::npos) continue;
        if (s.find("UNUSED_OBJECT") != std::string::npos) continue;  // infos: LOD nodes outside the scene
        if (s.find("MESH_PRIMITIVE_GENERATED_TANGENT_SPACE") != std::string::npos) continue;  // info
        // info about the source PNG itself (Spot's has gAMA/cHRM chunks); embedded unchanged on purpose
        if (s.find("IMAGE_FEATURES_UNSUPPORTED") != std::string::npos) continue;
        out.push_back(s);
    }
    return out;
}

inline std::vector<std::uint8_t> read_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

struct Glb {
    nlohmann::json json;
    std::vector<std::uint8_t> bin;
};

inline std::uint32_t u32_at(const std::vector<std::uint8_t>& b, std::size_t at) {
    std::uint32_t v = 0;
    std::memcpy(&v, b.data() + at, 4);
    return v;
}

inline Glb split_glb(const std::vector<std::uint8_t>& b) {
    Glb g;
    if (b.size() < 20 || u32_at(b, 0) != 0x46546C67) return g;
    const std::uint32_t json_len = u32_at(b, 12);
    g.json = nlohmann::json::parse(b.begin() + 20, b.begin() + 20 + json_len);
    const std::size_t bin_at = 20 + json_len;
    if (b.size() >= bin_at + 8) {
        const std::uint32_t bin_len = u32_at(b, bin_at);
        g.bin.assign(b.begin() + static_cast<std::ptrdiff_t>(bin_at + 8),
                     b.begin() + static_cast<std::ptrdiff_t>(bin_at + 8 + bin_len));
    }
    return g;
}

// Triangles of node `node`'s mesh: the index counts of its primitives / 3.
inline std::size_t node_triangles(const Glb& g, std::size_t node) {
    const auto& mesh = g.json["meshes"][g.json["nodes"][node]["mesh"].get<std::size_t>()];
    std::size_t n = 0;
    for (const auto& p : mesh["primitives"]) n += g.json["accessors"][p["indices"].get<std::size_t>()]["count"].get<std::size_t>();
    return n / 3;
}

// The coarser levels' nodes, as MSFT_lod lists them on node 0 (empty without the extension).
inline std::vector<std::size_t> lod_ids(const Glb& g) {
    const auto& node = g.json["nodes"][0];
    if (!node.contains("extensions")) return {};
    return node["extensions"]["MSFT_lod"]["ids"].get<std::vector<std::size_t>>();
}

inline std::vector<std::uint8_t> image_bytes(const Glb& g, std::size_t image) {
    const auto& view = g.json["bufferViews"][g.json["images"][image]["bufferView"].get<std::size_t>()];
    const std::size_t at = view["byteOffset"].get<std::size_t>(), len = view["byteLength"].get<std::size_t>();
    return {g.bin.begin() + static_cast<std::ptrdiff_t>(at), g.bin.begin() + static_cast<std::ptrdiff_t>(at + len)};
}

// Values of a float or unsigned-short VEC4 (or VEC3, last component 0) accessor.
inline std::vector<std::array<float, 4>> vec4_values(const test::Glb& g, std::size_t accessor) {
    const auto& a = g.json["accessors"][accessor];
    const auto& view = g.json["bufferViews"][a["bufferView"].get<std::size_t>()];
    const std::size_t count = a["count"].get<std::size_t>();
    const int type = a["componentType"].get<int>();
    const std::size_t size = type == 5126 ? 4 : type == 5123 ? 2 : 1;
    const std::size_t components = a["type"] == "VEC3" ? 3 : 4;
    const std::size_t stride = view.contains("byteStride") ? view["byteStride"].get<std::size_t>() : components * size;
    const std::size_t at = view["byteOffset"].get<std::size_t>() + a.value("byteOffset", std::size_t{0});
    std::vector<std::array<float, 4>> out(count, std::array<float, 4>{0, 0, 0, 0});
    for (std::size_t i = 0; i < count; ++i)
        for (std::size_t c = 0; c < components; ++c) {
            const std::uint8_t* p = g.bin.data() + at + i * stride + c * size;
            if (size == 4) std::memcpy(&out[i][c], p, 4);
            else if (size == 2) out[i][c] = static_cast<float>(p[0] | (p[1] << 8));
            else out[i][c] = p[0];
        }
    return out;
}

}  // namespace lodforge::test

// glTF 2.0 export of a morphing mesh with LOD: levels over one vertex buffer (MSFT_lod, as the LOD
// pack), the frames as morph targets, and a weights animation that steps through the keyframes.
//
// Based on:
//  - the glTF 2.0 specification (Khronos), §3.7.2.2 morph targets (displacements added to the base
//    attributes, weighted) and §3.11 animations (LINEAR weights interpolation);
//  - J. F. Ramos, "LODStrips" (UJI thesis, 2008), ch. 6: one connectivity for all frames, so each level's
//    faces serve every frame, here each level's vertices carry every frame as a target.
// With targets j = frame j+1 − frame 0 and one-hot weights at each key, LINEAR interpolation between keys
// k and k+1 gives V0 + (1 − s)(Vk − V0) + s(Vk+1 − V0) = (1 − s)Vk + s·Vk+1: exactly the morph's V(t).
#include "lodforge/morph/morph_gltf.h"

#include "lodforge/error.h"
#include "lodforge/io/gltf_reader.h"
#include "lodforge/io/mesh_io.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

namespace lodforge {

MorphGltfTiming morph_gltf_timing(const MorphMesh& morph) {
    MorphGltfTiming timing;
    std::error_code ec;
    if (morph.source.empty() || std::filesystem::is_directory(morph.source, ec)) return timing;
    const FileFormat f = detect_format(morph.source);
    if (f != FileFormat::gltf && f != FileFormat::glb) return timing;
    GltfMorphTargets mt;
    GltfReadOptions o;
    o.morph_targets = &mt;
    read_gltf(morph.source, nullptr, o);
    if (mt.key_times.empty()) {
        timing.animated = false;
        return timing;
    }
    timing.start_seconds = mt.key_times.front();
    const std::size_t k = morph.frame_count();
    timing.seconds_per_frame = k > 1 ? (double(mt.key_times.back()) - double(mt.key_times.front())) / double(k - 1) : 1.0;
    if (!(timing.seconds_per_frame > 0)) timing.seconds_per_frame = 1.0 / 30.0;
    return timing;
}

SharedLodBuffers morph_gltf_buffers(const MorphMesh& morph, const MorphLod& lod, const MorphStripsBuild& strips) {
    const lodstrips::Data& d = strips.data.strips;
    const std::uint32_t n = d.vertex_count;
    const Mesh& base = morph.base;
    SharedLodBuffers out;
    Mesh& v = out.vertices;
    v.positions.resize(n);
    v.normals.resize(n);
    if (base.has_colors()) v.colors.resize(n);
    v.texcoords.assign(base.texcoords.size(), std::vector<Vec2f>(n));
    for (std::uint32_t c = 0; c < n; ++c) {
        const std::uint32_t i = strips.input_vertex[c];
        v.positions[c] = morph.frame_positions[0][i];
        v.normals[c] = morph.frame_normals[0][i];
        if (base.has_colors()) v.colors[c] = base.colors[i];
        for (std::size_t s = 0; s < base.texcoords.size(); ++s) v.texcoords[s][c] = base.texcoords[s][i];
    }
    v.materials = base.materials;
    v.source_dir = base.source_dir;
    out.input_vertex = strips.input_vertex;

    // The levels' triangles are the strips' own at each level (the runtime replays the records), with
    // the material of their strip.
    lodstrips::LodStrips rt;
    std::string why;
    if (!rt.assign(d, &why)) throw Error(Error::Kind::invalid, "morph glTF: " + why);
    std::vector<std::size_t> levels{0};
    for (std::size_t c : lod.sequences.front().level_collapses) levels.push_back(c);
    std::vector<std::uint32_t> tri;
    for (std::size_t k : levels) {
        rt.go_to_level(k);
        LodIndexRange r;
        r.first_index = out.indices.size();
        r.vertex_count = static_cast<std::uint32_t>(rt.vertex_count());
        for (std::size_t s = 0; s < rt.strip_count(); ++s) {
            tri.clear();
            rt.append_strip_triangles(s, tri);
            out.indices.insert(out.indices.end(), tri.begin(), tri.end());
            if (!base.materials.empty()) out.face_materials.insert(out.face_materials.end(), tri.size() / 3, rt.strip_material(s));
        }
        r.index_count = out.indices.size() - r.first_index;
        out.levels.push_back(r);
    }
    return out;
}

namespace {

// A normal displacement for normalized BYTE storage. n0 + d is normalised by renderers, so any d with
// n0 + d along n will do: d = λ·n − n0 with the largest λ in (0, 1] whose components lie in [-1, 1]
// keeps the direction exactly, and BYTE rounding (≤ 1/254 per component) then turns it by about
// 0.0068/λ rad. λ gets small only when n nearly reverses an axis-aligned n0; there a clamped d can point
// closer, so the candidate (exact λ, or λ = 1, 1/2, ... 1/32 clamped) whose rounded value points closest
// to n wins.
Vec3f fitted_normal_delta(Vec3f n0, Vec3f n) {
    const Vec3f d = n - n0;
    if (std::fabs(d.x) <= 1.f && std::fabs(d.y) <= 1.f && std::fabs(d.z) <= 1.f) return d;
    float lambda = 1.f;
    for (int i = 0; i < 3; ++i) {
        const float a = n0[i], b = n[i];
        if (b > 0.f) lambda = std::min(lambda, (1.f + a) / b);
        if (b < 0.f) lambda = std::min(lambda, (1.f - a) / -b);
    }
    auto candidate = [&](float l) {
        const Vec3f c = n * l - n0;
        return Vec3f{std::clamp(c.x, -1.f, 1.f), std::clamp(c.y, -1.f, 1.f), std::clamp(c.z, -1.f, 1.f)};
    };
    auto rounded_cosine = [&](Vec3f c) {
        const Vec3f q{std::round(c.x * 127.f) / 127.f, std::round(c.y * 127.f) / 127.f, std::round(c.z * 127.f) / 127.f};
        const Vec3f sum = n0 + q;
        const float len = length(sum);
        return len > 0.f ? dot(sum, n) / len : -1.f;
    };
    Vec3f best = candidate(std::max(lambda, 0.f));
    float best_cos = rounded_cosine(best);
    for (float l = 1.f; l >= 1.f / 32.f; l *= 0.5f) {
        const Vec3f c = candidate(l);
        const float cs = rounded_cosine(c);
        if (cs > best_cos) best_cos = cs, best = c;
    }
    return best;
}

}  // namespace

GlbMorphTargets morph_gltf_targets(const MorphMesh& morph, const MorphStripsBuild& strips, const MorphGltfTiming& timing,
                                   bool quantize) {
    const std::size_t K = morph.frame_count();
    if (K < 2) throw Error(Error::Kind::invalid, "morph glTF: at least two frames are needed for morph targets");
    const std::uint32_t n = strips.data.strips.vertex_count;
    GlbMorphTargets t;
    for (std::size_t j = 1; j < K; ++j) {
        std::vector<Vec3f>& dp = t.position_deltas.emplace_back(n);
        std::vector<Vec3f>& dn = t.normal_deltas.emplace_back(n);
        for (std::uint32_t c = 0; c < n; ++c) {
            const std::uint32_t i = strips.input_vertex[c];
            dp[c] = morph.frame_positions[j][i] - morph.frame_positions[0][i];
            dn[c] = quantize ? fitted_normal_delta(morph.frame_normals[0][i], morph.frame_normals[j][i])
                             : morph.frame_normals[j][i] - morph.frame_normals[0][i];
        }
        t.names.push_back(j < morph.frame_names.size() ? morph.frame_names[j] : "frame " + std::to_string(j));
    }
    t.quantize = quantize;
    if (timing.animated) {
        for (std::size_t k = 0; k < K; ++k) {
            t.key_times.push_back(static_cast<float>(timing.start_seconds + timing.seconds_per_frame * double(k)));
            std::vector<float>& w = t.key_weights.emplace_back(K - 1, 0.f);
            if (k > 0) w[k - 1] = 1.f;
        }
    }
    return t;
}

MorphGltfResult write_morph_glb(const MorphMesh& morph, const MorphLod& lod, const MorphStripsBuild& strips,
                                const MorphGltfOptions& options, const std::string& path, Progress* progress) {
    const SharedLodBuffers shared = morph_gltf_buffers(morph, lod, strips);
    const GlbMorphTargets targets = morph_gltf_targets(morph, strips, options.timing, options.quantize);
    GlbOptions go;
    go.name = options.name;
    go.screen_coverage = options.screen_coverage;
    MorphGltfResult r;
    r.glb = write_glb(shared, go, targets, path, progress);
    r.targets = targets.position_deltas.size();
    for (const LodIndexRange& l : shared.levels) {
        r.level_triangles.push_back(l.index_count / 3);
        r.level_vertices.push_back(l.vertex_count);
    }
    return r;
}

}  // namespace lodforge

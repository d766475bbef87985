// Writes what the standalone morph runtime test reads: a per-frame .lfmstrips file made by the core (the
// morph sphere, 9 frames, one change set per frame, degenerate joins) and the reference faces of each
// frame's own collapse sequence (morph_level_indices) at a set of times and LOD factors.
// Usage: morph_strips_fixture DIR. Reference file: u32 case count, then per case f64 t, f64 lod, u32 change
// set, u32 triangle count, 3 × u32 per triangle (vertex numbers of the file, input winding, smallest
// first, sorted); little-endian.
#include "lodforge/morph/morph.h"
#include "lodforge/morph/morph_lod.h"
#include "lodforge/morph/morph_lodstrips.h"

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: morph_strips_fixture DIR\n");
        return 2;
    }
    try {
        using namespace lodforge;
        std::filesystem::create_directories(argv[1]);
        MorphLoadOptions o;
        o.frames = 9;
        const MorphMesh morph =
            load_morph(std::string(LODFORGE_SHARED_DATA) + "/morph-animated-morph-sphere/AnimatedMorphSphere.gltf", o);
        MorphLodParams p;
        p.order = MorphOrder::per_frame;
        p.levels = {0.5f, 0.1f};
        p.simplify.preserve_seams = false;
        const MorphLod lod = build_morph_lod(morph, p);
        MorphStripsParams sp;
        sp.join = StripJoin::degenerate;
        sp.max_strip_length = 48;
        const MorphStripsBuild b = build_morph_lodstrips(morph, lod, sp);
        const std::string stem = std::string(argv[1]) + "/sphere_per_frame";
        write_morph_lodstrips(b.data, stem + ".lfmstrips", MorphEncoding::float32);
        std::ofstream out(stem + ".ref", std::ios::binary);
        auto put = [&](const auto& v) { out.write(reinterpret_cast<const char*>(&v), sizeof v); };
        const double times[] = {0.0, 0.2, 0.49, 0.75, 1.0};
        const double lods[] = {1.0, 0.7, 0.3, 0.0};
        put(static_cast<std::uint32_t>(std::size(times) * std::size(lods)));
        for (double t : times)
            for (double f : lods) {
                const std::size_t q = morph_sequence_at(lod, morph.frame_count(), t);
                const MorphSequence& seq = lod.sequences[q];
                const std::vector<std::uint32_t> idx = morph_level_indices(morph, seq, morph_collapses_for(seq, f));
                std::vector<std::array<std::uint32_t, 3>> tris;
                for (std::size_t i = 0; i < idx.size(); i += 3) {
                    std::array<std::uint32_t, 3> tri{b.canonical[idx[i]], b.canonical[idx[i + 1]], b.canonical[idx[i + 2]]};
                    std::rotate(tri.begin(), std::min_element(tri.begin(), tri.end()), tri.end());
                    tris.push_back(tri);
                }
                std::sort(tris.begin(), tris.end());
                put(t), put(f), put(static_cast<std::uint32_t>(q)), put(static_cast<std::uint32_t>(tris.size()));
                for (const auto& tri : tris)
                    for (std::uint32_t v : tri) put(v);
            }
        if (!out) throw std::runtime_error("cannot write " + stem + ".ref");
    } catch (const std::exception& e) {
        std::fprintf(stderr, "morph_strips_fixture: %s\n", e.what());
        return 1;
    }
    return 0;
}

// Morph LOD benchmark: the three collapse orders of build_morph_lod (single order over all frames,
// one order per keyframe as the LODStrips thesis does, naive = frame 0's order reused) on the horse
// gallop and the glTF morph samples, in one run.
//
// Printed per model, order and level: Metro distance (compare(), symmetric, relative to the frame's
// bounding-box diagonal) of the level at every keyframe against that keyframe's full mesh — mean over
// the frames of the mean distance, and the worst frame's Hausdorff distance; build seconds; the .lfmorph
// file size per frame (float and 16-bit quantised positions); extraction time per frame change (blend +
// faces of the level + compact mesh, median over a sweep of t at fixed LOD factor; also the face replay
// alone and the blend alone, which is all a runtime redoes per frame while the sequence stays); for the
// orders, the morph LODStrips file (.lfmstrips; per-frame: one change set per keyframe) per frame, for
// the orders with one sequence the glTF export (morph targets per level, .glb) per frame, the strip
// runtime's time per frame change (set_frame at a fixed level) and per LOD change (go_to_lod between
// levels, at a fixed frame), and for per-frame change sets the frame-switch cost (same set, switch to a
// set at the level, switch to a set at full detail). --strips-only prints only the strip tables.
//
//   lodforge_bench_morph [--models horse,sphere,cube] [--samples N] [--frame-stride S] [--reps N]
//                        [--frame-cost max|sum] [--cost-frames N] [--orders single,per-frame,naive]
//                        [--strips-only] [--schedule default|passes|greedy]

#include "bench_util.h"
#include "lodforge/error.h"
#include "lodforge/morph/morph.h"
#include "lodforge/morph/morph_file.h"
#include "lodforge/morph/morph_gltf.h"
#include "lodforge/morph/morph_lodstrips.h"
#include "lodforge/morph/morph_lod.h"

#include <meshoptimizer.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <malloc.h>
#include <sstream>
#include <string>
#include <vector>

using namespace lodforge;

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

using lodforge::bench::split;

struct Model {
    std::string key, label, path;
    bool close_seams = false;  // flat-shaded quads: every edge is a normal seam
};

// Bytes allocated on the heap now (glibc).
std::size_t heap_bytes() {
    const struct mallinfo2 m = mallinfo2();
    return m.uordblks + m.hblkhd;
}

template <class F>
double median_ms(std::size_t reps, F&& f) {
    std::vector<double> v;
    for (std::size_t r = 0; r < reps; ++r) {
        const auto a = Clock::now();
        f(r);
        v.push_back(seconds_since(a) * 1e3);
    }
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

// The morph LODStrips of every order (per-frame: one change set per keyframe) and the glTF export of the
// one-sequence orders: storage per frame, runtime times.
void strips_section(const MorphMesh& morph, const std::vector<MorphLod>& lods, std::size_t reps, const std::string& key) {
    const double K = double(morph.frame_count());
    const std::string glb = (std::filesystem::temp_directory_path() / ("lodforge-bench-morph-" + key + ".glb")).string();
    std::printf("\n| order | .lfmstrips 16-bit, KB/frame | .lfmstrips float, KB/frame | of which strips + changes, KB | "
                ".glb (morph targets), KB/frame | build strips s | change sets | further change sets (SETS), KB |\n"
                "|---|---|---|---|---|---|---|---|\n");
    std::vector<std::pair<const MorphLod*, MorphStripsBuild>> built;
    for (const MorphLod& lod : lods) {
        auto t0 = Clock::now();
        MorphStripsBuild b = build_morph_lodstrips(morph, lod);
        const double build = seconds_since(t0);
        const MorphStripsStorage q = morph_lodstrips_storage(b.data, MorphEncoding::quantized16);
        const MorphStripsStorage f = morph_lodstrips_storage(b.data, MorphEncoding::float32);
        std::string glb_kb = "n/a (one order per level)";
        if (morph.frame_count() > 1 && lod.sequences.size() == 1) {
            MorphGltfOptions o;
            o.timing = morph_gltf_timing(morph);
            const MorphGltfResult r = write_morph_glb(morph, lod, b, o, glb);
            char text[32];
            std::snprintf(text, sizeof text, "%.1f", double(r.glb.bytes) / K / 1024.0);
            glb_kb = text;
            std::filesystem::remove(glb);
        }
        std::printf("| %s | **%.1f** | %.1f | %.1f | %s | %.3f | %zu | %.1f |\n", morph_order_name(lod.order),
                    q.bytes_per_frame / 1024.0, f.bytes_per_frame / 1024.0, double(q.strips_bytes) / 1024.0, glb_kb.c_str(),
                    build, b.data.change_set_count(), double(q.sets_bytes) / 1024.0);
        built.emplace_back(&lod, std::move(b));
    }
    std::printf("\n| order | LOD factor | triangles | set_frame (frame change), ms | go_to_lod 1 → f → 1, ms | "
                "frame + LOD change, ms |\n|---|---|---|---|---|---|\n");
    for (auto& [lod, b] : built) {
        lodstrips::MorphLodStrips rt;
        std::string why;
        if (!rt.assign(b.data, &why)) throw Error(Error::Kind::invalid, why);
        for (double f : {1.0, 0.5, 0.0}) {
            rt.go_to_lod(f);
            const std::size_t tris = rt.triangle_count();
            const double frame = median_ms(reps, [&](std::size_t r) { rt.set_frame(double(r % 7 + 1) / 8.0); });
            const double lodc = median_ms(reps, [&](std::size_t) {
                rt.go_to_lod(f);
                rt.go_to_lod(1.0);
            });
            const double both = median_ms(reps, [&](std::size_t r) {
                rt.set_frame(double(r % 7 + 1) / 8.0);
                rt.go_to_lod(r % 2 ? f : 1.0);
            });
            rt.clear_changes();
            rt.clear_vertex_changes();
            std::printf("| %s | %.1f | %zu | %.4f | %.4f | %.4f |\n", morph_order_name(lod->order), f, tris, frame, lodc, both);
        }
    }
    // Per-frame change sets: what a frame change costs when it stays in one change set, when it switches
    // to a set already at the level (each set keeps its own buffer: the steady state of playback at a
    // fixed LOD), and when it switches to a set still at full detail (first visit, or after a LOD change
    // elsewhere: the set replays the collapses from level 0), and what the engine then uploads.
    for (auto& [lod, b] : built) {
        if (b.data.change_set_count() < 3) continue;
        std::string why;
        lodstrips::MorphLodStrips one;  // memory: the same data as a single order (change set 0 alone)
        lodstrips::MorphData single = b.data;
        single.frame_sets.clear();
        const std::size_t heap0 = heap_bytes();
        if (!one.assign(std::move(single), &why)) throw Error(Error::Kind::invalid, why);
        const std::size_t heap1 = heap_bytes();
        lodstrips::MorphLodStrips rt;
        if (!rt.assign(b.data, &why)) throw Error(Error::Kind::invalid, why);
        const std::size_t heap2 = heap_bytes();
        lodstrips::MorphLodStrips lim;  // one further set live: the others parked as records
        lim.set_live_set_limit(1);
        if (!lim.assign(b.data, &why)) throw Error(Error::Kind::invalid, why);
        const std::size_t heap3 = heap_bytes();
        std::printf("\nruntime heap: %.1f MB with %zu change sets live, %.1f MB with one further set live "
                    "(set_live_set_limit(1)), %.1f MB with change set 0 alone\n",
                    (double(heap2) - double(heap1)) / 1048576.0, rt.change_set_count(),
                    (double(heap3) - double(heap2)) / 1048576.0, (double(heap1) - double(heap0)) / 1048576.0);
        const std::size_t sets = rt.change_set_count();
        const auto t_of = [&](std::size_t q) { return double(rt.change_set_frame(q)) / std::max(1.0, K - 1.0); };
        // a quarter frame past a keyframe: still that keyframe's set, and every case blends two frames
        const double step = 0.25 / std::max(1.0, K - 1.0);
        std::printf("\n%s, %zu change sets: frame-switch cost (median of %zu)\n\n| LOD factor | triangles | set_frame, same set, ms "
                    "| set_frame, switch to a set at the level, ms | set_frame, switch to a set at full detail, ms | "
                    "upload after a switch: indices + vertices, KB | switch to a parked set (limit 1: rebuild), ms |\n"
                    "|---|---|---|---|---|---|---|\n",
                    morph_order_name(lod->order), sets, reps);
        for (double f : {1.0, 0.5, 0.0}) {
            rt.go_to_lod(f);
            for (std::size_t q = 0; q < sets; ++q) rt.set_frame(t_of(q));  // every set at the level
            const std::size_t tris = rt.triangle_count();
            const double same = median_ms(reps, [&](std::size_t r) { rt.set_frame(t_of(sets / 2) + step * (r % 2 ? 1.0 : 0.5)); });
            const double warm = median_ms(reps, [&](std::size_t r) { rt.set_frame(t_of((r * 7 + 3) % sets) + step); });
            std::vector<double> cold;
            for (std::size_t r = 0; r < reps; ++r) {
                const std::size_t q = (r * 7 + 3) % sets, other = (q + sets / 2) % sets;
                rt.go_to_lod(1.0);
                rt.set_frame(t_of(q));  // set q at full detail
                rt.set_frame(t_of(other));
                rt.go_to_lod(f);
                const auto a = Clock::now();
                rt.set_frame(t_of(q) + step);
                cold.push_back(seconds_since(a) * 1e3);
            }
            std::sort(cold.begin(), cold.end());
            const double upload = double(rt.index_count() * 4 + rt.vertex_count() * 24) / 1024.0;
            rt.clear_changes();
            rt.clear_vertex_changes();
            lim.go_to_lod(f);
            const double parked = median_ms(reps, [&](std::size_t r) { lim.set_frame(t_of((r * 7 + 3) % sets) + step); });
            std::printf("| %.1f | %zu | %.4f | %.4f | %.4f | %.1f | %.4f |\n", f, tris, same, warm, cold[cold.size() / 2],
                        upload, parked);
        }
    }
}

// The glTF export of the first one-sequence order: quantised targets (KHR_mesh_quantization, the
// default) and float targets, per frame; and what meshoptimizer's vertex codec (EXT_meshopt_compression's
// ATTRIBUTES mode) would make of the quantised target views of that very file, which the Khronos
// validator here cannot check (it does not implement the extension), so it is an estimate, not an export.
void gltf_section(const MorphMesh& morph, const std::vector<MorphLod>& lods, const std::string& key) {
    if (morph.frame_count() < 2) return;
    const MorphLod* lod = nullptr;
    for (const MorphLod& l : lods)
        if (l.sequences.size() == 1 && !lod) lod = &l;
    if (!lod) return;
    const double K = double(morph.frame_count());
    const MorphStripsBuild b = build_morph_lodstrips(morph, *lod);
    const std::string path = (std::filesystem::temp_directory_path() / ("lodforge-bench-morph-gltf-" + key + ".glb")).string();
    MorphGltfOptions o;
    o.timing = morph_gltf_timing(morph);
    const MorphGltfResult f = [&] {
        o.quantize = false;
        return write_morph_glb(morph, *lod, b, o, path);
    }();
    o.quantize = true;
    const MorphGltfResult q = write_morph_glb(morph, *lod, b, o, path);
    // The quantised file's target views, encoded by meshopt_encodeVertexBuffer (version 0 codec).
    std::ifstream in(path, std::ios::binary);
    const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::filesystem::remove(path);
    auto u32 = [&](std::size_t at) {
        return std::uint32_t(bytes[at]) | std::uint32_t(bytes[at + 1]) << 8 | std::uint32_t(bytes[at + 2]) << 16 |
               std::uint32_t(bytes[at + 3]) << 24;
    };
    const std::size_t json_len = u32(12);
    const nlohmann::json j = nlohmann::json::parse(bytes.begin() + 20, bytes.begin() + 20 + long(json_len));
    const std::size_t bin = 20 + json_len + 8;
    std::vector<int> views;
    for (const auto& mesh : j["meshes"])
        for (const auto& p : mesh["primitives"])
            for (const auto& t : p["targets"])
                for (const char* a : {"POSITION", "NORMAL"}) {
                    const int v = j["accessors"][t[a].get<int>()]["bufferView"].get<int>();
                    if (std::find(views.begin(), views.end(), v) == views.end()) views.push_back(v);
                }
    std::size_t raw = 0, encoded = 0;
    for (int v : views) {
        const auto& view = j["bufferViews"][std::size_t(v)];
        const std::size_t len = view["byteLength"].get<std::size_t>(), stride = view["byteStride"].get<std::size_t>();
        const std::size_t count = len / stride;
        std::vector<unsigned char> out(meshopt_encodeVertexBufferBound(count, stride));
        encoded += meshopt_encodeVertexBuffer(out.data(), out.size(), bytes.data() + bin + view["byteOffset"].get<std::size_t>(),
                                              count, stride);
        raw += len;
    }
    const double vertices = double(b.data.strips.vertex_count);
    std::printf("\n| %s .glb | quantised (default), KB/frame | float (--gltf-float), KB/frame | quantised targets, B per vertex "
                "and frame | + meshopt vertex codec on the targets (estimate), KB/frame |\n|---|---|---|---|---|\n",
                key.c_str());
    std::printf("| %s | **%.1f** | %.1f | %.1f | %.1f |\n", morph_order_name(lod->order), double(q.glb.bytes) / K / 1024.0,
                double(f.glb.bytes) / K / 1024.0, double(raw) / (K - 1) / vertices,
                double(q.glb.bytes - raw + encoded) / K / 1024.0);
}

}  // namespace

int main(int argc, char** argv) {
    std::string models = "horse,sphere,cube";
    std::size_t samples = 20000, stride = 1, reps = 50, cost_frames = MorphLodParams{}.cost_frames;  // the product default (16)
    std::string frame_cost = "sum", orders = "single,per-frame,naive", schedule = "default";
    bool strips_only = false;  // only the morph LODStrips tables (no Metro errors, .lfmorph, extraction)
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&] { return bench::option_value(argc, argv, i); };
        if (a == "--models") models = next();
        else if (a == "--samples") samples = std::strtoul(next().c_str(), nullptr, 10);
        else if (a == "--frame-stride") stride = std::max<std::size_t>(1, std::strtoul(next().c_str(), nullptr, 10));
        else if (a == "--frame-cost") frame_cost = next();
        else if (a == "--cost-frames") cost_frames = std::strtoul(next().c_str(), nullptr, 10);
        else if (a == "--orders") orders = next();
        else if (a == "--reps") reps = std::max<std::size_t>(1, std::strtoul(next().c_str(), nullptr, 10));
        else if (a == "--strips-only") strips_only = true;
        else if (a == "--schedule") schedule = next();
        else {
            std::fprintf(stderr, "usage: lodforge_bench_morph [--models horse,sphere,cube] [--samples N] "
                                 "[--frame-stride S] [--reps N] [--frame-cost max|sum] [--cost-frames N]\n"
                                 "       [--orders single,per-frame,naive] [--strips-only] [--schedule default|passes|greedy]\n");
            return 2;
        }
    }
    const std::string data = LODFORGE_SHARED_DATA;
    const std::vector<Model> all = {
        {"horse", "horse gallop (48 OBJ frames)", data + "/seq-horse-gallop", false},
        {"sphere", "AnimatedMorphSphere (glTF, 2 targets, weights animation)",
         data + "/morph-animated-morph-sphere/AnimatedMorphSphere.gltf", true},
        {"cube", "AnimatedMorphCube (glTF, 2 targets, weights animation)",
         data + "/morph-animated-morph-cube/AnimatedMorphCube.gltf", true},
    };
    const std::string tmp = (std::filesystem::temp_directory_path() / "lodforge-bench-morph.lfmorph").string();
    try {
        for (const std::string& key : split(models)) {
            const auto it = std::find_if(all.begin(), all.end(), [&](const Model& m) { return m.key == key; });
            if (it == all.end()) {
                std::fprintf(stderr, "unknown model %s\n", key.c_str());
                return 2;
            }
            auto t0 = Clock::now();
            const MorphMesh morph = load_morph(it->path);
            std::printf("\n## %s: %zu vertices, %zu triangles, %zu frames (load %.2f s)\n", it->label.c_str(),
                        morph.vertex_count(), morph.base.triangle_count(), morph.frame_count(), seconds_since(t0));
            MorphMeasureParams mp;
            for (std::size_t f = 0; f < morph.frame_count(); f += stride) mp.frames.push_back(f);
            mp.distance.samples = samples;
            std::printf("measured at %zu frames, %zu samples per surface\n\n", mp.frames.size(), samples);
            std::printf("| order | level | triangles | mean of per-frame mean | worst frame mean | worst Hausdorff | build s |\n");
            std::printf("|---|---|---|---|---|---|---|\n");
            std::vector<MorphLod> lods;
            for (MorphOrder order : {MorphOrder::single, MorphOrder::per_frame, MorphOrder::naive}) {
                if (orders.find(morph_order_name(order)) == std::string::npos) continue;
                MorphLodParams p;
                p.frame_cost = frame_cost == "max" ? SimplifyParams::FrameCost::max : SimplifyParams::FrameCost::sum;
                p.cost_frames = cost_frames;
                p.order = order;
                p.simplify.preserve_seams = !it->close_seams;
                if (schedule == "passes") p.simplify.schedule = SimplifyParams::Schedule::passes;
                else if (schedule == "greedy") p.simplify.schedule = SimplifyParams::Schedule::greedy;
                t0 = Clock::now();
                MorphLod lod = build_morph_lod(morph, p);
                const double build = seconds_since(t0);
                if (strips_only) {
                    std::printf("| %s | (build only) | | | | | %.3f |\n", morph_order_name(order), build);
                    lods.push_back(std::move(lod));
                    continue;
                }
                const std::vector<MorphLevelError> errors = measure_morph_lod(morph, lod, mp);
                for (std::size_t level = 0; level < lod.levels.size(); ++level) {
                    double sum = 0, worst_mean = 0, worst_h = 0, tris = 0;
                    std::size_t n = 0;
                    for (const MorphLevelError& e : errors) {
                        if (e.level != level) continue;
                        sum += e.distance.mean_relative;
                        worst_mean = std::max(worst_mean, e.distance.mean_relative);
                        worst_h = std::max(worst_h, e.distance.hausdorff_relative);
                        tris += double(e.triangles);
                        ++n;
                    }
                    std::printf("| %s | %.2f | %.0f | %.3e | %.3e | %.3e | %s |\n", morph_order_name(order),
                                double(lod.levels[level]), tris / double(n), sum / double(n), worst_mean, worst_h,
                                level == 0 ? std::to_string(build).substr(0, 5).c_str() : "");
                }
                lods.push_back(std::move(lod));
            }
            if (strips_only) {
                strips_section(morph, lods, reps, it->key);
                continue;
            }
            std::printf("\n| order | encoding | file bytes | bytes per frame | per frame, KB | sequences, KB |\n|---|---|---|---|---|---|\n");
            for (const MorphLod& lod : lods)
                for (MorphEncoding enc : {MorphEncoding::float32, MorphEncoding::quantized16}) {
                    MorphWriteOptions wo;
                    wo.encoding = enc;
                    write_morph_lod(tmp, morph, lod, wo);
                    const auto bytes = std::filesystem::file_size(tmp);
                    const MorphFileStats st = morph_file_stats(morph, lod, wo);
                    std::printf("| %s | %s | %llu | %.0f | %.1f | %.1f |\n", morph_order_name(lod.order),
                                enc == MorphEncoding::float32 ? "float" : "16-bit", static_cast<unsigned long long>(bytes),
                                double(bytes) / double(morph.frame_count()), double(bytes) / double(morph.frame_count()) / 1024.0,
                                double(st.sequence_bytes) / 1024.0);
                }
            std::filesystem::remove(tmp);
            // Extraction per frame change: t sweeps the sequence at a fixed LOD factor.
            std::printf("\n| order | LOD factor | extraction per frame change, ms (median of %zu) | faces only, ms | blend only, ms |\n|---|---|---|---|---|\n", reps);
            for (const MorphLod& lod : lods)
                for (double f : {1.0, 0.5, 0.0}) {
                    std::vector<double> full, faces, blend;
                    std::vector<Vec3f> pos, nrm;
                    for (std::size_t r = 0; r < reps; ++r) {
                        const double t = double(r) / double(reps - 1 > 0 ? reps - 1 : 1);
                        auto a = Clock::now();
                        const Mesh m = extract_morph(morph, lod, t, f);
                        full.push_back(seconds_since(a) * 1e3);
                        const MorphSequence& seq = lod.sequences[morph_sequence_at(lod, morph.frame_count(), t)];
                        a = Clock::now();
                        const auto idx = morph_level_indices(morph, seq, morph_collapses_for(seq, f));
                        faces.push_back(seconds_since(a) * 1e3);
                        if (m.triangle_count() * 3 != idx.size()) throw Error(Error::Kind::invalid, "extraction mismatch");
                        a = Clock::now();
                        morph_positions_at(morph, t, pos);
                        morph_normals_at(morph, t, nrm);
                        blend.push_back(seconds_since(a) * 1e3);
                    }
                    std::sort(full.begin(), full.end());
                    std::sort(faces.begin(), faces.end());
                    std::sort(blend.begin(), blend.end());
                    std::printf("| %s | %.1f | %.3f | %.3f | %.3f |\n", morph_order_name(lod.order), f, full[full.size() / 2],
                                faces[faces.size() / 2], blend[blend.size() / 2]);
                }
            strips_section(morph, lods, reps, it->key);
            gltf_section(morph, lods, it->key);
        }
    } catch (const Error& e) {
        std::fprintf(stderr, "lodforge_bench_morph: %s\n", e.what());
        return 1;
    }
    return 0;
}

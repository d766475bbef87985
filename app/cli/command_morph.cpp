// `lodforge morph build | extract | info`: morphing meshes with LOD (docs/morph.md).
#include "commands.h"
#include "mesh_output.h"
#include "simplify_options.h"
#include "terminal_progress.h"

#include "lodforge/error.h"
#include "lodforge/io/mesh_io.h"
#include "lodforge/morph/morph.h"
#include "lodforge/morph/morph_file.h"
#include "lodforge/morph/morph_gltf.h"
#include "lodforge/morph/morph_lodstrips.h"
#include "lodforge/morph/morph_lod.h"
#include "lodforge/morph/supermesh.h"

#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace lodforge::cli {
namespace {

MorphOrder parse_order(const std::string& s) {
    if (s == "single") return MorphOrder::single;
    if (s == "per-frame") return MorphOrder::per_frame;
    if (s == "naive") return MorphOrder::naive;
    throw Error(Error::Kind::argument, "morph build: --order must be single, per-frame or naive, got '" + s + "'");
}

void add_morph_build(CLI::App& morph, const GlobalOptions& global) {
    struct Options {
        std::vector<std::string> inputs;
        std::string output, order = "single", levels = "0.5,0.25,0.1,0.03", landmarks, weights;
        std::string encoding = "16bit", frame_cost = "sum", gltf, strips;
        long long frames = 0, cost_frames = 16;
        bool close_seams = false, gltf_float = false;
    };
    auto o = std::make_shared<Options>();
    CLI::App* cmd = morph.add_subcommand(
        "build", "Build a morph LOD file from keyframes with identical connectivity (a directory of .obj/.ply "
                 "frames sorted by name, or a .gltf/.glb with morph targets), or from two closed genus-0 meshes "
                 "A B aligned by --landmarks (supermesh)");
    cmd->add_option("INPUT", o->inputs, "Sequence directory or glTF, or two closed genus-0 meshes A B with --landmarks")
        ->required()
        ->expected(1, 2);
    cmd->add_option("-o,--output", o->output, "Output .lfmorph file")->required();
    cmd->add_option("--frames", o->frames, "Keep this many keyframes, evenly spread (0 = all)");
    cmd->add_option("--order", o->order, "Collapse order: single (one order over all frames), per-frame, naive")
        ->capture_default_str();
    cmd->add_option("--levels", o->levels, "Stored levels as triangle ratios, decreasing, in (0, 1)")->capture_default_str();
    cmd->add_option("--frame-cost", o->frame_cost, "single order: combine frame costs by max or sum")
        ->check(CLI::IsMember({"max", "sum"}))
        ->capture_default_str();
    cmd->add_option("--cost-frames", o->cost_frames, "single order: frames whose shapes enter the cost (0 = all)")
        ->capture_default_str();
    cmd->add_option("--encoding", o->encoding, "Positions/normals in the file: float or 16bit")
        ->check(CLI::IsMember({"float", "16bit"}))
        ->capture_default_str();
    cmd->add_option("--weights", o->weights, kWeightsHelp);
    cmd->add_flag("--close-seams", o->close_seams, "Let attribute seams close (flat-shaded inputs)");
    cmd->add_option("--gltf", o->gltf,
                    "Also write a .glb: each level a mesh with the frames as morph targets and the source's "
                    "animation, plus the morph LODStrips file (.lfmstrips) next to it (single or naive order)");
    cmd->add_flag("--gltf-float", o->gltf_float,
                  "--gltf: float32 morph targets (default: 16-bit positions and 8-bit normals, KHR_mesh_quantization)");
    cmd->add_option("--strips", o->strips,
                    "Also write the morph LODStrips file (.lfmstrips) here (any order; per-frame: one change set per frame)");
    cmd->add_option("--landmarks", o->landmarks, "Landmark pairs (vertex of A, vertex of B) aligning two genus-0 meshes (docs/morph.md)");
    cmd->callback([o, &global] {
        const bool two_meshes = o->inputs.size() == 2;
        if (two_meshes != !o->landmarks.empty())
            throw Error(Error::Kind::argument, "morph build: two meshes need --landmarks L.json, and --landmarks needs two meshes");
        if (o->frames < 0 || o->cost_frames < 0)
            throw Error(Error::Kind::argument, "morph build: --frames and --cost-frames must be >= 0");
        if (o->frames == 1) throw Error(Error::Kind::argument, "morph build: --frames must be 0 (all) or at least 2");
        MorphLodParams params;
        params.order = parse_order(o->order);
        params.levels.clear();
        for (double r : parse_number_list(o->levels, "--levels")) params.levels.push_back(static_cast<float>(r));
        params.frame_cost = o->frame_cost == "max" ? SimplifyParams::FrameCost::max : SimplifyParams::FrameCost::sum;
        params.cost_frames = static_cast<std::size_t>(o->cost_frames);
        if (!o->weights.empty()) parse_weights(o->weights, params.simplify.weights);
        params.simplify.preserve_seams = !o->close_seams;
        TerminalProgress progress(!global.quiet && stderr_is_terminal());
        MorphLoadOptions lo;
        lo.frames = static_cast<std::size_t>(o->frames);
        SupermeshParams sp;
        sp.frames = lo.frames;
        const MorphMesh mesh = two_meshes ? load_supermesh(o->inputs[0], o->inputs[1], o->landmarks, sp, &progress)
                                          : load_morph(o->inputs.front(), lo, &progress);
        const MorphLod lod = build_morph_lod(mesh, params, &progress);
        MorphWriteOptions wo;
        wo.encoding = o->encoding == "float" ? MorphEncoding::float32 : MorphEncoding::quantized16;
        if (!o->gltf.empty() || !o->strips.empty()) {
            // Before anything is written, so that an order the strips cannot take leaves no output.
            // The strips take per-frame orders (one change set per frame); glTF levels need one
            // connectivity per level, so one order (docs/morph.md).
            if (lod.sequences.size() != 1 && !o->gltf.empty())
                throw_error(Error::Kind::unsupported, o->gltf,
                            "--gltf needs one collapse order (--order single or naive): a glTF level has one "
                            "connectivity for every frame (--strips takes per-frame orders; see docs/morph.md)");
            if (mesh.frame_count() < 2 && !o->gltf.empty())
                throw_error(Error::Kind::invalid, o->gltf, "morph targets need at least two frames");
        }
        // Everything is computed before the first write, and a failed later write removes the earlier
        // outputs of this run: a failed run leaves no output.
        const bool extra = !o->gltf.empty() || !o->strips.empty();
        MorphStripsBuild strips;
        MorphGltfOptions go;
        std::string strips_path = o->strips;
        if (extra) {
            strips = build_morph_lodstrips(mesh, lod, {}, &progress);
            if (strips_path.empty()) strips_path = std::filesystem::path(o->gltf).replace_extension(".lfmstrips").string();
            go.name = std::filesystem::path(o->gltf).stem().string();
            if (!o->gltf.empty()) go.timing = morph_gltf_timing(mesh);
            go.quantize = !o->gltf_float;
        }
        std::vector<std::string> written;
        try {
            write_morph_lod(o->output, mesh, lod, wo, &progress);
            written.push_back(o->output);
            if (extra) {
                write_morph_lodstrips(strips.data, strips_path, wo.encoding);
                written.push_back(strips_path);
                const MorphStripsStorage ss = morph_lodstrips_storage(strips.data, wo.encoding);
                std::printf("%s: %zu strips, %zu change set(s), %zu collapses in set 0, %zu bytes (%.1f KB per frame)\n",
                            strips_path.c_str(), strips.data.strips.strip_count(), strips.data.change_set_count(),
                            strips.data.strips.collapse_count(), ss.file_bytes, ss.bytes_per_frame / 1024.0);
            }
            if (!o->gltf.empty()) {
                const MorphGltfResult gr = write_morph_glb(mesh, lod, strips, go, o->gltf, &progress);
                std::printf("%s: %zu levels, %zu morph targets each, %s, %zu bytes\n", o->gltf.c_str(),
                            gr.level_triangles.size(), gr.targets, go.timing.animated ? "animated" : "no animation",
                            gr.glb.bytes);
            }
        } catch (...) {
            std::error_code ignored;
            for (const std::string& f : written) std::filesystem::remove(f, ignored);
            throw;
        }
        const MorphFileStats st = morph_file_stats(mesh, lod, wo);
        std::printf("%s: %zu frames, %zu vertices, %zu triangles, order %s, %zu sequence(s)\n", o->output.c_str(),
                    mesh.frame_count(), mesh.vertex_count(), lod.triangles, morph_order_name(lod.order), lod.sequences.size());
        for (std::size_t l = 0; l < lod.levels.size(); ++l)
            std::printf("  level %zu (ratio %.3g): %zu triangles\n", l, double(lod.levels[l]),
                        lod.sequences.front().level_triangles[l]);
        std::printf("  %zu bytes, %.1f KB per frame\n", st.total_bytes,
                    double(st.total_bytes) / double(mesh.frame_count()) / 1024.0);
    });
}

void add_morph_extract(CLI::App& morph, const GlobalOptions& global) {
    struct Options {
        std::string input, output;
        double t = 0, lod = 1;
    };
    auto o = std::make_shared<Options>();
    CLI::App* cmd = morph.add_subcommand("extract", "Write the pose at time t with LOD factor F as a mesh");
    cmd->add_option("IN", o->input, "Morph LOD file (.lfmorph) or morph LODStrips file (.lfmstrips: the strip "
                                    "runtime's set_frame + go_to_lod)")
        ->required();
    cmd->add_option("--t", o->t, "Time in [0, 1] across the whole sequence")->required();
    cmd->add_option("--lod", o->lod, "LOD factor in [0, 1]: 0 the coarsest stored level, 1 full detail")->required();
    cmd->add_option("-o,--output", o->output, "Output mesh (.ply, .obj or .glb)")->required();
    cmd->callback([o, &global] {
        if (!(o->t >= 0 && o->t <= 1)) throw Error(Error::Kind::argument, "morph extract: --t must be in [0, 1]");
        if (!(o->lod >= 0 && o->lod <= 1)) throw Error(Error::Kind::argument, "morph extract: --lod must be in [0, 1]");
        check_mesh_output("morph extract", o->output);
        TerminalProgress progress(!global.quiet && stderr_is_terminal());
        Mesh m;
        if (is_morph_lodstrips_file(o->input)) {
            lodstrips::MorphLodStrips rt;
            std::string why;
            if (!rt.assign(read_morph_lodstrips(o->input), &why)) throw_error(Error::Kind::format, o->input, why);
            rt.set_frame(o->t);
            rt.go_to_lod(o->lod);
            m = morph_lodstrips_mesh(rt);
        } else {
            const MorphLodFile f = read_morph_lod(o->input, &progress);
            m = extract_morph(f.morph, f.lod, o->t, o->lod);
        }
        write_mesh_output(m, o->output, {}, &progress);
        std::printf("%s: t %.4g, LOD %.4g: %zu triangles, %zu vertices\n", o->output.c_str(), o->t, o->lod,
                    m.triangle_count(), m.vertex_count());
    });
}

void print_strips_info(const std::string& path, bool json) {
    const lodstrips::MorphData d = read_morph_lodstrips(path);
    const auto bytes = std::filesystem::file_size(path);
    const lodstrips::Data& s = d.strips;
    nlohmann::ordered_json j;
    j["file"] = path;
    j["format"] = "lfmstrips";
    j["version"] = d.version;
    j["bytes"] = bytes;
    j["encoding"] = d.quantized ? "16bit" : "float";
    j["frames"] = d.frame_count;
    j["vertices"] = s.vertex_count;
    j["strips"] = s.strip_count();
    j["restart"] = s.restart;
    j["collapses"] = s.collapse_count();
    j["triangles"] = s.triangles.front();
    j["coarsest_triangles"] = s.triangles.back();
    j["bytes_per_frame"] = double(bytes) / double(d.frame_count);
    nlohmann::ordered_json sets = nlohmann::ordered_json::array();
    for (std::size_t i = 0; i < d.change_set_count(); ++i) {
        const lodstrips::Data& r = i == 0 ? s : d.frame_sets[i - 1].records;
        sets.push_back({{"frame", i == 0 ? d.strips_frame : d.frame_sets[i - 1].frame},
                        {"collapses", r.collapse_count()},
                        {"coarsest_triangles", r.triangles.back()}});
    }
    j["change_sets"] = sets;
    if (json) {
        std::printf("%s\n", j.dump(2).c_str());
        return;
    }
    std::printf("%s: lfmstrips v%u, %s, %llu bytes (%.1f KB per frame)\n", path.c_str(), d.version,
                d.quantized ? "16-bit" : "float", static_cast<unsigned long long>(bytes),
                double(bytes) / double(d.frame_count) / 1024.0);
    std::printf("frames: %u, vertices: %u, strips: %zu (%s), collapses: %zu, triangles: %u to %u\n", d.frame_count,
                s.vertex_count, s.strip_count(), s.restart ? "restart" : "degenerate joins", s.collapse_count(),
                s.triangles.front(), s.triangles.back());
    if (d.change_set_count() > 1)
        std::printf("change sets: %zu (one per sampled frame, frames %u to %u)\n", d.change_set_count(), d.strips_frame,
                    d.frame_sets.back().frame);
}

void add_morph_info(CLI::App& morph) {
    struct Options {
        std::string input;
        bool json = false;
    };
    auto o = std::make_shared<Options>();
    CLI::App* cmd = morph.add_subcommand("info", "Describe a morph LOD file (.lfmorph) or morph LODStrips file (.lfmstrips)");
    cmd->add_option("IN", o->input, "Morph LOD file (.lfmorph) or morph LODStrips file (.lfmstrips)")->required();
    cmd->add_flag("--json", o->json, "Print JSON");
    cmd->callback([o] {
        // A damaged .lfmstrips has no magic to recognise it by: its name decides, so that its reader
        // reports the problem (not the .lfmorph reader saying it is no .lfmorph file).
        if (is_morph_lodstrips_file(o->input) || std::filesystem::path(o->input).extension() == ".lfmstrips") {
            print_strips_info(o->input, o->json);
            return;
        }
        const MorphLodFile f = read_morph_lod(o->input);
        const MorphWriteOptions wo{f.encoding};
        const MorphFileStats st = morph_file_stats(f.morph, f.lod, wo);
        nlohmann::ordered_json j;
        j["file"] = o->input;
        j["version"] = f.version;
        j["bytes"] = f.file_bytes;
        j["encoding"] = f.encoding == MorphEncoding::float32 ? "float" : "16bit";
        j["frames"] = f.morph.frame_count();
        j["vertices"] = f.morph.vertex_count();
        j["triangles"] = f.lod.triangles;
        j["normals"] = f.morph.normals_from_input ? "stored" : "computed";
        j["order"] = morph_order_name(f.lod.order);
        j["sequences"] = f.lod.sequences.size();
        j["bytes_per_frame"] = double(f.file_bytes) / double(f.morph.frame_count());
        j["frame_bytes"] = st.frame_bytes;
        j["sequence_bytes"] = st.sequence_bytes;
        nlohmann::ordered_json levels = nlohmann::ordered_json::array();
        for (std::size_t l = 0; l < f.lod.levels.size(); ++l) {
            nlohmann::ordered_json e;
            e["ratio"] = f.lod.levels[l];
            e["triangles"] = f.lod.sequences.front().level_triangles[l];
            e["collapses"] = f.lod.sequences.front().level_collapses[l];
            levels.push_back(e);
        }
        j["levels"] = levels;
        if (o->json) {
            std::printf("%s\n", j.dump(2).c_str());
            return;
        }
        std::printf("%s: lfmorph v%u, %s, %zu bytes (%.1f KB per frame)\n", o->input.c_str(), f.version,
                    f.encoding == MorphEncoding::float32 ? "float" : "16-bit", f.file_bytes,
                    double(f.file_bytes) / double(f.morph.frame_count()) / 1024.0);
        std::printf("frames: %zu, vertices: %zu, triangles: %zu, normals: %s\n", f.morph.frame_count(),
                    f.morph.vertex_count(), f.lod.triangles, f.morph.normals_from_input ? "stored" : "computed");
        std::printf("order: %s, %zu sequence(s)\n", morph_order_name(f.lod.order), f.lod.sequences.size());
        for (std::size_t l = 0; l < f.lod.levels.size(); ++l)
            std::printf("  level %zu (ratio %.3g): %zu triangles\n", l, double(f.lod.levels[l]),
                        f.lod.sequences.front().level_triangles[l]);
    });
}

}  // namespace

void add_morph_command(CLI::App& app, const GlobalOptions& global) {
    CLI::App* morph = app.add_subcommand("morph", "Morphing meshes with LOD: build, extract, info");
    morph->require_subcommand(1);
    add_morph_build(*morph, global);
    add_morph_extract(*morph, global);
    add_morph_info(*morph);
}

}  // namespace lodforge::cli

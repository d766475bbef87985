// `lodforge strips`: build a .lodstrips model, describe one, extract a level as a mesh.
#include "commands.h"
#include "mesh_output.h"
#include "simplify_options.h"
#include "terminal_progress.h"

#include "lodforge/error.h"
#include "lodforge/strips/lodstrips.h"
#include "lodforge/io/mesh_io.h"

#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>

namespace lodforge::cli {
namespace {

void print_info(const std::string& path, const lodstrips::Data& d, bool json) {
    const LodStripsStorage st = lodstrips_storage(d);
    const std::size_t K = d.collapse_count();
    if (json) {
        nlohmann::ordered_json j;
        j["file"] = path;
        j["format_version"] = lodstrips::format_version;
        j["join"] = d.restart ? "restart" : "degenerate";
        j["vertices"] = d.vertex_count;
        j["attributes"] = {{"normals", !d.normals.empty()},
                           {"colors", d.colors.empty() ? "none" : (d.colors_8bit ? "rgba8" : "rgba32f")},
                           {"texcoord_sets", d.texcoords.size()}};
        j["materials"] = d.materials.size();
        j["strips"] = d.strip_count();
        j["indices"] = d.initial_indices.size();
        j["collapses"] = K;
        j["lods"] = K + 1;
        j["triangles"] = {{"full", d.triangles.front()}, {"coarsest", d.triangles.back()}};
        j["vertices_coarsest"] = d.vertex_count - d.collapse_begin.back();
        j["bytes"] = {{"file", st.file_bytes},
                      {"vertices", st.vertex_bytes},
                      {"strips", st.strip_bytes},
                      {"changes", st.change_bytes},
                      {"indexed_mesh", st.indexed_mesh_bytes}};
        j["ratio_to_indexed_mesh"] = st.ratio_to_indexed;
        std::printf("%s\n", j.dump(2).c_str());
        return;
    }
    std::printf("%s: LODStrips v%u, %s joins\n", path.c_str(), lodstrips::format_version,
                d.restart ? "restart" : "degenerate");
    std::printf("  vertices   %u (%s%s%zu texcoord sets), %zu materials\n", d.vertex_count,
                d.normals.empty() ? "" : "normals, ", d.colors.empty() ? "" : "colours, ", d.texcoords.size(),
                d.materials.size());
    std::printf("  strips     %zu, %zu indices at full detail\n", d.strip_count(), d.initial_indices.size());
    std::printf("  LODs       %zu (collapses %zu): %u triangles full, %u coarsest\n", K + 1, K, d.triangles.front(),
                d.triangles.back());
    std::printf("  bytes      %zu (vertices %zu, strips %zu, changes %zu)\n", st.file_bytes, st.vertex_bytes,
                st.strip_bytes, st.change_bytes);
    std::printf("  ratio      %.3f to the indexed mesh (%zu bytes: vertices + 12 bytes per triangle)\n",
                st.ratio_to_indexed, st.indexed_mesh_bytes);
}

}  // namespace

void add_strips_command(CLI::App& app, const GlobalOptions& global) {
    struct Options {
        std::string input, output, weights, preset;
        bool restart = false, degenerate = false, lock_border = false, json = false;
        double coarsest = 0.01;
        std::size_t max_strip_length = 256;
        std::string strip_order = "run-off";
        std::string info_file;
        bool info_json = false;
        std::string extract_file, extract_output;
        double lod = 1.0;
        long long triangles = -1;
    };
    auto o = std::make_shared<Options>();
    CLI::App* cmd = app.add_subcommand(
        "strips", "Build a LODStrips continuous-LOD model (.lodstrips); `strips info` / `strips extract` read one");
    cmd->add_option("IN", o->input, "Input mesh (.ply, .obj, .gltf, .glb)");
    cmd->add_option("-o,--output", o->output, "Output .lodstrips file");
    add_preset_option(cmd, o->preset);
    auto* restart = cmd->add_flag("--restart", o->restart, "Strips separated by primitive restart (default)");
    auto* degenerate = cmd->add_flag("--degenerate", o->degenerate, "Strips joined by degenerate triangles")->excludes(restart);
    cmd->add_option("--weights", o->weights, kWeightsHelp);
    auto* coarsest = cmd->add_option("--coarsest", o->coarsest, "Coarsest stored level as a fraction of the input triangles")
        ->check(CLI::Range(0.0, 1.0))
        ->capture_default_str();
    cmd->add_option("--max-strip-length", o->max_strip_length, "Longest strip piece in indices")
        ->check(CLI::Range(16, 65000))
        ->capture_default_str();
    cmd->add_flag("--lock-border", o->lock_border, "Never move border vertices");
    cmd->add_option("--strip-order", o->strip_order,
                    "run-off: fewest indices (smaller file); cache: meshoptimizer's vertex-cache order, "
                    "a few more indices, lower ACMR (docs/stripify.md)")
        ->check(CLI::IsMember({"run-off", "cache"}))
        ->capture_default_str();
    cmd->add_flag("--json", o->json, "Print the summary as JSON");
    cmd->require_subcommand(0, 1);

    CLI::App* info = cmd->add_subcommand("info", "Strips, LODs, bytes and the ratio to the indexed mesh");
    info->add_option("FILE", o->info_file, "A .lodstrips file")->required();
    info->add_flag("--json", o->info_json, "Print JSON");
    info->callback([o] { print_info(o->info_file, read_lodstrips(o->info_file), o->info_json); });

    CLI::App* extract = cmd->add_subcommand("extract", "Write one level of detail as a mesh (PLY, OBJ)");
    extract->add_option("FILE", o->extract_file, "A .lodstrips file")->required();
    auto* lod = extract->add_option("--lod", o->lod, "Level of detail: 0 = coarsest stored level, 1 = full detail")
                    ->check(CLI::Range(0.0, 1.0));
    extract->add_option("--triangles", o->triangles, "Or the finest level with at most this many triangles")
        ->check(CLI::NonNegativeNumber)
        ->excludes(lod);
    extract->add_option("-o,--output", o->extract_output, "Output mesh (.ply, .obj or .glb)")->required();
    extract->callback([o, &global] {
        check_mesh_output("strips extract", o->extract_output);
        lodstrips::LodStrips rt;
        std::string why;
        if (!rt.assign(read_lodstrips(o->extract_file), &why)) throw_error(Error::Kind::format, o->extract_file, why);
        if (o->triangles >= 0) rt.go_to_triangles(static_cast<std::size_t>(o->triangles));
        else rt.go_to_lod(o->lod);
        Mesh m = lodstrips_mesh(rt);
        m.source_dir = std::filesystem::path(o->extract_file).parent_path().string();
        TerminalProgress progress(!global.quiet && stderr_is_terminal());
        write_mesh_output(m, o->extract_output, {}, &progress);
        progress.finish();
        std::printf("level %zu of %zu: %zu triangles, %zu vertices -> %s\n", rt.level(), rt.collapse_count(),
                    rt.triangle_count(), rt.vertex_count(), o->extract_output.c_str());
    });

    cmd->callback([o, cmd, restart, degenerate, coarsest, &global] {
        if (!cmd->get_subcommands().empty()) return;  // `strips info` / `strips extract` ran
        if (o->input.empty() || o->output.empty())
            throw Error(Error::Kind::argument, "strips: give IN and -o OUT.lodstrips (or use `strips info` / `strips extract`)");
        LodStripsParams params;
        params.join = o->degenerate ? StripJoin::degenerate : StripJoin::restart;
        params.coarsest_ratio = static_cast<float>(o->coarsest);
        params.lock_border = o->lock_border;
        // A preset gives the joins, weights, border locking and, as the coarsest level, its last level.
        if (const std::optional<Preset> preset = preset_from_option(o->preset)) {
            if (!restart->count() && !degenerate->count())
                params.join = preset->strips.primitive_restart ? StripJoin::restart : StripJoin::degenerate;
            params.weights = preset->weights;
            params.lock_border = params.lock_border || preset->lock_border;
            if (!coarsest->count() && !preset->levels.empty()) {
                const LodTarget& last = preset->levels.back();
                if (last.kind == LodTarget::Kind::error)
                    throw Error(Error::Kind::argument, "strips: the preset's coarsest level is an error target; "
                                                       "LODStrips takes a ratio or a triangle count (give --coarsest)");
                params.coarsest_ratio = last.kind == LodTarget::Kind::ratio ? static_cast<float>(last.value) : 0.f;
                params.coarsest_triangles = last.kind == LodTarget::Kind::triangles
                                                ? static_cast<std::size_t>(last.value) : 0;
            }
        }
        if (!o->weights.empty()) parse_weights(o->weights, params.weights);
        params.max_strip_length = o->max_strip_length;
        params.strip_order = o->strip_order == "cache" ? StripOrder::cache : StripOrder::run_off;
        TerminalProgress progress(!global.quiet && stderr_is_terminal());
        const Mesh mesh = read_triangle_mesh("strips", o->input, &progress);
        const LodStripsBuild b = build_lodstrips(mesh, params, &progress);
        write_lodstrips(b.data, o->output);
        progress.finish();
        if (o->json) {
            print_info(o->output, b.data, true);
        } else {
            const LodStripsStorage st = lodstrips_storage(b.data);
            std::printf("%zu strips, %zu LODs (%u -> %u triangles), %zu bytes, ratio %.3f to the indexed mesh -> %s\n",
                        b.data.strip_count(), b.data.collapse_count() + 1, b.data.triangles.front(),
                        b.data.triangles.back(), st.file_bytes, st.ratio_to_indexed, o->output.c_str());
        }
    });
}

}  // namespace lodforge::cli

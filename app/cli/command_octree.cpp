// `lodforge octree build|info|extract`: the out-of-core octree LOD pipeline (docs/octree.md).
#include "commands.h"
#include "mesh_output.h"
#include "simplify_options.h"
#include "terminal_progress.h"

#include "lodforge/error.h"
#include "lodforge/io/mesh_io.h"
#include "lodforge/octree/octree_build.h"
#include "lodforge/octree/octree_info.h"
#include "lodforge/octree/octree_select.h"
#include "lodforge/octree/octree_store.h"
#include "lodforge/octree/ooc_cluster.h"
#include "lodforge/io/ply.h"
#include "lodforge/io/temp_directory.h"


#include <cmath>
#include <cstdio>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace lodforge::cli {
namespace {

// Exactly `count` comma-separated numbers (the list parser is simplify_options.h's).
std::vector<double> parse_numbers(const std::string& text, const std::string& what, std::size_t count) {
    std::vector<double> out = parse_number_list(text, "octree: " + what);
    if (out.size() != count)
        throw Error(Error::Kind::argument, "octree: " + what + " needs " + std::to_string(count) + " comma-separated numbers, got " +
                                               std::to_string(out.size()));
    return out;
}

std::string attributes_text(const VertexLayout& l) {
    std::string s = "position";
    if (l.normals) s += ", normals";
    if (l.colors) s += ", colors";
    if (l.texcoords) s += ", texcoords";
    return s;
}

void add_build(CLI::App& octree, const GlobalOptions& global) {
    struct Options {
        std::string input, output, mode = "octree", temp_dir, weights, preset;
        long long max_triangles = 10000, max_depth = 12, memory = 256, grid = 256, threads = 2;
        double level_ratio = OctreeBuildParams{}.level_ratio;
    };
    auto o = std::make_shared<Options>();
    CLI::App* cmd = octree.add_subcommand("build", "Build an octree LOD asset (or, with --mode cluster, one OoCS mesh) from a PLY of any size");
    cmd->add_option("IN", o->input, "Input mesh (.ply: ASCII or binary, any size)")->required();
    cmd->add_option("-o,--output", o->output, "Output asset (.lfo); with --mode cluster a .ply mesh")->required();
    add_preset_option(cmd, o->preset);
    auto* max_triangles = cmd->add_option("--max-triangles", o->max_triangles,
                                          "Split an octree node holding more input triangles than this")
                              ->capture_default_str();
    auto* max_depth = cmd->add_option("--max-depth", o->max_depth, "Never split below this depth (0..20)")->capture_default_str();
    auto* memory_mb = cmd->add_option("--memory", o->memory, "Working memory budget in MB (at least 4)")->capture_default_str();
    cmd->add_option("--level-ratio", o->level_ratio,
                    "Each level's size as a fraction of the level below (0.05..0.95; 0: collapse to the error bound)")
        ->capture_default_str();
    cmd->add_option("--mode", o->mode, "octree: multi-level crack-free asset; cluster: Lindstrom OoCS, one mesh (fast)")
        ->check(CLI::IsMember({"octree", "cluster"}))
        ->capture_default_str();
    cmd->add_option("--grid", o->grid, "Cluster mode: cells along the longest side of the bounding box")->capture_default_str();
    cmd->add_option("--temp-dir", o->temp_dir, "Directory for temporary files (default: beside the output)");
    cmd->add_option("--weights", o->weights, kWeightsHelp);
    cmd->add_option("--threads", o->threads, "Threads computing octree nodes (1 or 2; the asset is the same)")->capture_default_str();
    cmd->callback([o, max_triangles, max_depth, memory_mb, &global] {
        // A preset gives the octree's knobs and the weights; each flag given overrides its key.
        SimplifyWeights weights;
        if (const std::optional<Preset> preset = preset_from_option(o->preset)) {
            if (!max_triangles->count()) o->max_triangles = preset->octree.max_triangles_per_node;
            if (!max_depth->count()) o->max_depth = preset->octree.max_depth;
            if (!memory_mb->count()) o->memory = preset->octree.memory_mb;
            weights = preset->weights;
        }
        if (o->threads < 1 || o->threads > 2) throw Error(Error::Kind::argument, "octree build: --threads must be 1 or 2");
        if (o->memory < 4 || o->memory > (1ll << 30)) throw Error(Error::Kind::argument, "octree build: --memory must be at least 4 (MB)");
        if (o->max_triangles < 1) throw Error(Error::Kind::argument, "octree build: --max-triangles must be at least 1");
        if (o->max_depth < 0 || o->max_depth > 20) throw Error(Error::Kind::argument, "octree build: --max-depth must be in 0..20");
        if (o->level_ratio != 0 && !(o->level_ratio >= 0.05 && o->level_ratio <= 0.95))
            throw Error(Error::Kind::argument, "octree build: --level-ratio must be 0 or in 0.05..0.95");
        if (format_from_extension(o->input) != FileFormat::ply)
            throw Error(Error::Kind::argument, "octree build: " + o->input + ": the input must be a .ply file (convert it first)");
        TerminalProgress progress(!global.quiet && stderr_is_terminal());
        const std::size_t memory = static_cast<std::size_t>(o->memory) << 20;
        if (o->mode == "cluster") {
            if (format_from_extension(o->output) != FileFormat::ply)
                throw Error(Error::Kind::argument, "octree build: " + o->output + ": cluster mode writes a .ply mesh");
            if (o->grid < 2 || o->grid > (1 << 20)) throw Error(Error::Kind::argument, "octree build: --grid must be in 2..1048576");
            OocClusterParams p;
            p.grid_resolution = static_cast<std::size_t>(o->grid);
            p.memory_bytes = memory;
            p.temp_dir = o->temp_dir.empty() ? TempDirectory::beside(o->output) : o->temp_dir;
            OocClusterStats times;
            const OocClusterResult r = ooc_cluster(o->input, p, &progress, &times);
            write_ply(r.mesh, o->output, {}, &progress);
            progress.finish();
            std::printf("%s: %llu -> %zu triangles, %zu vertices (OoCS, grid %u x %u x %u, cell %.6g)\n", o->output.c_str(),
                        static_cast<unsigned long long>(r.input_triangles), r.mesh.triangle_count(), r.mesh.vertex_count(),
                        r.grid_dims[0], r.grid_dims[1], r.grid_dims[2], static_cast<double>(r.cell_size));
            std::printf("time: soup %.3f s, clustering %.3f s\n", times.soup_seconds, times.cluster_seconds);
            return;
        }
        OctreeBuildParams p;
        p.max_triangles = static_cast<std::size_t>(o->max_triangles);
        p.max_depth = static_cast<int>(o->max_depth);
        p.memory_bytes = memory;
        p.temp_dir = o->temp_dir;
        p.threads = static_cast<int>(o->threads);
        p.level_ratio = o->level_ratio;
        p.weights = weights;
        if (!o->weights.empty()) parse_weights(o->weights, p.weights);
        OctreeBuildStats times;
        const OctreeBuildResult r = build_octree(o->input, o->output, p, &progress, &times);
        progress.finish();
        const OctreeStats& s = r.stats;
        std::printf("%s: %llu triangles in %zu nodes (%zu leaves), depth reached %d, %d levels\n", o->output.c_str(),
                    static_cast<unsigned long long>(s.input_triangles), s.nodes, s.leaves, s.depth_reached,
                    static_cast<int>(s.triangles_per_level.size()));
        std::printf("triangles per level:");
        for (std::uint64_t t : s.triangles_per_level) std::printf(" %llu", static_cast<unsigned long long>(t));
        // The octree time includes the node operator; the operator's time is summed over the threads.
        std::printf("\nsoup: %s, %d pass%s; time: soup %.3f s, octree %.3f s, simplification %.3f s (summed over %d threads)\n",
                    r.soup.external ? "external sort" : "in memory", r.soup.passes, r.soup.passes == 1 ? "" : "es",
                    times.soup_seconds, times.build_seconds, times.simplify_seconds, p.threads);
        for (const std::string& w : r.warnings) std::printf("warning: %s\n", w.c_str());
    });
}

void add_info(CLI::App& octree) {
    struct Options {
        std::string asset;
        bool json = false;
    };
    auto o = std::make_shared<Options>();
    CLI::App* cmd = octree.add_subcommand("info", "Statistics of an octree LOD asset");
    cmd->add_option("ASSET", o->asset, "Octree asset (.lfo)")->required();
    cmd->add_flag("--json", o->json,
                  "Print JSON (keys: nodes, leaves, depth_reached, levels, triangles_per_level, leaves_per_depth, "
                  "triangles_per_depth, input_triangles, input_vertices, attributes, bounds, root_cube, max_triangles, "
                  "max_depth, file_bytes)");
    cmd->callback([o] {
        OctreeStore store(o->asset, 0);
        const OctreeStats s = store.stats();
        const OctreeHeader& h = store.header();
        if (o->json) {
            std::printf("%s\n", octree_info_json(s, h).c_str());
            return;
        }
        std::printf("%s: octree LOD asset, version %u\n", o->asset.c_str(), h.version);
        std::printf("input: %llu triangles, %llu vertices (%s)\n", static_cast<unsigned long long>(h.input_triangles),
                    static_cast<unsigned long long>(h.input_vertices), attributes_text(h.layout).c_str());
        std::printf("built with: max triangles per leaf %u, max depth %u\n", h.max_triangles, h.max_depth);
        std::printf("nodes: %zu, leaves: %zu, depth reached: %d, largest leaf: %zu triangles\n", s.nodes, s.leaves,
                    s.depth_reached, s.max_leaf_triangles);
        std::printf("leaves per depth:");
        for (std::uint64_t v : s.leaves_per_depth) std::printf(" %llu", static_cast<unsigned long long>(v));
        std::printf("\ntriangles per depth (in leaves):");
        for (std::uint64_t v : s.triangles_per_depth) std::printf(" %llu", static_cast<unsigned long long>(v));
        std::printf("\nlevels: %zu (0 = input, %zu = root)\n", s.triangles_per_level.size(), s.triangles_per_level.size() - 1);
        for (std::size_t l = 0; l < s.triangles_per_level.size(); ++l) {
            std::printf("  level %zu: %llu triangles", l, static_cast<unsigned long long>(s.triangles_per_level[l]));
            // How much each level saves over the one below (the document's levels give 30-50 %).
            if (l > 0 && s.triangles_per_level[l - 1] > 0)
                std::printf(" (%.0f %% of level %zu)", 100.0 * static_cast<double>(s.triangles_per_level[l]) /
                                                         static_cast<double>(s.triangles_per_level[l - 1]), l - 1);
            std::printf("\n");
        }
        std::printf("file: %llu bytes\n", static_cast<unsigned long long>(s.file_bytes));
    });
}

void add_extract(CLI::App& octree, const GlobalOptions& global) {
    struct Options {
        std::string asset, output, camera, viewport = "1920,1080";
        int level = -1;
        double screen_error = 0;
        bool no_culling = false;
    };
    auto o = std::make_shared<Options>();
    CLI::App* cmd = octree.add_subcommand("extract", "Extract a whole-model level or a view-dependent cut of an octree asset");
    cmd->add_option("ASSET", o->asset, "Octree asset (.lfo)")->required();
    cmd->add_option("-o,--output", o->output, "Output mesh (.ply, .obj or .glb)")->required();
    CLI::Option* level = cmd->add_option("--level", o->level, "Whole model at this level (0 = input; see `octree info`)");
    CLI::Option* error = cmd->add_option("--screen-error", o->screen_error, "View-dependent cut: tolerance in pixels (needs --camera)");
    cmd->add_option("--camera", o->camera,
                    "eye_x,eye_y,eye_z,target_x,target_y,target_z,fov: eye and target in model units, vertical field "
                    "of view in degrees (up is +Y, or +Z when looking along Y)");
    cmd->add_option("--viewport", o->viewport, "Viewport width,height in pixels")->capture_default_str();
    cmd->add_flag("--no-culling", o->no_culling, "Keep nodes outside the view frustum");
    cmd->callback([o, level, error, &global] {
        if ((level->count() > 0) == (error->count() > 0))
            throw Error(Error::Kind::argument, "octree extract: give exactly one of --level and --screen-error");
        if (error->count() && o->camera.empty()) throw Error(Error::Kind::argument, "octree extract: --screen-error needs --camera");
        check_mesh_output("octree extract", o->output);
        TerminalProgress progress(!global.quiet && stderr_is_terminal());
        OctreeStore store(o->asset);
        Cut cut;
        std::string what;
        if (level->count()) {
            cut = level_cut(store, o->level);
            what = "level " + std::to_string(o->level);
        } else {
            const std::vector<double> c = parse_numbers(o->camera, "--camera", 7);
            const std::vector<double> vp = parse_numbers(o->viewport, "--viewport", 2);
            Camera cam;
            cam.eye = {static_cast<float>(c[0]), static_cast<float>(c[1]), static_cast<float>(c[2])};
            cam.target = {static_cast<float>(c[3]), static_cast<float>(c[4]), static_cast<float>(c[5])};
            cam.fov_y_degrees = static_cast<float>(c[6]);
            if (!(vp[0] >= 1 && vp[1] >= 1 && vp[0] <= 1e6 && vp[1] <= 1e6))
                throw Error(Error::Kind::argument, "octree extract: --viewport must be two positive pixel counts");
            cam.viewport_width = static_cast<int>(vp[0]);
            cam.viewport_height = static_cast<int>(vp[1]);
            SelectParams sp;
            sp.screen_error_pixels = static_cast<float>(o->screen_error);
            sp.frustum_culling = !o->no_culling;
            const SelectResult s = select_cut(store, cam, sp);
            cut = s.cut;
            char buf[200];
            std::snprintf(buf, sizeof buf, "view cut: %zu nodes (%zu at full resolution, %zu simplified, %zu culled), deepest %d",
                          s.cut.size(), s.raw_leaves, s.simplified_nodes, s.culled_nodes, s.max_depth);
            what = buf;
        }
        const Mesh m = extract_mesh(store, cut, &progress);
        if (m.triangle_count() == 0) throw Error(Error::Kind::invalid, o->asset + ": the cut is empty (nothing in view)");
        write_mesh_output(m, o->output, {}, &progress);
        progress.finish();
        std::printf("%s: %s, %zu triangles, %zu vertices\n", o->output.c_str(), what.c_str(), m.triangle_count(), m.vertex_count());
    });
}

}  // namespace

void add_octree_command(CLI::App& app, const GlobalOptions& global) {
    CLI::App* octree = app.add_subcommand("octree", "Out-of-core octree LOD: build, inspect and extract assets");
    octree->require_subcommand(1);
    add_build(*octree, global);
    add_info(*octree);
    add_extract(*octree, global);
}

}  // namespace lodforge::cli

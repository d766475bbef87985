// `lodforge mcoctree build|extract|info`: the prioritized marching-cube octree (docs/mcoctree.md).
#include "commands.h"
#include "mesh_output.h"
#include "simplify_options.h"
#include "terminal_progress.h"

#include "lodforge/error.h"
#include "lodforge/mcoctree/mc_octree.h"
#include "lodforge/io/mesh_io.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <memory>
#include <optional>

namespace lodforge::cli {
namespace {

std::size_t internal_levels(const McOctree& t) { return t.levels + 1; }

}  // namespace

void add_mcoctree_command(CLI::App& app, const GlobalOptions& global) {
    CLI::App* cmd = app.add_subcommand("mcoctree", "Prioritized marching-cube octree: build from points, extract levels");
    cmd->require_subcommand(1);

    struct BuildOptions {
        std::string input, output, preset;
        long long resolution = 128;
        double cube_size = 0, band = 0;
    };
    auto b = std::make_shared<BuildOptions>();
    CLI::App* build = cmd->add_subcommand("build", "Rebuild a surface from points with normals (or a mesh) into a .mco octree");
    build->add_option("IN", b->input, "Point cloud PLY with normals (and colours), or a mesh (.ply, .obj, .gltf, .glb): its vertices, "
                      "plus points on its faces longer than two cubes")
        ->required();
    build->add_option("-o,--output", b->output, "Output octree (.mco)")->required();
    add_preset_option(build, b->preset);
    auto* resolution =
        build->add_option("--resolution", b->resolution, "Leaf cubes along the longest axis")->capture_default_str();
    build->add_option("--cube-size", b->cube_size, "Leaf cube edge in model units (overrides --resolution)");
    build->add_option("--band", b->band,
                      "Keep only cubes within this many cube sizes of a point (open scans end at their border); "
                      "0 = no limit, closed surface")
        ->capture_default_str();
    build->callback([b, resolution, &global] {
        // A preset gives the resolution (mcoctree.resolution) unless --resolution is given.
        if (const std::optional<Preset> preset = preset_from_option(b->preset); preset && !resolution->count())
            b->resolution = preset->mcoctree.resolution;
        if (b->resolution < 1) throw Error(Error::Kind::argument, "mcoctree build: --resolution must be at least 1");
        if (b->cube_size < 0) throw Error(Error::Kind::argument, "mcoctree build: --cube-size must be positive");
        if (b->band < 0) throw Error(Error::Kind::argument, "mcoctree build: --band must be >= 0");
        McOctreeParams p;
        p.resolution = static_cast<std::size_t>(b->resolution);
        p.cube_size = b->cube_size;
        p.band = b->band;
        TerminalProgress progress(!global.quiet && stderr_is_terminal());
        const Mesh mesh = read_mesh(b->input, {}, &progress);
        McOctreeBuildResult r;
        try {
            r = build_mc_octree(mesh, p, &progress);
        } catch (const Error& e) {
            // the core names its input generically; the user knows it by its file name
            std::string what = e.what();
            const std::string generic = "mcoctree input: ";
            if (what.rfind(generic, 0) == 0) what = what.substr(generic.size());
            if (e.kind() == Error::Kind::cancelled) throw;
            throw_error(e.kind(), b->input, what);
        }
        write_mc_octree(r.tree, b->output, &progress);
        progress.finish();
        for (const std::string& w : r.warnings) std::fprintf(stderr, "lodforge: warning: %s: %s\n", b->input.c_str(), w.c_str());
        if (r.face_samples > 0)
            std::printf("%zu points added on the %zu faces longer than two cubes\n", r.face_samples, r.sampled_faces);
        std::printf("%zu points -> %zu leaf cubes, %zu nodes, %u levels, %zu priorities, %llu..%llu triangles\n",
                    r.tree.input_points, r.leaf_cubes, r.tree.nodes.size(), r.tree.levels + 1, r.tree.max_priority(),
                    static_cast<unsigned long long>(r.tree.triangle_counts.front()),
                    static_cast<unsigned long long>(r.tree.triangle_counts.back()));
        std::printf("wrote %s\n", b->output.c_str());
    });

    struct ExtractOptions {
        std::string input, output;
        long long priority = -1, triangles = -1;
    };
    auto x = std::make_shared<ExtractOptions>();
    CLI::App* extract = cmd->add_subcommand("extract", "Extract the mesh of one priority or triangle budget");
    extract->add_option("IN", x->input, "Octree (.mco)")->required();
    extract->add_option("-o,--output", x->output, "Output mesh (.ply, .obj or .glb)")->required();
    CLI::Option* prio = extract->add_option("--priority", x->priority, "Priority index, 0 (root) .. the maximum (all leaves)");
    CLI::Option* tris = extract->add_option("--triangles", x->triangles, "Largest level with at most this many triangles");
    prio->excludes(tris);
    extract->callback([x, prio, tris, &global] {
        if (!prio->count() && !tris->count())
            throw Error(Error::Kind::argument, "mcoctree extract: give --priority or --triangles");
        check_mesh_output("mcoctree extract", x->output);
        TerminalProgress progress(!global.quiet && stderr_is_terminal());
        const McOctree tree = read_mc_octree(x->input, &progress);
        McOctreeExtractor ex(tree);
        std::size_t priority = 0;
        if (prio->count()) {
            if (x->priority < 0 || static_cast<unsigned long long>(x->priority) > tree.max_priority())
                throw Error(Error::Kind::argument,
                            "mcoctree extract: --priority must be in 0.." + std::to_string(tree.max_priority()));
            priority = static_cast<std::size_t>(x->priority);
        } else {
            if (x->triangles < 0) throw Error(Error::Kind::argument, "mcoctree extract: --triangles must be >= 0");
            priority = ex.priority_for_triangles(static_cast<std::uint64_t>(x->triangles));
        }
        const McExtraction& e = ex.extract(priority);
        write_mesh_output(e.mesh, x->output, {}, &progress);
        progress.finish();
        std::printf("priority %zu of %zu: %zu triangles, %zu vertices, %zu nodes (%zu on seams)\n", priority,
                    tree.max_priority(), e.mesh.triangle_count(), e.mesh.vertex_count(), e.active_nodes, e.transition_nodes);
        std::printf("wrote %s\n", x->output.c_str());
    });

    struct InfoOptions {
        std::string input;
        bool json = false;
    };
    auto in = std::make_shared<InfoOptions>();
    CLI::App* info = cmd->add_subcommand("info", "Nodes, levels, triangle counts and warnings of a .mco octree");
    info->add_option("IN", in->input, "Octree (.mco)")->required();
    info->add_flag("--json", in->json, "Machine-readable output");
    info->callback([in] {
        const McOctree t = read_mc_octree(in->input);
        std::vector<std::size_t> per_level(internal_levels(t), 0);
        for (const McNode& n : t.nodes) ++per_level[n.level];
        // the triangle table at 11 evenly spaced priorities (0 %, 10 %, ... 100 %)
        std::vector<std::pair<std::size_t, std::uint64_t>> table;
        for (int k = 0; k <= 10; ++k) {
            const std::size_t i = static_cast<std::size_t>(k) * t.max_priority() / 10;
            table.emplace_back(i, mc_triangles_at(t, i));
        }
        if (in->json) {
            nlohmann::ordered_json j;
            j["file"] = in->input;
            j["input_points"] = t.input_points;
            j["cube_size"] = t.cube_size;
            j["origin"] = {t.origin.x, t.origin.y, t.origin.z};
            j["levels"] = t.levels + 1;
            j["nodes"] = t.nodes.size();
            j["leaves"] = per_level[0];
            j["nodes_per_level"] = per_level;  // index = level, 0 = leaves
            j["vertices"] = t.positions.size();
            j["colors"] = t.has_colors();
            j["max_priority"] = t.max_priority();
            nlohmann::ordered_json tj = nlohmann::ordered_json::array();
            for (const auto& [i, n] : table) tj.push_back({{"priority", i}, {"triangles", n}});
            j["triangle_table"] = tj;
            j["warnings"] = t.warnings;
            std::printf("%s\n", j.dump(2).c_str());
            return;
        }
        std::printf("%s: marching-cube octree, %zu input points, cube size %.6g\n", in->input.c_str(), t.input_points,
                    double(t.cube_size));
        std::printf("  %zu nodes on %u levels (%zu leaves), %zu vertices%s\n", t.nodes.size(), t.levels + 1, per_level[0],
                    t.positions.size(), t.has_colors() ? ", colours" : "");
        std::printf("  nodes per level (leaves first):");
        for (std::size_t c : per_level) std::printf(" %zu", c);
        std::printf("\n  priorities 0..%zu; triangles:", t.max_priority());
        for (const auto& [i, n] : table) std::printf(" %zu:%llu", i, static_cast<unsigned long long>(n));
        std::printf("\n");
        for (const std::string& w : t.warnings) std::printf("  warning: %s\n", w.c_str());
    });
}

}  // namespace lodforge::cli

#include "commands.h"
#include "mesh_output.h"
#include "simplify_options.h"
#include "terminal_progress.h"

#include "lodforge/error.h"
#include "lodforge/io/mesh_io.h"
#include "lodforge/io/vertex_paint.h"
#include "lodforge/simplify/seams.h"
#include "lodforge/simplify/simplify.h"
#include "lodforge/simplify/simplify_cluster.h"
#include "lodforge/simplify/skin_cost.h"

#include <cmath>
#include <cstdio>
#include <optional>

namespace lodforge::cli {
namespace {

const char* reason_text(SimplifyResult::StopReason r) {
    switch (r) {
    case SimplifyResult::StopReason::target_reached: return "target reached";
    case SimplifyResult::StopReason::error_limit: return "error limit (the next collapse would exceed --max-error)";
    case SimplifyResult::StopReason::topology_limit: return "topology limit (no valid collapse left)";
    }
    return "unknown";
}

const char* reason_text(ClusterResult::StopReason r) {
    switch (r) {
    case ClusterResult::StopReason::target_reached: return "target reached (within 1%)";
    case ClusterResult::StopReason::closest: return "closest grid found (the count jumps over the target between cell sizes)";
    case ClusterResult::StopReason::grid_limit: return "grid limit (the finest grid still has fewer triangles)";
    case ClusterResult::StopReason::resolution_given: return "resolution given";
    }
    return "unknown";
}

}  // namespace

void add_simplify_command(CLI::App& app, const GlobalOptions& global) {
    struct Options {
        std::string input, output, preset;
        double ratio = 0, max_error = 0;
        long long triangles = 0;
        std::string weights, importance, lock, seams;
        bool lock_border = false;
        std::string mode = "collapse";
        std::string area_weight = "area";
        double height_weight = SimplifyParams{}.height_weight;
        // Optimal by default: lower geometric, UV and normal error than half-edge on every asset measured
        // (docs/bench-fidelity.md); `lod` and `pack` keep half-edge, their levels share one vertex buffer.
        std::string placement = "optimal";
        long long pose_samples = 0;
        double pose_weight = SkinCostParams{}.weight;
    };
    auto options = std::make_shared<Options>();
    CLI::App* cmd = app.add_subcommand("simplify", "Simplify a mesh to a triangle ratio, count or error bound");
    cmd->add_option("IN", options->input, "Input mesh (.ply, .obj, .gltf, .glb)")->required();
    cmd->add_option("-o,--output", options->output, "Output mesh (.ply, .obj or .glb)")->required();
    add_preset_option(cmd, options->preset);
    CLI::Option* ratio = cmd->add_option("--ratio", options->ratio, "Keep this fraction of the triangles, in (0, 1]");
    CLI::Option* triangles = cmd->add_option("--triangles", options->triangles, "Keep this many triangles");
    CLI::Option* max_error = cmd->add_option(
        "--max-error", options->max_error, "Simplify until the error estimate reaches this fraction of the bounding-box diagonal");
    cmd->add_option("--weights", options->weights, kWeightsHelp);
    CLI::Option* lock = cmd->add_flag("--lock-border", options->lock_border, "Never move border vertices (collapse mode)");
    add_paint_options(cmd, options->importance, options->lock, options->seams);
    CLI::Option* mode = cmd->add_option("--mode", options->mode, "collapse: quadric edge collapse; cluster: vertex clustering (faster, coarser)")
        ->check(CLI::IsMember({"collapse", "cluster"}))
        ->capture_default_str();
    CLI::Option* area_weight =
        cmd->add_option("--area-weight", options->area_weight,
                        "Face weight in the quadrics: sqrt (square root of the area) or area (collapse mode)")
            ->check(CLI::IsMember({"sqrt", "area"}))
            ->capture_default_str();
    CLI::Option* height_weight = cmd->add_option(
        "--height-weight", options->height_weight,
        "Weight of the accumulated height bound in the collapse order, >= 0; 0 = quadric order only (collapse mode)");
    height_weight->capture_default_str();
    CLI::Option* placement =
        cmd->add_option("--placement", options->placement,
                        "half-edge: kept vertices are input vertices; optimal: they move to the quadric-optimal "
                        "position and their UVs, normals and colours are re-solved there (collapse mode)")
            ->check(CLI::IsMember({"half-edge", "optimal"}))
            ->capture_default_str();
    CLI::Option* pose_samples = cmd->add_option(
        "--pose-samples", options->pose_samples,
        "Skinned meshes: also weigh each collapse in this many poses sampled from the animation (collapse mode, "
        "half-edge placement; docs/skinning.md)");
    CLI::Option* pose_weight = cmd->add_option("--pose-weight", options->pose_weight,
                                               "--pose-samples: weight of the poses' cost against the bind pose's, >= 0")
                                   ->capture_default_str();
    cmd->callback([options, ratio, triangles, max_error, lock, mode, area_weight, height_weight, placement,
                   pose_samples, pose_weight, &global] {
        Options o = *options;
        const int targets = static_cast<int>(ratio->count() > 0) + static_cast<int>(triangles->count() > 0) +
                            static_cast<int>(max_error->count() > 0);
        bool has_max_error = max_error->count() > 0;
        SimplifyWeights weights;
        // A preset gives the method, weights, border locking and, without a target flag, its first level.
        if (const std::optional<Preset> preset = preset_from_option(o.preset)) {
            if (!mode->count()) {
                if (preset->method != LodMethod::collapse && preset->method != LodMethod::cluster)
                    throw Error(Error::Kind::argument, "simplify: the preset's method '" +
                                                           std::string(to_string(preset->method)) +
                                                           "' makes no single mesh; give --mode, or use `lodforge lod`");
                o.mode = std::string(to_string(preset->method));
            }
            weights = preset->weights;
            if (!pose_samples->count()) o.pose_samples = preset->skin.pose_samples;
            if (!pose_weight->count()) o.pose_weight = preset->skin.weight;
            if (o.mode == "collapse") o.lock_border = o.lock_border || preset->lock_border;
            if (o.importance.empty()) o.importance = preset->importance;
            if (o.lock.empty()) o.lock = preset->lock;
            if (o.seams.empty()) o.seams = preset->seams;
            if (targets == 0) {
                if (preset->levels.empty())
                    throw Error(Error::Kind::argument, "simplify: the preset has no levels; give --ratio, --triangles or --max-error");
                const LodTarget& first = preset->levels.front();
                if (first.kind == LodTarget::Kind::ratio) o.ratio = first.value;
                else if (first.kind == LodTarget::Kind::triangles) o.triangles = static_cast<long long>(first.value);
                else o.max_error = first.value;
                has_max_error = first.kind == LodTarget::Kind::error;
            }
        } else if (targets != 1) {
            throw Error(Error::Kind::argument, "simplify: give exactly one of --ratio, --triangles and --max-error");
        }
        if (targets > 1)
            throw Error(Error::Kind::argument, "simplify: give exactly one of --ratio, --triangles and --max-error");
        if (ratio->count() && !(o.ratio > 0 && o.ratio <= 1))
            throw Error(Error::Kind::argument, "simplify: --ratio must be in (0, 1], got " + std::to_string(o.ratio));
        if (triangles->count() && o.triangles < 1)
            throw Error(Error::Kind::argument, "simplify: --triangles must be at least 1");
        if (max_error->count() && !(o.max_error > 0 && std::isfinite(o.max_error)))
            throw Error(Error::Kind::argument, "simplify: --max-error must be > 0 (a fraction of the diagonal)");
        const bool cluster = o.mode == "cluster";
        if (cluster && has_max_error)
            throw Error(Error::Kind::argument, "simplify: --max-error needs --mode collapse (clustering targets a triangle count)");
        if (cluster && (!o.importance.empty() || !o.lock.empty() || !o.seams.empty()))
            throw Error(Error::Kind::argument, "simplify: --importance, --lock and --seams need --mode collapse");
        if (cluster && lock->count())
            throw Error(Error::Kind::argument, "simplify: --lock-border needs --mode collapse");
        if (cluster && (area_weight->count() || height_weight->count() || placement->count()))
            throw Error(Error::Kind::argument, "simplify: --area-weight, --height-weight and --placement need --mode collapse");
        if (!cluster && height_weight->count() && o.placement != "half-edge")
            throw Error(Error::Kind::argument, "simplify: --height-weight needs --placement half-edge (it orders half-edge collapses)");
        if (!(o.height_weight >= 0 && std::isfinite(o.height_weight)))
            throw Error(Error::Kind::argument, "simplify: --height-weight must be finite and >= 0");
        if (o.pose_samples < 0 || o.pose_samples > 64)
            throw Error(Error::Kind::argument, "simplify: --pose-samples must be from 0 to 64");
        if (!(o.pose_weight >= 0 && std::isfinite(o.pose_weight)))
            throw Error(Error::Kind::argument, "simplify: --pose-weight must be finite and >= 0");
        if (pose_weight->count() && o.pose_samples == 0)
            throw Error(Error::Kind::argument, "simplify: --pose-weight needs --pose-samples");
        if (o.pose_samples > 0) {
            if (cluster) throw Error(Error::Kind::argument, "simplify: --pose-samples needs --mode collapse");
            // The poses' cost is the multi-frame cost, which moves no vertex: half-edge placement.
            if (placement->count() && o.placement != "half-edge")
                throw Error(Error::Kind::argument, "simplify: --pose-samples needs --placement half-edge");
            o.placement = "half-edge";
        }
        check_mesh_output("simplify", o.output);
        if (!o.weights.empty()) parse_weights(o.weights, weights);

        TerminalProgress progress(!global.quiet && stderr_is_terminal());
        const Mesh mesh = read_mesh(o.input, {}, &progress);
        const double diagonal = mesh.bounds().diagonal();
        Mesh out;
        std::size_t target = 0, dropped = 0;
        float error = 0, error_relative = 0;
        std::string reason;
        if (cluster) {
            ClusterParams p;
            p.target_ratio = static_cast<float>(o.ratio);
            p.target_triangles = static_cast<std::size_t>(o.triangles);
            p.weights = weights;
            ClusterResult r = simplify_cluster(mesh, p, &progress);
            target = r.target_triangles;
            error = r.error;
            error_relative = r.error_relative;
            reason = reason_text(r.reason);
            out = std::move(r.mesh);
        } else {
            SimplifyParams p;
            p.target_ratio = static_cast<float>(o.ratio);
            p.target_triangles = static_cast<std::size_t>(o.triangles);
            if (has_max_error) p.max_error = static_cast<float>(o.max_error);
            p.weights = weights;
            p.lock_border = o.lock_border;
            p.area_weight = o.area_weight == "area" ? SimplifyParams::AreaWeight::area : SimplifyParams::AreaWeight::sqrt_area;
            p.height_weight = static_cast<float>(o.height_weight);
            p.placement = o.placement == "optimal" ? Placement::optimal : Placement::half_edge;
            SkinCostParams skin;
            skin.pose_samples = static_cast<std::size_t>(o.pose_samples);
            skin.weight = static_cast<float>(o.pose_weight);
            const SkinPoseFrames poses = skin_pose_frames(mesh, skin);
            if (o.pose_samples > 0 && poses.frames.empty())
                throw_error(Error::Kind::invalid, o.input, "--pose-samples needs a skinned mesh with an animation");
            poses.attach(p);
            read_paint_sources(o.importance, o.lock, mesh, o.input, p.importance, p.lock);
            if (!o.seams.empty()) p.seam_weights = parse_seam_weights(o.seams);
            SimplifyResult r = simplify(mesh, p, &progress);
            target = r.target_triangles;
            dropped = r.dropped_faces;
            error = r.error;
            error_relative = r.error_relative;
            reason = reason_text(r.reason);
            out = std::move(r.mesh);
        }
        write_mesh_output(out, o.output, {}, &progress);
        progress.finish();
        std::printf("%s: %zu -> %zu triangles", o.output.c_str(), mesh.triangle_count(), out.triangle_count());
        if (target) std::printf(" (target %zu)", target);
        std::printf(", %zu vertices\n", out.point_count());
        std::printf("mode: %s\n", cluster ? "cluster" : "collapse");
        if (!cluster) std::printf("placement: %s\n", o.placement.c_str());
        if (o.pose_samples > 0) std::printf("poses: %lld sampled, weight %g\n", o.pose_samples, o.pose_weight);
        std::printf("error: %.6g (%.3g of the diagonal %.6g)\n", static_cast<double>(error),
                    static_cast<double>(error_relative), diagonal);
        std::printf("stop: %s\n", reason.c_str());
        if (dropped > 0)
            std::printf("dropped: %zu input faces degenerate on their points or repeating an earlier face\n", dropped);
    });
}

}  // namespace lodforge::cli

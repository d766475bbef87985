#include "commands.h"
#include "mesh_output.h"
#include "terminal_progress.h"

#include "lodforge/error.h"
#include "lodforge/metrics/distance_json.h"
#include "lodforge/metrics/heatmap.h"
#include "lodforge/io/mesh_io.h"
#include "lodforge/metrics/image_error.h"
#include "lodforge/metrics/metrics.h"
#include "lodforge/metrics/pose_error.h"
#ifdef LODFORGE_HAVE_RENDER
#include "lodforge/render/image_compare.h"
#endif

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace lodforge::cli {

void add_compare_command(CLI::App& app, const GlobalOptions& global) {
    struct Options {
        std::string reference, test, heatmap;
        bool json = false;
        long long samples = 0;
        long long poses = 0, animation = 0;
        double range = 0;
        std::string heatmap_on = "test";
        bool render = false;
        ImageErrorParams image;
    };
    auto options = std::make_shared<Options>();
    CLI::App* cmd = app.add_subcommand("compare", "Measure the surface distance between two meshes (Metro-style)");
    cmd->add_option("REF", options->reference, "Reference mesh (usually the original)")->required();
    cmd->add_option("TEST", options->test, "Test mesh (usually the simplified one)")->required();
    cmd->add_flag("--json", options->json,
                  "Print JSON (keys: hausdorff, mean, rms and *_relative, diagonal, one-sided distances, attribute errors)");
    cmd->add_option("--heatmap", options->heatmap,
                    "Write TEST coloured by the largest distance measured around each vertex, in either direction "
                    "(PLY with `quality`)");
    cmd->add_option("--heatmap-on", options->heatmap_on,
                    "Heat map on TEST's vertices or on REF's (the same field with the roles swapped: full detail)")
        ->check(CLI::IsMember({"test", "reference"}))
        ->capture_default_str();
    cmd->add_option("--range", options->range, "Heat map: distance at the top of the colour map (default: the largest)");
    cmd->add_option("--samples", options->samples, "Area-weighted samples per surface (0 = automatic)");
    cmd->add_option("--poses", options->poses,
                    "Skinned meshes: also the error in N poses sampled evenly over the animation, each mesh posed "
                    "by its own skeleton (worst and mean over the poses; docs/skinning.md)");
    cmd->add_option("--animation", options->animation, "--poses: which animation (index, default 0)");
    cmd->add_flag("--render", options->render,
                  "Also the image-space error: both meshes rendered as the studio draws them from 14 views "
                  "(docs/image-compare.md)");
    CLI::Option* size = cmd->add_option("--render-size", options->image.size, "--render: image size in pixels (square)")
        ->capture_default_str();
    CLI::Option* threshold = cmd->add_option("--render-threshold", options->image.threshold,
                    "--render: a pixel differs when a colour channel differs by more than this (0-255)")
        ->capture_default_str();
    CLI::Option* out = cmd->add_option("--render-out", options->image.output_dir,
                    "--render: write side-by-side and difference PNGs per view into this directory");
    cmd->callback([options, &global, size, threshold, out] {
        const Options& o = *options;
        if (o.samples < 0) throw Error(Error::Kind::argument, "compare: --samples must be >= 0");
        if (o.poses < 0) throw Error(Error::Kind::argument, "compare: --poses must be >= 0");
        if (o.animation < 0) throw Error(Error::Kind::argument, "compare: --animation must be >= 0");
        if (o.animation > 0 && o.poses == 0) throw Error(Error::Kind::argument, "compare: --animation needs --poses");
        if (!(o.range >= 0) || !std::isfinite(o.range))
            throw Error(Error::Kind::argument, "compare: --range must be >= 0");
        if (!o.heatmap.empty() && format_from_extension(o.heatmap) != FileFormat::ply)
            throw Error(Error::Kind::argument, "compare: --heatmap writes PLY; give a .ply file name");
        if (!o.render && (size->count() + threshold->count() + out->count()) > 0)
            throw Error(Error::Kind::argument, "compare: --render-size, --render-threshold and --render-out need --render");
#ifndef LODFORGE_HAVE_RENDER
        if (o.render) throw Error(Error::Kind::argument, "compare: this build has no renderer (LODFORGE_BUILD_RENDER=OFF)");
#endif
        TerminalProgress progress(!global.quiet && stderr_is_terminal());
        const Mesh reference = read_triangle_mesh("compare", o.reference, &progress);
        const Mesh test = read_triangle_mesh("compare", o.test, &progress);
        DistanceParams params;
        params.samples = static_cast<std::size_t>(o.samples);
        const bool on_reference = o.heatmap_on == "reference";
        params.vertex_errors = false;
        params.region_errors = !o.heatmap.empty() && !on_reference;
        PoseErrorResult poses;
        if (o.poses > 0) {
            PoseErrorParams pp;
            pp.poses = static_cast<std::size_t>(o.poses);
            pp.animation = static_cast<std::size_t>(o.animation);
            pp.distance = params;
            poses = compare_poses(reference, test, pp, o.reference, o.test, &progress);
        }
        const DistanceResult d = o.poses > 0 ? poses.bind : compare(reference, test, params, &progress);
        float heat_max = 0.f;
        if (!o.heatmap.empty()) {
            const std::vector<float>* field = &d.region_errors;
            DistanceResult swapped;
            if (on_reference) {
                // The same measurement with the roles swapped gives the field on the reference's vertices.
                params.region_errors = true;
                swapped = compare(test, reference, params, &progress);
                field = &swapped.region_errors;
            }
            const Heatmap h = make_heatmap(on_reference ? reference : test, *field, static_cast<float>(o.range));
            write_heatmap_ply(h, o.heatmap);
            for (float v : *field) heat_max = std::max(heat_max, v);
        }
        ImageError image;
#ifdef LODFORGE_HAVE_RENDER
        if (o.render) {
            image = render::compareImages(reference, test, o.image);
        }
#endif
        progress.finish();

        if (o.json) {
            nlohmann::ordered_json j;
            j["reference"] = o.reference;
            j["test"] = o.test;
            j.update(nlohmann::ordered_json::parse(distance_json(d, true)));
            j["triangles"] = {{"reference", reference.triangle_count()}, {"test", test.triangle_count()}};
            if (!o.heatmap.empty()) j["heatmap"] = {{"file", o.heatmap}, {"mesh", o.heatmap_on}, {"max", heat_max}};
            if (o.poses > 0) {
                nlohmann::ordered_json frames = nlohmann::ordered_json::array();
                for (const PoseFrameError& f : poses.frames)
                    frames.push_back({{"time", f.time}, {"hausdorff", f.distance.hausdorff}, {"mean", f.distance.mean}});
                j["poses"] = {{"animation", o.animation},
                              {"count", poses.frames.size()},
                              {"worst_hausdorff", poses.worst_hausdorff},
                              {"worst_mean", poses.worst_mean},
                              {"mean_mean", poses.mean_mean},
                              {"worst_hausdorff_relative", poses.worst_hausdorff_relative},
                              {"worst_mean_relative", poses.worst_mean_relative},
                              {"mean_mean_relative", poses.mean_mean_relative},
                              {"frames", frames}};
            }
            if (o.render) j["image"] = nlohmann::ordered_json::parse(image_error_json(image, true));
            std::printf("%s\n", j.dump(2).c_str());
            return;
        }
        std::printf("reference: %s (%zu triangles), test: %s (%zu triangles)\n", o.reference.c_str(),
                    reference.triangle_count(), o.test.c_str(), test.triangle_count());
        std::printf("hausdorff: %.6g (%.3g of the diagonal %.6g)\n", d.hausdorff, d.hausdorff_relative, d.diagonal);
        std::printf("mean:      %.6g (%.3g)\n", d.mean, d.mean_relative);
        std::printf("rms:       %.6g (%.3g)\n", d.rms, d.rms_relative);
        std::printf("test -> reference: max %.6g, mean %.6g; reference -> test: max %.6g, mean %.6g\n",
                    d.test_to_reference.max, d.test_to_reference.mean, d.reference_to_test.max, d.reference_to_test.mean);
        if (o.poses > 0)
            std::printf("poses (%zu over animation %lld): hausdorff worst %.6g (%.3g); mean worst %.6g (%.3g), "
                        "average %.6g (%.3g); bind pose mean %.6g\n",
                        poses.frames.size(), o.animation, poses.worst_hausdorff, poses.worst_hausdorff_relative,
                        poses.worst_mean, poses.worst_mean_relative, poses.mean_mean, poses.mean_mean_relative, d.mean);
        if (d.has_color_error) std::printf("colour RMS: %.4g (0-255)\n", d.color_rms);
        if (d.has_texcoord_error) std::printf("texcoord RMS: %.4g (UV units)\n", d.texcoord_rms);
        if (!o.heatmap.empty()) std::printf("heat map: %s (on the %s, largest value %.6g)\n", o.heatmap.c_str(), o.heatmap_on.c_str(), double(heat_max));
        if (o.render) {
            std::printf("image (%d px, %zu views, threshold %d): mean |colour difference| %.3f (0-255), "
                        "pixels over the threshold %.4f, silhouette mismatch %.4f\n",
                        image.size, image.views.size(), image.threshold, image.mean_abs, image.over_threshold,
                        image.silhouette);
            for (const ViewImageError& v : image.views)
                std::printf("  %-7s mean %.3f  over %.4f  silhouette %.4f\n", v.name.c_str(), v.mean_abs,
                            v.over_threshold, v.silhouette);
            if (!o.image.output_dir.empty())
                std::printf("images: %zu PNGs in %s\n", image.files.size(), o.image.output_dir.c_str());
        }
    });
}

}  // namespace lodforge::cli

// The algorithms of the core as Python functions: keyword arguments with the CLI's defaults, presets
// resolved by the CLI's rules (simplify_options.h), work done with the GIL released (py_progress.h).
#include "bind_algorithms.h"
#include "py_mesh.h"
#include "py_progress.h"
#include "simplify_options.h"

#include "lodforge/error.h"
#include "lodforge/io/mesh_io.h"
#include "lodforge/metrics/metrics.h"
#include "lodforge/octree/octree_build.h"
#include "lodforge/octree/octree_info.h"
#include "lodforge/octree/octree_select.h"
#include "lodforge/octree/octree_store.h"
#include "lodforge/pack/lod_pack.h"
#include "lodforge/pack/preset.h"
#include "lodforge/runtime/lodstrips_runtime.h"
#include "lodforge/simplify/lod_chain.h"
#include "lodforge/simplify/simplify.h"
#include "lodforge/simplify/simplify_cluster.h"
#include "lodforge/strips/lodstrips.h"
#ifdef LODFORGE_HAVE_RENDER
#include "lodforge/render/image_compare.h"
#endif

#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <cmath>
#include <filesystem>
#include <optional>
#include <string>

namespace py = pybind11;
namespace fs = std::filesystem;

namespace lodforge::python {
namespace {

template <class T>
py::array_t<T> to_numpy(const std::vector<T>& v) {
    return py::array_t<T>(static_cast<py::ssize_t>(v.size()), v.data());
}

// `weights`: None, the CLI's text ("normal=0.02,uv1=0.4") or a dict with the same names.
SimplifyWeights weights_from(const py::handle& weights, SimplifyWeights base) {
    if (weights.is_none()) return base;
    std::string text;
    if (py::isinstance<py::str>(weights)) {
        text = weights.cast<std::string>();
    } else if (py::isinstance<py::dict>(weights)) {
        for (auto [key, value] : weights.cast<py::dict>()) {
            if (!text.empty()) text += ',';
            text += py::str(key).cast<std::string>() + "=" + py::repr(py::float_(value.cast<double>())).cast<std::string>();
        }
    } else {
        throw Error(Error::Kind::argument, "weights: give a dict such as {'normal': 0.02} or the CLI's text");
    }
    cli::parse_weights(text, base);
    return base;
}

// `preset`: None, a shipped name or a .json path (the CLI's --preset), or a dict in the preset format.
std::optional<Preset> preset_from(const py::handle& preset) {
    if (preset.is_none()) return std::nullopt;
    if (py::isinstance<py::dict>(preset)) {
        const std::string text = py::module_::import("json").attr("dumps")(preset).cast<std::string>();
        return parse_preset(text, "<preset dict>");
    }
    if (py::isinstance<py::str>(preset) || py::hasattr(preset, "__fspath__"))
        return cli::preset_from_option(py::str(py::module_::import("os").attr("fspath")(preset)).cast<std::string>());
    throw Error(Error::Kind::argument, "preset: give a shipped name, a .json path or a dict");
}

struct SimplifyOutput {
    MeshPtr mesh;
    std::size_t triangles = 0, target_triangles = 0, dropped_faces = 0;
    double error = 0, error_relative = 0;
    std::string reason, mode;
};

const char* reason_key(SimplifyResult::StopReason r) {
    switch (r) {
    case SimplifyResult::StopReason::target_reached: return "target_reached";
    case SimplifyResult::StopReason::error_limit: return "error_limit";
    case SimplifyResult::StopReason::topology_limit: return "topology_limit";
    }
    return "unknown";
}

const char* reason_key(ClusterResult::StopReason r) {
    switch (r) {
    case ClusterResult::StopReason::target_reached: return "target_reached";
    case ClusterResult::StopReason::closest: return "closest";
    case ClusterResult::StopReason::grid_limit: return "grid_limit";
    case ClusterResult::StopReason::resolution_given: return "resolution_given";
    }
    return "unknown";
}

// The `lodforge simplify` command's rules with keyword arguments in place of flags.
SimplifyOutput simplify_py(const MeshHandle& handle, std::optional<double> ratio, std::optional<long long> triangles,
                           std::optional<double> max_error, const py::object& preset_arg, const py::object& weights_arg,
                           bool lock_border, std::optional<std::string> mode, const std::string& area_weight,
                           double height_weight, const std::string& placement, const py::object& callback) {
    const int targets = int(ratio.has_value()) + int(triangles.has_value()) + int(max_error.has_value());
    if (targets > 1) throw Error(Error::Kind::argument, "simplify: give exactly one of ratio, triangles and max_error");
    SimplifyWeights weights;
    if (const std::optional<Preset> preset = preset_from(preset_arg)) {
        if (!mode) {
            if (preset->method != LodMethod::collapse && preset->method != LodMethod::cluster)
                throw Error(Error::Kind::argument, "simplify: the preset's method '" + std::string(to_string(preset->method)) +
                                                       "' makes no single mesh; give mode, or use build_lod_chain");
            mode = std::string(to_string(preset->method));
        }
        weights = preset->weights;
        if (*mode == "collapse") lock_border = lock_border || preset->lock_border;
        if (targets == 0) {
            if (preset->levels.empty())
                throw Error(Error::Kind::argument, "simplify: the preset has no levels; give ratio, triangles or max_error");
            const LodTarget& first = preset->levels.front();
            if (first.kind == LodTarget::Kind::ratio) ratio = first.value;
            else if (first.kind == LodTarget::Kind::triangles) triangles = static_cast<long long>(first.value);
            else max_error = first.value;
        }
    } else if (targets != 1) {
        throw Error(Error::Kind::argument, "simplify: give exactly one of ratio, triangles and max_error");
    }
    const std::string m = mode.value_or("collapse");
    if (m != "collapse" && m != "cluster") throw Error(Error::Kind::argument, "simplify: mode must be 'collapse' or 'cluster'");
    if (area_weight != "area" && area_weight != "sqrt")
        throw Error(Error::Kind::argument, "simplify: area_weight must be 'area' or 'sqrt'");
    if (placement != "optimal" && placement != "half-edge")
        throw Error(Error::Kind::argument, "simplify: placement must be 'optimal' or 'half-edge'");
    if (ratio && !(*ratio > 0 && *ratio <= 1))
        throw Error(Error::Kind::argument, "simplify: ratio must be in (0, 1], got " + std::to_string(*ratio));
    if (triangles && *triangles < 1) throw Error(Error::Kind::argument, "simplify: triangles must be at least 1");
    if (max_error && !(*max_error > 0 && std::isfinite(*max_error)))
        throw Error(Error::Kind::argument, "simplify: max_error must be > 0 (a fraction of the diagonal)");
    if (!(height_weight >= 0 && std::isfinite(height_weight)))
        throw Error(Error::Kind::argument, "simplify: height_weight must be finite and >= 0");
    if (m == "cluster" && max_error)
        throw Error(Error::Kind::argument, "simplify: max_error needs mode 'collapse' (clustering targets a triangle count)");
    if (m == "collapse" && height_weight > 0 && placement != "half-edge")
        throw Error(Error::Kind::argument, "simplify: height_weight needs placement 'half-edge' (it orders half-edge collapses)");
    weights = weights_from(weights_arg, weights);
    const Mesh& mesh = checked(handle);

    SimplifyOutput out;
    out.mode = m;
    run_with_progress(callback, [&](Progress* progress) {
        if (m == "cluster") {
            ClusterParams p;
            p.target_ratio = static_cast<float>(ratio.value_or(0));
            p.target_triangles = static_cast<std::size_t>(triangles.value_or(0));
            p.weights = weights;
            ClusterResult r = simplify_cluster(mesh, p, progress);
            out.target_triangles = r.target_triangles;
            out.error = r.error;
            out.error_relative = r.error_relative;
            out.reason = reason_key(r.reason);
            out.mesh = wrap(std::move(r.mesh));
        } else {
            SimplifyParams p;
            p.target_ratio = static_cast<float>(ratio.value_or(0));
            p.target_triangles = static_cast<std::size_t>(triangles.value_or(0));
            if (max_error) p.max_error = static_cast<float>(*max_error);
            p.weights = weights;
            p.lock_border = lock_border;
            p.area_weight = area_weight == "area" ? SimplifyParams::AreaWeight::area : SimplifyParams::AreaWeight::sqrt_area;
            p.height_weight = static_cast<float>(height_weight);
            p.placement = placement == "optimal" ? Placement::optimal : Placement::half_edge;
            SimplifyResult r = simplify(mesh, p, progress);
            out.target_triangles = r.target_triangles;
            out.dropped_faces = r.dropped_faces;
            out.error = r.error;
            out.error_relative = r.error_relative;
            out.reason = reason_key(r.reason);
            out.mesh = wrap(std::move(r.mesh));
        }
        return 0;
    });
    out.triangles = out.mesh->mesh.triangle_count();
    return out;
}

struct ChainLevel {
    MeshPtr mesh;
    std::size_t triangles = 0, target_triangles = 0;
    std::string reason;
    double step_error = 0, step_error_relative = 0, accumulated_error = 0, accumulated_error_relative = 0;
    std::optional<DistanceResult> distance;
    py::array_t<std::uint32_t> input_vertex;
};

struct ChainOutput {
    std::vector<ChainLevel> levels;
    MeshPtr shared;  // every level's triangles over one vertex buffer
    std::vector<std::tuple<std::size_t, std::size_t, std::uint32_t>> shared_ranges;
};

std::vector<LodLevelTarget> chain_targets(const std::optional<std::vector<double>>& ratios,
                                          const std::optional<std::vector<long long>>& triangles,
                                          const std::optional<std::vector<double>>& errors,
                                          const std::optional<Preset>& preset) {
    const int given = int(ratios.has_value()) + int(triangles.has_value()) + int(errors.has_value());
    if (given > 1) throw Error(Error::Kind::argument, "build_lod_chain: give at most one of levels, level_triangles and level_errors");
    std::vector<LodLevelTarget> out;
    if (ratios) for (double r : *ratios) out.push_back({.ratio = static_cast<float>(r)});
    if (triangles)
        for (long long t : *triangles) {
            if (t < 1) throw Error(Error::Kind::argument, "build_lod_chain: level_triangles must be positive");
            out.push_back({.triangles = static_cast<std::size_t>(t)});
        }
    if (errors) for (double e : *errors) out.push_back({.max_error = static_cast<float>(e)});
    if (given == 0 && preset) {
        for (const LodTarget& t : preset->levels) {
            if (t.kind == LodTarget::Kind::ratio) out.push_back({.ratio = static_cast<float>(t.value)});
            else if (t.kind == LodTarget::Kind::triangles) out.push_back({.triangles = static_cast<std::size_t>(t.value)});
            else out.push_back({.max_error = static_cast<float>(t.value)});
        }
    }
    if (out.empty()) throw Error(Error::Kind::argument, "build_lod_chain: give one of levels, level_triangles and level_errors (or preset)");
    return out;
}

ChainOutput chain_py(const MeshHandle& handle, const std::optional<std::vector<double>>& ratios,
                     const std::optional<std::vector<long long>>& triangles, const std::optional<std::vector<double>>& errors,
                     const py::object& preset_arg, const py::object& weights_arg, bool lock_border, bool measure,
                     std::size_t samples, const py::object& callback) {
    const std::optional<Preset> preset = preset_from(preset_arg);
    if (preset && preset->method != LodMethod::collapse)
        throw Error(Error::Kind::argument, "build_lod_chain: the preset's method '" + std::string(to_string(preset->method)) +
                                               "' is not an edge-collapse chain; use write_lod_pack");
    LodChainParams params;
    params.levels = chain_targets(ratios, triangles, errors, preset);
    params.simplify.weights = weights_from(weights_arg, preset ? preset->weights : Preset{}.weights);
    params.simplify.lock_border = lock_border || (preset && preset->lock_border);
    params.measure = measure;
    params.distance.samples = samples;
    params.distance.vertex_errors = false;
    const Mesh& mesh = checked(handle);
    LodChainResult r = run_with_progress(callback, [&](Progress* p) { return build_lod_chain(mesh, params, p); });
    ChainOutput out;
    for (std::size_t k = 0; k < r.levels.size(); ++k) {
        LodLevel& l = r.levels[k];
        ChainLevel c;
        c.mesh = k == 0 ? std::make_shared<MeshHandle>(handle.mesh) : wrap(std::move(l.mesh));
        c.triangles = l.triangles;
        c.target_triangles = l.target_triangles;
        c.reason = k == 0 ? "input" : reason_key(l.reason);
        c.step_error = l.step_error;
        c.step_error_relative = l.step_error_relative;
        c.accumulated_error = l.accumulated_error;
        c.accumulated_error_relative = l.accumulated_error_relative;
        if (l.measured) c.distance = l.distance;
        c.input_vertex = to_numpy(l.input_vertex);
        out.levels.push_back(std::move(c));
    }
    Mesh shared = std::move(r.shared.vertices);
    shared.indices = std::move(r.shared.indices);
    shared.face_materials = std::move(r.shared.face_materials);
    out.shared = wrap(std::move(shared));
    for (const LodIndexRange& range : r.shared.levels)
        out.shared_ranges.emplace_back(range.first_index, range.index_count, range.vertex_count);
    return out;
}

py::dict pack_level_dict(const PackLevel& l) {
    py::dict d;
    d["triangles"] = l.triangles;
    d["vertices"] = l.vertices;
    d["wedges"] = l.wedges;
    d["error"] = l.error;
    d["error_relative"] = l.error_relative;
    d["mean_error"] = l.mean_error;
    d["mean_error_relative"] = l.mean_error_relative;
    d["screen_coverage"] = l.screen_coverage;
    d["screen_size"] = l.screen_size;
    d["files"] = l.files;
    if (l.image_error) d["image_error"] = *l.image_error;
    return d;
}

// The `lodforge pack` command: flags as keyword arguments over the preset (the studio's default without one).
py::dict pack_py(const py::object& mesh_arg, const fs::path& output_path, const py::object& preset_arg,
                 std::optional<fs::path> source_path, std::optional<std::string> method,
                 std::optional<std::vector<double>> ratios, std::optional<std::vector<double>> triangles,
                 std::optional<std::vector<double>> errors, const py::object& weights_arg, bool lock_border,
                 bool image_error, const py::object& callback) {
    const std::string output_dir = output_path.string();
    PackParams params;
    params.preset = preset_from(preset_arg).value_or(Preset{});
    if (method) params.preset.method = lod_method_from_string(*method);
    const auto list = [](const std::optional<std::vector<double>>& v) {
        std::string text;
        if (v) for (double x : *v) text += (text.empty() ? "" : ",") + py::repr(py::float_(x)).cast<std::string>();
        return text;
    };
    std::vector<LodTarget> targets = cli::parse_level_targets(list(ratios), list(triangles), list(errors), "write_lod_pack");
    if (!targets.empty()) params.preset.levels = std::move(targets);
    params.preset.weights = weights_from(weights_arg, params.preset.weights);
    params.preset.lock_border = params.preset.lock_border || lock_border;
    if (image_error) params.preset.exports.image_error = true;
#ifdef LODFORGE_HAVE_RENDER
    if (params.preset.exports.image_error) params.image_error = render::packImageError();
#endif
    params.output_dir = output_dir;
    std::shared_ptr<const MeshHandle> handle;
    if (py::isinstance<MeshHandle>(mesh_arg)) {
        if (!source_path) throw Error(Error::Kind::argument, "write_lod_pack: give source_path, the file the mesh came from (hashed into pack.json)");
        handle = mesh_arg.cast<MeshPtr>();
        checked(*handle);
        params.source_path = source_path->string();
    } else {
        params.source_path = py::str(py::module_::import("os").attr("fspath")(mesh_arg)).cast<std::string>();
    }
    const PackResult r = run_with_progress(callback, [&](Progress* p) {
        // As `lodforge pack` reads it: every placement of an instanced glTF mesh.
        Mesh read;
        if (!handle) {
            ReadOptions options;
            options.place_every_instance = true;
            read = read_mesh(params.source_path, options, p);
        }
        return write_lod_pack(handle ? handle->mesh : read, params, p);
    });
    py::dict d;
    py::list levels;
    for (const PackLevel& l : r.levels) levels.append(pack_level_dict(l));
    d["output_dir"] = output_dir;
    d["glb"] = r.glb.empty() ? py::object(py::none()) : py::object(py::str(r.glb));
    d["source_sha256"] = r.source_sha256;
    d["levels"] = levels;
    d["files"] = r.files;
    d["dropped_levels"] = r.dropped_levels;
    d["notes"] = r.notes;
    d["manifest"] = r.manifest;
    return d;
}

// `lodforge octree info --json` as a dict: one core description, so the keys are the CLI's.
py::dict octree_info_dict(const OctreeStore& store) {
    return py::module_::import("json").attr("loads")(octree_info_json(store.stats(), store.header()));
}

// `lodforge octree build` (octree mode): flags as keyword arguments; None takes the preset's value,
// else the CLI's default.
py::dict octree_build_py(const fs::path& input_path, const fs::path& asset_path, const py::object& preset_arg,
                         std::optional<long long> max_triangles, std::optional<long long> max_depth,
                         std::optional<long long> memory_mb, const fs::path& temp_dir, const py::object& weights_arg,
                         int threads, const py::object& callback) {
    const std::string input = input_path.string(), asset = asset_path.string();
    OctreeBuildParams p;
    long long tri = 10000, depth = 12, memory = 256;
    if (const std::optional<Preset> preset = preset_from(preset_arg)) {
        tri = static_cast<long long>(preset->octree.max_triangles_per_node);
        depth = preset->octree.max_depth;
        memory = static_cast<long long>(preset->octree.memory_mb);
        p.weights = preset->weights;
    }
    tri = max_triangles.value_or(tri);
    depth = max_depth.value_or(depth);
    memory = memory_mb.value_or(memory);
    if (threads < 1 || threads > 2) throw Error(Error::Kind::argument, "build_octree: threads must be 1 or 2");
    if (memory < 4 || memory > (1ll << 30)) throw Error(Error::Kind::argument, "build_octree: memory_mb must be at least 4");
    if (tri < 1) throw Error(Error::Kind::argument, "build_octree: max_triangles must be at least 1");
    if (depth < 0 || depth > 20) throw Error(Error::Kind::argument, "build_octree: max_depth must be in 0..20");
    if (format_from_extension(input) != FileFormat::ply)
        throw Error(Error::Kind::argument, "build_octree: " + input + ": the input must be a .ply file (convert it first)");
    p.max_triangles = static_cast<std::size_t>(tri);
    p.max_depth = static_cast<int>(depth);
    p.memory_bytes = static_cast<std::size_t>(memory) << 20;
    p.temp_dir = temp_dir.string();
    p.threads = threads;
    p.weights = weights_from(weights_arg, p.weights);
    const OctreeBuildResult r = run_with_progress(callback, [&](Progress* pr) { return build_octree(input, asset, p, pr); });
    py::dict d = octree_info_dict(OctreeStore(asset));
    d["warnings"] = r.warnings;
    return d;
}

MeshPtr octree_extract_py(const fs::path& asset, std::optional<int> level, std::optional<std::vector<double>> camera,
                          std::optional<double> screen_error, std::pair<int, int> viewport, bool culling,
                          const py::object& callback) {
    if (level.has_value() == screen_error.has_value())
        throw Error(Error::Kind::argument, "extract_octree: give exactly one of level and screen_error");
    if (screen_error && (!camera || camera->size() != 7))
        throw Error(Error::Kind::argument, "extract_octree: screen_error needs camera=(eye x, y, z, target x, y, z, fov in degrees)");
    Mesh m = run_with_progress(callback, [&](Progress* p) {
        OctreeStore store(asset.string());
        Cut cut;
        if (level) {
            cut = level_cut(store, *level);
        } else {
            const std::vector<double>& c = *camera;
            Camera cam;
            cam.eye = {float(c[0]), float(c[1]), float(c[2])};
            cam.target = {float(c[3]), float(c[4]), float(c[5])};
            cam.fov_y_degrees = float(c[6]);
            if (viewport.first < 1 || viewport.second < 1)
                throw Error(Error::Kind::argument, "extract_octree: viewport must be two positive pixel counts");
            cam.viewport_width = viewport.first;
            cam.viewport_height = viewport.second;
            SelectParams sp;
            sp.screen_error_pixels = static_cast<float>(*screen_error);
            sp.frustum_culling = culling;
            cut = select_cut(store, cam, sp).cut;
        }
        return extract_mesh(store, cut, p);
    });
    return wrap(std::move(m));
}

// `lodforge strips`: a .lodstrips file from a mesh.
py::dict strips_build_py(const MeshHandle& handle, const fs::path& path, const py::object& preset_arg,
                         std::optional<double> coarsest, bool degenerate, const py::object& weights_arg, bool lock_border,
                         std::size_t max_strip_length, const std::string& strip_order, const py::object& callback) {
    LodStripsParams params;
    params.join = degenerate ? StripJoin::degenerate : StripJoin::restart;
    params.coarsest_ratio = static_cast<float>(coarsest.value_or(0.01));
    params.lock_border = lock_border;
    if (const std::optional<Preset> preset = preset_from(preset_arg)) {
        if (!degenerate) params.join = preset->strips.primitive_restart ? StripJoin::restart : StripJoin::degenerate;
        params.weights = preset->weights;
        params.lock_border = params.lock_border || preset->lock_border;
        if (!coarsest && !preset->levels.empty()) {
            const LodTarget& last = preset->levels.back();
            if (last.kind == LodTarget::Kind::error)
                throw Error(Error::Kind::argument, "build_lodstrips: the preset's coarsest level is an error target; "
                                                   "LODStrips takes a ratio or a triangle count (give coarsest)");
            params.coarsest_ratio = last.kind == LodTarget::Kind::ratio ? static_cast<float>(last.value) : 0.f;
            params.coarsest_triangles = last.kind == LodTarget::Kind::triangles ? static_cast<std::size_t>(last.value) : 0;
        }
    }
    if (coarsest && !(*coarsest >= 0 && *coarsest <= 1)) throw Error(Error::Kind::argument, "build_lodstrips: coarsest must be in [0, 1]");
    if (strip_order != "run-off" && strip_order != "cache")
        throw Error(Error::Kind::argument, "build_lodstrips: strip_order must be 'run-off' or 'cache'");
    params.weights = weights_from(weights_arg, params.weights);
    params.max_strip_length = max_strip_length;
    params.strip_order = strip_order == "cache" ? StripOrder::cache : StripOrder::run_off;
    const Mesh& mesh = checked(handle);
    const LodStripsBuild b = run_with_progress(callback, [&](Progress* p) {
        LodStripsBuild built = build_lodstrips(mesh, params, p);
        write_lodstrips(built.data, path.string());
        return built;
    });
    const LodStripsStorage st = lodstrips_storage(b.data);
    py::dict d;
    d["strips"] = b.data.strip_count();
    d["lods"] = b.data.collapse_count() + 1;
    d["max_triangles"] = b.data.triangles.front();
    d["min_triangles"] = b.data.triangles.back();
    d["file_bytes"] = st.file_bytes;
    d["ratio_to_indexed"] = st.ratio_to_indexed;
    return d;
}

MeshPtr strips_extract_py(const fs::path& file, double lod, std::optional<long long> triangles) {
    if (!(lod >= 0 && lod <= 1)) throw Error(Error::Kind::argument, "extract_lodstrips: lod must be in [0, 1]");
    if (triangles && *triangles < 0) throw Error(Error::Kind::argument, "extract_lodstrips: triangles must be >= 0");
    const std::string path = file.string();
    py::gil_scoped_release release;
    lodstrips::LodStrips rt;
    std::string why;
    if (!rt.assign(read_lodstrips(path), &why)) throw_error(Error::Kind::format, path, why);
    if (triangles) rt.go_to_triangles(static_cast<std::size_t>(*triangles));
    else rt.go_to_lod(lod);
    Mesh m = lodstrips_mesh(rt);
    m.source_dir = std::filesystem::path(path).parent_path().string();
    return wrap(std::move(m));
}

}  // namespace

void bind_algorithms(py::module_& m) {
    py::class_<OneSidedDistance>(m, "OneSidedDistance", "Distances from one mesh's samples to the other surface.")
        .def_readonly("max", &OneSidedDistance::max)
        .def_readonly("mean", &OneSidedDistance::mean)
        .def_readonly("rms", &OneSidedDistance::rms)
        .def_readonly("samples", &OneSidedDistance::samples);
    py::class_<DistanceResult>(m, "Distance", "Metro surface distance (model units; *_relative: of the reference's diagonal).")
        .def_readonly("test_to_reference", &DistanceResult::test_to_reference)
        .def_readonly("reference_to_test", &DistanceResult::reference_to_test)
        .def_readonly("hausdorff", &DistanceResult::hausdorff)
        .def_readonly("mean", &DistanceResult::mean)
        .def_readonly("rms", &DistanceResult::rms)
        .def_readonly("diagonal", &DistanceResult::diagonal)
        .def_readonly("hausdorff_relative", &DistanceResult::hausdorff_relative)
        .def_readonly("mean_relative", &DistanceResult::mean_relative)
        .def_readonly("rms_relative", &DistanceResult::rms_relative)
        .def_property_readonly("color_rms", [](const DistanceResult& d) { return d.has_color_error ? py::object(py::float_(d.color_rms)) : py::object(py::none()); },
                               "Colour RMS (0-255) when both meshes have colours, else None.")
        .def_property_readonly("texcoord_rms", [](const DistanceResult& d) { return d.has_texcoord_error ? py::object(py::float_(d.texcoord_rms)) : py::object(py::none()); },
                               "Texcoord RMS (UV units, set 0) when both meshes have them, else None.")
        .def_property_readonly("vertex_errors", [](const DistanceResult& d) { return to_numpy(d.vertex_errors); },
                               "Per test vertex distance to the reference (vertex_errors=True), float32.")
        .def_property_readonly("region_errors", [](const DistanceResult& d) { return to_numpy(d.region_errors); },
                               "Per test vertex heat-map field (region_errors=True), float32.");

    py::class_<SimplifyOutput>(m, "SimplifyResult", "What simplify() made.")
        .def_readonly("mesh", &SimplifyOutput::mesh)
        .def_readonly("triangles", &SimplifyOutput::triangles)
        .def_readonly("target_triangles", &SimplifyOutput::target_triangles)
        .def_readonly("dropped_faces", &SimplifyOutput::dropped_faces)
        .def_readonly("error", &SimplifyOutput::error, "Largest collapse error estimate (model units).")
        .def_readonly("error_relative", &SimplifyOutput::error_relative)
        .def_readonly("reason", &SimplifyOutput::reason,
                      "target_reached, error_limit, topology_limit (collapse); closest, grid_limit (cluster).")
        .def_readonly("mode", &SimplifyOutput::mode);
    m.def("simplify", &simplify_py, py::arg("mesh"), py::kw_only(), py::arg("ratio") = py::none(),
          py::arg("triangles") = py::none(), py::arg("max_error") = py::none(), py::arg("preset") = py::none(),
          py::arg("weights") = py::none(), py::arg("lock_border") = false, py::arg("mode") = py::none(),
          py::arg("area_weight") = "area", py::arg("height_weight") = SimplifyParams{}.height_weight,
          py::arg("placement") = "optimal", py::arg("progress") = py::none(),
          R"(Simplifies a mesh as `lodforge simplify` does, with its defaults.

Give one of ratio (in (0, 1]), triangles or max_error (fraction of the diagonal), or a preset
(name, .json path or dict) whose first level, weights and method are used. mode: 'collapse'
(quadric edge collapse) or 'cluster'; placement: 'optimal' or 'half-edge'.)");

    py::class_<ChainLevel>(m, "LodLevel", "One level of build_lod_chain() (level 0 is the input).")
        .def_readonly("mesh", &ChainLevel::mesh)
        .def_readonly("triangles", &ChainLevel::triangles)
        .def_readonly("target_triangles", &ChainLevel::target_triangles)
        .def_readonly("reason", &ChainLevel::reason)
        .def_readonly("step_error", &ChainLevel::step_error)
        .def_readonly("step_error_relative", &ChainLevel::step_error_relative)
        .def_readonly("accumulated_error", &ChainLevel::accumulated_error)
        .def_readonly("accumulated_error_relative", &ChainLevel::accumulated_error_relative)
        .def_readonly("distance", &ChainLevel::distance, "Measured against the input (None for level 0 or measure=False).")
        .def_readonly("input_vertex", &ChainLevel::input_vertex, "Level vertex -> input vertex.");
    py::class_<ChainOutput>(m, "LodChain", "The levels of build_lod_chain() and all of them over one vertex buffer.")
        .def_readonly("levels", &ChainOutput::levels)
        .def_readonly("shared", &ChainOutput::shared,
                      "One Mesh: the vertices every level uses (coarsest first) and every level's triangles, level 0 first.")
        .def_readonly("shared_ranges", &ChainOutput::shared_ranges,
                      "Per level (first_index, index_count, vertex_count) in `shared` (indices counted flat).");
    m.def("build_lod_chain", &chain_py, py::arg("mesh"), py::kw_only(), py::arg("levels") = py::none(),
          py::arg("level_triangles") = py::none(), py::arg("level_errors") = py::none(), py::arg("preset") = py::none(),
          py::arg("weights") = py::none(), py::arg("lock_border") = false, py::arg("measure") = true,
          py::arg("samples") = 0, py::arg("progress") = py::none(),
          R"(Levels of detail by successive edge collapse, as `lodforge lod` builds them.

levels: triangle ratios of the input, decreasing (or level_triangles, decreasing counts, or
level_errors, increasing fractions of the diagonal), or a preset with the collapse method.)");

    m.def(
        "compare",
        [](const MeshHandle& reference, const MeshHandle& test, std::size_t samples, std::uint64_t seed,
           bool vertex_errors, bool region_errors, const py::object& callback) {
            DistanceParams p;
            p.samples = samples;
            p.seed = seed;
            p.vertex_errors = vertex_errors;
            p.region_errors = region_errors;
            const Mesh& r = checked(reference, "reference");
            const Mesh& t = checked(test, "test");
            return run_with_progress(callback, [&](Progress* pr) { return compare(r, t, p, pr); });
        },
        py::arg("reference"), py::arg("test"), py::kw_only(), py::arg("samples") = 0, py::arg("seed") = 1,
        py::arg("vertex_errors") = false, py::arg("region_errors") = false, py::arg("progress") = py::none(),
        "Metro distance between two meshes, as `lodforge compare` measures it (samples 0 = automatic).");

    py::class_<ViewImageError>(m, "ViewImageError", "The image-space error of one of the 14 views.")
        .def_readonly("name", &ViewImageError::name)
        .def_readonly("mean_abs", &ViewImageError::mean_abs)
        .def_readonly("over_threshold", &ViewImageError::over_threshold)
        .def_readonly("silhouette", &ViewImageError::silhouette)
        .def_readonly("covered", &ViewImageError::covered);
    py::class_<ImageError>(m, "ImageError", "Image-space error over 14 views (docs/image-compare.md).")
        .def_readonly("views", &ImageError::views)
        .def_readonly("mean_abs", &ImageError::mean_abs)
        .def_readonly("over_threshold", &ImageError::over_threshold)
        .def_readonly("silhouette", &ImageError::silhouette)
        .def_readonly("size", &ImageError::size)
        .def_readonly("threshold", &ImageError::threshold)
        .def_readonly("files", &ImageError::files);
#ifdef LODFORGE_HAVE_RENDER
    m.attr("HAVE_RENDER") = true;
    m.def(
        "render_compare",
        [](const MeshHandle& reference, const MeshHandle& test, int size, int threshold, const fs::path& output_dir) {
            ImageErrorParams p;
            p.size = size;
            p.threshold = threshold;
            p.output_dir = output_dir.string();
            const Mesh& r = checked(reference, "reference");
            const Mesh& t = checked(test, "test");
            py::gil_scoped_release release;
            return render::compareImages(r, t, p);
        },
        py::arg("reference"), py::arg("test"), py::kw_only(), py::arg("size") = ImageErrorParams{}.size,
        py::arg("threshold") = ImageErrorParams{}.threshold, py::arg("output_dir") = "",
        "Image-space error as `lodforge compare --render` measures it (needs an X display or Xvfb).");
#else
    m.attr("HAVE_RENDER") = false;
#endif

    m.def("write_lod_pack", &pack_py, py::arg("mesh"), py::arg("output_dir"), py::kw_only(), py::arg("preset") = py::none(),
          py::arg("source_path") = py::none(), py::arg("method") = py::none(), py::arg("levels") = py::none(),
          py::arg("level_triangles") = py::none(), py::arg("level_errors") = py::none(), py::arg("weights") = py::none(),
          py::arg("lock_border") = false, py::arg("image_error") = false, py::arg("progress") = py::none(),
          R"(Writes a LOD pack as `lodforge pack` does (byte for byte, for a path).

mesh: a file path (read as the CLI reads it) or a Mesh with source_path, the file it came from.
preset: a shipped name, a .json path or a dict (default: the studio's preset); the other keywords
override its keys like the CLI's flags. Returns {'levels', 'files', 'glb', 'notes', 'manifest', ...}.)");

    m.def("build_octree", &octree_build_py, py::arg("input_ply"), py::arg("asset_path"), py::kw_only(),
          py::arg("preset") = py::none(), py::arg("max_triangles") = py::none(), py::arg("max_depth") = py::none(),
          py::arg("memory_mb") = py::none(), py::arg("temp_dir") = "", py::arg("weights") = py::none(),
          py::arg("threads") = 2, py::arg("progress") = py::none(),
          "Builds an out-of-core octree asset (.lfo) from a PLY as `lodforge octree build` does "
          "(defaults: the preset's, else max_triangles 10000, max_depth 12, memory_mb 256). Returns its statistics "
          "(octree_info's keys) and 'warnings'.");
    m.def(
        "octree_info", [](const fs::path& asset) { return octree_info_dict(OctreeStore(asset.string())); },
        py::arg("asset_path"), "Statistics of an octree asset: the keys and values of `lodforge octree info --json`.");
    m.def("extract_octree", &octree_extract_py, py::arg("asset_path"), py::kw_only(), py::arg("level") = py::none(),
          py::arg("camera") = py::none(), py::arg("screen_error") = py::none(),
          py::arg("viewport") = std::pair<int, int>{1920, 1080}, py::arg("culling") = true, py::arg("progress") = py::none(),
          "A whole-model level (level, 0 = input) or a view-dependent cut (screen_error in pixels with "
          "camera=(eye x, y, z, target x, y, z, fov degrees)) of an octree asset, as a Mesh.");

    m.def("build_lodstrips", &strips_build_py, py::arg("mesh"), py::arg("path"), py::kw_only(),
          py::arg("preset") = py::none(), py::arg("coarsest") = py::none(), py::arg("degenerate") = false,
          py::arg("weights") = py::none(), py::arg("lock_border") = false, py::arg("max_strip_length") = 256,
          py::arg("strip_order") = "run-off", py::arg("progress") = py::none(),
          "Writes a LODStrips continuous-LOD file as `lodforge strips` does (coarsest default 0.01 of the "
          "input triangles). Returns {'strips', 'lods', 'max_triangles', 'min_triangles', 'file_bytes', ...}.");
    m.def("extract_lodstrips", &strips_extract_py, py::arg("path"), py::kw_only(), py::arg("lod") = 1.0,
          py::arg("triangles") = py::none(),
          "One level of a .lodstrips file as a Mesh: lod 0 = coarsest stored, 1 = full detail, or the finest "
          "level with at most `triangles` triangles.");
}

}  // namespace lodforge::python

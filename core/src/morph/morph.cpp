// Morphing meshes: keyframes over one connectivity, linear blending.
//
// Based on:
//  - J. F. Ramos, "LODStrips: Continuous Level of Detail using Triangle Strips", PhD thesis, Universitat
//    Jaume I, 2008, chapter 6 (a supermesh connectivity shared by the shapes, V(t) = (1−t)·V(0) + t·V(1),
//    normals blended in the vertex shader);
//  - the glTF 2.0 specification, §3.7.2.2 "Morph Targets" (position = base + Σ wᵢ·targetᵢ, weights
//    animated per node).
//
// Decisions (docs/morph.md): t spans the whole sequence with evenly spaced keyframes; a glTF weights
// animation is sampled at evenly spaced times, as many as it has keys (its LINEAR keys are reproduced
// exactly when they are evenly spaced, which exporters do); normals the input lacks are recomputed per
// frame from the faces, so a pose's shading follows its shape.
#include "lodforge/morph/morph.h"

#include "lodforge/error.h"
#include "lodforge/io/gltf_reader.h"
#include "lodforge/io/mesh_io.h"
#include "union_find.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <numeric>

namespace lodforge {
namespace fs = std::filesystem;

namespace {

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return s;
}

Vec3f normalized(Vec3f v) {
    const float len = length(v);
    return len > 0.f ? v * (1.f / len) : Vec3f{0, 0, 1};
}

std::string describe_face(const Mesh& mesh, std::size_t corner) {
    return "face " + std::to_string(corner / 3) + " corner " + std::to_string(corner % 3) + " is vertex " +
           std::to_string(mesh.indices[corner]);
}

// The first difference in connectivity between `frame` and `first`, or empty.
std::string connectivity_difference(const Mesh& first, const Mesh& frame) {
    if (frame.vertex_count() != first.vertex_count())
        return std::to_string(frame.vertex_count()) + " vertices, the first frame has " +
               std::to_string(first.vertex_count());
    if (frame.indices.size() != first.indices.size())
        return std::to_string(frame.triangle_count()) + " triangles, the first frame has " +
               std::to_string(first.triangle_count());
    for (std::size_t i = 0; i < first.indices.size(); ++i)
        if (frame.indices[i] != first.indices[i])
            return describe_face(frame, i) + ", in the first frame vertex " + std::to_string(first.indices[i]);
    if (frame.has_normals() != first.has_normals())
        return std::string(frame.has_normals() ? "has" : "has no") + " normals, the first frame " +
               (first.has_normals() ? "has" : "has none");
    if (frame.position_ids != first.position_ids) {
        for (std::size_t v = 0; v < std::min(frame.position_ids.size(), first.position_ids.size()); ++v)
            if (frame.position_ids[v] != first.position_ids[v])
                return "vertex " + std::to_string(v) + " is a wedge of point " + std::to_string(frame.position_ids[v]) +
                       ", in the first frame of point " + std::to_string(first.position_ids[v]);
        return "a different vertex-to-point layout than the first frame";
    }
    return {};
}

MorphMesh load_sequence(const std::string& dir, const MorphLoadOptions& options, Progress* progress) {
    std::vector<fs::path> files;
    std::error_code ec;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string ext = lower(it->path().extension().string());
        if ((ext == ".obj" || ext == ".ply") && it->is_regular_file(ec)) files.push_back(it->path());
    }
    if (ec) throw_error(Error::Kind::io, dir, "cannot list the directory: " + ec.message());
    std::sort(files.begin(), files.end(), [](const fs::path& a, const fs::path& b) {
        return a.filename().string() < b.filename().string();
    });
    if (files.size() < 2)
        throw_error(Error::Kind::invalid, dir,
                    "a morph sequence needs at least two .obj or .ply frames, found " + std::to_string(files.size()));
    const std::vector<std::size_t> chosen = spread_frames(files.size(), options.frames);
    MorphMesh morph;
    morph.source = dir;
    for (std::size_t i = 0; i < chosen.size(); ++i) {
        check_progress(progress, double(i) / double(chosen.size()), "Reading frames");
        const std::string file = files[chosen[i]].string();
        Mesh mesh = read_mesh(file);
        if (mesh.triangle_count() == 0) throw_error(Error::Kind::invalid, file, "frame has no triangles");
        if (i == 0) {
            morph.base = mesh;
            morph.normals_from_input = mesh.has_normals();
        } else if (const std::string diff = connectivity_difference(morph.base, mesh); !diff.empty()) {
            throw_error(Error::Kind::invalid, file,
                        "connectivity differs from " + files[chosen[0]].filename().string() + ": " + diff);
        }
        morph.frame_positions.push_back(std::move(mesh.positions));
        if (morph.normals_from_input) morph.frame_normals.push_back(std::move(mesh.normals));
        morph.frame_names.push_back(files[chosen[i]].filename().string());
    }
    check_progress(progress, 1.0, "Reading frames");
    return morph;
}

std::vector<float> weights_at(const GltfMorphTargets& mt, double time) {
    const auto& times = mt.key_times;
    const auto& keys = mt.key_weights;
    if (time <= times.front()) return keys.front();
    if (time >= times.back()) return keys.back();
    const std::size_t k = static_cast<std::size_t>(std::upper_bound(times.begin(), times.end(), float(time)) - times.begin()) - 1;
    if (mt.interpolation == "STEP") return keys[k];
    // LINEAR, and CUBICSPLINE approximated by its key values (tangents dropped; docs/morph.md).
    const double s = (time - times[k]) / (double(times[k + 1]) - times[k]);
    std::vector<float> w(keys[k].size());
    for (std::size_t i = 0; i < w.size(); ++i)
        w[i] = static_cast<float>((1 - s) * keys[k][i] + s * keys[k + 1][i]);
    return w;
}

MorphMesh load_gltf_morph(const std::string& path, const MorphLoadOptions& options, Progress* progress) {
    GltfMorphTargets mt;
    GltfReadOptions gopt;
    gopt.morph_targets = &mt;
    MorphMesh morph;
    morph.source = path;
    morph.base = read_gltf(path, progress, gopt);
    if (mt.target_count() == 0) throw_error(Error::Kind::unsupported, path, "has no morph targets");
    if (morph.base.triangle_count() == 0) throw_error(Error::Kind::invalid, path, "has no triangles");
    std::vector<std::vector<float>> weights;
    if (!mt.key_times.empty()) {
        const std::size_t n = options.frames ? options.frames : mt.key_times.size();
        const double t0 = mt.key_times.front(), t1 = mt.key_times.back();
        for (std::size_t i = 0; i < n; ++i) {
            const double time = n == 1 ? t0 : t0 + (t1 - t0) * double(i) / double(n - 1);
            weights.push_back(weights_at(mt, time));
            morph.frame_names.push_back("key " + std::to_string(i) + " (t = " + std::to_string(time) + " s)");
        }
    } else {
        std::vector<std::vector<float>> all(1, std::vector<float>(mt.target_count(), 0.f));
        std::vector<std::string> names{"base"};
        for (std::size_t t = 0; t < mt.target_count(); ++t) {
            all.emplace_back(mt.target_count(), 0.f);
            all.back()[t] = 1.f;
            names.push_back("target " + std::to_string(t) + (mt.names[t].empty() ? "" : " '" + mt.names[t] + "'"));
        }
        for (std::size_t i : spread_frames(all.size(), options.frames)) {
            weights.push_back(all[i]);
            morph.frame_names.push_back(names[i]);
        }
    }
    const bool blend_normals = morph.base.has_normals() && !mt.normal_deltas.empty();
    morph.normals_from_input = blend_normals;
    const std::size_t nv = morph.base.vertex_count();
    for (const auto& w : weights) {
        std::vector<Vec3f> p = morph.base.positions;
        std::vector<Vec3f> n = blend_normals ? morph.base.normals : std::vector<Vec3f>();
        for (std::size_t t = 0; t < mt.target_count(); ++t) {
            if (w[t] == 0.f) continue;
            for (std::size_t v = 0; v < nv; ++v) p[v] = p[v] + mt.position_deltas[t][v] * w[t];
            if (blend_normals)
                for (std::size_t v = 0; v < nv; ++v) n[v] = n[v] + mt.normal_deltas[t][v] * w[t];
        }
        for (Vec3f& x : n) x = normalized(x);
        morph.frame_positions.push_back(std::move(p));
        if (blend_normals) morph.frame_normals.push_back(std::move(n));
    }
    if (!blend_normals) morph.base.normals.clear();  // stale for every pose but the base
    return morph;
}

// Blends frame arrays a and b at fraction s, renormalising when asked.
void blend_frames(const std::vector<Vec3f>& a, const std::vector<Vec3f>* b, float s, bool unit, std::vector<Vec3f>& out) {
    out.resize(a.size());
    if (!b || s == 0.f) {
        std::copy(a.begin(), a.end(), out.begin());
        return;
    }
    const float r = 1.f - s;
    for (std::size_t v = 0; v < a.size(); ++v) {
        const Vec3f x = a[v] * r + (*b)[v] * s;
        out[v] = unit ? normalized(x) : x;
    }
}

}  // namespace

std::vector<std::size_t> spread_frames(std::size_t total, std::size_t count) {
    std::vector<std::size_t> out;
    if (count == 0 || count >= total) {
        out.resize(total);
        std::iota(out.begin(), out.end(), std::size_t{0});
        return out;
    }
    for (std::size_t i = 0; i < count; ++i)
        out.push_back(count == 1 ? 0
                                 : static_cast<std::size_t>(std::llround(double(i) * double(total - 1) / double(count - 1))));
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

MorphSpan morph_span(std::size_t frame_count, double t) {
    if (frame_count == 0) throw Error(Error::Kind::argument, "morph: no frames");
    if (!(t >= 0.0 && t <= 1.0)) throw Error(Error::Kind::argument, "morph: t must be in [0, 1], got " + std::to_string(t));
    if (frame_count == 1) return {0, 0.f};
    const double x = t * double(frame_count - 1);
    const auto k = std::min(static_cast<std::size_t>(x), frame_count - 2);
    return {k, static_cast<float>(x - double(k))};
}

void morph_positions_at(const MorphMesh& morph, double t, std::vector<Vec3f>& out) {
    const MorphSpan span = morph_span(morph.frame_count(), t);
    const auto& f = morph.frame_positions;
    blend_frames(f[span.frame], span.frame + 1 < f.size() ? &f[span.frame + 1] : nullptr, span.s, false, out);
}

void morph_normals_at(const MorphMesh& morph, double t, std::vector<Vec3f>& out) {
    const MorphSpan span = morph_span(morph.frame_count(), t);
    const auto& f = morph.frame_normals;
    blend_frames(f[span.frame], span.frame + 1 < f.size() ? &f[span.frame + 1] : nullptr, span.s, true, out);
}

Mesh morph_mesh_at(const MorphMesh& morph, double t) {
    Mesh m = morph.base;
    morph_positions_at(morph, t, m.positions);
    morph_normals_at(morph, t, m.normals);
    return m;
}

Mesh morph_keyframe_mesh(const MorphMesh& morph, std::size_t frame) {
    if (frame >= morph.frame_count())
        throw Error(Error::Kind::argument, "morph: frame " + std::to_string(frame) + " of " + std::to_string(morph.frame_count()));
    Mesh m = morph.base;
    m.positions = morph.frame_positions[frame];
    m.normals = morph.frame_normals[frame];
    return m;
}

std::vector<Vec3f> vertex_normals(const Mesh& mesh, const std::vector<Vec3f>& positions) {
    const std::size_t nv = positions.size();
    const bool ids = mesh.position_ids.size() == nv;
    const std::size_t points = ids ? mesh.point_count() : nv;
    std::vector<Vec3f> sum(points);
    auto point = [&](std::uint32_t v) { return ids ? mesh.position_ids[v] : v; };
    for (std::size_t f = 0; f < mesh.triangle_count(); ++f) {
        const std::uint32_t* c = &mesh.indices[3 * f];
        // Twice the area times the unit normal: larger faces count more.
        const Vec3f n = cross(positions[c[1]] - positions[c[0]], positions[c[2]] - positions[c[0]]);
        for (int k = 0; k < 3; ++k) sum[point(c[k])] = sum[point(c[k])] + n;
    }
    std::vector<Vec3f> out(nv);
    for (std::uint32_t v = 0; v < nv; ++v) out[v] = normalized(sum[point(v)]);
    return out;
}

std::vector<std::uint32_t> morph_points(const MorphMesh& morph) {
    const std::size_t n = morph.vertex_count();
    detail::UnionFind sets(n);
    const auto& ids = morph.base.position_ids;
    if (ids.size() == n) {
        std::vector<std::uint32_t> first(morph.base.point_count(), 0xffffffffu);
        for (std::uint32_t v = 0; v < n; ++v) {
            if (first[ids[v]] == 0xffffffffu) first[ids[v]] = v;
            else sets.unite(first[ids[v]], v);
        }
    }
    // Bit-identical in every frame, by a lexicographic sort over the frames.
    auto less_at = [](Vec3f a, Vec3f b) {
        if (a.x != b.x) return a.x < b.x;
        if (a.y != b.y) return a.y < b.y;
        return a.z < b.z;
    };
    std::vector<std::uint32_t> order(n);
    std::iota(order.begin(), order.end(), 0u);
    const auto& frames = morph.frame_positions;
    std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
        for (const auto& f : frames) {
            if (less_at(f[a], f[b])) return true;
            if (less_at(f[b], f[a])) return false;
        }
        return a < b;
    });
    for (std::size_t i = 1; i < n; ++i) {
        const std::uint32_t a = order[i - 1], b = order[i];
        const bool same = std::all_of(frames.begin(), frames.end(), [&](const auto& f) { return f[a] == f[b]; });
        if (same) sets.unite(a, b);
    }
    std::vector<std::uint32_t> id(n), id_of_root(n, 0xffffffffu);
    std::uint32_t next = 0;
    for (std::uint32_t v = 0; v < n; ++v) {
        const std::uint32_t r = sets.find(v);
        if (id_of_root[r] == 0xffffffffu) id_of_root[r] = next++;
        id[v] = id_of_root[r];
    }
    return id;
}

void finish_morph(MorphMesh& morph, const std::string& source) {
    if (morph.frame_positions.empty()) throw_error(Error::Kind::invalid, source, "a morph mesh needs at least one frame");
    if (morph.base.positions.empty()) morph.base.positions = morph.frame_positions.front();
    const std::size_t nv = morph.base.vertex_count();
    if (morph.base.triangle_count() == 0) throw_error(Error::Kind::invalid, source, "a morph mesh needs triangles");
    for (std::size_t i = 0; i < morph.base.indices.size(); ++i)
        if (morph.base.indices[i] >= nv)
            throw_error(Error::Kind::invalid, source, describe_face(morph.base, i) + ", out of range (" +
                                                          std::to_string(nv) + " vertices)");
    if (!morph.frame_normals.empty() && morph.frame_normals.size() != morph.frame_positions.size())
        throw_error(Error::Kind::invalid, source, std::to_string(morph.frame_normals.size()) + " normal frames for " +
                                                      std::to_string(morph.frame_positions.size()) + " position frames");
    for (std::size_t k = 0; k < morph.frame_positions.size(); ++k) {
        const std::string name = k < morph.frame_names.size() ? morph.frame_names[k] : "frame " + std::to_string(k);
        if (morph.frame_positions[k].size() != nv)
            throw_error(Error::Kind::invalid, source, name + " has " + std::to_string(morph.frame_positions[k].size()) +
                                                          " positions, the connectivity " + std::to_string(nv) + " vertices");
        for (std::size_t v = 0; v < nv; ++v)
            if (!is_finite(morph.frame_positions[k][v]))
                throw_error(Error::Kind::invalid, source, name + ": vertex " + std::to_string(v) + " has a non-finite position");
        if (!morph.frame_normals.empty()) {
            if (morph.frame_normals[k].size() != nv)
                throw_error(Error::Kind::invalid, source, name + " has " + std::to_string(morph.frame_normals[k].size()) +
                                                              " normals for " + std::to_string(nv) + " vertices");
            for (std::size_t v = 0; v < nv; ++v)
                if (!is_finite(morph.frame_normals[k][v]))
                    throw_error(Error::Kind::invalid, source, name + ": vertex " + std::to_string(v) + " has a non-finite normal");
        }
    }
    while (morph.frame_names.size() < morph.frame_count()) morph.frame_names.push_back("frame " + std::to_string(morph.frame_names.size()));
    if (morph.frame_normals.empty()) {
        morph.normals_from_input = false;
        for (const auto& p : morph.frame_positions) morph.frame_normals.push_back(vertex_normals(morph.base, p));
    } else {
        // Unit normals stay bit for bit (a float file round trip is exact); others are renormalised.
        for (auto& frame : morph.frame_normals)
            for (Vec3f& n : frame)
                if (std::fabs(dot(n, n) - 1.f) > 1e-6f) n = normalized(n);
    }
    morph.base.positions = morph.frame_positions.front();
    if (morph.normals_from_input) morph.base.normals = morph.frame_normals.front();
    else morph.base.normals.clear();
    if (morph.source.empty()) morph.source = source;
}

MorphMesh load_morph(const std::string& path, const MorphLoadOptions& options, Progress* progress) {
    std::error_code ec;
    if (!fs::exists(path, ec)) throw_error(Error::Kind::io, path, "no such file or directory");
    MorphMesh morph;
    if (fs::is_directory(path, ec)) {
        morph = load_sequence(path, options, progress);
    } else {
        const FileFormat f = detect_format(path);
        if (f != FileFormat::gltf && f != FileFormat::glb)
            throw_error(Error::Kind::unsupported, path,
                        "morph input must be a directory of .obj/.ply frames or a .gltf/.glb with morph targets");
        morph = load_gltf_morph(path, options, progress);
    }
    finish_morph(morph, path);
    return morph;
}

}  // namespace lodforge

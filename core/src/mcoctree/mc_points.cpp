// The marching-cube octree's input points (mc_points.h). Follows Hasup Lee, "Efficient Level-of-Detail
// Model Generation of 3D Objects using Prioritized Marching Cube Octree" (doctoral thesis, KAIST, 2007,
// ch. 4): oriented points, normals after Hoppe, DeRose, Duchamp, McDonald, Stuetzle, "Surface
// Reconstruction from Unorganized Points" (SIGGRAPH 1992); departures in docs/mcoctree.md, "Decisions".
#include "mcoctree/mc_points.h"

#include "lodforge/error.h"
#include "mcoctree/mc_face_samples.h"
#include "mcoctree/mc_octree_internal.h"
#include "parallel_for.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

namespace lodforge::mc {

PointCloud points_of(const Mesh& mesh, std::size_t& skipped, unsigned threads, std::vector<Vec3f>& unit_normals,
                     std::vector<std::uint32_t>& point_ids) {
    if (mesh.positions.empty()) throw_error(Error::Kind::invalid, input_name, "no points");
    for (std::size_t i = 0; i < mesh.positions.size(); ++i)
        if (!is_finite(mesh.positions[i]))
            throw_error(Error::Kind::invalid, input_name, "point " + std::to_string(i) + " is not finite");
    // Faces are read for normals, samples and the winding number, with or without the file's normals.
    for (std::size_t t = 0; t < mesh.indices.size(); ++t)
        if (mesh.indices[t] >= mesh.positions.size())
            throw_error(Error::Kind::invalid, input_name, "face " + std::to_string(t / 3) + " has an index out of range");
    PointCloud pc;
    std::vector<Vec3f> normals;
    std::vector<float> magnitude;  // per point: the summed length of what its normal adds up
    auto normals_of = [&] {
        normals = mesh.normals;
        if (normals.size() == mesh.positions.size()) {
            magnitude.resize(normals.size());
            for (std::size_t i = 0; i < normals.size(); ++i) magnitude[i] = length(normals[i]);
        } else {
            if (mesh.indices.empty())
                throw_error(Error::Kind::invalid, input_name,
                            "the points have no normals and there are no faces to compute them from");
            normals.assign(mesh.positions.size(), Vec3f{});
            magnitude.assign(mesh.positions.size(), 0.f);
            for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
                const std::uint32_t a = mesh.indices[t], b = mesh.indices[t + 1], c = mesh.indices[t + 2];
                // cross product length = twice the area: area-weighted average of the adjacent face normals
                const Vec3f n = cross(mesh.positions[b] - mesh.positions[a], mesh.positions[c] - mesh.positions[a]);
                normals[a] = normals[a] + n, normals[b] = normals[b] + n, normals[c] = normals[c] + n;
                const float m = length(n);
                magnitude[a] += m, magnitude[b] += m, magnitude[c] += m;
            }
            for (std::size_t i = 0; i < normals.size(); ++i)
                if (length(normals[i]) < kFoldedFaces * magnitude[i]) normals[i] = Vec3f{}, magnitude[i] = 0;
        }
        for (std::size_t i = 0; i < mesh.positions.size(); ++i)
            if (!is_finite(normals[i]))
                throw_error(Error::Kind::invalid, input_name, "normal of point " + std::to_string(i) + " is not finite");
    };
    // Points at exactly the same position are one surface point (D1): the first keeps the sum of their
    // normals (for normals from faces, the normal of the welded vertex), the others are dropped. When the
    // sum vanishes (opposite normals) the first point's own normal stays. Finding the copies needs the
    // positions only, so the normals are made on a second thread meanwhile.
    const bool colors = mesh.colors.size() == mesh.positions.size();
    std::vector<std::uint8_t> merged(mesh.positions.size(), 0);  // 1: a later copy, 2: the first of copies
    mc::KeyMap first;
    std::vector<std::uint32_t> firsts;  // the first point of each group of copies, in order of discovery
    auto key_of = [](const Vec3f& p) {
        auto bits = [](float f) { return std::bit_cast<std::uint32_t>(f == 0 ? 0.f : f); };  // -0 == +0
        const std::uint64_t key = (std::uint64_t(bits(p.x)) * 0x9E3779B97F4A7C15ULL) ^
                                  (std::uint64_t(bits(p.y)) * 0xC2B2AE3D27D4EB4FULL) ^ (std::uint64_t(bits(p.z)) << 7);
        return key & ~(std::uint64_t(1) << 63);  // never the map's empty key
    };
    auto find_copies = [&] {
        first = mc::KeyMap(mesh.positions.size());
        for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
            const Vec3f p = mesh.positions[i];
            const std::uint32_t at = first.insert(key_of(p), static_cast<std::uint32_t>(i));
            if (at == i || !(mesh.positions[at] == p)) continue;  // new, or another position with this hash
            merged[i] = 1;
            if (merged[at] < 2) merged[at] = 2, firsts.push_back(at);
        }
    };
    detail::run_beside(threads, find_copies, normals_of);  // the longer one here (thread CPU = critical path)
    if (!firsts.empty()) {
        std::vector<std::uint32_t> group(mesh.positions.size(), none);
        std::vector<Vec3f> sums;  // per group: the sum of its normals, in point order
        std::vector<float> sum_magnitudes;
        for (std::size_t g = 0; g < firsts.size(); ++g) {
            group[firsts[g]] = static_cast<std::uint32_t>(g);
            sums.push_back(normals[firsts[g]]);
            sum_magnitudes.push_back(magnitude[firsts[g]]);
        }
        for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
            if (merged[i] != 1) continue;
            const std::uint32_t g = group[first.find(key_of(mesh.positions[i]))];
            sums[g] = sums[g] + normals[i];
            sum_magnitudes[g] += magnitude[i];
        }
        for (std::size_t g = 0; g < firsts.size(); ++g)
            if (length(sums[g]) > kCancelled * sum_magnitudes[g]) normals[firsts[g]] = sums[g];
    }
    pc.points.reserve(mesh.positions.size());
    pc.normals.reserve(mesh.positions.size());
    if (colors) pc.colors.reserve(mesh.positions.size());
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
        if (merged[i] == 1) continue;
        const Vec3f n = normals[i];
        const float len = length(n);
        // unreferenced vertex, degenerate faces only, or faces that cancel: no orientation, skip
        if (!(len > 0)) {
            ++skipped;
            continue;
        }
        pc.points.push_back(mesh.positions[i]);
        pc.normals.push_back(n * (1.f / len));
        if (colors) pc.colors.push_back(mesh.colors[i]);
    }
    if (pc.points.empty())
        throw_error(Error::Kind::invalid, input_name, "no point has a usable normal (all zero)");
    if (!mesh.indices.empty()) {
        unit_normals.assign(mesh.positions.size(), Vec3f{});
        point_ids.resize(mesh.positions.size());
        for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
            if (merged[i] == 1) continue;
            point_ids[i] = static_cast<std::uint32_t>(i);
            const float len = length(normals[i]);
            if (len > 0) unit_normals[i] = normals[i] * (1.f / len);
        }
        for (std::size_t i = 0; i < mesh.positions.size(); ++i)
            if (merged[i] == 1) point_ids[i] = first.find(key_of(mesh.positions[i])), unit_normals[i] = unit_normals[point_ids[i]];
    }
    pc.coords.reserve(pc.points.size());
    for (const Vec3f& p : pc.points) pc.coords.push_back({p.x, p.y, p.z});
    return pc;
}

double median_spacing(const PointCloud& pc, const KdTree& tree) {
    const std::size_t n = pc.points.size();
    if (n < 2) return 0;
    const std::size_t samples = std::min<std::size_t>(n, 2000);
    std::vector<float> d;
    d.reserve(samples);
    for (std::size_t s = 0; s < samples; ++s) {
        const std::size_t i = s * n / samples;
        const float q[3] = {pc.points[i].x, pc.points[i].y, pc.points[i].z};
        std::uint32_t idx[2];
        float d2[2];
        nanoflann::KNNResultSet<float, std::uint32_t> rs(2);
        rs.init(idx, d2);
        tree.findNeighbors(rs, q, nanoflann::SearchParams());
        if (rs.size() == 2) d.push_back(std::sqrt(d2[1]));
    }
    if (d.empty()) return 0;
    std::nth_element(d.begin(), d.begin() + std::ptrdiff_t(d.size() / 2), d.end());
    return d[d.size() / 2];
}

}  // namespace lodforge::mc

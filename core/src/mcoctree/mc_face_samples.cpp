#include "mcoctree/mc_face_samples.h"

#include "lodforge/error.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <unordered_map>

namespace lodforge::mc {

namespace {

Vec4f mix(const Vec4f& a, float wa, const Vec4f& b, float wb, const Vec4f& c, float wc) {
    return {a.x * wa + b.x * wb + c.x * wc, a.y * wa + b.y * wb + c.y * wc, a.z * wa + b.z * wb + c.z * wc,
            a.w * wa + b.w * wb + c.w * wc};
}

// acos within 7e-5 rad (Abramowitz and Stegun 4.4.45): the angle weights of a pseudo-normal need no
// more, and the library's acosf was half of the pseudo-normals' time on the dragon (2.6 M corners).
float fast_acos(float x) {
    const float a = std::fabs(x);
    const float r = std::sqrt(std::max(0.f, 1 - a)) * (1.5707288f + a * (-0.2121144f + a * (0.0742610f - a * 0.0187293f)));
    return x < 0 ? 3.14159265f - r : r;
}

Vec3f unit_or(Vec3f v, Vec3f fallback) {
    const float len = length(v);
    return len > 0 ? v * (1.f / len) : fallback;
}

}  // namespace

bool has_long_face(const Mesh& mesh, float min_edge) {
    const auto& P = mesh.positions;
    const float min2 = min_edge * min_edge;
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        const Vec3f a = P[mesh.indices[t]], b = P[mesh.indices[t + 1]], c = P[mesh.indices[t + 2]];
        if (dot(b - a, b - a) > min2 || dot(c - b, c - b) > min2 || dot(a - c, a - c) > min2) return true;
    }
    return false;
}

FaceSamples sample_large_faces(const Mesh& mesh, std::span<const Vec3f> vertex_normals,
                               std::span<const std::uint32_t> point_id, const FaceSampleParams& params) {
    FaceSamples out;
    const bool colors = mesh.colors.size() == mesh.positions.size();
    const auto& P = mesh.positions;
    const auto& N = vertex_normals;
    const std::size_t faces = mesh.indices.size() / 3;
    auto segments = [&](float len) { return std::ceil(double(len) / double(params.spacing)); };
    auto usable = [&](std::uint32_t v) { return !(vertex_normals[v] == Vec3f{}); };
    auto corners = [&](std::size_t f) {
        return std::array<std::uint32_t, 3>{mesh.indices[3 * f], mesh.indices[3 * f + 1], mesh.indices[3 * f + 2]};
    };
    auto edge_lengths = [&](const std::array<std::uint32_t, 3>& v) {
        return std::array<float, 3>{length(P[v[1]] - P[v[0]]), length(P[v[2]] - P[v[1]]), length(P[v[0]] - P[v[2]])};
    };
    auto face_normal = [&](const std::array<std::uint32_t, 3>& v) {
        return unit_or(cross(P[v[1]] - P[v[0]], P[v[2]] - P[v[0]]), Vec3f{});
    };
    // The long faces and their corners' points; everything below looks only at faces touching those, so a
    // scan with a few long faces (the dragon at 256: 3,706 of 871,414) pays little more than this pass.
    const float min_edge2 = params.min_edge * params.min_edge;
    std::vector<std::uint32_t> long_faces;
    std::vector<std::uint8_t> marked(P.size(), 0);  // per point id: a corner of a long face
    for (std::size_t f = 0; f < faces; ++f) {
        const auto v = corners(f);
        auto len2 = [&](std::uint32_t a, std::uint32_t b) { const Vec3f d = P[b] - P[a]; return dot(d, d); };
        if (!(std::max({len2(v[0], v[1]), len2(v[1], v[2]), len2(v[2], v[0])}) > min_edge2)) continue;
        long_faces.push_back(static_cast<std::uint32_t>(f));
        for (std::uint32_t i : v) marked[point_id[i]] = 1;
    }
    if (long_faces.empty()) return out;
    auto touches = [&](const std::array<std::uint32_t, 3>& v, int at_least) {
        return marked[point_id[v[0]]] + marked[point_id[v[1]]] + marked[point_id[v[2]]] >= at_least;
    };
    // A face turned against its corners' normals from the faces around them is folded back under its
    // neighbours (a sliver in the Duck's bill): its side is the wrong one for everything around it, so it
    // orients nothing. (The file's normals do not tell: the Duck's agree with the fold.)
    std::vector<Vec3f> around(P.size());  // per marked point: the area-weighted sum of its faces' normals
    for (std::size_t f = 0; f < faces; ++f) {
        const auto v = corners(f);
        if (!touches(v, 1)) continue;
        const Vec3f n = cross(P[v[1]] - P[v[0]], P[v[2]] - P[v[0]]);
        for (std::uint32_t i : v)
            if (marked[point_id[i]]) around[point_id[i]] = around[point_id[i]] + n;
    }
    // Only asked of faces with at least two marked corners (on a long face's edge); the third corner's
    // sum is then complete too when it is marked, and zero (no say) when it is not.
    auto agrees = [&](const std::array<std::uint32_t, 3>& v, Vec3f n) {
        return dot(n, unit_or(around[point_id[v[0]]], {}) + unit_or(around[point_id[v[1]]], {}) +
                          unit_or(around[point_id[v[2]]], {})) > 0;
    };
    auto sampled = [&](const std::array<std::uint32_t, 3>& v) {
        return usable(v[0]) && usable(v[1]) && usable(v[2]) && agrees(v, face_normal(v));
    };
    auto edge_key = [&](std::uint32_t a, std::uint32_t b) {
        const std::uint64_t pa = point_id[a], pb = point_id[b];
        return std::min(pa, pb) << 32 | std::max(pa, pb);
    };
    // First the count (an upper bound: shared edges counted twice), so a resolution far beyond what the
    // faces can be sampled at is refused before anything is allocated; and the edges to sample.
    double needed = 0;
    struct Edge {
        Vec3f sum;  // of its faces' unit normals
        bool done = false;
    };
    std::unordered_map<std::uint64_t, Edge> edge_normal;  // the edges to sample
    std::size_t to_sample = 0;
    for (const std::uint32_t f : long_faces) {
        const auto v = corners(f);
        const auto e = edge_lengths(v);
        if (!sampled(v)) continue;
        // rows parallel to the shortest edge: about rows * (shortest / spacing) / 2 points, plus one a row
        const double rows = segments(std::max({e[0], e[1], e[2]}));
        needed += rows * (segments(std::min({e[0], e[1], e[2]})) / 2 + 1) + segments(e[0]) + segments(e[1]) + segments(e[2]);
        ++to_sample;
        for (std::size_t k = 0; k < 3; ++k)
            if (segments(e[k]) >= 2) edge_normal.emplace(edge_key(v[k], v[(k + 1) % 3]), Edge{});
    }
    if (needed > double(params.max_samples))
        throw_error(Error::Kind::argument, "mcoctree input",
                    "resolution too high for this mesh's faces: they would need about " +
                        std::to_string(static_cast<unsigned long long>(needed)) + " surface samples (at most " +
                        std::to_string(params.max_samples) + "); lower --resolution or raise --cube-size");
    if (to_sample == 0) return out;
    // Every face on an edge to sample adds its normal (sampled itself or not: a short face beside a long
    // one) unless it is folded back.
    for (std::size_t f = 0; f < faces; ++f) {
        const auto v = corners(f);
        if (!touches(v, 2)) continue;
        const Vec3f n = face_normal(v);
        if (!agrees(v, n)) continue;
        for (std::size_t k = 0; k < 3; ++k) {
            const auto it = edge_normal.find(edge_key(v[k], v[(k + 1) % 3]));
            if (it != edge_normal.end()) it->second.sum = it->second.sum + n;
        }
    }

    auto add = [&](Vec3f p, Vec3f n, Vec3f shade, const Vec4f& col) {
        out.points.push_back(p);
        out.normals.push_back(n);
        out.shading.push_back(unit_or(shade, n));
        if (colors) out.colors.push_back(col);
    };
    const Vec4f none{};
    auto col = [&](std::uint32_t i) -> const Vec4f& { return colors ? mesh.colors[i] : none; };
    for (const std::uint32_t f : long_faces) {
        const auto v = corners(f);
        const auto e = edge_lengths(v);
        if (!sampled(v)) continue;
        const Vec3f face = face_normal(v);
        if (face == Vec3f{}) continue;  // degenerate: no side to tell
        ++out.faces;
        const std::size_t s0 = e[0] <= e[1] && e[0] <= e[2] ? 0 : e[1] <= e[2] ? 1 : 2;  // shortest: v[s0] -> v[s0+1]
        const std::uint32_t A = v[(s0 + 2) % 3], B = v[s0], C = v[(s0 + 1) % 3];
        const auto rows = static_cast<std::uint32_t>(segments(std::max(e[(s0 + 1) % 3], e[(s0 + 2) % 3])));
        for (std::uint32_t i = 1; i < rows; ++i) {
            const float r = float(i) / float(rows);
            const auto k = static_cast<std::uint32_t>(segments(r * e[s0]));
            for (std::uint32_t j = 1; j < k; ++j) {
                const float u = float(j) / float(k);
                const float wa = 1 - r, wb = r * (1 - u), wc = r * u;
                add(P[A] * wa + P[B] * wb + P[C] * wc, face, N[A] * wa + N[B] * wb + N[C] * wc,
                    mix(col(A), wa, col(B), wb, col(C), wc));
            }
        }
        for (std::size_t k = 0; k < 3; ++k) {
            const std::uint32_t a = v[k], b = v[(k + 1) % 3];
            const auto it = edge_normal.find(edge_key(a, b));
            if (it == edge_normal.end() || it->second.done) continue;  // short, or sampled by another face
            it->second.done = true;
            // Opposite faces (a fin folded flat) leave no direction: this face's normal decides.
            const Vec3f pseudo = unit_or(it->second.sum, face);
            const auto m = static_cast<std::uint32_t>(segments(e[k]));
            for (std::uint32_t s = 1; s < m; ++s) {
                const float wb = float(s) / float(m), wa = 1 - wb;
                add(P[a] * wa + P[b] * wb, pseudo, N[a] * wa + N[b] * wb, mix(col(a), wa, col(b), wb, none, 0));
            }
        }
    }
    return out;
}

std::vector<Vec3f> vertex_pseudo_normals(const Mesh& mesh, std::span<const std::uint32_t> point_id) {
    const auto& P = mesh.positions;
    struct Sum {
        Vec3f n;
        float angles = 0;  // beside the sum: one cache line per scattered add
    };
    std::vector<Sum> sum(P.size());
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        const std::uint32_t v[3] = {mesh.indices[t], mesh.indices[t + 1], mesh.indices[t + 2]};
        const Vec3f e[3] = {P[v[1]] - P[v[0]], P[v[2]] - P[v[1]], P[v[0]] - P[v[2]]};  // e[k]: from corner k
        const float l[3] = {length(e[0]), length(e[1]), length(e[2])};
        const Vec3f n = unit_or(cross(e[2], e[0]), Vec3f{});
        if (n == Vec3f{} || !(l[0] > 0 && l[1] > 0 && l[2] > 0)) continue;
        for (int k = 0; k < 3; ++k) {
            const int in = (k + 2) % 3;  // the edge arriving at corner k
            const float angle = fast_acos(std::clamp(-dot(e[k], e[in]) / (l[k] * l[in]), -1.f, 1.f));
            Sum& s = sum[point_id[v[k]]];
            s.n = s.n + n * angle;
            s.angles += angle;
        }
    }
    std::vector<Vec3f> out(P.size());
    for (std::size_t p = 0; p < P.size(); ++p) {
        const float len = length(sum[p].n);
        if (len > 0.1f * sum[p].angles && len > 0) out[p] = sum[p].n * (1.f / len);
    }
    return out;
}

}  // namespace lodforge::mc

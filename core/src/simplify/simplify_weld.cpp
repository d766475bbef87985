// Welding and output layout of the collapse simplifier (see simplify_weld.h).
#include "simplify/simplify_weld.h"

#include "lodforge/error.h"
#include "union_find.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <numeric>
#include <string>
#include <unordered_map>

namespace lodforge {
namespace simplify_detail {
namespace {

constexpr std::uint32_t kNone = 0xffffffffu;

}  // namespace


// Point id of every vertex: dense, numbered by first occurrence; `representative` gets the first vertex
// of each point.
std::vector<std::uint32_t> derive_points(const Mesh& mesh, bool weld, float tolerance,
                                         std::vector<std::uint32_t>& representative) {
    const std::size_t n = mesh.vertex_count();
    // The smallest vertex index of a set stays its root: the point's representative.
    detail::UnionFind sets(n);
    if (mesh.position_ids.size() == n) {
        std::vector<std::uint32_t> first(mesh.point_count(), kNone);
        for (std::uint32_t v = 0; v < n; ++v) {
            std::uint32_t& f = first[mesh.position_ids[v]];
            if (f == kNone) f = v;
            else sets.unite(f, v);
        }
    }
    if (weld && tolerance <= 0.f) {
        // Open-addressing hash of the position bits (linear, where a sort was 5% of a run): each vertex
        // joins the first earlier vertex at an equal position. -0 is hashed as +0, since they compare
        // equal; NaN equals nothing, as with ==.
        auto bits = [](float f) {
            std::uint32_t b;
            if (f == 0.f) f = 0.f;
            std::memcpy(&b, &f, sizeof b);
            return b;
        };
        std::size_t size = 16;
        while (size < 2 * n) size *= 2;
        std::vector<std::uint32_t> table(size, kNone);
        for (std::uint32_t v = 0; v < n; ++v) {
            const Vec3f p = mesh.positions[v];
            std::uint64_t h = (std::uint64_t(bits(p.x)) * 0x9E3779B97F4A7C15ull) ^
                              (std::uint64_t(bits(p.y)) * 0xC2B2AE3D27D4EB4Full) ^
                              (std::uint64_t(bits(p.z)) * 0x165667B19E3779F9ull);
            h ^= h >> 29;
            for (std::size_t i = h & (size - 1);; i = (i + 1) & (size - 1)) {
                const std::uint32_t o = table[i];
                if (o == kNone) {
                    table[i] = v;
                    break;
                }
                if (mesh.positions[o] == p) {
                    sets.unite(o, v);
                    break;
                }
            }
        }
    } else if (weld) {
        // Grid of cell size `tolerance`: a vertex joins the first earlier vertex within tolerance found
        // in the 27 cells around it.
        auto key = [](std::int64_t x, std::int64_t y, std::int64_t z) {
            return static_cast<std::uint64_t>((x * 73856093) ^ (y * 19349663) ^ (z * 83492791));
        };
        std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> grid;
        const double inv = 1.0 / tolerance;
        const double tol2 = static_cast<double>(tolerance) * tolerance;
        for (std::uint32_t v = 0; v < n; ++v) {
            const Vec3f p = mesh.positions[v];
            const auto cx = static_cast<std::int64_t>(std::floor(p.x * inv));
            const auto cy = static_cast<std::int64_t>(std::floor(p.y * inv));
            const auto cz = static_cast<std::int64_t>(std::floor(p.z * inv));
            std::uint32_t found = kNone;
            for (int dx = -1; dx <= 1 && found == kNone; ++dx)
                for (int dy = -1; dy <= 1 && found == kNone; ++dy)
                    for (int dz = -1; dz <= 1 && found == kNone; ++dz) {
                        auto it = grid.find(key(cx + dx, cy + dy, cz + dz));
                        if (it == grid.end()) continue;
                        for (std::uint32_t o : it->second) {
                            const Vec3f d = mesh.positions[o] - p;
                            if (static_cast<double>(dot(d, d)) <= tol2) { found = o; break; }
                        }
                    }
            if (found != kNone) sets.unite(found, v);
            else grid[key(cx, cy, cz)].push_back(v);
        }
    }
    std::vector<std::uint32_t> point(n);
    std::vector<std::uint32_t> id_of_root(n, kNone);
    representative.clear();
    for (std::uint32_t v = 0; v < n; ++v) {
        const std::uint32_t r = sets.find(v);
        if (id_of_root[r] == kNone) {
            id_of_root[r] = static_cast<std::uint32_t>(representative.size());
            representative.push_back(r);
        }
        point[v] = id_of_root[r];
    }
    return point;
}

// A mesh made of the faces `corners` (input vertex ids; `face_source` = input face of each) with the
// vertices they use, laid out as Mesh requires: one vertex per point first (input order), extra wedges
// after. `vertex_map` receives output vertex → input vertex. Normals are renormalised.
Mesh build_mesh(const Mesh& src, const std::vector<std::uint32_t>& point_of, const std::vector<Vec3f>* positions,
                const std::vector<std::uint32_t>& corners, const std::vector<std::uint32_t>& face_source,
                std::vector<std::uint32_t>& vertex_map) {
    const std::size_t n = src.vertex_count();
    std::vector<std::uint8_t> used(n, 0);
    for (std::uint32_t c : corners) used[c] = 1;
    PointsFirstLayout layout = points_first_layout(
        used, point_of, point_of.empty() ? 0 : *std::max_element(point_of.begin(), point_of.end()) + 1);
    const std::vector<std::uint32_t>& new_point = layout.point_of_group;
    vertex_map = std::move(layout.order);
    std::vector<std::uint32_t> new_index(n, kNone);
    for (std::uint32_t i = 0; i < vertex_map.size(); ++i) new_index[vertex_map[i]] = i;

    Mesh out;
    const std::size_t m = vertex_map.size();
    out.positions.resize(m);
    out.position_ids.resize(m);
    allocate_vertex_attributes(out, src, m);
    for (std::size_t i = 0; i < m; ++i) {
        const std::uint32_t v = vertex_map[i];
        out.positions[i] = positions ? (*positions)[point_of[v]] : src.positions[v];
        out.position_ids[i] = new_point[point_of[v]];
        // A kept wedge keeps its influences (joint indices are labels, never averaged); solved attributes
        // (write_solved_attributes) overwrite normals, colours and UVs afterwards.
        copy_vertex_attributes(out, i, src, v);
        if (src.has_normals()) {
            Vec3f nn = src.normals[v];
            const float len = length(nn);
            if (len > 0.f) nn = nn * (1.f / len);
            out.normals[i] = nn;
        }
    }
    out.indices.resize(corners.size());
    for (std::size_t i = 0; i < corners.size(); ++i) out.indices[i] = new_index[corners[i]];
    if (!src.face_materials.empty()) {
        out.face_materials.resize(face_source.size());
        for (std::size_t f = 0; f < face_source.size(); ++f) out.face_materials[f] = src.face_materials[face_source[f]];
    }
    out.materials = src.materials;
    out.source_dir = src.source_dir;
    return out;
}

// Faces the simplifier starts from: not degenerate on points, and not a repeat of an earlier face's
// points (scans carry such duplicates; they would pin their points as non-manifold).
std::vector<std::uint8_t> initial_faces(const Mesh& mesh, const std::vector<std::uint32_t>& point) {
    const std::size_t nf = mesh.triangle_count();
    std::vector<std::uint8_t> keep(nf, 0);
    // Faces bucketed by their smallest point (counting sort, input order within a bucket); a face stays
    // unless an earlier face of its bucket has the same two other points.
    std::vector<std::array<std::uint32_t, 3>> sorted(nf);
    std::uint32_t points = 0;
    for (std::uint32_t p : point) points = std::max(points, p + 1);
    std::vector<std::uint32_t> begin(std::size_t(points) + 1, 0);
    for (std::size_t f = 0; f < nf; ++f) {
        std::array<std::uint32_t, 3> p{point[mesh.indices[3 * f]], point[mesh.indices[3 * f + 1]],
                                       point[mesh.indices[3 * f + 2]]};
        if (p[0] == p[1] || p[1] == p[2] || p[0] == p[2]) {
            sorted[f][0] = kNone;
            continue;
        }
        // Either winding: a face and its reverse are a zero-thickness sheet that no collapse can pass
        // (the link condition sees two surfaces); the first one stays.
        // Three compare-exchanges (std::sort of three was a call with its loops: a fifth of this function).
        if (p[1] < p[0]) std::swap(p[0], p[1]);
        if (p[2] < p[1]) std::swap(p[1], p[2]);
        if (p[1] < p[0]) std::swap(p[0], p[1]);
        sorted[f] = p;
        ++begin[p[0] + 1];
    }
    for (std::size_t p = 0; p < points; ++p) begin[p + 1] += begin[p];
    std::vector<std::uint32_t> bucket(begin.back());
    {
        std::vector<std::uint32_t> fill(begin.begin(), begin.end() - 1);
        for (std::uint32_t f = 0; f < nf; ++f)
            if (sorted[f][0] != kNone) bucket[fill[sorted[f][0]]++] = f;
    }
    auto same = [&](std::uint32_t a, std::uint32_t b) {
        return sorted[a][1] == sorted[b][1] && sorted[a][2] == sorted[b][2];
    };
    for (std::size_t p = 0; p < points; ++p) {
        const std::uint32_t b = begin[p], e = begin[p + 1];
        if (e - b <= 32) {
            for (std::uint32_t i = b; i < e; ++i) {
                bool first = true;
                for (std::uint32_t j = b; j < i && first; ++j) first = !same(bucket[j], bucket[i]);
                if (first) keep[bucket[i]] = 1;
            }
            continue;
        }
        // A point with many faces: sort its bucket by the other two points, then by face index.
        std::sort(bucket.begin() + b, bucket.begin() + e, [&](std::uint32_t x, std::uint32_t y) {
            if (sorted[x][1] != sorted[y][1]) return sorted[x][1] < sorted[y][1];
            if (sorted[x][2] != sorted[y][2]) return sorted[x][2] < sorted[y][2];
            return x < y;
        });
        for (std::uint32_t i = b; i < e; ++i)
            if (i == b || !same(bucket[i - 1], bucket[i])) keep[bucket[i]] = 1;
    }
    return keep;
}

// A triangle soup (a quarter or more of the vertices repeat an earlier one in every attribute) is run on
// its merged vertices and the result is told in the input's numbering: every copy of a removed vertex
// moves with it. Indexed meshes with a few coincident vertices (the dragon's scan cracks) keep them as
// wedges (the welding decision of docs/simplification.md).
bool soup_worth_merging(const Mesh& mesh, const SimplifyParams& params, IdenticalVertices& iv) {
    if (!params.weld || !params.extra_frames.empty() || mesh.vertex_count() == 0) return false;
    // An indexed surface has about half a vertex per triangle (a little more with seams), a soup three:
    // below three quarters the hash pass is not worth its time.
    if (4 * mesh.vertex_count() < mesh.indices.size()) return false;
    for (std::uint32_t i : mesh.indices)
        if (i >= mesh.vertex_count()) return false;  // the engine reports it
    iv = find_identical_vertices(mesh);
    return iv.duplicates * 4 >= mesh.vertex_count();
}

void to_input_numbering(SimplifyResult& r, const IdenticalVertices& iv) {
    const std::size_t n = iv.merged_of.size(), k = iv.first_of.size();
    std::vector<std::uint32_t> start(k + 1, 0), copies(n);  // merged vertex -> its input vertices (CSR)
    for (std::uint32_t m : iv.merged_of) ++start[m + 1];
    for (std::size_t i = 0; i < k; ++i) start[i + 1] += start[i];
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (std::uint32_t v = 0; v < n; ++v) copies[fill[iv.merged_of[v]]++] = v;
    std::vector<VertexMove> moves;
    moves.reserve(r.moves.size() * (n + k - 1) / k);
    for (Collapse& c : r.collapses) {
        const auto begin = static_cast<std::uint32_t>(moves.size());
        for (std::uint32_t m = c.moves_begin; m < c.moves_end; ++m) {
            const VertexMove mv = r.moves[m];
            for (std::uint32_t j = start[mv.from]; j < start[mv.from + 1]; ++j)
                moves.push_back({copies[j], iv.first_of[mv.to]});
        }
        c.moves_begin = begin;
        c.moves_end = static_cast<std::uint32_t>(moves.size());
    }
    r.moves = std::move(moves);
    for (std::uint32_t& v : r.vertex_map) v = iv.first_of[v];
    std::vector<std::uint32_t> points(n);
    for (std::uint32_t v = 0; v < n; ++v) points[v] = r.input_points[iv.merged_of[v]];
    r.input_points = std::move(points);
}

}  // namespace simplify_detail

using namespace simplify_detail;

Mesh weld_seams(const Mesh& mesh, float tolerance) {
    if (!(tolerance >= 0.f) || !std::isfinite(tolerance))
        throw Error(Error::Kind::argument, "weld_seams: tolerance must be finite and >= 0");
    std::vector<std::uint32_t> representative;
    const std::vector<std::uint32_t> point = derive_points(mesh, true, tolerance, representative);
    std::vector<Vec3f> snapped(representative.size());
    for (std::size_t i = 0; i < representative.size(); ++i) snapped[i] = mesh.positions[representative[i]];
    // Keep every vertex (unused ones too): list them all as "corners" of a pseudo face set, then restore
    // the real faces.
    std::vector<std::uint32_t> all(mesh.vertex_count());
    std::iota(all.begin(), all.end(), 0u);
    std::vector<std::uint32_t> map;
    Mesh out = build_mesh(mesh, point, &snapped, all, {}, map);
    std::vector<std::uint32_t> inverse(mesh.vertex_count());
    for (std::uint32_t i = 0; i < map.size(); ++i) inverse[map[i]] = i;
    out.indices.resize(mesh.indices.size());
    for (std::size_t i = 0; i < mesh.indices.size(); ++i) out.indices[i] = inverse[mesh.indices[i]];
    out.face_materials = mesh.face_materials;
    // build_mesh renormalises normals; welding must not change attributes.
    if (mesh.has_normals())
        for (std::uint32_t i = 0; i < map.size(); ++i) out.normals[i] = mesh.normals[map[i]];
    return out;
}

}  // namespace lodforge

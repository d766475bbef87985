// Out-of-core simplification by vertex clustering.
//
// Lindstrom, "Out-of-Core Simplification of Large Polygonal Models" (SIGGRAPH 2000): one pass over a
// triangle soup; each triangle's plane quadric is added to the cells of its three corners, triangles
// spanning three cells are kept, and every cell's representative minimises its quadric (pseudo-inverse,
// clamped into the cell; Rossignac & Borrel 1993 for the clustering itself). Attributes are the
// area-weighted mean of the corner attributes in each cell (OoCS is geometry only; the generalized
// quadric would double the per-cell state for little gain at this speed/quality point).
#include "lodforge/octree/ooc_cluster.h"

#include "lodforge/error.h"
#include "lodforge/io/mesh_validate.h"
#include "lodforge/io/temp_directory.h"
#include "lodforge/octree/octree_simplify.h"
#include "lodforge/simplify/quadric.h"

#include "octree/ooc_internal.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>

namespace lodforge {
namespace {

using Clock = std::chrono::steady_clock;

struct Cell {
    Quadric q;
    double sum[3] = {0, 0, 0};
    double count = 0;
};

}  // namespace

OocClusterResult ooc_cluster_soup(const std::string& soup_path, const OocClusterParams& params, Progress* progress,
                                  OocClusterStats* stats) {
    if (params.grid_resolution < 2 || params.grid_resolution > (std::size_t{1} << 20))
        throw Error(Error::Kind::argument, "cluster: the grid resolution must be in [2, 1048576]");
    const Clock::time_point t0 = Clock::now();
    SoupReader reader(soup_path);
    OocClusterResult r;
    r.input_triangles = reader.triangles();
    const VertexLayout L = reader.layout();
    const std::size_t floats = L.floats(), attrs = floats - 3;
    const std::size_t corner = soup_corner_bytes(L), tri = soup_triangle_bytes(L);
    const Bounds b = reader.bounds();
    const Vec3f ext = b.size();
    const double longest = std::max({ext.x, ext.y, ext.z});
    if (!(longest > 0)) throw_error(Error::Kind::invalid, soup_path, "the mesh has no extent");
    const double h = longest / static_cast<double>(params.grid_resolution) * (1 + 1e-6);
    const double origin[3] = {b.min.x, b.min.y, b.min.z};
    const float e3[3] = {ext.x, ext.y, ext.z};
    for (int a = 0; a < 3; ++a)
        r.grid_dims[a] = static_cast<std::uint32_t>(std::clamp(std::floor(e3[a] / h) + 1.0, 1.0, 1048576.0));
    r.cell_size = static_cast<float>(h);
    // Positions are quadric'd relative to the box and in units of the longest side (conditioning).
    const double inv = 1.0 / longest;
    ooc::FlatMap cell_of(1 << 16);
    std::vector<Cell> cells;
    std::vector<double> attr_sum;  // attrs per cell, area weighted
    std::vector<double> attr_weight;
    ooc::FlatMap triangles(1 << 16);
    std::vector<std::uint32_t> out_tris;
    std::vector<std::byte> buf;
    const std::uint32_t dims[3] = {r.grid_dims[0], r.grid_dims[1], r.grid_dims[2]};
    constexpr std::size_t kCache = 4096;
    std::vector<std::uint64_t> cache_code(kCache, ~0ull);
    std::vector<std::uint32_t> cache_id(kCache, 0);
    std::uint64_t done = 0;
    while (std::size_t n = reader.read(1 << 15, buf)) {
        check_progress(progress, static_cast<double>(done) / std::max<std::uint64_t>(r.input_triangles, 1), "cluster: quadrics");
        for (std::size_t t = 0; t < n; ++t) {
            const std::byte* rec = buf.data() + t * tri;
            const float* v[3];
            std::uint32_t id[3];
            Vec3d p[3];
            for (int k = 0; k < 3; ++k) {
                v[k] = reinterpret_cast<const float*>(rec + static_cast<std::size_t>(k) * corner + 4);
                std::uint64_t code = 0;
                for (int a = 0; a < 3; ++a) {
                    const double c = std::floor((v[k][a] - origin[a]) / h);
                    code = code << 21 | static_cast<std::uint64_t>(std::clamp(c, 0.0, static_cast<double>(dims[a] - 1)));
                }
                // Soup order is spatially coherent: a small direct-mapped cache in front of the table.
                const std::size_t slot = (code ^ (code >> 21) ^ (code >> 42)) & (kCache - 1);
                if (cache_code[slot] == code) {
                    id[k] = cache_id[slot];
                } else {
                    bool inserted = false;
                    id[k] = cell_of.find_or_insert(code, static_cast<std::uint32_t>(cells.size()), inserted);
                    if (inserted) {
                        cells.emplace_back();
                        attr_sum.resize(attr_sum.size() + attrs, 0.0);
                        attr_weight.push_back(0);
                    }
                    cache_code[slot] = code;
                    cache_id[slot] = id[k];
                }
                p[k] = {(v[k][0] - origin[0]) * inv, (v[k][1] - origin[1]) * inv, (v[k][2] - origin[2]) * inv};
            }
            double area = 0;
            if (const std::optional<Quadric> q = Quadric::from_triangle(p[0], p[1], p[2], area))
                for (int k = 0; k < 3; ++k) cells[id[k]].q += *q;
            const double w = area > 0 ? area : 1e-30;
            for (int k = 0; k < 3; ++k) {
                Cell& c = cells[id[k]];
                c.sum[0] += p[k].x;
                c.sum[1] += p[k].y;
                c.sum[2] += p[k].z;
                c.count += 1;
                double* s = &attr_sum[std::size_t{id[k]} * attrs];
                for (std::size_t j = 0; j < attrs; ++j) s[j] += w * v[k][3 + j];
                attr_weight[id[k]] += w;
            }
            if (id[0] == id[1] || id[1] == id[2] || id[0] == id[2]) continue;
            // One triangle per cell triple, either winding; exact key while ids fit 21 bits each.
            std::uint32_t s[3] = {id[0], id[1], id[2]};
            std::sort(s, s + 3);
            const std::uint64_t key = s[2] < (1u << 21)
                                          ? (std::uint64_t{s[0]} << 42 | std::uint64_t{s[1]} << 21 | s[2])
                                          : ooc::mix64(std::uint64_t{s[0]} << 32 | s[1]) ^ ooc::mix64(s[2] + 0x9e3779b97f4a7c15ull);
            bool inserted = false;
            triangles.find_or_insert(key & ~(std::uint64_t{1} << 63) , 0, inserted);
            if (inserted) out_tris.insert(out_tris.end(), id, id + 3);
        }
        done += n;
    }
    // Representatives, then the mesh with only the cells a kept triangle uses.
    check_progress(progress, 0.95, "cluster: representatives");
    std::vector<std::uint32_t> remap(cells.size(), ~0u);
    Mesh& m = r.mesh;
    for (std::uint32_t& i : out_tris) {
        if (remap[i] == ~0u) {
            remap[i] = static_cast<std::uint32_t>(m.positions.size());
            const Cell& c = cells[i];
            const Vec3d mean{c.sum[0] / c.count, c.sum[1] / c.count, c.sum[2] / c.count};
            // The cell in normalised units, recovered from its mean (every member lies in the cell).
            double lo[3], hi[3];
            const double mm[3] = {mean.x, mean.y, mean.z};
            for (int a = 0; a < 3; ++a) {
                const double cell = std::clamp(std::floor(mm[a] * longest / h), 0.0, static_cast<double>(dims[a] - 1));
                lo[a] = cell * h * inv;
                hi[a] = (cell + 1) * h * inv;
            }
            const Vec3d x = clamped_minimizer(c.q, mean, lo, hi);
            m.positions.push_back({static_cast<float>(x.x * longest + origin[0]), static_cast<float>(x.y * longest + origin[1]),
                                   static_cast<float>(x.z * longest + origin[2])});
            const double* s = &attr_sum[std::size_t{i} * attrs];
            const double w = attr_weight[i] > 0 ? attr_weight[i] : 1.0;
            std::size_t j = 0;
            if (L.normals) {
                Vec3f n{static_cast<float>(s[0] / w), static_cast<float>(s[1] / w), static_cast<float>(s[2] / w)};
                const float len = length(n);
                m.normals.push_back(len > 0 ? n * (1.f / len) : Vec3f{0, 0, 1});
                j += 3;
            }
            if (L.colors) {
                auto ch = [&](std::size_t k) { return static_cast<float>(std::clamp(s[j + k] / w, 0.0, 1.0)); };
                m.colors.push_back({ch(0), ch(1), ch(2), ch(3)});
                j += 4;
            }
            if (L.texcoords) {
                if (m.texcoords.empty()) m.texcoords.resize(1);
                m.texcoords[0].push_back({static_cast<float>(s[j] / w), static_cast<float>(s[j + 1] / w)});
            }
        }
        i = remap[i];
    }
    m.indices = std::move(out_tris);
    r.occupied_cells = cells.size();
    if (stats) stats->cluster_seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    check_progress(progress, 1.0, "cluster: representatives");
    return r;
}

namespace {
OocClusterResult ooc_cluster_with_scratch(const std::string& input_ply, const OocClusterParams& params,
                                          Progress* progress, OocClusterStats* stats) {
    if (params.grid_resolution < 2 || params.grid_resolution > (std::size_t{1} << 20))
        throw Error(Error::Kind::argument, "cluster: the grid resolution must be in [2, 1048576]");
    TempDirectory scratch(params.temp_dir.empty() ? std::filesystem::temp_directory_path().string() : params.temp_dir);
    const Clock::time_point t0 = Clock::now();
    SoupParams sp;
    sp.memory_bytes = params.memory_bytes;
    sp.count_edges = false;
    SoupResult soup = convert_to_soup(input_ply, scratch.file("soup"), sp, progress);
    check_extent(input_ply, soup.bounds);
    const double soup_seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    OocClusterResult r = ooc_cluster_soup(soup.path, params, progress, stats);
    r.soup = std::move(soup);
    if (stats) stats->soup_seconds = soup_seconds;
    return r;
}
}  // namespace

OocClusterResult ooc_cluster(const std::string& input_ply, const OocClusterParams& params, Progress* progress,
                             OocClusterStats* stats) {
    try {
        return ooc_cluster_with_scratch(input_ply, params, progress, stats);
    } catch (const Error& e) {
        throw without_temporary_names(e, input_ply);
    }
}

}  // namespace lodforge

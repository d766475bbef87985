// Building the prioritized marching-cube octree: leaf cubes, octree, shared vertices (the points are
// mc_points.h's, the distance field mc_field.h's).
//
// Follows Hasup Lee, "Efficient Level-of-Detail Model Generation of 3D Objects using Prioritized Marching
// Cube Octree" (doctoral thesis, KAIST, 2007, ch. 4-5):
// leaf cubes from the signed distance to the nearest input point, sign from (v - p) . n_p (after Hoppe,
// DeRose, Duchamp, McDonald, Stuetzle, "Surface Reconstruction from Unorganized Points", SIGGRAPH 1992),
// edge vertices at the crossing ratio |d_a| / (|d_a| + |d_b|), null cubes not stored, the octree built
// bottom-up with the edge-ratio extension so that every level's vertices are leaf-edge vertices. Where we
// depart from the document (one field for all cubes instead of "the nearest point inside the cube",
// direct corner evaluation instead of rules B-D) is in docs/mcoctree.md, "Decisions".
#include "lodforge/error.h"
#include "lodforge/mcoctree/mc_octree.h"
#include "mcoctree/mc_face_samples.h"
#include "mcoctree/mc_field.h"
#include "mcoctree/mc_leaf_flood.h"
#include "mcoctree/mc_octree_internal.h"
#include "mcoctree/mc_points.h"
#include "mcoctree/mc_winding.h"
#include "parallel_for.h"

#include <nanoflann.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstring>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <thread>

namespace lodforge {

std::size_t McOctree::leaf_count() const {
    return static_cast<std::size_t>(
        std::count_if(nodes.begin(), nodes.end(), [](const McNode& n) { return n.level == 0; }));
}

namespace {

using mc::Blocks;
using mc::CubeSet;
using mc::Field;
using mc::KdTree;
using mc::KeyMap;
using mc::LeafFlood;
using mc::LowestNearest;
using mc::PointCloud;
using mc::for_cubes_around;
using mc::input_name;
using mc::median_spacing;
using mc::none;
using mc::pack;
using mc::parallel_for;
using mc::points_of;
using mc::thread_count;
using mc::TmpNode;

// Wall, process CPU time (all threads) and the calling thread's CPU time per build stage, for
// McOctreeBuildResult::stages.
class StageClock {
public:
    explicit StageClock(std::vector<McBuildStage>& out) : out_(out) { reset(); }
    void mark(const char* name) {
        const auto w = std::chrono::steady_clock::now();
        const std::clock_t c = std::clock();
        const double t = thread_cpu();
        out_.push_back({name, std::chrono::duration<double>(w - wall_).count(), double(c - cpu_) / CLOCKS_PER_SEC,
                        t - thread_});
        wall_ = w, cpu_ = c, thread_ = t;
    }
    void reset() { wall_ = std::chrono::steady_clock::now(), cpu_ = std::clock(), thread_ = thread_cpu(); }

private:
    static double thread_cpu() {
        timespec ts{};
        clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
        return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
    }
    std::vector<McBuildStage>& out_;
    std::chrono::steady_clock::time_point wall_;
    std::clock_t cpu_;
    double thread_ = 0;
};

}  // namespace

McOctreeBuildResult build_mc_octree(const Mesh& input, const McOctreeParams& params, Progress* progress) {
    check_progress(progress, 0, "mcoctree: points");
    if (!(params.band >= 0) || !std::isfinite(params.band))
        throw_error(Error::Kind::argument, input_name, "band must be 0 (unlimited) or a positive number");
    if (!(params.cube_size >= 0) || !std::isfinite(params.cube_size))
        throw_error(Error::Kind::argument, input_name, "cube size must be a positive number");
    if (params.cube_size == 0 && params.resolution == 0)
        throw_error(Error::Kind::argument, input_name, "resolution must be at least 1");
    std::size_t skipped = 0;
    const unsigned threads = thread_count(params.threads);
    std::vector<Vec3f> unit_normals;
    std::vector<std::uint32_t> point_ids;
    PointCloud pc = points_of(input, skipped, threads, unit_normals, point_ids);
    Bounds bounds;
    for (const Vec3f& p : pc.points) bounds.add(p);
    const Vec3f ext = bounds.size();
    const double longest = std::max({double(ext.x), double(ext.y), double(ext.z)});
    // Coordinates whose extent overflows float (read_mesh's validation refuses them; this guards other
    // callers): the cube count below would be NaN, and casting it was a wild grid size and a crash.
    if (!std::isfinite(longest) || !std::isfinite(bounds.diagonal()))
        throw_error(Error::Kind::invalid, input_name, "coordinates too large: the points' extent overflows float");
    double h = params.cube_size > 0 ? params.cube_size : longest / double(params.resolution);
    if (!(h > 0)) {
        if (params.cube_size > 0) h = params.cube_size;
        else throw_error(Error::Kind::invalid, input_name, "all points coincide: give --cube-size");
    }
    const int pad = static_cast<int>(std::ceil(params.band > 0 ? params.band : 2.0)) + 1;
    std::uint32_t dims = 0;
    for (int a = 0; a < 3; ++a) {
        const double cubes = std::ceil(double(ext[a]) / h) + 2.0 * pad;
        if (cubes > 65536.0)
            throw_error(Error::Kind::argument, input_name,
                        "resolution too high: " + std::to_string(static_cast<long long>(cubes)) +
                            " cubes along an axis (at most 65536)");
        dims = std::max(dims, static_cast<std::uint32_t>(cubes));
    }
    const std::uint32_t grid = std::max<std::uint32_t>(2, std::bit_ceil(dims));
    const auto levels = static_cast<std::uint32_t>(std::countr_zero(grid));

    McOctreeBuildResult result;
    McOctree& tree = result.tree;
    StageClock clock(result.stages);
    tree.cube_size = static_cast<float>(h);
    tree.levels = levels;
    tree.input_points = pc.points.size();
    mc::WindingTree winding;  // for a low-poly mesh's sign (below)
    if (!input.indices.empty() && mc::has_long_face(input, static_cast<float>(2 * h))) {
        // Faces longer than two cubes get points a cube apart (docs/mcoctree.md D1, "Faces larger than a
        // cube"). The scans' faces are shorter at the resolutions their density allows, and there the
        // vertices alone do as well: the dragon at 256 gets 9,932 samples, at 512 (beyond its density)
        // 439,142, which with the pseudo-normals below halve its mean error for about 0.8 s.
        mc::FaceSampleParams sp;
        sp.min_edge = static_cast<float>(2 * h);
        sp.spacing = static_cast<float>(h);
        sp.max_samples = std::size_t(1) << 25;  // 32 M points: about 2 GB for the points and the field
        // The vertices' pseudo-normals (below) are made beside the samples: both only read the mesh.
        mc::FaceSamples fs;
        std::vector<Vec3f> pseudo;
        detail::run_beside(
            threads, [&] { fs = mc::sample_large_faces(input, unit_normals, point_ids, sp); },
            [&] { pseudo = mc::vertex_pseudo_normals(input, point_ids); });
        result.face_samples = fs.points.size();
        result.sampled_faces = fs.faces;
        pc.points.insert(pc.points.end(), fs.points.begin(), fs.points.end());
        if (!fs.points.empty()) {
            // With samples the vertices must tell their side as exactly as the samples: their pseudo-normals
            // (Spot's control cage: a sheet to the grid's edge with the area-weighted ones, Hausdorff 0.92
            // of the diagonal, 0.041 with these). Their old normals stay for shading. Without samples (the
            // scans' faces are short) nothing changes.
            pc.shading = pc.normals;
            pc.shading.insert(pc.shading.end(), fs.shading.begin(), fs.shading.end());
            // Every vertex, not only the long faces' corners: the horse's sharp parts are short faces, and
            // with pseudo-normals at the long faces' corners alone its surface still ran to the grid's edge
            // at 64 and 128 (Hausdorff 4.4 and 2.6 % of the diagonal against 1.3 and 0.95).
            std::size_t k = 0;  // pc's vertex points are the first vertices of their positions, in order, less the skipped
            for (std::size_t i = 0; i < input.positions.size(); ++i) {
                if (point_ids[i] != i || unit_normals[i] == Vec3f{}) continue;
                if (!(pseudo[i] == Vec3f{})) pc.normals[k] = pseudo[i];
                ++k;
            }
        }
        pc.normals.insert(pc.normals.end(), fs.normals.begin(), fs.normals.end());
        pc.colors.insert(pc.colors.end(), fs.colors.begin(), fs.colors.end());
        // A mesh that is mostly its samples (a low-poly model) is signed by its winding number: folds, slivers
        // and ridges thinner than a cube fool the nearest point's normal there (the Duck's bill, Spot's cage).
        // Not an open sheet, where the winding number never passes 1/2 (frag_115 at 512 went from 0.35 to
        // 4.9 % of the diagonal); nor a scan with some long faces: over 871 K faces it would cost seconds.
        if (fs.points.size() > tree.input_points && input.triangle_count() <= 200000 && mc::openness(input) < 0.1)
            winding = mc::build_winding_tree(input);
        for (const Vec3f& p : fs.points) pc.coords.push_back({p.x, p.y, p.z});
    }
    tree.origin = bounds.min - Vec3f{1, 1, 1} * static_cast<float>(pad * h);

    // Built once, below (nanoflann's constructor builds the index too unless told not to: main built it twice).
    // Leaves of 32 points: the closing's coarse samples, 1-8 cube sizes from the surface, are answered about
    // 5 % faster than with 16 and the tree is built 10 % faster; the flood's queries take as long (8, 4, 64
    // and 128 are slower; docs/mcoctree.md, "Build"). The values do not depend on it (D1).
    KdTree kd(3, pc, nanoflann::KDTreeSingleIndexAdaptorParams(32, nanoflann::KDTreeSingleIndexAdaptorFlags::SkipInitialBuildIndex));
    Field field(pc, kd, tree.origin, static_cast<float>(h), grid, threads);
    if (!winding.nodes.empty()) field.sign_by_winding(&winding);
    const float cap = params.band > 0 ? static_cast<float>(params.band * h) : INFINITY;

    // The kd-tree is built on a second thread while this one finds the seed cubes and scatters the field
    // near the points (D1); an exception there (bad_alloc) is rethrown here once both have ended.
    auto build_kd = [&] {
        kd.buildIndex();
        result.point_spacing = median_spacing(pc, kd);
    };
    // Leaf cubes: flood along the surface from the cubes holding points, across every face the surface
    // crosses, so no crossing face of a kept cube leads to an unexamined one (that would be a hole).
    LeafFlood flood(field, grid, cap, threads, progress, pc.points.size() * 2);
    bool scattering = false;
    auto seeds_and_scatter = [&] {
        flood.seed(pc.points, tree.origin, h);
        // The field's blocks number about a quarter to a half of the seeds on the scans (dragon, frag_115 at
        // 64-512): room for half of them at once saves the copies and page faults of growing 1.3 KB per block
        // (only what is written becomes resident).
        field.reserve_blocks(flood.frontier.size() / 2 + 4096);
        // Scattering costs per point and per lattice point within the radius, a query per lattice point:
        // within 2 cube sizes (nearly every value the flood asks for) where there are at most 2 points per
        // cube holding points, within 1 (about 60 % of them, in the kd-tree's build time) up to 8.
        const double per_cube = double(pc.points.size()) / double(flood.frontier.size());
        float radius = per_cube <= 2 ? 2.f : per_cube <= 8 ? 1.f : 0.f;
        if (params.field != McFieldMethod::automatic) radius = params.field == McFieldMethod::scatter ? 2.f : 0.f;
        scattering = radius > 0;
        if (scattering) field.scatter(radius, threads);
    };
    detail::run_beside(threads, seeds_and_scatter, build_kd);
    check_progress(progress, 0.05, "mcoctree: distance field");
    const bool density_warned = result.point_spacing > h;
    if (density_warned) {
        char buf[256];
        std::snprintf(buf, sizeof buf,
                      "the cube size %.4g is below the typical point spacing %.4g: the resolution exceeds the data "
                      "density, expect holes and bumps (a resolution near %zu or lower fits the data)",
                      h, result.point_spacing,
                      static_cast<std::size_t>(std::max(1.0, std::floor(longest / result.point_spacing))));
        tree.warnings.push_back(buf);
    }
    if (skipped > 0)
        tree.warnings.push_back(std::to_string(skipped) + " of " + std::to_string(input.positions.size()) +
                                " points have no usable normal (zero, no face uses them, or their faces cancel: the "
                                "same triangle with both windings, or folded back) and were skipped");
    clock.mark(scattering ? "points, kd-tree + scatter" : "points, kd-tree");
    std::vector<std::uint64_t> corner_keys;
    flood.run();
    clock.mark("flood");
    if (flood.leaves.empty())
        throw_error(Error::Kind::invalid, input_name,
                    "no surface: the signed distance never changes sign at cube size " + std::to_string(h) +
                        " (a part thinner than a cube has no inside lattice point: try a finer --resolution or "
                        "--cube-size)");

    // Closing the coarse levels before building anything (D2): a node's samples are the field at lattice
    // points, whichever of its children exist, so the coarse crossings are known from the set of nodes
    // alone. Each new leaf adds its missing ancestors; each new ancestor's crossings descend (D5) to leaf
    // edges whose four cubes must be examined; the flood from those may add leaves, and so on. Only the new
    // nodes of a round are looked at, so the octree and its vertices are then built once.
    // present[l]: the coarse nodes of level l so far, each with the index of its sample mask in
    // coarse_inside (the octree below takes the masks from there instead of assembling them again).
    std::vector<KeyMap> present;
    std::vector<std::uint32_t> coarse_inside;
    {
        const auto& subs = mc::sub_edges();
        present.reserve(levels + 1);
        for (std::uint32_t l = 0; l <= levels; ++l) present.emplace_back(l == 0 ? 16 : flood.leaves.size() >> (2 * l));
        std::vector<std::pair<std::uint32_t, std::uint64_t>> fresh;  // new coarse nodes: (level, packed x, y, z)
        std::vector<std::uint32_t> fresh_inside;  // their sample masks
        std::vector<std::uint8_t> fresh_edges;    // their crossings' leaf edges found in parallel (255: none)
        std::vector<std::uint64_t> sample_keys;
        auto coarse_sample = [](std::uint32_t l, std::uint64_t node, int s) {
            const std::uint32_t half = 1u << (l - 1);
            const auto x = std::uint32_t(node & mc::max_lattice), y = std::uint32_t((node >> 17) & mc::max_lattice),
                       z = std::uint32_t((node >> 34) & mc::max_lattice);
            return pack((x << l) + std::uint32_t(s % 3) * half, (y << l) + std::uint32_t((s / 3) % 3) * half,
                        (z << l) + std::uint32_t(s / 9) * half);
        };
        std::size_t seen = 0;
        while (seen < flood.leaves.size()) {
            fresh.clear();
            sample_keys.clear();
            for (; seen < flood.leaves.size(); ++seen) {
                const TmpNode& leaf = flood.leaves[seen];
                for (std::uint32_t l = 1; l <= levels; ++l) {
                    const std::uint64_t key = pack(leaf.x >> l, leaf.y >> l, leaf.z >> l);
                    if (present[l].find(key) != none) break;
                    present[l].insert(key, static_cast<std::uint32_t>(coarse_inside.size() + fresh.size()));
                    fresh.emplace_back(l, key);
                    for (int sm = 0; sm < 27; ++sm)
                        if (sm != 13) sample_keys.push_back(coarse_sample(l, key, sm));
                }
            }
            field.evaluate(sample_keys);  // in parallel; the descents below mostly find known values
            // Each fresh node's mask, and the leaf edge of each of its crossings (the descent of D5), on
            // every thread from the values known now; a node whose descent meets a value not evaluated yet
            // is left to the serial pass below, which also adds the cubes around the leaf edges to the flood
            // in node order.
            fresh_inside.resize(fresh.size());
            fresh_edges.assign(fresh.size(), 0);
            // One contiguous range of fresh nodes per thread (one range when there are few), each with its
            // own list of leaf edges, read back in node order below.
            const std::size_t ranges = fresh.size() < 1024 ? 1 : std::max(1u, threads);
            auto range_begin = [&](std::size_t r) { return r * fresh.size() / ranges; };
            std::vector<std::vector<std::uint64_t>> edges_of_range(ranges);
            constexpr std::uint8_t serial = 255;
            auto descend = [&](std::uint32_t l, std::uint64_t key, const mc::SubEdge& se, bool a_inside,
                               auto&& inside_at) -> std::uint64_t {
                std::uint64_t a = coarse_sample(l, key, se.a);
                for (std::uint32_t k = se.length == 2 ? l : l - 1; k > 0; --k) {
                    const std::uint64_t mid = a + (std::uint64_t(1u << (k - 1)) << (17 * se.axis));
                    const int in = inside_at(mid);
                    if (in < 0) return none;
                    if (bool(in) == a_inside) a = mid;
                }
                return a;
            };
            detail::parallel_for(ranges, unsigned(ranges), 1, [&](std::size_t first_range, std::size_t end_range) {
                for (std::size_t range = first_range; range < end_range; ++range) {
                    std::vector<std::uint64_t>& out = edges_of_range[range];
                    std::vector<Blocks::Cached> cache(Blocks::cache_size), visited_cache(Blocks::cache_size);
                    auto peek = [&](std::uint64_t k) { return field.peek_inside(k, cache.data()); };
                    for (std::size_t i = range_begin(range), e = range_begin(range + 1); i < e; ++i) {
                        const auto [l, key] = fresh[i];
                        std::uint32_t inside = 0;
                        bool known = true;
                        for (int sm = 0; sm < 27 && known; ++sm) {
                            if (sm == 13) continue;
                            const int in = peek(coarse_sample(l, key, sm));
                            known = in >= 0;
                            if (in > 0) inside |= 1u << sm;
                        }
                        const std::size_t start = out.size();
                        for (int se_i = 0; se_i < mc::sub_edge_count && known; ++se_i) {
                            const mc::SubEdge& se = subs[se_i];
                            const bool a_inside = (inside >> se.a) & 1u;
                            if (a_inside == bool((inside >> se.b) & 1u)) continue;
                            const std::uint64_t a = descend(l, key, se, a_inside, peek);
                            known = a != none;
                            // A leaf edge whose four cubes were all examined before this round adds
                            // nothing to the flood: left out here, so the serial pass below skips it.
                            bool examined = known;
                            if (examined)
                                for_cubes_around(a, se.axis, [&](std::uint64_t cube) {
                                    examined = examined && flood.visited.contains(cube, visited_cache.data());
                                });
                            if (known && !examined) out.push_back(a | std::uint64_t(se.axis) << 51);
                        }
                        fresh_inside[i] = inside;
                        if (known) {
                            fresh_edges[i] = static_cast<std::uint8_t>(out.size() - start);
                        } else {
                            out.resize(start);
                            fresh_edges[i] = serial;
                        }
                    }
                }
            });
            flood.frontier.clear();
            auto flood_around = [&](std::uint64_t a, int axis) {
                for_cubes_around(a, axis, [&](std::uint64_t cube) {
                    flood.add(cube);
                });
            };
            for (std::size_t range = 0; range < ranges; ++range) {
                const std::vector<std::uint64_t>& edges = edges_of_range[range];
                std::size_t at = 0;
                for (std::size_t i = range_begin(range), e = range_begin(range + 1); i < e; ++i) {
                    const auto [l, key] = fresh[i];
                    if (fresh_edges[i] != serial) {
                        coarse_inside.push_back(fresh_inside[i]);
                        for (const std::size_t stop = at + fresh_edges[i]; at < stop; ++at)
                            flood_around(edges[at] & ((std::uint64_t(1) << 51) - 1), int(edges[at] >> 51));
                        continue;
                    }
                    std::uint32_t inside = 0;  // as above, evaluating what is missing
                    for (int sm = 0; sm < 27; ++sm)
                        if (sm != 13 && field.inside(coarse_sample(l, key, sm))) inside |= 1u << sm;
                    coarse_inside.push_back(inside);
                    for (int se_i = 0; se_i < mc::sub_edge_count; ++se_i) {
                        const mc::SubEdge& se = subs[se_i];
                        const bool a_inside = (inside >> se.a) & 1u;
                        if (a_inside == bool((inside >> se.b) & 1u)) continue;
                        flood_around(descend(l, key, se, a_inside, [&](std::uint64_t k) { return int(field.inside(k)); }),
                                     se.axis);
                    }
                }
            }
            flood.run();
        }
    }

    clock.mark("closing");
    // The other sign of a resolution above the data density: more surface cubes than points, so most
    // cubes get their corner values from points outside them (the spacing test above misses it where the
    // sampling is uneven, e.g. the dragon at 512). Not for a mesh that is mostly its face samples (more
    // samples than vertices: a low-poly model): there the faces are the data, sampled a cube apart, and
    // cubes outnumber points by the sampling's spacing (Spot's control cage at 64, 188 vertices and 15,782
    // samples for 24,829 cubes, was warned about). A scan with a few long faces is still judged by its
    // vertices (the bunny at 100).
    if (flood.leaves.size() > tree.input_points && !density_warned && result.face_samples <= tree.input_points) {
        char buf[256];
        std::snprintf(buf, sizeof buf,
                      "%zu surface cubes for %zu points: the resolution exceeds the data density, expect holes and "
                      "bumps (a resolution near %zu or lower fits the data)",
                      flood.leaves.size(), tree.input_points,
                      static_cast<std::size_t>(std::max(1.0, std::floor(longest / h * std::sqrt(double(tree.input_points) /
                                                                                                 double(flood.leaves.size()))))));
        tree.warnings.push_back(buf);
    }
    // An open input: the zero set runs on past the input's border (an open scan, or a hole too wide for
    // the field to bridge) until the grid's boundary, which counts as outside (D2), closes it there, far
    // from any point. Nothing is wrong with the tree, but a user sees a skirt or sheet that is not in the
    // input: say where, and what ends the surface near the border instead.
    if (params.band == 0) {
        std::uint32_t sides = 0;  // bit 2 * axis + (1 for the high side)
        for (const TmpNode& leaf : flood.leaves) {
            const std::uint32_t c[3] = {leaf.x, leaf.y, leaf.z};
            for (int a = 0; a < 3; ++a) {
                if (c[a] == 0) sides |= 1u << (2 * a);
                if (c[a] + 1 >= grid) sides |= 2u << (2 * a);
            }
        }
        if (sides) {
            std::string where;
            for (int f = 0; f < 6; ++f)
                if (sides & (1u << f)) where += std::string(where.empty() ? "" : ", ") + (f & 1 ? "+" : "-") + "xyz"[f / 2];
            result.reaches_grid_edge = true;
            tree.warnings.push_back("the surface runs to the grid's edge (" + where +
                                    "): the input is open there (an open scan, or a hole too wide to bridge), and the "
                                    "surface is closed along the grid's boundary, far from the input; a band (--band "
                                    "2.5) ends it near the input's border instead");
        }
    }

    // The octree and its vertices. The closing above makes the first pass the only one; the check at the
    // end of a pass stays as a safety net (it rebuilds only if a required leaf cube was never examined).
    std::vector<std::vector<TmpNode>> lv;
    std::vector<std::size_t> offset;
    std::size_t node_count = 0;
    std::vector<KeyMap> maps;
    const bool colors = !pc.colors.empty();
    std::vector<std::uint64_t> vertex_edge;  // leaf edge of each vertex: lattice key | axis << 51
    // Same-level neighbours (faces and edges) for the seams: they depend on the octree only, and are
    // made on a second thread while this one numbers the vertices. Top-down, from the parents'
    // neighbours: the cube next to a child across a face or edge is a sibling or a child of the parent's
    // neighbour in the directions that leave the parent (a face or an edge slot too), so no look-up in the
    // level maps is needed. Made per parent: its 18 neighbours' child masks are read once for all its
    // children (instead of once per child and slot), and a table of (child octant, slot) → (parent-level
    // direction, target octant) replaces the per-slot coordinate arithmetic. A target outside the grid
    // needs no test: the parent's neighbour in that direction is outside too, so it is `none` (by induction
    // from the root, whose row is all `none`). Each level reads only its parents' rows, so it could split
    // over threads; measured no faster than beside the numbering (docs/mcoctree.md, "Build").
    auto build_neighbours = [&] {
        constexpr int ns = mc::neighbour_slots;
        tree.neighbours.assign(node_count * ns, none);
        int slot_of[27];
        for (int& v : slot_of) v = -1;
        for (int sl = 0; sl < ns; ++sl) {
            const auto o = mc::neighbour_offset(sl);
            slot_of[(o[0] + 1) + 3 * (o[1] + 1) + 9 * (o[2] + 1)] = sl;
        }
        struct Step {
            std::uint8_t dir, octant;  // dir: the parent-level cube, (dx + 1) + 3 (dy + 1) + 9 (dz + 1); 13 = the parent
        };
        std::array<std::array<Step, ns>, 8> step{};
        for (int oc = 0; oc < 8; ++oc)
            for (int sl = 0; sl < ns; ++sl) {
                const auto o = mc::neighbour_offset(sl);
                int dir = 0, octant = 0;
                for (int a = 0, scale = 1; a < 3; ++a, scale *= 3) {
                    const int c = ((oc >> a) & 1) + o[a];  // -1..2 in the parent's child coordinates
                    dir += (c < 0 ? 0 : c < 2 ? 1 : 2) * scale;
                    octant |= (c & 1) << a;  // -1 & 1 = 1: the far child of the lower neighbour
                }
                step[std::size_t(oc)][std::size_t(sl)] = {static_cast<std::uint8_t>(dir), static_cast<std::uint8_t>(octant)};
            }
        static constexpr std::array<std::uint8_t, 256> below = [] {
            std::array<std::uint8_t, 256> t{};
            for (unsigned m = 0; m < 256; ++m) t[m] = static_cast<std::uint8_t>((m & 1) + t[m >> 1]);
            return t;
        }();
        auto rows_of_children = [&](std::size_t b, std::size_t e) {
            std::uint8_t mask[27];
            std::uint32_t first[27];
            for (std::size_t pi = b; pi < e; ++pi) {
                const McNode& p = tree.nodes[pi];
                const std::uint32_t* pnb = &tree.neighbours[pi * ns];
                for (int d = 0; d < 27; ++d) {
                    const std::uint32_t q = d == 13 ? std::uint32_t(pi) : slot_of[d] < 0 ? none : pnb[slot_of[d]];
                    mask[d] = q == none ? 0 : tree.nodes[q].child_mask;
                    first[d] = q == none ? 0 : tree.nodes[q].first_child;
                }
                for (std::uint32_t m = p.child_mask, ci = p.first_child; m; m &= m - 1, ++ci) {
                    const auto& st = step[std::size_t(std::countr_zero(m))];
                    std::uint32_t* row = &tree.neighbours[std::size_t(ci) * ns];
                    for (int sl = 0; sl < ns; ++sl) {
                        const unsigned d = st[std::size_t(sl)].dir, o = st[std::size_t(sl)].octant;
                        if ((mask[d] >> o) & 1u) row[sl] = first[d] + below[mask[d] & ((1u << o) - 1u)];
                    }
                }
            }
        };
        for (std::uint32_t l = levels; l >= 1; --l)  // parents of level l - 1, coarsest first
            rows_of_children(offset[l], offset[l] + lv[l].size());
    };
    for (int pass = 0;; ++pass) {
        tree.nodes.clear();
        tree.vertex_ids.clear();
        tree.positions.clear();
        tree.normals.clear();
        tree.colors.clear();
        vertex_edge.clear();
        result.leaf_cubes = flood.leaves.size();

        // Levels bottom-up: each level sorted by Morton code, so a node's children are contiguous.
        check_progress(progress, 0.5, "mcoctree: octree");
        lv.assign(levels + 1, {});
        lv[0] = flood.leaves;
        std::sort(lv[0].begin(), lv[0].end(), [](const TmpNode& a, const TmpNode& b) { return a.code < b.code; });
        for (std::uint32_t l = 1; l <= levels; ++l) {
            for (const TmpNode& c : lv[l - 1]) {
                const std::uint64_t code = c.code >> 3;
                if (lv[l].empty() || lv[l].back().code != code) lv[l].push_back({code, c.x >> 1, c.y >> 1, c.z >> 1, 0});
            }
        }
        offset.assign(levels + 2, 0);
        for (std::uint32_t l = levels + 1; l-- > 0;) offset[l] = (l == levels ? 0 : offset[l + 1] + lv[l + 1].size());
        node_count = offset[0] + lv[0].size();
        tree.nodes.resize(node_count);
        for (std::uint32_t l = 0; l <= levels; ++l) {
            std::size_t child = 0;
            for (std::size_t i = 0; i < lv[l].size(); ++i) {
                McNode& n = tree.nodes[offset[l] + i];
                n.x = lv[l][i].x, n.y = lv[l][i].y, n.z = lv[l][i].z;
                n.level = static_cast<std::uint8_t>(l);
                if (l == 0)
                    for (int c = 0; c < 8; ++c)
                        if (lv[0][i].corners & (1u << c)) n.inside |= 1u << mc::corner_sample(c);
                if (l == 0) continue;
                n.first_child = static_cast<std::uint32_t>(offset[l - 1] + child);
                while (child < lv[l - 1].size() && (lv[l - 1][child].code >> 3) == lv[l][i].code) {
                    n.child_mask = static_cast<std::uint8_t>(n.child_mask | (1u << (lv[l - 1][child].code & 7)));
                    tree.nodes[offset[l - 1] + child].parent = static_cast<std::uint32_t>(offset[l] + i);
                    ++child;
                }
            }
        }

        // Each level's nodes by position, for the priority numbering's corner neighbours only (D7), so they
        // are made on this thread after the vertex numbering below, while the neighbour table still runs
        // beside it, instead of here in the serial octree stage.
        auto build_maps = [&] {
            maps.clear();
            maps.reserve(levels + 1);
            for (std::uint32_t l = 0; l <= levels; ++l) {
                maps.emplace_back(lv[l].size());
                for (std::size_t ni = offset[l], e = offset[l] + lv[l].size(); ni < e; ++ni)
                    maps[l].insert(pack(tree.nodes[ni].x, tree.nodes[ni].y, tree.nodes[ni].z), static_cast<std::uint32_t>(ni));
            }
        };

        // Samples of every node (corners of leaves; the 3x3x3 lattice of internal nodes, body centre aside).
        auto sample_key = [&](const McNode& n, int s) {
            const int i = s % 3, j = (s / 3) % 3, k = s / 9;
            if (n.level == 0) return pack(n.x + std::uint32_t(i / 2), n.y + std::uint32_t(j / 2), n.z + std::uint32_t(k / 2));
            const std::uint32_t half = 1u << (n.level - 1);
            return pack((n.x << n.level) + std::uint32_t(i) * half, (n.y << n.level) + std::uint32_t(j) * half,
                        (n.z << n.level) + std::uint32_t(k) * half);
        };
        // Every sample of an internal node is a corner of one of its children (a sample in the middle of an
        // axis is the upper corner of the lower child and the lower corner of the upper one), so the masks are
        // assembled bottom-up from the children's corners; only samples no existing child has are evaluated.
        struct Source {
            std::uint8_t octant, corner;
        };
        std::array<std::vector<Source>, 27> sources;
        for (int sm = 0; sm < 27; ++sm) {
            const int c3[3] = {sm % 3, (sm / 3) % 3, sm / 9};
            for (int o = 0; o < 8; ++o) {
                int corner = 0;
                bool ok = true;
                for (int a = 0; a < 3; ++a) {
                    const int half = (o >> a) & 1, rel = c3[a] - half;  // position inside the child, 0 or 1
                    if (rel < 0 || rel > 1) ok = false;
                    else corner |= rel << a;
                }
                if (ok) sources[std::size_t(sm)].push_back({static_cast<std::uint8_t>(o), static_cast<std::uint8_t>(corner)});
            }
        }
        std::array<std::uint8_t, 256> below{};  // popcount of the child-mask bits below an octant
        for (int m = 0; m < 256; ++m) below[std::size_t(m)] = static_cast<std::uint8_t>(std::popcount(unsigned(m)));
        std::vector<std::pair<std::uint32_t, int>> missing;
        for (std::uint32_t l = 1; l <= levels; ++l) {
            check_progress(progress, 0.55 + 0.1 * double(l) / double(levels), "mcoctree: octree");
            missing.clear();
            corner_keys.clear();
            for (std::size_t i = 0; i < lv[l].size(); ++i) {
                const auto ni = static_cast<std::uint32_t>(offset[l] + i);
                McNode& n = tree.nodes[ni];
                const std::uint32_t closed = present.empty() ? none : present[l].find(pack(n.x, n.y, n.z));
                if (closed != none) {  // every node but those of a safety-net pass (below)
                    n.inside = coarse_inside[closed];
                    continue;
                }
                for (int sm = 0; sm < 27; ++sm) {
                    if (sm == 13) continue;
                    bool found = false;
                    for (const Source& src : sources[std::size_t(sm)]) {
                        if (!(n.child_mask & (1u << src.octant))) continue;
                        const McNode& ch = tree.nodes[n.first_child + below[n.child_mask & ((1u << src.octant) - 1)]];
                        if ((ch.inside >> mc::corner_sample(src.corner)) & 1u) n.inside |= 1u << sm;
                        found = true;
                        break;
                    }
                    if (!found) {
                        missing.emplace_back(ni, sm);
                        corner_keys.push_back(sample_key(n, sm));
                    }
                }
            }
            field.evaluate(corner_keys);
            for (const auto& [ni, sm] : missing)
                if (field.inside(sample_key(tree.nodes[ni], sm))) tree.nodes[ni].inside |= 1u << sm;
        }
        std::vector<KeyMap>().swap(present);  // used once: the peak memory comes later
        std::vector<std::uint32_t>().swap(coarse_inside);

        // Vertices: the crossing of an edge at any level is the crossing of the one leaf edge the recursive
        // edge-ratio extension lands on, so all levels share vertices by index.
        clock.mark("octree, samples");
        check_progress(progress, 0.65, "mcoctree: vertices");
        const auto& subs = mc::sub_edges();
        constexpr std::uint64_t key_bits = (std::uint64_t(1) << 51) - 1, unknown = ~std::uint64_t(0);
        // Each node's crossings (both threads); its slots in vertex_ids follow from the last node to the first.
        parallel_for(node_count, threads, [&](std::size_t b, std::size_t e) {
            for (std::size_t ni = b; ni < e; ++ni) {
                McNode& n = tree.nodes[ni];
                const int count = n.level == 0 ? mc::full_edges : mc::sub_edge_count;
                std::uint64_t crossings = 0;
                for (int se = 0; se < count; ++se)
                    if (((n.inside >> subs[se].a) & 1u) != ((n.inside >> subs[se].b) & 1u)) crossings |= std::uint64_t(1) << se;
                n.crossings = crossings;
            }
        });
        std::size_t slots = 0;
        for (std::size_t ni = node_count; ni-- > 0;) {
            tree.nodes[ni].first_vertex = static_cast<std::uint32_t>(slots);
            slots += std::size_t(std::popcount(tree.nodes[ni].crossings));
        }
        // The leaf edge of each crossing, by the edge-ratio extension's descent (both threads, reading the
        // field only; a value not evaluated yet leaves the slot to the serial pass).
        std::vector<std::uint64_t> slot_edge(slots);
        std::vector<std::size_t> memo_of(slots);  // each slot's leaf-edge memo (Field::npos: find it serially)
        field.clear_leaf_edge_vertices(threads);
        auto descend = [&](const McNode& n, const mc::SubEdge& se, auto&& inside_at) -> std::uint64_t {
            std::uint64_t a = sample_key(n, se.a);
            const int a_inside = inside_at(a);
            if (a_inside < 0) return unknown;
            for (std::uint32_t l = n.level == 0 ? 0 : (se.length == 2 ? n.level : n.level - 1u); l > 0; --l) {
                const std::uint64_t mid = a + (std::uint64_t(1u << (l - 1)) << (17 * se.axis));
                const int in = inside_at(mid);
                if (in < 0) return unknown;
                if (in == a_inside) a = mid;  // the crossing is in the upper half
            }
            return a | std::uint64_t(se.axis) << 51;
        };
        parallel_for(node_count, threads, [&](std::size_t b, std::size_t e) {
            std::vector<Blocks::Cached> cache(Blocks::cache_size);
            auto peek = [&](std::uint64_t k) { return field.peek_inside(k, cache.data()); };
            for (std::size_t ni = b; ni < e; ++ni) {
                const McNode& n = tree.nodes[ni];
                for (std::uint64_t c = n.crossings, sl = n.first_vertex; c; c &= c - 1, ++sl) {
                    const std::uint64_t ek = descend(n, subs[std::size_t(std::countr_zero(c))], peek);
                    slot_edge[sl] = ek;
                    memo_of[sl] = ek == unknown ? Field::npos : field.peek_leaf_edge_slot(ek & key_bits, int(ek >> 51), cache.data());
                }
            }
        });
        // Vertex ids in the order the leaves (Morton order), then the coarser nodes, first use them, so an
        // extraction reads vertex data nearly sequentially (serial: the leaf-edge memo is shared; the
        // neighbour table is made beside it).
        detail::run_beside(threads, [&] {
            tree.vertex_ids.assign(slots, none);
            auto number = [&](std::size_t ni) {
                const McNode& n = tree.nodes[ni];
                std::size_t sl = n.first_vertex;
                for (std::uint64_t c = n.crossings; c; c &= c - 1, ++sl) {
                    std::uint64_t ek = slot_edge[sl];
                    if (ek == unknown)
                        slot_edge[sl] = ek = descend(n, subs[std::size_t(std::countr_zero(c))],
                                                     [&](std::uint64_t k) { return int(field.inside(k)); });
                    std::size_t memo = memo_of[sl];
                    if (memo == Field::npos) memo = field.leaf_edge_slot(ek & key_bits, int(ek >> 51));
                    std::uint32_t& v = field.leaf_edge_vertex_at(memo);
                    if (v == none) {
                        v = static_cast<std::uint32_t>(vertex_edge.size());
                        vertex_edge.push_back(ek);
                    }
                    tree.vertex_ids[sl] = v;
                }
            };
            for (std::size_t ni = offset[0]; ni < node_count; ++ni) number(ni);
            for (std::size_t ni = 0; ni < offset[0]; ++ni) number(ni);
            build_maps();  // after the numbering: the neighbour table beside it takes longer
        }, build_neighbours);
        // The stage's parallel loops do not report; a cancel is seen here, between them.
        check_progress(progress, 0.72, "mcoctree: vertices");
        // Position, normal and colour of each vertex (both threads; a value not evaluated yet, serially).
        const std::size_t vcount = vertex_edge.size();
        tree.positions.resize(vcount);
        tree.normals.resize(vcount);
        if (colors) tree.colors.resize(vcount);
        auto make_vertex = [&](std::size_t v, std::uint32_t ia, std::uint32_t ib) {
            const std::uint64_t a_key = vertex_edge[v] & key_bits;
            const int axis = int(vertex_edge[v] >> 51);
            const float da = std::fabs(field.dist(ia)), db = std::fabs(field.dist(ib));
            // Strictly inside the edge (D3): a lattice point on the surface (value 0) would otherwise hold
            // the vertices of all its crossing edges at one position, and their triangles have zero area.
            // |d| is a distance to a point, so a clamp of 1/1024 moves a vertex only where a lattice point
            // lies within about h/1000 of an input point (cubically rare: none on the scans).
            constexpr float min_t = 1.f / 1024;
            const float t = da + db > 0 ? std::clamp(da / (da + db), min_t, 1 - min_t) : 0.5f;
            Vec3f p = field.world(a_key);
            if (axis == 0) p.x += t * float(h);
            else if (axis == 1) p.y += t * float(h);
            else p.z += t * float(h);
            const std::uint32_t pa = field.nearest(ia), pb = field.nearest(ib);
            const std::vector<Vec3f>& shade = pc.shading.empty() ? pc.normals : pc.shading;
            Vec3f nrm = shade[pa] * (1 - t) + shade[pb] * t;
            const float len = length(nrm);
            if (len > 1e-12f) {
                nrm = nrm * (1.f / len);
            } else {  // opposite normals (a thin sheet): point from the inside corner to the outside one
                nrm = Vec3f{};
                const float dir = field.dist(ia) < 0 ? 1.f : -1.f;
                if (axis == 0) nrm.x = dir;
                else if (axis == 1) nrm.y = dir;
                else nrm.z = dir;
            }
            tree.positions[v] = p;
            tree.normals[v] = nrm;
            if (colors) {
                const Vec4f ca = pc.colors[pa], cb = pc.colors[pb];
                tree.colors[v] = {ca.x + (cb.x - ca.x) * t, ca.y + (cb.y - ca.y) * t, ca.z + (cb.z - ca.z) * t,
                                  ca.w + (cb.w - ca.w) * t};
            }
        };
        auto b_of = [&](std::size_t v) {
            return (vertex_edge[v] & key_bits) + (std::uint64_t(1) << (17 * int(vertex_edge[v] >> 51)));
        };
        std::vector<std::uint8_t> later(vcount, 0);
        parallel_for(vcount, threads, [&](std::size_t b, std::size_t e) {
            std::vector<Blocks::Cached> cache(Blocks::cache_size);
            for (std::size_t v = b; v < e; ++v) {
                const std::uint32_t ia = field.peek_index(vertex_edge[v] & key_bits, cache.data());
                const std::uint32_t ib = field.peek_index(b_of(v), cache.data());
                if (ia == none || ib == none) later[v] = 1;
                else make_vertex(v, ia, ib);
            }
        });
        for (std::size_t v = 0; v < vcount; ++v)
            if (later[v]) {
                const std::uint32_t ia = field.index(vertex_edge[v] & key_bits);
                make_vertex(v, ia, field.index(b_of(v)));
            }
        clock.mark("vertices, neighbours");
        flood.frontier.clear();
        // Cubes around a vertex's leaf edge not examined yet (none, in practice; both threads), then
        // added in the order the vertices were first met from the last node to the first.
        std::atomic<bool> unexamined{false};
        parallel_for(vertex_edge.size(), threads, [&](std::size_t b, std::size_t e) {
            std::vector<Blocks::Cached> cache(Blocks::cache_size);
            bool found = false;
            for (std::size_t v = b; v < e && !found; ++v)
                for_cubes_around(vertex_edge[v] & ((std::uint64_t(1) << 51) - 1), int(vertex_edge[v] >> 51),
                                 [&](std::uint64_t cube) { found = found || !flood.visited.contains(cube, cache.data()); });
            if (found) unexamined = true;
        });
        if (unexamined) {
            std::vector<std::uint8_t> met(vertex_edge.size(), 0);
            for (const std::uint32_t v : tree.vertex_ids) {
                if (met[v]) continue;
                met[v] = 1;
                const std::uint64_t ek = vertex_edge[v];
                for_cubes_around(ek & ((std::uint64_t(1) << 51) - 1), int(ek >> 51), [&](std::uint64_t cube) {
                    flood.add(cube);
                });
            }
        }
        if (flood.frontier.empty() || pass >= 32) break;
        // With a band, the cube diagonal to a kept one across a crossing edge may sit behind a dropped
        // face neighbour and was never examined; it is usually dropped too, and then the tree stands.
        const std::size_t kept = flood.leaves.size();
        flood.run();
        if (flood.leaves.size() == kept) break;
    }

    clock.mark("check");
    // Area-difference metric: area of the children's triangles minus the node's own.
    check_progress(progress, 0.8, "mcoctree: priorities");
    std::vector<float> area(node_count, 0.f);
    const mc::CaseTable& table = mc::case_table();
    parallel_for(node_count, threads, [&](std::size_t b, std::size_t e) {
        for (std::size_t ni = b; ni < e; ++ni) {
            const McNode& n = tree.nodes[ni];
            const std::uint32_t c = mc::corner_config(n.inside);
            double sum = 0;
            for (int t = 0; t < table.count[c]; ++t) {
                const Vec3f p0 = tree.positions[mc::sub_edge_vertex(tree, n, table.edges[c][3 * t])];
                const Vec3f p1 = tree.positions[mc::sub_edge_vertex(tree, n, table.edges[c][3 * t + 1])];
                const Vec3f p2 = tree.positions[mc::sub_edge_vertex(tree, n, table.edges[c][3 * t + 2])];
                sum += 0.5 * double(length(cross(p1 - p0, p2 - p0)));
            }
            area[ni] = static_cast<float>(sum);
        }
    });
    tree.metric.assign(node_count, 0.f);
    for (std::size_t ni = 0; ni < offset[0]; ++ni) {
        const McNode& n = tree.nodes[ni];
        double children = 0;
        for (int k = 0, c = 0; k < 8; ++k)
            if (n.child_mask & (1u << k)) children += area[n.first_child + std::uint32_t(c++)];
        tree.metric[ni] = static_cast<float>(children - area[ni]);
    }
    clock.mark("area metric");
    result.hidden_cuts = mc::number_mc_octree(tree, maps, threads, progress);
    clock.mark("numbering");

    result.dropped_far_cubes = flood.dropped_far_cubes;
    result.field_samples = field.size() + field.scattered();
    result.scattered_samples = field.scattered();
    result.warnings = tree.warnings;
    check_progress(progress, 1, "mcoctree: done");
    return result;
}

}  // namespace lodforge

// Prioritized marching-cube octree (docs/mcoctree.md): a surface rebuilt from points with normals (or a
// mesh's vertices) by marching cubes on an octree whose internal nodes are numbered by priority, so that a
// crack-free mesh at any of thousands of levels is extracted with integer work only.
//
//   McOctreeParams p;  p.resolution = 256;
//   McOctree tree = build_mc_octree(mesh, p).tree;        // or read_mc_octree("x.mco")
//   McOctreeExtractor ex(tree);
//   const Mesh& m = ex.extract(ex.priority_for_triangles(50000)).mesh;
//
// Priority index i (0 .. tree.max_priority()) means "the first tree.cuts[i] internal nodes of the priority
// order are expanded": 0 is the root alone, max_priority() is every leaf. The triangle count is
// non-decreasing in i (the cuts of the order that a later cut undercuts are not levels; docs/mcoctree.md). The extracted mesh is closed wherever the
// leaf surface is (no border edges, no T-junctions: vertices are shared by index between levels).
#pragma once

#include "lodforge/mesh.h"
#include "lodforge/progress.h"
#include "lodforge/types.h"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace lodforge {

// How the distance field is evaluated (docs/mcoctree.md, D1). Every method gives the same values: the
// nearest input point of each lattice point, ties to the lowest point index.
enum class McFieldMethod {
    automatic,  // scatter when the points are not much denser than the cubes, else queries only
    queries,    // one kd-tree query per lattice point
    scatter,    // every point to the lattice points within 2 cube sizes, kd-tree queries for the others
};

struct McOctreeParams {
    // Leaf cubes along the longest axis of the input's bounding box (used when cube_size is 0).
    std::size_t resolution = 128;
    // Leaf cube edge length in model units; > 0 overrides resolution.
    double cube_size = 0;
    // 0: every cube the surface crosses is kept, so the surface is closed (holes in a scan are bridged by
    // the field's zero set). > 0: a leaf cube is kept only when every corner lies within band * cube size
    // of an input point, so the surface of an open scan ends near its border (and is open there).
    double band = 0;
    // Worker threads for the distance field (0 = hardware concurrency). The tree does not depend on it.
    unsigned threads = 0;
    McFieldMethod field = McFieldMethod::automatic;  // speed only: the tree does not depend on it
};

// One octree node. Coordinates are in units of the node's own size: the node covers
// [origin + (x, y, z) * size, origin + (x + 1, y + 1, z + 1) * size) with size = cube_size * 2^level.
struct McNode {
    std::uint32_t x = 0, y = 0, z = 0;
    std::uint8_t level = 0;        // 0 = leaf
    std::uint8_t child_mask = 0;   // bit k: child in octant k (bit 0 = +x, bit 1 = +y, bit 2 = +z) exists
    std::uint32_t first_child = 0; // children are stored contiguously, in octant order
    std::uint32_t parent = UINT32_MAX;
    // Bit s set = sample s of the node's 3x3x3 lattice (s = i + 3j + 9k) is inside the surface. Leaves
    // carry only their 8 corners.
    std::uint32_t inside = 0;
    // Bit e set = sub-edge e (12 edges, 24 half edges, 24 face-interior edges; mc_tables.cpp) crosses the
    // surface; its vertex is vertex_ids[first_vertex + popcount(crossings & ((1 << e) - 1))].
    std::uint64_t crossings = 0;
    std::uint32_t first_vertex = 0;
    // 1-based position in the priority order for internal nodes; UINT32_MAX for leaves.
    std::uint32_t priority = UINT32_MAX;
};

// The built octree. Plain data: build_mc_octree fills it, write/read_mc_octree store it.
struct McOctree {
    Vec3f origin;             // corner of the root cube
    float cube_size = 0;      // leaf cube edge
    std::uint32_t levels = 0; // root level (the root cube is cube_size * 2^levels wide)
    std::size_t input_points = 0;

    // Surface vertices, one per leaf edge the surface crosses (shared by every level).
    std::vector<Vec3f> positions;
    std::vector<Vec3f> normals;
    std::vector<Vec4f> colors;  // empty when the input had none

    std::vector<McNode> nodes;           // root first, then level by level towards the leaves
    std::vector<std::uint32_t> vertex_ids;
    // 18 same-level neighbours per node (6 faces, then 12 edges, mc_tables.h order); UINT32_MAX = none.
    std::vector<std::uint32_t> neighbours;
    std::vector<std::uint32_t> order;    // order[k] = node with priority k + 1
    // Priority levels: cuts[i] = how many nodes of `order` are expanded at priority i (strictly increasing,
    // cuts[0] = 0, cuts.back() = order.size()).
    std::vector<std::uint32_t> cuts;
    // triangle_counts[i] = triangles of the mesh extracted at priority i (size cuts.size(), non-decreasing).
    std::vector<std::uint64_t> triangle_counts;
    std::vector<float> metric;           // per internal node: area of the children's surface - own area

    std::vector<std::string> warnings;   // e.g. resolution above the data density

    std::size_t max_priority() const { return cuts.empty() ? 0 : cuts.size() - 1; }
    std::size_t leaf_count() const;
    bool has_colors() const { return !colors.empty(); }
};

// Time spent in one stage of the build: wall clock, CPU time of the whole process (all threads) and of the
// calling thread (the stage's critical path where the helper threads' shares end first; on a machine shared
// with other jobs it is what the stage would take with both cores to itself, the wall clock is not).
struct McBuildStage {
    std::string name;
    double wall_s = 0, cpu_s = 0, thread_cpu_s = 0;
};

struct McOctreeBuildResult {
    McOctree tree;
    std::size_t leaf_cubes = 0;        // non-null leaf cubes stored
    std::size_t field_samples = 0;     // distance-field values (lattice points)
    std::size_t scattered_samples = 0; // of which found by scattering the points (the rest: kd-tree queries)
    std::size_t dropped_far_cubes = 0; // crossing cubes dropped by the band rule (surface ends there)
    bool reaches_grid_edge = false;    // band 0 and the surface runs to the grid's boundary (an open input; warned)
    double point_spacing = 0;          // median distance of an input point to its nearest neighbour
    std::size_t face_samples = 0;      // points added on the mesh's faces longer than two cubes (D1)
    std::size_t sampled_faces = 0;     // faces that got them
    std::size_t hidden_cuts = 0;       // cuts of the order that are not levels (a later cut has fewer triangles)
    std::vector<std::string> warnings; // same as tree.warnings
    std::vector<McBuildStage> stages;  // in build order
};

// Points are the mesh's positions; normals are the mesh's or, when absent, the area-weighted normals
// of the adjacent triangles; colours are used when present. Throws Error(invalid) for an empty input,
// no normals and no faces, non-finite values; Error(argument) for a bad resolution; Error(cancelled).
McOctreeBuildResult build_mc_octree(const Mesh& input, const McOctreeParams& params = {},
                                    Progress* progress = nullptr);

// The triangle count at priority i is exact (tree.triangle_counts[i]).
std::uint64_t mc_triangles_at(const McOctree& tree, std::size_t priority);
// The largest priority whose mesh has at most `triangles` triangles (0 when even the root has more).
std::size_t mc_priority_for_triangles(const McOctree& tree, std::uint64_t triangles);

// A node of the cut drawn at some priority, for overlays (the octree cells of the studio).
struct McCell {
    Vec3f min;
    float size = 0;
    std::uint8_t level = 0;
    std::uint32_t node = 0;
};

struct McExtraction {
    Mesh mesh;                    // positions, normals (and colours); indices counter-clockwise outside
    std::size_t priority = 0;
    std::size_t active_nodes = 0; // nodes of the cut (triangulated)
    std::size_t transition_nodes = 0; // of which have finer neighbours (re-triangulated for the seams)
};

// Extraction with reusable scratch space and, built once per tree, every node's triangulations over its
// life in the cuts (the seams its neighbours bring, in priority order) with their vertices resolved, laid
// out in the order the cuts reach the nodes, and the vertices renumbered in the order the cuts first use
// them: an extraction at priority i reads only the records of the nodes expanded up to i and their
// children, and the vertices of a prefix of the renumbered vertex arrays (docs/mcoctree.md, D9). Table
// look-ups and copies only, no work proportional to the whole tree. The tree must outlive the extractor.
// Not thread-safe (one extractor per thread; the tree may be shared).
class McOctreeExtractor {
public:
    explicit McOctreeExtractor(const McOctree& tree);
    ~McOctreeExtractor();
    McOctreeExtractor(const McOctreeExtractor&) = delete;
    McOctreeExtractor& operator=(const McOctreeExtractor&) = delete;
    // Throws Error(argument) when priority > tree.max_priority().
    const McExtraction& extract(std::size_t priority);
    const McExtraction& extract_triangles(std::uint64_t triangles) {
        return extract(mc_priority_for_triangles(*tree_, triangles));
    }
    std::size_t priority_for_triangles(std::uint64_t triangles) const {
        return mc_priority_for_triangles(*tree_, triangles);
    }
    // The nodes triangulated at `priority` (cells overlay).
    std::vector<McCell> cells(std::size_t priority) const;

private:
    const McOctree* tree_;
    McExtraction result_;
    // Records: the root, then the children of order[0], of order[1], ... (the nodes a cut at rank R can
    // hold are the first record_start_[R + 1]). Per record its own priority (in the cut while rank < it)
    // and its events record_event_[k] .. record_event_[k + 1].
    std::vector<std::uint32_t> record_start_;
    std::vector<std::uint32_t> record_own_;
    std::vector<std::uint32_t> record_event_;
    // Event e: from rank event_rank_[e] on, the node is triangulated by the pool entry at event_entry_[e]
    // (triangle count, whether refined, local vertex triples) over the vertices
    // event_ids_[event_first_id_[e] .. event_first_id_[e + 1]) (renumbered ids).
    std::vector<std::uint32_t> event_rank_;
    std::vector<std::uint32_t> event_entry_;
    std::vector<std::uint32_t> event_first_id_;
    std::vector<std::uint32_t> event_ids_;
    std::vector<std::uint8_t> pool_;
    // Renumbered vertices (first use in the cuts); empty when the tree's own order is that already.
    std::vector<Vec3f> positions_, normals_;
    std::vector<Vec4f> colors_;
    // prefix_[i] = vertices first used at priority <= i: every vertex of the cut at i is below it.
    std::vector<std::uint32_t> prefix_;
    std::vector<std::uint32_t> stamp_, remap_;  // per renumbered vertex
    std::uint32_t generation_ = 0;
};

// One-shot convenience.
McExtraction extract_mc_octree(const McOctree& tree, std::size_t priority);

// The .mco file (docs/formats/mco.md). Both throw Error naming the file; the writer goes through AtomicFile.
void write_mc_octree(const McOctree& tree, const std::string& path, Progress* progress = nullptr);
McOctree read_mc_octree(const std::string& path, Progress* progress = nullptr);

// Checks the structural invariants a reader or a caller relies on (indices in range, children after
// parents, counts consistent); throws Error(format) naming `file` on the first violation.
void validate_mc_octree(const McOctree& tree, const std::string& file);

}  // namespace lodforge

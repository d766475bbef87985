// Builds the out-of-core octree LOD asset from a PLY of any size within a memory budget
// (docs/octree.md): triangle soup by external distribution sort (ooc_soup.h), an adaptive octree
// on disk driven by the two knobs (max triangles per leaf, max depth), every node simplified with the
// boundary-preserving operator (octree_simplify.h) bottom-up to the root, written as one asset file
// (octree_store.h).
//
//     OctreeBuildParams p;  p.max_triangles = 5000;  p.max_depth = 10;  p.memory_bytes = 64 << 20;
//     OctreeBuildResult r = build_octree("scan.ply", "scan.lfo", p, &progress);
//     r.stats.leaves, r.stats.depth_reached, r.stats.triangles_per_level ...
//
// Assignment rule: a triangle belongs to the octant containing its centroid (ties go to the upper
// half), so it is stored exactly once, unclipped; a node is split while it holds more than
// max_triangles and its depth is below max_depth.
#pragma once

#include "lodforge/octree/octree_store.h"
#include "lodforge/octree/ooc_soup.h"
#include "lodforge/progress.h"
#include "lodforge/simplify/simplify.h"

#include <cstddef>
#include <string>
#include <vector>

namespace lodforge {

struct OctreeBuildParams {
    std::size_t max_triangles = 10000;  // split a node holding more input triangles than this (≥ 1)
    int max_depth = 12;                 // never split below this depth (0 = the root is the only leaf; ≤ 20)
    std::size_t memory_bytes = std::size_t{256} << 20;  // working memory (≥ 4 MB)
    std::string temp_dir;               // empty: a temporary directory beside the asset
    SimplifyWeights weights;            // attribute weights of the generalized quadric
    // Each level's size as a fraction of the level below, in [0.05, 0.95] (0: the old schedule, collapse to
    // the fans' size or the error bound). A level stays larger where the cells' cut lines, kept at full
    // resolution for crack-free mixed cuts, are most of it (docs/octree.md, "Level sizes").
    double level_ratio = 0.35;
    // The root's (coarsest level's) triangles, reached by one free collapse of the root (0: by level_ratio).
    std::size_t coarsest_triangles = 0;
    // 1 or 2: the nodes of a subtree held in memory are computed on two threads (the asset is the same
    // byte for byte whatever this is).
    int threads = 2;
};

struct OctreeBuildResult {
    SoupResult soup;
    OctreeStats stats;
    std::uint64_t split_passes = 0;       // nodes split by streaming over a temporary file
    std::uint64_t closed_components = 0;  // components without a boundary edge in their node (clustered), per node
    std::uint64_t degenerate_triangles = 0;  // input triangles with a repeated vertex (in no simplified mesh)
    std::size_t oversized_leaves = 0;     // leaves at max_depth holding more than max_triangles
    std::vector<std::string> warnings;
};

// Optional profile of a build (not part of the asset or its description).
struct OctreeBuildStats {
    double soup_seconds = 0;     // PLY → soup
    double build_seconds = 0;    // soup → octree + every node simplified + asset written
    double simplify_seconds = 0; // time in the node operator, summed over the threads (may exceed build_seconds)
};

// Throws Error(argument) for bad parameters, Error(io / format / invalid) naming the input or the
// asset, Error(cancelled). On any failure no asset and no temporary file is left behind.
OctreeBuildResult build_octree(const std::string& input_ply, const std::string& asset_path,
                               const OctreeBuildParams& params = {}, Progress* progress = nullptr,
                               OctreeBuildStats* stats = nullptr);

}  // namespace lodforge

// The marching-cube octree's leaf cubes: a flood along the surface from the cubes holding points, across
// every face the surface crosses, so no crossing face of a kept cube leads to an unexamined one (that
// would be a hole). Internal to the core (mc_octree_build.cpp); design and decisions (D1, D2):
// docs/mcoctree.md.
#pragma once

#include "lodforge/progress.h"
#include "mcoctree/mc_field.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace lodforge::mc {

// Morton code of lattice cube (x, y, z): the octree's leaf order.
std::uint64_t morton(std::uint32_t x, std::uint32_t y, std::uint32_t z);

// A node of the octree under construction (leaves come from the flood).
struct TmpNode {
    std::uint64_t code;  // Morton code at the node's level
    std::uint32_t x, y, z;
    std::uint32_t corners = 0;  // leaves: inside corners (bit c = corner c), known from the flood
};

class LeafFlood {
public:
    // `grid`: cubes per axis; a cube whose corner values reach beyond `cap` (the band) is dropped;
    // `expected`: about how many cubes will be examined (sizes the visited set).
    LeafFlood(Field& field, std::uint32_t grid, float cap, unsigned threads, Progress* progress,
              std::size_t expected);

    // The seed cubes: each cube holding a point (both cubes for a point on a lattice plane), in lattice
    // order in `frontier`. `origin` and `h`: the lattice's corner and cube size.
    void seed(const std::vector<Vec3f>& points, Vec3f origin, double h);
    // Examines the frontier until none is left: cubes the surface crosses are appended to `leaves`, and
    // their crossed faces' neighbours not examined before join the next frontier. Throws Error(cancelled)
    // when progress asks to stop.
    void run();
    // Puts `cube` on the frontier unless it was examined (or queued) before.
    void add(std::uint64_t cube) {
        if (visited.insert(cube)) frontier.push_back(cube);
    }

    CubeSet visited;                      // every cube examined or queued
    std::vector<std::uint64_t> frontier;  // cubes queued for the next run()
    std::vector<TmpNode> leaves;          // the kept cubes, in the order found
    std::size_t dropped_far_cubes = 0;    // crossed cubes dropped by the band

private:
    Field& field;
    std::uint32_t grid;
    float cap;
    unsigned threads;
    Progress* progress;
    std::size_t round = 0;
    std::vector<std::uint64_t> corner_keys, next;
    // A frontier cube examined on the worker threads: its inside corners, the faces to flood across
    // (bit f: face f = 2 * axis + side), and what became of it.
    struct CubeState {
        enum : std::uint8_t { none, far, kept, serial };
        std::uint8_t inside, faces, state;
    };
    std::vector<CubeState> cube_states;
};

}  // namespace lodforge::mc

// What every reader fuzzer checks on a Mesh it was given: the Mesh contract, as a crash
// (__builtin_trap) so that libFuzzer reports a violation as a finding.
#pragma once

#include "lodforge/mesh.h"

#include <cstddef>
#include <cstdint>

namespace lodforge::fuzz {

inline void check(bool ok) {
    if (!ok) __builtin_trap();
}

inline void check_mesh(const Mesh& m) {
    const std::size_t n = m.positions.size();
    check(m.normals.empty() || m.normals.size() == n);
    check(m.colors.empty() || m.colors.size() == n);
    for (const auto& set : m.texcoords) check(set.size() == n);
    check(m.position_ids.empty() || m.position_ids.size() == n);
    for (std::uint32_t id : m.position_ids) check(id < n);
    check(m.indices.size() % 3 == 0);
    for (std::uint32_t i : m.indices) check(i < n);
    check(m.face_materials.empty() || m.face_materials.size() == m.indices.size() / 3);
    for (std::uint32_t f : m.face_materials) check(f < m.materials.size());
    for (const auto& p : m.positions) check(is_finite(p));
}

}  // namespace lodforge::fuzz

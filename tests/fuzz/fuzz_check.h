// What every reader fuzzer checks on a Mesh it was given: the Mesh contract, as a crash
// (__builtin_trap) so that libFuzzer reports a violation as a finding. And the one scratch directory
// the fuzzers write their inputs into (the readers take paths).
#pragma once

#include "lodforge/mesh.h"

#include <cerrno>
#include <csignal>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>
#include <unistd.h>

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

// A directory of this process, removed at exit (libFuzzer ends a timed run through exit()). On tmpfs
// (/dev/shm) when the machine has one: an input written to a disk-backed /tmp cost several times the
// reader's own time per execution. $LODFORGE_FUZZ_DIR overrides the parent. Call it first from
// LLVMFuzzerInitialize so that no execution pays for creating it.
inline const std::filesystem::path& scratch_dir() {
    namespace fs = std::filesystem;
    static const fs::path dir = [] {
        std::error_code ec;
        fs::path parent = fs::temp_directory_path();
        if (const char* env = std::getenv("LODFORGE_FUZZ_DIR"))
            parent = env;
        else if (fs::is_directory("/dev/shm", ec))
            parent = "/dev/shm";
        // libFuzzer ends some runs through _Exit (merges, -runs limits), past atexit: remove what
        // processes that no longer exist left behind.
        for (const auto& entry : fs::directory_iterator(parent, ec)) {
            const std::string name = entry.path().filename().string();
            if (name.rfind("lodforge-fuzz-", 0) != 0) continue;
            const long pid = std::strtol(name.c_str() + 14, nullptr, 10);
            if (pid > 0 && ::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH) fs::remove_all(entry.path(), ec);
        }
        fs::path d = parent / ("lodforge-fuzz-" + std::to_string(::getpid()));
        fs::create_directories(d);
        std::atexit([] {
            std::error_code ignored;
            fs::remove_all(scratch_dir(), ignored);
        });
        return d;
    }();
    return dir;
}

}  // namespace lodforge::fuzz

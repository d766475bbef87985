// libFuzzer target for the PLY reader. Each input is read twice: from memory with read_ply (the whole
// importer: wedges, strips, materials), and from a temporary file through the streaming PlyReader with
// a tiny read buffer and small chunks, so buffer refills, growth and seeks run on every input.
// Invariants the Mesh contract promises are checked with __builtin_trap so a violation is a crash.

#include "io/ply_internal.h"

#include "fuzz_check.h"
#include "lodforge/error.h"
#include "lodforge/io/ply.h"

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace {

using lodforge::fuzz::check;
using lodforge::fuzz::check_mesh;

const std::string& temp_path() {
    static const std::string path = (lodforge::fuzz::scratch_dir() / "fuzz.ply").string();
    return path;
}

void read_streaming(const std::string& path) {
    lodforge::PlyReader reader(path);
    std::vector<lodforge::Vec3f> p(5), n(5);
    std::vector<lodforge::Vec4f> c(5);
    std::vector<lodforge::Vec2f> t(5);
    lodforge::PlyFaceChunk faces;
    const std::uint64_t vertices = reader.vertex_count();
    while (reader.current_element()) {
        const std::uint64_t before = reader.position();
        if (reader.at_vertices()) {
            check(reader.read_vertices(p, n, c, t) > 0);
        } else if (reader.at_faces()) {
            faces.clear();
            check(reader.read_faces(3, faces) > 0);
            for (std::uint32_t i : faces.indices) check(i < vertices);
        } else {
            reader.skip_element();
        }
        check(reader.position() >= before);
    }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    (void)temp_path();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        lodforge::PlyReader reader({reinterpret_cast<const std::byte*>(data), size}, "fuzz.ply");
        check_mesh(lodforge::read_ply(reader));
    } catch (const lodforge::Error&) {
    }

    if (std::FILE* f = std::fopen(temp_path().c_str(), "wb")) {
        std::fwrite(data, 1, size, f);
        std::fclose(f);
        lodforge::ply_detail::set_file_buffer_size(1 + size % 61);
        try {
            read_streaming(temp_path());
        } catch (const lodforge::Error&) {
        }
    }
    return 0;
}

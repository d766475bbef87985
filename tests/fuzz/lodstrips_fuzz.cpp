// libFuzzer target for the .lodstrips decoder and runtime (header-only: nothing else is compiled in).
// Whatever load_memory accepts must be walkable over every level without leaving the buffer. The
// container's checksums are recomputed first (tests/support/own_format_seal.h): mutations reach the
// decoder.
#include "../support/own_format_seal.h"
#include "lodforge/runtime/lodstrips_runtime.h"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    std::string bytes(reinterpret_cast<const char*>(data), size);
    lodforge::test::seal_container(bytes);
    lodstrips::LodStrips rt;
    std::string why;
    if (!rt.load_memory(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(), &why)) return 0;
    rt.go_to_level(rt.collapse_count());
    rt.go_to_lod(0.5);
    rt.go_to_triangles(rt.triangle_count_at(0) / 3);
    std::vector<std::uint32_t> tris;
    rt.triangles(tris);
    rt.go_to_level(0);
    (void)rt.changes();
    return 0;
}

// libFuzzer targets for the file readers other than PLY: one source, one target per reader, chosen by
// LODFORGE_FUZZ_READER at compile time (tests/fuzz/CMakeLists.txt). Each input is written to a temporary
// file with the reader's extension (the readers take paths) and read, the own formats with their
// checksums recomputed first (tests/support/own_format_seal.h); a lodforge::Error is the expected answer
// to bad bytes, anything else (a crash, a sanitizer report, another exception, a leak, a Mesh breaking
// its contract) is a finding.
//   gltf      .gltf, or .glb when the input starts with "glTF"
//   obj       .obj; the bytes after a line "#--mtl--" are written as fuzz.mtl beside it
//   lfo       .lfo octree asset: header, node table, and every node's mesh loaded
//   mco       .mco marching-cube octree
//   lfmorph   .lfmorph morph LOD
//   lfmstrips .lfmstrips morph LODStrips
//   lodstrips .lodstrips (the file reader; lodstrips_fuzz covers the runtime)
//   preset    pack preset JSON
//   landmarks morph landmark JSON
#include "fuzz_check.h"
#include "../support/own_format_seal.h"
#include "lodforge/error.h"
#include "lodforge/mesh.h"

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>

#define FUZZ_IS(name) (std::string_view(LODFORGE_FUZZ_READER) == name)

#include "lodforge/io/gltf_reader.h"
#include "lodforge/io/obj.h"
#include "lodforge/mcoctree/mc_octree.h"
#include "lodforge/morph/landmarks.h"
#include "lodforge/morph/morph_file.h"
#include "lodforge/morph/morph_lodstrips.h"
#include "lodforge/octree/octree_store.h"
#include "lodforge/pack/preset.h"
#include "lodforge/strips/lodstrips.h"

namespace {

using lodforge::fuzz::check;
using lodforge::fuzz::check_mesh;

std::string write(const std::string& name, std::string_view bytes) {
    const std::string path = (lodforge::fuzz::scratch_dir() / name).string();
    if (std::FILE* f = std::fopen(path.c_str(), "wb")) {
        std::fwrite(bytes.data(), 1, bytes.size(), f);
        std::fclose(f);
    }
    return path;
}

void read(std::string_view bytes) {
    using namespace lodforge;
    if constexpr (FUZZ_IS("gltf")) {
        const bool glb = bytes.substr(0, 4) == "glTF";
        check_mesh(read_gltf(write(glb ? "fuzz.glb" : "fuzz.gltf", bytes)));
    } else if constexpr (FUZZ_IS("obj")) {
        constexpr std::string_view kMarker = "\n#--mtl--\n";
        const std::size_t at = bytes.find(kMarker);
        write("fuzz.mtl", at == std::string_view::npos ? std::string_view() : bytes.substr(at + kMarker.size()));
        check_mesh(read_obj(write("fuzz.obj", bytes.substr(0, at))));
    } else if constexpr (FUZZ_IS("lfo")) {
        std::string sealed(bytes);
        test::seal_lfo(sealed);
        OctreeStore store(write("fuzz.lfo", sealed), std::size_t{1} << 20);
        (void)store.stats();
        for (std::uint32_t i = 0; i < store.nodes().size(); ++i) {
            const bool leaf = store.children(i).empty();
            (void)store.load(i, false);
            if (leaf) (void)store.load(i, true);
        }
    } else if constexpr (FUZZ_IS("mco")) {
        std::string sealed(bytes);
        test::seal_own_format(sealed, 2, binary::fnv1a_basis);
        (void)read_mc_octree(write("fuzz.mco", sealed));
    } else if constexpr (FUZZ_IS("lfmorph")) {
        std::string sealed(bytes);
        test::seal_own_format(sealed, 1, binary::lfmorph1_fnv1a_basis);
        (void)read_morph_lod(write("fuzz.lfmorph", sealed));
    } else if constexpr (FUZZ_IS("lfmstrips")) {
        std::string sealed(bytes);
        test::seal_container(sealed);
        (void)read_morph_lodstrips(write("fuzz.lfmstrips", sealed));
    } else if constexpr (FUZZ_IS("lodstrips")) {
        std::string sealed(bytes);
        test::seal_container(sealed);
        (void)read_lodstrips(write("fuzz.lodstrips", sealed));
    } else if constexpr (FUZZ_IS("preset")) {
        (void)load_preset(write("fuzz.json", bytes));
    } else if constexpr (FUZZ_IS("landmarks")) {
        (void)read_landmarks(write("fuzz.json", bytes));
    }
}
static_assert(FUZZ_IS("gltf") || FUZZ_IS("obj") || FUZZ_IS("lfo") || FUZZ_IS("mco") || FUZZ_IS("lfmorph") ||
                  FUZZ_IS("lfmstrips") || FUZZ_IS("lodstrips") || FUZZ_IS("preset") || FUZZ_IS("landmarks"),
              "unknown LODFORGE_FUZZ_READER");

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    (void)lodforge::fuzz::scratch_dir();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        read({reinterpret_cast<const char*>(data), size});
    } catch (const lodforge::Error&) {
    }
    return 0;
}

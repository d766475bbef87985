// Writes the seed corpus for ply_fuzz: small real files from ../shared/data (cut to 4 KiB: their headers
// matter, and small seeds keep the fuzzer fast) and synthetic files covering what the real ones lack
// (big endian, every scalar type, polygons, tristrips, wedge texcoords with texnumber, unknown elements
// with lists, CRLF headers).
//
//   ply_fuzz_seeds <corpus dir> <real file>...
// writes <corpus dir>/seeds and an empty <corpus dir>/found for the inputs libFuzzer discovers.

#include "lodforge/mesh.h"
#include "lodforge/io/ply.h"

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace fs = std::filesystem;
using namespace lodforge;

namespace {

void save(const fs::path& dir, const std::string& name, const std::string& bytes) {
    std::ofstream(dir / name, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

template <typename T>
void put(std::string& s, T v, bool big) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof v);
    if (big)
        for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(b[i], b[sizeof(T) - 1 - i]);
    s.append(b, sizeof b);
}

Mesh small_mesh() {
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5f, 0.5f, 1}};
    m.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 1, 0}};
    m.colors = {{1, 0, 0, 1}, {0, 1, 0, 1}, {0, 0, 1, 1}, {1, 1, 1, 0.5f}, {0.2f, 0.4f, 0.6f, 1}};
    m.texcoords = {{{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0.5f, 0.5f}}};
    m.indices = {0, 1, 2, 0, 2, 3, 0, 1, 4, 1, 2, 4};
    m.materials.emplace_back().base_color_texture.path = "skin.png";
    return m;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: ply_fuzz_seeds <corpus dir> <real file>...\n");
        return 2;
    }
    const fs::path root = argv[1];
    const fs::path dir = root / "seeds";
    fs::remove_all(root);
    fs::create_directories(dir);
    fs::create_directories(root / "found");
    for (int i = 2; i < argc; ++i) {
        std::ifstream in(argv[i], std::ios::binary);
        std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        save(dir, "real-" + fs::path(argv[i]).filename().string(), bytes.substr(0, 4 * 1024));
    }

    const Mesh m = small_mesh();
    int k = 0;
    for (PlyEncoding enc : {PlyEncoding::ascii, PlyEncoding::binary_little_endian, PlyEncoding::binary_big_endian})
        for (bool uchar : {true, false}) {
            WriteOptions o;
            o.ply_encoding = enc;
            o.ply_colors_as_uchar = uchar;
            write_ply(m, (dir / ("written-" + std::to_string(k++) + ".ply")).string(), o);
        }

    // Every scalar type in one vertex element, polygons and an unknown element with lists.
    for (bool big : {false, true}) {
        std::string s = std::string("ply\nformat ") + (big ? "binary_big_endian" : "binary_little_endian") +
                        " 1.0\ncomment TextureFile a.png\ncomment TextureFile b.png\n"
                        "element vertex 4\nproperty char a\nproperty uchar b\nproperty short x\nproperty ushort c\n"
                        "property int y\nproperty uint d\nproperty float z\nproperty double e\n"
                        "property list uchar short tags\n"
                        "element blob 2\nproperty list uint double values\n"
                        "element face 2\nproperty list ushort uint vertex_index\nproperty list uchar float texcoord\n"
                        "property int texnumber\nend_header\n";
        for (int v = 0; v < 4; ++v) {
            put<std::int8_t>(s, -1, big);
            put<std::uint8_t>(s, 2, big);
            put<std::int16_t>(s, static_cast<std::int16_t>(v & 1), big);
            put<std::uint16_t>(s, 4, big);
            put<std::int32_t>(s, v >> 1, big);
            put<std::uint32_t>(s, 6, big);
            put<float>(s, 0.5f * v, big);
            put<double>(s, 8.0, big);
            put<std::uint8_t>(s, 2, big);
            put<std::int16_t>(s, 9, big);
            put<std::int16_t>(s, 10, big);
        }
        for (int b = 0; b < 2; ++b) {
            put<std::uint32_t>(s, 1, big);
            put<double>(s, 3.25, big);
        }
        put<std::uint16_t>(s, 4, big);  // a quad with wedge uvs, texture 1
        for (std::uint32_t i : {0u, 1u, 3u, 2u}) put<std::uint32_t>(s, i, big);
        put<std::uint8_t>(s, 8, big);
        for (float f : {0.f, 0.f, 1.f, 0.f, 1.f, 1.f, 0.f, 1.f}) put<float>(s, f, big);
        put<std::int32_t>(s, 1, big);
        put<std::uint16_t>(s, 3, big);  // a triangle without uvs, texture 0
        for (std::uint32_t i : {0u, 1u, 2u}) put<std::uint32_t>(s, i, big);
        put<std::uint8_t>(s, 0, big);
        put<std::int32_t>(s, 0, big);
        save(dir, big ? "types-be.ply" : "types-le.ply", s);
    }

    // Stanford-style triangle strips, binary and ASCII.
    {
        std::string s = "ply\nformat binary_little_endian 1.0\nelement vertex 6\nproperty float x\nproperty float y\n"
                        "property float z\nelement tristrips 1\nproperty list int int vertex_indices\nend_header\n";
        for (int v = 0; v < 6; ++v) {
            put<float>(s, float(v % 3), false);
            put<float>(s, float(v / 3), false);
            put<float>(s, 0.f, false);
        }
        const int strip[] = {3, 0, 4, 1, 5, 2, -1, 0, 1, 1, 2};
        put<std::int32_t>(s, static_cast<std::int32_t>(std::size(strip)), false);
        for (int i : strip) put<std::int32_t>(s, i, false);
        save(dir, "tristrips-le.ply", s);
        save(dir, "tristrips-ascii.ply",
             "ply\r\nformat ascii 1.0\r\nelement vertex 4\r\nproperty float x\r\nproperty float y\r\nproperty float z\r\n"
             "element tristrips 1\r\nproperty list int int vertex_indices\r\nend_header\r\n"
             "0 0 0\r\n1 0 0\r\n0 1 0\r\n1 1 0\r\n6 0 1 2 3 -1 3\r\n");
    }
    std::printf("wrote %zu seeds to %s\n",
                static_cast<std::size_t>(std::distance(fs::directory_iterator(dir), fs::directory_iterator())),
                dir.string().c_str());
    return 0;
}

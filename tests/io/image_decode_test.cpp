// Texture decoding: real PNGs, orientation (row 0 = top), embedded bytes and the error cases.
#include "io_test_util.h"

#include "lodforge/io/image_decode.h"

#include <gtest/gtest.h>

#include <string>

namespace lodforge {
namespace {
using test::expect_error;
using test::shared_data;

// A 2x3 binary PPM: top row red/green, middle blue/white, bottom black/grey.
std::string tiny_ppm() {
    const unsigned char pixels[] = {255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255, 0, 0, 0, 128, 128, 128};
    return std::string("P6\n2 3\n255\n") + std::string(reinterpret_cast<const char*>(pixels), sizeof pixels);
}

TEST(ImageDecode, RealPngsDecodeToRgba8) {
    const Image spot = decode_image_file(shared_data("tex-spot/spot_texture.png"));
    EXPECT_EQ(spot.width, 1024);
    EXPECT_EQ(spot.height, 1024);
    EXPECT_EQ(spot.rgba.size(), 1024u * 1024u * 4u);
    const Image duck = decode_image_file(shared_data("tex-duck/glTF/DuckCM.png"));  // palette PNG
    EXPECT_EQ(duck.width, 512);
    EXPECT_EQ(duck.rgba.size(), 512u * 512u * 4u);
    for (std::size_t i = 3; i < duck.rgba.size(); i += 4) ASSERT_EQ(duck.rgba[i], 255);
}

TEST(ImageDecode, FirstRowIsTheTopOfTheImage) {
    test::ScratchDir dir("img-orient");
    test::write_text(dir.file("t.ppm"), tiny_ppm());
    const Image image = decode_image_file(dir.file("t.ppm"));
    ASSERT_EQ(image.width, 2);
    ASSERT_EQ(image.height, 3);
    const std::vector<std::uint8_t> expected = {255, 0,   0,   255, 0,   255, 0,   255, 0,   0,   255, 255,
                                                255, 255, 255, 255, 0,   0,   0,   255, 128, 128, 128, 255};
    EXPECT_EQ(image.rgba, expected);
}

TEST(ImageDecode, EmbeddedBytesAndFileReferences) {
    Mesh mesh;
    TextureRef embedded;
    const std::string ppm = tiny_ppm();
    embedded.bytes.assign(ppm.begin(), ppm.end());
    EXPECT_EQ(decode_texture(mesh, embedded).height, 3);

    mesh.source_dir = shared_data("tex-spot");
    TextureRef file;
    file.path = "spot_texture.png";
    EXPECT_EQ(decode_texture(mesh, file).width, 1024);

    expect_error([&] { decode_texture(mesh, TextureRef{}); }, Error::Kind::argument, {"no texture"});
}

TEST(ImageDecode, MissingFileIsIoErrorNamingResolvedPath) {
    Mesh mesh;
    mesh.source_dir = "/nonexistent/textures";
    TextureRef ref;
    ref.path = "albedo.png";
    expect_error([&] { decode_texture(mesh, ref); }, Error::Kind::io, {"/nonexistent/textures/albedo.png"});
}

TEST(ImageDecode, UndecodableIsFormatErrorWithReason) {
    test::ScratchDir dir("img-bad");
    test::write_text(dir.file("bad.png"), "\x89PNG\r\n\x1a\n this is not a png body");
    expect_error([&] { decode_image_file(dir.file("bad.png")); }, Error::Kind::format, {"bad.png", "cannot decode"});
    test::write_text(dir.file("empty.png"), "");
    expect_error([&] { decode_image_file(dir.file("empty.png")); }, Error::Kind::format, {"empty.png"});
    TextureRef junk;
    junk.bytes = {1, 2, 3, 4, 5};
    junk.mime_type = "image/png";
    expect_error([&] { decode_texture(Mesh{}, junk); }, Error::Kind::format, {"embedded image/png"});
}

TEST(ImageDecode, TruncatedPngPrefixesThrow) {
    const std::vector<std::uint8_t> png = test::read_bytes(shared_data("tex-duck/glTF/DuckCM.png"));
    Mesh mesh;
    for (std::size_t n = 0; n < png.size(); n += 1 + n / 3) {
        TextureRef ref;
        ref.bytes.assign(png.begin(), png.begin() + static_cast<std::ptrdiff_t>(n));
        if (n == 0) ref.path = "x.png";  // empty bytes: falls back to the (missing) file
        SCOPED_TRACE(n);
        try {
            decode_texture(mesh, ref);
            ADD_FAILURE() << "truncated PNG decoded";
        } catch (const Error&) {
        }
    }
}

}  // namespace
}  // namespace lodforge

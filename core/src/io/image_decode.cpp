// Texture decoding through stb_image (PNG, JPEG, TGA, BMP, GIF, PSD, HDR, PIC, PNM), always to RGBA8
// with the first row at the top of the image (stb_image's default orientation, never flipped here).
//
// stb_image is compiled into this file with internal linkage (STB_IMAGE_STATIC) so it cannot clash
// with the copy that Debian's tinygltf shared library exports.
#include "lodforge/io/image_decode.h"

#include "lodforge/error.h"

#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#include <stb_image.h>

#include <cerrno>
#include <climits>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>

namespace lodforge {

namespace {

Image decode_bytes(const std::uint8_t* data, std::size_t size, const std::string& name) {
    if (size == 0) throw_error(Error::Kind::format, name, "image is empty");
    if (size > static_cast<std::size_t>(INT_MAX)) throw_error(Error::Kind::unsupported, name, "image file over 2 GiB");
    int width = 0, height = 0, channels = 0;
    std::unique_ptr<stbi_uc, void (*)(void*)> pixels(
        stbi_load_from_memory(data, static_cast<int>(size), &width, &height, &channels, 4), stbi_image_free);
    if (!pixels) {
        const char* reason = stbi_failure_reason();
        throw_error(Error::Kind::format, name, std::string("cannot decode image: ") + (reason ? reason : "unknown reason"));
    }
    Image image;
    image.width = width;
    image.height = height;
    const std::size_t bytes = static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 4;
    image.rgba.assign(pixels.get(), pixels.get() + bytes);
    return image;
}

}  // namespace

Image decode_image_file(const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) throw_error(Error::Kind::io, path, "texture file not found");
    if (std::filesystem::is_directory(path, ec)) throw_error(Error::Kind::io, path, "is a directory, not an image");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw_error(Error::Kind::io, path, std::string("cannot open texture: ") + std::strerror(errno));
    const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in.bad()) throw_error(Error::Kind::io, path, "read error");
    return decode_bytes(bytes.data(), bytes.size(), path);
}

Image decode_texture(const Mesh& mesh, const TextureRef& texture) {
    if (!texture.bytes.empty()) {
        const std::string name = texture.path.empty()
                                     ? "embedded " + (texture.mime_type.empty() ? std::string("image") : texture.mime_type)
                                     : texture.path;
        return decode_bytes(texture.bytes.data(), texture.bytes.size(), name);
    }
    if (texture.path.empty()) throw_error(Error::Kind::argument, "", "material has no texture to decode");
    return decode_image_file(mesh.resolve_texture_path(texture));
}

}  // namespace lodforge

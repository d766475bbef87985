// Decoding of texture images (PNG, JPEG, ...) referenced by materials, through stb_image.
#pragma once

#include "lodforge/mesh.h"

#include <cstdint>
#include <string>
#include <vector>

namespace lodforge {

struct Image {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> rgba;  // width * height * 4 bytes, first row = top of the image
    bool empty() const { return rgba.empty(); }
};

// Decodes an embedded texture or the file it names (resolved against mesh.source_dir).
// Throws Error(io) naming the path when the file is missing, Error(format) when it does not decode.
Image decode_texture(const Mesh& mesh, const TextureRef& texture);
Image decode_image_file(const std::string& path);

}  // namespace lodforge

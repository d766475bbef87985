// Image-space error between two meshes: both rendered offscreen the way the studio draws them
// (render/surface.h: textures, vertex colours, material colour, headlight, background) from 14 views
// around the reference's bounding sphere (6 along the axes, 8 along the diagonals), with one camera per
// view for both meshes, and compared pixel by pixel (docs/image-compare.md).
#pragma once

#include "lodforge/io/image_decode.h"
#include "lodforge/mesh.h"
#include "lodforge/metrics/image_error.h"

#include <functional>
#include <memory>
#include <vector>

namespace lodforge::render {

// `referenceImages` / `testImages`: the meshes' decoded base colour textures (decodeBaseColorTextures).
// Same meshes and parameters give the same numbers. Needs an X display (ensureDisplay is called).
// Throws Error(argument) for a size outside 16..4096 or a threshold outside 0..255, Error(invalid) for a
// mesh without triangles, Error(io) without a display or for PNGs that cannot be written (naming them).
ImageError compareImages(const Mesh& reference, const std::vector<std::shared_ptr<const Image>>& referenceImages,
                         const Mesh& test, const std::vector<std::shared_ptr<const Image>>& testImages,
                         const ImageErrorParams& params);

// The same, decoding both meshes' textures first (a texture that cannot be read is drawn untextured).
ImageError compareImages(const Mesh& reference, const Mesh& test, const ImageErrorParams& params);

// PackParams::image_error for the front ends: compareImages with `params`, the input's textures decoded
// once for all its levels (levels keep the input's materials, so they share its images when they have
// as many materials).
std::function<ImageError(const Mesh& input, const Mesh& level)> packImageError(const ImageErrorParams& params = {});

// One rendered view: RGB rows bottom-up as OpenGL reads them, and whether each pixel shows the mesh.
struct RenderedView {
    int size = 0;
    std::vector<unsigned char> rgb;   // size * size * 3
    std::vector<unsigned char> mask;  // size * size, 1 where the mesh covers the pixel
};

// `mesh` from each of the 14 views (names: viewNames()), framed on `frameOf`'s bounding sphere. For
// tests that look at the pictures themselves (the seam check). `unlit`: the surface colours (texture,
// vertex colours) without shading, so only what the texture shows differs.
std::vector<RenderedView> renderViews(const Mesh& mesh, const std::vector<std::shared_ptr<const Image>>& images,
                                      const Mesh& frameOf, int size, bool unlit = false);

const std::vector<std::string>& viewNames();

// Per view of renderViews(mesh, ..., frameOf, size): 1 where a UV seam of `mesh` is visible, a seam being
// an edge whose two triangles give its points different texture coordinates (set 0). No texture
// coordinates: empty masks. Vertices at bit-identical positions are one point (as the simplifier welds).
std::vector<std::vector<unsigned char>> seamMasks(const Mesh& mesh, const Mesh& frameOf, int size);

}  // namespace lodforge::render

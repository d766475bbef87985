// lodforge::Mesh -> VTK actors, drawn the way the studio draws them (textures, vertex colours, material
// colour, lighting). One library for the studio's views and the offscreen renderer of `compare --render`,
// so an image-space error measures what the artist sees in the studio. Qt-free; VTK in its headers.
#pragma once

#include "lodforge/io/image_decode.h"
#include "lodforge/mesh.h"
#include "lodforge/progress.h"

#include <vtkActor.h>
#include <vtkImageData.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkSmartPointer.h>
#include <vtkTexture.h>

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace lodforge::render {

// One material's triangles, ready for a mapper.
struct SurfacePart {
    std::string material;
    vtkSmartPointer<vtkPolyData> polyData;  // points, normals, optional RGBA colours and tcoords
    vtkSmartPointer<vtkImageData> texture;  // RGBA, rows bottom-up as VTK samples them; null if none
    std::array<double, 4> baseColor{1, 1, 1, 1};  // material base colour factor (linear RGBA)
    bool hasMaterial = false;
};

struct SurfaceParts {
    std::vector<SurfacePart> parts;
    bool hasColors = false;        // per-vertex RGBA colours
    bool computedNormals = false;  // the mesh had no normals; smooth ones were computed
};

// `materialImages[i]` is the decoded base colour texture of `mesh.materials[i]` (null where the material
// has none or it could not be decoded; materials sharing a file may share one Image); a shorter vector
// means no textures for the rest.
//
// Without `face_materials` the whole mesh is one part textured with the first material that has a
// decoded base colour texture; with `face_materials`, one part per material used. Normals are the mesh's
// own; a mesh without normals gets smooth normals per surface point (vertexNormals).
// Throws lodforge::Error(invalid) for an index or material out of range.
SurfaceParts buildSurfaceParts(const Mesh& mesh, const std::vector<std::shared_ptr<const Image>>& materialImages);

// The base colour texture of every material (index = material), each distinct file decoded once. A
// texture that cannot be read leaves null and a message in `warnings` (when given): the mesh is still
// worth drawing. A mesh without texture coordinates gets no images. Throws Error(cancelled) when
// `progress` asks to stop.
std::vector<std::shared_ptr<const Image>> decodeBaseColorTextures(const Mesh& mesh,
                                                                  std::vector<std::string>* warnings = nullptr,
                                                                  Progress* progress = nullptr);

// Per-vertex normals: the mesh's own when present, else area-weighted face normals summed per surface
// point (position_ids), so all wedges of a point share one normal. Points without area get +Z.
std::vector<Vec3f> vertexNormals(const Mesh& mesh);

// A vtkPolyData of the given triangles (indices into mesh.triangle_count(); all triangles when
// `triangles` is empty and `all` is set). Only the vertices these triangles use are copied. Attributes:
// normals (from `normals`), colours as unsigned char RGBA scalars named "Colors" when the mesh has
// colours, texture coordinates from `texcoordSet` when that set exists.
vtkSmartPointer<vtkPolyData> meshToPolyData(const Mesh& mesh, const std::vector<Vec3f>& normals,
                                            std::span<const std::uint32_t> triangles, bool all, int texcoordSet);

// RGBA image with its first row at the top -> vtkImageData with its first row at the bottom.
vtkSmartPointer<vtkImageData> imageToVtk(const Image& image);

// A part's actor and what its look depends on.
struct SurfaceActor {
    vtkSmartPointer<vtkActor> actor;
    vtkSmartPointer<vtkPolyDataMapper> mapper;
    vtkSmartPointer<vtkTexture> texture;  // null when the part has no texture
    bool hasTcoords = false;
    bool hasColors = false;
    bool hasMaterial = false;
    std::array<double, 4> baseColor{1, 1, 1, 1};
};

// Actor, mapper and (mipmapped, repeating) texture for a part; its look is set by applySurfaceLook.
SurfaceActor makeSurfaceActor(const SurfacePart& part);

// The lit look: ambient 0.12, diffuse 0.88, specular 0.08 (power 30), both faces. Colour: `texture`
// (the part's own, the studio's UV checker, or null for none) modulated by the material colour; vertex
// colours where no texture shows and `vertexColors` is set; else the material colour or neutral grey.
// Opacity: the material's alpha.
void applySurfaceLook(SurfaceActor& a, vtkTexture* texture, bool vertexColors, bool checker = false);

// The studio's solid background (also tells the model's pixels from the background in its tests).
inline constexpr std::array<unsigned char, 3> backgroundRgb{46, 52, 64};

}  // namespace lodforge::render

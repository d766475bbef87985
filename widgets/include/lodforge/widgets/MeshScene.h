// A mesh made ready for drawing: one part per material (sharing the mesh's vertex attributes), each with
// its decoded base colour texture. Building it is the slow part of showing a mesh, so it happens on the
// loading thread; the view only wraps the parts in actors. The type is opaque so that VTK, which holds
// the data, stays private to the widgets library.
#pragma once

#include "lodforge/io/image_decode.h"
#include "lodforge/pack/preset_levels.h"
#include "lodforge/mesh.h"

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace lodforge::widgets {

class MeshScene;

// `materialImages[i]` is the decoded base colour texture of `mesh.materials[i]` (null where the material
// has none or it could not be decoded; materials sharing a file may share one Image); a shorter vector
// means no textures for the rest.
//
// Parts: without `face_materials` the whole mesh is one part textured with the first material that has
// a decoded base colour texture; with `face_materials`, one part per material used, each with its own
// texture and base colour. Normals are the mesh's own; a mesh without normals gets smooth normals
// computed per surface point (`position_ids`), so wedges split at seams keep one shared normal.
// Throws lodforge::Error(invalid) for an index out of range, std::bad_alloc when memory runs out.
std::shared_ptr<const MeshScene> buildMeshScene(
    const lodforge::Mesh& mesh,
    const std::vector<std::shared_ptr<const lodforge::Image>>& materialImages);

// A heat map scene: `mesh`'s surface (one part, no materials, colours or texture) with one scalar per vertex
// (`values`, e.g. distances in model units) that the view colour-maps (viridis) over a range it is given.
// Throws lodforge::Error(argument) when the sizes differ.
std::shared_ptr<const MeshScene> buildScalarScene(const lodforge::Mesh& mesh, const std::vector<float>& values);

// A cells overlay scene: every cell's cube as its 12 edges (line segments), with two per-line colour
// arrays, by depth and by triangle count (cellDepthColor, cellTriangleColor); the view shows the one its
// options ask for. Empty `cells`: nullptr.
std::shared_ptr<const MeshScene> buildCellsScene(const std::vector<lodforge::StructureCell>& cells);

struct MeshScenePartInfo {
    std::string material;        // material name, empty when the mesh has no materials
    std::size_t points = 0;      // render vertices of this part
    std::size_t triangles = 0;
    bool textured = false;       // has texture coordinates and a decoded texture
    int textureWidth = 0;
    int textureHeight = 0;
};

struct MeshSceneInfo {
    std::vector<MeshScenePartInfo> parts;
    bool hasColors = false;       // per-vertex RGBA colours
    bool computedNormals = false; // the mesh had no normals; smooth ones were computed
    bool hasScalars = false;      // a heat map scene (buildScalarScene)
    bool isCells = false;         // a cells overlay scene (buildCellsScene)
    std::size_t lines = 0;        // its line segments
    double scalarMax = 0;         // its largest value
};

MeshSceneInfo describe(const MeshScene& scene);

}  // namespace lodforge::widgets

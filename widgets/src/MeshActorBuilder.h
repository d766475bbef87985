// lodforge::Mesh -> VTK data. Private to the widgets library: VTK must not leak into its public headers.
#pragma once

#include "lodforge/widgets/MeshScene.h"

#include <vtkImageData.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkStaticCellLocator.h>

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace lodforge::widgets {

class MeshScene {
public:
    struct Part {
        std::string material;
        vtkSmartPointer<vtkPolyData> polyData;  // points, normals, optional RGBA colours and tcoords
        vtkSmartPointer<vtkImageData> texture;  // RGBA, rows bottom-up as VTK samples them; null if none
        std::array<double, 4> baseColor{1, 1, 1, 1};  // material base colour factor (linear RGBA)
        bool hasMaterial = false;
        // Heat map parts: built with the scene (on the worker), so picking the value under the cursor
        // does not test every triangle on the GUI thread.
        vtkSmartPointer<vtkStaticCellLocator> locator;
    };

    std::vector<Part> parts;
    bool hasColors = false;
    bool computedNormals = false;
    // Heat map scenes: a float point array named scalarArrayName() on the single part.
    bool hasScalars = false;
    double scalarMax = 0;
    // Cells overlay scenes: one part of lines with the cell data colour arrays named below.
    bool isCells = false;
};

inline const char* scalarArrayName() { return "Scalars"; }
inline const char* cellDepthColorsName() { return "DepthColors"; }
inline const char* cellTriangleColorsName() { return "TriangleColors"; }

// Per-vertex normals: the mesh's own when present, else area-weighted face normals summed per surface
// point (position_ids), so all wedges of a point share one normal. Points without area get +Z.
std::vector<lodforge::Vec3f> vertexNormals(const lodforge::Mesh& mesh);

// A vtkPolyData of the given triangles (indices into mesh.triangle_count(); all triangles when
// `triangles` is empty and `all` is set). Only the vertices these triangles use are copied. Attributes:
// normals (from `normals`), colours as unsigned char RGBA scalars named "Colors" when the mesh has
// colours, texture coordinates from `texcoordSet` when that set exists.
vtkSmartPointer<vtkPolyData> meshToPolyData(const lodforge::Mesh& mesh,
                                            const std::vector<lodforge::Vec3f>& normals,
                                            std::span<const std::uint32_t> triangles, bool all,
                                            int texcoordSet);

// RGBA image with its first row at the top -> vtkImageData with its first row at the bottom.
vtkSmartPointer<vtkImageData> imageToVtk(const lodforge::Image& image);

}  // namespace lodforge::widgets

// lodforge::Mesh -> VTK data. Private to the widgets library: VTK must not leak into its public headers.
#pragma once

#include "lodforge/render/surface.h"
#include "lodforge/widgets/MeshScene.h"

#include <vtkSmartPointer.h>
#include <vtkStaticCellLocator.h>

#include <vector>

namespace lodforge::widgets {

class MeshScene {
public:
    // Parts are built by lodforge_render (render/surface.h), which the offscreen renderer shares.
    struct Part : render::SurfacePart {
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

}  // namespace lodforge::widgets

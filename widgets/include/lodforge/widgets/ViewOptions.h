// How the 3D view draws a mesh. One options model shared by the studio's View menu and its command line
// (`--wireframe`, `--flat`, `--no-texture`, `--no-colors`, `--edges`, `--normals`, `--uv-checker`), so both always mean the same thing.
#pragma once

#include <QColor>

#include <cstddef>

namespace lodforge::widgets {

struct ViewOptions {
    bool wireframe = false;     // draw triangle edges instead of filled surfaces
    bool flatShading = false;   // one normal per triangle instead of the interpolated vertex normals
    bool textures = true;       // apply base colour textures where the mesh has texture coordinates
    bool vertexColors = true;   // show per-vertex colours on parts that show no texture
    bool edges = false;         // triangle edges drawn over the shaded surface
    bool normalColors = false;  // colour = normal (x, y, z -> r, g, b), unlit: shows the shading normals
    bool uvChecker = false;     // a checker texture on the texture coordinates instead of the mesh's texture
    bool heatmapOutline = false;  // the original's silhouette drawn over a level's heat map
    int uvCheckerCells = 8;     // the checker's squares per unit of texture coordinate, each way (2..128)
    bool cells = false;         // the structure's cells (octree, MC octree) as wireframe boxes over the mesh
    bool cellsByTriangles = false;  // colour the cells by their triangle count instead of their depth

    friend bool operator==(const ViewOptions&, const ViewOptions&) = default;
};

inline constexpr int minUvCheckerCells = 2, maxUvCheckerCells = 128;

// The view's solid background. Tests and the screenshot checker use it to tell the model's pixels from
// the background, so it is one constant rather than a setting.
QColor viewBackgroundColor();  // the offscreen renderer's too (render::backgroundRgb)

// The cells overlay's line colours (docs/studio.md): one saturated hue per depth (cycling after eight);
// by triangle count, viridis over log(1 + triangles) / log(1 + the largest count of the scene).
QColor cellDepthColor(int depth);
QColor cellTriangleColor(double triangles, double maxTriangles);

// The continuous LOD view's strip colours: a hue from a hash of the strip index, so neighbouring strips
// (consecutive indices) differ clearly.
QColor stripColor(std::size_t strip);

}  // namespace lodforge::widgets

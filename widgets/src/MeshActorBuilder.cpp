#include "MeshActorBuilder.h"

#include "lodforge/error.h"
#include "lodforge/metrics/heatmap.h"
#include "lodforge/widgets/ViewOptions.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkFloatArray.h>
#include <vtkIdTypeArray.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iterator>
#include <limits>
#include <map>
#include <utility>

namespace lodforge::widgets {

std::shared_ptr<const MeshScene> buildMeshScene(const Mesh& mesh,
                                                const std::vector<std::shared_ptr<const Image>>& materialImages) {
    render::SurfaceParts built = render::buildSurfaceParts(mesh, materialImages);
    auto scene = std::make_shared<MeshScene>();
    scene->hasColors = built.hasColors;
    scene->computedNormals = built.computedNormals;
    scene->parts.reserve(built.parts.size());
    for (render::SurfacePart& part : built.parts) {
        MeshScene::Part p;
        static_cast<render::SurfacePart&>(p) = std::move(part);
        scene->parts.push_back(std::move(p));
    }
    return scene;
}

std::shared_ptr<const MeshScene> buildScalarScene(const Mesh& mesh, const std::vector<float>& values) {
    if (values.size() != mesh.vertex_count())
        throw Error(Error::Kind::argument, "heat map: " + std::to_string(values.size()) + " values for " +
                                               std::to_string(mesh.vertex_count()) + " vertices");
    auto scene = std::make_shared<MeshScene>();
    scene->computedNormals = mesh.normals.size() != mesh.vertex_count();
    const std::vector<Vec3f> normals = scene->computedNormals ? render::vertexNormals(mesh) : mesh.normals;
    MeshScene::Part part;
    part.polyData = render::meshToPolyData(mesh, normals, {}, true, -1);
    part.polyData->GetPointData()->SetScalars(nullptr);  // the mesh's colours are not shown on a heat map
    vtkNew<vtkFloatArray> scalars;
    scalars->SetName(scalarArrayName());
    scalars->SetNumberOfComponents(1);
    scalars->SetNumberOfTuples(static_cast<vtkIdType>(values.size()));
    std::copy(values.begin(), values.end(), scalars->GetPointer(0));
    part.polyData->GetPointData()->AddArray(scalars);
    part.locator = vtkSmartPointer<vtkStaticCellLocator>::New();
    part.locator->SetDataSet(part.polyData);
    part.locator->BuildLocator();
    scene->parts.push_back(std::move(part));
    scene->hasScalars = true;
    for (float v : values) scene->scalarMax = std::max(scene->scalarMax, double(v));
    return scene;
}

QColor viewBackgroundColor() {
    return QColor(render::backgroundRgb[0], render::backgroundRgb[1], render::backgroundRgb[2]);
}

QColor cellDepthColor(int depth) {
    // Far apart in hue and bright against the dark background, so neighbouring depths read apart.
    static const QColor palette[] = {{255, 80, 80},  {255, 200, 40}, {80, 220, 80},  {40, 200, 255},
                                     {170, 110, 255}, {255, 110, 220}, {255, 150, 60}, {220, 255, 120}};
    return palette[std::size_t(std::max(depth, 0)) % std::size(palette)];
}

QColor cellTriangleColor(double triangles, double maxTriangles) {
    const double t = maxTriangles > 0 ? std::log1p(std::max(triangles, 0.0)) / std::log1p(maxTriangles) : 0.0;
    const Vec4f c = viridis(static_cast<float>(std::clamp(t, 0.0, 1.0)));
    return QColor::fromRgbF(c.x, c.y, c.z);
}

std::shared_ptr<const MeshScene> buildCellsScene(const std::vector<StructureCell>& cells) {
    if (cells.empty()) return nullptr;
    double maxTriangles = 0;
    for (const StructureCell& c : cells) maxTriangles = std::max(maxTriangles, double(c.triangles));
    vtkNew<vtkPoints> points;
    points->SetDataTypeToFloat();
    points->SetNumberOfPoints(static_cast<vtkIdType>(cells.size() * 8));
    vtkNew<vtkCellArray> lines;
    lines->AllocateExact(static_cast<vtkIdType>(cells.size() * 12), static_cast<vtkIdType>(cells.size() * 24));
    vtkNew<vtkUnsignedCharArray> byDepth, byTriangles;
    for (auto [array, name] : {std::pair{byDepth.Get(), cellDepthColorsName()},
                               std::pair{byTriangles.Get(), cellTriangleColorsName()}}) {
        array->SetName(name);
        array->SetNumberOfComponents(3);
        array->SetNumberOfTuples(static_cast<vtkIdType>(cells.size() * 12));
    }
    // Corner k of a cube: x from bit 0, y from bit 1, z from bit 2; an edge joins corners one bit apart.
    static const int edges[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3},
                                     {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
    vtkIdType line = 0;
    for (std::size_t i = 0; i < cells.size(); ++i) {
        const StructureCell& c = cells[i];
        const auto base = static_cast<vtkIdType>(i * 8);
        for (int k = 0; k < 8; ++k)
            points->SetPoint(base + k, c.min[0] + ((k & 1) ? c.size : 0.f), c.min[1] + ((k & 2) ? c.size : 0.f),
                             c.min[2] + ((k & 4) ? c.size : 0.f));
        const QColor d = cellDepthColor(c.depth), t = cellTriangleColor(double(c.triangles), maxTriangles);
        for (const auto& e : edges) {
            const vtkIdType ids[2] = {base + e[0], base + e[1]};
            lines->InsertNextCell(2, ids);
            const unsigned char dc[3] = {static_cast<unsigned char>(d.red()), static_cast<unsigned char>(d.green()),
                                         static_cast<unsigned char>(d.blue())};
            const unsigned char tc[3] = {static_cast<unsigned char>(t.red()), static_cast<unsigned char>(t.green()),
                                         static_cast<unsigned char>(t.blue())};
            byDepth->SetTypedTuple(line, dc);
            byTriangles->SetTypedTuple(line, tc);
            ++line;
        }
    }
    auto scene = std::make_shared<MeshScene>();
    MeshScene::Part part;
    part.polyData = vtkSmartPointer<vtkPolyData>::New();
    part.polyData->SetPoints(points);
    part.polyData->SetLines(lines);
    part.polyData->GetCellData()->AddArray(byDepth);
    part.polyData->GetCellData()->AddArray(byTriangles);
    scene->parts.push_back(std::move(part));
    scene->isCells = true;
    return scene;
}

MeshSceneInfo describe(const MeshScene& scene) {
    MeshSceneInfo info;
    info.hasScalars = scene.hasScalars;
    info.isCells = scene.isCells;
    if (scene.isCells && !scene.parts.empty()) info.lines = std::size_t(scene.parts.front().polyData->GetNumberOfLines());
    info.scalarMax = scene.scalarMax;
    info.hasColors = scene.hasColors;
    info.computedNormals = scene.computedNormals;
    for (const MeshScene::Part& part : scene.parts) {
        MeshScenePartInfo p;
        p.material = part.material;
        p.points = static_cast<std::size_t>(part.polyData->GetNumberOfPoints());
        p.triangles = static_cast<std::size_t>(part.polyData->GetNumberOfPolys());
        p.textured = part.texture && part.polyData->GetPointData()->GetTCoords();
        if (part.texture) {
            int dims[3] = {0, 0, 0};
            part.texture->GetDimensions(dims);
            p.textureWidth = dims[0];
            p.textureHeight = dims[1];
        }
        info.parts.push_back(std::move(p));
    }
    return info;
}

}  // namespace lodforge::widgets

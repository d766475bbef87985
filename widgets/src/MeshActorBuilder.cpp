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

namespace {

constexpr std::uint32_t unmapped = std::numeric_limits<std::uint32_t>::max();

unsigned char toByte(float c) {
    if (!(c > 0.f)) return 0;  // also NaN
    if (c >= 1.f) return 255;
    return static_cast<unsigned char>(std::lround(c * 255.f));
}

std::string triangleIndexError(std::size_t triangle, std::uint32_t index, std::size_t vertices) {
    return "triangle " + std::to_string(triangle) + " uses vertex " + std::to_string(index) +
           " but the mesh has " + std::to_string(vertices) + " vertices";
}

}  // namespace

std::vector<Vec3f> vertexNormals(const Mesh& mesh) {
    const std::size_t vertexCount = mesh.vertex_count();
    const bool haveIds = mesh.position_ids.size() == vertexCount && vertexCount > 0;
    std::size_t pointCount = vertexCount;
    if (haveIds) pointCount = *std::max_element(mesh.position_ids.begin(), mesh.position_ids.end()) + 1u;
    auto pointOf = [&](std::uint32_t v) -> std::size_t { return haveIds ? mesh.position_ids[v] : v; };

    std::vector<Vec3f> sums(pointCount);
    const std::size_t triangleCount = mesh.triangle_count();
    for (std::size_t t = 0; t < triangleCount; ++t) {
        const std::uint32_t a = mesh.indices[3 * t], b = mesh.indices[3 * t + 1], c = mesh.indices[3 * t + 2];
        if (a >= vertexCount || b >= vertexCount || c >= vertexCount) continue;  // reported by meshToPolyData
        // Unnormalised cross product: faces contribute in proportion to their area.
        const Vec3f n = cross(mesh.positions[b] - mesh.positions[a], mesh.positions[c] - mesh.positions[a]);
        if (!is_finite(n)) continue;
        for (std::uint32_t v : {a, b, c}) {
            Vec3f& s = sums[pointOf(v)];
            s = s + n;
        }
    }
    for (Vec3f& s : sums) {
        const float len = length(s);
        s = len > 0.f && std::isfinite(len) ? s * (1.f / len) : Vec3f{0, 0, 1};
    }
    std::vector<Vec3f> normals(vertexCount);
    for (std::size_t v = 0; v < vertexCount; ++v) normals[v] = sums[pointOf(static_cast<std::uint32_t>(v))];
    return normals;
}

vtkSmartPointer<vtkPolyData> meshToPolyData(const Mesh& mesh, const std::vector<Vec3f>& normals,
                                            std::span<const std::uint32_t> triangles, bool all,
                                            int texcoordSet) {
    const std::size_t vertexCount = mesh.vertex_count();
    const std::size_t triangleCount = all ? mesh.triangle_count() : triangles.size();
    auto triangleAt = [&](std::size_t i) -> std::size_t { return all ? i : triangles[i]; };

    // Vertex selection: every vertex for the whole mesh (ids stay the mesh's), else only the used ones.
    std::vector<std::uint32_t> used;       // output vertex -> mesh vertex
    std::vector<std::uint32_t> remap;      // mesh vertex -> output vertex (parts only)
    if (!all) {
        remap.assign(vertexCount, unmapped);
        used.reserve(std::min(vertexCount, triangleCount * 3));
    }

    vtkNew<vtkIdTypeArray> offsets;
    offsets->SetNumberOfValues(static_cast<vtkIdType>(triangleCount + 1));
    vtkNew<vtkIdTypeArray> connectivity;
    connectivity->SetNumberOfValues(static_cast<vtkIdType>(triangleCount * 3));
    vtkIdType* offsetOut = offsets->GetPointer(0);
    vtkIdType* connOut = connectivity->GetPointer(0);
    for (std::size_t i = 0; i < triangleCount; ++i) {
        const std::size_t t = triangleAt(i);
        offsetOut[i] = static_cast<vtkIdType>(3 * i);
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t v = mesh.indices[3 * t + static_cast<std::size_t>(k)];
            if (v >= vertexCount) throw Error(Error::Kind::invalid, triangleIndexError(t, v, vertexCount));
            std::uint32_t out = v;
            if (!all) {
                if (remap[v] == unmapped) {
                    remap[v] = static_cast<std::uint32_t>(used.size());
                    used.push_back(v);
                }
                out = remap[v];
            }
            connOut[3 * i + static_cast<std::size_t>(k)] = out;
        }
    }
    offsetOut[triangleCount] = static_cast<vtkIdType>(3 * triangleCount);

    const std::size_t outCount = all ? vertexCount : used.size();
    auto source = [&](std::size_t i) -> std::size_t { return all ? i : used[i]; };

    vtkNew<vtkFloatArray> positions;
    positions->SetNumberOfComponents(3);
    positions->SetNumberOfTuples(static_cast<vtkIdType>(outCount));
    float* p = positions->GetPointer(0);
    for (std::size_t i = 0; i < outCount; ++i) {
        const Vec3f& v = mesh.positions[source(i)];
        p[3 * i] = v.x;
        p[3 * i + 1] = v.y;
        p[3 * i + 2] = v.z;
    }
    vtkNew<vtkPoints> points;
    points->SetData(positions);

    auto polyData = vtkSmartPointer<vtkPolyData>::New();
    polyData->SetPoints(points);
    vtkNew<vtkCellArray> polys;
    polys->SetData(offsets, connectivity);
    polyData->SetPolys(polys);

    if (normals.size() == vertexCount) {
        vtkNew<vtkFloatArray> n;
        n->SetName("Normals");
        n->SetNumberOfComponents(3);
        n->SetNumberOfTuples(static_cast<vtkIdType>(outCount));
        float* out = n->GetPointer(0);
        for (std::size_t i = 0; i < outCount; ++i) {
            const Vec3f& v = normals[source(i)];
            out[3 * i] = v.x;
            out[3 * i + 1] = v.y;
            out[3 * i + 2] = v.z;
        }
        polyData->GetPointData()->SetNormals(n);
    }
    if (mesh.colors.size() == vertexCount) {
        vtkNew<vtkUnsignedCharArray> c;
        c->SetName("Colors");
        c->SetNumberOfComponents(4);
        c->SetNumberOfTuples(static_cast<vtkIdType>(outCount));
        unsigned char* out = c->GetPointer(0);
        for (std::size_t i = 0; i < outCount; ++i) {
            const Vec4f& v = mesh.colors[source(i)];
            out[4 * i] = toByte(v.x);
            out[4 * i + 1] = toByte(v.y);
            out[4 * i + 2] = toByte(v.z);
            out[4 * i + 3] = toByte(v.w);
        }
        polyData->GetPointData()->SetScalars(c);
    }
    if (texcoordSet >= 0 && static_cast<std::size_t>(texcoordSet) < mesh.texcoords.size() &&
        mesh.texcoords[static_cast<std::size_t>(texcoordSet)].size() == vertexCount) {
        const auto& uv = mesh.texcoords[static_cast<std::size_t>(texcoordSet)];
        vtkNew<vtkFloatArray> t;
        t->SetName("TCoords");
        t->SetNumberOfComponents(2);
        t->SetNumberOfTuples(static_cast<vtkIdType>(outCount));
        float* out = t->GetPointer(0);
        for (std::size_t i = 0; i < outCount; ++i) {
            const Vec2f& v = uv[source(i)];
            out[2 * i] = v.x;
            out[2 * i + 1] = v.y;
        }
        polyData->GetPointData()->SetTCoords(t);
    }
    return polyData;
}

vtkSmartPointer<vtkImageData> imageToVtk(const Image& image) {
    if (image.empty() || image.width <= 0 || image.height <= 0 ||
        image.rgba.size() != static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height) * 4u)
        return nullptr;
    auto data = vtkSmartPointer<vtkImageData>::New();
    data->SetDimensions(image.width, image.height, 1);
    data->AllocateScalars(VTK_UNSIGNED_CHAR, 4);
    auto* out = static_cast<unsigned char*>(data->GetScalarPointer());
    const std::size_t rowBytes = static_cast<std::size_t>(image.width) * 4u;
    const std::size_t rows = static_cast<std::size_t>(image.height);
    // lodforge::Image starts with the top row; VTK's image origin is the bottom-left corner, which is
    // where texture coordinate (0, 0) samples.
    for (std::size_t row = 0; row < rows; ++row)
        std::memcpy(out + row * rowBytes, image.rgba.data() + (rows - 1 - row) * rowBytes, rowBytes);
    return data;
}

std::shared_ptr<const MeshScene> buildMeshScene(const Mesh& mesh,
                                                const std::vector<std::shared_ptr<const Image>>& materialImages) {
    auto scene = std::make_shared<MeshScene>();
    scene->hasColors = mesh.colors.size() == mesh.vertex_count() && mesh.vertex_count() > 0;
    scene->computedNormals = mesh.normals.size() != mesh.vertex_count();
    const std::vector<Vec3f> computed = scene->computedNormals ? vertexNormals(mesh) : std::vector<Vec3f>{};
    const std::vector<Vec3f>& normals = scene->computedNormals ? computed : mesh.normals;

    auto imageOf = [&](std::size_t material) -> const Image* {
        if (material >= materialImages.size() || !materialImages[material] || materialImages[material]->empty())
            return nullptr;
        return materialImages[material].get();
    };
    std::map<const Image*, vtkSmartPointer<vtkImageData>> converted;  // materials sharing an image
    auto textureOf = [&](std::size_t material) -> vtkSmartPointer<vtkImageData> {
        const Image* image = imageOf(material);
        if (!image || !mesh.has_texcoords()) return nullptr;
        auto [it, inserted] = converted.try_emplace(image);
        if (inserted) it->second = imageToVtk(*image);
        return it->second;
    };
    auto texcoordSetOf = [&](std::size_t material) -> int {
        if (mesh.texcoords.empty()) return -1;
        int set = material < mesh.materials.size() ? mesh.materials[material].base_color_texture.texcoord_set : 0;
        if (set < 0 || static_cast<std::size_t>(set) >= mesh.texcoords.size()) set = 0;
        return set;
    };
    auto makePart = [&](std::size_t material, std::span<const std::uint32_t> triangles, bool all) {
        MeshScene::Part part;
        if (material < mesh.materials.size()) {
            const Material& m = mesh.materials[material];
            part.material = m.name;
            part.baseColor = {m.base_color.x, m.base_color.y, m.base_color.z, m.base_color.w};
            part.hasMaterial = true;
        }
        part.texture = textureOf(material);
        part.polyData = meshToPolyData(mesh, normals, triangles, all, texcoordSetOf(material));
        scene->parts.push_back(std::move(part));
    };

    const std::size_t triangleCount = mesh.triangle_count();
    if (mesh.face_materials.empty() || mesh.materials.empty()) {
        // One part. Its texture: the first material that has a decoded base colour texture.
        std::size_t material = 0;
        for (std::size_t m = 0; m < mesh.materials.size(); ++m) {
            if (imageOf(m)) {
                material = m;
                break;
            }
        }
        makePart(material, {}, true);
        return scene;
    }

    if (mesh.face_materials.size() != triangleCount)
        throw Error(Error::Kind::invalid, "the mesh has " + std::to_string(triangleCount) + " triangles but " +
                                              std::to_string(mesh.face_materials.size()) + " face materials");
    std::vector<std::vector<std::uint32_t>> groups(mesh.materials.size());
    for (std::size_t t = 0; t < triangleCount; ++t) {
        const std::uint32_t m = mesh.face_materials[t];
        if (m >= mesh.materials.size())
            throw Error(Error::Kind::invalid, "triangle " + std::to_string(t) + " uses material " +
                                                  std::to_string(m) + " but the mesh has " +
                                                  std::to_string(mesh.materials.size()) + " materials");
        groups[m].push_back(static_cast<std::uint32_t>(t));
    }
    for (std::size_t m = 0; m < groups.size(); ++m) {
        if (groups[m].empty()) continue;
        if (groups[m].size() == triangleCount) {
            // A single material for everything: keep the mesh's vertex ids, no copy of the index list.
            groups[m].clear();
            groups[m].shrink_to_fit();
            makePart(m, {}, true);
            break;
        }
        makePart(m, groups[m], false);
        groups[m].clear();
        groups[m].shrink_to_fit();
    }
    return scene;
}

std::shared_ptr<const MeshScene> buildScalarScene(const Mesh& mesh, const std::vector<float>& values) {
    if (values.size() != mesh.vertex_count())
        throw Error(Error::Kind::argument, "heat map: " + std::to_string(values.size()) + " values for " +
                                               std::to_string(mesh.vertex_count()) + " vertices");
    auto scene = std::make_shared<MeshScene>();
    scene->computedNormals = mesh.normals.size() != mesh.vertex_count();
    const std::vector<Vec3f> normals = scene->computedNormals ? vertexNormals(mesh) : mesh.normals;
    MeshScene::Part part;
    part.polyData = meshToPolyData(mesh, normals, {}, true, -1);
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

#include "lodforge/render/surface.h"

#include "lodforge/error.h"

#include <vtkCellArray.h>
#include <vtkFloatArray.h>
#include <vtkIdTypeArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkProperty.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <utility>

namespace lodforge::render {

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
        // RGB only: the mesh model has no blend mode, and glTF's default (OPAQUE) ignores a colour's alpha.
        // With RGBA scalars VTK draws the surface in its translucent pass, which writes no depth: the
        // image compare's coverage mask came out empty and RGBA-coloured levels measured 0.
        c->SetNumberOfComponents(3);
        c->SetNumberOfTuples(static_cast<vtkIdType>(outCount));
        unsigned char* out = c->GetPointer(0);
        for (std::size_t i = 0; i < outCount; ++i) {
            const Vec4f& v = mesh.colors[source(i)];
            out[3 * i] = toByte(v.x);
            out[3 * i + 1] = toByte(v.y);
            out[3 * i + 2] = toByte(v.z);
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

SurfaceParts buildSurfaceParts(const Mesh& mesh, const std::vector<std::shared_ptr<const Image>>& materialImages) {
    SurfaceParts out;
    out.hasColors = mesh.colors.size() == mesh.vertex_count() && mesh.vertex_count() > 0;
    out.computedNormals = mesh.normals.size() != mesh.vertex_count();
    const std::vector<Vec3f> computed = out.computedNormals ? vertexNormals(mesh) : std::vector<Vec3f>{};
    const std::vector<Vec3f>& normals = out.computedNormals ? computed : mesh.normals;

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
        SurfacePart part;
        if (material < mesh.materials.size()) {
            const Material& m = mesh.materials[material];
            part.material = m.name;
            part.baseColor = {m.base_color.x, m.base_color.y, m.base_color.z, m.base_color.w};
            part.hasMaterial = true;
        }
        part.texture = textureOf(material);
        part.polyData = meshToPolyData(mesh, normals, triangles, all, texcoordSetOf(material));
        out.parts.push_back(std::move(part));
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
        return out;
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
    return out;
}


std::vector<std::shared_ptr<const Image>> decodeBaseColorTextures(const Mesh& mesh, std::vector<std::string>* warnings,
                                                                  Progress* progress) {
    std::vector<std::shared_ptr<const Image>> images(mesh.materials.size());
    if (!mesh.has_texcoords()) return images;
    std::map<std::string, std::shared_ptr<const Image>> byFile;  // resolved path -> image
    const std::size_t count = mesh.materials.size();
    for (std::size_t m = 0; m < count; ++m) {
        check_progress(progress, static_cast<double>(m) / static_cast<double>(count), "Decoding textures");
        const TextureRef& texture = mesh.materials[m].base_color_texture;
        if (texture.empty()) continue;
        const std::string file = texture.bytes.empty() ? mesh.resolve_texture_path(texture) : std::string{};
        if (!file.empty()) {
            if (auto it = byFile.find(file); it != byFile.end()) {
                images[m] = it->second;
                continue;
            }
        }
        try {
            auto image = std::make_shared<const Image>(decode_texture(mesh, texture));
            images[m] = image;
            if (!file.empty()) byFile.emplace(file, image);
        } catch (const Error& e) {
            if (e.kind() == Error::Kind::cancelled) throw;
            if (warnings) warnings->push_back(e.what());
            if (!file.empty()) byFile.emplace(file, nullptr);
        }
    }
    check_progress(progress, 1.0, "Decoding textures");
    return images;
}

namespace {

// Neutral material for surfaces with neither texture nor colours.
constexpr double neutralGrey[3] = {0.78, 0.78, 0.80};

double linearToSrgb(double c) {
    if (!(c > 0.0)) return 0.0;
    if (c >= 1.0) return 1.0;
    return c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
}

}  // namespace

SurfaceActor makeSurfaceActor(const SurfacePart& part) {
    SurfaceActor a;
    a.mapper = vtkSmartPointer<vtkPolyDataMapper>::New();
    a.mapper->SetInputData(part.polyData);
    a.mapper->SetScalarModeToUsePointData();
    a.mapper->SetColorModeToDirectScalars();
    a.actor = vtkSmartPointer<vtkActor>::New();
    a.actor->SetMapper(a.mapper);
    a.hasTcoords = part.polyData->GetPointData()->GetTCoords() != nullptr;
    a.hasColors = part.polyData->GetPointData()->GetScalars() != nullptr;
    a.hasMaterial = part.hasMaterial;
    a.baseColor = part.baseColor;
    if (part.texture && a.hasTcoords) {
        a.texture = vtkSmartPointer<vtkTexture>::New();
        a.texture->SetInputData(part.texture);
        a.texture->InterpolateOn();
        a.texture->MipmapOn();
        a.texture->RepeatOn();
        a.texture->SetColorModeToDirectScalars();
    }
    vtkProperty* property = a.actor->GetProperty();
    property->SetSpecularPower(30.0);
    property->BackfaceCullingOff();
    property->SetEdgeColor(0.08, 0.08, 0.1);
    return a;
}

void applySurfaceLook(SurfaceActor& a, vtkTexture* texture, bool vertexColors, bool checker) {
    vtkProperty* property = a.actor->GetProperty();
    property->SetAmbient(0.12);
    property->SetDiffuse(0.88);
    property->SetSpecular(0.08);
    a.mapper->SetScalarModeToUsePointData();
    a.mapper->SetColorModeToDirectScalars();

    const bool showTexture = texture != nullptr;
    const bool showColors = !showTexture && vertexColors && a.hasColors;
    a.actor->SetTexture(texture);
    a.mapper->SetScalarVisibility(showColors);

    property->SetOpacity(a.hasMaterial ? std::clamp(a.baseColor[3], 0.0, 1.0) : 1.0);
    const bool whiteMaterial =
        !a.hasMaterial || (a.baseColor[0] >= 1.0 && a.baseColor[1] >= 1.0 && a.baseColor[2] >= 1.0);
    if (showColors || (showTexture && checker)) {
        property->SetColor(1.0, 1.0, 1.0);
    } else if (showTexture || !whiteMaterial) {
        // A texture is modulated by the material's colour factor, as glTF defines it.
        property->SetColor(linearToSrgb(a.baseColor[0]), linearToSrgb(a.baseColor[1]), linearToSrgb(a.baseColor[2]));
    } else {
        property->SetColor(neutralGrey[0], neutralGrey[1], neutralGrey[2]);
    }
}

}  // namespace lodforge::render

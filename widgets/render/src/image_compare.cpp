#include "lodforge/render/image_compare.h"

#include "lodforge/error.h"
#include "lodforge/render/offscreen_display.h"
#include "lodforge/render/surface.h"

#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkFloatArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <set>
#include <string>

namespace lodforge::render {

namespace {

struct ViewDirection {
    std::array<double, 3> toEye;  // unit, from the centre towards the camera
    std::array<double, 3> up;
};

const std::vector<ViewDirection>& viewDirections() {
    static const std::vector<ViewDirection> views = [] {
        std::vector<ViewDirection> v;
        // Axes. Looking along Y, "up" is -Z / +Z so the picture is not rolled arbitrarily.
        v.push_back({{1, 0, 0}, {0, 1, 0}});
        v.push_back({{-1, 0, 0}, {0, 1, 0}});
        v.push_back({{0, 1, 0}, {0, 0, -1}});
        v.push_back({{0, -1, 0}, {0, 0, 1}});
        v.push_back({{0, 0, 1}, {0, 1, 0}});
        v.push_back({{0, 0, -1}, {0, 1, 0}});
        const double k = 1.0 / std::sqrt(3.0);
        for (int sx : {1, -1})
            for (int sy : {1, -1})
                for (int sz : {1, -1}) v.push_back({{sx * k, sy * k, sz * k}, {0, 1, 0}});
        return v;
    }();
    return views;
}

// Bounds of the vertices triangles use: unused vertices must not move the camera.
Bounds usedBounds(const Mesh& mesh) {
    Bounds b;
    for (std::uint32_t i : mesh.indices)
        if (i < mesh.positions.size()) b.add(mesh.positions[i]);
    return b;
}

struct Sphere {
    std::array<double, 3> centre{0, 0, 0};
    double radius = 1;
};

Sphere sphereOf(const Bounds& b) {
    Sphere s;
    s.centre = {0.5 * (double(b.min.x) + b.max.x), 0.5 * (double(b.min.y) + b.max.y), 0.5 * (double(b.min.z) + b.max.z)};
    const double dx = double(b.max.x) - b.min.x, dy = double(b.max.y) - b.min.y, dz = double(b.max.z) - b.min.z;
    s.radius = 0.5 * std::sqrt(dx * dx + dy * dy + dz * dz);
    if (!(s.radius > 0)) s.radius = 1;
    return s;
}

// One offscreen window for all the views of a comparison (a GL context costs more than a picture).
class OffscreenRenderer {
public:
    explicit OffscreenRenderer(int size) : size_(size) {
        ensureDisplay();
        window_->SetOffScreenRendering(1);
        window_->SetMultiSamples(0);
        window_->SetSize(size, size);
        window_->AddRenderer(renderer_);
        renderer_->SetBackground(backgroundRgb[0] / 255.0, backgroundRgb[1] / 255.0, backgroundRgb[2] / 255.0);
        renderer_->SetTwoSidedLighting(true);
    }
    ~OffscreenRenderer() { window_->Finalize(); }
    OffscreenRenderer(const OffscreenRenderer&) = delete;
    OffscreenRenderer& operator=(const OffscreenRenderer&) = delete;

    // `overlay`: drawn too (the seam lines); `plain`: the surface untextured and uncoloured (grey);
    // `unlit`: colours as they are, no shading.
    std::vector<RenderedView> render(const Mesh& mesh, const std::vector<std::shared_ptr<const Image>>& images,
                                     const Sphere& frame, const Sphere& clip, vtkActor* overlay = nullptr,
                                     bool plain = false, bool unlit = false) {
        const SurfaceParts parts = buildSurfaceParts(mesh, images);
        std::vector<SurfaceActor> actors;
        for (const SurfacePart& part : parts.parts) {
            SurfaceActor a = makeSurfaceActor(part);
            applySurfaceLook(a, plain ? nullptr : a.texture.Get(), !plain);
            if (unlit) {
                a.actor->GetProperty()->SetAmbient(1.0);
                a.actor->GetProperty()->SetDiffuse(0.0);
                a.actor->GetProperty()->SetSpecular(0.0);
            }
            renderer_->AddActor(a.actor);
            actors.push_back(std::move(a));
        }
        if (overlay) renderer_->AddActor(overlay);
        vtkCamera* camera = renderer_->GetActiveCamera();
        const double angle = 30.0;  // the studio's (VTK's default) view angle
        const double distance = frame.radius / std::sin(angle * 0.5 * 3.14159265358979323846 / 180.0);
        // Everything of both meshes between the planes, with no depth to spare: depth precision matters
        // for the silhouettes of nearly coplanar parts.
        const double dc = std::sqrt(std::pow(clip.centre[0] - frame.centre[0], 2) +
                                    std::pow(clip.centre[1] - frame.centre[1], 2) +
                                    std::pow(clip.centre[2] - frame.centre[2], 2));
        const double reach = dc + clip.radius * 1.01;
        std::vector<RenderedView> out;
        for (const ViewDirection& v : viewDirections()) {
            camera->SetViewAngle(angle);
            camera->SetFocalPoint(frame.centre.data());
            camera->SetPosition(frame.centre[0] + v.toEye[0] * distance, frame.centre[1] + v.toEye[1] * distance,
                                frame.centre[2] + v.toEye[2] * distance);
            camera->SetViewUp(v.up.data());
            camera->OrthogonalizeViewUp();
            camera->SetClippingRange(std::max(distance - reach, distance * 1e-3), distance + reach);
            window_->Render();
            out.push_back(grab());
        }
        for (const SurfaceActor& a : actors) renderer_->RemoveActor(a.actor);
        if (overlay) renderer_->RemoveActor(overlay);
        return out;
    }

private:
    RenderedView grab() {
        RenderedView view;
        view.size = size_;
        const int last = size_ - 1;
        vtkNew<vtkUnsignedCharArray> rgb;
        window_->GetPixelData(0, 0, last, last, 1, rgb);  // the frame just rendered, as vtkWindowToImageFilter reads it
        view.rgb.assign(rgb->GetPointer(0), rgb->GetPointer(0) + std::size_t(size_) * std::size_t(size_) * 3);
        vtkNew<vtkFloatArray> depth;
        window_->GetZbufferData(0, 0, last, last, depth);
        view.mask.resize(std::size_t(size_) * std::size_t(size_));
        for (std::size_t i = 0; i < view.mask.size(); ++i) view.mask[i] = depth->GetValue(vtkIdType(i)) < 1.0f ? 1 : 0;
        return view;
    }

    int size_;
    vtkNew<vtkRenderWindow> window_;
    vtkNew<vtkRenderer> renderer_;
};

void checkMesh(const Mesh& mesh, const char* role) {
    if (mesh.triangle_count() == 0 || usedBounds(mesh).empty())
        throw Error(Error::Kind::invalid, std::string("image compare: the ") + role + " mesh has no triangles");
}

void writePng(const std::string& path, int width, int height, const std::vector<unsigned char>& rgb) {
    vtkNew<vtkImageData> image;
    image->SetDimensions(width, height, 1);
    image->AllocateScalars(VTK_UNSIGNED_CHAR, 3);
    std::copy(rgb.begin(), rgb.end(), static_cast<unsigned char*>(image->GetScalarPointer()));
    vtkNew<vtkPNGWriter> writer;
    writer->SetInputData(image);
    writer->SetFileName(path.c_str());
    writer->Write();
    if (writer->GetErrorCode() != 0 || !std::filesystem::exists(path))
        throw Error(Error::Kind::io, path + ": cannot write the PNG");
}

// Side by side (reference | test) and the difference: |reference - test| per channel times 4, and
// magenta where only one of the two covers the pixel.
void writeViewImages(const std::string& dir, std::size_t index, const std::string& name, const RenderedView& a,
                     const RenderedView& b, std::vector<std::string>& files) {
    const int n = a.size;
    std::vector<unsigned char> side(std::size_t(n) * std::size_t(n) * 6);
    std::vector<unsigned char> diff(std::size_t(n) * std::size_t(n) * 3);
    for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x) {
            const std::size_t p = std::size_t(y) * std::size_t(n) + std::size_t(x);
            for (int c = 0; c < 3; ++c) {
                side[(std::size_t(y) * std::size_t(2 * n) + std::size_t(x)) * 3 + std::size_t(c)] = a.rgb[3 * p + std::size_t(c)];
                side[(std::size_t(y) * std::size_t(2 * n) + std::size_t(n + x)) * 3 + std::size_t(c)] = b.rgb[3 * p + std::size_t(c)];
                const int d = std::abs(int(a.rgb[3 * p + std::size_t(c)]) - int(b.rgb[3 * p + std::size_t(c)]));
                diff[3 * p + std::size_t(c)] = static_cast<unsigned char>(std::min(255, 4 * d));
            }
            if (a.mask[p] != b.mask[p]) {
                diff[3 * p] = 255;
                diff[3 * p + 1] = 0;
                diff[3 * p + 2] = 255;
            }
        }
    }
    const std::string prefix = (index < 10 ? "0" : "") + std::to_string(index);
    const std::string base = (std::filesystem::path(dir) / (prefix + "_" + name)).string();
    writePng(base + "_side.png", 2 * n, n, side);
    writePng(base + "_diff.png", n, n, diff);
    files.push_back(base + "_side.png");
    files.push_back(base + "_diff.png");
}

ViewImageError compareView(const std::string& name, const RenderedView& a, const RenderedView& b, int threshold) {
    ViewImageError v;
    v.name = name;
    double sum = 0;
    std::size_t over = 0, silhouette = 0;
    for (std::size_t p = 0; p < a.mask.size(); ++p) {
        if (!a.mask[p] && !b.mask[p]) continue;
        ++v.covered;
        int total = 0, largest = 0;
        for (std::size_t c = 0; c < 3; ++c) {
            const int d = std::abs(int(a.rgb[3 * p + c]) - int(b.rgb[3 * p + c]));
            total += d;
            largest = std::max(largest, d);
        }
        sum += total / 3.0;
        if (largest > threshold) ++over;
        if (a.mask[p] != b.mask[p]) ++silhouette;
    }
    if (v.covered > 0) {
        const auto c = static_cast<double>(v.covered);
        v.mean_abs = sum / c;
        v.over_threshold = static_cast<double>(over) / c;
        v.silhouette = static_cast<double>(silhouette) / c;
    }
    return v;
}

void checkSize(int size) {
    if (size < 16 || size > 4096)
        throw Error(Error::Kind::argument, "image compare: the size must be 16..4096 pixels, not " + std::to_string(size));
}

}  // namespace

const std::vector<std::string>& viewNames() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> out;
        auto sign = [](double v) { return v > 0 ? std::string("+") : std::string("-"); };
        for (const ViewDirection& v : viewDirections()) {
            std::string name;
            const char axes[3] = {'x', 'y', 'z'};
            for (int k = 0; k < 3; ++k)
                if (v.toEye[std::size_t(k)] != 0) name += sign(v.toEye[std::size_t(k)]) + axes[k];
            out.push_back(name);
        }
        return out;
    }();
    return names;
}

std::vector<RenderedView> renderViews(const Mesh& mesh, const std::vector<std::shared_ptr<const Image>>& images,
                                      const Mesh& frameOf, int size, bool unlit) {
    checkSize(size);
    checkMesh(mesh, "rendered");
    checkMesh(frameOf, "framing");
    Bounds both = usedBounds(frameOf);
    const Bounds own = usedBounds(mesh);
    both.add(own.min);
    both.add(own.max);
    OffscreenRenderer renderer(size);
    return renderer.render(mesh, images, sphereOf(usedBounds(frameOf)), sphereOf(both), nullptr, false, unlit);
}

std::vector<std::vector<unsigned char>> seamMasks(const Mesh& mesh, const Mesh& frameOf, int size) {
    checkSize(size);
    checkMesh(mesh, "rendered");
    checkMesh(frameOf, "framing");
    // Seam edges: a point pair whose triangles give it different texture coordinates on either side.
    vtkNew<vtkPoints> points;
    vtkNew<vtkCellArray> lines;
    if (mesh.has_texcoords() && mesh.texcoords.front().size() == mesh.vertex_count()) {
        const auto& uv = mesh.texcoords.front();
        // Points: vertices at bit-identical positions are one (glTF splits every seam vertex without
        // saying which belong together; the simplifier welds them the same way).
        std::map<std::array<std::uint32_t, 3>, std::uint32_t> byPosition;
        std::vector<std::uint32_t> point(mesh.vertex_count());
        for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
            const Vec3f& p = mesh.positions[v];
            const std::array<std::uint32_t, 3> key{std::bit_cast<std::uint32_t>(p.x), std::bit_cast<std::uint32_t>(p.y),
                                                   std::bit_cast<std::uint32_t>(p.z)};
            point[v] = byPosition.try_emplace(key, static_cast<std::uint32_t>(byPosition.size())).first->second;
        }
        auto pointOf = [&](std::uint32_t v) { return point[v]; };
        // Edge (by points, smaller first) -> the wedge pair of the first triangle seen, in the same order.
        std::map<std::pair<std::uint32_t, std::uint32_t>, std::pair<std::uint32_t, std::uint32_t>> first;
        std::set<std::pair<std::uint32_t, std::uint32_t>> seams;
        for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
            for (int k = 0; k < 3; ++k) {
                std::uint32_t a = mesh.indices[t + std::size_t(k)], b = mesh.indices[t + std::size_t((k + 1) % 3)];
                if (a >= mesh.vertex_count() || b >= mesh.vertex_count()) continue;
                if (pointOf(a) > pointOf(b)) std::swap(a, b);
                const std::pair key{pointOf(a), pointOf(b)};
                const auto [it, inserted] = first.try_emplace(key, a, b);
                if (inserted) continue;
                const auto [fa, fb] = it->second;
                if (!(uv[fa] == uv[a]) || !(uv[fb] == uv[b])) seams.insert(key);
            }
        }
        std::map<std::uint32_t, vtkIdType> pointIds;
        auto idOf = [&](std::uint32_t wedge) {
            const auto [it, inserted] = pointIds.try_emplace(pointOf(wedge), 0);
            if (inserted) {
                const Vec3f& p = mesh.positions[wedge];
                it->second = points->InsertNextPoint(p.x, p.y, p.z);
            }
            return it->second;
        };
        for (const auto& key : seams) {
            const auto [a, b] = first.at(key);
            const vtkIdType line[2] = {idOf(a), idOf(b)};
            lines->InsertNextCell(2, line);
        }
    }
    vtkNew<vtkPolyData> seamData;
    seamData->SetPoints(points);
    seamData->SetLines(lines);
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputData(seamData);
    mapper->ScalarVisibilityOff();
    // The lines lie on the surface: drawn in front of it where it is visible, hidden where it is not.
    mapper->SetRelativeCoincidentTopologyLineOffsetParameters(-1, -100);
    vtkNew<vtkActor> actor;
    actor->SetMapper(mapper);
    actor->GetProperty()->SetLighting(false);
    actor->GetProperty()->SetColor(1.0, 0.0, 1.0);
    actor->GetProperty()->SetLineWidth(1.0f);

    Bounds both = usedBounds(frameOf);
    const Bounds own = usedBounds(mesh);
    both.add(own.min);
    both.add(own.max);
    OffscreenRenderer renderer(size);
    const std::vector<RenderedView> views =
        renderer.render(mesh, {}, sphereOf(usedBounds(frameOf)), sphereOf(both), actor, true);
    std::vector<std::vector<unsigned char>> masks;
    for (const RenderedView& v : views) {
        std::vector<unsigned char> m(v.mask.size(), 0);
        for (std::size_t p = 0; p < m.size(); ++p)
            m[p] = v.rgb[3 * p] == 255 && v.rgb[3 * p + 1] == 0 && v.rgb[3 * p + 2] == 255 ? 1 : 0;
        masks.push_back(std::move(m));
    }
    return masks;
}

ImageError compareImages(const Mesh& reference, const std::vector<std::shared_ptr<const Image>>& referenceImages,
                         const Mesh& test, const std::vector<std::shared_ptr<const Image>>& testImages,
                         const ImageErrorParams& params) {
    checkSize(params.size);
    if (params.threshold < 0 || params.threshold > 255)
        throw Error(Error::Kind::argument,
                    "image compare: the threshold must be 0..255, not " + std::to_string(params.threshold));
    checkMesh(reference, "reference");
    checkMesh(test, "test");
    if (!params.output_dir.empty()) {
        std::error_code ec;
        std::filesystem::create_directories(params.output_dir, ec);
        if (ec) throw Error(Error::Kind::io, params.output_dir + ": cannot create the directory (" + ec.message() + ")");
    }
    const Bounds referenceBounds = usedBounds(reference);
    Bounds both = referenceBounds;
    const Bounds testBounds = usedBounds(test);
    both.add(testBounds.min);
    both.add(testBounds.max);
    const Sphere frame = sphereOf(referenceBounds), clip = sphereOf(both);

    OffscreenRenderer renderer(params.size);
    const std::vector<RenderedView> a = renderer.render(reference, referenceImages, frame, clip);
    const std::vector<RenderedView> b = renderer.render(test, testImages, frame, clip);

    ImageError out;
    out.size = params.size;
    out.threshold = params.threshold;
    const std::vector<std::string>& names = viewNames();
    for (std::size_t k = 0; k < a.size(); ++k) {
        out.views.push_back(compareView(names[k], a[k], b[k], params.threshold));
        if (!params.output_dir.empty()) writeViewImages(params.output_dir, k, names[k], a[k], b[k], out.files);
    }
    summarize_image_error(out);
    return out;
}

ImageError compareImages(const Mesh& reference, const Mesh& test, const ImageErrorParams& params) {
    return compareImages(reference, decodeBaseColorTextures(reference), test, decodeBaseColorTextures(test), params);
}

std::function<ImageError(const Mesh&, const Mesh&)> packImageError(const ImageErrorParams& params) {
    struct Cache {
        const Mesh* input = nullptr;
        std::vector<std::shared_ptr<const Image>> images;
    };
    auto cache = std::make_shared<Cache>();
    return [cache, params](const Mesh& input, const Mesh& level) {
        if (cache->input != &input) {
            cache->images = decodeBaseColorTextures(input);
            cache->input = &input;
        }
        const bool shared = level.materials.size() == input.materials.size() && level.source_dir == input.source_dir;
        return compareImages(input, cache->images, level, shared ? cache->images : decodeBaseColorTextures(level),
                             params);
    };
}

}  // namespace lodforge::render

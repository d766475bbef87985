#include "lodforge/io/mesh_validate.h"

#include "lodforge/error.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <sstream>

namespace lodforge {
namespace {

class FindingBuilder {
public:
    FindingBuilder(ValidationFinding::Severity severity, std::string code, std::size_t max_examples)
        : max_examples_(max_examples) {
        finding_.severity = severity;
        finding_.code = std::move(code);
    }
    void add(std::size_t index) {
        if (finding_.examples.size() < max_examples_) finding_.examples.push_back(index);
        ++finding_.count;
    }
    void add_many(std::size_t count) { finding_.count += count; }
    std::size_t count() const { return finding_.count; }
    // `what` is the plural noun phrase, `item`/`items` name the example kind ("face"/"faces").
    void emit(ValidationReport& report, const std::string& what, const std::string& item,
              const std::string& items) {
        if (finding_.count == 0) return;
        std::ostringstream s;
        s << finding_.count << ' ' << what;
        if (!finding_.examples.empty()) {
            s << " (e.g. " << (finding_.examples.size() > 1 ? items : item) << ' ';
            for (std::size_t i = 0; i < finding_.examples.size(); ++i) s << (i ? ", " : "") << finding_.examples[i];
            s << ')';
        }
        finding_.message = s.str();
        report.findings.push_back(std::move(finding_));
    }

private:
    ValidationFinding finding_;
    std::size_t max_examples_;
};

bool finite2(Vec2f v) { return std::isfinite(v.x) && std::isfinite(v.y); }
bool finite4(Vec4f v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) && std::isfinite(v.w); }

// Vertex v's attributes in the spans that are present (empty spans are absent attributes).
bool finite_attributes(std::span<const Vec3f> normals, std::span<const Vec4f> colors,
                       std::span<const Vec2f> texcoords, std::size_t v) {
    return (normals.empty() || is_finite(normals[v])) && (colors.empty() || finite4(colors[v])) &&
           (texcoords.empty() || finite2(texcoords[v]));
}

std::string extent_message(const Bounds& b) {
    std::ostringstream s;
    s << "coordinates too large: the bounding box (" << b.min.x << ", " << b.min.y << ", " << b.min.z << ") .. ("
      << b.max.x << ", " << b.max.y << ", " << b.max.z << ") has a diagonal beyond the float range; scale the model down";
    return s.str();
}

}  // namespace

bool ValidationReport::has_errors() const {
    return std::any_of(findings.begin(), findings.end(),
                       [](const auto& f) { return f.severity == ValidationFinding::Severity::error; });
}

const ValidationFinding* ValidationReport::find(const std::string& code) const {
    for (const auto& f : findings)
        if (f.code == code) return &f;
    return nullptr;
}

ValidationReport validate(const Mesh& mesh, const ValidationParams& params) {
    using Severity = ValidationFinding::Severity;
    ValidationReport report;
    const std::size_t n = mesh.positions.size();
    const std::size_t max_ex = params.max_examples;

    FindingBuilder sizes(Severity::error, "array_size_mismatch", max_ex);
    if (!mesh.normals.empty() && mesh.normals.size() != n) sizes.add_many(1);
    if (!mesh.colors.empty() && mesh.colors.size() != n) sizes.add_many(1);
    for (const auto& set : mesh.texcoords)
        if (set.size() != n) sizes.add_many(1);
    if (!mesh.position_ids.empty() && mesh.position_ids.size() != n) sizes.add_many(1);
    if (mesh.indices.size() % 3 != 0) sizes.add_many(1);
    if (!mesh.face_materials.empty() && mesh.face_materials.size() != mesh.triangle_count()) sizes.add_many(1);
    sizes.emit(report, "attribute arrays whose length does not match their element count", "array", "arrays");
    if (report.has_errors()) return report;  // the checks below index these arrays

    FindingBuilder nan_pos(Severity::error, "non_finite_position", max_ex);
    for (std::size_t v = 0; v < n; ++v)
        if (!is_finite(mesh.positions[v])) nan_pos.add(v);
    nan_pos.emit(report, "vertices with NaN or infinite coordinates", "vertex", "vertices");

    // Finite coordinates whose bounding-box diagonal overflows float (extent beyond ~1.8e19): every
    // command measures in fractions of that diagonal, so they all went wrong without a word (errors
    // "-nan of the diagonal inf", cluster simplification to 0 triangles, a crash in mcoctree build).
    if (nan_pos.count() == 0 && n > 0) {
        const Bounds b = mesh.bounds();
        if (!std::isfinite(b.diagonal())) {
            ValidationFinding f;
            f.severity = Severity::error;
            f.code = "extent_overflow";
            f.count = 1;
            f.message = extent_message(b);
            report.findings.push_back(std::move(f));
        }
    }

    FindingBuilder nan_attr(Severity::error, "non_finite_attribute", max_ex);
    for (std::size_t v = 0; v < n; ++v) {
        bool bad = !finite_attributes(mesh.normals, mesh.colors, {}, v);
        for (const auto& set : mesh.texcoords) bad = bad || !finite2(set[v]);
        if (bad) nan_attr.add(v);
    }
    nan_attr.emit(report, "vertices with NaN or infinite normals, colours or texture coordinates", "vertex", "vertices");

    const std::size_t tris = mesh.triangle_count();
    FindingBuilder range(Severity::error, "index_out_of_range", max_ex);
    for (std::size_t t = 0; t < tris; ++t)
        for (int k = 0; k < 3; ++k)
            if (mesh.indices[3 * t + k] >= n) { range.add(t); break; }
    range.emit(report, "triangles referencing a vertex that does not exist", "face", "faces");

    FindingBuilder material(Severity::error, "material_out_of_range", max_ex);
    for (std::size_t t = 0; t < mesh.face_materials.size(); ++t)
        if (mesh.face_materials[t] >= mesh.materials.size()) material.add(t);
    material.emit(report, "triangles referencing a material that does not exist", "face", "faces");
    if (report.has_errors()) return report;

    // Topology is judged on surface points, not wedges: two wedges of one point are one vertex.
    auto point = [&](std::uint32_t v) -> std::uint32_t {
        return mesh.position_ids.empty() ? v : mesh.position_ids[v];
    };

    FindingBuilder degenerate(Severity::warning, "degenerate_triangle", max_ex);
    FindingBuilder zero_area(Severity::warning, "zero_area_triangle", max_ex);
    std::vector<std::array<std::uint32_t, 4>> sorted_faces;  // 3 sorted points + face index
    sorted_faces.reserve(tris);
    for (std::size_t t = 0; t < tris; ++t) {
        const std::uint32_t a = point(mesh.indices[3 * t]), b = point(mesh.indices[3 * t + 1]),
                            c = point(mesh.indices[3 * t + 2]);
        if (a == b || b == c || a == c) { degenerate.add(t); continue; }
        const Vec3f& pa = mesh.positions[mesh.indices[3 * t]];
        const Vec3f& pb = mesh.positions[mesh.indices[3 * t + 1]];
        const Vec3f& pc = mesh.positions[mesh.indices[3 * t + 2]];
        const Vec3f nrm = cross(pb - pa, pc - pa);
        if (nrm.x == 0.f && nrm.y == 0.f && nrm.z == 0.f) zero_area.add(t);
        std::array<std::uint32_t, 4> key{a, b, c, static_cast<std::uint32_t>(t)};
        std::sort(key.begin(), key.begin() + 3);
        sorted_faces.push_back(key);
    }
    degenerate.emit(report, "degenerate triangles (a vertex repeated)", "face", "faces");
    zero_area.emit(report, "triangles with zero area", "face", "faces");

    FindingBuilder duplicate(Severity::warning, "duplicate_triangle", max_ex);
    std::sort(sorted_faces.begin(), sorted_faces.end());
    for (std::size_t i = 1; i < sorted_faces.size(); ++i)
        if (std::equal(sorted_faces[i].begin(), sorted_faces[i].begin() + 3, sorted_faces[i - 1].begin()))
            duplicate.add(sorted_faces[i][3]);
    duplicate.emit(report, "duplicate triangles (same three vertices as an earlier face)", "face", "faces");

    // Sorting packed edge keys beats a hash map here and keeps memory at 8 bytes per half-edge.
    std::vector<std::uint64_t> edges;
    edges.reserve(sorted_faces.size() * 3);
    for (const auto& f : sorted_faces) {
        edges.push_back((std::uint64_t(f[0]) << 32) | f[1]);
        edges.push_back((std::uint64_t(f[1]) << 32) | f[2]);
        edges.push_back((std::uint64_t(f[0]) << 32) | f[2]);
    }
    std::sort(edges.begin(), edges.end());
    FindingBuilder non_manifold(Severity::warning, "non_manifold_edge", max_ex);
    for (std::size_t i = 0; i < edges.size();) {
        std::size_t j = i;
        while (j < edges.size() && edges[j] == edges[i]) ++j;
        if (j - i > 2) non_manifold.add(static_cast<std::size_t>(edges[i] >> 32));
        i = j;
    }
    non_manifold.emit(report, "non-manifold edges (shared by more than two triangles)", "edge at point", "edges at points");

    // A mesh without triangles is a point cloud (valid input for the marching-cube octree), where
    // unreferenced vertices are the point of the file rather than a defect.
    if (tris == 0) return report;
    FindingBuilder unused(Severity::warning, "unreferenced_vertex", max_ex);
    std::vector<bool> used(mesh.point_count(), false);
    for (std::uint32_t v : mesh.indices) used[point(v)] = true;
    for (std::size_t p = 0; p < used.size(); ++p)
        if (!used[p]) unused.add(p);
    unused.emit(report, "vertices not used by any triangle", "vertex", "vertices");
    return report;
}

void check_vertex_chunk(const std::string& path, std::size_t first, std::span<const Vec3f> positions,
                        std::span<const Vec3f> normals, std::span<const Vec4f> colors,
                        std::span<const Vec2f> texcoords) {
    for (std::size_t v = 0; v < positions.size(); ++v) {
        if (!is_finite(positions[v]))
            throw_error(Error::Kind::invalid, path, "vertex " + std::to_string(first + v) +
                                                        " has a NaN or infinite coordinate");
        if (!finite_attributes(normals, colors, texcoords, v))
            throw_error(Error::Kind::invalid, path, "vertex " + std::to_string(first + v) +
                                                        " has a NaN or infinite normal, colour or texture coordinate");
    }
}

void check_extent(const std::string& path, const Bounds& bounds) {
    if (!bounds.empty() && !std::isfinite(bounds.diagonal())) throw_error(Error::Kind::invalid, path, extent_message(bounds));
}

}  // namespace lodforge

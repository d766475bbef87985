// Heat maps of per-vertex scalars. Colour map: viridis (van der Walt & Smith, matplotlib 2015), its nine
// standard stops interpolated linearly in sRGB (within a few 1/255 of the 256-entry table).
#include "lodforge/metrics/heatmap.h"

#include "lodforge/io/atomic_file.h"
#include "lodforge/error.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>

namespace lodforge {
namespace {

// viridis at 0, 1/8, ..., 1 (#440154 #472d7b #3b528b #2c728e #21918c #28ae80 #5ec962 #addc30 #fde725).
constexpr std::uint8_t kViridis[9][3] = {
    {68, 1, 84},    {71, 45, 123},  {59, 82, 139},  {44, 114, 142}, {33, 145, 140},
    {40, 174, 128}, {94, 201, 98},  {173, 220, 48}, {253, 231, 37},
};

template <typename T>
void put(std::string& buf, T value) {
    static_assert(std::endian::native == std::endian::little, "the heat map writer assumes a little-endian host");
    char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));
    buf.append(bytes, sizeof(T));
}

// std::to_string prints six decimals, which reads 0.000000 for a range of a few micrometres in metres.
std::string format_range(float v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", double(v));
    return buf;
}

std::uint8_t to_byte(float c) { return static_cast<std::uint8_t>(std::lround(std::clamp(c, 0.f, 1.f) * 255.f)); }

}  // namespace

Vec4f viridis(float t) {
    if (!(t > 0.f)) t = 0.f;  // NaN too
    t = std::min(t, 1.f);
    const float x = t * 8.f;
    const int i = std::min(static_cast<int>(x), 7);
    const float f = x - static_cast<float>(i);
    const std::uint8_t* a = kViridis[i];
    const std::uint8_t* b = kViridis[i + 1];
    auto channel = [&](int c) { return (static_cast<float>(a[c]) + (static_cast<float>(b[c]) - a[c]) * f) / 255.f; };
    return {channel(0), channel(1), channel(2), 1.f};
}

Heatmap make_heatmap(const Mesh& mesh, const std::vector<float>& values, float range_max) {
    if (values.size() != mesh.vertex_count())
        throw Error(Error::Kind::argument, "make_heatmap: " + std::to_string(values.size()) + " values for " +
                                               std::to_string(mesh.vertex_count()) + " vertices");
    float largest = 0.f;
    for (std::size_t i = 0; i < values.size(); ++i) {
        if (!(values[i] >= 0.f) || !std::isfinite(values[i]))
            throw Error(Error::Kind::argument,
                        "make_heatmap: value " + std::to_string(i) + " is negative or not finite");
        largest = std::max(largest, values[i]);
    }
    if (!std::isfinite(range_max)) throw Error(Error::Kind::argument, "make_heatmap: range_max must be finite");
    Heatmap h;
    h.range_max = range_max > 0.f ? range_max : largest;
    h.mesh = mesh;
    h.quality = values;
    h.mesh.colors.resize(mesh.vertex_count());
    const float inv = h.range_max > 0.f ? 1.f / h.range_max : 0.f;
    for (std::size_t i = 0; i < values.size(); ++i) h.mesh.colors[i] = viridis(values[i] * inv);
    return h;
}

float heatmap_range(const Mesh& mesh, const std::vector<float>& values, float percentile) {
    if (values.size() != mesh.vertex_count())
        throw Error(Error::Kind::argument, "heatmap_range: " + std::to_string(values.size()) + " values for " +
                                               std::to_string(mesh.vertex_count()) + " vertices");
    if (!(percentile > 0.f && percentile <= 1.f))
        throw Error(Error::Kind::argument, "heatmap_range: the percentile must be in (0, 1]");
    std::vector<char> used(values.size(), 0);
    for (std::uint32_t i : mesh.indices)
        if (i < used.size()) used[i] = 1;
    std::vector<float> kept;
    kept.reserve(values.size());
    for (std::size_t i = 0; i < values.size(); ++i)
        if (used[i] && values[i] >= 0.f && std::isfinite(values[i])) kept.push_back(values[i]);
    if (kept.empty()) return 0.f;
    // The smallest value with at least `percentile` of the values at or below it (nearest rank).
    // The float percentile back to the decimal it was written as (0.99f is 0.9900000095...), so that
    // 99 % of 100 values is rank 99, not 100.
    const double p = std::round(double(percentile) * 1e6) / 1e6;
    const auto rank = static_cast<std::size_t>(std::ceil(p * double(kept.size())));
    const auto nth = kept.begin() + static_cast<std::ptrdiff_t>(std::clamp<std::size_t>(rank, 1, kept.size()) - 1);
    std::nth_element(kept.begin(), nth, kept.end());
    return *nth;
}

void write_heatmap_ply(const Heatmap& heatmap, const std::string& path) {
    const Mesh& m = heatmap.mesh;
    if (heatmap.quality.size() != m.vertex_count() || m.colors.size() != m.vertex_count())
        throw Error(Error::Kind::argument, "write_heatmap_ply: quality and colours must have one value per vertex");
    AtomicFile file(path);
    std::string header = "ply\nformat binary_little_endian 1.0\ncomment lodforge error heat map (quality = distance, "
                         "viridis 0.." + format_range(heatmap.range_max) + ")\n";
    header += "element vertex " + std::to_string(m.vertex_count()) + "\n";
    header += "property float x\nproperty float y\nproperty float z\nproperty float quality\n";
    header += "property uchar red\nproperty uchar green\nproperty uchar blue\nproperty uchar alpha\n";
    header += "element face " + std::to_string(m.triangle_count()) + "\n";
    header += "property list uchar int vertex_indices\nend_header\n";
    file.stream().write(header.data(), static_cast<std::streamsize>(header.size()));
    std::string buf;
    buf.reserve(1 << 20);
    auto flush = [&] {
        file.stream().write(buf.data(), static_cast<std::streamsize>(buf.size()));
        buf.clear();
    };
    for (std::size_t v = 0; v < m.vertex_count(); ++v) {
        const Vec3f p = m.positions[v];
        const Vec4f c = m.colors[v];
        put(buf, p.x);
        put(buf, p.y);
        put(buf, p.z);
        put(buf, heatmap.quality[v]);
        put(buf, to_byte(c.x));
        put(buf, to_byte(c.y));
        put(buf, to_byte(c.z));
        put(buf, to_byte(c.w));
        if (buf.size() > (1u << 20)) flush();
    }
    for (std::size_t f = 0; f < m.triangle_count(); ++f) {
        put(buf, std::uint8_t{3});
        for (int k = 0; k < 3; ++k) put(buf, static_cast<std::int32_t>(m.indices[3 * f + k]));
        if (buf.size() > (1u << 20)) flush();
    }
    flush();
    file.commit();
}

}  // namespace lodforge

// Seam classes: the simplifier's notion of a seam (simplify.cpp: faces on either side of an edge using
// different wedges; border and non-manifold edges by their face counts), told apart by which attribute
// differs.
#include "lodforge/simplify/seams.h"

#include "lodforge/error.h"
#include "simplify/simplify_weld.h"

#include <algorithm>
#include <cmath>
#include <charconv>
#include <numbers>
#include <string>

namespace lodforge {

std::string_view to_string(SeamClass c) {
    constexpr std::array<std::string_view, kSeamClasses> names{"uv", "uv_mirror", "crease", "material",
                                                               "color", "border", "non_manifold"};
    return names[static_cast<int>(c)];
}

SeamReport classify_seams(const Mesh& mesh, const SeamParams& params) {
    std::vector<std::uint32_t> representative;
    const std::vector<std::uint32_t> point = simplify_detail::derive_points(mesh, true, 0.f, representative);
    // Edge (a, b) on points, a < b, from every face corner: (a, b, face, wedge at a, wedge at b).
    struct Half {
        std::uint32_t a, b, face, wa, wb;
    };
    std::vector<Half> halves;
    halves.reserve(mesh.indices.size());
    for (std::uint32_t f = 0; f < mesh.triangle_count(); ++f) {
        const std::uint32_t* c = &mesh.indices[3 * f];
        for (int k = 0; k < 3; ++k) {
            std::uint32_t wa = c[k], wb = c[(k + 1) % 3];
            if (point[wa] == point[wb]) continue;
            if (point[wa] > point[wb]) std::swap(wa, wb);
            halves.push_back({point[wa], point[wb], f, wa, wb});
        }
    }
    std::sort(halves.begin(), halves.end(), [](const Half& x, const Half& y) {
        return x.a != y.a ? x.a < y.a : x.b != y.b ? x.b < y.b : x.face < y.face;
    });
    SeamReport r;
    r.uv_set_edges.assign(mesh.texcoords.size(), 0);
    const float crease_cos = std::cos(params.crease_angle_degrees * std::numbers::pi_v<float> / 180.f);
    auto uv_orientation = [&](std::uint32_t f) {
        const auto& t = mesh.texcoords[0];
        const std::uint32_t* c = &mesh.indices[3 * f];
        const Vec2f p = t[c[0]], q = t[c[1]], s = t[c[2]];
        const double area = (double(q.x) - p.x) * (double(s.y) - p.y) - (double(q.y) - p.y) * (double(s.x) - p.x);
        return area > 0 ? 1 : area < 0 ? -1 : 0;
    };
    auto differ = [&](const Half& x, const Half& y, auto&& attribute_differs) {
        return attribute_differs(x.wa, y.wa) || attribute_differs(x.wb, y.wb);
    };
    for (std::size_t i = 0; i < halves.size();) {
        std::size_t j = i;
        while (j < halves.size() && halves[j].a == halves[i].a && halves[j].b == halves[i].b) ++j;
        const std::pair<std::uint32_t, std::uint32_t> edge{representative[halves[i].a], representative[halves[i].b]};
        auto add = [&](SeamClass c) { r.edges[static_cast<int>(c)].push_back(edge); };
        ++r.edge_count;
        if (j - i == 1) add(SeamClass::border);
        else if (j - i > 2) add(SeamClass::non_manifold);
        else {
            const Half& x = halves[i];
            const Half& y = halves[i + 1];
            bool uv = false;
            for (std::size_t s = 0; s < mesh.texcoords.size(); ++s) {
                const auto& t = mesh.texcoords[s];
                if (t.empty()) continue;
                const bool seam = differ(x, y, [&](std::uint32_t u, std::uint32_t w) {
                    return t[u].x != t[w].x || t[u].y != t[w].y;
                });
                r.uv_set_edges[s] += seam;
                uv = uv || seam;
            }
            if (uv) add(SeamClass::uv);
            if (!mesh.texcoords.empty() && !mesh.texcoords[0].empty() &&
                uv_orientation(x.face) * uv_orientation(y.face) < 0)
                add(SeamClass::uv_mirror);
            if (mesh.has_normals() && differ(x, y, [&](std::uint32_t u, std::uint32_t w) {
                    const Vec3f n = mesh.normals[u], m = mesh.normals[w];
                    const float l = length(n) * length(m);
                    return l > 0 && dot(n, m) < crease_cos * l;
                }))
                add(SeamClass::crease);
            if (!mesh.face_materials.empty() && mesh.face_materials[x.face] != mesh.face_materials[y.face])
                add(SeamClass::material);
            if (mesh.has_colors() && differ(x, y, [&](std::uint32_t u, std::uint32_t w) {
                    const Vec4f a = mesh.colors[u], b = mesh.colors[w];
                    const float d = std::max({std::abs(a.x - b.x), std::abs(a.y - b.y), std::abs(a.z - b.z), std::abs(a.w - b.w)});
                    return d > params.color_tolerance;
                }))
                add(SeamClass::color);
        }
        i = j;
    }
    return r;
}

std::vector<float> parse_seam_weights(std::string_view text) {
    auto fail = [&](const std::string& why) -> void {
        throw Error(Error::Kind::argument, "seams '" + std::string(text) + "': " + why);
    };
    constexpr std::string_view prefix = "weight=";
    if (text.substr(0, prefix.size()) != prefix) fail("give weight=CLASS:W,...; per-class protect and allow are not supported");
    std::vector<float> weights(kSeamClasses, 1.f);
    std::string_view rest = text.substr(prefix.size());
    while (true) {
        const std::size_t comma = rest.find(',');
        const std::string_view item = rest.substr(0, comma);
        const std::size_t colon = item.find(':');
        if (colon == std::string_view::npos) fail("'" + std::string(item) + "' is not CLASS:W");
        const std::string_view name = item.substr(0, colon), number = item.substr(colon + 1);
        int c = 0;
        while (c < kSeamClasses && to_string(SeamClass(c)) != name) ++c;
        if (c == kSeamClasses)
            fail("unknown seam class '" + std::string(name) + "' (uv, uv_mirror, crease, material, color, border, non_manifold)");
        float w = 0;
        const auto [end, ec] = std::from_chars(number.data(), number.data() + number.size(), w);
        if (ec != std::errc() || end != number.data() + number.size() || !(w > 0.f) || !std::isfinite(w))
            fail("the weight of " + std::string(name) + " must be a finite number > 0");
        weights[std::size_t(c)] = w;
        if (comma == std::string_view::npos) break;
        rest = rest.substr(comma + 1);
    }
    return weights;
}

}  // namespace lodforge

#include "lodforge/skeleton.h"

#include "lodforge/mesh.h"

#include <algorithm>
#include <utility>

namespace lodforge {

float Animation::duration() const {
    float end = 0.f;
    for (const AnimationSampler& s : samplers)
        if (!s.input.empty()) end = std::max(end, s.input.back());
    return end;
}

namespace {

struct Influence {
    std::uint16_t joint = 0;
    float weight = 0.f;
};

// The vertex's positive influences over every set, one entry per joint (a joint listed twice, which
// glTF forbids but exporters write, has its weights added).
std::vector<Influence> influences_of(const Mesh& mesh, std::size_t v) {
    std::vector<Influence> list;
    const std::size_t sets = std::min(mesh.joints.size(), mesh.weights.size());
    for (std::size_t s = 0; s < sets; ++s) {
        const Joints4& j = mesh.joints[s][v];
        const Vec4f& w = mesh.weights[s][v];
        const float ws[4] = {w.x, w.y, w.z, w.w};
        for (int c = 0; c < 4; ++c) {
            if (!(ws[c] > 0.f)) continue;
            auto it = std::find_if(list.begin(), list.end(), [&](const Influence& i) { return i.joint == j[static_cast<std::size_t>(c)]; });
            if (it != list.end()) it->weight += ws[c];
            else list.push_back({j[static_cast<std::size_t>(c)], ws[c]});
        }
    }
    return list;
}

}  // namespace

void limit_influences(Mesh& mesh, std::size_t max_influences) {
    if (mesh.joints.empty()) return;
    const std::size_t n = mesh.vertex_count();
    std::size_t keep = max_influences;
    if (keep == 0) keep = std::max<std::size_t>(max_influence_count(mesh), 1);
    const std::size_t sets = (keep + 3) / 4;
    std::vector<std::vector<Joints4>> joints(sets, std::vector<Joints4>(n, Joints4{0, 0, 0, 0}));
    std::vector<std::vector<Vec4f>> weights(sets, std::vector<Vec4f>(n, Vec4f{}));
    for (std::size_t v = 0; v < n; ++v) {
        std::vector<Influence> list = influences_of(mesh, v);
        // Heaviest first; equal weights by joint so the result does not depend on the set order.
        std::sort(list.begin(), list.end(), [](const Influence& a, const Influence& b) {
            return a.weight != b.weight ? a.weight > b.weight : a.joint < b.joint;
        });
        if (list.size() > keep) list.resize(keep);
        double sum = 0;
        for (const Influence& i : list) sum += i.weight;
        if (list.empty() || !(sum > 0)) {
            list = {{0, 1.f}};
            sum = 1;
        }
        for (std::size_t k = 0; k < list.size(); ++k) {
            joints[k / 4][v][k % 4] = list[k].joint;
            Vec4f& w = weights[k / 4][v];
            float& slot = k % 4 == 0 ? w.x : k % 4 == 1 ? w.y : k % 4 == 2 ? w.z : w.w;
            slot = static_cast<float>(list[k].weight / sum);
        }
    }
    mesh.joints = std::move(joints);
    mesh.weights = std::move(weights);
}

void carry_influences(const Mesh& from, const std::vector<std::uint32_t>& from_vertex, Mesh& to) {
    if (from.joints.empty()) return;
    to.joints.assign(from.joints.size(), std::vector<Joints4>(from_vertex.size()));
    to.weights.assign(from.weights.size(), std::vector<Vec4f>(from_vertex.size()));
    for (std::size_t i = 0; i < from_vertex.size(); ++i) {
        for (std::size_t s = 0; s < from.joints.size(); ++s) to.joints[s][i] = from.joints[s][from_vertex[i]];
        for (std::size_t s = 0; s < from.weights.size(); ++s) to.weights[s][i] = from.weights[s][from_vertex[i]];
    }
    to.skeleton = from.skeleton;
}

std::size_t max_influence_count(const Mesh& mesh) {
    std::size_t most = 0;
    for (std::size_t v = 0; v < mesh.vertex_count() && !mesh.joints.empty(); ++v)
        most = std::max(most, influences_of(mesh, v).size());
    return most;
}

}  // namespace lodforge

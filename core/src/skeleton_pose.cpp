// Posing a skinned mesh: node transforms from the animation samplers, then linear blend skinning.
//
// Based on:
//  - the glTF 2.0 specification, §3.7.3 "Skins" (joint matrix = world(joint) · inverse bind matrix, the
//    skinned node's own transform ignored) and §3.11 / Appendix C "Animation Sampler Interpolation
//    Modes" (LINEAR with spherical linear interpolation for rotations, STEP, CUBICSPLINE Hermite splines
//    with tangents scaled by the key interval, rotations renormalised);
//  - N. Magnenat-Thalmann, R. Laperrière, D. Thalmann, "Joint-dependent local deformations for hand
//    animation and object grasping", Graphics Interface 1988 (linear blend skinning: the vertex moved by
//    the weighted sum of its joints' matrices).
#include "lodforge/skeleton_pose.h"

#include "lodforge/error.h"
#include "lodforge/skeleton.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <optional>

namespace lodforge {

namespace {

using Eigen::Matrix4d;
using Eigen::Quaterniond;
using Eigen::Vector3d;

struct NodePose {
    std::optional<Vector3d> translation, scale;
    std::optional<Quaterniond> rotation;
};

// The sampler's value at `time`: `components` numbers (a rotation renormalised by the caller).
std::optional<std::vector<double>> sample(const AnimationSampler& s, double time, bool rotation) {
    const std::size_t n = s.input.size();
    const std::size_t c = static_cast<std::size_t>(std::max(s.components, 1));
    const bool cubic = s.interpolation == "CUBICSPLINE";
    if (n == 0 || s.output.size() < n * c * (cubic ? 3 : 1)) return std::nullopt;  // unusable: skip the channel
    auto value = [&](std::size_t k) { return &s.output[(cubic ? 3 * k + 1 : k) * c]; };
    auto as_vector = [&](const float* p) { return std::vector<double>(p, p + c); };
    if (time <= s.input.front() || n == 1) return as_vector(value(0));
    if (time >= s.input.back()) return as_vector(value(n - 1));
    const std::size_t k = static_cast<std::size_t>(std::upper_bound(s.input.begin(), s.input.end(), float(time)) -
                                                   s.input.begin()) - 1;
    const double t0 = s.input[k], t1 = s.input[k + 1], dt = t1 - t0;
    const double u = dt > 0 ? (time - t0) / dt : 0.0;
    if (s.interpolation == "STEP") return as_vector(value(k));
    std::vector<double> out(c);
    if (cubic) {
        const float* out_tangent = &s.output[(3 * k + 2) * c];
        const float* in_tangent = &s.output[(3 * (k + 1)) * c];
        const double u2 = u * u, u3 = u2 * u;
        for (std::size_t i = 0; i < c; ++i)
            out[i] = (2 * u3 - 3 * u2 + 1) * value(k)[i] + (u3 - 2 * u2 + u) * dt * out_tangent[i] +
                     (-2 * u3 + 3 * u2) * value(k + 1)[i] + (u3 - u2) * dt * in_tangent[i];
        return out;
    }
    if (rotation && c == 4) {
        const float* a = value(k);
        const float* b = value(k + 1);
        const Quaterniond q = Quaterniond(a[3], a[0], a[1], a[2]).normalized().slerp(
            u, Quaterniond(b[3], b[0], b[1], b[2]).normalized());
        return std::vector<double>{q.x(), q.y(), q.z(), q.w()};
    }
    for (std::size_t i = 0; i < c; ++i) out[i] = (1 - u) * value(k)[i] + u * value(k + 1)[i];
    return out;
}

Matrix4d local_matrix(const SkeletonNode& node, const NodePose& pose) {
    const bool animated = pose.translation || pose.rotation || pose.scale;
    if (node.matrix.size() == 16 && !animated) return Eigen::Map<const Matrix4d>(node.matrix.data());
    Vector3d t = Vector3d::Zero(), s = Vector3d::Ones();
    Quaterniond r = Quaterniond::Identity();
    if (node.translation.size() == 3) t = {node.translation[0], node.translation[1], node.translation[2]};
    if (node.rotation.size() == 4) r = Quaterniond(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]);
    if (node.scale.size() == 3) s = {node.scale[0], node.scale[1], node.scale[2]};
    if (pose.translation) t = *pose.translation;
    if (pose.rotation) r = *pose.rotation;
    if (pose.scale) s = *pose.scale;
    Eigen::Affine3d m = Eigen::Translation3d(t) * r.normalized() * Eigen::Scaling(s);
    return m.matrix();
}

// Joint matrices (world · inverse bind) at the pose.
std::vector<Matrix4d> joint_matrices(const Skeleton& sk, const PoseParams& params) {
    const std::size_t nodes = sk.nodes.size();
    std::vector<NodePose> poses(nodes);
    if (!sk.animations.empty() && !params.rest) {
        if (params.animation >= sk.animations.size())
            throw Error(Error::Kind::argument, "pose: animation " + std::to_string(params.animation) +
                                                   " does not exist (the skeleton has " +
                                                   std::to_string(sk.animations.size()) + ")");
        const Animation& a = sk.animations[params.animation];
        for (const AnimationChannel& ch : a.channels) {
            if (ch.node < 0 || std::size_t(ch.node) >= nodes || ch.sampler < 0 || std::size_t(ch.sampler) >= a.samplers.size())
                continue;
            const bool rotation = ch.path == "rotation";
            const auto v = sample(a.samplers[std::size_t(ch.sampler)], params.time, rotation);
            if (!v) continue;
            NodePose& p = poses[std::size_t(ch.node)];
            if (rotation && v->size() == 4) p.rotation = Quaterniond((*v)[3], (*v)[0], (*v)[1], (*v)[2]).normalized();
            else if (ch.path == "translation" && v->size() == 3) p.translation = Vector3d((*v)[0], (*v)[1], (*v)[2]);
            else if (ch.path == "scale" && v->size() == 3) p.scale = Vector3d((*v)[0], (*v)[1], (*v)[2]);
        }
    }
    std::vector<int> parent(nodes, -1);
    for (std::size_t i = 0; i < nodes; ++i)
        for (int c : sk.nodes[i].children)
            if (c >= 0 && std::size_t(c) < nodes && parent[std::size_t(c)] < 0) parent[std::size_t(c)] = int(i);
    // World matrices from the roots down; a node on a parent cycle (invalid glTF) stops at the cycle.
    std::vector<Matrix4d> world(nodes);
    std::vector<char> state(nodes, 0);  // 0 unseen, 1 on the current path, 2 done
    for (std::size_t start = 0; start < nodes; ++start) {
        std::vector<std::size_t> path;
        for (int n = int(start); n >= 0 && state[std::size_t(n)] == 0; n = parent[std::size_t(n)]) {
            state[std::size_t(n)] = 1;
            path.push_back(std::size_t(n));
        }
        for (std::size_t i = path.size(); i-- > 0;) {
            const std::size_t n = path[i];
            const int p = parent[n];
            const Matrix4d local = local_matrix(sk.nodes[n], poses[n]);
            world[n] = p >= 0 && state[std::size_t(p)] == 2 ? Matrix4d(world[std::size_t(p)] * local) : local;
            state[n] = 2;
        }
    }
    std::vector<Matrix4d> out(sk.joints.size(), Matrix4d::Identity());
    for (std::size_t j = 0; j < sk.joints.size(); ++j) {
        const int node = sk.joints[j];
        const Matrix4d w = node >= 0 && std::size_t(node) < nodes ? world[std::size_t(node)] : Matrix4d::Identity();
        Matrix4d inverse_bind = Matrix4d::Identity();
        if (j < sk.inverse_bind_matrices.size())
            inverse_bind = Eigen::Map<const Eigen::Matrix4f>(sk.inverse_bind_matrices[j].data()).cast<double>();
        out[j] = w * inverse_bind;
    }
    return out;
}

}  // namespace

PoseResult pose_mesh(const Mesh& mesh, const PoseParams& params) {
    if (!mesh.has_skin())
        throw Error(Error::Kind::invalid, "pose: the mesh has no skin (no JOINTS_0/WEIGHTS_0 or no skeleton)");
    const Skeleton& sk = *mesh.skeleton;
    const std::vector<Matrix4d> joints = joint_matrices(sk, params);
    const std::size_t n = mesh.vertex_count();
    const std::size_t sets = std::min(mesh.joints.size(), mesh.weights.size());
    PoseResult out;
    out.positions.resize(n);
    if (mesh.has_normals()) out.normals.resize(n);
    for (std::size_t v = 0; v < n; ++v) {
        Matrix4d m = Matrix4d::Zero();
        double sum = 0;
        for (std::size_t s = 0; s < sets; ++s) {
            const Vec4f& w = mesh.weights[s][v];
            const float ws[4] = {w.x, w.y, w.z, w.w};
            for (std::size_t c = 0; c < 4; ++c) {
                if (!(ws[c] > 0.f)) continue;
                const std::size_t j = mesh.joints[s][v][c];
                if (j >= joints.size())
                    throw Error(Error::Kind::invalid, "pose: vertex " + std::to_string(v) + " follows joint " +
                                                          std::to_string(j) + ", the skin has " +
                                                          std::to_string(joints.size()) + " joints");
                m += double(ws[c]) * joints[j];
                sum += ws[c];
            }
        }
        // Weights off by rounding are renormalised; a vertex without weights follows joint 0 (as
        // limit_influences binds it).
        if (sum > 0) m /= sum;
        else m = joints.empty() ? Matrix4d::Identity() : joints[0];
        const Vec3f p = mesh.positions[v];
        const Eigen::Vector4d q = m * Eigen::Vector4d(p.x, p.y, p.z, 1.0);
        out.positions[v] = {float(q.x()), float(q.y()), float(q.z())};
        if (!out.normals.empty()) {
            const Vec3f nv = mesh.normals[v];
            const Eigen::Matrix3d linear = m.topLeftCorner<3, 3>();
            Vector3d r = linear.inverse().transpose() * Vector3d(nv.x, nv.y, nv.z);
            const double len = r.norm();
            r = len > 0 && std::isfinite(len) ? Vector3d(r / len) : Vector3d(nv.x, nv.y, nv.z);
            out.normals[v] = {float(r.x()), float(r.y()), float(r.z())};
        }
    }
    return out;
}

Mesh posed_copy(const Mesh& mesh, const PoseParams& params) {
    PoseResult pose = pose_mesh(mesh, params);
    Mesh out = mesh;
    out.positions = std::move(pose.positions);
    if (!pose.normals.empty()) out.normals = std::move(pose.normals);
    return out;
}

std::vector<double> pose_sample_times(const Skeleton& skeleton, std::size_t animation, std::size_t count) {
    const double duration = animation < skeleton.animations.size() ? skeleton.animations[animation].duration() : 0.0;
    std::vector<double> times(count);
    for (std::size_t i = 0; i < count; ++i) times[i] = duration * (double(i) + 0.5) / double(count);
    return times;
}

}  // namespace lodforge

// Supermesh of two genus-0 meshes: sphere maps aligned by landmarks, then overlaid (issue 8, case (b);
// docs/morph.md, "Case (b): two meshes").
//
// Follows:
// - J. R. Kent, W. E. Carlson, R. E. Parent, "Shape transformation for polyhedral objects", SIGGRAPH 1992,
//   and M. Alexa, "Merging polyhedral shapes with scattered features", The Visual Computer 16 (2000):
//   map both meshes to the sphere, align them by user features, merge the edge graphs.
// - W. Kabsch, "A solution for the best rotation to relate two sets of vectors", Acta Cryst. A32 (1976).
// - The landmark warp is a flow of small Gaussian-RBF displacement steps on the sphere (as Alexa's
//   feature alignment moves features in small fold-checked steps); each step is a near-identity smooth
//   map, and a step that would fold a face is halved.
// - LODStrips thesis, chapter 6: the supermesh is one connectivity carrying both shapes, V(0) and V(1).
#include "lodforge/morph/supermesh.h"

#include "lodforge/error.h"
#include "lodforge/io/mesh_io.h"
#include "morph/sphere_geometry.h"
#include "morph/sphere_overlay.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace lodforge {

using sphere::D3;

namespace {

// The rotation minimising Σ |R·b_i − a_i|² (Kabsch, with the reflection excluded).
Eigen::Matrix3d kabsch(const std::vector<D3>& from, const std::vector<D3>& to)
{
    if (from.size() == 1) {
        // One pair: the shortest rotation taking b to a.
        const Eigen::Vector3d f(from[0][0], from[0][1], from[0][2]), t(to[0][0], to[0][1], to[0][2]);
        return Eigen::Quaterniond::FromTwoVectors(f, t).toRotationMatrix();
    }
    Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
    for (std::size_t i = 0; i < from.size(); ++i)
        h += Eigen::Vector3d(from[i][0], from[i][1], from[i][2]) * Eigen::Vector3d(to[i][0], to[i][1], to[i][2]).transpose();
    Eigen::JacobiSVD<Eigen::Matrix3d> svd(h, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
    if ((svd.matrixV() * svd.matrixU().transpose()).determinant() < 0) d(2, 2) = -1;
    return svd.matrixV() * d * svd.matrixU().transpose();
}

D3 rotate(const Eigen::Matrix3d& r, const D3& p)
{
    const Eigen::Vector3d q = r * Eigen::Vector3d(p[0], p[1], p[2]);
    return sphere::normalized({q[0], q[1], q[2]});
}

bool all_positive(const std::vector<D3>& x, const std::vector<std::array<std::uint32_t, 3>>& faces)
{
    for (const auto& f : faces)
        if (sphere::orient_sign(x[f[0]], x[f[1]], x[f[2]]) <= 0) return false;
    return true;
}

double max_gap(const std::vector<D3>& x, const std::vector<std::uint32_t>& moving, const std::vector<D3>& target)
{
    double g = 0;
    for (std::size_t i = 0; i < moving.size(); ++i) g = std::max(g, sphere::angle_between(x[moving[i]], target[i]));
    return g;
}

double signed_volume(const SphereTopology& t)
{
    double v = 0;
    for (const auto& f : t.faces) {
        const Vec3f a = t.points[f[0]], b = t.points[f[1]], c = t.points[f[2]];
        v += double(a.x) * (double(b.y) * c.z - double(b.z) * c.y) - double(a.y) * (double(b.x) * c.z - double(b.z) * c.x) +
             double(a.z) * (double(b.x) * c.y - double(b.y) * c.x);
    }
    return v / 6;
}

struct WarpResult {
    int steps = 0;
    double residual = 0;
};

// Moves points `moving` of the map x towards `target` by a flow of smooth Gaussian-RBF displacement
// fields, each step fold-checked over all faces and halved when it would fold one.
WarpResult landmark_warp(std::vector<D3>& x, const SphereTopology& mesh,
                         const std::vector<std::uint32_t>& moving, const std::vector<D3>& target, const SupermeshParams& params,
                         Progress* progress)
{
    WarpResult r;
    const std::size_t k = moving.size();
    std::vector<D3> y(x.size());
    std::vector<std::uint8_t> pinned(x.size(), 0);
    for (auto v : moving) pinned[v] = 1;
    const double start_gap = max_gap(x, moving, target);
    r.residual = start_gap;
    // One fold-checked step of the flow with Gaussians of width sigma (chord distance); y = the result.
    auto try_step = [&](double sigma) {
        const double sigma2 = sigma * sigma;
        // Tangent displacements at the landmarks (log map), interpolated by Gaussians in chord distance.
        Eigen::MatrixXd kmat{Eigen::Index(k), Eigen::Index(k)}, d{Eigen::Index(k), 3};
        double longest = 0;
        for (std::size_t i = 0; i < k; ++i) {
            const D3& p = x[moving[i]];
            const D3 t = sphere::sub(target[i], sphere::mul(p, sphere::dot(target[i], p)));
            const double ang = sphere::angle_between(p, target[i]);
            const D3 v = sphere::norm(t) > 0 ? sphere::mul(sphere::normalized(t), ang) : D3{0, 0, 0};
            longest = std::max(longest, ang);
            for (int c = 0; c < 3; ++c) d(Eigen::Index(i), c) = v[std::size_t(c)];
            for (std::size_t j = 0; j < k; ++j) {
                const D3 e = sphere::sub(p, x[moving[j]]);
                kmat(Eigen::Index(i), Eigen::Index(j)) = std::exp(-sphere::dot(e, e) / sigma2) + (i == j ? 1e-9 : 0.0);
            }
        }
        const Eigen::MatrixXd w = kmat.ldlt().solve(d);
        // At most 0.05 rad per step, so each step is close to the identity.
        double alpha = std::min(1.0, 0.05 / std::max(longest, 1e-300));
        bool moved = false;
        for (int attempt = 0; attempt < 12 && !moved; ++attempt, alpha *= 0.5) {
            for (std::size_t v = 0; v < x.size(); ++v) {
                D3 f{0, 0, 0};
                for (std::size_t j = 0; j < k; ++j) {
                    const D3 e = sphere::sub(x[v], x[moving[j]]);
                    const double g = std::exp(-sphere::dot(e, e) / sigma2);
                    f = sphere::add(f, {g * w(Eigen::Index(j), 0), g * w(Eigen::Index(j), 1), g * w(Eigen::Index(j), 2)});
                }
                f = sphere::sub(f, sphere::mul(x[v], sphere::dot(f, x[v])));
                y[v] = sphere::normalized(sphere::add(x[v], sphere::mul(f, alpha)));
            }
            // A smooth near-identity step cannot fold a well-shaped face; slivers can (at any step size: their
            // orientation changes at first order), and get local untangling with the landmarks held (each
            // point into the kernel of its star), then the sphere map's own fold repair.
            bool pos = all_positive(y, mesh.faces);
            if (!pos) pos = untangle_sphere_folds(mesh, y, pinned, 10) == 0 || repair_sphere_folds(mesh, y, 20) == 0;
            if (pos && max_gap(y, moving, target) < r.residual) moved = true;
        }
        return moved;
    };
    while (r.steps < params.max_warp_steps && r.residual > params.warp_tolerance) {
        check_progress(progress, start_gap > 0 ? 1 - r.residual / start_gap : 1, "supermesh: landmark warp");
        // Wide fields first (they move whole regions); narrower ones when a wide one would fold a face.
        bool moved = false;
        for (double sigma : {0.5, 1.0, 0.25, 0.125})
            if ((moved = try_step(sigma))) break;
        if (!moved) break;
        x.swap(y);
        // The flow squeezes the regions a landmark moves into; spread them again (landmarks pinned).
        relax_sphere_slivers(mesh, x, pinned, 0.05, 3);
        r.residual = max_gap(x, moving, target);
        ++r.steps;
    }
    return r;
}

// The automorphism of the unit ball taking c (|c| < 1) to the centre, on the sphere: a Möbius map
// (conformal, orientation-preserving: two reflections) that spreads points away from the direction of c.
D3 mobius(const D3& x, const D3& c)
{
    const D3 d = sphere::sub(x, c);
    return sphere::normalized(sphere::sub(sphere::mul(d, (1 - sphere::dot(c, c)) / sphere::dot(d, d)), c));
}

struct MobiusFit {
    D3 c{0, 0, 0};
    Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
    double cost = 0;
};

// The Möbius map plus rotation that best takes `from` onto `to` (least squares over the ball point c by
// Nelder–Mead, the rotation by Kabsch for each c). Sphere maps of two shapes differ mostly by where
// they crowd area, which is what a Möbius map moves; a rotation alone leaves that to the warp.
MobiusFit fit_mobius(const std::vector<D3>& from, const std::vector<D3>& to)
{
    auto evaluate = [&](const D3& c) {
        MobiusFit f;
        f.c = c;
        if (sphere::dot(c, c) > 0.8 * 0.8) {
            f.cost = 1e300;
            return f;
        }
        std::vector<D3> m(from.size());
        for (std::size_t i = 0; i < from.size(); ++i) m[i] = mobius(from[i], c);
        f.rotation = kabsch(m, to);
        for (std::size_t i = 0; i < m.size(); ++i) {
            const D3 e = sphere::sub(rotate(f.rotation, m[i]), to[i]);
            f.cost += sphere::dot(e, e);
        }
        return f;
    };
    std::array<MobiusFit, 4> simplex;
    simplex[0] = evaluate({0, 0, 0});
    for (int k = 0; k < 3; ++k) {
        D3 c{0, 0, 0};
        c[std::size_t(k)] = 0.25;
        simplex[std::size_t(k) + 1] = evaluate(c);
    }
    auto blend = [](const D3& a, const D3& b, double t) { return sphere::add(a, sphere::mul(sphere::sub(b, a), t)); };
    for (int it = 0; it < 400; ++it) {
        std::sort(simplex.begin(), simplex.end(), [](const MobiusFit& a, const MobiusFit& b) { return a.cost < b.cost; });
        if (simplex[3].cost - simplex[0].cost < 1e-14) break;
        const D3 centroid = sphere::mul(sphere::add(sphere::add(simplex[0].c, simplex[1].c), simplex[2].c), 1.0 / 3);
        const MobiusFit reflected = evaluate(blend(centroid, simplex[3].c, -1));
        if (reflected.cost < simplex[0].cost) {
            const MobiusFit expanded = evaluate(blend(centroid, simplex[3].c, -2));
            simplex[3] = expanded.cost < reflected.cost ? expanded : reflected;
        } else if (reflected.cost < simplex[2].cost) {
            simplex[3] = reflected;
        } else {
            const MobiusFit contracted = evaluate(blend(centroid, simplex[3].c, 0.5));
            if (contracted.cost < simplex[3].cost) {
                simplex[3] = contracted;
            } else {
                for (std::size_t k = 1; k < 4; ++k) simplex[k] = evaluate(blend(simplex[0].c, simplex[k].c, 0.5));
            }
        }
    }
    std::sort(simplex.begin(), simplex.end(), [](const MobiusFit& a, const MobiusFit& b) { return a.cost < b.cost; });
    return simplex[0];
}

std::string degrees(double rad)
{
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", rad * 180 / M_PI);
    return buf;
}

}  // namespace

SupermeshResult build_supermesh(const Mesh& a, const Mesh& b, const Landmarks& landmarks, const SupermeshParams& params,
                                const std::string& source_a, const std::string& source_b, const std::string& landmark_source,
                                Progress* progress)
{
    check_landmarks(landmarks, a.vertex_count(), b.vertex_count(), landmark_source);
    if (landmarks.pairs.empty())
        throw_error(Error::Kind::invalid, landmark_source, "no landmark pairs; at least one is needed to align the meshes");
    const SphereTopology ta = check_sphere_topology(a, source_a);
    const SphereTopology tb = check_sphere_topology(b, source_b);
    // Two wedges of one point named in two pairs would ask for one point to be in two places.
    std::vector<std::uint32_t> la, lb;
    for (std::size_t i = 0; i < landmarks.pairs.size(); ++i) {
        const std::uint32_t pa = ta.point_of_vertex[landmarks.pairs[i].a], pb = tb.point_of_vertex[landmarks.pairs[i].b];
        for (std::size_t j = 0; j < la.size(); ++j)
            if (la[j] == pa || lb[j] == pb)
                throw_error(Error::Kind::invalid, landmark_source,
                            "pairs " + std::to_string(j) + " and " + std::to_string(i) + " name the same point of " +
                                (la[j] == pa ? source_a : source_b));
        la.push_back(pa);
        lb.push_back(pb);
    }

    // The sphere map follows the face order; an inside-out mesh would morph A's outside onto B's inside.
    const double va = signed_volume(ta), vb = signed_volume(tb);
    if ((va < 0) != (vb < 0))
        throw_error(Error::Kind::invalid, va < 0 ? source_a : source_b,
                    "the faces are oriented inwards (negative enclosed volume) while the other mesh's face outwards; "
                    "flip one mesh's faces");
    SphereMap ma = map_to_sphere(ta, params.sphere, source_a, progress);
    SphereMap mb = map_to_sphere(tb, params.sphere, source_b, progress);

    // Rotation (and, with three pairs or more, a Möbius map), then the fold-free warp that brings the
    // landmarks of the two maps together.
    std::vector<D3> from, to;
    for (std::size_t i = 0; i < la.size(); ++i) from.push_back(mb.points[lb[i]]), to.push_back(ma.points[la[i]]);
    const Eigen::Matrix3d rot = kabsch(from, to);
    std::vector<D3> start(mb.points.size());
    for (std::size_t i = 0; i < start.size(); ++i) start[i] = rotate(rot, mb.points[i]);
    if (!all_positive(start, tb.faces))
        throw_error(Error::Kind::invalid, source_b, "sphere map: a face folds when the map is rotated (faces too thin)");
    SupermeshResult result;
    result.rotation_residual = max_gap(start, lb, to);
    if (lb.size() >= 3) {
        const MobiusFit fit = fit_mobius(from, to);
        std::vector<D3> moved(start.size());
        for (std::size_t i = 0; i < moved.size(); ++i) moved[i] = rotate(fit.rotation, mobius(mb.points[i], fit.c));
        // A Möbius map is a bijection of the sphere but can fold a face it stretches much (its chord
        // triangle is not its image); kept only when it is fold-free (after local repair) and helps.
        if ((all_positive(moved, tb.faces) || repair_sphere_folds(tb, moved, 20) == 0) &&
            max_gap(moved, lb, to) < result.rotation_residual) {
            start.swap(moved);
            result.mobius_residual = max_gap(start, lb, to);
        }
    }
    if (result.mobius_residual == 0) result.mobius_residual = result.rotation_residual;

    // Strategies, in order, until the pairs meet: (1) both maps flow halfway, to the pairs' midpoints
    // (half the displacement each, so half the strain); (2) B's map the whole way; (3) B's map one more
    // pair at a time, the pairs already met held in place (gets through configurations the joint flow
    // cannot).
    struct Aligned {
        std::vector<D3> a, b;
        int steps = 0;
        double gap = 1e300;
    };
    auto pair_gap = [&](const Aligned& x) {
        double g = 0;
        for (std::size_t i = 0; i < la.size(); ++i) g = std::max(g, sphere::angle_between(x.a[la[i]], x.b[lb[i]]));
        return g;
    };
    auto align = [&](int strategy) {
        Aligned x{ma.points, start, 0, 0};
        if (strategy == 0) {
            std::vector<D3> mid(la.size());
            for (std::size_t i = 0; i < la.size(); ++i) mid[i] = sphere::normalized(sphere::add(x.a[la[i]], x.b[lb[i]]));
            x.steps += landmark_warp(x.a, ta, la, mid, params, progress).steps;
            x.steps += landmark_warp(x.b, tb, lb, mid, params, progress).steps;
        } else if (strategy == 1) {
            x.steps = landmark_warp(x.b, tb, lb, to, params, progress).steps;
        } else {
            for (std::size_t c = 1; c <= lb.size(); ++c) {
                const std::vector<std::uint32_t> sub_b(lb.begin(), lb.begin() + long(c));
                const std::vector<D3> sub_t(to.begin(), to.begin() + long(c));
                const WarpResult w = landmark_warp(x.b, tb, sub_b, sub_t, params, progress);
                x.steps += w.steps;
                if (w.residual > 0.01) break;
            }
        }
        x.gap = pair_gap(x);
        return x;
    };
    Aligned best;
    for (int strategy = 0; strategy < (lb.size() > 1 ? 3 : 2) && !(best.gap <= 0.01); ++strategy) {
        Aligned x = align(strategy);
        if (x.gap < best.gap) best = std::move(x);
    }
    result.landmark_residual = best.gap;
    result.warp_steps = best.steps;
    if (!(best.gap <= 0.01))
        throw_error(Error::Kind::invalid, landmark_source,
                    "the landmark pairs cannot be brought together without folding the sphere map (still " +
                        degrees(best.gap) + " degrees apart after " + std::to_string(best.steps) +
                        " steps); are the pairs in a consistent order on both meshes?");
    ma.points.swap(best.a);
    mb.points.swap(best.b);

    // Overlay; on a near-degenerate configuration turn B by a tiny rotation and try again.
    sphere::Overlay ov;
    std::string why;
    bool ok = false;
    std::vector<D3> b_points = mb.points;
    for (int attempt = 0; attempt < std::max(1, params.max_overlay_tries) && !ok; ++attempt) {
        check_progress(progress, double(attempt) / params.max_overlay_tries, "supermesh: overlay");
        if (attempt > 0) {
            const double angle = 1e-7 * attempt;
            const Eigen::Matrix3d turn =
                Eigen::AngleAxisd(angle, Eigen::Vector3d(0.36 * attempt, 0.48, 0.8).normalized()).toRotationMatrix();
            for (std::size_t i = 0; i < b_points.size(); ++i) b_points[i] = rotate(turn, mb.points[i]);
            if (!all_positive(b_points, tb.faces)) continue;
        }
        ok = sphere::overlay_triangulations({&ma.points, &ta.faces}, {&b_points, &tb.faces}, ov, why);
        result.overlay_tries = attempt + 1;
    }
    if (!ok)
        throw_error(Error::Kind::invalid, source_a + " + " + source_b,
                    "the sphere maps could not be overlaid in general position (" + why + ")");

    // Both shapes on the merged connectivity: each vertex at its place on A's and on B's surface.
    const std::size_t nv = ov.points.size();
    MorphMesh& m = result.morph;
    m.frame_positions.assign(2, std::vector<Vec3f>(nv));
    for (std::size_t v = 0; v < nv; ++v) {
        for (int frame = 0; frame < 2; ++frame) {
            const sphere::OverlayWeights& w = frame == 0 ? ov.in_a[v] : ov.in_b[v];
            const std::vector<Vec3f>& pts = frame == 0 ? ta.points : tb.points;
            double p[3] = {0, 0, 0};
            for (int c = 0; c < 3; ++c)
                if (w.weight[std::size_t(c)] != 0) {
                    const Vec3f q = pts[w.corner[std::size_t(c)]];
                    p[0] += w.weight[std::size_t(c)] * q.x, p[1] += w.weight[std::size_t(c)] * q.y,
                        p[2] += w.weight[std::size_t(c)] * q.z;
                }
            m.frame_positions[std::size_t(frame)][v] = {float(p[0]), float(p[1]), float(p[2])};
        }
    }
    // A's and B's own points keep their exact input coordinates (weight 1, no rounding through doubles).
    for (std::size_t i = 0; i < ta.points.size(); ++i) m.frame_positions[0][i] = ta.points[i];
    for (std::size_t i = 0; i < tb.points.size(); ++i) m.frame_positions[1][ta.points.size() + i] = tb.points[i];
    m.base.indices.reserve(ov.triangles.size() * 3);
    for (const auto& t : ov.triangles) m.base.indices.insert(m.base.indices.end(), t.begin(), t.end());
    m.frame_names = {source_a, source_b};
    m.source = source_a + " + " + source_b;
    finish_morph(m, m.source);

    result.a_points = ta.points.size();
    result.b_points = tb.points.size();
    result.crossings = ov.crossings;
    result.min_face_orient = ov.min_det;
    result.sphere_points = std::move(ov.points);
    check_progress(progress, 1.0, "supermesh");
    return result;
}

MorphMesh load_supermesh(const std::string& path_a, const std::string& path_b, const std::string& landmarks_path,
                         const SupermeshParams& params, Progress* progress)
{
    const Landmarks l = read_landmarks(landmarks_path);
    const Mesh a = read_mesh(path_a, {}, progress);
    const Mesh b = read_mesh(path_b, {}, progress);
    MorphMesh m = build_supermesh(a, b, l, params, path_a, path_b, landmarks_path, progress).morph;
    if (params.frames > 2) {
        const MorphMesh two = m;
        m.frame_positions.clear();
        m.frame_normals.clear();
        m.frame_names.clear();
        for (std::size_t k = 0; k < params.frames; ++k) {
            const double t = double(k) / double(params.frames - 1);
            m.frame_positions.emplace_back();
            morph_positions_at(two, t, m.frame_positions.back());
            char name[48];
            std::snprintf(name, sizeof name, "blend t=%.4g", t);
            m.frame_names.push_back(k == 0 ? path_a : (k + 1 == params.frames ? path_b : std::string(name)));
        }
        m.base.positions.clear();
        finish_morph(m, m.source);
    }
    return m;
}

}  // namespace lodforge

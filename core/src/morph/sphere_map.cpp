// Genus-0 topology check and bijective spherical parametrisation (issue 8, case (b); docs/morph.md).
//
// Follows:
// - W. T. Tutte, "How to draw a graph", Proc. London Math. Soc. 13 (1963): a 3-connected planar graph
//   with its outer face fixed to a convex polygon and every other vertex a convex combination of its
//   neighbours is embedded without crossings.
// - M. S. Floater, "Mean value coordinates", CAGD 20 (2003): positive weights from the 3D geometry,
//   so Tutte's theorem holds with less distortion than uniform weights.
// - C. Gotsman, X. Gu, A. Sheffer, "Fundamentals of spherical parameterization for 3D meshes",
//   SIGGRAPH 2003, and E. Praun, H. Hoppe, "Spherical parametrization and remeshing", SIGGRAPH 2003:
//   relaxation on the sphere collapses unless it is re-centred (Möbius normalisation) and checked for
//   folds; a move that would flip a face is rejected.
#include "lodforge/morph/supermesh.h"

#include "lodforge/error.h"
#include "morph/sphere_geometry.h"
#include "union_find.h"

#include <Eigen/Sparse>
#include <Eigen/SparseLU>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>

namespace lodforge {

using sphere::D3;

namespace {

std::uint64_t key(std::uint32_t a, std::uint32_t b) { return (std::uint64_t(a) << 32) | b; }

}  // namespace

SphereTopology check_sphere_topology(const Mesh& mesh, const std::string& source)
{
    SphereTopology t;
    const std::size_t nv = mesh.vertex_count();
    if (mesh.triangle_count() == 0) throw_error(Error::Kind::invalid, source, "the mesh has no triangles");
    t.point_of_vertex.resize(nv);
    std::size_t np = 0;
    for (std::size_t v = 0; v < nv; ++v) {
        t.point_of_vertex[v] = mesh.position_ids.empty() ? std::uint32_t(v) : mesh.position_ids[v];
        np = std::max<std::size_t>(np, t.point_of_vertex[v] + 1);
    }
    t.points.assign(np, Vec3f{});
    for (std::size_t v = nv; v-- > 0;) t.points[t.point_of_vertex[v]] = mesh.positions[v];

    std::vector<std::uint8_t> used(np, 0);
    std::unordered_map<std::uint64_t, std::uint32_t> directed;  // (from, to) -> face
    directed.reserve(mesh.indices.size() * 2);
    for (std::size_t f = 0; f < mesh.triangle_count(); ++f) {
        std::array<std::uint32_t, 3> p{};
        for (int c = 0; c < 3; ++c) {
            const std::uint32_t v = mesh.indices[3 * f + c];
            if (v >= nv) throw_error(Error::Kind::invalid, source, "face " + std::to_string(f) + " uses vertex " +
                                                                       std::to_string(v) + " of " + std::to_string(nv));
            p[c] = t.point_of_vertex[v];
            used[p[c]] = 1;
        }
        if (p[0] == p[1] || p[1] == p[2] || p[0] == p[2])
            throw_error(Error::Kind::invalid, source,
                        "face " + std::to_string(f) + " repeats point " +
                            std::to_string(p[0] == p[1] || p[0] == p[2] ? p[0] : p[1]) +
                            " (degenerate face); a sphere map needs a simplicial surface");
        for (int c = 0; c < 3; ++c) {
            const std::uint32_t a = p[c], b = p[(c + 1) % 3];
            if (!directed.emplace(key(a, b), std::uint32_t(f)).second)
                throw_error(Error::Kind::invalid, source,
                            "edge " + std::to_string(a) + "-" + std::to_string(b) + " is used twice in the same direction "
                            "(faces " + std::to_string(directed[key(a, b)]) + " and " + std::to_string(f) +
                            "): non-manifold or inconsistently oriented");
        }
        t.faces.push_back(p);
    }
    std::size_t border = 0;
    for (const auto& [k, f] : directed)
        if (!directed.count((k << 32) | (k >> 32))) ++border;
    if (border)
        throw_error(Error::Kind::invalid, source,
                    std::to_string(border) + " border edges: the mesh is open; a sphere map needs a closed surface");
    const std::size_t unused = std::size_t(std::count(used.begin(), used.end(), 0));
    if (unused)
        throw_error(Error::Kind::invalid, source, std::to_string(unused) + " points are used by no face");

    // Vertex manifoldness: the faces around each point form one fan (one cycle of next-around edges).
    std::vector<std::uint32_t> degree(np, 0), first_out(np, UINT32_MAX);
    std::unordered_map<std::uint64_t, std::uint32_t> next_around;  // (u, v) -> w with face (u, v, w)
    next_around.reserve(directed.size());
    for (const auto& f : t.faces)
        for (int c = 0; c < 3; ++c) {
            const std::uint32_t u = f[c], v = f[(c + 1) % 3], w = f[(c + 2) % 3];
            next_around[key(u, v)] = w;
            ++degree[u];
            first_out[u] = v;
        }
    for (std::uint32_t u = 0; u < np; ++u) {
        std::uint32_t v = first_out[u], steps = 0;
        do {
            v = next_around.at(key(u, v));
            ++steps;
        } while (v != first_out[u] && steps <= degree[u]);
        if (steps != degree[u])
            throw_error(Error::Kind::invalid, source,
                        "point " + std::to_string(u) + " is non-manifold (its faces form several fans)");
    }
    detail::UnionFind uf(np);
    for (const auto& f : t.faces) {
        uf.unite(f[0], f[1]);
        uf.unite(f[1], f[2]);
    }
    std::size_t components = 0;
    for (std::uint32_t u = 0; u < np; ++u)
        if (uf.find(u) == u) ++components;
    if (components != 1)
        throw_error(Error::Kind::unsupported, source,
                    std::to_string(components) + " components; a sphere map needs one connected closed surface");
    const long long euler = (long long)np - (long long)directed.size() / 2 + (long long)t.faces.size();
    if (euler != 2)
        throw_error(Error::Kind::unsupported, source,
                    "genus " + std::to_string((2 - euler) / 2) + " (Euler characteristic " + std::to_string(euler) +
                        "); only genus-0 (sphere-like) meshes can be mapped to the sphere");
    return t;
}

namespace {

struct Star {
    std::vector<std::uint32_t> offset, faces;        // faces around each point (CSR)
    std::vector<std::uint32_t> nbr_offset, nbrs;     // neighbours of each point (CSR)
};

Star build_star(const SphereTopology& m)
{
    Star s;
    const std::size_t np = m.points.size();
    s.offset.assign(np + 1, 0);
    for (const auto& f : m.faces)
        for (auto p : f) ++s.offset[p + 1];
    for (std::size_t i = 0; i < np; ++i) s.offset[i + 1] += s.offset[i];
    s.faces.resize(s.offset[np]);
    std::vector<std::uint32_t> fill(s.offset.begin(), s.offset.end() - 1);
    for (std::uint32_t f = 0; f < m.faces.size(); ++f)
        for (auto p : m.faces[f]) s.faces[fill[p]++] = f;
    // In a closed manifold the neighbours of a point are as many as its faces: one per face (the next corner).
    s.nbr_offset = s.offset;
    s.nbrs.resize(s.faces.size());
    for (std::uint32_t p = 0; p < np; ++p)
        for (std::uint32_t i = s.offset[p]; i < s.offset[p + 1]; ++i) {
            const auto& f = m.faces[s.faces[i]];
            const int c = f[0] == p ? 0 : (f[1] == p ? 1 : 2);
            s.nbrs[i] = f[(c + 1) % 3];
        }
    return s;
}

D3 to_d3(Vec3f v) { return {double(v.x), double(v.y), double(v.z)}; }

// det[p0, p1, p2] as det[p0, p1 − p0, p2 − p0]: the differences first, so a tiny face (the Tutte start
// crowds protrusions together) keeps its sign accurately instead of drowning in the rounding of 1.
double face_det(const std::vector<D3>& x, const std::array<std::uint32_t, 3>& f)
{
    return sphere::det3(x[f[0]], sphere::sub(x[f[1]], x[f[0]]), sphere::sub(x[f[2]], x[f[0]]));
}

bool positive(const std::vector<D3>& x, const std::array<std::uint32_t, 3>& f)
{
    return sphere::orient_sign(x[f[0]], x[f[1]], x[f[2]]) > 0;
}

std::size_t star_folds(const std::vector<D3>& x, const SphereTopology& m, const Star& s, std::uint32_t p)
{
    std::size_t n = 0;
    for (std::uint32_t i = s.offset[p]; i < s.offset[p + 1]; ++i)
        if (!positive(x, m.faces[s.faces[i]])) ++n;
    return n;
}

std::size_t folded_faces(const std::vector<D3>& x, const SphereTopology& m)
{
    std::size_t n = 0;
    for (const auto& f : m.faces)
        if (!positive(x, f)) ++n;
    return n;
}

// Möbius transformation of the ball that moves the centre to -a (pushes points away from a), restricted
// to the sphere: f(x) = (1 − |a|²)(x − a)/|x − a|² − a.
D3 mobius(const D3& x, const D3& a)
{
    const D3 d = sphere::sub(x, a);
    return sphere::normalized(sphere::sub(sphere::mul(d, (1 - sphere::dot(a, a)) / sphere::dot(d, d)), a));
}

// Centroid of the mesh's surface area carried to the sphere: weighted by each face's 3D area (the
// sphere's own area weighting would always give the centre of a one-sheeted cover).
D3 area_centroid(const std::vector<D3>& x, const SphereTopology& m, const std::vector<double>& face_area)
{
    D3 c{0, 0, 0};
    double total = 0;
    for (std::size_t i = 0; i < m.faces.size(); ++i) {
        const auto& f = m.faces[i];
        const D3 centre = sphere::normalized(sphere::add(sphere::add(x[f[0]], x[f[1]]), x[f[2]]));
        c = sphere::add(c, sphere::mul(centre, face_area[i]));
        total += face_area[i];
    }
    return total > 0 ? sphere::mul(c, 1 / total) : c;
}

// One damped Möbius centering step; kept only when it folds no further face.
void center_step(std::vector<D3>& x, const SphereTopology& m, const std::vector<double>& face_area)
{
    D3 a = area_centroid(x, m, face_area);
    if (sphere::norm(a) < 1e-4) return;
    const std::size_t before = folded_faces(x, m);
    std::vector<D3> y(x.size());
    for (int attempt = 0; attempt < 8; ++attempt, a = sphere::mul(a, 0.5)) {
        for (std::size_t i = 0; i < x.size(); ++i) y[i] = mobius(x[i], a);
        if (folded_faces(y, m) <= before) {
            x.swap(y);
            return;
        }
    }
}

// Moves each point (or, with folded_only, each point of a folded face) towards its neighbours' centroid
// when that does not fold a face of its star (or unfolds some).
void relax_sweep(std::vector<D3>& x, const SphereTopology& m, const Star& s, bool folded_only)
{
    for (std::uint32_t p = 0; p < x.size(); ++p) {
        if (folded_only && star_folds(x, m, s, p) == 0) continue;
        D3 sum{0, 0, 0};
        for (std::uint32_t i = s.nbr_offset[p]; i < s.nbr_offset[p + 1]; ++i) sum = sphere::add(sum, x[s.nbrs[i]]);
        const D3 target = sphere::normalized(sum);
        const D3 old = x[p];
        const std::size_t before = star_folds(x, m, s, p);
        for (double w = 1.0; w > 0.1; w *= 0.5) {
            x[p] = sphere::normalized(sphere::add(sphere::mul(old, 1 - w), sphere::mul(target, w)));
            const std::size_t after = star_folds(x, m, s, p);
            if (after < before || (after == 0 && before == 0)) break;
            x[p] = old;
        }
    }
}

double min_angle(const std::vector<D3>& x, const SphereTopology& m)
{
    double best = M_PI;
    for (const auto& f : m.faces)
        for (int c = 0; c < 3; ++c) {
            const D3 e1 = sphere::sub(x[f[(c + 1) % 3]], x[f[c]]), e2 = sphere::sub(x[f[(c + 2) % 3]], x[f[c]]);
            best = std::min(best, sphere::angle_between(e1, e2));
        }
    return best;
}

}  // namespace

namespace {

double face_sine(const std::vector<D3>& x, const std::array<std::uint32_t, 3>& f)
{
    // The smallest corner's sine, signed by the orientation (a scale-free shape measure).
    double best = INFINITY;
    for (int c = 0; c < 3; ++c) {
        const D3& p = x[f[std::size_t(c)]];
        const D3 u = sphere::sub(x[f[std::size_t((c + 1) % 3)]], p), v = sphere::sub(x[f[std::size_t((c + 2) % 3)]], p);
        best = std::min(best, sphere::dot(p, sphere::cross(u, v)) / std::max(1e-300, sphere::norm(u) * sphere::norm(v)));
    }
    return best;
}

double star_min_sine(const std::vector<D3>& x, const SphereTopology& m, const Star& s, std::uint32_t p)
{
    double best = INFINITY;
    for (std::uint32_t i = s.offset[p]; i < s.offset[p + 1]; ++i) best = std::min(best, face_sine(x, m.faces[s.faces[i]]));
    return best;
}

}  // namespace

void relax_sphere_slivers(const SphereTopology& mesh, std::vector<std::array<double, 3>>& points,
                          const std::vector<std::uint8_t>& pinned, double min_sine, int sweeps)
{
    const Star star = build_star(mesh);
    for (int sweep = 0; sweep < sweeps; ++sweep) {
        bool any = false;
        for (std::uint32_t p = 0; p < points.size(); ++p) {
            if (pinned[p]) continue;
            const double before = star_min_sine(points, mesh, star, p);
            if (before >= min_sine) continue;
            any = true;
            D3 sum{0, 0, 0};
            for (std::uint32_t i = star.nbr_offset[p]; i < star.nbr_offset[p + 1]; ++i) sum = sphere::add(sum, points[star.nbrs[i]]);
            const D3 target = sphere::normalized(sum), old = points[p];
            for (double w = 1.0; w > 0.1; w *= 0.5) {
                points[p] = sphere::normalized(sphere::add(sphere::mul(old, 1 - w), sphere::mul(target, w)));
                if (star_folds(points, mesh, star, p) == 0 && star_min_sine(points, mesh, star, p) > before) break;
                points[p] = old;
            }
        }
        if (!any) break;
    }
}

// A point of a folded face moves into the kernel of its star: the region on the sphere where every face
// around it is positive, p · (q_i × q_{i+1}) > 0 for each link edge (q_i, q_{i+1}) (Freitag and
// Plassmann's local untangling, on the sphere). The most interior direction — the largest smallest
// normalised margin — is found by subgradient ascent from the current position; the move is kept when it
// lowers the star's folds (or keeps a fold-free star fold-free). The other corners and the corners'
// neighbours get their turn in the same sweep, so a face whose kernel is empty for one corner can still
// be untangled by another; pinned points never move.
std::size_t untangle_sphere_folds(const SphereTopology& mesh, std::vector<std::array<double, 3>>& points,
                                  const std::vector<std::uint8_t>& pinned, int sweeps)
{
    const Star star = build_star(mesh);
    std::vector<D3> normals;
    for (int sweep = 0; sweep < sweeps; ++sweep) {
        // The corners of folded faces and their neighbours: a corner whose kernel is empty gets one once
        // its neighbours have moved to the middle of theirs.
        std::vector<std::uint32_t> todo;
        bool any = false;
        for (const auto& f : mesh.faces)
            if (!positive(points, f)) {
                any = true;
                for (auto p : f) {
                    if (!pinned[p]) todo.push_back(p);
                    for (std::uint32_t i = star.nbr_offset[p]; i < star.nbr_offset[p + 1]; ++i)
                        if (!pinned[star.nbrs[i]]) todo.push_back(star.nbrs[i]);
                }
            }
        if (!any) break;
        std::sort(todo.begin(), todo.end());
        todo.erase(std::unique(todo.begin(), todo.end()), todo.end());
        for (std::uint32_t p : todo) {
            normals.clear();
            for (std::uint32_t i = star.offset[p]; i < star.offset[p + 1]; ++i) {
                const auto& f = mesh.faces[star.faces[i]];
                const int c = f[0] == p ? 0 : (f[1] == p ? 1 : 2);
                const D3 n = sphere::cross(points[f[(c + 1) % 3]], points[f[(c + 2) % 3]]);
                if (sphere::norm(n) > 0) normals.push_back(sphere::normalized(n));
            }
            if (normals.empty()) continue;
            const D3 old = points[p];
            const std::size_t before = star_folds(points, mesh, star, p);
            auto margin = [&](const D3& x, std::size_t* worst) {
                double m = 1e300;
                for (std::size_t i = 0; i < normals.size(); ++i) {
                    const double d = sphere::dot(normals[i], x);
                    if (d < m) m = d, *worst = i;
                }
                return m;
            };
            D3 x = old, best = old;
            std::size_t worst = 0;
            double best_margin = margin(x, &worst);
            // Steps from half the star's longest edge down, so the point can cross most of its star.
            double step = 0;
            for (std::uint32_t i = star.nbr_offset[p]; i < star.nbr_offset[p + 1]; ++i)
                step = std::max(step, sphere::norm(sphere::sub(points[star.nbrs[i]], old)));
            step = std::max(0.5 * step, 1e-9);
            for (int it = 0; it < 80; ++it) {
                x = sphere::normalized(sphere::add(x, sphere::mul(normals[worst], step)));
                const double m = margin(x, &worst);
                if (m > best_margin) {
                    best_margin = m, best = x;
                } else {
                    step *= 0.7;
                }
            }
            points[p] = best;
            const std::size_t after = star_folds(points, mesh, star, p);
            if (after > before || (before > 0 && after == before)) points[p] = old;
        }
    }
    return folded_faces(points, mesh);
}

std::size_t repair_sphere_folds(const SphereTopology& mesh, std::vector<std::array<double, 3>>& points, int sweeps)
{
    const Star star = build_star(mesh);
    for (int sweep = 0; sweep < sweeps && folded_faces(points, mesh) > 0; ++sweep) relax_sweep(points, mesh, star, true);
    return folded_faces(points, mesh);
}

SphereMap map_to_sphere(const SphereTopology& m, const SphereMapParams& params, const std::string& source,
                        Progress* progress)
{
    const std::size_t np = m.points.size();
    if (np < 4) throw_error(Error::Kind::invalid, source, "fewer than 4 points; not a closed surface");
    const Star star = build_star(m);
    SphereMap out;

    // Cut the largest face (a stable choice; its three corners become the outer triangle).
    std::vector<D3> pos(np);
    for (std::size_t i = 0; i < np; ++i) pos[i] = to_d3(m.points[i]);
    double best_area = -1;
    std::vector<double> face_area(m.faces.size());
    for (std::size_t f = 0; f < m.faces.size(); ++f) {
        const auto& t = m.faces[f];
        const double a = sphere::norm(sphere::cross(sphere::sub(pos[t[1]], pos[t[0]]), sphere::sub(pos[t[2]], pos[t[0]])));
        face_area[f] = std::isfinite(a) ? a : 0.0;
        if (a > best_area) best_area = a, out.cut_face = f;
    }
    const auto outer = m.faces[out.cut_face];
    check_progress(progress, 0.0, "sphere map: Tutte embedding");

    // Mean-value weights (Floater), uniform where the geometry is degenerate.
    std::vector<int> index(np, -1);
    std::vector<std::uint32_t> inner;
    for (std::uint32_t p = 0; p < np; ++p)
        if (p != outer[0] && p != outer[1] && p != outer[2]) {
            index[p] = int(inner.size());
            inner.push_back(p);
        }
    // Boundary clockwise in the plane: the complement of a counter-clockwise face is counter-clockwise.
    const double corner[3][2] = {{0, 1}, {std::sqrt(3.0) / 2, -0.5}, {-std::sqrt(3.0) / 2, -0.5}};
    std::vector<double> px(np, 0), py(np, 0);
    for (int c = 0; c < 3; ++c) px[outer[c]] = corner[c][0], py[outer[c]] = corner[c][1];

    // Mean-value weight of each (point, star slot, side): side 0 the slot's next corner q, side 1 the one
    // after it w (the angle at p between q and w enters both edges' weights).
    std::vector<double> base_w(2 * star.nbrs.size());
    std::vector<std::uint32_t> other(2 * star.nbrs.size());
    for (std::uint32_t p = 0; p < np; ++p)
        for (std::uint32_t i = star.offset[p]; i < star.offset[p + 1]; ++i) {
            const std::uint32_t q = star.nbrs[i];
            const auto& f = m.faces[star.faces[i]];
            const int c = f[0] == p ? 0 : (f[1] == p ? 1 : 2);
            const std::uint32_t w = f[(c + 2) % 3];
            const D3 eq = sphere::sub(pos[q], pos[p]), ew = sphere::sub(pos[w], pos[p]);
            const double half_tan = std::tan(0.5 * sphere::angle_between(eq, ew));
            for (int side = 0; side < 2; ++side) {
                double weight = half_tan / sphere::norm(side ? ew : eq);
                if (!std::isfinite(weight) || !(weight > 1e-12)) weight = 1e-3;  // degenerate geometry
                base_w[2 * i + std::size_t(side)] = weight;
                other[2 * i + std::size_t(side)] = side ? w : q;
            }
        }
    const std::size_t n = inner.size();
    // Tutte embedding with each neighbour j's weight scaled by factor[j] (positive: still an embedding).
    auto tutte = [&](const std::vector<double>& factor) {
        std::vector<Eigen::Triplet<double>> trip;
        Eigen::VectorXd bx = Eigen::VectorXd::Zero(Eigen::Index(n)), by = Eigen::VectorXd::Zero(Eigen::Index(n));
        for (std::size_t r = 0; r < n; ++r) {
            const std::uint32_t p = inner[r];
            double diag = 0;
            for (std::size_t i = 2 * std::size_t(star.offset[p]); i < 2 * std::size_t(star.offset[p + 1]); ++i) {
                const std::uint32_t j = other[i];
                const double weight = base_w[i] * factor[j];
                diag += weight;
                if (index[j] >= 0) trip.emplace_back(Eigen::Index(r), index[j], -weight);
                else bx[Eigen::Index(r)] += weight * px[j], by[Eigen::Index(r)] += weight * py[j];
            }
            trip.emplace_back(Eigen::Index(r), Eigen::Index(r), diag);
        }
        Eigen::SparseMatrix<double> a{Eigen::Index(n), Eigen::Index(n)};
        a.setFromTriplets(trip.begin(), trip.end());
        Eigen::SparseLU<Eigen::SparseMatrix<double>> solver;
        solver.compute(a);
        if (solver.info() != Eigen::Success)
            throw_error(Error::Kind::invalid, source, "sphere map: the Tutte system is singular");
        const Eigen::VectorXd sx = solver.solve(bx), sy = solver.solve(by);
        for (std::size_t r = 0; r < n; ++r) px[inner[r]] = sx[Eigen::Index(r)], py[inner[r]] = sy[Eigen::Index(r)];
    };
    // Inverse stereographic projection, scaled so half the inner points fall on the southern hemisphere.
    auto project = [&]() {
        std::vector<double> radius;
        for (auto p : inner) radius.push_back(std::hypot(px[p], py[p]));
        double scale = 1;
        if (!radius.empty()) {
            std::nth_element(radius.begin(), radius.begin() + long(radius.size() / 2), radius.end());
            const double median = radius[radius.size() / 2];
            if (median > 0 && std::isfinite(median)) scale = 1 / median;
        }
        std::vector<D3> y(np);
        for (std::size_t p = 0; p < np; ++p) {
            const double u = px[p] * scale, v = py[p] * scale, r2 = u * u + v * v;
            // Mirrored (−v) so the counter-clockwise planar faces stay counter-clockwise seen from outside.
            y[p] = sphere::normalized({2 * u, -2 * v, r2 - 1});
        }
        return y;
    };
    // Area distortion per face: (3D area share) / (sphere area share); 1 everywhere for an area-preserving map.
    const double total_3d = std::accumulate(face_area.begin(), face_area.end(), 0.0);
    auto distortion = [&](const std::vector<D3>& y, std::vector<double>& ratio) {
        double total_s = 0;
        std::vector<double> as(m.faces.size());
        for (std::size_t f = 0; f < m.faces.size(); ++f) {
            const auto& t = m.faces[f];
            as[f] = std::max(1e-300, sphere::norm(sphere::cross(sphere::sub(y[t[1]], y[t[0]]), sphere::sub(y[t[2]], y[t[0]]))));
            total_s += as[f];
        }
        ratio.resize(m.faces.size());
        double energy = 0;
        for (std::size_t f = 0; f < m.faces.size(); ++f) {
            ratio[f] = (face_area[f] / total_3d) / (as[f] / total_s);
            energy += face_area[f] / total_3d * ratio[f];
        }
        return energy;  // ≥ 1, = 1 when area-proportional
    };

    // Stretch-reweighted Tutte (after Yoshizawa, Belyaev, Seidel, "A fast and simple stretch-minimizing
    // mesh parameterization", SMI 2004): the plain embedding crowds protrusions into tiny clusters; each
    // round divides a neighbour's weight by its area stretch on the sphere, so crowded regions push out.
    std::vector<double> factor(np, 1.0), ratio, best_factor = factor;
    double best_energy = INFINITY;
    std::vector<D3> x;
    for (int round = 0; round < std::max(1, params.stretch_rounds); ++round) {
        check_progress(progress, 0.3 * round / std::max(1, params.stretch_rounds), "sphere map: Tutte embedding");
        tutte(factor);
        std::vector<D3> y = project();
        const double energy = distortion(y, ratio);
        if (energy < best_energy) best_energy = energy, best_factor = factor, x = std::move(y);
        std::vector<double> stretch(np, 0), weight(np, 0);
        for (std::size_t f = 0; f < m.faces.size(); ++f)
            for (auto p : m.faces[f]) stretch[p] += face_area[f] * ratio[f], weight[p] += face_area[f];
        for (std::size_t p = 0; p < np; ++p) {
            const double sigma = weight[p] > 0 ? std::sqrt(stretch[p] / weight[p]) : 1.0;
            factor[p] /= std::clamp(sigma, 0.1, 10.0);
        }
    }
    out.area_distortion = best_energy;
    check_progress(progress, 0.3, "sphere map: relaxation");
    if (folded_faces(x, m) > m.faces.size() / 2)
        for (auto& p : x) p[0] = -p[0];

    // Local repair: only the points of folded faces move (towards their neighbours' centroid), so the
    // stretch-balanced layout stays as it is everywhere else (global Laplacian relaxation measurably
    // undoes the balancing: on Spot it raised the distortion from 1.7 to 126).
    for (int sweep = 0; sweep < params.repair_sweeps && folded_faces(x, m) > 0; ++sweep) relax_sweep(x, m, star, true);
    // Fallback: global relaxation with Möbius centering until nothing is folded.
    for (int round = 0; round < params.fallback_rounds && folded_faces(x, m) > 0; ++round) {
        check_progress(progress, 0.5 + 0.5 * round / std::max(1, params.fallback_rounds), "sphere map: relaxation");
        center_step(x, m, face_area);
        for (int sweep = 0; sweep < 10; ++sweep) relax_sweep(x, m, star, false);
    }
    const std::size_t folds = folded_faces(x, m);
    if (folds)
        throw_error(Error::Kind::invalid, source,
                    "sphere map failed: " + std::to_string(folds) + " of " + std::to_string(m.faces.size()) +
                        " faces stay folded on the sphere (degenerate or extremely thin geometry)");
    out.min_face_orient = INFINITY;
    for (const auto& f : m.faces) out.min_face_orient = std::min(out.min_face_orient, face_det(x, f));
    out.min_face_angle = min_angle(x, m);
    out.points = std::move(x);
    check_progress(progress, 1.0, "sphere map");
    return out;
}

}  // namespace lodforge

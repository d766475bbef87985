// Vertex clustering on a uniform grid with quadric representatives.
//
// Rossignac & Borrel, "Multi-resolution 3D approximations for rendering complex scenes" (1993): every
// vertex moves to a representative of its grid cell, triangles with two corners in one cell vanish.
// Lindstrom, "Out-of-Core Simplification of Large Polygonal Models" (SIGGRAPH 2000): the representative
// minimises the sum of the plane quadrics of the triangles touching the cell, solved with a
// pseudo-inverse so flat and straight cells stay stable. Attributes use Hoppe's generalized quadric
// (IEEE Visualization 1999, quadric.h), eliminated into the position solve and evaluated at the
// representative for the output attributes. The cell size comes from a secant search in log space
// (triangle count ~ size^-2) bracketed like regula falsi.
#include "union_find.h"
#include "lodforge/simplify/simplify_cluster.h"

#include "lodforge/error.h"
#include "lodforge/simplify/quadric.h"


#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <string>

namespace lodforge {
namespace {

constexpr std::uint32_t kNone = ~0u;
constexpr std::uint32_t kMaxCells = 1u << 20;  // per axis: 3 × 21 bits pack into one 64-bit code

std::uint64_t mix(std::uint64_t x) {  // splitmix64 finaliser
    x ^= x >> 30;
    x *= 0xbf58476d1ce4e5b9ull;
    x ^= x >> 27;
    x *= 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

std::size_t table_size(std::size_t n) {
    std::size_t s = 16;
    while (s < 2 * n) s <<= 1;
    return s;
}

// The grid for one cell size, and the dense cell id of every used vertex.
struct Grid {
    Vec3f origin;
    double size = 0;
    std::uint32_t dims[3] = {1, 1, 1};
    std::vector<std::uint32_t> cell_of;   // vertex → dense cell (kNone when unused)
    std::vector<std::uint64_t> codes;     // dense cell → packed (i, j, k)

    std::uint64_t code(Vec3f p) const {
        auto axis = [&](float v, float o, std::uint32_t d) {
            const double c = std::floor((static_cast<double>(v) - o) / size);
            return static_cast<std::uint64_t>(std::clamp(c, 0.0, static_cast<double>(d - 1)));
        };
        return (axis(p.x, origin.x, dims[0]) << 42) | (axis(p.y, origin.y, dims[1]) << 21) | axis(p.z, origin.z, dims[2]);
    }
};

class Clusterer {
public:
    Clusterer(const Mesh& mesh, const ClusterParams& params, Progress* progress)
        : mesh_(mesh), params_(params), progress_(progress) {
        const std::size_t n = mesh.vertex_count();
        used_.assign(n, 0);
        for (std::uint32_t v : mesh.indices) used_[v] = 1;
        for (std::uint32_t v = 0; v < n; ++v)
            if (used_[v]) bounds_.add(mesh.positions[v]);
        const Vec3f s = bounds_.size();
        longest_ = std::max({s.x, s.y, s.z});
        diagonal_ = bounds_.diagonal();
        if (!(longest_ > 0.f)) throw Error(Error::Kind::invalid, "simplify_cluster: the mesh has no extent");
    }

    // Dense cell ids for cell size h; returns the number of distinct non-degenerate triangles.
    std::size_t assign(double h, Grid& g) {
        g.origin = bounds_.min;
        g.size = h;
        const Vec3f s = bounds_.size();
        const float ext[3] = {s.x, s.y, s.z};
        for (int a = 0; a < 3; ++a)
            g.dims[a] = static_cast<std::uint32_t>(
                std::clamp(std::floor(static_cast<double>(ext[a]) / h) + 1.0, 1.0, static_cast<double>(kMaxCells)));
        const std::size_t n = mesh_.vertex_count();
        g.cell_of.assign(n, kNone);
        g.codes.clear();
        const std::size_t cap = table_size(n);
        keys_.assign(cap, ~0ull);
        ids_.resize(cap);
        const std::size_t mask = cap - 1;
        for (std::uint32_t v = 0; v < n; ++v) {
            if (!used_[v]) continue;
            const std::uint64_t c = g.code(mesh_.positions[v]);
            std::size_t slot = mix(c) & mask;
            while (keys_[slot] != ~0ull && keys_[slot] != c) slot = (slot + 1) & mask;
            if (keys_[slot] != c) {
                keys_[slot] = c;
                ids_[slot] = static_cast<std::uint32_t>(g.codes.size());
                g.codes.push_back(c);
            }
            g.cell_of[v] = ids_[slot];
        }
        return count_triangles(g, nullptr);
    }

    // Distinct triangles on cells (either winding counts once). With `keep`, receives the input face
    // of each kept triangle in input order.
    std::size_t count_triangles(const Grid& g, std::vector<std::uint32_t>* keep) {
        const std::size_t faces = mesh_.triangle_count();
        const std::size_t cap = table_size(faces);
        tri_.assign(cap * 3, kNone);
        const std::size_t mask = cap - 1;
        std::size_t count = 0;
        for (std::size_t f = 0; f < faces; ++f) {
            std::uint32_t c[3] = {g.cell_of[mesh_.indices[3 * f]], g.cell_of[mesh_.indices[3 * f + 1]],
                                  g.cell_of[mesh_.indices[3 * f + 2]]};
            if (c[0] == c[1] || c[1] == c[2] || c[0] == c[2]) continue;
            if (c[0] > c[1]) std::swap(c[0], c[1]);
            if (c[1] > c[2]) std::swap(c[1], c[2]);
            if (c[0] > c[1]) std::swap(c[0], c[1]);
            std::size_t slot = mix((static_cast<std::uint64_t>(c[0]) << 32 | c[1]) ^ mix(c[2])) & mask;
            bool found = false;
            while (tri_[3 * slot] != kNone) {
                if (tri_[3 * slot] == c[0] && tri_[3 * slot + 1] == c[1] && tri_[3 * slot + 2] == c[2]) {
                    found = true;
                    break;
                }
                slot = (slot + 1) & mask;
            }
            if (found) continue;
            std::memcpy(&tri_[3 * slot], c, sizeof c);
            ++count;
            if (keep) keep->push_back(static_cast<std::uint32_t>(f));
        }
        return count;
    }

    ClusterResult run();

private:
    double search(std::size_t target, ClusterResult& out);
    void build(const Grid& g, ClusterResult& out);

    const Mesh& mesh_;
    const ClusterParams& params_;
    Progress* progress_;
    std::vector<std::uint8_t> used_;
    Bounds bounds_;
    float longest_ = 0, diagonal_ = 0;
    std::vector<std::uint64_t> keys_;
    std::vector<std::uint32_t> ids_;
    std::vector<std::uint32_t> tri_;
};

double Clusterer::search(std::size_t target, ClusterResult& out) {
    // Initial guess: a surface of area A crosses about 1.5 A / h² cells, and a closed triangulation has
    // about twice as many triangles as vertices.
    double area = 0;
    for (std::size_t f = 0; f < mesh_.triangle_count(); ++f) {
        const Vec3f* p = &mesh_.positions[0];
        const std::uint32_t* i = &mesh_.indices[3 * f];
        area += 0.5 * static_cast<double>(length(cross(p[i[1]] - p[i[0]], p[i[2]] - p[i[0]])));
    }
    const double h_min = static_cast<double>(longest_) / (kMaxCells - 1);
    const double h_max = 2.0 * longest_;
    double h = std::clamp(std::sqrt(3.0 * area / static_cast<double>(target)), h_min, h_max);
    const double want = static_cast<double>(target);
    double lo_h = 0, lo_f = 0;   // a size giving more triangles than wanted (smaller cells)
    double hi_h = 0, hi_f = 0;   // a size giving fewer
    double best_h = h, finest_h = h;
    double best_gap = INFINITY;
    Grid g;
    out.reason = ClusterResult::StopReason::closest;
    for (int pass = 0; pass < params_.max_passes; ++pass) {
        check_progress(progress_, 0.6 * pass / params_.max_passes, "cluster: grid search");
        const std::size_t f = assign(h, g);
        ++out.passes;
        // A size that keeps no triangle is never the closest (a thin part collapses to nothing once the
        // cells are wider than it): the target is at least one triangle.
        const double gap = f > 0 ? std::fabs(static_cast<double>(f) - want) : INFINITY;
        finest_h = std::min(finest_h, h);
        if (gap < best_gap) {
            best_gap = gap;
            best_h = h;
        }
        if (gap <= params_.tolerance * want) {
            out.reason = ClusterResult::StopReason::target_reached;
            break;
        }
        if (static_cast<double>(f) > want) {
            lo_h = h;
            lo_f = static_cast<double>(f);
        } else {
            if (h <= h_min * 1.000001) {
                out.reason = ClusterResult::StopReason::grid_limit;
                break;
            }
            hi_h = h;
            hi_f = std::max<double>(static_cast<double>(f), 0.5);
        }
        double next;
        if (lo_h > 0 && hi_h > 0) {
            if (hi_h / lo_h < 1.0 + 1e-7) break;  // the count jumps over the target between these sizes
            // Secant on log f = a + b log h, kept well inside the bracket.
            const double t = (std::log(want) - std::log(lo_f)) / (std::log(hi_f) - std::log(lo_f));
            const double tc = std::clamp(t, 0.1, 0.9);
            next = std::exp(std::log(lo_h) + tc * (std::log(hi_h) - std::log(lo_h)));
        } else {
            const double ratio = std::clamp(std::sqrt(std::max<double>(static_cast<double>(f), 0.5) / want), 0.25, 4.0);
            next = std::clamp(h * ratio, h_min, h_max);
            if (next == h) break;
        }
        h = next;
    }
    return std::isfinite(best_gap) ? best_h : finest_h;
}

void Clusterer::build(const Grid& g, ClusterResult& out) {
    const Mesh& m = mesh_;
    const std::size_t n = m.vertex_count();
    const std::size_t cells = g.codes.size();
    out.grid_origin = g.origin;
    out.cell_size = static_cast<float>(g.size);
    std::copy(std::begin(g.dims), std::end(g.dims), std::begin(out.grid_dims));

    // Wedge classes: vertices of a cell joined by an edge inside the cell are one class. Cells without
    // seam vertices (a position shared by several vertices) are one class; elsewhere classes without
    // a seam vertex join the cell's largest class.
    const bool attributes = m.has_normals() || m.has_colors() || m.has_texcoords();
    detail::UnionFind sets(n);
    std::vector<std::uint8_t> seam(n, 0);
    std::vector<std::uint8_t> cell_has_seam(cells, 0);
    if (params_.preserve_seams && attributes) {
        std::vector<std::uint32_t> order;
        order.reserve(n);
        for (std::uint32_t v = 0; v < n; ++v)
            if (used_[v]) order.push_back(v);
        const auto& P = m.positions;
        std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
            if (P[a].x != P[b].x) return P[a].x < P[b].x;
            if (P[a].y != P[b].y) return P[a].y < P[b].y;
            return P[a].z < P[b].z;
        });
        for (std::size_t i = 1; i < order.size(); ++i)
            if (P[order[i]] == P[order[i - 1]]) seam[order[i]] = seam[order[i - 1]] = 1;
        for (std::uint32_t v = 0; v < n; ++v)
            if (seam[v]) cell_has_seam[g.cell_of[v]] = 1;
    }
    {
        std::vector<std::uint32_t> first(cells, kNone);
        for (std::uint32_t v = 0; v < n; ++v) {
            if (!used_[v]) continue;
            const std::uint32_t c = g.cell_of[v];
            if (cell_has_seam[c]) continue;
            if (first[c] == kNone) first[c] = v;
            else sets.unite(first[c], v);
        }
        for (std::size_t f = 0; f < m.triangle_count(); ++f)
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t a = m.indices[3 * f + k], b = m.indices[3 * f + (k + 1) % 3];
                if (g.cell_of[a] == g.cell_of[b] && cell_has_seam[g.cell_of[a]]) sets.unite(a, b);
            }
        // Classes without a seam vertex join the cell's largest class.
        std::vector<std::uint32_t> size(n, 0);
        std::vector<std::uint8_t> class_has_seam(n, 0);
        for (std::uint32_t v = 0; v < n; ++v)
            if (used_[v] && cell_has_seam[g.cell_of[v]]) {
                ++size[sets.find(v)];
                if (seam[v]) class_has_seam[sets.find(v)] = 1;
            }
        std::vector<std::uint32_t> largest(cells, kNone);
        for (std::uint32_t v = 0; v < n; ++v) {
            if (!used_[v] || !cell_has_seam[g.cell_of[v]] || sets.find(v) != v) continue;
            std::uint32_t& l = largest[g.cell_of[v]];
            if (l == kNone || size[v] > size[l]) l = v;
        }
        for (std::uint32_t v = 0; v < n; ++v) {
            if (!used_[v] || !cell_has_seam[g.cell_of[v]]) continue;
            const std::uint32_t r = sets.find(v);
            if (!class_has_seam[r]) sets.unite(largest[g.cell_of[v]], v);
        }
    }
    std::vector<std::uint32_t> class_of(n, kNone);
    std::vector<std::uint32_t> class_cell;
    for (std::uint32_t v = 0; v < n; ++v) {
        if (!used_[v]) continue;
        const std::uint32_t r = sets.find(v);
        if (class_of[r] == kNone) {
            class_of[r] = static_cast<std::uint32_t>(class_cell.size());
            class_cell.push_back(g.cell_of[v]);
        }
        class_of[v] = class_of[r];
    }
    const std::size_t classes = class_cell.size();

    // Quadrics in coordinates normalised to a unit diagonal (weights mean what they mean for simplify()).
    const Vec3f centre = bounds_.center();
    const double scale = diagonal_ > 0 ? diagonal_ : 1.0;
    auto norm = [&](Vec3f p) {
        return Vec3d{(p.x - centre.x) / scale, (p.y - centre.y) / scale, (p.z - centre.z) / scale};
    };
    const SimplifyWeights& w = params_.weights;
    auto eff = [](float x) { return std::max(static_cast<double>(x), 1e-4); };
    const double wn = eff(w.normal), wc = eff(w.color);
    std::vector<double> wt(m.texcoords.size());
    for (std::size_t s = 0; s < wt.size(); ++s) wt[s] = eff(s < w.texcoord_sets.size() ? w.texcoord_sets[s] : w.texcoord);
    const std::size_t dim = (m.has_normals() ? 3 : 0) + (m.has_colors() ? 4 : 0) + 2 * m.texcoords.size();
    auto attributes_of = [&](std::uint32_t v, double* s) {
        std::size_t j = 0;
        if (m.has_normals()) {
            const Vec3f nn = m.normals[v];
            s[j++] = wn * nn.x; s[j++] = wn * nn.y; s[j++] = wn * nn.z;
        }
        if (m.has_colors()) {
            const Vec4f c = m.colors[v];
            s[j++] = wc * c.x; s[j++] = wc * c.y; s[j++] = wc * c.z; s[j++] = wc * c.w;
        }
        for (std::size_t t = 0; t < m.texcoords.size(); ++t) {
            s[j++] = wt[t] * m.texcoords[t][v].x;
            s[j++] = wt[t] * m.texcoords[t][v].y;
        }
    };

    std::vector<Quadric> geo(cells);
    AttributeQuadrics attr(dim ? classes : 0, dim);
    std::vector<double> mean(3 * cells, 0.0);
    std::vector<std::uint32_t> members(cells, 0);
    for (std::uint32_t v = 0; v < n; ++v) {
        if (!used_[v]) continue;
        const Vec3d p = norm(m.positions[v]);
        const std::uint32_t c = g.cell_of[v];
        mean[3 * c] += p.x; mean[3 * c + 1] += p.y; mean[3 * c + 2] += p.z;
        ++members[c];
    }
    std::vector<double> s0(dim), s1(dim), s2(dim);
    const std::size_t faces = m.triangle_count();
    for (std::size_t f = 0; f < faces; ++f) {
        if ((f & 0xffff) == 0) check_progress(progress_, 0.6 + 0.3 * static_cast<double>(f) / faces, "cluster: quadrics");
        const std::uint32_t* i = &m.indices[3 * f];
        const Vec3d p0 = norm(m.positions[i[0]]), p1 = norm(m.positions[i[1]]), p2 = norm(m.positions[i[2]]);
        double area = 0;
        const std::optional<Quadric> q = Quadric::from_triangle(p0, p1, p2, area);
        if (!q) continue;
        for (int k = 0; k < 3; ++k) geo[g.cell_of[i[k]]] += *q;
        if (dim) {
            attributes_of(i[0], s0.data());
            attributes_of(i[1], s1.data());
            attributes_of(i[2], s2.data());
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t cl = class_of[i[k]];
                if (k > 0 && cl == class_of[i[0]]) continue;
                if (k > 1 && cl == class_of[i[1]]) continue;
                attr.add_triangle(cl, p0, p1, p2, s0.data(), s1.data(), s2.data(), area);
            }
        }
    }

    // Representative of every cell: pseudo-inverse solve around the cell's mean vertex, clamped.
    std::vector<Quadric> total = geo;
    if (dim)
        for (std::size_t cl = 0; cl < classes; ++cl) total[class_cell[cl]] += attr.eliminated(cl);
    std::vector<Vec3d> rep(cells);
    for (std::size_t c = 0; c < cells; ++c) {
        const double k = members[c] ? 1.0 / members[c] : 0.0;
        const Vec3d near = minimizer_near(total[c], {mean[3 * c] * k, mean[3 * c + 1] * k, mean[3 * c + 2] * k});
        double x[3] = {near.x, near.y, near.z};
        // Clamp into the cell (in model units, where the grid lives).
        const std::uint64_t code = g.codes[c];
        const std::uint32_t cid[3] = {static_cast<std::uint32_t>(code >> 42), static_cast<std::uint32_t>((code >> 21) & 0x1fffff),
                                      static_cast<std::uint32_t>(code & 0x1fffff)};
        const float o[3] = {g.origin.x, g.origin.y, g.origin.z};
        const float ctr[3] = {centre.x, centre.y, centre.z};
        for (int a = 0; a < 3; ++a) {
            const double lo = o[a] + g.size * cid[a], hi = lo + g.size;
            const double model = std::clamp(x[a] * scale + ctr[a], lo, hi);
            x[a] = (model - ctr[a]) / scale;
        }
        rep[c] = {x[0], x[1], x[2]};
    }

    // Triangles kept (first of each cell triple, input order) and the vertices they use.
    std::vector<std::uint32_t> keep;
    keep.reserve(faces / 4);
    count_triangles(g, &keep);
    std::vector<std::uint8_t> class_used(classes, 0);
    for (std::uint32_t f : keep)
        for (int k = 0; k < 3; ++k) class_used[class_of[m.indices[3 * f + k]]] = 1;
    // Layout: one vertex per point (cell) first, in class order; extra wedges after.
    PointsFirstLayout cell_layout = points_first_layout(class_used, class_cell, cells);
    const std::vector<std::uint32_t>& point_of_cell = cell_layout.point_of_group;
    const std::vector<std::uint32_t>& layout = cell_layout.order;
    std::vector<std::uint32_t> out_of_class(classes, kNone);
    for (std::uint32_t i = 0; i < layout.size(); ++i) out_of_class[layout[i]] = i;

    Mesh& o = out.mesh;
    const std::size_t outn = layout.size();
    o.positions.resize(outn);
    o.position_ids.resize(outn);
    if (m.has_normals()) o.normals.resize(outn);
    if (m.has_colors()) o.colors.resize(outn);
    o.texcoords.assign(m.texcoords.size(), std::vector<Vec2f>(outn));
    // Fallback attributes for classes with no usable attribute quadric: those of one member vertex.
    std::vector<std::uint32_t> member(classes, kNone);
    for (std::uint32_t v = 0; v < n; ++v)
        if (used_[v] && member[class_of[v]] == kNone) member[class_of[v]] = v;
    std::vector<double> s(dim);
    double max_cost = 0;
    for (std::uint32_t i = 0; i < outn; ++i) {
        const std::uint32_t cl = layout[i];
        const std::uint32_t c = class_cell[cl];
        const Vec3d p = rep[c];
        o.positions[i] = {static_cast<float>(p.x * scale + centre.x), static_cast<float>(p.y * scale + centre.y),
                          static_cast<float>(p.z * scale + centre.z)};
        o.position_ids[i] = point_of_cell[c];
        double cost = geo[c].evaluate(p);
        if (dim) {
            if (!attr.optimal_attributes(cl, p, s.data())) attributes_of(member[cl], s.data());
            else cost += attr.evaluate(cl, p, s.data());
            std::size_t j = 0;
            if (m.has_normals()) {
                Vec3f nn{static_cast<float>(s[j] / wn), static_cast<float>(s[j + 1] / wn), static_cast<float>(s[j + 2] / wn)};
                j += 3;
                const float len = length(nn);
                o.normals[i] = len > 0.f ? nn * (1.f / len) : m.normals[member[cl]];
            }
            if (m.has_colors()) {
                auto ch = [&](std::size_t k) { return static_cast<float>(std::clamp(s[j + k] / wc, 0.0, 1.0)); };
                o.colors[i] = {ch(0), ch(1), ch(2), ch(3)};
                j += 4;
            }
            for (std::size_t t = 0; t < m.texcoords.size(); ++t, j += 2)
                o.texcoords[t][i] = {static_cast<float>(s[j] / wt[t]), static_cast<float>(s[j + 1] / wt[t])};
        }
        if (geo[c].weight > 0) max_cost = std::max(max_cost, cost / geo[c].weight);
    }
    o.indices.resize(3 * keep.size());
    for (std::size_t t = 0; t < keep.size(); ++t)
        for (int k = 0; k < 3; ++k) o.indices[3 * t + k] = out_of_class[class_of[m.indices[3 * keep[t] + k]]];
    if (!m.face_materials.empty()) {
        o.face_materials.resize(keep.size());
        for (std::size_t t = 0; t < keep.size(); ++t) o.face_materials[t] = m.face_materials[keep[t]];
    }
    o.materials = m.materials;
    o.source_dir = m.source_dir;
    out.triangles = keep.size();
    out.error_relative = static_cast<float>(std::sqrt(max_cost));
    out.error = static_cast<float>(std::sqrt(max_cost) * scale);
    out.vertex_cluster.assign(n, kNone);
    for (std::uint32_t v = 0; v < n; ++v)
        if (used_[v]) out.vertex_cluster[v] = out_of_class[class_of[v]];
}

ClusterResult Clusterer::run() {
    ClusterResult out;
    Grid g;
    if (params_.grid_resolution > 0) {
        out.reason = ClusterResult::StopReason::resolution_given;
        assign(static_cast<double>(longest_) / static_cast<double>(params_.grid_resolution), g);
    } else {
        std::size_t target = params_.target_triangles;
        if (params_.target_ratio > 0.f)
            target = std::max(target, static_cast<std::size_t>(std::llround(static_cast<double>(params_.target_ratio) *
                                                                            static_cast<double>(mesh_.triangle_count()))));
        target = std::max<std::size_t>(target, 1);
        out.target_triangles = target;
        const double h = search(target, out);
        assign(h, g);
    }
    check_progress(progress_, 0.6, "cluster: quadrics");
    build(g, out);
    if (out.mesh.triangle_count() == 0)
        throw Error(Error::Kind::invalid,
                    params_.grid_resolution > 0
                        ? "simplify_cluster: a grid of " + std::to_string(params_.grid_resolution) +
                              " cells collapses the mesh to nothing; use a finer grid"
                        : "simplify_cluster: every cell size tried collapses the mesh to nothing (its parts are thinner "
                          "than the cells a target this low needs); use a larger target or --mode collapse");
    check_progress(progress_, 1.0, "cluster");
    return out;
}

}  // namespace

ClusterResult simplify_cluster(const Mesh& mesh, const ClusterParams& params, Progress* progress) {
    const bool target = params.target_triangles > 0 || params.target_ratio != 0.f;
    if (params.target_ratio != 0.f && !(params.target_ratio > 0.f && params.target_ratio <= 1.f))
        throw Error(Error::Kind::argument, "simplify_cluster: target ratio " + std::to_string(params.target_ratio) +
                                               " is outside (0, 1]");
    if (params.grid_resolution > 0 && target)
        throw Error(Error::Kind::argument, "simplify_cluster: give either a grid resolution or a triangle target, not both");
    if (params.grid_resolution == 0 && !target)
        throw Error(Error::Kind::argument, "simplify_cluster: give a triangle target or a grid resolution");
    if (params.grid_resolution >= kMaxCells)
        throw Error(Error::Kind::argument, "simplify_cluster: grid resolution must be below " + std::to_string(kMaxCells));
    if (!(params.tolerance >= 0.f && params.tolerance < 1.f))
        throw Error(Error::Kind::argument, "simplify_cluster: tolerance must be in [0, 1)");
    if (params.max_passes < 1) throw Error(Error::Kind::argument, "simplify_cluster: max_passes must be at least 1");
    if (mesh.triangle_count() == 0) throw Error(Error::Kind::invalid, "simplify_cluster: the mesh has no triangles");
    Clusterer c(mesh, params, progress);
    return c.run();
}

}  // namespace lodforge

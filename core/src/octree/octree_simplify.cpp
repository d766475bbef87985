// Node simplification of the out-of-core octree.
//
// Bade, Daman, Sunar, Tan, "Out-of-Core Simplification with Appearance Preservation for Computer
// Game Applications" (Universiti Teknologi Malaysia report, 2006, §3.5): a modified
// vertex clustering (Rossignac & Borrel 1993) in which the node's boundary edges are preserved and
// fanned to one representative
// vertex, every interior triangle dropped; the representative minimises the node's generalized quadric
// (Garland & Heckbert, "Simplifying Surfaces with Color and Texture using Quadric Error Metrics",
// IEEE Visualization 1998; stored in Hoppe's 1999 form, quadric.h), solved with a pseudo-inverse around
// the mean vertex as in Lindstrom's OoCS (SIGGRAPH 2000) and clamped into the node cell. Boundary edges
// are found with a hash map of edge use counts (the document's list search is its §5.4 bottleneck).
#include "union_find.h"
#include "lodforge/octree/octree_simplify.h"

#include "octree/ooc_internal.h"
#include "octree/part_collapse.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numeric>

namespace lodforge {
namespace {

constexpr std::uint32_t kNone = ~0u;
constexpr std::uint64_t kClusterKey = std::uint64_t{1} << 62;  // with kRepresentativeKey: a cluster vertex
// A collapsed part stops at its target (its fan's size, or the level ratio of its triangles) or before a
// collapse whose error estimate exceeds this
// fraction of the node's cell side, so each level's error bound doubles with its cell size. Measured on
// the bunny at 2 000 per leaf (docs/octree.md, "Parts simplified by edge collapse"): 0.01 made levels
// 30 % larger, 0.04 doubled the Hausdorff distance.
constexpr double kCollapseError = 0.02;

double weight_or_floor(float w) { return std::max(static_cast<double>(w), 1e-4); }

double texcoord_weight(const SimplifyWeights& w) {
    return weight_or_floor(!w.texcoord_sets.empty() ? w.texcoord_sets[0] : w.texcoord);
}


// Whether the edge a–b of a node's input is shared with no other node: an input border edge, a chord a
// descendant made of free edges, or an edge between one node's cluster vertices (the border of a
// clustered component that had holes).
bool free_edge(const NodeMesh& input, const NodeBorderEdges& border, std::uint32_t a, std::uint32_t b) {
    const std::uint64_t ka = input.keys[a], kb = input.keys[b];
    constexpr std::uint64_t cluster = kRepresentativeKey | kClusterKey;
    if ((ka & cluster) == cluster && (kb & cluster) == cluster) return true;
    if ((ka | kb) & kRepresentativeKey) return false;
    if (border.input) {
        const std::uint64_t x = ka & 0xffffffffu, y = kb & 0xffffffffu;
        const std::uint64_t key = x < y ? (x << 32 | y) : (y << 32 | x);
        if (std::binary_search(border.input->begin(), border.input->end(), key)) return true;
    }
    if (border.chords) {
        const std::pair<std::uint64_t, std::uint64_t> c{std::min(ka, kb), std::max(ka, kb)};
        if (std::binary_search(border.chords->begin(), border.chords->end(), c)) return true;
    }
    return false;
}

// The border edges of a collapsed part whose border was all free are shared with no other node: they
// are free for the parent, as chords are (added to `chords`, which the caller keeps sorted).
void free_border_chords(const NodeMesh& input, const std::vector<std::uint32_t>& indices,
                        std::vector<std::pair<std::uint64_t, std::uint64_t>>& chords) {
    std::map<std::pair<std::uint64_t, std::uint64_t>, int> net;
    for (std::size_t c = 0; c < indices.size(); c += 3)
        for (int k = 0; k < 3; ++k) {
            const std::uint64_t a = input.keys[indices[c + k]], b = input.keys[indices[c + (k + 1) % 3]];
            net[{std::min(a, b), std::max(a, b)}] += a < b ? 1 : -1;
        }
    for (const auto& [edge, n] : net)
        if (n != 0) chords.push_back(edge);
}

// Chains of free edges (input border edges, and chords earlier nodes made of them) are shared with no
// other node, so a node may replace each maximal chain by two chords through its middle vertex between its
// pinned ends: vertices
// that touch a kept edge that is not free, or where free edges branch. Every vertex keeps as many
// kept uses coming in as going out, so the fan stays paired; a loop of free edges with no pinned vertex
// (a hole wholly inside the node) is dropped, which fills the hole. docs/octree.md, "Coarse levels".
std::vector<std::pair<std::uint32_t, std::uint32_t>> collapse_free_chains(
    const NodeMesh& input, const std::vector<std::pair<std::uint32_t, std::uint32_t>>& kept,
    const std::vector<std::uint32_t>& kept_component, const std::vector<std::uint8_t>& frozen, const NodeBorderEdges& border,
    float cell_size, NodeSimplifyStats& st, std::vector<std::uint32_t>& origin) {
    const std::size_t n = input.vertex_count();
    std::vector<std::uint8_t> free(kept.size());
    std::vector<std::uint32_t> free_in(n, 0), free_out(n, 0);
    std::vector<std::uint8_t> pinned(n, 0);
    std::vector<std::uint32_t> next_use(n, kNone);  // the free use leaving an unpinned vertex
    bool any = false;
    for (std::size_t i = 0; i < kept.size(); ++i) {
        const auto [a, b] = kept[i];
        free[i] = !frozen[kept_component[i]] && free_edge(input, border, a, b);
        if (!free[i]) {
            pinned[a] = pinned[b] = 1;
            continue;
        }
        any = true;
        ++free_out[a];
        ++free_in[b];
        next_use[a] = static_cast<std::uint32_t>(i);
    }
    origin.clear();
    if (!any) {
        origin.resize(kept.size());
        std::iota(origin.begin(), origin.end(), 0u);
        return kept;
    }
    for (std::size_t v = 0; v < n; ++v)
        if (free_in[v] != 1 || free_out[v] != 1) pinned[v] = 1;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> out;
    out.reserve(kept.size());
    std::vector<std::uint8_t> done(kept.size(), 0);
    std::vector<std::uint32_t> chain;  // vertices of the chain being walked
    // Each output use remembers the kept use it comes from (`origin`); a chain lies in one component.
    std::uint32_t from = 0;
    auto emit = [&](std::uint32_t a, std::uint32_t b) {
        out.emplace_back(a, b);
        origin.push_back(from);
    };
    auto chord = [&](std::uint32_t a, std::uint32_t b) {
        emit(a, b);
        st.chords.emplace_back(std::min(input.keys[a], input.keys[b]), std::max(input.keys[a], input.keys[b]));
    };
    auto walk = [&](std::size_t i) {
        chain.assign({kept[i].first});
        done[i] = 1;
        std::uint32_t end = kept[i].second;
        while (!pinned[end] && end != chain.front()) {
            chain.push_back(end);
            const std::uint32_t u = next_use[end];
            done[u] = 1;
            end = kept[u].second;
        }
        return end;
    };
    for (std::size_t i = 0; i < kept.size(); ++i) {
        from = static_cast<std::uint32_t>(i);
        if (!free[i]) {
            emit(kept[i].first, kept[i].second);
            continue;
        }
        if (done[i] || !pinned[kept[i].first]) continue;
        // From a pinned vertex to the next: a→m→d through the chain's middle vertex m. The chord ends
        // are never joined by an input edge elsewhere (m's triangles all lie in this node), so a chord
        // cannot merge with a real edge in a coarser node.
        const std::uint32_t end = walk(i);
        const std::uint32_t a = chain.front();
        if (a == end) continue;  // a loop through one pinned vertex: in and out vanish together
        if (chain.size() <= 2) {
            for (std::size_t k = 0; k < chain.size(); ++k) emit(chain[k], k + 1 < chain.size() ? chain[k + 1] : end);
            continue;
        }
        const std::uint32_t m = chain[chain.size() / 2];
        chord(a, m);
        chord(m, end);
    }
    // Loops of unpinned vertices: a hole or an outer border wholly inside the node. Small ones (within
    // one 16th of the cell) are dropped, which fills the hole; larger ones keep kLoopVertices vertices.
    constexpr std::size_t kLoopVertices = 8;
    for (std::size_t i = 0; i < kept.size(); ++i) {
        if (!free[i] || done[i]) continue;
        from = static_cast<std::uint32_t>(i);
        walk(i);
        float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (std::uint32_t v : chain)
            for (int a = 0; a < 3; ++a) {
                lo[a] = std::min(lo[a], input.vertex(v)[a]);
                hi[a] = std::max(hi[a], input.vertex(v)[a]);
            }
        const float extent = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
        if (extent < cell_size / 16) continue;
        if (chain.size() <= kLoopVertices) {
            for (std::size_t k = 0; k < chain.size(); ++k) emit(chain[k], chain[(k + 1) % chain.size()]);
            continue;
        }
        for (std::size_t k = 0; k < kLoopVertices; ++k)
            chord(chain[k * chain.size() / kLoopVertices], chain[(k + 1) % kLoopVertices * chain.size() / kLoopVertices]);
    }
    st.free_uses_removed += kept.size() - out.size();
    std::sort(st.chords.begin(), st.chords.end());
    st.chords.erase(std::unique(st.chords.begin(), st.chords.end()), st.chords.end());
    return out;
}

// Components with no boundary edge in the node touch no other node, so they may be simplified freely
// as long as they stay closed: vertex clustering on a grid of kClosedGrid³ cells over the node cell,
// keeping the clustered triangles as an oriented chain (opposite copies of one cell triple cancel, the
// rest are kept with their multiplicity). The boundary of the clustered chain is the clustered boundary
// of the component, zero, so no border edge appears; a component inside one grid cell vanishes.
constexpr int kClosedGrid = 16;

void cluster_closed(const NodeMesh& input, const std::vector<std::uint32_t>& closed, const float cell_min[3],
                    float cell_size, std::uint64_t representative_key, NodeMesh& out, NodeSimplifyStats& st) {
    const std::size_t f = input.layout.floats();
    const std::uint32_t* idx = input.indices.data();
    auto cell_of = [&](std::uint32_t v) {
        const float* p = input.vertex(v);
        std::uint32_t c = 0;
        for (int a = 2; a >= 0; --a) {
            const double x = (static_cast<double>(p[a]) - cell_min[a]) / cell_size * kClosedGrid;
            const int i = std::clamp(static_cast<int>(std::floor(x)), 0, kClosedGrid - 1);
            c = c * kClosedGrid + static_cast<std::uint32_t>(i);
        }
        return c;
    };
    std::vector<std::uint32_t> cell(input.vertex_count(), kNone);
    for (std::uint32_t t : closed)
        for (int k = 0; k < 3; ++k)
            if (cell[idx[3 * t + k]] == kNone) cell[idx[3 * t + k]] = cell_of(idx[3 * t + k]);
    // Net multiplicity per cell triple: +1 for a triangle in the triple's sorted cyclic order, −1 reversed.
    ooc::FlatMap slot(closed.size() + 16);
    std::vector<std::array<std::uint32_t, 3>> triples;
    std::vector<std::int32_t> net;
    for (std::uint32_t t : closed) {
        std::array<std::uint32_t, 3> c{cell[idx[3 * t]], cell[idx[3 * t + 1]], cell[idx[3 * t + 2]]};
        if (c[0] == c[1] || c[1] == c[2] || c[0] == c[2]) continue;
        // Rotate the smallest first; then the order of the other two is the orientation.
        while (c[0] > c[1] || c[0] > c[2]) std::rotate(c.begin(), c.begin() + 1, c.end());
        const bool forward = c[1] < c[2];
        if (!forward) std::swap(c[1], c[2]);
        const std::uint64_t key = std::uint64_t{c[0]} << 24 | std::uint64_t{c[1]} << 12 | c[2];
        bool inserted = false;
        const std::uint32_t s = slot.find_or_insert(key, static_cast<std::uint32_t>(triples.size()), inserted);
        if (inserted) {
            triples.push_back(c);
            net.push_back(0);
        }
        net[s] += forward ? 1 : -1;
    }
    // Cluster vertices: the mean record of the component vertices in the cell.
    std::vector<double> sum;
    std::vector<std::uint32_t> count;
    ooc::FlatMap vertex_of(64);
    auto cluster_vertex = [&](std::uint32_t c) {
        bool inserted = false;
        const std::uint32_t v = vertex_of.find_or_insert(c, static_cast<std::uint32_t>(count.size()), inserted);
        if (inserted) {
            count.push_back(0);
            sum.resize(sum.size() + f, 0.0);
        }
        return v;
    };
    for (std::size_t s = 0; s < triples.size(); ++s)
        if (net[s] != 0)
            for (std::uint32_t c : triples[s]) cluster_vertex(c);
    std::vector<std::uint8_t> seen(input.vertex_count(), 0);
    for (std::uint32_t t : closed)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t v = idx[3 * t + k];
            if (seen[v]) continue;
            seen[v] = 1;
            const std::uint32_t* c = vertex_of.find(cell[v]);
            if (!c) continue;
            ++count[*c];
            for (std::size_t j = 0; j < f; ++j) sum[*c * f + j] += input.vertex(v)[j];
        }
    const std::uint32_t base = static_cast<std::uint32_t>(out.keys.size());
    std::vector<std::uint32_t> cell_id(count.size());
    vertex_of.for_each([&](std::uint64_t c, std::uint32_t v) { cell_id[v] = static_cast<std::uint32_t>(c); });
    for (std::size_t v = 0; v < count.size(); ++v) {
        std::vector<float> r(f);
        for (std::size_t j = 0; j < f; ++j) r[j] = static_cast<float>(sum[v * f + j] / std::max<std::uint32_t>(count[v], 1));
        if (input.layout.normals) {
            float* nrm = &r[input.layout.normal_offset()];
            const float len = std::sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
            if (len > 0)
                for (int a = 0; a < 3; ++a) nrm[a] /= len;
        }
        // Closed components of different materials in one cell keep different cluster vertices (the
        // material in bits 45-61, above the cell's 13 bits).
        const std::uint64_t material = input.layout.material ? static_cast<std::uint64_t>(r[input.layout.material_offset()]) & 0x1ffff : 0;
        out.keys.push_back(representative_key | kClusterKey | material << 45 | (std::uint64_t{cell_id[v]} + 1) << 32);
        out.vertices.insert(out.vertices.end(), r.begin(), r.end());
    }
    std::size_t emitted = 0;
    for (std::size_t s = 0; s < triples.size(); ++s) {
        if (net[s] == 0) continue;
        const std::array<std::uint32_t, 3>& c = triples[s];
        const std::uint32_t a = base + *vertex_of.find(c[0]), b = base + *vertex_of.find(c[1]), d = base + *vertex_of.find(c[2]);
        for (std::int32_t m = 0; m < std::abs(net[s]); ++m) {
            out.indices.push_back(a);
            out.indices.push_back(net[s] > 0 ? b : d);
            out.indices.push_back(net[s] > 0 ? d : b);
            ++emitted;
        }
    }
    st.closed_triangles_in += closed.size();
    st.closed_triangles_out += emitted;
    // Every cluster vertex lies within one grid cell of the surface it stands for.
    st.error = std::max(st.error, static_cast<double>(cell_size) / kClosedGrid);
}

// Splits directed uses that come in and go out equally often at every vertex into simple cycles (no
// vertex twice): cycle number per use. Walks from each unused use, and closes a cycle whenever the walk
// reaches a vertex already on its path. Uses that cannot be closed (a vertex with more uses out than in,
// only possible at odd non-manifold edges) share one number per walk.
std::vector<std::uint32_t> simple_cycles(std::size_t n, const std::vector<std::pair<std::uint32_t, std::uint32_t>>& uses) {
    std::vector<std::uint32_t> first(n + 1, 0);
    for (const auto& [a, b] : uses) ++first[a + 1];
    for (std::size_t v = 0; v < n; ++v) first[v + 1] += first[v];
    std::vector<std::uint32_t> out(uses.size()), cursor(first.begin(), first.end() - 1);
    for (std::size_t e = 0; e < uses.size(); ++e) out[cursor[uses[e].first]++] = static_cast<std::uint32_t>(e);
    std::copy(first.begin(), first.end() - 1, cursor.begin());
    std::vector<std::uint32_t> cycle(uses.size(), kNone), position(n, kNone), path;  // path: uses walked
    std::vector<std::uint8_t> used(uses.size(), 0);
    std::uint32_t cycles = 0;
    auto next_use = [&](std::uint32_t v) {
        while (cursor[v] < first[v + 1] && used[out[cursor[v]]]) ++cursor[v];
        return cursor[v] < first[v + 1] ? out[cursor[v]] : kNone;
    };
    for (std::size_t start = 0; start < uses.size(); ++start) {
        if (used[start]) continue;
        std::uint32_t e = static_cast<std::uint32_t>(start), w = uses[e].first;
        position[w] = 0;
        while (e != kNone) {
            used[e] = 1;
            path.push_back(e);
            w = uses[e].second;
            if (position[w] == kNone) {
                position[w] = static_cast<std::uint32_t>(path.size());
            } else {
                // The uses since w's place on the path close a cycle.
                for (std::size_t i = position[w]; i < path.size(); ++i) {
                    cycle[path[i]] = cycles;
                    if (i > position[w]) position[uses[path[i]].first] = kNone;
                }
                path.resize(position[w]);
                ++cycles;
            }
            e = next_use(w);
        }
        for (std::uint32_t u : path) {
            cycle[u] = cycles;
            position[uses[u].first] = kNone;
        }
        if (!path.empty()) ++cycles;
        path.clear();
        position[uses[start].first] = position[w] = kNone;
    }
    return cycle;
}

// The apex record of a fan: position minimising `quadric` (geometry plus the attribute part eliminated)
// by pseudo-inverse around its mean vertex, so flat and straight patches keep a point near their middle,
// clamped into the node cell and into the bounds of the patch's vertices `patch` (so no fan reaches past
// the surface it replaces); attributes at their quadric optimum there. `error`: RMS plane distance, model units.
std::vector<float> representative(const NodeQuadric& quadric, const NodeMesh& input, const std::vector<std::uint32_t>& patch,
                                  const QuadricFrame& frame, const float cell_min[3], float cell_size, double& error) {
    Quadric total = quadric.geometry;
    if (frame.attribute_dimension() > 0) total += quadric.attributes.eliminated(0);
    double lo[3], hi[3], box_lo[3] = {INFINITY, INFINITY, INFINITY}, box_hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    Vec3d mean{0, 0, 0};
    for (std::uint32_t v : patch) {
        const Vec3d p = frame.to_frame(input.vertex(v));
        const double c[3] = {p.x, p.y, p.z};
        for (int a = 0; a < 3; ++a) {
            box_lo[a] = std::min(box_lo[a], c[a]);
            box_hi[a] = std::max(box_hi[a], c[a]);
        }
        mean = {mean.x + p.x, mean.y + p.y, mean.z + p.z};
    }
    const double count = static_cast<double>(std::max<std::size_t>(patch.size(), 1));
    mean = {mean.x / count, mean.y / count, mean.z / count};
    if (quadric.position_count > 0) {
        const double k = 1.0 / quadric.position_count;
        mean = {quadric.position_sum[0] * k, quadric.position_sum[1] * k, quadric.position_sum[2] * k};
    }
    const double o[3] = {frame.origin.x, frame.origin.y, frame.origin.z};
    for (int a = 0; a < 3; ++a) {
        lo[a] = (cell_min[a] - o[a]) / frame.scale;
        hi[a] = lo[a] + cell_size / frame.scale;
        // A patch always meets its cell (its triangles' centroids are inside); if rounding says not, the
        // patch's bounds alone.
        if (!patch.empty() && std::max(lo[a], box_lo[a]) <= std::min(hi[a], box_hi[a])) {
            lo[a] = std::max(lo[a], box_lo[a]);
            hi[a] = std::min(hi[a], box_hi[a]);
        } else if (!patch.empty()) {
            lo[a] = box_lo[a];
            hi[a] = box_hi[a];
        }
    }
    const Vec3d p = clamped_minimizer(total, mean, lo, hi);
    const std::size_t f = input.layout.floats();
    std::vector<float> rep(f, 0.f);
    rep[0] = static_cast<float>(p.x * frame.scale + frame.origin.x);
    rep[1] = static_cast<float>(p.y * frame.scale + frame.origin.y);
    rep[2] = static_cast<float>(p.z * frame.scale + frame.origin.z);
    const std::size_t m = frame.attribute_dimension();
    if (m > 0) {
        double s[9] = {};
        if (!quadric.attributes.optimal_attributes(0, p, s)) {
            // No area to weigh by (all triangles degenerate): the plain mean of the patch's vertices.
            double tmp[9];
            for (std::uint32_t v : patch) {
                frame.attributes(input.vertex(v), tmp);
                for (std::size_t j = 0; j < m; ++j) s[j] += tmp[j] / count;
            }
        }
        std::size_t j = 0, r = 3;
        if (frame.layout.normals) {
            const double w = weight_or_floor(frame.weights.normal);
            double nx = s[j] / w, ny = s[j + 1] / w, nz = s[j + 2] / w;
            const double len = std::sqrt(nx * nx + ny * ny + nz * nz);
            if (len > 0) {
                nx /= len;
                ny /= len;
                nz /= len;
            } else {
                nx = 0;
                ny = 0;
                nz = 1;
            }
            rep[r++] = static_cast<float>(nx);
            rep[r++] = static_cast<float>(ny);
            rep[r++] = static_cast<float>(nz);
            j += 3;
        }
        if (frame.layout.colors) {
            const double w = weight_or_floor(frame.weights.color);
            for (int a = 0; a < 4; ++a) rep[r++] = static_cast<float>(std::clamp(s[j++] / w, 0.0, 1.0));
        }
        if (frame.layout.texcoords) {
            const double w = texcoord_weight(frame.weights);
            for (int a = 0; a < 2; ++a) rep[r++] = static_cast<float>(s[j++] / w);
        }
    }
    // A material is a label: the patch's own (a connected part has one, its vertices' keys split at
    // material borders).
    if (input.layout.material && !patch.empty()) rep[input.layout.material_offset()] = input.vertex(patch[0])[input.layout.material_offset()];
    error = quadric.geometry.weight > 0 ? std::sqrt(quadric.geometry.evaluate(p) / quadric.geometry.weight) * frame.scale : 0;
    return rep;
}

}  // namespace

NodeMesh merge_node_meshes(const std::vector<const NodeMesh*>& parts) {
    NodeMesh out;
    std::size_t vertices = 0, indices = 0;
    for (const NodeMesh* p : parts) {
        vertices += p->vertex_count();
        indices += p->indices.size();
        out.layout = p->layout;
    }
    const std::size_t f = out.layout.floats();
    out.keys.reserve(vertices);
    out.vertices.reserve(vertices * f);
    out.indices.reserve(indices);
    ooc::FlatMap map(vertices);
    std::vector<std::uint32_t> local;
    for (const NodeMesh* p : parts) {
        local.resize(p->vertex_count());
        for (std::size_t i = 0; i < p->vertex_count(); ++i) {
            bool inserted = false;
            std::uint32_t& v = map.find_or_insert(p->keys[i], static_cast<std::uint32_t>(out.keys.size()), inserted);
            if (inserted) {
                out.keys.push_back(p->keys[i]);
                out.vertices.insert(out.vertices.end(), p->vertex(i), p->vertex(i) + f);
            }
            local[i] = v;
        }
        for (std::uint32_t i : p->indices) out.indices.push_back(local[i]);
    }
    return out;
}

Vec3d QuadricFrame::to_frame(const float* v) const {
    return {(v[0] - origin.x) / scale, (v[1] - origin.y) / scale, (v[2] - origin.z) / scale};
}

void QuadricFrame::attributes(const float* v, double* out) const {
    std::size_t j = 0, k = 3;
    if (layout.normals) {
        const double w = weight_or_floor(weights.normal);
        for (int a = 0; a < 3; ++a) out[j++] = w * v[k++];
    }
    if (layout.colors) {
        const double w = weight_or_floor(weights.color);
        for (int a = 0; a < 4; ++a) out[j++] = w * v[k++];
    }
    if (layout.texcoords) {
        const double w = texcoord_weight(weights);
        for (int a = 0; a < 2; ++a) out[j++] = w * v[k++];
    }
}

void NodeQuadric::add_triangle(const QuadricFrame& frame, const float* v0, const float* v1, const float* v2) {
    const Vec3d p0 = frame.to_frame(v0), p1 = frame.to_frame(v1), p2 = frame.to_frame(v2);
    for (const Vec3d& p : {p0, p1, p2}) {
        position_sum[0] += p.x;
        position_sum[1] += p.y;
        position_sum[2] += p.z;
    }
    position_count += 3;
    double area = 0;
    const std::optional<Quadric> plane = Quadric::from_triangle(p0, p1, p2, area);
    if (!plane) return;
    geometry += *plane;
    const std::size_t m = frame.attribute_dimension();
    if (m == 0) return;
    double s[3][9];
    frame.attributes(v0, s[0]);
    frame.attributes(v1, s[1]);
    frame.attributes(v2, s[2]);
    attributes.add_triangle(0, p0, p1, p2, s[0], s[1], s[2], area);
}

void NodeQuadric::add(const NodeQuadric& other) {
    geometry += other.geometry;
    attributes.add(0, other.attributes, 0);
    for (int a = 0; a < 3; ++a) position_sum[a] += other.position_sum[a];
    position_count += other.position_count;
}

Vec3d clamped_minimizer(const Quadric& q, Vec3d around, const double lo[3], const double hi[3]) {
    const Vec3d v = minimizer_near(q, around);
    return {std::clamp(v.x, lo[0], hi[0]), std::clamp(v.y, lo[1], hi[1]), std::clamp(v.z, lo[2], hi[2])};
}

NodeMesh simplify_node(const NodeMesh& input, const NodeQuadric& quadric, const QuadricFrame& frame,
                       const float cell_min[3], float cell_size, std::uint64_t representative_key,
                       const std::vector<std::uint64_t>* odd_non_manifold_edges, NodeSimplifyStats* stats,
                       const NodeBorderEdges* border) {
    NodeSimplifyStats local_stats;
    NodeSimplifyStats& st = stats ? *stats : local_stats;
    st = {};
    const std::size_t n = input.vertex_count();
    const std::size_t tris = input.triangle_count();
    const std::uint32_t* idx = input.indices.data();
    auto degenerate = [&](std::size_t t) {
        const std::uint32_t a = idx[3 * t], b = idx[3 * t + 1], c = idx[3 * t + 2];
        return a == b || b == c || a == c;
    };
    auto edge_key = [](std::uint32_t a, std::uint32_t b) {
        return a < b ? (std::uint64_t{a} << 32 | b) : (std::uint64_t{b} << 32 | a);
    };
    // A node that shares nothing, of an input without border or odd non-manifold edges (closed once its
    // split-vertex seams are welded, as Spot), has no edge to keep: one collapse of its whole input, seams
    // welded (they are otherwise kept at full resolution up to the root). Borders go the general way,
    // whose chords keep a cut's new border edges between input border vertices.
    const bool closed_input = border && (!border->input || border->input->empty()) &&
                              (!odd_non_manifold_edges || odd_non_manifold_edges->empty());
    if (closed_input && border->alone && (border->alone_triangles || border->keep_ratio > 0)) {
        std::vector<std::uint32_t> all;
        for (std::size_t t = 0; t < tris; ++t)
            if (!degenerate(t)) all.push_back(static_cast<std::uint32_t>(t));
        const std::size_t target = border->alone_triangles
                                       ? border->alone_triangles
                                       : static_cast<std::size_t>(std::ceil(border->keep_ratio * static_cast<double>(all.size())));
        ooc::PartCollapse collapse;
        if (target < all.size() && ooc::collapse_part(input, all, target, INFINITY, false, collapse, true)) {
            st.degenerate_dropped = tris - all.size();
            st.error = collapse.error;
            NodeMesh out;
            out.layout = input.layout;
            const std::size_t f = input.layout.floats();
            std::vector<std::uint32_t> remap(n, kNone);
            for (std::uint32_t v : collapse.indices) {
                if (remap[v] == kNone) {
                    remap[v] = static_cast<std::uint32_t>(out.keys.size());
                    out.keys.push_back(input.keys[v]);
                    out.vertices.insert(out.vertices.end(), input.vertex(v), input.vertex(v) + f);
                }
                out.indices.push_back(remap[v]);
            }
            return out;
        }
    }
    // Per undirected edge: its net use (uses min→max minus max→min). A degenerate triangle (a, a, b)
    // would add a→b and b→a, which changes no net use, so dropping it changes no boundary.
    ooc::FlatMap slot_of(tris * 3 / 2 + 16);
    std::vector<std::int32_t> net;
    std::vector<std::uint32_t> edge_of(3 * tris, ~0u);  // corner k of triangle t → edge t.k..t.k+1
    for (std::size_t t = 0; t < tris; ++t) {
        if (degenerate(t)) {
            ++st.degenerate_dropped;
            continue;
        }
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = idx[3 * t + k], b = idx[3 * t + (k + 1) % 3];
            bool inserted = false;
            const std::uint32_t e = slot_of.find_or_insert(edge_key(a, b), static_cast<std::uint32_t>(net.size()), inserted);
            if (inserted) net.push_back(0);
            net[e] += a < b ? 1 : -1;
            edge_of[3 * t + k] = e;
        }
    }
    // Edges of the input used an odd number ≥ 3 of times keep every use in every node.
    std::vector<std::uint8_t> keep_all(net.size(), 0);
    if (odd_non_manifold_edges && !odd_non_manifold_edges->empty())
        for (std::size_t t = 0; t < tris; ++t) {
            if (degenerate(t)) continue;
            for (int k = 0; k < 3; ++k) {
                const std::uint64_t ka = input.keys[idx[3 * t + k]], kb = input.keys[idx[3 * t + (k + 1) % 3]];
                if ((ka | kb) & kRepresentativeKey) continue;
                // The low 32 bits are the input vertex (above them: a wedge UV hash, octree_build.cpp).
                const std::uint64_t a = ka & 0xffffffffu, b = kb & 0xffffffffu;
                const std::uint64_t key = a < b ? (a << 32 | b) : (b << 32 | a);
                if (std::binary_search(odd_non_manifold_edges->begin(), odd_non_manifold_edges->end(), key))
                    keep_all[edge_of[3 * t + k]] = 1;
            }
        }
    // Copies of each edge still to emit in its net direction.
    std::vector<std::int32_t> remaining(net.size());
    for (std::size_t e = 0; e < net.size(); ++e) remaining[e] = net[e] < 0 ? -net[e] : net[e];
    auto boundary = [&](std::size_t corner) {
        const std::uint32_t e = edge_of[corner];
        return keep_all[e] || net[e] != 0;
    };
    // Emits the use a→b (corner `corner`) when it belongs to the node's kept boundary.
    auto take = [&](std::size_t corner, std::uint32_t a, std::uint32_t b) {
        const std::uint32_t e = edge_of[corner];
        if (keep_all[e]) return true;
        if (remaining[e] == 0 || (net[e] > 0) != (a < b)) return false;
        --remaining[e];
        return true;
    };

    // Components: triangles joined through shared edges (not through a vertex alone, so two parts of the
    // patch that touch at a vertex get fans of their own), and whether each has a boundary edge. All
    // uses of an edge lie in one component, so each component's kept uses are a cycle of their own.
    detail::UnionFind sets(tris);
    {
        std::vector<std::uint32_t> first_triangle(net.size(), kNone);
        for (std::size_t t = 0; t < tris; ++t)
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t e = edge_of[3 * t + k];
                if (e == kNone) continue;
                if (first_triangle[e] == kNone) first_triangle[e] = static_cast<std::uint32_t>(t);
                else sets.unite(first_triangle[e], static_cast<std::uint32_t>(t));
            }
    }
    std::vector<std::uint32_t> component(tris, kNone);
    for (std::size_t t = 0; t < tris; ++t)
        if (!degenerate(t)) component[t] = sets.find(static_cast<std::uint32_t>(t));
    std::vector<std::uint8_t> has_boundary(tris, 0);
    for (std::size_t t = 0; t < tris; ++t) {
        if (degenerate(t)) continue;
        for (int k = 0; k < 3; ++k)
            if (boundary(3 * t + k)) has_boundary[component[t]] = 1;
    }

    // Kept boundary uses (a→b, in triangle order) with their component, and the closed components' triangles.
    std::vector<std::pair<std::uint32_t, std::uint32_t>> kept;
    std::vector<std::uint32_t> kept_component, closed;
    std::vector<std::uint8_t> counted(tris, 0);
    for (std::size_t t = 0; t < tris; ++t) {
        if (degenerate(t)) continue;
        const std::uint32_t root = component[t];
        if (!has_boundary[root]) {
            if (!counted[root]) {
                counted[root] = 1;
                ++st.closed_components;
            }
            continue;
        }
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = idx[3 * t + k], b = idx[3 * t + (k + 1) % 3];
            if (take(3 * t + k, a, b)) {
                kept.emplace_back(a, b);
                kept_component.push_back(root);
            }
        }
    }
    std::vector<std::uint8_t> alive(tris, 0);  // per component: it keeps boundary uses
    // Per component: its kept uses are not its oriented boundary (an odd non-manifold edge keeps every
    // use, free chains shrank to chords), so only a fan, not a collapse of its triangles, has them.
    std::vector<std::uint8_t> fan_only(tris, 0);
    for (std::size_t t = 0; t < tris; ++t)
        if (!degenerate(t))
            for (int k = 0; k < 3; ++k)
                if (keep_all[edge_of[3 * t + k]]) fan_only[component[t]] = 1;
    // Parts that will be collapsed keep their free chains: the collapse keeps the part's whole border.
    std::vector<std::uint32_t> component_triangles(tris, 0), kept_uses(tris, 0);
    for (std::uint32_t c : kept_component) ++kept_uses[c];
    for (std::size_t t = 0; t < tris; ++t)
        if (!degenerate(t)) ++component_triangles[component[t]];
    std::vector<std::uint8_t> collapsible(tris, 0);
    for (std::uint32_t c : kept_component) collapsible[c] = !fan_only[c] && kept_uses[c] < component_triangles[c];
    // A part whose kept uses are all free touches no other node along an edge (a fragment, the root of an
    // open model): its border may slide, so the collapse shrinks it instead of the chords.
    std::vector<std::uint8_t> shared_border(tris, 0);
    if (border && (border->input || border->chords)) {
        for (std::size_t e = 0; e < kept.size(); ++e)
            if (!shared_border[kept_component[e]] && !free_edge(input, *border, kept[e].first, kept[e].second))
                shared_border[kept_component[e]] = 1;
    } else {
        for (std::uint32_t c : kept_component) shared_border[c] = 1;
    }
    if (border && (border->input || border->chords) && !kept.empty()) {
        std::vector<std::uint32_t> origin;
        kept = collapse_free_chains(input, kept, kept_component, collapsible, *border, cell_size, st, origin);
        for (std::uint32_t& c : origin) c = kept_component[c];
        kept_component.swap(origin);
    }
    for (std::uint32_t c : kept_component) alive[c] = 1;
    // Parts without kept uses: a closed part, or one whose boundary was all free and is gone (an almost
    // closed model whose holes were filled). Where they hang on a part that is fanned through a vertex
    // they are dropped with the fan's interior; otherwise they share nothing with another node and are
    // clustered (or copied).
    {
        detail::UnionFind touching(n);
        for (std::size_t t = 0; t < tris; ++t)
            if (!degenerate(t)) {
                touching.unite(idx[3 * t], idx[3 * t + 1]);
                touching.unite(idx[3 * t], idx[3 * t + 2]);
            }
        std::vector<std::uint8_t> fanned(n, 0);
        for (std::size_t e = 0; e < kept.size(); ++e) fanned[touching.find(kept[e].first)] = 1;
        for (std::size_t t = 0; t < tris; ++t)
            if (!degenerate(t) && !alive[component[t]] && !fanned[touching.find(idx[3 * t])])
                closed.push_back(static_cast<std::uint32_t>(t));
    }

    // One fan per component: a single representative for separate sheets (both sides of a thin tail, a
    // claw beside a leg) made fan triangles across the empty space between them, up to a cell long
    // (issue #27). A component whose fan would not be smaller than its triangles keeps them (same
    // oriented boundary, so no crack), so no node grows (issue #32 row 10).
    std::vector<std::uint32_t> fan_triangles(tris, 0);
    for (std::uint32_t c : kept_component) ++fan_triangles[c];
    std::vector<std::uint32_t> fans;  // roots with a fan, in order of their first kept use
    std::vector<std::uint8_t> copied(tris, 0), collapsed(tris, 0);
    // A part whose kept uses are its oriented boundary is simplified by edge collapse with that boundary
    // locked, to at most the size of its fan: a fan is a fair approximation of a flat disc only, and a
    // part cut from a fold (an ear), a tube or a border winding round the cell became a star through one
    // point whose triangles cross the part (issue #27: the bunny's level 2 at 5.6 % Hausdorff).
    std::vector<std::vector<std::uint32_t>> part_triangles;
    std::vector<std::uint32_t> part_slot(tris, kNone);
    for (std::uint32_t root : kept_component)
        if (collapsible[root] && part_slot[root] == kNone) {
            part_slot[root] = static_cast<std::uint32_t>(part_triangles.size());
            part_triangles.emplace_back();
        }
    for (std::size_t t = 0; t < tris; ++t)
        if (!degenerate(t) && part_slot[component[t]] != kNone)
            part_triangles[part_slot[component[t]]].push_back(static_cast<std::uint32_t>(t));
    std::vector<std::uint32_t> collapsed_indices;
    ooc::PartCollapse collapse;
    const double keep_ratio = border ? border->keep_ratio : 0;
    const double max_error = kCollapseError * cell_size;
    // A part's collapse target: its fan's size, or with a keep ratio that fraction of its triangles.
    auto part_target = [&](std::size_t triangles, std::size_t fan) {
        if (keep_ratio <= 0) return fan;
        return std::max(fan, static_cast<std::size_t>(std::ceil(keep_ratio * static_cast<double>(triangles))));
    };
    for (std::uint32_t root : kept_component) {
        if (alive[root] == 2) continue;
        if (fan_triangles[root] >= component_triangles[root]) {
            copied[root] = 1;
        } else if (part_slot[root] != kNone &&
                   ooc::collapse_part(input, part_triangles[part_slot[root]],
                                      part_target(component_triangles[root], fan_triangles[root]), max_error,
                                      shared_border[root] != 0, collapse)) {
            collapsed[root] = 1;
            collapsed_indices.insert(collapsed_indices.end(), collapse.indices.begin(), collapse.indices.end());
            st.error = std::max(st.error, collapse.error);
            if (!shared_border[root]) free_border_chords(input, collapse.indices, st.chords);
            ++st.collapsed_parts;
        } else if (alive[root] == 1) {
            fans.push_back(root);
        }
        alive[root] = 2;
    }
    // Within a component, the kept uses split into simple cycles (a boundary that touches itself at a
    // vertex, as a staircase cut through a grid does, is two cycles there), each fanned to a vertex of its
    // own: one apex for both would use the spoke to the touching vertex four times (non-manifold).
    // Cycles are walked within one part (parts may touch at a vertex): a vertex of each part is a node
    // of its own in the walk.
    std::vector<std::pair<std::uint32_t, std::uint32_t>> part_uses(kept.size());
    std::uint32_t part_vertices = 0;
    {
        ooc::FlatMap part_vertex(kept.size() + 16);
        auto id = [&](std::uint32_t v, std::uint32_t part) {
            bool inserted = false;
            const std::uint32_t i = part_vertex.find_or_insert(std::uint64_t{part} << 32 | v, part_vertices, inserted);
            part_vertices += inserted;
            return i;
        };
        for (std::size_t e = 0; e < kept.size(); ++e)
            part_uses[e] = {id(kept[e].first, kept_component[e]), id(kept[e].second, kept_component[e])};
    }
    const std::vector<std::uint32_t> cycle = simple_cycles(part_vertices, part_uses);
    std::vector<std::uint32_t> slot(tris, kNone);
    for (std::size_t i = 0; i < fans.size(); ++i) slot[fans[i]] = static_cast<std::uint32_t>(i);
    std::vector<std::vector<std::uint32_t>> fan_vertices(fans.size());
    // The node's quadric sums the input triangles below it (children's fans only approximate them), but
    // it describes this fan only when no other part shares the node.
    const bool own_quadrics = fans.size() > 1 || st.collapsed_parts > 0;
    std::vector<NodeQuadric> fan_quadrics;
    if (own_quadrics) fan_quadrics.assign(fans.size(), NodeQuadric(frame.attribute_dimension()));
    std::vector<std::uint8_t> listed(n, 0);
    for (std::size_t t = 0; t < tris; ++t) {
        if (degenerate(t)) continue;
        const std::uint32_t s = slot[component[t]];
        if (s == kNone) continue;
        if (own_quadrics) fan_quadrics[s].add_triangle(frame, input.vertex(idx[3 * t]), input.vertex(idx[3 * t + 1]),
                                                          input.vertex(idx[3 * t + 2]));
        for (int k = 0; k < 3; ++k)
            if (!listed[idx[3 * t + k]]) {
                listed[idx[3 * t + k]] = 1;
                fan_vertices[s].push_back(idx[3 * t + k]);
            }
    }

    NodeMesh out;
    out.layout = input.layout;
    const std::size_t f = input.layout.floats();
    std::vector<std::uint32_t> remap(n, kNone);
    auto use = [&](std::uint32_t v) {
        if (remap[v] == kNone) {
            remap[v] = static_cast<std::uint32_t>(out.keys.size());
            out.keys.push_back(input.keys[v]);
            out.vertices.insert(out.vertices.end(), input.vertex(v), input.vertex(v) + f);
        }
        return remap[v];
    };
    // Apex records: the first fan keeps the node's representative key, the others add their number
    // above the node id (bit 62 stays clear: that is a cluster vertex).
    std::vector<std::vector<float>> apex(fans.size());
    for (std::size_t i = 0; i < fans.size(); ++i) {
        double component_error = 0;
        apex[i] = representative(own_quadrics ? fan_quadrics[i] : quadric, input, fan_vertices[i], frame, cell_min,
                                 cell_size, component_error);
        st.error = std::max(st.error, component_error);
    }
    std::vector<std::uint32_t> apex_of_cycle;
    std::uint64_t apexes = 0;
    for (std::size_t e = 0; e < kept.size(); ++e) {
        const auto [a, b] = kept[e];
        const std::uint32_t root = kept_component[e];
        if (copied[root] || collapsed[root]) continue;
        if (cycle[e] >= apex_of_cycle.size()) apex_of_cycle.resize(cycle[e] + 1, kNone);
        std::uint32_t& v = apex_of_cycle[cycle[e]];
        if (v == kNone) {
            v = static_cast<std::uint32_t>(out.keys.size());
            out.keys.push_back(representative_key | apexes++ << 32);
            const std::vector<float>& r = apex[slot[root]];
            out.vertices.insert(out.vertices.end(), r.begin(), r.end());
        }
        // The fan: the edge keeps its direction in its source triangle, so the fan faces the same way.
        out.indices.push_back(use(a));
        out.indices.push_back(use(b));
        out.indices.push_back(v);
        ++st.boundary_edges;
    }
    for (std::size_t t = 0; t < tris; ++t)
        if (!degenerate(t) && copied[component[t]])
            for (int k = 0; k < 3; ++k) out.indices.push_back(use(idx[3 * t + k]));
    for (std::uint32_t v : collapsed_indices) out.indices.push_back(use(v));
    if (!closed.empty()) {
        if (border && border->cluster_closed) {
            // Parts sharing no edge with another node (a closed surface inside the cell, the root of a
            // closed model) collapse freely to the node's error bound; the 16³ clustering, which lost
            // Lucy's relief at her top levels (2.4 % Hausdorff at 4 554 triangles, 6.5× an edge
            // collapse), is left for parts the collapse cannot keep oriented.
            std::vector<std::uint32_t> group, rest;
            std::sort(closed.begin(), closed.end(), [&](std::uint32_t a, std::uint32_t b) {
                return std::pair(component[a], a) < std::pair(component[b], b);
            });
            for (std::size_t i = 0; i < closed.size();) {
                group.clear();
                const std::uint32_t root = component[closed[i]];
                while (i < closed.size() && component[closed[i]] == root) group.push_back(closed[i++]);
                if (!ooc::collapse_part(input, group, part_target(group.size(), 1), max_error, false, collapse)) {
                    rest.insert(rest.end(), group.begin(), group.end());
                    continue;
                }
                for (std::uint32_t v : collapse.indices) out.indices.push_back(use(v));
                free_border_chords(input, collapse.indices, st.chords);
                st.error = std::max(st.error, collapse.error);
                st.closed_triangles_in += group.size();
                st.closed_triangles_out += collapse.indices.size() / 3;
            }
            if (!rest.empty()) cluster_closed(input, rest, cell_min, cell_size, representative_key, out, st);
        } else
            for (std::uint32_t t : closed)
                for (int k = 0; k < 3; ++k) out.indices.push_back(use(idx[3 * t + k]));
    }
    std::sort(st.chords.begin(), st.chords.end());
    st.chords.erase(std::unique(st.chords.begin(), st.chords.end()), st.chords.end());
    return out;
}

}  // namespace lodforge

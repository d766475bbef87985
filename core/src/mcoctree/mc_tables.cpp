// Marching-cube tables for the prioritized marching-cube octree.
//
// Lorensen, Cline, "Marching Cubes: A High Resolution 3D Surface Construction Algorithm", SIGGRAPH 1987
// (cube cases); Nielson, Hamann, "The Asymptotic Decider", Visualization 1991 (the face ambiguity that
// makes the classic 15-case table leave holes). Instead of a hand-typed table we derive every case from
// one face rule, so neighbouring cubes always agree on their common face: on each face polygon, every
// maximal run of inside samples is cut off by one segment joining the two crossings that bound it
// ("inside corners are separated"). The segments of the six faces close into loops on the cube's surface
// and each loop is fanned into triangles (from a crossing whose diagonals stay off the parts of the
// boundary another node can hold; docs/mcoctree.md, D6). The same rule applies to faces split for a finer neighbour
// (docs/mcoctree.md, "Crack-free seams"), which is what makes the seams between levels watertight.
#include "mcoctree/mc_tables.h"

#include <cstring>

namespace lodforge::mc {
namespace {

struct Tables {
    std::array<SubEdge, sub_edge_count> edges{};
    std::array<std::array<std::int8_t, 27>, 27> between{};  // sample pair -> sub-edge id, -1 none
    std::array<std::uint8_t, sub_edge_count> faces{};       // bit f: the sub-edge lies on face f
    CaseTable cases;

    Tables() {
        for (auto& row : between) row.fill(-1);
        auto coord = [](int axis, int a, int u, int v, int u_axis, int v_axis) {
            int c[3] = {0, 0, 0};
            c[axis] = a;
            c[u_axis] = u;
            c[v_axis] = v;
            return sample_index(c[0], c[1], c[2]);
        };
        auto add = [&](int id, int sa, int sb, int axis, int length) {
            if (sa > sb) std::swap(sa, sb);
            edges[id] = {static_cast<std::uint8_t>(sa), static_cast<std::uint8_t>(sb),
                         static_cast<std::uint8_t>(axis), static_cast<std::uint8_t>(length)};
            between[sa][sb] = between[sb][sa] = static_cast<std::int8_t>(id);
        };
        for (int e = 0; e < full_edges; ++e) {
            const int a = e / 4, u = (a + 1) % 3, v = (a + 2) % 3;
            const int cu = (e & 1) * 2, cv = ((e >> 1) & 1) * 2;
            add(e, coord(a, 0, cu, cv, u, v), coord(a, 2, cu, cv, u, v), a, 2);
            add(12 + 2 * e, coord(a, 0, cu, cv, u, v), coord(a, 1, cu, cv, u, v), a, 1);
            add(13 + 2 * e, coord(a, 1, cu, cv, u, v), coord(a, 2, cu, cv, u, v), a, 1);
        }
        for (int f = 0; f < 6; ++f) {
            const int a = f / 2, s = (f & 1) * 2, u = (a + 1) % 3, v = (a + 2) % 3;
            const int centre = coord(a, s, 1, 1, u, v);
            add(36 + 4 * f + 0, centre, coord(a, s, 0, 1, u, v), u, 1);
            add(36 + 4 * f + 1, centre, coord(a, s, 2, 1, u, v), u, 1);
            add(36 + 4 * f + 2, centre, coord(a, s, 1, 0, u, v), v, 1);
            add(36 + 4 * f + 3, centre, coord(a, s, 1, 2, u, v), v, 1);
        }
        for (int e = 0; e < sub_edge_count; ++e) {
            const int sa = edges[e].a, sb = edges[e].b;
            const int ca[3] = {sa % 3, (sa / 3) % 3, sa / 9}, cb[3] = {sb % 3, (sb / 3) % 3, sb / 9};
            for (int a = 0; a < 3; ++a)
                if (ca[a] == cb[a] && ca[a] != 1) faces[e] |= static_cast<std::uint8_t>(1u << (2 * a + ca[a] / 2));
        }
    }
};

const Tables& tables() {
    static const Tables t;
    return t;
}

// Face f's square [u0, u0 + d] x [v0, v0 + d] (face coordinates), counter-clockwise seen from outside.
void face_square(int f, int u0, int v0, int d, int out[4]) {
    const int a = f / 2, s = (f & 1) * 2, u = (a + 1) % 3, v = (a + 2) % 3;
    auto at = [&](int cu, int cv) {
        int c[3] = {0, 0, 0};
        c[a] = s;
        c[u] = cu;
        c[v] = cv;
        return sample_index(c[0], c[1], c[2]);
    };
    // (u, v, axis) is right-handed, so (0,0),(d,0),(d,d),(0,d) turns counter-clockwise about +axis.
    if (s == 2) {
        out[0] = at(u0, v0), out[1] = at(u0 + d, v0), out[2] = at(u0 + d, v0 + d), out[3] = at(u0, v0 + d);
    } else {
        out[0] = at(u0, v0), out[1] = at(u0, v0 + d), out[2] = at(u0 + d, v0 + d), out[3] = at(u0 + d, v0);
    }
}

int midpoint(int sa, int sb) {
    const int ia = sa % 3, ja = (sa / 3) % 3, ka = sa / 9, ib = sb % 3, jb = (sb / 3) % 3, kb = sb / 9;
    return sample_index((ia + ib) / 2, (ja + jb) / 2, (ka + kb) / 2);
}

// Links the crossings of one face polygon: entering crossing -> the leaving crossing of the same run.
void link_polygon(const int* samples, int n, std::uint32_t inside, std::int8_t* next) {
    const Tables& t = tables();
    int crossing_at[8];
    int crossings = 0;
    for (int i = 0; i < n; ++i) crossing_at[i] = -1;
    for (int i = 0; i < n; ++i) {
        const int a = samples[i], b = samples[(i + 1) % n];
        if (((inside >> a) & 1u) != ((inside >> b) & 1u)) {
            crossing_at[i] = t.between[a][b];
            ++crossings;
        }
    }
    if (crossings == 0) return;
    for (int i = 0; i < n; ++i) {
        if (crossing_at[i] < 0 || ((inside >> samples[i]) & 1u)) continue;  // not an entering crossing
        for (int k = 1; k <= n; ++k) {
            const int j = (i + k) % n;
            if (crossing_at[j] >= 0) {
                next[crossing_at[i]] = static_cast<std::int8_t>(crossing_at[j]);
                break;
            }
        }
    }
}

// Triangulation of one loop (docs/mcoctree.md, D6). A fan diagonal between two crossings on one face of
// the node lies on the node's boundary; if some other node's cube holds both crossings, that node may use
// the same pair as a diagonal too: four triangles on one edge. The other nodes that can touch a part of
// the boundary: across each face, one node holding the whole face (same level or coarser), or, where the
// face is split, four finer ones holding a quarter each; across each edge, one node holding the whole
// edge (its level unknown when the faces beside it are split, so the whole edge). Costs of a diagonal:
// 0 through the interior, or on the boundary but in no such region (across two quarters of a split face:
// the node alone holds it); 2 or 3 in such regions only on + faces; `minus_face` or one more in one on a
// - face (an edge counts as - if either of its faces is). Two nodes sharing a segment are separated by a
// plane holding it, on a - face of one of them, so a diagonal below `minus_face` is never used by two
// nodes; a loop that needs one of `minus_face` is the flat band below.
constexpr int minus_face = 512;  // more than the + costs of any loop (at most 57 diagonals of 3)

struct Box {
    std::uint8_t lo[3], hi[3];
    bool minus;
};

bool holds(const Box& box, int e) {
    const SubEdge& s = tables().edges[std::size_t(e)];
    const int ca[3] = {s.a % 3, (s.a / 3) % 3, s.a / 9}, cb[3] = {s.b % 3, (s.b / 3) % 3, s.b / 9};
    for (int a = 0; a < 3; ++a)
        if (ca[a] < box.lo[a] || ca[a] > box.hi[a] || cb[a] < box.lo[a] || cb[a] > box.hi[a]) return false;
    return true;
}

// The regions of the node's boundary that another node's cube may hold, for refinement `refine`.
int shared_regions(std::uint32_t refine, Box* out) {
    int n = 0;
    for (int f = 0; f < 6; ++f) {
        const int a = f / 2, side = (f & 1) * 2;
        const bool split = (refine & face_bit(f)) != 0;
        for (int q = 0; q < (split ? 4 : 1); ++q) {
            Box b{};
            b.minus = (f & 1) == 0;
            for (int k = 0; k < 3; ++k) b.lo[k] = 0, b.hi[k] = 2;
            b.lo[a] = b.hi[a] = static_cast<std::uint8_t>(side);
            if (split) {
                const int u = (a + 1) % 3, v = (a + 2) % 3;
                b.lo[u] = static_cast<std::uint8_t>(q & 1), b.hi[u] = static_cast<std::uint8_t>((q & 1) + 1);
                b.lo[v] = static_cast<std::uint8_t>(q >> 1), b.hi[v] = static_cast<std::uint8_t>((q >> 1) + 1);
            }
            out[n++] = b;
        }
    }
    for (int e = 0; e < full_edges; ++e) {
        const int a = e / 4, u = (a + 1) % 3, v = (a + 2) % 3;
        Box b{};
        b.minus = (e & 3) != 3;  // on the - face of u or of v
        b.lo[a] = 0, b.hi[a] = 2;
        b.lo[u] = b.hi[u] = static_cast<std::uint8_t>((e & 1) * 2);
        b.lo[v] = b.hi[v] = static_cast<std::uint8_t>(((e >> 1) & 1) * 2);
        out[n++] = b;
    }
    return n;
}

// A sub-edge's place (its midpoint, x first): the order two nodes sharing a face agree on.
int place(int e) {
    const SubEdge& s = tables().edges[std::size_t(e)];
    return (s.a % 3 + s.b % 3) * 25 + ((s.a / 3) % 3 + (s.b / 3) % 3) * 5 + (s.a / 9 + s.b / 9);
}

// `first` is the loop's crossing of least place. A loop that lies flat on a face (a band between two split
// edges) has no diagonal off it; there the node on the face's - side takes the diagonals from `first` and
// the one on the + side the others, so the two nodes never take the same one.
struct DiagonalCost {
    Box regions[6 * 4 + full_edges];
    int count = 0;
    int first = 0;
    explicit DiagonalCost(std::uint32_t refine) : count(shared_regions(refine, regions)) {}
    int operator()(int a, int b) const {
        if ((tables().faces[std::size_t(a)] & tables().faces[std::size_t(b)]) == 0) return 0;
        const bool from_first = a == first || b == first;
        int cost = 0;
        for (int r = 0; r < count; ++r)
            if (holds(regions[r], a) && holds(regions[r], b)) {
                if (regions[r].minus) return minus_face + (from_first ? 0 : 1);
                cost = from_first ? 3 : 2;
            }
        return cost;
    }
};

// Appends the loop's triangles (counter-clockwise as the loop turns) to `out`; returns the new count.
// The first fan (from loop[0], then loop[1], ...) whose diagonals all run through the interior; where no
// fan has that, a triangulation of least total diagonal cost (dynamic programming over the polygon,
// ties to the smallest split vertex).
int triangulate_loop(const int* loop, int n, DiagonalCost& diagonal_cost, std::uint8_t* out,
                     int triangles) {
    auto emit = [&](int a, int b, int c) {
        if (triangles >= max_triangles) return;
        out[3 * triangles] = static_cast<std::uint8_t>(loop[a]);
        out[3 * triangles + 1] = static_cast<std::uint8_t>(loop[b]);
        out[3 * triangles + 2] = static_cast<std::uint8_t>(loop[c]);
        ++triangles;
    };
    if (n < 3) return triangles;
    diagonal_cost.first = loop[0];
    for (int i = 1; i < n; ++i)
        if (place(loop[i]) < place(diagonal_cost.first)) diagonal_cost.first = loop[i];
    for (int apex = 0; apex < n; ++apex) {
        bool interior = true;
        for (int i = 2; i + 1 < n && interior; ++i) interior = diagonal_cost(loop[apex], loop[(apex + i) % n]) == 0;
        if (!interior) continue;
        for (int i = 1; i + 1 < n; ++i) emit(apex, (apex + i) % n, (apex + i + 1) % n);
        return triangles;
    }
    // best[i][j]: least cost of triangulating the polygon loop[i..j] (its chord i-j not counted).
    static constexpr int cap = sub_edge_count;
    int best[cap][cap];
    std::int8_t split[cap][cap];
    for (int len = 2; len < n; ++len) {
        for (int i = 0; i + len < n; ++i) {
            const int j = i + len;
            int b = -1, bk = -1;
            for (int k = i + 1; k < j; ++k) {
                int c = 0;
                if (k - i >= 2) c += best[i][k] + diagonal_cost(loop[i], loop[k]);
                if (j - k >= 2) c += best[k][j] + diagonal_cost(loop[k], loop[j]);
                if (b < 0 || c < b) b = c, bk = k;
            }
            best[i][j] = b;
            split[i][j] = static_cast<std::int8_t>(bk);
        }
    }
    int stack[2 * cap];
    int top = 0;
    stack[top++] = 0;
    stack[top++] = n - 1;
    while (top > 0) {
        const int j = stack[--top], i = stack[--top];
        if (j - i < 2) continue;
        const int k = split[i][j];
        emit(i, k, j);
        stack[top++] = i, stack[top++] = k;
        stack[top++] = k, stack[top++] = j;
    }
    return triangles;
}

CaseTable make_case_table() {
    CaseTable table;
    std::uint8_t buf[3 * max_triangles];
    for (std::uint32_t c = 0; c < 256; ++c) {
        std::uint32_t inside = 0;
        for (int k = 0; k < 8; ++k)
            if (c & (1u << k)) inside |= 1u << corner_sample(k);
        const int n = triangulate(inside, 0, buf);
        table.count[c] = static_cast<std::uint8_t>(n);
        std::memcpy(table.edges[c].data(), buf, static_cast<std::size_t>(3 * n));
    }
    return table;
}

}  // namespace

const std::array<SubEdge, sub_edge_count>& sub_edges() { return tables().edges; }

std::array<int, 3> neighbour_offset_of(int slot) {
    std::array<int, 3> o{0, 0, 0};
    if (slot < 6) {
        o[slot / 2] = (slot & 1) ? 1 : -1;
    } else {
        const int e = slot - 6, a = e / 4;
        o[(a + 1) % 3] = (e & 1) ? 1 : -1;
        o[(a + 2) % 3] = (e & 2) ? 1 : -1;
    }
    return o;
}

std::array<int, 3> edge_neighbour_slots(int e) {
    const int a = e / 4, u = (a + 1) % 3, v = (a + 2) % 3;
    return {2 * u + (e & 1), 2 * v + ((e >> 1) & 1), 6 + e};
}

std::uint32_t face_edges_mask(int f) {
    int sq[4];
    face_square(f, 0, 0, 2, sq);
    std::uint32_t mask = 0;
    for (int i = 0; i < 4; ++i) mask |= 1u << tables().between[sq[i]][sq[(i + 1) % 4]];
    return mask;
}

int triangulate(std::uint32_t inside, std::uint32_t refine, std::uint8_t* out) {
    const Tables& t = tables();
    std::int8_t next[sub_edge_count];
    std::memset(next, -1, sizeof next);
    for (int f = 0; f < 6; ++f) {
        if (refine & face_bit(f)) {
            for (int q = 0; q < 4; ++q) {
                int sq[4];
                face_square(f, q & 1, q >> 1, 1, sq);
                link_polygon(sq, 4, inside, next);
            }
            continue;
        }
        int sq[4];
        face_square(f, 0, 0, 2, sq);
        int poly[8];
        int n = 0;
        for (int i = 0; i < 4; ++i) {
            poly[n++] = sq[i];
            const int e = t.between[sq[i]][sq[(i + 1) % 4]];
            if (refine & (1u << e)) poly[n++] = midpoint(sq[i], sq[(i + 1) % 4]);
        }
        link_polygon(poly, n, inside, next);
    }
    int triangles = 0;
    bool used[sub_edge_count] = {};
    DiagonalCost diagonal_cost(refine);
    for (int start = 0; start < sub_edge_count; ++start) {
        if (next[start] < 0 || used[start]) continue;
        int loop[sub_edge_count];
        int n = 0;
        for (int e = start; e >= 0 && !used[e] && n < sub_edge_count; e = next[e]) {
            used[e] = true;
            loop[n++] = e;
        }
        triangles = triangulate_loop(loop, n, diagonal_cost, out, triangles);
    }
    return triangles;
}

const CaseTable& case_table() {
    static const CaseTable table = make_case_table();
    return table;
}

}  // namespace lodforge::mc

// Marching-cube tables for the prioritized marching-cube octree.
//
// Lorensen, Cline, "Marching Cubes: A High Resolution 3D Surface Construction Algorithm", SIGGRAPH 1987
// (cube cases); Nielson, Hamann, "The Asymptotic Decider", Visualization 1991 (the face ambiguity that
// makes the classic 15-case table leave holes). Instead of a hand-typed table we derive every case from
// one face rule, so neighbouring cubes always agree on their common face: on each face polygon, every
// maximal run of inside samples is cut off by one segment joining the two crossings that bound it
// ("inside corners are separated"). The segments of the six faces close into loops on the cube's surface
// and each loop is fanned into triangles. The same rule applies to faces split for a finer neighbour
// (docs/mcoctree.md, "Crack-free seams"), which is what makes the seams between levels watertight.
#include "mc_tables.h"

#include <cstring>

namespace lodforge::mc {
namespace {

struct Tables {
    std::array<SubEdge, sub_edge_count> edges{};
    std::array<std::array<std::int8_t, 27>, 27> between{};  // sample pair -> sub-edge id, -1 none
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
    for (int start = 0; start < sub_edge_count; ++start) {
        if (next[start] < 0 || used[start]) continue;
        int loop[sub_edge_count];
        int n = 0;
        for (int e = start; e >= 0 && !used[e] && n < sub_edge_count; e = next[e]) {
            used[e] = true;
            loop[n++] = e;
        }
        for (int i = 1; i + 1 < n && triangles < max_triangles; ++i) {
            out[3 * triangles] = static_cast<std::uint8_t>(loop[0]);
            out[3 * triangles + 1] = static_cast<std::uint8_t>(loop[i]);
            out[3 * triangles + 2] = static_cast<std::uint8_t>(loop[i + 1]);
            ++triangles;
        }
    }
    return triangles;
}

const CaseTable& case_table() {
    static const CaseTable table = make_case_table();
    return table;
}

}  // namespace lodforge::mc

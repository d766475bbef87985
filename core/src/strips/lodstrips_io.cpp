// The .lodstrips file: writer here, reader in lodstrips_runtime.h (one decoder for engines and the core).
// Format: docs/lodstrips.md. Variable-width integers (LEB128) and per-strip positions follow the
// grouping of Ramos 2008, ch. 5; the container (CRC-32 per section) is io/binary_io.h's.
#include "lodforge/error.h"
#include "lodforge/strips/lodstrips.h"
#include "io/binary_io.h"

#include <algorithm>

namespace lodforge {
namespace {

struct Sections {
    binary::Writer meta, vert, matl, strp, coll;
};

Sections encode_sections(const lodstrips::Data& d) {
    Sections out;
    const std::size_t N = d.vertex_count, S = d.strip_count(), K = d.collapse_count();
    binary::Writer& m = out.meta;
    const std::uint32_t flags = (d.restart ? 1u : 0u) | (d.normals.empty() ? 0u : 2u) | (d.colors.empty() ? 0u : 4u) |
                                (d.colors_8bit && !d.colors.empty() ? 8u : 0u);
    m.varint(flags);
    m.varint(N);
    m.varint(d.texcoords.size());
    m.varint(d.materials.size());
    m.varint(S);
    m.varint(d.initial_indices.size());
    m.varint(K);
    m.varint(d.collapse_begin.back());
    m.varint(d.rewrite_positions.size());
    m.varint(d.removals.size());

    binary::Writer& v = out.vert;
    for (float f : d.positions) v.put(f);
    for (float f : d.normals) v.put(f);
    if (d.colors_8bit)
        for (float f : d.colors) v.put<std::uint8_t>(static_cast<std::uint8_t>(std::clamp(std::lround(f * 255.f), 0l, 255l)));
    else
        for (float f : d.colors) v.put(f);
    for (const auto& set : d.texcoords)
        for (float f : set) v.put(f);

    binary::Writer& t = out.matl;
    for (const lodstrips::Material& mat : d.materials) {
        t.str(mat.name);
        for (float c : mat.base_color) t.put(c);
        t.put(mat.metallic);
        t.put(mat.roughness);
        for (float c : mat.emissive) t.put(c);
        t.put(std::uint8_t{mat.double_sided});
        t.str(mat.base_color_texture);
        t.str(mat.normal_texture);
        t.str(mat.metallic_roughness_texture);
        t.str(mat.occlusion_texture);
        t.str(mat.emissive_texture);
        t.varint(mat.base_color_texcoord_set);
    }

    binary::Writer& s = out.strp;
    for (std::size_t r = 0; r < S; ++r) {
        s.varint(d.strip_offsets[r + 1] - d.strip_offsets[r]);
        s.varint(d.strip_materials[r]);
    }
    std::int64_t prev = 0;
    for (std::size_t r = 0; r < S; ++r) {
        const std::uint32_t end = d.strip_offsets[r + 1] - (d.restart ? 1u : 0u);
        for (std::uint32_t e = d.strip_offsets[r]; e < end; ++e) {
            s.zigzag(std::int64_t(d.initial_indices[e]) - prev);
            prev = d.initial_indices[e];
        }
    }

    // Per collapse: the removed vertices' targets, then one group per strip it touches with each removed
    // vertex's positions in that strip (delta-coded) and the strip's removals.
    binary::Writer& c = out.coll;
    c.varint(d.triangles[0]);
    struct Item {
        std::uint32_t strip, vertex, pos;
        bool operator<(const Item& o) const {
            return strip != o.strip ? strip < o.strip : (vertex != o.vertex ? vertex < o.vertex : pos < o.pos);
        }
    };
    std::vector<Item> items;
    std::vector<std::uint32_t> strips;
    for (std::size_t k = 0; k < K; ++k) {
        const std::uint32_t ob = d.collapse_begin[k], oe = d.collapse_begin[k + 1];
        c.varint(oe - ob);
        c.varint(d.triangles[k] - d.triangles[k + 1]);
        for (std::uint32_t o = ob; o < oe; ++o) c.varint(d.vertex_of_ordinal(o) - d.targets[o]);
        items.clear();
        strips.clear();
        for (std::uint32_t o = ob; o < oe; ++o)
            for (std::uint32_t i = d.rewrite_begin[o]; i < d.rewrite_begin[o + 1]; ++i) {
                const std::uint32_t p = d.rewrite_positions[i];
                const auto it = std::upper_bound(d.strip_offsets.begin(), d.strip_offsets.end(), p);
                const std::uint32_t r = static_cast<std::uint32_t>(it - d.strip_offsets.begin() - 1);
                items.push_back({r, o - ob, p - d.strip_offsets[r]});
                strips.push_back(r);
            }
        for (std::uint32_t i = d.removal_begin[k]; i < d.removal_begin[k + 1]; ++i) strips.push_back(d.removals[i].strip);
        std::sort(items.begin(), items.end());
        std::sort(strips.begin(), strips.end());
        strips.erase(std::unique(strips.begin(), strips.end()), strips.end());
        c.varint(strips.size());
        std::int64_t prev_strip = 0;
        std::size_t it = 0;
        std::uint32_t rm = d.removal_begin[k];
        for (std::uint32_t r : strips) {
            c.zigzag(std::int64_t(r) - prev_strip);
            prev_strip = r;
            for (std::uint32_t j = 0; j < oe - ob; ++j) {
                std::size_t e = it;
                while (e < items.size() && items[e].strip == r && items[e].vertex == j) ++e;
                c.varint(e - it);
                for (std::size_t i = it; i < e; ++i) c.varint(i == it ? items[i].pos : items[i].pos - items[i - 1].pos - 1);
                it = e;
            }
            std::uint32_t re = rm;
            while (re < d.removal_begin[k + 1] && d.removals[re].strip == r) ++re;
            c.varint(re - rm);
            for (std::uint32_t i = rm; i < re; ++i) {
                const lodstrips::Removal& x = d.removals[i];
                c.varint(x.pos);
                c.varint((std::uint64_t(x.count / 2 - 1) << 1) | std::uint64_t(x.type - 1));
            }
            rm = re;
        }
        if (it != items.size() || rm != d.removal_begin[k + 1])
            throw Error(Error::Kind::invalid, "encode_lodstrips: collapse " + std::to_string(k) +
                                                  " has records out of strip order");
    }
    return out;
}

}  // namespace

std::vector<std::uint8_t> encode_lodstrips(const lodstrips::Data& data) {
    {
        lodstrips::LodStrips check;
        std::string why;
        if (!check.assign(data, &why)) throw Error(Error::Kind::invalid, "encode_lodstrips: " + why);
    }
    const Sections s = encode_sections(data);
    try {
        return binary::write_container(lodstrips::file_magic, lodstrips::format_version,
                                       {{"META", &s.meta.bytes}, {"VERT", &s.vert.bytes}, {"MATL", &s.matl.bytes},
                                        {"STRP", &s.strp.bytes}, {"COLL", &s.coll.bytes}});
    } catch (const Error& e) {
        throw Error(e.kind(), std::string("encode_lodstrips: ") + e.what());
    }
}

LodStripsStorage lodstrips_storage(const lodstrips::Data& data) {
    const Sections s = encode_sections(data);
    LodStripsStorage st;
    st.vertex_bytes = s.vert.bytes.size();
    st.strip_bytes = s.strp.bytes.size();
    st.change_bytes = s.coll.bytes.size();
    st.file_bytes = binary::container_size(
        {s.meta.bytes.size(), s.vert.bytes.size(), s.matl.bytes.size(), s.strp.bytes.size(), s.coll.bytes.size()});
    st.indexed_mesh_bytes = st.vertex_bytes + 12u * std::size_t(data.triangles.empty() ? 0 : data.triangles[0]);
    st.ratio_to_indexed = st.indexed_mesh_bytes ? double(st.file_bytes) / double(st.indexed_mesh_bytes) : 0.0;
    return st;
}

void write_lodstrips(const lodstrips::Data& data, const std::string& path) {
    binary::write_file(path, encode_lodstrips(data));
}

lodstrips::Data read_lodstrips(const std::string& path) {
    const std::vector<std::uint8_t> bytes = binary::read_file(path, "a .lodstrips file");
    lodstrips::Data d;
    std::string why;
    if (!lodstrips::decode(bytes.data(), bytes.size(), d, &why)) throw_error(Error::Kind::format, path, why);
    lodstrips::LodStrips check;
    if (!check.assign(d, &why)) throw_error(Error::Kind::format, path, why);
    return d;
}

}  // namespace lodforge

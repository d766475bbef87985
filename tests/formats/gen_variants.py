#!/usr/bin/env python3
"""Derives format variants from the real meshes in ../shared/data (QA matrix, docs/import-obj-gltf.md).

Usage: gen_variants.py DATA_DIR OUT_DIR
Writes OUT_DIR/<name>/<file> per variant and OUT_DIR/manifest.json: for each variant the file, the
original it is derived from, and what a correct import gives (triangles, vertices, attributes) or
"error" for input that must be refused. Python standard library only; nothing is committed.
"""
import base64, json, math, os, shutil, struct, sys

DATA, OUT = sys.argv[1], sys.argv[2]
manifest = []

def add(name, fname, orig, expect):
    manifest.append({"name": name, "file": os.path.join(OUT, name, fname), "orig": orig, **expect})

def vdir(name):
    d = os.path.join(OUT, name)
    os.makedirs(d, exist_ok=True)
    return d

# ---------------------------------------------------------------- glTF helpers
FLOAT, UBYTE, USHORT, UINT, BYTE, SHORT = 5126, 5121, 5123, 5125, 5120, 5122
CSIZE = {FLOAT: 4, UBYTE: 1, USHORT: 2, UINT: 4, BYTE: 1, SHORT: 2}
CFMT = {FLOAT: 'f', UBYTE: 'B', USHORT: 'H', UINT: 'I', BYTE: 'b', SHORT: 'h'}
NCOMP = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}

def read_accessor(g, bins, ai):
    a = g["accessors"][ai]; bv = g["bufferViews"][a["bufferView"]]
    ct, n = a["componentType"], NCOMP[a["type"]]
    stride = bv.get("byteStride", CSIZE[ct] * n)
    base = bv.get("byteOffset", 0) + a.get("byteOffset", 0)
    buf = bins[bv["buffer"]]
    out = []
    for i in range(a["count"]):
        vals = struct.unpack_from("<%d%s" % (n, CFMT[ct]), buf, base + i * stride)
        out.append(vals if n > 1 else vals[0])
    return out

def load_duck():
    d = os.path.join(DATA, "tex-duck/glTF")
    g = json.load(open(os.path.join(d, "Duck.gltf")))
    bins = [open(os.path.join(d, b["uri"]), "rb").read() for b in g["buffers"]]
    p = g["meshes"][0]["primitives"][0]
    return dict(pos=read_accessor(g, bins, p["attributes"]["POSITION"]),
                nrm=read_accessor(g, bins, p["attributes"]["NORMAL"]),
                uv=read_accessor(g, bins, p["attributes"]["TEXCOORD_0"]),
                idx=read_accessor(g, bins, p["indices"]),
                png=open(os.path.join(d, "DuckCM.png"), "rb").read())

class G:
    """A glTF under construction: one binary buffer, accessors appended."""
    def __init__(self):
        self.bin = bytearray(); self.j = {"asset": {"version": "2.0"}, "accessors": [], "bufferViews": [],
                                          "meshes": [], "nodes": [], "scenes": [{"nodes": []}], "scene": 0}
    def view(self, data, stride=None, target=None):
        while len(self.bin) % 4: self.bin.append(0)
        v = {"buffer": 0, "byteOffset": len(self.bin), "byteLength": len(data)}
        if stride: v["byteStride"] = stride
        if target: v["target"] = target
        self.bin += data; self.j["bufferViews"].append(v); return len(self.j["bufferViews"]) - 1
    def acc(self, values, ct, typ, normalized=False, minmax=False, pad_to=None):
        n = NCOMP[typ]; fmt = "<%d%s" % (n, CFMT[ct]); data = bytearray(); stride = None
        for v in values:
            rec = struct.pack(fmt, *(v if n > 1 else (v,)))
            if pad_to:
                rec += b"\0" * (pad_to - len(rec))
            data += rec
        if pad_to: stride = pad_to
        a = {"bufferView": self.view(bytes(data), stride), "componentType": ct, "count": len(values), "type": typ}
        if normalized: a["normalized"] = True
        if minmax:
            cols = list(zip(*values)) if n > 1 else [values]
            a["min"] = [min(c) for c in cols]; a["max"] = [max(c) for c in cols]
        self.j["accessors"].append(a); return len(self.j["accessors"]) - 1
    def mesh(self, prims, name="m"):
        self.j["meshes"].append({"name": name, "primitives": prims}); return len(self.j["meshes"]) - 1
    def node(self, root=True, **kw):
        self.j["nodes"].append(kw); i = len(self.j["nodes"]) - 1
        if root: self.j["scenes"][0]["nodes"].append(i)
        return i
    def texture_material(self, image):
        self.j["images"] = [image]; self.j["textures"] = [{"source": 0}]
        self.j["materials"] = [{"name": "duck", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]
    def write_gltf(self, path, embed=False, binname=None):
        self.j["buffers"] = [{"byteLength": len(self.bin)}]
        if embed:
            self.j["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64.b64encode(self.bin).decode()
        else:
            binname = binname or os.path.splitext(os.path.basename(path))[0] + ".bin"
            self.j["buffers"][0]["uri"] = binname
            open(os.path.join(os.path.dirname(path), binname), "wb").write(self.bin)
        for k in [k for k, v in self.j.items() if v == []]: del self.j[k]
        json.dump(self.j, open(path, "w"))
    def write_glb(self, path):
        self.j["buffers"] = [{"byteLength": len(self.bin)}]
        for k in [k for k, v in self.j.items() if v == []]: del self.j[k]
        js = json.dumps(self.j).encode()
        js += b" " * (-len(js) % 4); b = bytes(self.bin) + b"\0" * (-len(self.bin) % 4)
        out = struct.pack("<4sII", b"glTF", 2, 12 + 8 + len(js) + 8 + len(b))
        out += struct.pack("<I4s", len(js), b"JSON") + js + struct.pack("<I4s", len(b), b"BIN\0") + b
        open(path, "wb").write(out)

duck = load_duck()
NV, NT = len(duck["pos"]), len(duck["idx"]) // 3
TRIS = [tuple(duck["idx"][3 * i:3 * i + 3]) for i in range(NT)]
NONDEG = sum(1 for t in TRIS if len(set(t)) == 3)
DUCK_ATTRS = ["normal", "texcoord0"]

def duck_base(g, textured=True, image=None, **prim_extra):
    pa = g.acc(duck["pos"], FLOAT, "VEC3", minmax=True)
    na = g.acc(duck["nrm"], FLOAT, "VEC3")
    ta = g.acc(duck["uv"], FLOAT, "VEC2")
    ia = g.acc(duck["idx"], USHORT, "SCALAR")
    prim = {"attributes": {"POSITION": pa, "NORMAL": na, "TEXCOORD_0": ta}, "indices": ia, **prim_extra}
    if textured:
        g.texture_material(image or {"uri": "DuckCM.png"}); prim["material"] = 0
    return prim, pa

def copy_png(d, name="DuckCM.png"):
    open(os.path.join(d, name), "wb").write(duck["png"])

ORIG_DUCK = os.path.join(DATA, "tex-duck/glTF/Duck.gltf")
ok_duck = {"triangles": NT, "vertices": NV, "attributes": DUCK_ATTRS, "textures": 1}

# plain re-encode (reference for this writer)
d = vdir("g_plain"); g = G(); prim, _ = duck_base(g); g.node(mesh=g.mesh([prim])); copy_png(d)
g.write_gltf(os.path.join(d, "duck.gltf")); add("g_plain", "duck.gltf", ORIG_DUCK, ok_duck)

# interleaved buffer with byteStride 32 (pos, normal, uv)
d = vdir("g_interleaved"); g = G()
data = bytearray()
for p, n, t in zip(duck["pos"], duck["nrm"], duck["uv"]): data += struct.pack("<8f", *p, *n, *t)
bv = g.view(bytes(data), stride=32, target=34962)
mn = [min(c) for c in zip(*duck["pos"])]; mx = [max(c) for c in zip(*duck["pos"])]
g.j["accessors"] += [{"bufferView": bv, "byteOffset": 0, "componentType": FLOAT, "count": NV, "type": "VEC3", "min": mn, "max": mx},
                     {"bufferView": bv, "byteOffset": 12, "componentType": FLOAT, "count": NV, "type": "VEC3"},
                     {"bufferView": bv, "byteOffset": 24, "componentType": FLOAT, "count": NV, "type": "VEC2"}]
ia = g.acc(duck["idx"], USHORT, "SCALAR"); g.texture_material({"uri": "DuckCM.png"}); copy_png(d)
g.node(mesh=g.mesh([{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}, "indices": ia, "material": 0}]))
g.write_gltf(os.path.join(d, "duck.gltf")); add("g_interleaved", "duck.gltf", ORIG_DUCK, ok_duck)

# data: URIs for buffer and image
d = vdir("g_datauri"); g = G()
prim, _ = duck_base(g, image={"uri": "data:image/png;base64," + base64.b64encode(duck["png"]).decode()})
g.node(mesh=g.mesh([prim])); g.write_gltf(os.path.join(d, "duck.gltf"), embed=True)
add("g_datauri", "duck.gltf", ORIG_DUCK, {**ok_duck, "embedded_textures": 1})

# data: URI with application/gltf-buffer MIME
d = vdir("g_datauri_gltfbuffer"); g = G(); prim, _ = duck_base(g, textured=False); g.node(mesh=g.mesh([prim]))
g.write_gltf(os.path.join(d, "duck.gltf"), embed=True)
g.j["buffers"][0]["uri"] = g.j["buffers"][0]["uri"].replace("application/octet-stream", "application/gltf-buffer")
json.dump(g.j, open(os.path.join(d, "duck.gltf"), "w"))
add("g_datauri_gltfbuffer", "duck.gltf", ORIG_DUCK, {"triangles": NT, "vertices": NV, "attributes": DUCK_ATTRS})

# GLB with the image in a bufferView
d = vdir("g_glb_imgbv"); g = G(); prim, _ = duck_base(g, textured=False)
iv = g.view(duck["png"]); g.texture_material({"bufferView": iv, "mimeType": "image/png"}); prim["material"] = 0
g.node(mesh=g.mesh([prim])); g.write_glb(os.path.join(d, "duck.glb"))
add("g_glb_imgbv", "duck.glb", ORIG_DUCK, {**ok_duck, "embedded_textures": 1})

# index types: uint8 on a patch of < 256 vertices, uint16 and uint32 on the whole duck
patch_tris, remap = [], {}
for t in TRIS:
    new = [v for v in t if v not in remap]
    if len(remap) + len(new) > 255: break
    for v in t:
        if v not in remap: remap[v] = len(remap)
    patch_tris.append(tuple(remap[v] for v in t))
inv = sorted(remap, key=remap.get)
d = vdir("g_idx_u8"); g = G()
pa = g.acc([duck["pos"][v] for v in inv], FLOAT, "VEC3", minmax=True)
ia = g.acc([i for t in patch_tris for i in t], UBYTE, "SCALAR")
g.node(mesh=g.mesh([{"attributes": {"POSITION": pa}, "indices": ia}])); g.write_gltf(os.path.join(d, "patch.gltf"))
add("g_idx_u8", "patch.gltf", None, {"triangles": len(patch_tris), "vertices": len(inv), "attributes": []})
d = vdir("g_idx_u32"); g = G(); prim, _ = duck_base(g)
g.j["accessors"][prim["indices"]] = None; g.j["accessors"].pop()
prim["indices"] = g.acc(duck["idx"], UINT, "SCALAR"); copy_png(d)
g.node(mesh=g.mesh([prim])); g.write_gltf(os.path.join(d, "duck.gltf")); add("g_idx_u32", "duck.gltf", ORIG_DUCK, ok_duck)

# non-indexed
d = vdir("g_nonindexed"); g = G()
pa = g.acc([duck["pos"][i] for i in duck["idx"]], FLOAT, "VEC3", minmax=True)
na = g.acc([duck["nrm"][i] for i in duck["idx"]], FLOAT, "VEC3")
ta = g.acc([duck["uv"][i] for i in duck["idx"]], FLOAT, "VEC2")
g.texture_material({"uri": "DuckCM.png"}); copy_png(d)
g.node(mesh=g.mesh([{"attributes": {"POSITION": pa, "NORMAL": na, "TEXCOORD_0": ta}, "material": 0}]))
g.write_gltf(os.path.join(d, "duck.gltf")); add("g_nonindexed", "duck.gltf", ORIG_DUCK, {**ok_duck, "vertices": 3 * NT})

# TRIANGLE_STRIP: each duck triangle, joined by degenerate triangles with the parity kept
strip = []
for t in TRIS:
    if len(set(t)) < 3: continue
    if strip:
        strip += [strip[-1], t[0]]
        if len(strip) % 2: strip.append(t[0])
    strip += list(t)
d = vdir("g_strip"); g = G(); prim, _ = duck_base(g); copy_png(d)
g.j["accessors"].pop(); prim["indices"] = g.acc(strip, UINT, "SCALAR"); prim["mode"] = 5
g.node(mesh=g.mesh([prim])); g.write_gltf(os.path.join(d, "duck.gltf"))
add("g_strip", "duck.gltf", ORIG_DUCK, {**ok_duck, "triangles": NONDEG})

# TRIANGLE_FAN: the first 64 triangles as 3-index fans, the rest as TRIANGLES, one POSITION accessor
d = vdir("g_fan"); g = G(); prim, pa = duck_base(g); copy_png(d)
g.j["accessors"].pop(); prim["indices"] = g.acc([i for t in TRIS[64:] for i in t], USHORT, "SCALAR")
prims = [prim] + [{**{k: v for k, v in prim.items() if k != "indices"}, "mode": 6,
                   "indices": g.acc(list(t), USHORT, "SCALAR")} for t in TRIS[:64]]
g.node(mesh=g.mesh(prims)); g.write_gltf(os.path.join(d, "duck.gltf")); add("g_fan", "duck.gltf", ORIG_DUCK, ok_duck)

# real fan: a disc (n = 32) as a single TRIANGLE_FAN, non-indexed
d = vdir("g_fan_disc"); g = G()
disc = [(0.0, 0.0, 0.0)] + [(math.cos(2 * math.pi * k / 32), math.sin(2 * math.pi * k / 32), 0.0) for k in range(33)]
g.node(mesh=g.mesh([{"attributes": {"POSITION": g.acc(disc, FLOAT, "VEC3", minmax=True)}, "mode": 6}]))
g.write_gltf(os.path.join(d, "disc.gltf")); add("g_fan_disc", "disc.gltf", None, {"triangles": 32, "vertices": 34, "attributes": []})

# POINTS and LINES primitives next to the duck (skipped), and a file of only points / only lines
d = vdir("g_points_lines"); g = G(); prim, _ = duck_base(g); copy_png(d)
pts = g.acc(duck["pos"][:100], FLOAT, "VEC3", minmax=True)
lin = g.acc(duck["pos"][100:200], FLOAT, "VEC3", minmax=True)
g.node(mesh=g.mesh([prim, {"attributes": {"POSITION": pts}, "mode": 0}, {"attributes": {"POSITION": lin}, "mode": 1},
                    {"attributes": {"POSITION": lin}, "mode": 3}]))
g.write_gltf(os.path.join(d, "duck.gltf")); add("g_points_lines", "duck.gltf", ORIG_DUCK, ok_duck)
for mode, nm in [(0, "g_only_points"), (1, "g_only_lines")]:
    d = vdir(nm); g = G(); pts = g.acc(duck["pos"], FLOAT, "VEC3", minmax=True)
    g.node(mesh=g.mesh([{"attributes": {"POSITION": pts}, "mode": mode}])); g.write_gltf(os.path.join(d, "pts.gltf"))
    add(nm, "pts.gltf", None, {"error_or_empty": True})

# sparse accessors: positions without a base view (all from sparse), and a base view with 10 replaced
def sparse(g, base_view, count, idxs, vals, typ="VEC3"):
    iv = g.view(struct.pack("<%dI" % len(idxs), *idxs)); vv = g.view(b"".join(struct.pack("<3f", *v) for v in vals))
    a = {"componentType": FLOAT, "count": count, "type": typ,
         "sparse": {"count": len(idxs), "indices": {"bufferView": iv, "componentType": UINT}, "values": {"bufferView": vv}}}
    if base_view is not None: a["bufferView"] = base_view
    cols = list(zip(*duck["pos"])); a["min"] = [min(c) for c in cols]; a["max"] = [max(c) for c in cols]
    g.j["accessors"].append(a); return len(g.j["accessors"]) - 1
d = vdir("g_sparse_nobase"); g = G(); prim, pa = duck_base(g); copy_png(d)
prim["attributes"]["POSITION"] = sparse(g, None, NV, list(range(NV)), duck["pos"])
g.node(mesh=g.mesh([prim])); g.write_gltf(os.path.join(d, "duck.gltf")); add("g_sparse_nobase", "duck.gltf", ORIG_DUCK, {**ok_duck, "same_geometry": True})
d = vdir("g_sparse_base"); g = G(); prim, pa = duck_base(g); copy_png(d)
zero_view = g.view(b"".join(struct.pack("<3f", *(duck["pos"][i] if i % 10 else (0, 0, 0))) for i in range(NV)))
ids = [i for i in range(NV) if i % 10 == 0]
prim["attributes"]["POSITION"] = sparse(g, zero_view, NV, ids, [duck["pos"][i] for i in ids])
g.node(mesh=g.mesh([prim])); g.write_gltf(os.path.join(d, "duck.gltf")); add("g_sparse_base", "duck.gltf", ORIG_DUCK, {**ok_duck, "same_geometry": True})

# KHR_mesh_quantization: positions as normalized int16 scaled back by the node, normals int8 normalized
# (padded to 4 bytes), texcoords unorm16
d = vdir("g_quant"); g = G(); copy_png(d)
cols = list(zip(*duck["pos"])); lo = [min(c) for c in cols]; hi = [max(c) for c in cols]
ext = max(max(abs(l), abs(h)) for l, h in zip(lo, hi))
qp = [tuple(int(round(c / ext * 32767)) for c in p) for p in duck["pos"]]
qn = [tuple(max(-127, min(127, int(round(c * 127)))) for c in n) for n in duck["nrm"]]
qt = [tuple(max(0, min(65535, int(round(c * 65535)))) for c in t) for t in duck["uv"]]
pa = g.acc(qp, SHORT, "VEC3", normalized=True, minmax=True, pad_to=8)
g.j["accessors"][pa]["min"] = [m / 32767 for m in g.j["accessors"][pa]["min"]]
g.j["accessors"][pa]["max"] = [m / 32767 for m in g.j["accessors"][pa]["max"]]
na = g.acc(qn, BYTE, "VEC3", normalized=True, pad_to=4); ta = g.acc(qt, USHORT, "VEC2", normalized=True)
ia = g.acc(duck["idx"], USHORT, "SCALAR"); g.texture_material({"uri": "DuckCM.png"})
g.node(mesh=g.mesh([{"attributes": {"POSITION": pa, "NORMAL": na, "TEXCOORD_0": ta}, "indices": ia, "material": 0}]),
       scale=[ext, ext, ext])
g.j["extensionsUsed"] = g.j["extensionsRequired"] = ["KHR_mesh_quantization"]
g.write_gltf(os.path.join(d, "duck.gltf")); add("g_quant", "duck.gltf", ORIG_DUCK, {**ok_duck, "same_geometry": True})
# quantized positions as plain (non-normalized) uint16 with translation + scale
d = vdir("g_quant_u16"); g = G()
qp = [tuple(int(round((c - l) / (h - l) * 65535)) for c, l, h in zip(p, lo, hi)) for p in duck["pos"]]
pa = g.acc(qp, USHORT, "VEC3", minmax=True, pad_to=8); ia = g.acc(duck["idx"], USHORT, "SCALAR")
g.node(mesh=g.mesh([{"attributes": {"POSITION": pa}, "indices": ia}]), translation=lo,
       scale=[(h - l) / 65535 for l, h in zip(lo, hi)])
g.j["extensionsUsed"] = g.j["extensionsRequired"] = ["KHR_mesh_quantization"]
g.write_gltf(os.path.join(d, "duck.gltf")); add("g_quant_u16", "duck.gltf", ORIG_DUCK, {"triangles": NT, "vertices": NV, "attributes": [], "same_geometry": True})

# COLOR_0 variants
def col(i): p = duck["pos"][i]; return ((p[0] - lo[0]) / (hi[0] - lo[0]), (p[1] - lo[1]) / (hi[1] - lo[1]), (p[2] - lo[2]) / (hi[2] - lo[2]))
for nm, ct, typ, norm in [("g_color_vec3_float", FLOAT, "VEC3", False), ("g_color_vec4_float", FLOAT, "VEC4", False),
                          ("g_color_vec4_unorm8", UBYTE, "VEC4", True), ("g_color_vec3_unorm8", UBYTE, "VEC3", True),
                          ("g_color_vec3_unorm16", USHORT, "VEC3", True), ("g_color_vec4_unorm16", USHORT, "VEC4", True)]:
    d = vdir(nm); g = G(); prim, _ = duck_base(g); copy_png(d)
    scale = {FLOAT: 1, UBYTE: 255, USHORT: 65535}[ct]
    vals = []
    for i in range(NV):
        c = list(col(i)) + ([0.5] if typ == "VEC4" else [])
        vals.append(tuple(c) if ct == FLOAT else tuple(int(round(x * scale)) for x in c))
    pad = 4 if (ct == UBYTE and typ == "VEC3") else (8 if (ct == USHORT and typ == "VEC3") else None)
    prim["attributes"]["COLOR_0"] = g.acc(vals, ct, typ, normalized=norm, pad_to=pad)
    g.node(mesh=g.mesh([prim])); g.write_gltf(os.path.join(d, "duck.gltf"))
    add(nm, "duck.gltf", ORIG_DUCK, {**ok_duck, "attributes": DUCK_ATTRS + ["color"]})

# TEXCOORD_1
d = vdir("g_texcoord1"); g = G(); prim, _ = duck_base(g); copy_png(d)
prim["attributes"]["TEXCOORD_1"] = g.acc([(u * 0.5, v * 0.5) for u, v in duck["uv"]], FLOAT, "VEC2")
g.j["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["texCoord"] = 1
g.node(mesh=g.mesh([prim])); g.write_gltf(os.path.join(d, "duck.gltf"))
add("g_texcoord1", "duck.gltf", ORIG_DUCK, {**ok_duck, "attributes": DUCK_ATTRS + ["texcoord1"]})

# node hierarchy: TRS parent with a matrix child; and a negative-determinant scale (winding must flip)
d = vdir("g_hierarchy"); g = G(); prim, _ = duck_base(g); copy_png(d); m = g.mesh([prim])
child = g.node(root=False, mesh=m, matrix=[0, 0, -1, 0, 0, 1, 0, 0, 1, 0, 0, 0, 5, 0, 0, 1])
mid = g.node(root=False, children=[child], rotation=[0, 0.7071068, 0, 0.7071068])
g.node(children=[mid], translation=[1, 2, 3], scale=[0.01, 0.01, 0.01])
g.write_gltf(os.path.join(d, "duck.gltf")); add("g_hierarchy", "duck.gltf", ORIG_DUCK, {**ok_duck, "winding": "ccw"})
for nm, kw in [("g_negscale_trs", {"scale": [-0.01, 0.01, 0.01]}),
               ("g_negscale_matrix", {"matrix": [0.01, 0, 0, 0, 0, -0.01, 0, 0, 0, 0, 0.01, 0, 0, 0, 0, 1]})]:
    d = vdir(nm); g = G(); prim, _ = duck_base(g); copy_png(d); g.node(mesh=g.mesh([prim]), **kw)
    g.write_gltf(os.path.join(d, "duck.gltf")); add(nm, "duck.gltf", ORIG_DUCK, {**ok_duck, "winding": "ccw"})

# multiple meshes, primitives and materials: the duck split in 3 primitives with 3 materials, plus a
# second mesh (the uint8 patch) with no material
d = vdir("g_multi"); g = G(); copy_png(d)
pa = g.acc(duck["pos"], FLOAT, "VEC3", minmax=True); na = g.acc(duck["nrm"], FLOAT, "VEC3"); ta = g.acc(duck["uv"], FLOAT, "VEC2")
g.texture_material({"uri": "DuckCM.png"})
g.j["materials"] += [{"name": "red", "pbrMetallicRoughness": {"baseColorFactor": [1, 0, 0, 1]}},
                     {"name": "", "pbrMetallicRoughness": {"baseColorFactor": [0, 1, 0, 1]}}]
thirds = [TRIS[:NT // 3], TRIS[NT // 3:2 * NT // 3], TRIS[2 * NT // 3:]]
prims = [{"attributes": {"POSITION": pa, "NORMAL": na, "TEXCOORD_0": ta}, "material": k,
          "indices": g.acc([i for t in part for i in t], USHORT, "SCALAR")} for k, part in enumerate(thirds)]
m0 = g.mesh(prims, "duck")
pa2 = g.acc([duck["pos"][v] for v in inv], FLOAT, "VEC3", minmax=True)
m1 = g.mesh([{"attributes": {"POSITION": pa2}, "indices": g.acc([i for t in patch_tris for i in t], UBYTE, "SCALAR")}], "patch")
g.node(mesh=m0); g.node(mesh=m1, translation=[200, 0, 0])
g.write_gltf(os.path.join(d, "multi.gltf"))
add("g_multi", "multi.gltf", None, {"triangles": NT + len(patch_tris), "vertices": NV + len(inv), "attributes": DUCK_ATTRS,
                                    "materials": 4, "textures": 1})

# a missing image file, and an image URI with a space (percent-encoded)
d = vdir("g_missing_image"); g = G(); prim, _ = duck_base(g, image={"uri": "nothere.png"}); g.node(mesh=g.mesh([prim]))
g.write_gltf(os.path.join(d, "duck.gltf")); add("g_missing_image", "duck.gltf", ORIG_DUCK, {**ok_duck, "missing_textures": 1})
d = vdir("g_uri_space"); g = G(); prim, _ = duck_base(g, image={"uri": "duck%20tex.png"}); g.node(mesh=g.mesh([prim]))
copy_png(d, "duck tex.png"); g.write_gltf(os.path.join(d, "duck model.gltf"), binname="duck model.bin")
g.j["buffers"][0]["uri"] = "duck%20model.bin"; json.dump(g.j, open(os.path.join(d, "duck model.gltf"), "w"))
add("g_uri_space", "duck model.gltf", ORIG_DUCK, ok_duck)

# KHR_texture_transform (used, and required)
for nm, req in [("g_ktt_used", False), ("g_ktt_required", True)]:
    d = vdir(nm); g = G(); prim, _ = duck_base(g); copy_png(d)
    g.j["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] = {
        "KHR_texture_transform": {"offset": [0.5, 0], "scale": [0.5, 0.5], "rotation": 0.3}}
    g.j["extensionsUsed"] = ["KHR_texture_transform"]
    if req: g.j["extensionsRequired"] = ["KHR_texture_transform"]
    g.node(mesh=g.mesh([prim])); g.write_gltf(os.path.join(d, "duck.gltf"))
    add(nm, "duck.gltf", ORIG_DUCK, ok_duck)  # applied to the UVs (docs/import-obj-gltf.md)

# unsupported required extensions
for nm, extname in [("g_draco", "KHR_draco_mesh_compression"), ("g_meshopt", "EXT_meshopt_compression")]:
    d = vdir(nm); g = G(); prim, _ = duck_base(g); copy_png(d)
    prim["extensions"] = {extname: {"bufferView": 0, "attributes": {"POSITION": 0}}}
    g.j["extensionsUsed"] = g.j["extensionsRequired"] = [extname]
    g.node(mesh=g.mesh([prim])); g.write_gltf(os.path.join(d, "duck.gltf")); add(nm, "duck.gltf", None, {"error": True})

# truncated GLBs (real Duck.glb) at several lengths
glb = open(os.path.join(DATA, "tex-duck/glTF_Binary/Duck.glb"), "rb").read()
for cut in [0, 4, 11, 12, 19, 20, 100, 1000, len(glb) // 2, len(glb) - 1]:
    nm = "g_glb_trunc_%d" % cut; d = vdir(nm); open(os.path.join(d, "duck.glb"), "wb").write(glb[:cut])
    add(nm, "duck.glb", None, {"error": True})
# GLB whose header length lies (larger than the file), and a GLB chunk length that lies
d = vdir("g_glb_lying_len"); b = bytearray(glb); struct.pack_into("<I", b, 8, len(glb) + 1000)
open(os.path.join(d, "duck.glb"), "wb").write(b); add("g_glb_lying_len", "duck.glb", None, {"error": True})
d = vdir("g_glb_lying_chunk"); b = bytearray(glb); jl = struct.unpack_from("<I", b, 12)[0]
struct.pack_into("<I", b, 20 + jl, 0x7ffffff0); open(os.path.join(d, "duck.glb"), "wb").write(b)
add("g_glb_lying_chunk", "duck.glb", None, {"error": True})

# bad accessors
def bad(nm, fn):
    d = vdir(nm); g = G(); prim, pa = duck_base(g); copy_png(d); fn(g, prim, pa)
    g.node(mesh=g.mesh([prim])); g.write_gltf(os.path.join(d, "duck.gltf")); add(nm, "duck.gltf", None, {"error": True})
bad("g_bad_offset", lambda g, p, pa: g.j["accessors"][pa].__setitem__("byteOffset", 1 << 20))
bad("g_bad_offset_unaligned", lambda g, p, pa: g.j["accessors"][pa].__setitem__("byteOffset", 2))
bad("g_bad_count", lambda g, p, pa: g.j["accessors"][pa].__setitem__("count", NV * 10))
bad("g_bad_count_huge", lambda g, p, pa: g.j["accessors"][pa].__setitem__("count", 4000000000))
bad("g_bad_idx_count", lambda g, p, pa: g.j["accessors"][p["indices"]].__setitem__("count", 10 ** 6))
bad("g_bad_view_len", lambda g, p, pa: g.j["bufferViews"][g.j["accessors"][pa]["bufferView"]].__setitem__("byteLength", 1 << 24))
bad("g_bad_accessor_ref", lambda g, p, pa: p["attributes"].__setitem__("NORMAL", 99))
bad("g_bad_material_ref", lambda g, p, pa: p.__setitem__("material", 7))
bad("g_bad_stride", lambda g, p, pa: g.j["bufferViews"][g.j["accessors"][pa]["bufferView"]].__setitem__("byteStride", 4))
def oob_index(g, p, pa):
    i = g.acc([NV + 5] + duck["idx"][1:], USHORT, "SCALAR"); p["indices"] = i
bad("g_index_oob", oob_index)
def nan_pos(g, p, pa):
    vals = list(duck["pos"]); vals[7] = (float("nan"), 0.0, 0.0)
    p["attributes"]["POSITION"] = g.acc(vals, FLOAT, "VEC3")
bad("g_nan_position", nan_pos)
bad("g_pos_vec2", lambda g, p, pa: g.j["accessors"][pa].__setitem__("type", "VEC2"))
d = vdir("g_pos_int_nonquant"); g = G(); prim, pa = duck_base(g); copy_png(d); g.j["accessors"][pa]["componentType"] = UINT
g.node(mesh=g.mesh([prim])); g.write_gltf(os.path.join(d, "duck.gltf")); add("g_pos_int_nonquant", "duck.gltf", None, {"error_or_ok": True})  # read leniently
def idx_float(g, p, pa): g.j["accessors"][p["indices"]]["componentType"] = FLOAT; g.j["accessors"][p["indices"]]["count"] //= 2
bad("g_idx_float", idx_float)
# malformed data URIs, an unaligned bufferView (in bounds), and a 2-element-wide stride
d = vdir("g_bad_base64_image"); g = G(); prim, _ = duck_base(g, image={"uri": "data:image/png;base64,!!!not base64!!!"})
g.node(mesh=g.mesh([prim])); g.write_gltf(os.path.join(d, "duck.gltf")); add("g_bad_base64_image", "duck.gltf", None, {"error_or_ok": True})
d = vdir("g_bad_base64_buffer"); g = G(); prim, _ = duck_base(g, textured=False); g.node(mesh=g.mesh([prim]))
g.write_gltf(os.path.join(d, "duck.gltf"), embed=True); g.j["buffers"][0]["uri"] = g.j["buffers"][0]["uri"][:-40] + "*&^%"
json.dump(g.j, open(os.path.join(d, "duck.gltf"), "w")); add("g_bad_base64_buffer", "duck.gltf", None, {"error": True})
d = vdir("g_unaligned_view"); g = G(); g.bin += b"\0\0"
raw = b"".join(struct.pack("<3f", *p) for p in duck["pos"]); g.j["bufferViews"].append({"buffer": 0, "byteOffset": 2, "byteLength": len(raw)}); g.bin += raw
g.j["accessors"].append({"bufferView": 0, "componentType": FLOAT, "count": NV, "type": "VEC3", "min": lo, "max": hi})
ia = g.acc(duck["idx"], USHORT, "SCALAR"); g.node(mesh=g.mesh([{"attributes": {"POSITION": 0}, "indices": ia}]))
g.write_gltf(os.path.join(d, "duck.gltf")); add("g_unaligned_view", "duck.gltf", None, {"error_or_ok": True, "triangles": NT})
d = vdir("g_wide_stride"); g = G()
raw = b"".join(struct.pack("<3f", *p) + b"\0" * 20 for p in duck["pos"]); bv = g.view(raw, stride=32)
g.j["accessors"].append({"bufferView": bv, "componentType": FLOAT, "count": NV, "type": "VEC3", "min": lo, "max": hi})
ia = g.acc(duck["idx"], USHORT, "SCALAR"); g.node(mesh=g.mesh([{"attributes": {"POSITION": 0}, "indices": ia}]))
g.write_gltf(os.path.join(d, "duck.gltf")); add("g_wide_stride", "duck.gltf", ORIG_DUCK, {"triangles": NT, "vertices": NV, "attributes": []})
d = vdir("g_missing_bin"); g = G(); prim, _ = duck_base(g); g.node(mesh=g.mesh([prim])); g.write_gltf(os.path.join(d, "duck.gltf"))
os.remove(os.path.join(d, "duck.bin")); add("g_missing_bin", "duck.gltf", None, {"error": True})
d = vdir("g_short_bin"); g = G(); prim, _ = duck_base(g); g.node(mesh=g.mesh([prim])); g.write_gltf(os.path.join(d, "duck.gltf"))
open(os.path.join(d, "duck.bin"), "r+b").truncate(1000); add("g_short_bin", "duck.gltf", None, {"error": True})
d = vdir("g_bad_json"); open(os.path.join(d, "x.gltf"), "w").write('{"asset": {"version": "2.0"}, "meshes": [')
add("g_bad_json", "x.gltf", None, {"error": True})
d = vdir("g_version1"); open(os.path.join(d, "x.gltf"), "w").write('{"asset": {"version": "1.0"}, "meshes": {}}')
add("g_version1", "x.gltf", None, {"error": True})
d = vdir("g_no_meshes"); open(os.path.join(d, "x.gltf"), "w").write('{"asset": {"version": "2.0"}}')
add("g_no_meshes", "x.gltf", None, {"error_or_empty": True})
d = vdir("g_node_cycle"); g = G(); prim, _ = duck_base(g, textured=False); m = g.mesh([prim])
g.node(mesh=m, children=[1]); g.node(root=False, children=[0]); g.write_gltf(os.path.join(d, "duck.gltf"))
add("g_node_cycle", "duck.gltf", None, {"error": True})
for real in ["tex-cesium-milk-truck/CesiumMilkTruck.gltf", "tex-water-bottle/WaterBottle.gltf", "tex-duck/glTF_Binary/Duck.glb",
             "morph-animated-morph-cube/AnimatedMorphCube.gltf"]:
    p = os.path.join(DATA, real)
    if os.path.exists(p):
        manifest.append({"name": "real_" + os.path.basename(p), "file": p, "orig": p, "real": True})

# ---------------------------------------------------------------- OBJ
SPOT = os.path.join(DATA, "tex-spot/spot_triangulated.obj")
spot = open(SPOT).read().splitlines()
sv = [l for l in spot if l.startswith("v ")]; svt = [l for l in spot if l.startswith("vt ")]
sf = [l for l in spot if l.startswith("f ")]
SPOT_T, SPOT_V = len(sf), len(sv)
ok_spot = {"triangles": SPOT_T, "vertices": SPOT_V, "attributes": ["texcoord0"], "textures": 1}
SPOT_PNG = os.path.join(DATA, "tex-spot/spot_texture.png")

def obj_variant(nm, lines, expect, fname="spot.obj", mtl=None, png=True, orig=SPOT, nl="\n", sub=None):
    d = vdir(nm) if sub is None else os.path.join(vdir(nm), sub)
    os.makedirs(d, exist_ok=True)
    open(os.path.join(d, fname), "w", newline="").write(nl.join(lines) + nl)
    if mtl is not None: open(os.path.join(d, mtl[0]), "w").write(mtl[1])
    if png: shutil.copy(SPOT_PNG, os.path.join(d, png if isinstance(png, str) else "spot_texture.png"))
    add(nm, fname if sub is None else os.path.join(sub, fname), orig, expect)

MTL = "newmtl spot\nKd 1 1 1\nmap_Kd spot_texture.png\n"
withmtl = ["mtllib spot.mtl", "usemtl spot"] + sv + svt + sf
obj_variant("o_plain", withmtl, ok_spot, mtl=("spot.mtl", MTL))
# negative indices
neg, nv_seen, nvt_seen = [], 0, 0
for l in withmtl:
    if l.startswith("v "): nv_seen += 1
    if l.startswith("vt "): nvt_seen += 1
    if l.startswith("f "):
        cs = []
        for c in l.split()[1:]:
            v, t = c.split("/")[:2]; cs.append("%d/%d" % (int(v) - nv_seen - 1, int(t) - nvt_seen - 1))
        l = "f " + " ".join(cs)
    neg.append(l)
obj_variant("o_negidx", neg, ok_spot, mtl=("spot.mtl", MTL))
# interleaved v and f with negative indices (each face refers to the most recent vertices)
inter, out_v = [], 0
for l in sf[:500]:
    cs = l.split()[1:]
    for c in cs: inter.append(sv[int(c.split("/")[0]) - 1])
    inter.append("f -3 -2 -1")
obj_variant("o_negidx_interleaved", inter, {"triangles": 500, "vertices": 1500, "attributes": []}, png=False, orig=None)
# quads (real) and n-gons: pairs of spot's triangles sharing an edge merged into quads, and spot's control mesh
QUAD = os.path.join(DATA, "tex-spot/spot_quadrangulated.obj")
ql = open(QUAD).read().splitlines()
qT = sum(len(l.split()) - 3 for l in ql if l.startswith("f "))
obj_variant("o_quads", ql, {"triangles": qT, "vertices": sum(1 for l in ql if l.startswith("v ")), "attributes": ["texcoord0"]},
            png=True, orig=QUAD)
ngon = ["v %f %f 0" % (math.cos(2 * math.pi * k / 40), math.sin(2 * math.pi * k / 40)) for k in range(40)]
ngon += ["f " + " ".join(str(k + 1) for k in range(40)), "f 1 2 3 4 5"]
obj_variant("o_ngon40", ngon, {"triangles": 38 + 3, "vertices": 40, "attributes": []}, png=False, orig=None)
big = ["v %f %f 0" % (math.cos(2 * math.pi * k / 300), math.sin(2 * math.pi * k / 300)) for k in range(300)]
big += ["f " + " ".join(str(k + 1) for k in range(300))]
obj_variant("o_ngon300", big, {"error_or_ok": True, "triangles": 298}, png=False, orig=None)
# vertex colours
vc = ["usemtl spot", "mtllib spot.mtl"] + [l + " %.4f %.4f %.4f" % ((i % 7) / 6, (i % 5) / 4, (i % 3) / 2) for i, l in enumerate(sv)] + svt + sf
obj_variant("o_vcolor", vc, {**ok_spot, "attributes": ["texcoord0", "color"]}, mtl=("spot.mtl", MTL))
# vt with 3 components
obj_variant("o_vt3", ["mtllib spot.mtl", "usemtl spot"] + sv + [l + " 0" for l in svt] + sf, ok_spot, mtl=("spot.mtl", MTL))
# faces without vt/vn mixed with faces with v/vt/vn, v//vn
vn = ["vn 0 0 1", "vn 0 1 0"]
mixed = []
for i, l in enumerate(sf):
    cs = l.split()[1:]
    if i % 3 == 0: mixed.append("f " + " ".join(c.split("/")[0] for c in cs))
    elif i % 3 == 1: mixed.append("f " + " ".join(c + "/1" for c in cs))
    else: mixed.append("f " + " ".join(c.split("/")[0] + "//2" for c in cs))
obj_variant("o_mixed", ["mtllib spot.mtl", "usemtl spot"] + sv + svt + vn + mixed,
            {**ok_spot, "attributes": ["normal", "texcoord0"]}, mtl=("spot.mtl", MTL))
# o/g/s groups and many usemtl
grp = ["mtllib spot.mtl"] + sv + svt
mtl10 = "".join("newmtl m%d\nKd %f 0.5 0.5\nmap_Kd spot_texture.png\n" % (k, k / 10) for k in range(10))
for i, l in enumerate(sf):
    if i % 400 == 0: grp += ["o part%d" % (i // 400), "g grp%d sub" % (i // 400), "s %s" % (["off", "1", "2"][i % 3])]
    if i % 97 == 0: grp.append("usemtl m%d" % (i % 10))
    grp.append(l)
obj_variant("o_groups_usemtl", grp, {**ok_spot, "materials": 10}, mtl=("spot.mtl", mtl10))
# missing .mtl, missing texture, map_Kd with options, spaces in names
obj_variant("o_missing_mtl", ["mtllib nothere.mtl", "usemtl spot"] + sv + svt + sf, {**ok_spot, "textures": None}, png=False)
obj_variant("o_missing_tex", withmtl, {**ok_spot, "missing_textures": 1}, mtl=("spot.mtl", "newmtl spot\nmap_Kd gone.png\n"), png=False)
obj_variant("o_mapkd_opts", withmtl, ok_spot, mtl=("spot.mtl", "newmtl spot\nKd 1 1 1\nmap_Kd -s 1 1 1 -o 0 0 0 -bm 1 spot_texture.png\n"))
obj_variant("o_mapkd_clamp", withmtl, ok_spot, mtl=("spot.mtl", "newmtl spot\nmap_Kd -clamp on -blendu off spot_texture.png\n"))
obj_variant("o_spaces", ["mtllib spot model.mtl", "usemtl spot mat"] + sv + svt + sf, ok_spot, fname="spot model.obj",
            mtl=("spot model.mtl", "newmtl spot mat\nmap_Kd spot tex.png\n"), png="spot tex.png", sub="dir with spaces")
obj_variant("o_backslash_path", withmtl, ok_spot, mtl=("spot.mtl", "newmtl spot\nmap_Kd textures\\spot_texture.png\n"), png=False)
os.makedirs(os.path.join(OUT, "o_backslash_path", "textures"), exist_ok=True)
shutil.copy(SPOT_PNG, os.path.join(OUT, "o_backslash_path", "textures", "spot_texture.png"))
obj_variant("o_crlf", withmtl, ok_spot, mtl=("spot.mtl", MTL.replace("\n", "\r\n")), nl="\r\n")
cont = []
for l in withmtl:
    if l.startswith("f "): cs = l.split(); l = " ".join(cs[:2]) + " \\\n  " + " ".join(cs[2:])
    elif l.startswith("v "): cs = l.split(); l = " ".join(cs[:2]) + " \\\n" + " ".join(cs[2:])
    cont.append(l)
obj_variant("o_continuation", cont, ok_spot, mtl=("spot.mtl", MTL))
obj_variant("o_idx_oob", withmtl[:-1] + ["f 1/1 2/2 99999/3"], {"error": True}, mtl=("spot.mtl", MTL))
obj_variant("o_vt_oob", withmtl[:-1] + ["f 1/1 2/2 3/99999"], {"error": True}, mtl=("spot.mtl", MTL))
obj_variant("o_neg_oob", withmtl[:-1] + ["f 1/1 2/2 -99999/3"], {"error": True}, mtl=("spot.mtl", MTL))
obj_variant("o_idx_zero", withmtl[:-1] + ["f 1/1 2/2 0/3"], {"error": True}, mtl=("spot.mtl", MTL))
obj_variant("o_nan", ["mtllib spot.mtl", "usemtl spot", "v nan nan nan"] + sv[1:] + svt + sf, {"error": True}, mtl=("spot.mtl", MTL))
obj_variant("o_inf", ["v inf 0 0"] + sv[1:] + svt + sf, {"error": True})
obj_variant("o_garbage_number", ["v 1.0abc 0 0"] + sv[1:] + svt + sf, {"error_or_ok": True})
obj_variant("o_no_faces", sv, {"triangles": 0, "vertices": SPOT_V, "attributes": [], "pointcloud": True}, png=False)
obj_variant("o_empty", [""], {"error": True}, png=False)
d = vdir("o_binary"); open(os.path.join(d, "x.obj"), "wb").write(b"\x00\x01binary" * 100); add("o_binary", "x.obj", None, {"error": True})
obj_variant("o_mtl_dir", ["mtllib sub"] + sv + svt + sf, {**ok_spot, "textures": None}, png=False)
os.makedirs(os.path.join(OUT, "o_mtl_dir", "sub"), exist_ok=True)
HORSE = os.path.join(DATA, "seq-horse-gallop/0001.obj")
if os.path.exists(HORSE): manifest.append({"name": "real_horse0001", "file": HORSE, "orig": HORSE, "real": True})
manifest.append({"name": "real_spot", "file": SPOT, "orig": SPOT, "real": True})

# ---------------------------------------------------------------- PLY (from ASCII exports, see run_matrix.sh)
def read_ascii_ply(path):
    lines = open(path).read().split("\n"); i = 0; props = []; counts = {}
    while lines[i].strip() != "end_header":
        w = lines[i].split()
        if w and w[0] == "element": counts[w[1]] = int(w[2]); cur = w[1]
        if w and w[0] == "property" and cur == "vertex": props.append(w[-1])
        i += 1
    i += 1; V = [list(map(float, lines[i + k].split())) for k in range(counts["vertex"])]; i += counts["vertex"]
    F = [list(map(int, lines[i + k].split()))[1:] for k in range(counts.get("face", 0))]
    return props, V, F

def ply_header(fmt, elems, comments=()):
    h = ["ply", "format %s 1.0" % fmt] + ["comment " + c for c in comments]
    for name, n, props in elems:
        h.append("element %s %d" % (name, n)); h += ["property " + p for p in props]
    return "\n".join(h + ["end_header"]) + "\n"

ASC = sys.argv[3] if len(sys.argv) > 3 else None  # dir with ascii exports: res4.ply, color.ply
if ASC:
    DR4 = os.path.join(DATA, "scan-dragon/dragon_vrip_res4.ply"); COL = os.path.join(DATA, "color-open3d-small/color.ply")
    LAU = os.path.join(DATA, "tex-ply-wedge-uv/laurana500.ply")
    _, dv, dfaces = read_ascii_ply(os.path.join(ASC, "res4.ply"))
    cprops, cv, cfaces = read_ascii_ply(os.path.join(ASC, "color.ply"))
    def ply_variant(nm, data, expect, orig, fname="m.ply", extra=()):
        d = vdir(nm); open(os.path.join(d, fname), "wb").write(data if isinstance(data, bytes) else data.encode())
        for src, dst in extra: shutil.copy(src, os.path.join(d, dst))
        add(nm, fname, orig, expect)
    DT, DV = len(dfaces), len(dv)
    xyz = ["float x", "float y", "float z"]
    def verts_ascii(V, cols=3): return "".join(" ".join("%r" % x for x in v[:cols]) + "\n" for v in V)
    # tristrips: every triangle a strip of 3, separated by -1; and a binary version with long strips
    strip = []
    for f in dfaces: strip += f + [-1]
    strip.pop()
    ply_variant("p_tristrips", ply_header("ascii", [("vertex", DV, xyz), ("tristrips", 1, ["list int int vertex_indices"])]) +
                verts_ascii(dv) + "%d %s\n" % (len(strip), " ".join(map(str, strip))),
                {"triangles": DT, "vertices": DV, "attributes": []}, DR4)
    body = b"".join(struct.pack("<3f", *v[:3]) for v in dv) + struct.pack("<i", len(strip)) + struct.pack("<%di" % len(strip), *strip)
    ply_variant("p_tristrips_bin", ply_header("binary_little_endian", [("vertex", DV, xyz), ("tristrips", 1, ["list int int vertex_indices"])]).encode() + body,
                {"triangles": DT, "vertices": DV, "attributes": []}, DR4)
    body = b"".join(struct.pack("<3f", *v[:3]) for v in dv) + struct.pack("<I", len(strip)) + struct.pack("<%dI" % len(strip), *[s & 0xffffffff for s in strip])
    ply_variant("p_tristrips_uint", ply_header("binary_little_endian", [("vertex", DV, xyz), ("tristrips", 1, ["list uint uint vertex_indices"])]).encode() + body,
                {"triangles": DT, "vertices": DV, "attributes": []}, DR4)
    faces_ascii = "".join("3 %d %d %d\n" % tuple(f) for f in dfaces)
    ply_variant("p_vertex_index", ply_header("ascii", [("vertex", DV, xyz), ("face", DT, ["list uchar int vertex_index"])]) + verts_ascii(dv) + faces_ascii,
                {"triangles": DT, "vertices": DV, "attributes": []}, DR4)
    for lt, it, fmt_c, fmt_i in [("ushort", "int", "H", "i"), ("uchar", "uint", "B", "I"), ("uint", "ushort", "I", "H"), ("char", "short", "b", "h")]:
        if it in ("ushort", "short") and DV > 32767: continue
        body = b"".join(struct.pack("<3f", *v[:3]) for v in dv) + b"".join(struct.pack("<" + fmt_c + "3" + fmt_i, 3, *f) for f in dfaces)
        ply_variant("p_list_%s_%s" % (lt, it), ply_header("binary_little_endian", [("vertex", DV, xyz), ("face", DT, ["list %s %s vertex_indices" % (lt, it)])]).encode() + body,
                    {"triangles": DT, "vertices": DV, "attributes": []}, DR4)
    # color.ply derived: x y z nx ny nz red green blue alpha (as exported)
    CV, CT = len(cv), len(cfaces)
    cfa = "".join("3 %d %d %d\n" % tuple(f) for f in cfaces)
    ply_variant("p_texture_uv", ply_header("ascii", [("vertex", CV, xyz + ["float texture_u", "float texture_v"]), ("face", CT, ["list uchar int vertex_indices"])]) +
                "".join("%r %r %r %r %r\n" % (v[0], v[1], v[2], (v[0] + 1) / 2, (v[1] + 1) / 2) for v in cv) + cfa,
                {"triangles": CT, "vertices": CV, "attributes": ["texcoord0"]}, COL)
    ply_variant("p_float_colors", ply_header("ascii", [("vertex", CV, xyz + ["float nx", "float ny", "float nz", "float red", "float green", "float blue"]),
                                                       ("face", CT, ["list uchar int vertex_indices"])]) +
                "".join("%r %r %r %r %r %r %r %r %r\n" % (*v[:6], v[6] / 255, v[7] / 255, v[8] / 255) for v in cv) + cfa,
                {"triangles": CT, "vertices": CV, "attributes": ["normal", "color"]}, COL)
    ply_variant("p_double_colors_bin", ply_header("binary_big_endian", [("vertex", CV, xyz + ["double red", "double green", "double blue", "double alpha"]),
                                                       ("face", CT, ["list uchar int vertex_indices"])]).encode() +
                b"".join(struct.pack(">3f4d", *v[:3], v[6] / 255, v[7] / 255, v[8] / 255, 1.0) for v in cv) +
                b"".join(struct.pack(">B3i", 3, *f) for f in cfaces),
                {"triangles": CT, "vertices": CV, "attributes": ["color"]}, COL)
    hdr_c = ply_header("ascii", [("vertex", CV, xyz), ("face", CT, ["list uchar int vertex_indices"])])
    ply_variant("p_obj_info", hdr_c.replace("format ascii 1.0\n", "format ascii 1.0\nobj_info num_cols 640\nobj_info is_mesh 1\ncomment hi\n") + verts_ascii(cv) + cfa,
                {"triangles": CT, "vertices": CV, "attributes": []}, COL)
    ply_variant("p_unknown_elems", ply_header("ascii", [("vertex", CV, xyz + ["float confidence", "list uchar float weights"]),
                                                        ("camera", 1, ["float px", "list int uchar name"]),
                                                        ("face", CT, ["list uchar int vertex_indices", "uchar flags", "list uchar float texcoord"]),
                                                        ("edge", 2, ["int vertex1", "int vertex2", "list ushort int junk"]), ("material", 0, ["uchar r"])]) +
                "".join("%r %r %r 0.5 2 1 2\n" % tuple(v[:3]) for v in cv) + "0.5 3 65 66 67\n" +
                "".join("3 %d %d %d 7 0\n" % tuple(f) for f in cfaces) + "0 1 0\n1 2 3 5 6 7\n",
                {"triangles": CT, "vertices": CV, "attributes": []}, COL)
    body = b"".join(struct.pack("<3ff", *v[:3], 0.5) + struct.pack("<B2f", 2, 1, 2) for v in cv) + struct.pack("<fi3B", 0.5, 3, 65, 66, 67)
    body += b"".join(struct.pack("<B3iB", 3, *f, 7) + struct.pack("<B", 0) for f in cfaces) + struct.pack("<iiH", 0, 1, 0) + struct.pack("<iiH3i", 1, 2, 3, 5, 6, 7)
    ply_variant("p_unknown_elems_bin", ply_header("binary_little_endian", [("vertex", CV, xyz + ["float confidence", "list uchar float weights"]),
                                                        ("camera", 1, ["float px", "list int uchar name"]),
                                                        ("face", CT, ["list uchar int vertex_indices", "uchar flags", "list uchar float texcoord"]),
                                                        ("edge", 2, ["int vertex1", "int vertex2", "list ushort int junk"])]).encode() + body,
                {"triangles": CT, "vertices": CV, "attributes": []}, COL)
    # point clouds: zero faces, no face element; with normals and colours
    pc_props = xyz + ["float nx", "float ny", "float nz", "uchar red", "uchar green", "uchar blue"]
    pcb = b"".join(struct.pack("<6f3B", *v[:6], *map(int, v[6:9])) for v in cv)
    ply_variant("p_pointcloud_face0", ply_header("binary_little_endian", [("vertex", CV, pc_props), ("face", 0, ["list uchar int vertex_indices"])]).encode() + pcb,
                {"triangles": 0, "vertices": CV, "attributes": ["normal", "color"], "pointcloud": True}, COL)
    ply_variant("p_pointcloud_noface", ply_header("binary_little_endian", [("vertex", CV, pc_props)]).encode() + pcb,
                {"triangles": 0, "vertices": CV, "attributes": ["normal", "color"], "pointcloud": True}, COL)
    # lying counts and truncation
    cbody = b"".join(struct.pack("<3f", *v[:3]) for v in cv) + b"".join(struct.pack("<B3i", 3, *f) for f in cfaces)
    hb = lambda nv, nf: ply_header("binary_little_endian", [("vertex", nv, xyz), ("face", nf, ["list uchar int vertex_indices"])]).encode()
    ply_variant("p_lying_vcount_more", hb(CV + 100, CT) + cbody, {"error": True}, None)
    ply_variant("p_lying_vcount_less", hb(CV - 100, CT) + cbody, {"error": True}, None)
    ply_variant("p_lying_fcount_more", hb(CV, CT + 10) + cbody, {"error": True}, None)
    ply_variant("p_lying_huge", hb(4000000000, CT) + cbody, {"error": True}, None)
    ply_variant("p_lying_ascii_more", hdr_c.replace("vertex %d" % CV, "vertex %d" % (CV + 5)) + verts_ascii(cv) + cfa, {"error": True}, None)
    ply_variant("p_lying_ascii_less", hdr_c.replace("vertex %d" % CV, "vertex %d" % (CV - 5)) + verts_ascii(cv) + cfa, {"error": True}, None)
    for frac in [0.3, 0.6, 0.99]:
        full = hb(CV, CT) + cbody
        ply_variant("p_trunc_bin_%d" % int(frac * 100), full[:int(len(full) * frac)], {"error": True}, None)
    ply_variant("p_trunc_header", (hb(CV, CT))[:40], {"error": True}, None)
    ply_variant("p_idx_oob", hb(CV, 1) + cbody[:CV * 12] + struct.pack("<B3i", 3, 0, 1, CV), {"error": True}, None)
    ply_variant("p_neg_list", hb(CV, 1) + cbody[:CV * 12].replace(b"", b"")[:CV * 12] + struct.pack("<b3i", -3, 0, 1, 2) if False else
                ply_header("binary_little_endian", [("vertex", CV, xyz), ("face", 1, ["list char int vertex_indices"])]).encode() + cbody[:CV * 12] + struct.pack("<b3i", -3, 0, 1, 2),
                {"error": True}, None)
    nanb = bytearray(cbody); struct.pack_into("<f", nanb, 12 * 5, float("nan"))
    ply_variant("p_nan", hb(CV, CT) + bytes(nanb), {"error": True}, None)
    # TextureFile comments: laurana (real) with the texture missing, and two TextureFiles with texnumber
    lau = open(LAU, "rb").read()
    ply_variant("p_texfile_missing", lau.replace(b"TextureFile laurana500.png", b"TextureFile nothere.png"),
                {"triangles": 494, "vertices": 266, "attributes": ["texcoord0"], "missing_textures": 1}, LAU)
    ply_variant("p_wedge_texcoord", lau, {"triangles": 494, "vertices": 266, "attributes": ["texcoord0"], "textures": 1}, LAU,
                extra=[(os.path.join(DATA, "tex-ply-wedge-uv/laurana500.png"), "laurana500.png")])
    ply_variant("p_texfile_spaces", lau.replace(b"TextureFile laurana500.png", b"TextureFile my tex.png"),
                {"triangles": 494, "vertices": 266, "attributes": ["texcoord0"], "textures": 1}, LAU,
                extra=[(os.path.join(DATA, "tex-ply-wedge-uv/laurana500.png"), "my tex.png")])
    ply_variant("p_empty", b"", {"error": True}, None)
    ply_variant("p_header_only", hb(0, 0), {"error_or_empty": True}, None)
    for real in ["scan-bunny/bun_zipper.ply", "color-open3d-small/color.ply", "tex-ply-wedge-uv/matteonormb.ply", "scan-dragon/dragon_vrip_res4.ply"]:
        p = os.path.join(DATA, real); manifest.append({"name": "real_" + os.path.basename(p), "file": p, "orig": p, "real": True})

json.dump(manifest, open(os.path.join(OUT, "manifest.json"), "w"), indent=1)
print(len(manifest), "variants in", OUT)

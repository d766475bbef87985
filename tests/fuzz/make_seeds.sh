#!/usr/bin/env bash
# Seed corpora of the reader fuzzers (reader_fuzz.cpp): small real files from ../shared/data, own-format
# files the `lodforge` CLI writes from them, and the hostile inputs of issue 32 in small form. Every seed is
# kept to a few KB (meshes simplified to a handful of triangles): libFuzzer's default -max_len is the largest
# seed, and a reader's time per input grows with its size, so small seeds are what makes 10^6 runs feasible.
# Usage: make_seeds.sh OUT_DIR SHARED_DATA LODFORGE_BINARY
set -euo pipefail
out="$1" data="$2" lodforge="$3 --quiet"
rm -rf "$out"
for r in gltf obj lfo mco lfmorph lfmstrips lodstrips preset landmarks; do mkdir -p "$out/$r" "$out/$r-found"; done
work="$out/work"
mkdir -p "$work"

# A colored PLY cut down to 16 triangles (clustering: the collapse stops early on this open scan), the
# source of the small seeds below.
small="$work/small.ply"
$lodforge simplify "$data/color-open3d-small/color.ply" -o "$small" --triangles 16 --mode cluster

# glTF: self-contained files only (the harness writes one file, so external .bin files are absent).
$lodforge simplify "$data/tex-duck/glTF_Binary/Duck.glb" -o "$out/gltf/duck.glb" --triangles 16  # textured
$lodforge simplify "$data/skin-rigged-simple/RiggedSimple.glb" -o "$out/gltf/rigged.glb" --triangles 16  # skinned
$lodforge convert "$data/morph-animated-morph-cube/AnimatedMorphCube.gltf" "$out/gltf/morph-cube.glb"
$lodforge convert "$small" "$out/gltf/color.glb"
tri='AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA'
buffer='"buffers":[{"byteLength":36,"uri":"data:application/octet-stream;base64,'$tri'"}],"bufferViews":[{"buffer":0,"byteLength":36}]'
accessor='"accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3"}],"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}]'
echo '{"asset":{"version":"2.0"},'"$buffer,$accessor"',"nodes":[{"mesh":0,"matrix":[1,0,0,0,0,1,0,0,0,0,1,0,0,0,0,1]}],"scenes":[{"nodes":[0]}],"scene":0}' > "$out/gltf/triangle.gltf"
nodes=$(for i in $(seq 1 40); do printf '{"children":[%d]},' "$i"; done)
echo '{"asset":{"version":"2.0"},'"$buffer,$accessor"',"nodes":['"$nodes"'{"mesh":0}],"scenes":[{"nodes":[0]}]}' > "$out/gltf/deep-nodes.gltf"
echo '{"asset":{"version":"2.0"},'"$buffer"',"accessors":[{"componentType":5126,"count":3,"type":"VEC3","sparse":{"count":3,"indices":{"bufferView":0,"componentType":5125},"values":{"bufferView":0}}}],"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],"nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}],"extras":[[[[[[[[]]]]]]]]}' > "$out/gltf/sparse.gltf"

# OBJ: the text, a "#--mtl--" line, then the material library (its mtllib renamed to fuzz.mtl).
$lodforge simplify "$data/tex-spot/spot_control_mesh.obj" -o "$work/spot.obj" --triangles 16
{ sed 's/^mtllib .*/mtllib fuzz.mtl/' "$work/spot.obj"; echo '#--mtl--'; cat "$work/spot.mtl"; } > "$out/obj/spot.obj"
printf 'mtllib fuzz.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\nusemtl my red\nf 1/1/1 2/2/1 3/3/1\ng quad\nusemtl plain\nf 2 4 3\n#--mtl--\nnewmtl my red\nKd 1 0 0\nnewmtl plain\nKa 0 0 0\nKd 0 1 0\nd 0.5\n' > "$out/obj/materials.obj"

# Own formats, written by the CLI from small inputs.
$lodforge octree build "$small" -o "$out/lfo/small.lfo" --max-triangles 6
# The same asset marked as version 2 (the layout before the container index): refused, never parsed.
cp "$out/lfo/small.lfo" "$out/lfo/small-v2.lfo"
printf '\x02' | dd of="$out/lfo/small-v2.lfo" bs=1 seek=8 conv=notrunc status=none
$lodforge mcoctree build "$data/morph-animated-morph-cube/AnimatedMorphCube.gltf" -o "$out/mco/cube.mco" --resolution 4
$lodforge strips "$small" -o "$out/lodstrips/small.lodstrips"
$lodforge morph build "$data/morph-animated-morph-cube/AnimatedMorphCube.gltf" -o "$out/lfmorph/cube.lfmorph" \
  --frames 2 --levels 0.5 --strips "$out/lfmstrips/cube.lfmstrips"

# Presets and landmark files: the documented forms.
cat > "$out/preset/default.json" <<'JSON'
{"version": 1, "name": "default", "method": "collapse",
 "levels": [{"ratio": 0.5}, {"triangles": 1000}, {"error": 0.01}],
 "weights": {"normal": 0.05, "color": 0.1, "uv": 0.1, "uv_sets": [0.1, 0.2]}, "lock_border": false,
 "octree": {"max_triangles_per_node": 20000, "max_depth": 8, "memory_mb": 256}, "mcoctree": {"resolution": 128},
 "strips": {"primitive_restart": true}, "export": {"glb": true, "ply": false, "obj": false, "lodstrips": false}}
JSON
printf '{"format": "lodforge-landmarks", "version": 1, "pairs": [[0, 5], [12, 7], [3, 3]]}\n' > "$out/landmarks/pairs.json"
# landmarks_fuzz's first finding (a "format" that is not a string), kept so every run replays it.
printf '{"format": 1}' > "$out/landmarks/format-number.json"
rm -rf "$work"

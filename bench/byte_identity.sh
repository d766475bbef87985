#!/usr/bin/env bash
# Runs every command that writes a file (info, convert, simplify, lod, strips, pack with each method, octree,
# mcoctree, morph) on a few shared meshes and writes the outputs under OUT_DIR, so two builds can be compared
# byte for byte after a refactor:
#   bench/byte_identity.sh /work/main/build/bin/lodforge /tmp/before
#   bench/byte_identity.sh build/bin/lodforge /tmp/after
#   diff -r -I "time: " /tmp/before /tmp/after    # only the wall-clock "time:" lines of octree build may differ
# Data: the shared test meshes (DATA, default /work/shared/data). Runs single-threaded where a flag allows it.
set -euo pipefail
bin="$(realpath "$1")"; out="$2"; data="${DATA:-/work/shared/data}"
rm -rf "$out"; mkdir -p "$out"; cd "$out"
run() { local name="$1"; shift; "$bin" -q "$@" > "$name.stdout" 2> "$name.stderr" || echo "exit $?" >> "$name.stdout"; }
declare -A mesh=(
  [bunny]="$data/scan-bunny/bun_zipper.ply"
  [duck]="$data/tex-duck/glTF_Binary/Duck.glb"
  [color]="$data/color-open3d-small/color.ply"
  [rigged]="$data/skin-rigged-simple/RiggedSimple.glb"
)
for m in bunny duck color rigged; do
  in="${mesh[$m]}"
  run "$m.info" info "$in"
  run "$m.convert" convert "$in" "$m.convert.ply"
  run "$m.simplify" simplify "$in" -o "$m.simplify.ply" --ratio 0.25
  run "$m.simplify-cluster" simplify "$in" -o "$m.simplify-cluster.ply" --ratio 0.25 --mode cluster
  run "$m.lod" lod "$in" -o "$m.lod" --levels 0.5,0.1
  run "$m.strips" strips "$in" -o "$m.lodstrips" --json
  run "$m.strips-extract" strips extract "$m.lodstrips" --lod 0.5 -o "$m.strips-extract.ply"
  for method in collapse cluster octree lodstrips mcoctree; do
    run "$m.pack-$method" pack "$in" -o "$m.pack-$method" --method "$method" --json
  done
  run "$m.mcoctree" mcoctree build "$in" -o "$m.mco" --resolution 48
  run "$m.mcoctree-info" mcoctree info "$m.mco"
  run "$m.mcoctree-extract" mcoctree extract "$m.mco" --priority 3 -o "$m.mcoctree-extract.ply"
done
for m in bunny color; do
  in="${mesh[$m]}"
  run "$m.octree" octree build "$in" -o "$m.lfo" --max-triangles 2000 --threads 1
  run "$m.octree-info" octree info "$m.lfo"
  run "$m.octree-info-json" octree info "$m.lfo" --json
  run "$m.octree-extract" octree extract "$m.lfo" --level 1 -o "$m.octree-extract.ply"
  run "$m.octree-cluster" octree build "$in" -o "$m.octree-cluster.ply" --mode cluster --grid 64
done
run cube.morph morph build "$data/morph-animated-morph-cube/AnimatedMorphCube.gltf" -o cube.lfmorph --strips cube.lfmstrips
run cube.morph-info morph info cube.lfmorph
run cube.morph-extract morph extract cube.lfmorph --t 0.3 --lod 0.5 -o cube.morph-extract.ply
run cube.morph-strips-extract morph extract cube.lfmstrips --t 0.3 --lod 0.5 -o cube.morph-strips-extract.ply
mkdir -p horse; for f in 0001 0002 0003 0004; do ln -sf "$data/seq-horse-gallop/$f.obj" horse/; done
run horse.morph morph build horse -o horse.lfmorph --levels 0.5,0.1
run horse.morph-extract morph extract horse.lfmorph --t 0.5 --lod 0.3 -o horse.morph-extract.ply

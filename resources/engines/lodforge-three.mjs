// LodForge packs in three.js: every level of a pack in a THREE.LOD, switching at the pack's screen
// coverage.
//
// three.js's GLTFLoader ignores MSFT_lod and shows level 0 at every distance. This module loads each
// level node the pack lists (GLTFLoader's parser.getDependency) and puts the levels in a THREE.LOD
// whose distances are recomputed from the rendering camera, so the switch points are the pack's
// MSFT_screencoverage thresholds: the projected bounding sphere's area over the screen area, as
// Babylon.js measures it (docs/pack.md, "Screen coverage").
//
// Contract:
//   const gltf = await new GLTFLoader().loadAsync(url);
//   const packs = await createLodForgeLods(THREE, gltf);
//   - THREE: the three.js namespace (`import * as THREE from "three"`); tested with three 0.187.
//   - Replaces, in gltf.scene, every object whose glTF node carries MSFT_lod by a THREE.LOD (placed at
//     the level-0 bounding-box centre, so three's camera distance is the distance to the sphere's
//     centre) holding every level. Resolves to one entry per such node: { lod, levels: [Object3D, ...]
//     (level 0 first), coverage: [c0, c1, ...] }.
//   - Perspective cameras only: the distances follow the camera's fov, aspect and zoom at each
//     render (LOD.update), so resizing needs no call. Level k is drawn while the coverage is at most
//     c[k-1] and above c[k].
//   - Rejects with an Error when no node carries MSFT_lod.

const LOD = 'MSFT_lod';

// Bounding box of an object's meshes in the object's own frame.
function localBox(THREE, object) {
  object.updateWorldMatrix(true, true);
  const inverse = object.matrixWorld.clone().invert();
  const box = new THREE.Box3();
  const toLocal = new THREE.Matrix4();
  object.traverse((o) => {
    if (!o.isMesh) return;
    if (!o.geometry.boundingBox) o.geometry.computeBoundingBox();
    box.union(o.geometry.boundingBox.clone().applyMatrix4(toLocal.multiplyMatrices(inverse, o.matrixWorld)));
  });
  return box;
}

// Camera distance at which the sphere of radius r covers `coverage` of the screen:
// coverage = pi r^2 / (4 d^2 tan^2(fov/2) aspect).
function switchDistance(radius, coverage, camera) {
  if (!(coverage > 0)) return Infinity;
  const t = Math.tan((camera.fov * Math.PI) / 360);
  return (radius / (2 * t)) * Math.sqrt(Math.PI / (coverage * camera.aspect));
}

export async function createLodForgeLods(THREE, gltf) {
  const parser = gltf.parser;
  const json = parser.json;
  const objects = new Map();  // glTF node index -> its Object3D in gltf.scene
  gltf.scene.traverse((o) => {
    const a = parser.associations.get(o);
    if (a && a.nodes !== undefined) objects.set(a.nodes, o);
  });
  const packs = [];
  for (const [index, base] of objects) {
    const node = json.nodes[index];
    if (!node.extensions || !node.extensions[LOD]) continue;
    const coverage = (node.extras && node.extras.MSFT_screencoverage) || [];
    const others = await Promise.all((node.extensions[LOD].ids || []).map((id) => parser.getDependency('node', id)));
    const levels = [base, ...others];

    const box = localBox(THREE, base);
    const centre = box.getCenter(new THREE.Vector3()).applyMatrix4(base.matrix);
    const radius = (box.getSize(new THREE.Vector3()).length() / 2) * base.matrix.getMaxScaleOnAxis();  // parent frame
    const lod = new THREE.LOD();
    lod.name = `${base.name}_LODs`;
    lod.position.copy(centre);
    base.parent.add(lod);
    levels.forEach((level) => {
      level.position.sub(centre);  // the levels share level 0's frame (the pack writes them so)
      lod.addLevel(level, 0);
    });
    let key = '';
    const update = lod.update.bind(lod);
    lod.update = (camera) => {
      const scale = lod.parent ? lod.parent.matrixWorld.getMaxScaleOnAxis() : 1;
      const next = `${camera.fov}/${camera.aspect}/${scale}`;
      if (next !== key) {
        key = next;
        // Level k+1 takes over where the coverage falls below c[k]; three sorts by distance.
        for (let k = 1; k < levels.length; ++k) lod.levels[k].distance = switchDistance(radius * scale, coverage[k - 1], camera);
      }
      update(camera);
    };
    packs.push({ lod, levels, coverage });
  }
  if (packs.length === 0) throw new Error('no node carries MSFT_lod (is this a LodForge pack?)');
  return packs;
}

// LodForge packs in Babylon.js: every level of a pack, switching at the pack's screen coverage.
//
// Babylon's stock glTF loader treats MSFT_lod as progressive loading only: it loads every level,
// keeps level 0 and never reads MSFT_screencoverage (docs/engines.md). This module loads the
// pack with MSFT_lod off, puts every level node into the scene, and gives each LOD group one Babylon
// LOD chain (`useLODScreenCoverage`, `addLODLevel`), so Babylon itself picks the level per frame from
// the projected bounding sphere, the measure the pack's thresholds are made for.
//
// Contract:
//   const packs = await loadLodForgePack(BABYLON, scene, url);
//   - BABYLON: the Babylon namespace (the `babylonjs` UMD global or `import * as BABYLON from
//     "@babylonjs/core"` with the glTF loader registered) that has the module-level ImportMeshAsync
//     with pluginOptions (Babylon.js 7.x and later). Tested with 9.28.
//   - Resolves to one entry per node that carries MSFT_lod: { levels: [Mesh, ...] (level 0 first),
//     coverage: [c0, c1, ...] (the pack's MSFT_screencoverage), result } where `result` is Babylon's
//     ImportMeshAsync result. levels[0] is the mesh to move, hide or dispose: Babylon draws a LOD level
//     with its master's world matrix, so the other levels follow it.
//   - Level k is drawn while the coverage is at most c[k-1] and above c[k] (level 0 from 1, the last
//     down to 0); a level with an empty range is disabled. A level whose glTF mesh has several
//     primitives (materials) becomes one mesh with a MultiMaterial: a Babylon LOD level is one mesh.
//   - Rejects with an Error naming the URL when the file has no MSFT_lod node.

const LOD = 'MSFT_lod';

function lodNodes(json) {
  const out = [];
  (json.nodes || []).forEach((node, index) => {
    if (node.extensions && node.extensions[LOD]) out.push(index);
  });
  return out;
}

// Puts the level nodes of every LOD group beside their level 0 (same parent, or the same scene roots)
// and tags each level in extras, which Babylon copies to metadata.gltf.extras.
function exposeLevels(json) {
  const parents = new Map();
  (json.nodes || []).forEach((node, index) => (node.children || []).forEach((c) => parents.set(c, index)));
  for (const index of lodNodes(json)) {
    const node = json.nodes[index];
    const ids = node.extensions[LOD].ids || [];
    const coverage = (node.extras && node.extras.MSFT_screencoverage) || [];
    const levels = [index, ...ids];
    levels.forEach((id, level) => {
      const n = json.nodes[id];
      n.extras = Object.assign({}, n.extras, { lodforge: { group: index, level, coverage } });
    });
    const parent = parents.get(index);
    if (parent !== undefined) {
      json.nodes[parent].children.push(...ids);
    } else {
      for (const scene of json.scenes || []) if ((scene.nodes || []).includes(index)) scene.nodes.push(...ids);
    }
    delete node.extensions[LOD];
  }
}

// One mesh per level: the node itself, or its primitives merged (materials kept as submeshes).
function levelMesh(BABYLON, node) {
  if (node instanceof BABYLON.Mesh && node.getTotalVertices() > 0) return node;
  const parts = node.getChildMeshes(true).filter((m) => m instanceof BABYLON.Mesh);
  if (parts.length === 1) return parts[0];
  // Merge in the node's own frame: detached, the node's (identity) transform is the world.
  const parent = node.parent;
  node.parent = null;
  node.computeWorldMatrix(true);
  parts.forEach((m) => m.computeWorldMatrix(true));
  const merged = BABYLON.Mesh.MergeMeshes(parts, true, true, undefined, false, true);
  node.parent = parent;
  merged.name = node.name;
  merged.parent = node;
  merged.metadata = node.metadata;
  return merged;
}

export async function loadLodForgePack(BABYLON, scene, url) {
  let groups = 0;
  const result = await BABYLON.ImportMeshAsync(url, scene, {
    pluginOptions: {
      gltf: {
        extensionOptions: { [LOD]: { enabled: false } },
        onParsed: (data) => {
          groups = lodNodes(data.json).length;
          exposeLevels(data.json);
        },
      },
    },
  });
  if (groups === 0) throw new Error(`${url}: no node carries MSFT_lod (is this a LodForge pack?)`);
  const byGroup = new Map();
  for (const node of [...result.transformNodes, ...result.meshes]) {
    const tag = node.metadata && node.metadata.gltf && node.metadata.gltf.extras && node.metadata.gltf.extras.lodforge;
    if (!tag) continue;
    if (!byGroup.has(tag.group)) byGroup.set(tag.group, { nodes: [], coverage: tag.coverage });
    byGroup.get(tag.group).nodes[tag.level] = node;
  }
  const packs = [];
  for (const { nodes, coverage } of byGroup.values()) {
    const levels = nodes.map((n) => levelMesh(BABYLON, n));
    const base = levels[0];
    base.useLODScreenCoverage = true;
    // Level k+1 takes over below c[k]; the coarsest (c = 0) is never culled. A level with an empty
    // range (c[k+1] = c[k]) is left out: Babylon would pick the first of equal thresholds.
    const last = levels.length - 1;
    for (let k = 0; k < last; ++k) {
      if (k + 1 < last && !(coverage[k + 1] < coverage[k])) levels[k + 1].setEnabled(false);
      else base.addLODLevel(coverage[k], levels[k + 1]);
    }
    packs.push({ levels, coverage, result });
  }
  return packs;
}

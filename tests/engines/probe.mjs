// Runs in the page (page.html): loads a pack with LodForge's runtime for Babylon.js or three.js and
// answers the test's probes. Every draw call of a frame is recorded from the WebGL context itself, so
// the test sees what the engine drew, not what it says is active.
// ?engine=babylon|three, or babylon-stock|three-stock: the engine's own glTF loader without the runtime.
const engineName = new URLSearchParams(location.search).get('engine');
const stock = engineName.endsWith('-stock');
const canvas = document.getElementById('view');
const background = [0.2, 0.2, 0.25];

// Draw-call recorder: index or vertex count per call, while `recording` is set.
const draws = [];
let recording = false;
for (const proto of [WebGLRenderingContext.prototype, WebGL2RenderingContext.prototype]) {
  for (const name of ['drawElements', 'drawArrays', 'drawElementsInstanced', 'drawArraysInstanced']) {
    const original = proto[name];
    if (!original) continue;
    proto[name] = function (mode, ...rest) {
      if (recording) draws.push({ mode, count: name.startsWith('drawElements') ? rest[0] : rest[1] });
      return original.call(this, mode, ...rest);
    };
  }
}

function readPixels(gl) {
  const px = new Uint8Array(canvas.width * canvas.height * 4);
  gl.readPixels(0, 0, canvas.width, canvas.height, gl.RGBA, gl.UNSIGNED_BYTE, px);
  return Array.from(px);
}

async function babylon(packUrl) {
  await import('/babylon/babylon.js');
  await import('/babylon-loaders/babylonjs.loaders.js');
  const BABYLON = window.BABYLON;
  const { loadLodForgePack } = await import('/engines/lodforge-babylon.mjs');
  const engine = new BABYLON.Engine(canvas, false, { preserveDrawingBuffer: true, antialias: false });
  const scene = new BABYLON.Scene(engine);
  scene.clearColor = new BABYLON.Color4(...background, 1);
  scene.skipFrustumClipping = false;
  new BABYLON.HemisphericLight('sky', new BABYLON.Vector3(0.3, 1, 0.5), scene);
  const camera = new BABYLON.UniversalCamera('camera', new BABYLON.Vector3(0, 0, -10), scene);
  camera.fov = 0.8;
  let pack;
  if (stock) {
    // Babylon's own loader, MSFT_lod on: done once every level it loads progressively has come in.
    let complete = null;
    BABYLON.SceneLoader.OnPluginActivatedObservable.addOnce((loader) => { complete = loader.whenCompleteAsync(); });
    await BABYLON.ImportMeshAsync(packUrl, scene);
    await complete;
    pack = { levels: scene.meshes.filter((m) => m.getTotalVertices() > 0) };
  } else {
    [pack] = await loadLodForgePack(BABYLON, scene, packUrl);
  }
  const base = pack.levels[0];
  const sphere = () => base.getBoundingInfo().boundingSphere;
  await scene.whenReadyAsync();
  const gl = engine._gl;
  return {
    fov: camera.fov,
    aspect: engine.getAspectRatio(camera),
    // The test speaks glTF's frame; the loader's root maps glTF (x, y, z) to Babylon's (-x, y, z).
    centre() { base.computeWorldMatrix(true); const c = sphere().centerWorld; return [-c.x, c.y, c.z]; },
    place(eye, target, near, far) {
      camera.position.set(-eye[0], eye[1], eye[2]);
      camera.setTarget(new BABYLON.Vector3(-target[0], target[1], target[2]));
      camera.minZ = near; camera.maxZ = far;
    },
    async frame() { scene.render(); await scene.whenReadyAsync(); },
    render() { scene.render(); },
    pixels: () => readPixels(gl),
    force(k) {
      for (const l of base.getLODLevels().slice()) base.removeLODLevel(l.mesh);
      pack.levels.forEach((m, i) => { m.setEnabled(true); m.isVisible = i === k; });
    },
    untextured() {
      for (const m of scene.materials) { m.albedoTexture = null; m.diffuseTexture = null; m.emissiveTexture = null; }
    },
  };
}

async function three(packUrl) {
  const THREE = await import('three');
  const { GLTFLoader } = await import('three/addons/loaders/GLTFLoader.js');
  const { createLodForgeLods } = await import('/engines/lodforge-three.mjs');
  const renderer = new THREE.WebGLRenderer({ canvas, antialias: false, preserveDrawingBuffer: true });
  renderer.setClearColor(new THREE.Color().setRGB(...background, THREE.SRGBColorSpace), 1);
  const scene = new THREE.Scene();
  scene.add(new THREE.HemisphereLight(0xffffff, 0x444444, 2.5));
  const sun = new THREE.DirectionalLight(0xffffff, 1.5);
  sun.position.set(0.3, 1, 0.5);
  scene.add(sun);
  const camera = new THREE.PerspectiveCamera(0.8 * 180 / Math.PI, canvas.width / canvas.height, 0.01, 1000);
  const gltf = await new GLTFLoader().loadAsync(packUrl);
  scene.add(gltf.scene);
  // The stock loader alone: level 0 in a stand-in for the LOD (nothing switches).
  const [pack] = stock ? [{ lod: gltf.scene.children[0], levels: [gltf.scene.children[0]] }] : await createLodForgeLods(THREE, gltf);
  const gl = renderer.getContext();
  return {
    fov: 0.8,
    aspect: camera.aspect,
    centre() { scene.updateMatrixWorld(true); return pack.lod.getWorldPosition(new THREE.Vector3()).toArray(); },
    place(eye, target, near, far) {
      camera.position.fromArray(eye); camera.lookAt(new THREE.Vector3().fromArray(target));
      camera.near = near; camera.far = far; camera.updateProjectionMatrix();
    },
    async frame() { renderer.render(scene, camera); },
    render() { renderer.render(scene, camera); },
    pixels: () => readPixels(gl),
    // The THREE.LOD's level distances for a camera with this field of view (degrees) and aspect.
    lodDistances(fovDeg, aspect) {
      const saved = [camera.fov, camera.aspect];
      [camera.fov, camera.aspect] = [fovDeg, aspect];
      camera.updateProjectionMatrix();
      pack.lod.update(camera);
      const distances = pack.lod.levels.map((l) => l.distance);
      [camera.fov, camera.aspect] = saved;
      camera.updateProjectionMatrix();
      pack.lod.update(camera);
      return distances;
    },
    force(k) { pack.lod.autoUpdate = false; pack.levels.forEach((o, i) => { o.visible = i === k; }); },
    untextured() {
      scene.traverse((o) => { if (o.isMesh) { o.material.map = null; o.material.emissiveMap = null; o.material.needsUpdate = true; } });
    },
  };
}

let view = null;

// Places the camera on the view direction at `distance` from the sphere centre.
function look(distance) {
  const c = view.centre();
  const dir = [0.35, 0.25, 0.9];
  const n = Math.hypot(...dir);
  const eye = c.map((v, i) => v + (dir[i] / n) * distance);
  view.place(eye, c, distance * 0.01, distance * 10 + 1);
}

// Renders until two frames draw the same calls (shaders compile asynchronously) and returns the last one's.
async function drawnFrame() {
  let previous = '';
  for (let i = 0; i < 20; ++i) {
    await view.frame();
    draws.length = 0;
    recording = true;
    view.render();
    recording = false;
    const key = JSON.stringify(draws);
    if (key === previous && draws.length > 0) break;
    previous = key;
  }
  return draws.slice();
}

window.probe = {
  async load(packUrl) {
    view = engineName.startsWith('babylon') ? await babylon(packUrl) : await three(packUrl);
    return { fov: view.fov, aspect: view.aspect };
  },
  lodDistances: (fovDeg, aspect) => view.lodDistances(fovDeg, aspect),
  // The draw calls of a frame with the camera `distance` from the sphere centre.
  async drawsAt(distance) { look(distance); return drawnFrame(); },
  // Pixels of level k (forced) seen from `distance`; untextured: with the textures taken off.
  async imageOf(k, distance, untextured = false) {
    view.force(k);
    if (untextured) view.untextured();
    look(distance);
    const d = await drawnFrame();
    return { draws: d, pixels: view.pixels(), width: canvas.width, height: canvas.height };
  },
};
window.probeReady = true;

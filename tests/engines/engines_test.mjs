#!/usr/bin/env node
// Usage: node engines_test.mjs LODFORGE MESH WORK_DIR [ENGINE...]
//
// Makes a LodForge pack of MESH, serves it with the engine runtimes (resources/engines) from a loopback
// HTTP server, and loads it in headless Chromium in Babylon.js and three.js (or the ENGINEs named).
// For every level that has a coverage range it checks, from the WebGL draw calls of one frame, that the
// level drawn is the expected one: in the middle of the range and just either side of each threshold.
// Then it renders each level close up and checks that its textures show (the image differs from the
// same level untextured) and that it looks like level 0 within a tolerance. Exit 0 when all pass.
import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import http from 'node:http';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import puppeteer from 'puppeteer-core';

const here = path.dirname(fileURLToPath(import.meta.url));
const root = path.resolve(here, '../..');
const [lodforge, work, ...meshes] = process.argv.slice(2);
if (!lodforge || !work || meshes.length === 0) {
  console.error('usage: engines_test.mjs LODFORGE WORK_DIR MESH...');
  process.exit(2);
}
const engines = (process.env.LODFORGE_ENGINES || 'babylon,three').split(',');
const failures = [];
const check = (ok, what) => { console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}`); if (!ok) failures.push(what); };

// --- the packs ------------------------------------------------------------------------------------
// Triangles per primitive of each level, from the GLB's JSON chunk: what one frame of that level draws.
function primitiveTriangles(glbPath) {
  const b = fs.readFileSync(glbPath);
  const json = JSON.parse(b.subarray(20, 20 + b.readUInt32LE(12)).toString('utf8'));
  const base = json.nodes.findIndex((node) => node.extensions && node.extensions.MSFT_lod);
  const ids = [base, ...json.nodes[base].extensions.MSFT_lod.ids];
  return ids.map((id) => json.meshes[json.nodes[id].mesh].primitives.map((p) => json.accessors[p.indices].count / 3).sort((x, y) => x - y));
}

function makePack(mesh) {
  const name = path.basename(mesh).replace(/\.[^.]*$/, '');
  const dir = path.join(work, name);
  fs.rmSync(dir, { recursive: true, force: true });
  execFileSync(lodforge, ['pack', mesh, '-o', dir, '--levels', '0.3,0.05'], { stdio: ['ignore', 'inherit', 'inherit'] });
  const manifest = JSON.parse(fs.readFileSync(path.join(dir, 'pack.json'), 'utf8'));
  const coverage = manifest.levels.map((l) => l.screen_coverage);
  const n = coverage.length;
  // Levels an engine can show: a non-empty coverage range (level k from c[k-1] down to c[k]).
  const shown = [...Array(n).keys()].filter((k) => k === 0 || (k === n - 1 ? coverage[k - 1] > 0 : coverage[k] < coverage[k - 1]));
  const probes = [];  // [coverage, level expected, why]
  shown.forEach((k, i) => {
    const hi = k === 0 ? Math.max(2 * coverage[0], 1) : coverage[k - 1];
    const lo = k === n - 1 ? hi / 25 : coverage[k];
    probes.push([Math.sqrt(hi * lo), k, `inside level ${k}'s range`]);
    if (i + 1 < shown.length) {
      const t = coverage[shown[i + 1] - 1];
      probes.push([t * 1.03, k, `3 % above threshold ${t.toPrecision(4)}`]);
      probes.push([t / 1.03, shown[i + 1], `3 % below threshold ${t.toPrecision(4)}`]);
    }
  });
  return { file: path.basename(mesh), url: `/pack/${name}/${manifest.glb}`, manifest, coverage, shown, probes,
           radius: manifest.source.diagonal / 2, expected: primitiveTriangles(path.join(dir, manifest.glb)) };
}
const packs = meshes.map(makePack);

// --- a loopback server: the page, the runtimes, the engines, the pack -----------------------------
const mounts = {
  '/test/': here,
  '/engines/': path.join(root, 'resources/engines'),
  '/babylon/': path.join(here, 'node_modules/babylonjs'),
  '/babylon-loaders/': path.join(here, 'node_modules/babylonjs-loaders'),
  '/three/': path.join(here, 'node_modules/three'),
  '/pack/': work,
};
const types = { '.html': 'text/html', '.js': 'text/javascript', '.mjs': 'text/javascript', '.glb': 'model/gltf-binary', '.json': 'application/json' };
const server = http.createServer((req, res) => {
  const url = decodeURIComponent(new URL(req.url, 'http://x').pathname);
  const mount = Object.keys(mounts).find((m) => url.startsWith(m));
  const file = mount && path.join(mounts[mount], url.slice(mount.length));
  if (!file || !file.startsWith(mounts[mount]) || !fs.existsSync(file) || !fs.statSync(file).isFile()) {
    res.writeHead(404).end();
    return;
  }
  res.writeHead(200, { 'Content-Type': types[path.extname(file)] || 'application/octet-stream' });
  fs.createReadStream(file).pipe(res);
});
await new Promise((resolve) => server.listen(0, '127.0.0.1', resolve));
const origin = `http://127.0.0.1:${server.address().port}`;

// --- image measures ------------------------------------------------------------------------------
const BG = [51, 51, 64];
function covered(img) {
  const m = new Uint8Array(img.width * img.height);
  for (let i = 0; i < m.length; ++i) m[i] = [0, 1, 2].some((c) => Math.abs(img.pixels[4 * i + c] - BG[c]) > 6) ? 1 : 0;
  return m;
}
// Mean |difference| (0-255, channels averaged) over the pixels either image covers, and the fraction
// of those covered by one only.
function difference(a, b) {
  const ca = covered(a), cb = covered(b);
  let sum = 0, count = 0, silhouette = 0;
  for (let i = 0; i < ca.length; ++i) {
    if (!ca[i] && !cb[i]) continue;
    ++count;
    if (ca[i] !== cb[i]) ++silhouette;
    for (let c = 0; c < 3; ++c) sum += Math.abs(a.pixels[4 * i + c] - b.pixels[4 * i + c]) / 3;
  }
  return { mean_abs: count ? sum / count : 0, silhouette: count ? silhouette / count : 0, covered: count / ca.length };
}
const triangles = (draws) => draws.filter((d) => d.mode === 4).map((d) => d.count / 3).sort((x, y) => x - y);
const same = (a, b) => a.length === b.length && a.every((v, i) => v === b[i]);

// --- the engines ------------------------------------------------------------------------------------
const browser = await puppeteer.launch({
  executablePath: process.env.LODFORGE_CHROMIUM || '/usr/bin/chromium',
  headless: true,
  protocolTimeout: 60000,
  args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist', '--disable-dev-shm-usage'],
});
// A page with `engine` and the pack at `url` loaded; distance(a): the camera distance at which the
// bounding sphere (radius r) covers `a` of the screen (Babylon's measure).
async function open(engine, url, r) {
  const page = await browser.newPage();
  page.on('pageerror', (e) => console.log(`${engine} page error: ${e.message}`));
  await page.goto(`${origin}/test/page.html?engine=${engine}`);
  await page.waitForFunction('window.probeReady === true', { timeout: 30000 });
  const { fov, aspect } = await page.evaluate((u) => window.probe.load(u), origin + url);
  return { page, distance: (a) => (r / (2 * Math.tan(fov / 2))) * Math.sqrt(Math.PI / (a * aspect)) };
}

try {
  for (const { file, url, manifest, coverage, shown, probes, radius, expected } of packs) for (const engine of engines) {
    const { page, distance } = await open(engine, url, radius);
    const name = `${engine} ${file}`;
    for (const [a, k, why] of probes) {
      const drawn = triangles(await page.evaluate((d) => window.probe.drawsAt(d), distance(a)));
      check(same(drawn, expected[k]), `${name}: coverage ${a.toPrecision(4)} (${why}) draws level ${k} [${expected[k]}] — drew [${drawn}]`);
    }
    if (engine === 'three') {
      // The runtime's distances for the pack's switch screen and field of view are pack.json's Godot
      // visibility ranges: the same switch points, computed apart (lodforge-three.mjs, switch_points.cpp).
      const sw = manifest.switch;
      const got = await page.evaluate((f, a) => window.probe.lodDistances(f, a), sw.fov_deg, sw.screen[0] / sw.screen[1]);
      for (let k = 1; k < got.length; ++k) {
        const want = manifest.levels[k].switch.godot.visibility_range_begin;
        check(Math.abs(got[k] - want) <= 1e-5 * want,
              `${name}: three.js switches to level ${k} at distance ${got[k].toPrecision(6)}, pack.json's Godot visibility_range_begin ${want.toPrecision(6)}`);
      }
    }
    // Close-ups, one level at a time (forced), the object covering about a third of the view.
    const close = distance(0.35);
    for (const k of shown) {
      const img = await page.evaluate((kk, d) => window.probe.imageOf(kk, d), k, close);
      check(same(triangles(img.draws), expected[k]), `${name}: close-up of level ${k} draws it`);
      if (k === 0) {
        const bare = await page.evaluate((d) => window.probe.imageOf(0, d, true), close);
        const texture = difference(img, bare);
        check(texture.mean_abs > 10, `${name}: textures show (level 0 differs from itself untextured by ${texture.mean_abs.toFixed(1)} > 10)`);
      }
    }
    // Each level against level 0 at the size it takes over on the reference screen (pack.json's
    // screen_reference), where the pack promises about a pixel of error: the sphere's radius in pixels,
    // at most 40 (a level good at 200 pixels is good at 40). Below 6 pixels an image says nothing.
    // Allowed: a band of the level's error (at least a pixel) around the silhouette, half the colour
    // range inside it, plus 12 levels for shading and texture shift (UV error, which the Hausdorff
    // distance does not see: Spot's 5 % level differs by 17 where the band alone allows 10).
    const ref = manifest.screen_reference;
    for (const k of shown.slice(1)) {
      const rhoRef = Math.sqrt((coverage[k - 1] * ref.width * ref.height) / Math.PI);
      if (rhoRef < 6) { console.log(`note ${name}: level ${k} takes over at ${rhoRef.toFixed(1)} px, too small to compare`); continue; }
      const rho = Math.min(40, rhoRef);
      const band = Math.max(1, 2 * manifest.levels[k].error.hausdorff_relative * rho);
      const allowed = 12 + 128 * Math.min(1, (2 * band) / rho);
      const d = distance((Math.PI * rho * rho) / (128 * 128));
      const a = await page.evaluate((kk, dd) => window.probe.imageOf(kk, dd), 0, d);
      const b = await page.evaluate((kk, dd) => window.probe.imageOf(kk, dd), k, d);
      const diff = difference(a, b);
      check(diff.mean_abs <= allowed, `${name}: level ${k} looks like level 0 where it takes over (sphere radius ${rho.toFixed(1)} px: mean |diff| ${diff.mean_abs.toFixed(1)} <= ${allowed.toFixed(1)}, silhouette ${diff.silhouette.toFixed(3)})`);
    }
    await page.close();
  }
  // The stock loaders, without the runtimes, on the first pack: they draw level 0 where the coarsest
  // level belongs (docs/engines.md). This is what the draw-call check above must tell apart.
  const { file, url, coverage, shown, radius, expected } = packs[0];
  for (const engine of ['babylon-stock', 'three-stock']) {
    const { page, distance } = await open(engine, url, radius);
    const last = shown[shown.length - 1];
    const drawn = triangles(await page.evaluate((d) => window.probe.drawsAt(d), distance(coverage[last - 1] / 5)));
    check(same(drawn, expected[0]) && !same(drawn, expected[last]),
          `${engine} ${file}: the stock loader draws level 0 [${expected[0]}] where level ${last} [${expected[last]}] belongs — drew [${drawn}]`);
    await page.close();
  }
} finally {
  await browser.close();
  server.close();
}
console.log(failures.length ? `${failures.length} check(s) failed` : 'all checks passed');
process.exit(failures.length ? 1 : 0);

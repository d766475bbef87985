#!/usr/bin/env node
// Attribute fidelity benchmark (issue 26): LodForge's default `simplify` against gltfpack `-si R -sv` and
// meshoptimizer's JS `simplifyWithAttributes` on every textured or coloured mesh in ../shared/data plus
// generated variants, at 50 %, 20 % and 5 %. Every output is measured by the same `lodforge compare --json`
// against the same reference (the input converted to GLB by `lodforge convert`), at gltfpack's triangle
// count (LodForge and meshoptimizer are asked for exactly the triangles gltfpack produced).
//
//   node bench/fidelity_bench.mjs [--lodforge build/bin/lodforge] [--data ../shared/data] [--work DIR]
//        [--ratios 0.5,0.2,0.05] [--assets spot,duck,...] [--quick] [--markdown FILE] [--json FILE]
//        [--placement half-edge|optimal] [--packs]
//
// The comparators are pinned in bench/comparators/package-lock.json (packaging/install-deps.sh installs
// them). Columns: geometric max / mean (symmetric, relative to the diagonal), colour RMS (0-255), UV RMS,
// image-space error (`lodforge compare --render`, when the build has it), wall time of the simplifying
// command (LodForge also geometry-only, for the "attribute-aware time <= 2x geometry-only" rule).
// --placement is passed to LodForge's `simplify` runs (both of them); without it they use its default.
// --packs measures LOD packs instead: `lodforge pack --levels RATIOS --image-error` with each placement
// (optimal, half-edge), per level the image and mean error from pack.json, and the GLB's size.
import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const here = path.dirname(fileURLToPath(import.meta.url));
const root = path.resolve(here, '..');

function parseArgs(argv) {
	const a = {
		lodforge: path.join(root, 'build/bin/lodforge'),
		data: path.resolve(root, '../shared/data'),
		work: fs.mkdtempSync(path.join(os.tmpdir(), 'lodforge-fidelity-')),
		ratios: [0.5, 0.2, 0.05],
		assets: null,
		markdown: null,
		json: null,
		placement: null,
		packs: false,
	};
	for (let i = 2; i < argv.length; ++i) {
		const k = argv[i];
		const v = () => {
			if (i + 1 >= argv.length) usage(`${k} needs a value`);
			return argv[++i];
		};
		if (k === '--lodforge') a.lodforge = path.resolve(v());
		else if (k === '--data') a.data = path.resolve(v());
		else if (k === '--work') a.work = path.resolve(v());
		else if (k === '--ratios') a.ratios = v().split(',').map(Number);
		else if (k === '--assets') a.assets = v().split(',');
		else if (k === '--quick') {
			a.assets = a.assets ?? ['spot', 'duck'];
			a.ratios = [0.2];
		} else if (k === '--markdown') a.markdown = path.resolve(v());
		else if (k === '--json') a.json = path.resolve(v());
		else if (k === '--placement') a.placement = v();
		else if (k === '--packs') a.packs = true;
		else usage(`unknown option ${k}`);
	}
	if (a.ratios.some((r) => !(r > 0 && r < 1))) usage('--ratios: values in (0, 1)');
	if (a.placement !== null && !['half-edge', 'optimal'].includes(a.placement)) usage('--placement: half-edge or optimal');
	return a;
}

function usage(message) {
	console.error(`fidelity_bench: ${message}`);
	process.exit(2);
}

// ---------------------------------------------------------------------------------------------------
// Generated variants, from Spot (OBJ text) and written as OBJ or ASCII PLY.

function readObj(file) {
	const v = [], vt = [], faces = [];
	for (const line of fs.readFileSync(file, 'utf8').split('\n')) {
		const t = line.trim().split(/\s+/);
		if (t[0] === 'v') v.push(t.slice(1, 4).map(Number));
		else if (t[0] === 'vt') vt.push(t.slice(1, 3).map(Number));
		else if (t[0] === 'f') {
			const c = t.slice(1).map((s) => s.split('/').map((x) => Number(x) - 1));
			for (let k = 1; k + 1 < c.length; ++k) faces.push([c[0], c[k], c[k + 1]]);
		}
	}
	return { v, vt, faces };
}

// Deterministic noise (mulberry32), so every run generates the same variants.
function rng(seed) {
	return () => {
		seed |= 0;
		seed = (seed + 0x6d2b79f5) | 0;
		let t = Math.imul(seed ^ (seed >>> 15), 1 | seed);
		t = (t + Math.imul(t ^ (t >>> 7), 61 | t)) ^ t;
		return ((t ^ (t >>> 14)) >>> 0) / 4294967296;
	};
}

const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const norm = (a) => {
	const l = Math.hypot(a[0], a[1], a[2]) || 1;
	return [a[0] / l, a[1] / l, a[2] / l];
};

function faceNormal(m, f) {
	const p = f.map((c) => m.v[c[0]]);
	return cross(sub(p[1], p[0]), sub(p[2], p[0]));
}

function writeObj(file, v, vt, vn, faces /* [[[vi, ti, ni] x3]] */) {
	const out = [];
	for (const p of v) out.push(`v ${p[0]} ${p[1]} ${p[2]}`);
	for (const t of vt) out.push(`vt ${t[0]} ${t[1]}`);
	for (const n of vn) out.push(`vn ${n[0]} ${n[1]} ${n[2]}`);
	for (const f of faces) out.push('f ' + f.map((c) => c.map((x) => (x < 0 ? '' : x + 1)).join('/').replace(/\/$/, '')).join(' '));
	fs.writeFileSync(file, out.join('\n') + '\n');
}

function smoothNormals(m) {
	const n = m.v.map(() => [0, 0, 0]);
	for (const f of m.faces) {
		const fn = faceNormal(m, f);
		for (const c of f) for (let k = 0; k < 3; ++k) n[c[0]][k] += fn[k];
	}
	return n.map(norm);
}

function makeVariants(spotObj, dir) {
	const m = readObj(spotObj);
	const files = {};
	const plain = (name, v, vt = m.vt, vn = [], faces = m.faces.map((f) => f.map((c) => [c[0], c[1], -1]))) => {
		files[name] = path.join(dir, `${name}.obj`);
		writeObj(files[name], v, vt, vn, faces);
		// The texture beside it (found by name), so that the GLB has a textured material: gltfpack drops
		// texture coordinates no material uses, and with them the seams.
		fs.copyFileSync(path.join(path.dirname(spotObj), 'spot_texture.png'), path.join(dir, `${name}.png`));
	};
	plain('spot-x0.01', m.v.map((p) => p.map((x) => x * 0.01)));
	plain('spot-x100', m.v.map((p) => p.map((x) => x * 100)));
	// Noisy normals: the smooth normals turned by up to ~17 degrees at random.
	const r = rng(26);
	const noisy = smoothNormals(m).map((n) => norm(n.map((x) => x + 0.3 * (r() - 0.5))));
	plain('spot-noisy-normals', m.v, m.vt, noisy, m.faces.map((f) => f.map((c) => [c[0], c[1], c[0]])));
	// Flat shading: one normal per face, so every edge is a hard normal crease (split wedges).
	plain('spot-flat', m.v, m.vt, m.faces.map((f) => norm(faceNormal(m, f))), m.faces.map((f, i) => f.map((c) => [c[0], c[1], i])));
	// An atlas of many small charts: faces grouped by a 10^3 grid over their centroids, each group's UVs
	// moved to its own slot of a 4x4 atlas, so every group border is a UV seam.
	{
		const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
		for (const p of m.v) for (let k = 0; k < 3; ++k) (lo[k] = Math.min(lo[k], p[k])), (hi[k] = Math.max(hi[k], p[k]));
		const cell = (x, k) => Math.min(9, Math.floor((10 * (x - lo[k])) / (hi[k] - lo[k] || 1)));
		const vt = [], key = new Map(), faces = [];
		for (const f of m.faces) {
			const c = [0, 1, 2].map((k) => (m.v[f[0][0]][k] + m.v[f[1][0]][k] + m.v[f[2][0]][k]) / 3);
			const chart = cell(c[0], 0) + 10 * cell(c[1], 1) + 100 * cell(c[2], 2);
			const slot = [(chart % 4) * 0.25, (Math.floor(chart / 4) % 4) * 0.25];
			faces.push(f.map((cc) => {
				const k = `${chart}:${cc[1]}`;
				if (!key.has(k)) {
					key.set(k, vt.length);
					const t = m.vt[cc[1]];
					vt.push([slot[0] + 0.25 * t[0], slot[1] + 0.25 * t[1]]);
				}
				return [cc[0], key.get(k), -1];
			}));
		}
		plain('spot-atlas', m.v, vt, [], faces);
	}
	// Mirrored UVs: a planar projection along x, so both halves share the texture and the UV winding flips
	// where the surface turns through the projection direction (UV flips without seams).
	{
		const ys = m.v.map((p) => p[1]), zs = m.v.map((p) => p[2]);
		const [y0, y1, z0, z1] = [Math.min(...ys), Math.max(...ys), Math.min(...zs), Math.max(...zs)];
		const vt = m.v.map((p) => [(p[2] - z0) / (z1 - z0), (p[1] - y0) / (y1 - y0)]);
		plain('spot-mirrored', m.v, vt, [], m.faces.map((f) => f.map((c) => [c[0], c[0], -1])));
	}
	// RGBA vertex colours (smooth patterns, alpha varying), ASCII PLY.
	{
		const lines = [
			'ply', 'format ascii 1.0', `element vertex ${m.v.length}`, 'property float x', 'property float y', 'property float z',
			'property uchar red', 'property uchar green', 'property uchar blue', 'property uchar alpha',
			`element face ${m.faces.length}`, 'property list uchar int vertex_indices', 'end_header',
		];
		const b = (x) => Math.max(0, Math.min(255, Math.round(255 * (0.5 + 0.5 * x))));
		for (const p of m.v)
			lines.push(`${p[0]} ${p[1]} ${p[2]} ${b(Math.sin(7 * p[0]))} ${b(Math.sin(5 * p[1] + 1))} ${b(Math.cos(6 * p[2]))} ${b(Math.sin(4 * p[1] + 3 * p[2]))}`);
		for (const f of m.faces) lines.push(`3 ${f[0][0]} ${f[1][0]} ${f[2][0]}`);
		files['spot-rgba'] = path.join(dir, 'spot-rgba.ply');
		fs.writeFileSync(files['spot-rgba'], lines.join('\n') + '\n');
	}
	return files;
}

// ---------------------------------------------------------------------------------------------------
// meshoptimizer's JS simplifier on an ASCII PLY written by `lodforge convert --encoding ascii --float-colors`.

function readAsciiPly(file) {
	const text = fs.readFileSync(file, 'utf8');
	const end = text.indexOf('end_header\n');
	const header = text.slice(0, end).split('\n');
	const props = [];
	let nv = 0, nf = 0, el = '';
	for (const h of header) {
		const t = h.trim().split(/\s+/);
		if (t[0] === 'element') (el = t[1]), t[1] === 'vertex' ? (nv = +t[2]) : t[1] === 'face' ? (nf = +t[2]) : 0;
		else if (t[0] === 'property' && el === 'vertex') props.push(t[t.length - 1]);
	}
	const body = text.slice(end + 'end_header\n'.length).split('\n');
	const rows = body.slice(0, nv).map((l) => l.trim().split(/\s+/).map(Number));
	const indices = [];
	for (let i = 0; i < nf; ++i) {
		const t = body[nv + i].trim().split(/\s+/).map(Number);
		for (let k = 2; k < t[0]; ++k) indices.push(t[1], t[k], t[k + 1]);
	}
	return { header: header.join('\n'), props, rows, indices, headerLines: header };
}

async function meshoptSimplify(refPly, outPly, targetTriangles) {
	const { MeshoptSimplifier } = await import(path.join(here, 'comparators/node_modules/meshoptimizer/index.js'));
	await MeshoptSimplifier.ready;
	const ply = readAsciiPly(refPly);
	const col = (n) => ply.props.indexOf(n);
	const nv = ply.rows.length;
	const pos = new Float32Array(nv * 3);
	for (let i = 0; i < nv; ++i) for (let k = 0; k < 3; ++k) pos[3 * i + k] = ply.rows[i][col('xyz'[k])];
	// gltfpack's choice: normals 0.5, colours 1.0 (UV seams are kept by the topology, not weighted).
	const channels = [];
	for (const n of ['nx', 'ny', 'nz']) if (col(n) >= 0) channels.push([col(n), 0.5]);
	for (const n of ['red', 'green', 'blue', 'alpha']) if (col(n) >= 0) channels.push([col(n), 1.0]);
	const stride = Math.max(1, channels.length);
	const attrs = new Float32Array(nv * stride);
	for (let i = 0; i < nv; ++i) channels.forEach(([c], k) => (attrs[i * stride + k] = ply.rows[i][c]));
	const weights = channels.length ? channels.map(([, w]) => w) : [0];
	const indices = new Uint32Array(ply.indices);
	const t0 = process.hrtime.bigint();
	const [out] = MeshoptSimplifier.simplifyWithAttributes(indices, pos, 3, attrs, stride, weights, null, 3 * targetTriangles, 1.0);
	const seconds = Number(process.hrtime.bigint() - t0) / 1e9;
	// Compact: only the vertices the faces use, in the input's header layout.
	const remap = new Map(), rows = [];
	for (const i of out) if (!remap.has(i)) remap.set(i, rows.length), rows.push(ply.rows[i]);
	const lines = ply.headerLines.map((l) => l.replace(/^element vertex \d+/, `element vertex ${rows.length}`).replace(/^element face \d+/, `element face ${out.length / 3}`));
	lines.push('end_header');
	for (const r of rows) lines.push(r.join(' '));
	for (let i = 0; i < out.length; i += 3) lines.push(`3 ${remap.get(out[i])} ${remap.get(out[i + 1])} ${remap.get(out[i + 2])}`);
	fs.writeFileSync(outPly, lines.join('\n') + '\n');
	return seconds;
}

// ---------------------------------------------------------------------------------------------------

function run(cmd, args) {
	const t0 = process.hrtime.bigint();
	const stdout = execFileSync(cmd, args, { encoding: 'utf8', stdio: ['ignore', 'pipe', 'pipe'], maxBuffer: 1 << 26 });
	return { stdout, seconds: Number(process.hrtime.bigint() - t0) / 1e9 };
}

function main() {
	const a = parseArgs(process.argv);
	const lf = (...args) => run(a.lodforge, args);
	const gltfpack = path.join(here, 'comparators/node_modules/gltfpack/cli.js');
	if (!a.packs && !fs.existsSync(gltfpack)) usage('gltfpack missing: run packaging/install-deps.sh (npm ci in bench/comparators)');
	const renders = lf('compare', '--help').stdout.includes('--render');
	fs.mkdirSync(a.work, { recursive: true });
	const d = (p) => path.join(a.data, p);
	const sources = {
		spot: d('tex-spot/spot_triangulated.obj'),
		duck: d('tex-duck/glTF_Binary/Duck.glb'),
		'milk-truck': d('tex-cesium-milk-truck/CesiumMilkTruck.gltf'),
		'water-bottle': d('tex-water-bottle/WaterBottle.gltf'),
		laurana500: d('tex-ply-wedge-uv/laurana500.ply'),
		matteonormb: d('tex-ply-wedge-uv/matteonormb.ply'),
		frag_115: d('color-open3d-frag115/frag_115.ply'),
		color: d('color-open3d-small/color.ply'),
		...makeVariants(d('tex-spot/spot_triangulated.obj'), a.work),
	};
	const names = a.assets ?? Object.keys(sources);
	for (const n of names) if (!sources[n]) usage(`unknown asset ${n} (known: ${Object.keys(sources).join(', ')})`);

	const measure = (ref, test) => {
		const args = ['compare', ref, test, '--json'];
		if (renders) args.push('--render');
		const j = JSON.parse(lf(...args).stdout);
		const image = j.image ? j.image.mean_abs : null;
		return { max: j.hausdorff_relative, mean: j.mean_relative, color: j.color_rms ?? null, uv: j.texcoord_rms ?? null, image, triangles: j.triangles.test };
	};

	if (a.packs) return packs(a, lf, sources, names, renders);

	const cells = [];
	for (const name of names) {
		const ref = path.join(a.work, `${name}.glb`);
		lf('convert', sources[name], ref);
		const refPly = path.join(a.work, `${name}.ref.ply`);
		lf('convert', ref, refPly, '--encoding', 'ascii', '--float-colors');
		for (const ratio of a.ratios) {
			const tag = `${name}-${ratio}`;
			const gp = path.join(a.work, `${tag}.gltfpack.glb`);
			// gltfpack as an artist runs it (its default error limit), unquantized so that only the
			// simplification is measured. Where it stops above the ratio, the others get its count too.
			const gpRun = run('node', [gltfpack, '-i', ref, '-o', gp, '-si', String(ratio), '-sv', '-noq']);
			let gpM;
			try {
				gpM = measure(ref, gp);
			} catch (err) {
				console.error(`${tag}: gltfpack's output is not measurable (${err.stderr?.trim() ?? err.message}); cell skipped`);
				continue;
			}
			const target = gpM.triangles;
			const lfOut = path.join(a.work, `${tag}.lodforge.glb`);
			const placement = a.placement ? ['--placement', a.placement] : [];
			const lfRun = lf('simplify', ref, '-o', lfOut, '--triangles', String(target), ...placement);
			const lfM = measure(ref, lfOut);
			const geoOut = path.join(a.work, `${tag}.geometry.glb`);
			const geoRun = lf('simplify', ref, '-o', geoOut, '--triangles', String(target), '--weights', 'normal=0,color=0,uv=0', ...placement);
			const geoM = measure(ref, geoOut);
			const moOut = path.join(a.work, `${tag}.meshopt.ply`);
			const moSeconds = meshoptSeconds(refPly, moOut, target);
			const moM = moSeconds === null ? null : measure(ref, moOut);
			cells.push({ asset: name, ratio, target, gltfpack: { ...gpM, seconds: gpRun.seconds }, lodforge: { ...lfM, seconds: lfRun.seconds },
				geometry: { ...geoM, seconds: geoRun.seconds }, meshopt: moM && { ...moM, seconds: moSeconds } });
			console.error(`${tag}: ${target} triangles; mean gltfpack ${gpM.mean.toExponential(2)}, lodforge ${lfM.mean.toExponential(2)}`);
		}
	}
	const md = (a.placement ? `LodForge placement: ${a.placement}\n\n` : '') + table(cells, renders);
	console.log(md);
	if (a.markdown) fs.writeFileSync(a.markdown, md + '\n');
	if (a.json) fs.writeFileSync(a.json, JSON.stringify(cells, null, 1) + '\n');
}

// One pack per placement over the same levels (a chain: each level from the previous one), every level's
// image error rendered by `pack --image-error` (the same measure as `compare --render`).
function packs(a, lf, sources, names, renders) {
	if (!renders) usage('--packs needs a build with the renderer (pack --image-error)');
	const levels = [...a.ratios].sort((x, y) => y - x).join(',');
	const placements = ['optimal', 'half-edge'];
	const rows = [
		'| asset | level | triangles | image: optimal / half-edge | mean: optimal / half-edge | max: optimal / half-edge |',
		'|---|---|---|---|---|---|',
	];
	const sizes = [];
	let wins = 0, count = 0;
	for (const name of names) {
		const ref = path.join(a.work, `${name}.glb`);
		lf('convert', sources[name], ref);
		const result = {};
		for (const p of placements) {
			const dir = path.join(a.work, `${name}.pack.${p}`);
			fs.rmSync(dir, { recursive: true, force: true });
			lf('-q', 'pack', ref, '-o', dir, '--levels', levels, '--placement', p, '--image-error');
			const j = JSON.parse(fs.readFileSync(path.join(dir, 'pack.json'), 'utf8'));
			result[p] = { levels: j.levels, bytes: fs.statSync(path.join(dir, j.glb)).size };
		}
		const [O, H] = placements.map((p) => result[p]);
		for (let k = 1; k < O.levels.length && k < H.levels.length; ++k) {
			const o = O.levels[k], h = H.levels[k];
			count += 1;
			wins += o.image_error.mean_abs <= h.image_error.mean_abs;
			rows.push(`| ${name} | ${k} | ${o.triangles} / ${h.triangles} | ${f(o.image_error.mean_abs, 3)} / ${f(h.image_error.mean_abs, 3)} | ` +
				`${e(o.error.mean_relative)} / ${e(h.error.mean_relative)} | ${e(o.error.hausdorff_relative)} / ${e(h.error.hausdorff_relative)} |`);
		}
		sizes.push(`${name} ${(O.bytes / 1024).toFixed(1)} / ${(H.bytes / 1024).toFixed(1)} KiB (+${((O.bytes / H.bytes - 1) * 100).toFixed(0)} %)`);
		console.error(`${name}: packs written`);
	}
	rows.push('');
	rows.push(`Levels ${levels}. Optimal image error <= half-edge in ${wins} of ${count} levels. ` +
		`GLB size, optimal / half-edge: ${sizes.join('; ')}.`);
	const md = rows.join('\n');
	console.log(md);
	if (a.markdown) fs.writeFileSync(a.markdown, md + '\n');
}

// The meshoptimizer module is an ES module with top-level await of its wasm; run it in a child so the
// main loop stays synchronous.
function meshoptSeconds(refPly, outPly, target) {
	try {
		const r = run('node', [fileURLToPath(import.meta.url), '--meshopt-child', refPly, outPly, String(target)]);
		return Number(r.stdout.trim());
	} catch (e) {
		console.error(`meshoptimizer: ${e.message.split('\n')[0]}`);
		return null;
	}
}

const e = (x) => (x === null || x === undefined ? '—' : x.toExponential(2));
const f = (x, digits = 2) => (x === null || x === undefined ? '—' : x.toFixed(digits));

function table(cells, renders) {
	const rows = [
		'| asset | ratio | triangles | max: LodForge / gltfpack / meshopt | mean: LodForge / gltfpack / meshopt | colour RMS: LodForge / gltfpack / meshopt | UV RMS: LodForge / gltfpack / meshopt | image: LodForge / gltfpack | time s: LodForge / geometry-only / gltfpack / meshopt |',
		'|---|---|---|---|---|---|---|---|---|',
	];
	let meanWins = 0, maxWins = 0, colorWins = 0, colorCells = 0, imageWins = 0, imageCells = 0, worstImage = 0;
	for (const c of cells) {
		const L = c.lodforge, G = c.gltfpack, M = c.meshopt ?? {};
		meanWins += L.mean <= G.mean;
		maxWins += L.max <= G.max;
		if (L.color !== null && M.color !== undefined && M.color !== null) (colorCells += 1), (colorWins += L.color <= M.color);
		if (L.image !== null && G.image !== null) {
			imageCells += 1;
			imageWins += L.image <= G.image;
			// Both near zero (a level that looks like the original) is not a loss, whatever the ratio.
			if (G.image > 0.05) worstImage = Math.max(worstImage, L.image / G.image);
		}
		rows.push(`| ${c.asset} | ${c.ratio * 100} % | ${c.target} | ${e(L.max)} / ${e(G.max)} / ${e(M.max)} | ${e(L.mean)} / ${e(G.mean)} / ${e(M.mean)} | ` +
			`${f(L.color)} / ${f(G.color)} / ${f(M.color)} | ${e(L.uv)} / ${e(G.uv)} / ${e(M.uv)} | ${renders ? `${f(L.image, 3)} / ${f(G.image, 3)}` : '—'} | ` +
			`${f(L.seconds, 3)} / ${f(c.geometry.seconds, 3)} / ${f(G.seconds, 3)} / ${f(M.seconds, 3)} |`);
	}
	rows.push('');
	rows.push(`LodForge mean <= gltfpack in ${meanWins} of ${cells.length} cells, max <= gltfpack in ${maxWins}; ` +
		`colour RMS <= meshoptimizer in ${colorWins} of ${colorCells} coloured cells.` +
		(imageCells ? ` Image error <= gltfpack in ${imageWins} of ${imageCells} cells, at most ${worstImage.toFixed(2)}x it.` : ''));
	return rows.join('\n');
}

if (process.argv[2] === '--meshopt-child') {
	const seconds = await meshoptSimplify(process.argv[3], process.argv[4], Number(process.argv[5]));
	console.log(seconds);
} else {
	main();
}

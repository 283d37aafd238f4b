// Browser tests of `terramesh view` in headless Debian chromium (docs/viewer.md). Run by ctest
// (tests/viewer/CMakeLists.txt) with TERRAMESH_BIN, TERRAMESH_SOURCE_DIR and
// TERRAMESH_VIEWER_TEST_MODULES set.
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { mkdtempSync, readFileSync, writeFileSync, symlinkSync } from 'node:fs';
import { request } from 'node:http';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { pathToFileURL } from 'node:url';
import { after, before, test } from 'node:test';
import { endSession, settle, startSession } from './harness.mjs';
import { countColour, decodePng, fractionChanged, fractionNot } from './png.mjs';

const BIN = process.env.TERRAMESH_BIN;
const SOURCE = process.env.TERRAMESH_SOURCE_DIR;
const BACKGROUND = [0x1e, 0x22, 0x28];
const PATH_RGB = [0x00, 0xe5, 0xff];
const TRAJECTORY_RGB = [0xff, 0xd4, 0x00];
const POINTS_RGB = [0x7f, 0xd8, 0xff];
const HATCH_RGB = [225, 225, 225];  // viewer/src/colormaps.js UNKNOWN_HATCH_RGB

/** offroad (generated, the default) or kitti00 (real data from TERRAMESH_SHARED_DIR). */
const SCENARIO = process.env.TERRAMESH_VIEWER_SCENARIO || 'offroad';

let work, run, server, browser, viewer, meshText, expected;
let session = {};

/** Raw GET (no URL normalisation, unlike fetch): resolves {status, body}. */
function rawGet(host, port, path) {
  return new Promise((resolve, reject) => {
    const req = request({ host, port, path, method: 'GET' }, (res) => {
      const chunks = [];
      res.on('data', (c) => chunks.push(c));
      res.on('end', () => resolve({ status: res.statusCode, body: Buffer.concat(chunks).toString('latin1') }));
    });
    req.on('error', reject);
    req.end();
  });
}

/** The canvas as the user sees it; `bare` hides the header, legend and controls drawn over it. */
async function canvasImage(bare = false) {
  await settle(viewer.page);
  const overlays = '#legend, .lil-gui, #header';
  if (bare) await viewer.page.evaluate((s) => { for (const e of document.querySelectorAll(s)) e.style.visibility = 'hidden'; }, overlays);
  const box = await viewer.page.locator('#canvas').boundingBox();
  const image = decodePng(await viewer.page.screenshot({ clip: box }));
  if (bare) await viewer.page.evaluate((s) => { for (const e of document.querySelectorAll(s)) e.style.visibility = ''; }, overlays);
  return image;
}

/**
 * The offroad scene of `terramesh generate` (40 m), meshed with snapshots and traversability; a
 * path.csv over measured vertices and a voxels.bin near them are added by hand.
 */
async function offroadRun() {
  const gen = join(work, 'gen');
  execFileSync(BIN, ['generate', 'offroad', '-o', gen, '--length-m', '40'], { stdio: 'pipe' });
  execFileSync(BIN, ['mesh', join(gen, 'stream.tmstream'), '-o', run, '--snapshot-every', '4', '--quiet',
    '--robot', join(SOURCE, 'traversability/robots/small_wheeled.yaml')], { stdio: 'pipe' });
  // A planned path over measured mesh vertices (path.csv's columns), and OctoMap voxels near
  // them (voxels.bin is in the octree frame: metres, z along up; here up is within 2 degrees of z).
  const { parsePly } = await import(pathToFileURL(join(SOURCE, 'viewer/src/ply.js')));
  const buffer = readFileSync(join(run, 'mesh.ply'));
  const ply = parsePly(buffer.buffer.slice(buffer.byteOffset, buffer.byteOffset + buffer.length));
  const v = ply.element('vertex').scalars;
  const measured = [...v.x.keys()].filter((i) => !v.steiner[i]).sort((a, b) => v.x[a] - v.x[b]);
  const picks = [0, 0.25, 0.5, 0.75, 1].map((t) => measured[Math.round(t * (measured.length - 1))]);
  writeFileSync(join(run, 'path.csv'), 'x,y,z,yaw,face,cost\n' +
    picks.map((i) => `${v.x[i]},${v.y[i]},${v.z[i]},0,0,0`).join('\n') + '\n');
  const voxelCentres = measured.filter((_, k) => k % Math.ceil(measured.length / 20) === 0);
  const voxels = Buffer.alloc(16 + 16 * voxelCentres.length);
  voxels.write('TMVOXEL1', 0, 'latin1');
  voxels.writeUInt32LE(voxelCentres.length, 8);
  voxelCentres.forEach((i, k) => {
    [v.x[i], v.y[i], v.z[i], 1.5].forEach((value, c) => voxels.writeFloatLE(value, 16 + 16 * k + 4 * c));
  });
  writeFileSync(join(run, 'voxels.bin'), voxels);
  return { serverArgs: ['--stream', join(gen, 'stream.tmstream')], frames: 6 };
}

/**
 * Real KITTI 00 (the ORB-SLAM export of frames 0-50: 17 keyframes, ../shared/data), as docs/viewer.md
 * makes it: meshed at the ICP scale with snapshots and traversability, a path planned by
 * `terramesh plan` between the longest solved random pair, the OctoMap of `terramesh convert` left
 * as octomap.bt (the server converts it). Trajectory and points come from summary.txt's input.
 */
function kittiRun() {
  const input = join(process.env.TERRAMESH_SHARED_DIR || '', 'data/kitti00_orbslam/slam_data_version0.1_KITTI00_50frames.json');
  const scale = ['--metres-per-unit', '16.589'];
  execFileSync(BIN, ['mesh', input, '-o', run, ...scale, '--snapshot-every', '4', '--quiet',
    '--robot', join(SOURCE, 'traversability/robots/small_wheeled.yaml')], { stdio: 'pipe' });
  const pairs = join(work, 'pairs');
  execFileSync(BIN, ['plan', run, '--random-pairs', '5', '-o', pairs, '--quiet'], { stdio: 'pipe' });
  // The longest solved pair (pairs.csv: status in column 7, length_m in 8), so the drawn path
  // spans enough of the view to count its pixels.
  const solved = readFileSync(join(pairs, 'pairs.csv'), 'latin1').split('\n').slice(1)
    .map((l) => l.split(',')).filter((f) => f[7] === 'solved')
    .sort((a, b) => Number(b[8]) - Number(a[8]))[0];
  assert.ok(solved, 'terramesh plan solved none of 5 random pairs on KITTI 00');
  execFileSync(BIN, ['plan', run, '--start', ...solved.slice(1, 4), '--goal', ...solved.slice(4, 7), '-o', run, '--quiet'],
    { stdio: 'pipe' });
  execFileSync(BIN, ['convert', input, join(run, 'octomap.bt'), ...scale, '--quiet'], { stdio: 'pipe' });
  return { serverArgs: [], frames: null };
}

before(async () => {
  assert.ok(BIN && SOURCE, 'TERRAMESH_BIN and TERRAMESH_SOURCE_DIR must be set');
  work = mkdtempSync(join(tmpdir(), 'terramesh-viewer-test-'));
  run = join(work, 'out');
  expected = SCENARIO === 'kitti00' ? kittiRun() : await offroadRun();
  writeFileSync(join(work, 'secret.txt'), 'TOP-SECRET-OUTSIDE-OUTDIR\n');
  symlinkSync(join(work, 'secret.txt'), join(run, 'link_outside.txt'));
  meshText = readFileSync(join(run, 'mesh.ply')).toString('latin1', 0, 60);
  session = await startSession(BIN, run, expected.serverArgs);
  ({ server, browser, viewer } = session);
});

after(() => endSession(session, work));

test(`the page loads the ${SCENARIO} run with its layers, snapshots, trajectory, points, path and voxels`, async () => {
  const info = await viewer.page.evaluate(() => window.terramesh.info);
  const manifest = await viewer.page.evaluate(() => window.terramesh.manifest);
  assert.ok(info.faces > 100, `faces: ${info.faces}`);
  assert.equal(info.loadedUrl, 'run/traversability.ply');
  for (const layer of ['cost', 'slope_deg', 'step_m', 'contact', 'clearance_m', 'rays']) {
    assert.ok(info.layers.includes(layer), `${layer} missing from ${info.layers.join(',')}`);
  }
  assert.ok(manifest.snapshots.length >= 3, `${manifest.snapshots.length} snapshots`);
  assert.equal(info.frames.length, expected.frames ?? manifest.snapshots.length + 1, 'the snapshots and the final map');
  assert.ok(manifest.trajectory && manifest.points, 'trajectory and points');
  assert.equal(info.pathCount, 1);
  assert.ok(info.voxelCount >= 10, `voxels: ${info.voxelCount}`);
});

test('the canvas is not blank', async () => {
  const image = await canvasImage();
  const drawn = fractionNot(image, BACKGROUND);
  assert.ok(drawn > 0.05, `only ${(100 * drawn).toFixed(2)}% of the canvas differs from the background`);
});

test('switching the layer changes the pixels', async () => {
  await viewer.page.evaluate(() => window.terramesh.setLayer('cost'));
  const cost = await canvasImage();
  await viewer.page.evaluate(() => window.terramesh.setLayer('slope_deg'));
  const slope = await canvasImage();
  assert.equal(await viewer.page.evaluate(() => window.terramesh.info.shownLayer), 'slope_deg');
  const changed = fractionChanged(cost, slope);
  assert.ok(changed > 0.01, `layer switch changed ${(100 * changed).toFixed(2)}% of the pixels`);
  await viewer.page.evaluate(() => window.terramesh.setLayer('cost'));
});

test('the keyframe slider changes the mesh', async () => {
  const before = await canvasImage();
  const finalFaces = await viewer.page.evaluate(() => window.terramesh.info.faces);
  const slider = viewer.page.locator('#keyframe-slider');
  await slider.fill('0');  // sets the value and fires input, as a user's drag does
  await viewer.page.waitForFunction(() => window.terramesh.info.keyframe === 4);
  const info = await viewer.page.evaluate(() => window.terramesh.info);
  assert.equal(info.loadedUrl, 'run/snapshots/mesh_000004.ply');
  assert.notEqual(info.faces, finalFaces);
  const after = await canvasImage();
  const changed = fractionChanged(before, after);
  assert.ok(changed > 0.01, `slider changed ${(100 * changed).toFixed(2)}% of the pixels`);
  await slider.fill(String(info.frames.length - 1));
  await viewer.page.waitForFunction(() => window.terramesh.info.loadedUrl === 'run/traversability.ply');
});

test('"replay keyframes" steps through the snapshots to the final map', async () => {
  const page = viewer.page;
  const frames = (await page.evaluate(() => window.terramesh.info)).frames;
  await page.getByText('replay keyframes').click();
  await page.waitForFunction(() => window.terramesh.info.keyframe === 4);
  assert.equal(await page.inputValue('#keyframe-slider'), '0');
  await page.waitForFunction((n) => window.terramesh.info.loadedUrl === 'run/traversability.ply' &&
    document.getElementById('keyframe-slider').value === String(n - 1), frames.length, { timeout: 60000 });
});

test('unknown faces are hatched grey on every layer, and the legend says so', async () => {
  const info = await viewer.page.evaluate(() => window.terramesh.info);
  // Unknown faces include every face on a Steiner vertex: shown with the Steiner faces.
  await viewer.page.evaluate(() => window.terramesh.setOption('showSteiner', true));
  for (const layer of info.layers) {
    await viewer.page.evaluate((name) => window.terramesh.setLayer(name), layer);
    const shown = await viewer.page.evaluate(() => window.terramesh.info);
    assert.ok(shown.unknownFaces > 0, `${layer}: no unknown faces in the run`);
    const image = await canvasImage(true);
    const pixels = image.width * image.height;
    // The stripes (one light grey) and between them the shaded grey base (R = G = B, darker).
    const stripes = countColour(image, HATCH_RGB, 3);
    let base = 0;
    for (let i = 0; i < pixels; ++i) {
      const [r, g, b] = image.rgba.subarray(4 * i, 4 * i + 3);
      if (r === g && g === b && r >= 25 && r <= 140) ++base;
    }
    assert.ok(stripes > 0.005 * pixels && base > 0.005 * pixels,
      `${layer}: ${stripes} stripe and ${base} grey pixels for ${shown.unknownFaces} unknown faces`);
    const legend = await viewer.page.textContent('#legend');
    assert.match(legend, new RegExp(`unknown, hatched grey \\(${shown.unknownFaces}\\)`), `${layer}: legend "${legend}"`);
    assert.match(legend, /lethal \(\d+\)/);
  }
  await viewer.page.evaluate(() => { window.terramesh.setOption('showSteiner', false); window.terramesh.setLayer('cost'); });
});

test('the Steiner toggle shows and hides the Steiner faces', async () => {
  const info = await viewer.page.evaluate(() => window.terramesh.info);
  assert.ok(info.measured < info.faces, `${info.faces} faces, ${info.measured} measured: no Steiner faces to toggle`);
  await viewer.page.evaluate(() => window.terramesh.setOption('showSteiner', false));
  const hidden = await canvasImage();
  await viewer.page.evaluate(() => window.terramesh.setOption('showSteiner', true));
  const shown = await canvasImage();
  await viewer.page.evaluate(() => window.terramesh.setOption('showSteiner', false));
  const changed = fractionChanged(hidden, shown);
  assert.ok(changed > 0.01, `Steiner faces changed ${(100 * changed).toFixed(2)}% of the pixels`);
});

test('the camera trajectory and the SLAM points are drawn and toggled', async () => {
  for (const [option, rgb] of [['trajectory', TRAJECTORY_RGB], ['points', POINTS_RGB]]) {
    await viewer.page.evaluate((o) => window.terramesh.setOption(o, true), option);
    const on = countColour(await canvasImage(true), rgb, 12);
    await viewer.page.evaluate((o) => window.terramesh.setOption(o, false), option);
    const off = countColour(await canvasImage(true), rgb, 12);
    await viewer.page.evaluate((o) => window.terramesh.setOption(o, true), option);
    assert.ok(on > 20 && off < on / 5, `${option}: ${on} pixels of its colour shown, ${off} hidden`);
  }
});

test('the timing chart is linked to the slider both ways', async () => {
  const page = viewer.page;
  const info = await page.evaluate(() => window.terramesh.info);
  assert.equal(info.chartMarker, info.keyframe, 'the chart marks the final keyframe');
  // A click near the chart's left edge picks an early keyframe: the slider moves to the first
  // snapshot at or after it.
  const over = page.locator('#chart .u-over');
  const box = await over.boundingBox();
  await over.click({ position: { x: 3, y: box.height / 2 } });
  await page.waitForFunction(() => window.terramesh.info.keyframe === 4);
  assert.equal(await page.inputValue('#keyframe-slider'), '0');
  assert.equal(await page.evaluate(() => window.terramesh.info.chartMarker), 4);
  // Moving the slider moves the chart's marker.
  await page.locator('#keyframe-slider').fill('2');
  await page.waitForFunction(() => window.terramesh.info.keyframe === 12);
  assert.equal(await page.evaluate(() => window.terramesh.info.chartMarker), 12);
  await page.locator('#keyframe-slider').fill(String(info.frames.length - 1));
  await page.waitForFunction(() => window.terramesh.info.loadedUrl === 'run/traversability.ply');
});

test('the planned path is drawn', async () => {
  await viewer.page.evaluate(() => window.terramesh.setOption('paths', true));
  const withPath = countColour(await canvasImage(), PATH_RGB);
  await viewer.page.evaluate(() => window.terramesh.setOption('paths', false));
  const withoutPath = countColour(await canvasImage(), PATH_RGB);
  await viewer.page.evaluate(() => window.terramesh.setOption('paths', true));
  assert.ok(withPath > 50, `${withPath} path-coloured pixels with the path shown`);
  assert.ok(withoutPath < withPath / 5, `${withoutPath} path-coloured pixels with the path hidden`);
});

test('the voxel toggle changes the pixels', async () => {
  await viewer.page.evaluate(() => window.terramesh.setOption('voxels', true));
  const on = await canvasImage();
  await viewer.page.evaluate(() => window.terramesh.setOption('voxels', false));
  const off = await canvasImage();
  const changed = fractionChanged(on, off);
  assert.ok(changed > 0.001, `voxels changed ${(100 * changed).toFixed(3)}% of the pixels`);
});

test('the maps travel as binary PLY parsed in the worker, not through the page', async () => {
  // The page's own resource timeline: the manifest, CSVs, voxels; every PLY went to the worker.
  const fetched = await viewer.page.evaluate(() => performance.getEntriesByType('resource').map((e) => e.name));
  assert.ok(fetched.some((url) => url.endsWith('/api/manifest')), fetched.join(' '));
  assert.deepEqual(fetched.filter((url) => url.endsWith('.ply')), []);
  const response = await rawGet('127.0.0.1', server.port, '/run/traversability.ply');
  assert.equal(response.status, 200);
  assert.match(response.body.slice(0, 200), /^ply\nformat binary_little_endian 1\.0\n/);
});

test('the console has no errors', () => {
  assert.deepEqual(viewer.errors, []);
});

test('the server refuses paths outside OUTDIR', async () => {
  const ok = await rawGet('127.0.0.1', server.port, '/run/mesh.ply');
  assert.equal(ok.status, 200);
  assert.equal(ok.body.slice(0, 60), meshText);
  for (const path of ['/run/../secret.txt', '/run/%2e%2e/secret.txt', '/run/..%2fsecret.txt', '/../secret.txt',
    '/run/link_outside.txt', '/run//etc/passwd', '/run/snapshots/../../secret.txt', '/%2e%2e/%2e%2e/etc/passwd']) {
    const response = await rawGet('127.0.0.1', server.port, path);
    assert.ok(response.status >= 400 && response.status < 500, `${path}: HTTP ${response.status}`);
    assert.ok(!response.body.includes('TOP-SECRET') && !response.body.includes('root:'), `${path} leaked a file`);
  }
});

test('the server listens on 127.0.0.1 only', async () => {
  // /proc/net/tcp lists listening sockets (state 0A) as hex address:port; 0100007F is 127.0.0.1.
  const port = server.port.toString(16).toUpperCase().padStart(4, '0');
  const listening = readFileSync('/proc/net/tcp', 'latin1').split('\n').slice(1)
    .map((l) => l.trim().split(/\s+/)).filter((f) => f.length > 3 && f[3] === '0A' && f[1].endsWith(`:${port}`));
  assert.deepEqual(listening.map((f) => f[1]), [`0100007F:${port}`]);
  const v6 = readFileSync('/proc/net/tcp6', 'latin1').split('\n').filter((l) => l.includes(`:${port} `) && l.includes(' 0A '));
  assert.deepEqual(v6, []);
  // Another loopback address reaches a wildcard socket but not one bound to 127.0.0.1.
  await assert.rejects(rawGet('127.0.0.2', server.port, '/'), /ECONNREFUSED/);
});

// Browser tests of `terramesh view` in headless Debian chromium (docs/viewer.md). Run by ctest
// (tests/viewer/CMakeLists.txt) with TERRAMESH_BIN, TERRAMESH_SOURCE_DIR and
// TERRAMESH_VIEWER_TEST_MODULES set.
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { mkdtempSync, readFileSync, rmSync, writeFileSync, symlinkSync } from 'node:fs';
import { request } from 'node:http';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { pathToFileURL } from 'node:url';
import { after, before, test } from 'node:test';
import { launchBrowser, openViewer, settle, startServer, stopServer } from './harness.mjs';
import { countColour, decodePng, fractionChanged, fractionNot } from './png.mjs';

const BIN = process.env.TERRAMESH_BIN;
const SOURCE = process.env.TERRAMESH_SOURCE_DIR;
const BACKGROUND = [0x1e, 0x22, 0x28];
const PATH_RGB = [0xff, 0x3d, 0xf2];

let work, run, server, browser, viewer, meshText;

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

async function canvasImage() {
  await settle(viewer.page);
  const box = await viewer.page.locator('#canvas').boundingBox();
  return decodePng(await viewer.page.screenshot({ clip: box }));
}

before(async () => {
  assert.ok(BIN && SOURCE, 'TERRAMESH_BIN and TERRAMESH_SOURCE_DIR must be set');
  work = mkdtempSync(join(tmpdir(), 'terramesh-viewer-test-'));
  run = join(work, 'out');
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
  writeFileSync(join(work, 'secret.txt'), 'TOP-SECRET-OUTSIDE-OUTDIR\n');
  symlinkSync(join(work, 'secret.txt'), join(run, 'link_outside.txt'));
  meshText = buffer.toString('latin1', 0, 60);
  server = await startServer(BIN, run, ['--stream', join(gen, 'stream.tmstream')]);
  browser = await launchBrowser();
  viewer = await openViewer(browser.context, server.url);
});

after(async () => {
  if (browser) await browser.close();
  stopServer(server);
  if (work) rmSync(work, { recursive: true, force: true });
});

test('the page loads the generated run with its layers, snapshots, path and voxels', async () => {
  const info = await viewer.page.evaluate(() => window.terramesh.info);
  assert.ok(info.faces > 100, `faces: ${info.faces}`);
  assert.equal(info.loadedUrl, 'run/traversability.ply');
  assert.ok(info.layers.includes('cost') && info.layers.includes('slope_deg'), info.layers.join(','));
  assert.equal(info.frames.length, 6, 'five snapshots and the final map');
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

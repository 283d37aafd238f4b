// Browser test of `terramesh view` on a tiled map (docs/viewer.md, "A tiled map"): a 300 m street
// meshed with the online freeze into 40 m tiles and joined by `tiles merge`. The page must load
// the tiles around its view only, and page tiles in and out as the view moves. Run by ctest
// (tests/viewer/CMakeLists.txt, viewer.browser_tiles) with TERRAMESH_BIN and TERRAMESH_SOURCE_DIR.
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { mkdtempSync, readFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { after, before, test } from 'node:test';
import { endSession, settle, startSession } from './harness.mjs';
import { decodePng, fractionNot } from './png.mjs';

const BIN = process.env.TERRAMESH_BIN;
const SOURCE = process.env.TERRAMESH_SOURCE_DIR;
const BACKGROUND = [0x1e, 0x22, 0x28];

let work, tiles, index, viewer;
let session = {};

const centre = (b) => [(b.min_x + b.max_x) / 2, (b.min_y + b.max_y) / 2];
const distanceToBounds = (p, b) => Math.hypot(Math.max(b.min_x - p[0], 0, p[0] - b.max_x),
  Math.max(b.min_y - p[1], 0, p[1] - b.max_y));

async function canvasImage() {
  await settle(viewer.page);
  await viewer.page.evaluate(() => window.terramesh.renderNow());
  const box = await viewer.page.locator('#canvas').boundingBox();
  return decodePng(await viewer.page.screenshot({ clip: box }));
}

before(async () => {
  assert.ok(BIN && SOURCE, 'TERRAMESH_BIN and TERRAMESH_SOURCE_DIR must be set');
  work = mkdtempSync(join(tmpdir(), 'terramesh-tiles-viewer-'));
  const data = join(work, 'data');
  execFileSync(BIN, ['generate', 'street', '--length-m', '300', '--seed', '2', '--outlier-fraction', '0', '-o', data,
    '--quiet'], { stdio: 'pipe' });
  const run = join(work, 'run');
  execFileSync(BIN, ['mesh', join(data, 'stream.tmstream'), '-o', run, '--quiet', '--freeze-radius-m', '80',
    '--freeze-tile-m', '40', '--robot', join(SOURCE, 'traversability/robots/small_wheeled.yaml')], { stdio: 'pipe' });
  tiles = join(run, 'tiles');
  execFileSync(BIN, ['tiles', 'merge', join(tiles, 'plan.json'), '--quiet'], { stdio: 'pipe' });
  index = JSON.parse(readFileSync(join(tiles, 'tiles.json'), 'utf8'));
  session = await startSession(BIN, tiles);
  viewer = session.viewer;
});

after(() => endSession(session, work));

test('the manifest names the tile index, and the page loads the tiles around its view only', async () => {
  const manifest = await viewer.page.evaluate(() => window.terramesh.manifest);
  assert.equal(manifest.tile_index, 'run/tiles.json');
  assert.equal(manifest.mesh, null);
  const info = await viewer.page.evaluate(() => window.terramesh.info);
  const withFaces = index.tiles.filter((t) => t.faces > 0);
  assert.equal(info.tilesTotal, withFaces.length);
  assert.ok(withFaces.length > 8, `${withFaces.length} tiles with faces`);
  assert.ok(info.tilesLoaded.length >= 1 && info.tilesLoaded.length < withFaces.length,
    `${info.tilesLoaded.length} of ${withFaces.length} tiles loaded`);
  const faces = withFaces.filter((t) => info.tilesLoaded.includes(t.name)).reduce((s, t) => s + t.faces, 0);
  assert.equal(info.faces, faces, 'the faces drawn are those of the tiles loaded');
  assert.equal(info.shownLayer, 'cost');
  assert.ok(fractionNot(await canvasImage(), BACKGROUND) > 0.05, 'the tiles are drawn');
  assert.deepEqual(viewer.errors, []);
});

test('moving the view pages the tiles there in and the ones left behind out', async () => {
  const withFaces = index.tiles.filter((t) => t.faces > 0);
  // The page starts over the first tile with faces; go to the one farthest from it.
  const first = withFaces[0];
  const start = centre(first.bounds_m);
  const far = withFaces.reduce((best, t) => {
    const d = Math.hypot(centre(t.bounds_m)[0] - start[0], centre(t.bounds_m)[1] - start[1]);
    return d > best.d ? { t, d } : best;
  }, { t: null, d: -1 });
  assert.ok(far.d > 150, `the street spans ${far.d} m`);
  const before = await viewer.page.evaluate(() => window.terramesh.info.tilesLoaded);
  assert.ok(before.includes(first.name));
  const loaded = await viewer.page.evaluate(([x, y]) => window.terramesh.lookAt(x, y), centre(far.t.bounds_m));
  const info = await viewer.page.evaluate(() => window.terramesh.info);
  assert.ok(loaded.includes(far.t.name), `${far.t.name} loaded: ${loaded}`);
  // Held: every tile within the radius of the new target; none beyond the radius and the
  // hysteresis (the tiles of the start among them).
  for (const t of withFaces) {
    const d = distanceToBounds(info.target, t.bounds_m);
    if (d <= info.radiusM) assert.ok(loaded.includes(t.name), `${t.name} at ${d} m not loaded`);
    if (d > info.radiusM + info.hysteresisM) assert.ok(!loaded.includes(t.name), `${t.name} at ${d} m still held`);
  }
  assert.ok(!loaded.includes(first.name), `${first.name}, where the view started, dropped`);
  assert.ok(info.drops > 0 && info.loads > before.length);
  assert.ok(fractionNot(await canvasImage(), BACKGROUND) > 0.05, 'the tiles there are drawn');
  // And back: the first tile comes back.
  const again = await viewer.page.evaluate(([x, y]) => window.terramesh.lookAt(x, y), start);
  assert.ok(again.includes(first.name));
  assert.deepEqual(viewer.errors, []);
});

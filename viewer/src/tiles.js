// terramesh view on a tiled map (tiles.json of `terramesh tiles merge`, docs/tiles.md): the tiles
// around the camera's target are loaded, the ones left far behind dropped, as the user moves.
import GUI from 'lil-gui';
import { colourFaces, layerLabel, layerNames } from './layers.js';
import { renderLegend } from './legend.js';
import { MapScene } from './scene.js';

const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];

/** Distance in the plan from point `p` (metres) to a tile's bounds_m (0 inside). */
function distanceToBounds(p, b) {
  const dx = Math.max(b.min_x - p[0], 0, p[0] - b.max_x);
  const dy = Math.max(b.min_y - p[1], 0, p[1] - b.max_y);
  return Math.hypot(dx, dy);
}

/**
 * Which tiles to hold around a plan position: those within `radius` metres (loaded), and those
 * held already that are still within `radius + hysteresis` (kept, so that a tile on the edge does
 * not come and go). Tiles without faces are never loaded. Pure: exported for the tests.
 */
export function tilesAround(tiles, position, radius, hysteresis, held) {
  const wanted = new Set();
  for (const tile of tiles) {
    if (!tile.faces) continue;
    const d = distanceToBounds(position, tile.bounds_m);
    if (d <= radius || (held.has(tile.name) && d <= radius + hysteresis)) wanted.add(tile.name);
  }
  return wanted;
}

/** The index's plan frame: map point (map units) to plan metres and back (height 0). */
export class PlanFrame {
  constructor(frame) {
    this.x = frame.plan_x;
    this.y = frame.plan_y;
    this.up = frame.up;
    this.scale = frame.metres_per_unit;
  }
  toPlan(p) { return [dot(this.x, p) * this.scale, dot(this.y, p) * this.scale]; }
  fromPlan(xy) {
    const a = xy[0] / this.scale, b = xy[1] / this.scale;
    return [0, 1, 2].map((i) => a * this.x[i] + b * this.y[i]);
  }
}

/** The page for a tiled map; `status` shows a line, `$` finds an element. */
export async function runTiled(loader, manifest, $, status) {
  const index = JSON.parse(await loader.text(manifest.tile_index));
  const base = manifest.tile_index.slice(0, manifest.tile_index.lastIndexOf('/') + 1);
  const frame = new PlanFrame(index.frame);
  const tiles = index.tiles.map((tile) => ({
    ...tile,
    url: base + tile.files.find((file) => file.endsWith('traversability.ply')),
  }));
  const withFaces = tiles.filter((tile) => tile.faces > 0);
  if (!withFaces.length) throw new Error(`${manifest.tile_index}: no tile owns a face`);
  // Scene coordinates: relative to the first tile's centre (float32 keeps millimetres near it).
  const first = withFaces[0].bounds_m;
  const origin = frame.fromPlan([(first.min_x + first.max_x) / 2, (first.min_y + first.max_y) / 2]);
  const toScene = (xy) => frame.fromPlan(xy).map((v, i) => v - origin[i]);
  const tileM = index.tile_m;
  const scene = new MapScene($('canvas'));
  scene.frame(frame.up, 1.5 * tileM / frame.scale, toScene([(first.min_x + first.max_x) / 2, (first.min_y + first.max_y) / 2]));

  const state = { layer: 'cost', showSteiner: false };
  const info = { tilesTotal: withFaces.length, tilesLoaded: [], faces: 0, shownLayer: null, loads: 0, drops: 0,
    radiusM: 0, hysteresisM: tileM, target: null };
  const held = new Map();  // name -> {mesh, buffers}
  let layers = null;

  function recolour(name) {
    const entry = held.get(name);
    const layer = entry.mesh.layers[state.layer] ? state.layer : 'height';
    const legend = colourFaces(entry.mesh, layer, frame.up, entry.buffers.colours, entry.buffers.hatch);
    scene.coloursChanged(name);
    info.shownLayer = layer;
    return legend;
  }
  function recolourAll() {
    let legend = null;
    const counts = { unknownFaces: 0, lethalFaces: 0, uncertainFaces: 0 };
    for (const name of held.keys()) {
      legend = recolour(name);
      for (const key of Object.keys(counts)) counts[key] += legend[key];
    }
    if (!legend) return;
    renderLegend($('legend'), { ...legend, ...counts,
      note: `${held.size} of ${withFaces.length} tiles loaded${state.layer === 'height' ? ' (height ranged per tile)' : ''}` });
  }

  /** Loads the tiles around the camera's target and drops the far ones; resolves the names held. */
  let ticket = 0;
  async function page() {
    const mine = ++ticket;
    const target = scene.controls.target;
    const position = frame.toPlan([target.x + origin[0], target.y + origin[1], target.z + origin[2]]);
    const distance = scene.camera.position.distanceTo(target) * frame.scale;
    const radius = Math.min(Math.max(distance, tileM), 3 * tileM);
    info.radiusM = radius;
    info.target = position;
    const wanted = tilesAround(withFaces, position, radius, tileM, new Set(held.keys()));
    for (const name of [...held.keys()]) {
      if (!wanted.has(name)) { scene.removeTile(name); held.delete(name); ++info.drops; }
    }
    const missing = withFaces.filter((tile) => wanted.has(tile.name) && !held.has(tile.name));
    status(`loading ${missing.length} tile(s)…`);
    const loaded = await Promise.all(missing.map((tile) => loader.ply(tile.url, 'mesh', origin)));
    if (mine !== ticket) return info.tilesLoaded;  // a newer page() runs
    missing.forEach((tile, i) => {
      const mesh = loaded[i];
      held.set(tile.name, { mesh, buffers: scene.addTile(tile.name, mesh) });
      ++info.loads;
    });
    if (!layers && held.size) layers = layerNames(held.values().next().value.mesh);
    recolourAll();
    scene.showSteiner(state.showSteiner);
    info.tilesLoaded = [...held.keys()].sort();
    info.faces = [...held.values()].reduce((sum, entry) => sum + entry.mesh.faces, 0);
    status(`${held.size} of ${withFaces.length} tiles around the view, ${info.faces} faces`);
    return info.tilesLoaded;
  }

  let timer = null;
  scene.controls.addEventListener('end', () => { clearTimeout(timer); timer = setTimeout(page, 150); });
  await page();

  const gui = new GUI({ title: 'terramesh view: tiles' });
  gui.add(state, 'layer', Object.fromEntries((layers || ['height']).map((l) => [layerLabel(l), l])))
    .name('colour by').onChange(recolourAll);
  gui.add(state, 'showSteiner').name('Steiner faces').onChange(() => scene.showSteiner(state.showSteiner));

  // For the browser tests (tests/viewer/tiles_test.mjs).
  window.terramesh = {
    info, state, manifest, index,
    /** Moves the view's target to plan position (x, y) metres and pages; resolves the tiles held. */
    lookAt: (x, y) => { scene.moveTargetTo(toScene([x, y])); return page(); },
    renderNow: () => scene.renderNow(),
  };
  document.body.dataset.ready = 'true';
}

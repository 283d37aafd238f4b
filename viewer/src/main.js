// terramesh view: the page. Loads the run's manifest, then the final map (traversability.ply if
// present, else mesh.ply), the overlays and the timing chart; the slider replays the snapshots. A
// tiled map's folder goes to tiles.js.
import './style.css';
import GUI from 'lil-gui';
import { colourFaces, layerLabel, layerNames, setLayerRegistry } from './layers.js';
import { renderLegend } from './legend.js';
import { SlamPoints, Trajectory, pathObject, voxelObject } from './overlays.js';
import { RunLoader } from './run_loader.js';
import { MapScene } from './scene.js';
import { runTiled } from './tiles.js';
import { TimingChart, keyframeTimings } from './timing_chart.js';

const $ = (id) => document.getElementById(id);
const status = (text) => { $('status').textContent = text; };

/** Keeps the final mesh and the last few snapshots parsed. */
class MeshCache {
  constructor(loader, origin, keep) { this.loader = loader; this.origin = origin; this.keep = keep; this.entries = new Map(); }
  async get(url) {
    if (this.entries.has(url)) {
      const hit = this.entries.get(url);
      this.entries.delete(url);
      this.entries.set(url, hit);
      return hit;
    }
    const promise = this.loader.ply(url, 'mesh', this.origin);
    this.entries.set(url, promise);
    promise.catch(() => this.entries.delete(url));
    while (this.entries.size > this.keep) this.entries.delete(this.entries.keys().next().value);
    return promise;
  }
}

async function main() {
  const loader = new RunLoader();
  const manifest = await loader.manifest();
  setLayerRegistry(manifest.layers);
  $('run-name').textContent = `terramesh view: ${manifest.run}`;
  document.title = `terramesh view: ${manifest.run}`;
  // A tiled map (tiles.json, no single mesh): its tiles are paged in around the view.
  if (manifest.tile_index && !manifest.mesh) return runTiled(loader, manifest, $, status);
  const finalUrl = manifest.traversability || manifest.mesh;
  status(`loading ${finalUrl}…`);
  const finalMesh = await loader.ply(finalUrl, 'mesh');
  const origin = finalMesh.origin;
  const frame = manifest.map_frame ? await loader.yaml(manifest.map_frame) : {};
  const up = Array.isArray(frame.up) && frame.up.length === 3 ? frame.up : [0, 0, 1];

  const scene = new MapScene($('canvas'));
  let radius = 0;
  for (let i = 0; i < finalMesh.positions.length; i += 3) {
    radius = Math.max(radius, Math.hypot(finalMesh.positions[i], finalMesh.positions[i + 1], finalMesh.positions[i + 2]));
  }
  scene.frame(up, radius);

  const timings = manifest.keyframes ? keyframeTimings(await loader.csv(manifest.keyframes)) : { x: [], series: [] };
  const lastSnapshot = manifest.snapshots.length ? manifest.snapshots[manifest.snapshots.length - 1].keyframe : 0;
  const totalKeyframes = Math.max(timings.x.length, lastSnapshot);
  const frames = manifest.snapshots.filter((s) => s.keyframe < totalKeyframes)
    .map((s) => ({ keyframe: s.keyframe, url: s.url, final: false }));
  frames.push({ keyframe: totalKeyframes, url: finalUrl, final: true });

  const cache = new MeshCache(loader, origin, 6);
  cache.entries.set(finalUrl, Promise.resolve(finalMesh));
  const layers = layerNames(finalMesh);
  const state = {
    layer: layers.includes('cost') ? 'cost' : 'height',
    showSteiner: false,  // the Steiner faces close the map like a box; shown on demand
    trajectory: true,
    points: true,
    paths: true,
    voxels: Boolean(manifest.voxels),
    frameIndex: frames.length - 1,
  };
  const info = { frames, layers, loadedUrl: null, faces: 0, measured: 0, pathCount: 0, voxelCount: 0,
    shownLayer: null, keyframe: totalKeyframes, errors: [] };

  // Overlays.
  const overlays = {};
  if (manifest.trajectory) {
    overlays.trajectory = new Trajectory(await loader.csv(manifest.trajectory), origin);
    scene.overlays.add(overlays.trajectory.object);
  }
  if (manifest.points) {
    overlays.points = new SlamPoints(await loader.ply(manifest.points, 'points', origin));
    scene.overlays.add(overlays.points.object);
  }
  overlays.paths = [];
  for (const [i, url] of manifest.paths.entries()) {
    const object = pathObject(await loader.csv(url), origin, up, 0.004 * radius, i);
    overlays.paths.push(object);
    scene.overlays.add(object);
  }
  info.pathCount = overlays.paths.length;
  if (manifest.voxels) {
    const voxels = await loader.voxels(manifest.voxels);
    overlays.voxels = voxelObject(voxels, origin, up, Number(frame.metres_per_unit) || 1);
    info.voxelCount = voxels.count;
    scene.overlays.add(overlays.voxels);
  }

  const chart = timings.x.length ? new TimingChart($('chart'), timings, (k) => {
    let best = frames.length - 1;
    for (let i = frames.length - 1; i >= 0; --i) if (frames[i].keyframe >= k) best = i;
    setFrame(best);
  }) : null;

  function applyVisibility() {
    if (overlays.trajectory) overlays.trajectory.object.visible = state.trajectory;
    if (overlays.points) overlays.points.object.visible = state.points;
    for (const p of overlays.paths) p.visible = state.paths;
    if (overlays.voxels) overlays.voxels.visible = state.voxels;
    scene.showSteiner(state.showSteiner);
    scene.requestRender();
  }

  let buffers = null;
  function recolour() {
    const mesh = scene.mesh.userData;
    const name = mesh.layers[state.layer] || state.layer === 'height' ? state.layer : 'height';
    const legend = colourFaces(mesh, name, up, buffers.colours, buffers.hatch);
    if (name !== state.layer) legend.note = `${layerLabel(state.layer)} is in traversability.ply only; this snapshot is coloured by height`;
    else if (mesh.faces > mesh.measured) legend.note = `${mesh.measured} measured faces, ${mesh.faces - mesh.measured} Steiner faces (darker)`;
    renderLegend($('legend'), legend);
    info.shownLayer = name;
    info.unknownFaces = legend.unknownFaces;
    info.lethalFaces = legend.lethalFaces;
    info.uncertainFaces = legend.uncertainFaces;
    scene.coloursChanged();
  }

  let request = 0;
  async function setFrame(index) {
    state.frameIndex = index;
    $('keyframe-slider').value = String(index);
    const target = frames[index];
    const ticket = ++request;
    status(`loading ${target.url}…`);
    const mesh = await cache.get(target.url);
    if (ticket !== request) return;
    buffers = scene.setMesh(mesh);
    recolour();
    info.loadedUrl = target.url;
    info.faces = mesh.faces;
    info.measured = mesh.measured;
    info.keyframe = target.keyframe;
    if (overlays.trajectory) overlays.trajectory.setKeyframe(target.keyframe);
    if (overlays.points) overlays.points.setKeyframe(target.keyframe);
    if (chart) chart.setMarker(target.keyframe);
    info.chartMarker = chart ? chart.marker : null;
    applyVisibility();
    const name = target.url.split('/').pop();
    $('keyframe-label').textContent = `keyframe ${target.keyframe} / ${totalKeyframes}  (${name}, ${mesh.faces} faces)`;
    status(`${mesh.faces} faces (${mesh.measured} measured)${manifest.voxels_source ? `, voxels from ${manifest.voxels_source}` : ''}`);
  }

  const slider = $('keyframe-slider');
  slider.max = String(frames.length - 1);
  slider.disabled = frames.length < 2;  // no snapshots (mesh without --snapshot-every): the final map only
  slider.addEventListener('input', () => { replaying = false; setFrame(Number(slider.value)); });

  // Replays the reconstruction: every snapshot in turn, then the final map; again to stop.
  let replaying = false;
  const actions = {
    replay: async () => {
      if (replaying) { replaying = false; return; }
      replaying = true;
      for (let i = 0; i < frames.length && replaying; ++i) {
        await setFrame(i);
        await new Promise((resolve) => setTimeout(resolve, 400));
      }
      replaying = false;
    },
  };

  const gui = new GUI({ title: 'terramesh view' });
  gui.add(state, 'layer', Object.fromEntries(layers.map((l) => [layerLabel(l), l]))).name('colour by').onChange(recolour);
  if (frames.length > 1) gui.add(actions, 'replay').name('replay keyframes (start / stop)');
  gui.add(state, 'showSteiner').name('Steiner faces').onChange(applyVisibility);
  if (overlays.trajectory) gui.add(state, 'trajectory').name('camera trajectory').onChange(applyVisibility);
  if (overlays.points) gui.add(state, 'points').name('SLAM points').onChange(applyVisibility);
  if (overlays.paths.length) gui.add(state, 'paths').name(`planned paths (${overlays.paths.length})`).onChange(applyVisibility);
  if (overlays.voxels) gui.add(state, 'voxels').name(`OctoMap voxels (${info.voxelCount})`).onChange(applyVisibility);

  await setFrame(frames.length - 1);

  // For the browser tests and the frame-rate benchmark (tests/viewer/).
  window.terramesh = {
    info, state, manifest,
    setLayer: (name) => { state.layer = name; gui.controllersRecursive().forEach((c) => c.updateDisplay()); recolour(); },
    setFrame,
    setOption: (key, value) => { state[key] = value; gui.controllersRecursive().forEach((c) => c.updateDisplay()); applyVisibility(); },
    renderNow: () => scene.renderNow(),
    measureFps: (seconds, finish, dragging) => scene.measureFps(seconds, finish, dragging),
    framesRendered: () => scene.frames,
  };
  document.body.dataset.ready = 'true';
}

main().catch((error) => {
  status(`error: ${error.message}`);
  document.body.dataset.ready = 'error';
  console.error(error);
});

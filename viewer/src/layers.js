// Per-face colours of a layer: value ramp, then classes (unknown grey and hatched, lethal red,
// uncertain magenta) on top.
import { LETHAL_RGB, RAMPS, STEINER_TINT, UNCERTAIN_RGB, UNKNOWN_RGB, rampColour } from './colormaps.js';

/**
 * The layers of traversability.ply as the server's registry describes them (manifest.layers:
 * name, unit, description, optional fixed range; traversability/layer_registry.h), set once by
 * setLayerRegistry. Layers it does not name get their own name and an automatic range.
 */
const KNOWN = { height: { label: 'height along up (map units)' } };
/** The colour ramp of a layer, where it is not viridis. */
const RAMP_OF = { cost: 'cost' };

export function setLayerRegistry(layers) {
  for (const layer of layers || []) {
    KNOWN[layer.name] = { label: layer.description, ramp: RAMP_OF[layer.name], range: layer.range };
  }
}

/** The layer names a mesh offers, in a useful order: registry layers first, then height. */
export function layerNames(mesh) {
  const names = Object.keys(mesh.layers);
  const known = Object.keys(KNOWN).filter((k) => names.includes(k));
  return [...known, ...names.filter((n) => !known.includes(n)), 'height'];
}

export function layerLabel(name) { return (KNOWN[name] && KNOWN[name].label) || name; }

/** Robust range: the 2nd..98th percentile of the finite values (sampled). */
function autoRange(values) {
  const step = Math.max(1, Math.floor(values.length / 20000));
  const sample = [];
  for (let i = 0; i < values.length; i += step) if (Number.isFinite(values[i])) sample.push(values[i]);
  if (sample.length === 0) return [0, 1];
  sample.sort((a, b) => a - b);
  const lo = sample[Math.floor(0.02 * (sample.length - 1))];
  const hi = sample[Math.ceil(0.98 * (sample.length - 1))];
  return hi > lo ? [lo, hi] : [lo, lo + 1];
}

/** Height of each face's centroid along `up` (relative to the mesh origin). */
function faceHeights(mesh, up) {
  const h = new Float32Array(mesh.faces);
  const p = mesh.positions;
  for (let f = 0; f < mesh.faces; ++f) {
    const b = 9 * f;
    h[f] = ((p[b] + p[b + 3] + p[b + 6]) * up[0] + (p[b + 1] + p[b + 4] + p[b + 7]) * up[1] +
            (p[b + 2] + p[b + 5] + p[b + 8]) * up[2]) / 3;
  }
  return h;
}

/** Light direction for the baked shading: mostly from above, a little from the side. */
function lightDirection(up) {
  const u = normalised(up);
  const side = Math.abs(u[0]) < 0.9 ? [1, 0, 0] : [0, 1, 0];
  return normalised([u[0] + 0.45 * side[0], u[1] + 0.45 * side[1], u[2] + 0.45 * side[2]]);
}

function normalised(v) {
  const n = Math.hypot(v[0], v[1], v[2]) || 1;
  return [v[0] / n, v[1] / n, v[2] / n];
}

/**
 * Fills `colours` (Uint8Array, 3 corners x RGB per face) and `hatch` (Uint8Array, one per corner:
 * 255 on unknown faces, which the scene's shader stripes) for layer `name` and returns the legend
 * description. On every layer, height included, when the mesh has the class flags
 * (traversability.ply): unknown faces (flag, or NaN value of a traversability layer) are grey and
 * hatched, lethal faces red, uncertain faces magenta. Steiner faces are darkened. Flat shading is
 * baked in.
 */
export function colourFaces(mesh, name, up, colours, hatch) {
  const known = KNOWN[name] || {};
  const isHeight = name === 'height' || !mesh.layers[name];
  const values = isHeight ? faceHeights(mesh, up) : mesh.layers[name];
  const ramp = RAMPS[known.ramp || 'viridis'];
  const unknown = mesh.flags.unknown || null;
  const lethal = mesh.flags.lethal || null;
  const uncertain = mesh.flags.uncertain || null;
  const classes = Boolean(unknown || lethal);
  const knownValues = unknown ? values.filter((_, f) => !unknown[f]) : values;
  const [min, max] = known.range || autoRange(knownValues);
  const span = max - min;
  const light = lightDirection(up);
  const n = mesh.normals;
  let unknownFaces = 0, lethalFaces = 0, uncertainFaces = 0;
  for (let f = 0; f < mesh.faces; ++f) {
    const v = values[f];
    let rgb;
    const isUnknown = Boolean((unknown && unknown[f]) || (classes && !isHeight && Number.isNaN(v)));
    if (isUnknown) { rgb = UNKNOWN_RGB; ++unknownFaces; }
    else if (lethal && lethal[f]) { rgb = LETHAL_RGB; ++lethalFaces; }
    else if (uncertain && uncertain[f]) { rgb = UNCERTAIN_RGB; ++uncertainFaces; }
    else rgb = rampColour(ramp, v === Infinity ? 1 : (v - min) / span);
    // Flat Lambert shading of a two-sided surface, baked in (the material is unlit).
    const lambert = Math.abs(n[3 * f] * light[0] + n[3 * f + 1] * light[1] + n[3 * f + 2] * light[2]);
    const tint = (0.45 + 0.55 * lambert) * (f >= mesh.measured ? STEINER_TINT : 1);
    for (let c = 0; c < 3; ++c) {
      colours[9 * f + 3 * c] = rgb[0] * tint;
      colours[9 * f + 3 * c + 1] = rgb[1] * tint;
      colours[9 * f + 3 * c + 2] = rgb[2] * tint;
      if (hatch) hatch[3 * f + c] = isUnknown ? 255 : 0;
    }
  }
  return { title: layerLabel(name), ramp, min, max, classes, unknownFaces, lethalFaces, uncertainFaces };
}

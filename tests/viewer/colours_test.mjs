// The viewer's colouring without a browser (node --test; viewer/src is plain ES modules): unknown
// faces are hatched grey and lethal faces red on every layer, and neither colour can be mistaken
// for a colour of any layer's ramp, at any shading the page bakes in.
import assert from 'node:assert/strict';
import { join } from 'node:path';
import { test } from 'node:test';
import { pathToFileURL } from 'node:url';

const SOURCE = process.env.TERRAMESH_SOURCE_DIR;
const load = (file) => import(pathToFileURL(join(SOURCE, 'viewer/src', file)));
const { LETHAL_RGB, RAMPS, STEINER_TINT, UNCERTAIN_RGB, UNKNOWN_HATCH_RGB, UNKNOWN_RGB, rampColour } = await load('colormaps.js');
const { colourFaces, layerNames } = await load('layers.js');
const { renderLegend } = await load('legend.js');

/** Darkest shading layers.js bakes in: a face seen edge-on (0.45), Steiner (x 0.55). */
const DARKEST_TINT = 0.45 * STEINER_TINT;
const chroma = (rgb) => Math.max(...rgb) - Math.min(...rgb);

/** Hue in degrees (unchanged by the shading, which scales all channels alike). */
function hue([r, g, b]) {
  const max = Math.max(r, g, b), min = Math.min(r, g, b), d = max - min;
  if (d === 0) return NaN;
  const h = max === r ? ((g - b) / d) % 6 : max === g ? (b - r) / d + 2 : (r - g) / d + 4;
  return (60 * h + 360) % 360;
}
const hueDistance = (a, b) => Math.min(Math.abs(a - b), 360 - Math.abs(a - b));

test('unknown grey is achromatic and every ramp colour is not, even at the darkest shading', () => {
  assert.equal(chroma(UNKNOWN_RGB), 0);
  assert.equal(chroma(UNKNOWN_HATCH_RGB), 0);
  assert.ok(UNKNOWN_HATCH_RGB[0] - UNKNOWN_RGB[0] >= 60, 'the stripes must stand out of the grey');
  for (const [name, ramp] of Object.entries(RAMPS)) {
    for (let i = 0; i <= 100; ++i) {
      const rgb = rampColour(ramp, i / 100);
      assert.ok(DARKEST_TINT * chroma(rgb) >= 15, `${name} at ${i / 100}: chroma ${chroma(rgb)} too grey`);
    }
  }
});

test('lethal red is at least 15 degrees of hue from every ramp colour', () => {
  for (const [name, ramp] of Object.entries(RAMPS)) {
    for (let i = 0; i <= 100; ++i) {
      const rgb = rampColour(ramp, i / 100);
      const d = hueDistance(hue(rgb), hue(LETHAL_RGB));
      assert.ok(d >= 15, `${name} at ${i / 100}: hue ${hue(rgb).toFixed(1)} is ${d.toFixed(1)} deg from lethal`);
    }
  }
});

/** Four faces in the plane z = 0: known, unknown (flag), lethal, known; the last one Steiner. */
function fourFaces() {
  const positions = new Float32Array(36);
  for (let f = 0; f < 4; ++f) positions.set([f, 0, 0, f + 1, 0, 0, f, 1, 0], 9 * f);
  const normals = new Float32Array([0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1]);
  return {
    faces: 4, measured: 3, positions, normals,
    layers: {
      cost: new Float32Array([0.2, NaN, 1, 0.9]),
      slope_deg: new Float32Array([3, 40, 35, 10]),
      rays: new Float32Array([12, 0, 5, 30]),
    },
    flags: { unknown: new Uint8Array([0, 1, 0, 0]), lethal: new Uint8Array([0, 0, 1, 0]) },
  };
}

test('every layer, height included, greys and hatches the unknown face and reds the lethal one', () => {
  const mesh = fourFaces();
  const names = layerNames(mesh);
  assert.deepEqual(names, ['cost', 'slope_deg', 'rays', 'height']);
  for (const name of names) {
    const colours = new Uint8Array(36);
    const hatch = new Uint8Array(12);
    const legend = colourFaces(mesh, name, [0, 0, 1], colours, hatch);
    const face = (f) => [...colours.subarray(9 * f, 9 * f + 3)];
    assert.equal(chroma(face(1)), 0, `${name}: unknown face ${face(1)}`);
    assert.deepEqual([...hatch.subarray(3, 6)], [255, 255, 255], `${name}: unknown face not hatched`);
    for (const f of [0, 2, 3]) {
      assert.deepEqual([...hatch.subarray(3 * f, 3 * f + 3)], [0, 0, 0], `${name}: face ${f} hatched`);
      assert.ok(chroma(face(f)) >= 15, `${name}: face ${f} is grey: ${face(f)}`);
    }
    const lethal = face(2);
    assert.ok(hueDistance(hue(lethal), hue(LETHAL_RGB)) < 1 && lethal[0] > 100, `${name}: lethal face ${lethal}`);
    assert.equal(legend.classes, true);
    assert.equal(legend.unknownFaces, 1);
    assert.equal(legend.lethalFaces, 1);
  }
});

test('an uncertain face is magenta: 20 degrees of hue from every ramp colour and from lethal red', () => {
  for (const [name, ramp] of Object.entries(RAMPS)) {
    for (let i = 0; i <= 100; ++i) {
      const d = hueDistance(hue(rampColour(ramp, i / 100)), hue(UNCERTAIN_RGB));
      assert.ok(d >= 20, `${name} at ${i / 100}: ${d.toFixed(1)} deg from uncertain`);
    }
  }
  assert.ok(hueDistance(hue(LETHAL_RGB), hue(UNCERTAIN_RGB)) >= 20);
  const mesh = fourFaces();
  mesh.flags.uncertain = new Uint8Array([1, 0, 0, 0]);
  for (const name of layerNames(mesh)) {
    const colours = new Uint8Array(36);
    const legend = colourFaces(mesh, name, [0, 0, 1], colours, new Uint8Array(12));
    const face0 = [...colours.subarray(0, 3)];
    assert.ok(hueDistance(hue(face0), hue(UNCERTAIN_RGB)) < 1, `${name}: uncertain face ${face0}`);
    assert.equal(legend.uncertainFaces, 1);
    assert.equal(legend.lethalFaces, 1);
    const element = {};
    renderLegend(element, legend);
    assert.match(element.innerHTML, new RegExp(`background: rgb\\(${UNCERTAIN_RGB.join(',')}\\)"></span>uncertain \\(1\\)`));
  }
});

test('without class flags (a snapshot mesh.ply) nothing is hatched', () => {
  const mesh = fourFaces();
  mesh.flags = {};
  mesh.layers = {};
  const hatch = new Uint8Array(12).fill(7);
  const legend = colourFaces(mesh, 'height', [0, 0, 1], new Uint8Array(36), hatch);
  assert.deepEqual([...hatch], new Array(12).fill(0));
  assert.equal(legend.classes, false);
});

test('the legend shows the hatched unknown swatch and the lethal swatch with their counts', () => {
  const mesh = fourFaces();
  const legend = colourFaces(mesh, 'cost', [0, 0, 1], new Uint8Array(36), new Uint8Array(12));
  const element = {};
  renderLegend(element, legend);
  assert.match(element.innerHTML, /class="swatch unknown" style="background: repeating-linear-gradient\(/);
  assert.match(element.innerHTML, /unknown, hatched grey \(1\)/);
  assert.match(element.innerHTML, new RegExp(`background: rgb\\(${LETHAL_RGB.join(',')}\\)"></span>lethal \\(1\\)`));
  const noClasses = {};
  renderLegend(noClasses, { ...legend, classes: false });
  assert.doesNotMatch(noClasses.innerHTML, /unknown/);
});

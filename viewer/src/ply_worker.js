// Web worker: fetches a PLY, parses it and builds the flat typed arrays the scene draws, so a
// large map never blocks the page. Messages: {id, url, kind: 'mesh'|'points', origin?}.
import { parsePly } from './ply.js';

const FLAG_PROPERTIES = new Set(['steiner', 'lethal', 'unknown', 'uncertain']);

function centreOf(x, y, z) {
  const lo = [Infinity, Infinity, Infinity];
  const hi = [-Infinity, -Infinity, -Infinity];
  for (let i = 0; i < x.length; ++i) {
    const p = [x[i], y[i], z[i]];
    for (let k = 0; k < 3; ++k) {
      if (p[k] < lo[k]) lo[k] = p[k];
      if (p[k] > hi[k]) hi[k] = p[k];
    }
  }
  return x.length ? lo.map((l, k) => 0.5 * (l + hi[k])) : [0, 0, 0];
}

/**
 * Non-indexed triangles (flat shading and per-face colours need three corners per face), measured
 * faces first so that hiding Steiner faces is a draw range. Positions are relative to `origin`
 * (float32 keeps millimetres there even for kilometre-scale maps).
 */
function buildMesh(ply, origin) {
  const vertex = ply.element('vertex');
  const face = ply.element('face');
  if (!vertex || !face) throw new Error('PLY without vertex or face element');
  const { x, y, z } = vertex.scalars;
  if (!x || !y || !z) throw new Error('PLY vertices without x, y, z');
  const list = face.lists.vertex_indices || face.lists.vertex_index;
  if (!list) throw new Error('PLY faces without vertex_indices');
  const o = origin || centreOf(x, y, z);
  const vertexSteiner = vertex.scalars.steiner;
  const faceSteinerProp = face.scalars.steiner;
  const nIn = face.count;
  const steiner = new Uint8Array(nIn);
  let triangles = 0;
  for (let f = 0; f < nIn; ++f) {
    const a = list.offsets[f], b = list.offsets[f + 1];
    if (b - a !== 3) continue;
    ++triangles;
    if (faceSteinerProp) {
      steiner[f] = faceSteinerProp[f] ? 1 : 0;
    } else if (vertexSteiner) {
      const v = list.values;
      steiner[f] = vertexSteiner[v[a]] || vertexSteiner[v[a + 1]] || vertexSteiner[v[a + 2]] ? 1 : 0;
    }
  }
  // Order: measured faces, then Steiner faces; polygons that are not triangles are skipped.
  const order = new Uint32Array(triangles);
  let measured = 0;
  for (let f = 0; f < nIn; ++f) if (list.offsets[f + 1] - list.offsets[f] === 3 && !steiner[f]) order[measured++] = f;
  let at = measured;
  for (let f = 0; f < nIn; ++f) if (list.offsets[f + 1] - list.offsets[f] === 3 && steiner[f]) order[at++] = f;

  const positions = new Float32Array(9 * triangles);
  const normals = new Float32Array(3 * triangles);  // one per face: the page bakes flat shading into colours
  const v = list.values;
  for (let i = 0; i < triangles; ++i) {
    const base = list.offsets[order[i]];
    const p = [];
    for (let c = 0; c < 3; ++c) {
      const id = v[base + c];
      const px = x[id] - o[0], py = y[id] - o[1], pz = z[id] - o[2];
      positions[9 * i + 3 * c] = px; positions[9 * i + 3 * c + 1] = py; positions[9 * i + 3 * c + 2] = pz;
      p.push(px, py, pz);
    }
    const ux = p[3] - p[0], uy = p[4] - p[1], uz = p[5] - p[2];
    const wx = p[6] - p[0], wy = p[7] - p[1], wz = p[8] - p[2];
    let nx = uy * wz - uz * wy, ny = uz * wx - ux * wz, nz = ux * wy - uy * wx;
    const len = Math.hypot(nx, ny, nz) || 1;
    normals[3 * i] = nx / len; normals[3 * i + 1] = ny / len; normals[3 * i + 2] = nz / len;
  }
  // Per-face layers in the same order; flags stay flags.
  const layers = {};
  const flags = {};
  for (const p of face.properties) {
    if (p.list) continue;
    const source = face.scalars[p.name];
    const out = FLAG_PROPERTIES.has(p.name) ? new Uint8Array(triangles) : new Float32Array(triangles);
    for (let i = 0; i < triangles; ++i) out[i] = source[order[i]];
    (FLAG_PROPERTIES.has(p.name) ? flags : layers)[p.name] = out;
  }
  const transfer = [positions.buffer, normals.buffer];
  for (const a of Object.values(layers)) transfer.push(a.buffer);
  for (const a of Object.values(flags)) transfer.push(a.buffer);
  return {
    result: { origin: o, faces: triangles, measured, positions, normals, layers, flags,
      comments: ply.comments, skippedPolygons: nIn - triangles },
    transfer,
  };
}

function buildPoints(ply, origin) {
  const vertex = ply.element('vertex');
  if (!vertex) throw new Error('PLY without vertex element');
  const { x, y, z } = vertex.scalars;
  const o = origin || centreOf(x, y, z);
  const positions = new Float32Array(3 * vertex.count);
  for (let i = 0; i < vertex.count; ++i) {
    positions[3 * i] = x[i] - o[0]; positions[3 * i + 1] = y[i] - o[1]; positions[3 * i + 2] = z[i] - o[2];
  }
  const first = vertex.scalars.first_keyframe ? Uint32Array.from(vertex.scalars.first_keyframe) : null;
  const transfer = [positions.buffer];
  if (first) transfer.push(first.buffer);
  return { result: { origin: o, count: vertex.count, positions, firstKeyframe: first }, transfer };
}

self.onmessage = async (event) => {
  const { id, url, kind, origin } = event.data;
  try {
    const response = await fetch(url);
    if (!response.ok) throw new Error(`${url}: HTTP ${response.status}`);
    const ply = parsePly(await response.arrayBuffer());
    const { result, transfer } = kind === 'points' ? buildPoints(ply, origin) : buildMesh(ply, origin);
    self.postMessage({ id, ok: true, result }, transfer);
  } catch (error) {
    self.postMessage({ id, ok: false, error: `${url}: ${error.message}` });
  }
};

// Loads a run folder through the server: the manifest, text files, and PLYs parsed in a worker.
import { parseCsv, parseFlatYaml } from './csv.js';

export class RunLoader {
  constructor() {
    this.worker = new Worker(new URL('./ply_worker.js', import.meta.url), { type: 'module' });
    this.pending = new Map();
    this.nextId = 1;
    this.worker.onmessage = (event) => {
      const { id, ok, result, error } = event.data;
      const entry = this.pending.get(id);
      this.pending.delete(id);
      if (ok) entry.resolve(result); else entry.reject(new Error(error));
    };
  }

  /** Parses a PLY in the worker: kind 'mesh' (triangles and face layers) or 'points'. */
  ply(url, kind, origin) {
    const id = this.nextId++;
    return new Promise((resolve, reject) => {
      this.pending.set(id, { resolve, reject });
      this.worker.postMessage({ id, url, kind, origin });
    });
  }

  async text(url) {
    const response = await fetch(url);
    if (!response.ok) throw new Error(`${url}: HTTP ${response.status}`);
    return response.text();
  }

  async manifest() { return JSON.parse(await this.text('api/manifest')); }
  async csv(url) { return parseCsv(await this.text(url)); }
  async yaml(url) { return parseFlatYaml(await this.text(url)); }

  /** voxels.bin (docs/viewer.md): "TMVOXEL1", uint32 count, uint32 0, count x float32[4]. */
  async voxels(url) {
    const response = await fetch(url);
    if (!response.ok) throw new Error(`${url}: HTTP ${response.status}`);
    const buffer = await response.arrayBuffer();
    const magic = new TextDecoder().decode(new Uint8Array(buffer, 0, Math.min(8, buffer.byteLength)));
    if (magic !== 'TMVOXEL1') throw new Error(`${url}: not a voxels.bin (magic "${magic}")`);
    const count = new DataView(buffer).getUint32(8, true);
    if (buffer.byteLength < 16 + 16 * count) throw new Error(`${url}: truncated (${count} voxels announced)`);
    return { count, data: new Float32Array(buffer.slice(16, 16 + 16 * count)) };
  }
}

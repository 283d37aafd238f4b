// Frame-rate benchmark of the viewer in headless chromium with SwiftShader (software WebGL):
// synthetic run folders whose mesh.ply is a wavy height field of N faces, each loaded in the
// page and turned for a few seconds. Prints faces, load time (page open to map drawn) and frames
// per second at full resolution and at the half resolution used while the user drags: measured
// (wall clock, so it depends on what else runs on the machine) and from CPU time (frames per CPU
// second of chromium's whole process tree: what one otherwise idle core would give, whatever
// the load; SwiftShader may use more than one core, so an idle machine can do better).
// Usage (from the build tree's tests/viewer/npm, see docs/viewer.md):
//   TERRAMESH_VIEWER_TEST_MODULES=$PWD/node_modules node SOURCE/tests/viewer/bench_fps.mjs \
//       BUILD/apps/terramesh/terramesh [FACES ...]
import { mkdtempSync, rmSync, writeFileSync, mkdirSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { chromiumCpuSeconds, launchBrowser, openViewer, startServer, stopServer } from './harness.mjs';
import { loadavg } from 'node:os';

const [binary, ...sizes] = process.argv.slice(2);
if (!binary) {
  console.error('usage: node bench_fps.mjs TERRAMESH_BIN [FACES ...]');
  process.exit(2);
}
const faceCounts = sizes.length ? sizes.map(Number) : [100000, 250000, 500000, 1000000, 2000000];
const seconds = Number(process.env.TERRAMESH_FPS_SECONDS || 4);

/** A binary PLY grid of about `faces` triangles over 100 x 100 map units, 1/8 of it Steiner. */
function gridPly(faces) {
  const n = Math.max(2, Math.round(Math.sqrt(faces / 2)));
  const vertices = (n + 1) * (n + 1);
  const header = `ply\nformat binary_little_endian 1.0\nelement vertex ${vertices}\n` +
    'property double x\nproperty double y\nproperty double z\nproperty uchar steiner\n' +
    `element face ${2 * n * n}\nproperty list uchar uint vertex_indices\nend_header\n`;
  const body = Buffer.alloc(vertices * 25 + 2 * n * n * 13);
  let at = 0;
  for (let j = 0; j <= n; ++j) {
    for (let i = 0; i <= n; ++i) {
      const x = (100 * i) / n, y = (100 * j) / n;
      body.writeDoubleLE(x, at); body.writeDoubleLE(y, at + 8);
      body.writeDoubleLE(2 * Math.sin(x / 7) * Math.cos(y / 9), at + 16);
      body[at + 24] = j > (7 * n) / 8 ? 1 : 0;
      at += 25;
    }
  }
  for (let j = 0; j < n; ++j) {
    for (let i = 0; i < n; ++i) {
      const a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      for (const [p, q, r] of [[a, b, d], [a, d, c]]) {
        body[at] = 3; body.writeUInt32LE(p, at + 1); body.writeUInt32LE(q, at + 5); body.writeUInt32LE(r, at + 9);
        at += 13;
      }
    }
  }
  return { bytes: Buffer.concat([Buffer.from(header, 'latin1'), body]), faces: 2 * n * n };
}

const work = mkdtempSync(join(tmpdir(), 'terramesh-viewer-bench-'));
const browser = await launchBrowser();
console.log(`load average at start: ${loadavg().map((l) => l.toFixed(1)).join(' ')}`);
console.log('faces      ply_MB  load_s  fps  fps_cpu  fps_drag  fps_drag_cpu  (SwiftShader; canvas 1100x570, while dragging 550x285; all faces shown)');
try {
  for (const target of faceCounts) {
    const run = join(work, `run_${target}`);
    mkdirSync(run);
    const { bytes, faces } = gridPly(target);
    writeFileSync(join(run, 'mesh.ply'), bytes);
    const server = await startServer(binary, run);
    try {
      const start = performance.now();
      const { page, errors } = await openViewer(browser.context, server.url, 600000);
      const load = (performance.now() - start) / 1000;
      await page.evaluate(() => window.terramesh.setOption('showSteiner', true));
      const measure = async (dragging) => {
        const cpu0 = chromiumCpuSeconds(browser.profile);
        const r = await page.evaluate(([s, d]) => window.terramesh.measureFps(s, true, d), [seconds, dragging]);
        return { fps: r.fps, cpuFps: r.frames / Math.max(0.01, chromiumCpuSeconds(browser.profile) - cpu0) };
      };
      const full = await measure(false);
      const drag = await measure(true);
      const f = (x, w) => x.toFixed(1).padStart(w);
      console.log(`${String(faces).padEnd(10)} ${f(bytes.length / 1e6, 6)}  ${f(load, 6)}  ${f(full.fps, 5)}  ${f(full.cpuFps, 6)}  ${f(drag.fps, 7)}  ${f(drag.cpuFps, 10)}` +
        (errors.length ? `  errors: ${errors.join('; ')}` : ''));
      await page.close();
    } finally {
      stopServer(server);
    }
    rmSync(run, { recursive: true, force: true });
  }
  console.log(`load average at end: ${loadavg().map((l) => l.toFixed(1)).join(' ')}`);
} finally {
  await browser.close();
  rmSync(work, { recursive: true, force: true });
}

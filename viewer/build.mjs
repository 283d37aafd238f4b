// Bundles the viewer: node build.mjs SOURCE_DIR OUT_DIR, run from the build tree's npm folder
// (viewer/CMakeLists.txt), whose node_modules holds three, lil-gui, uplot and esbuild.
import { build } from 'esbuild';
import { copyFileSync, mkdirSync } from 'node:fs';
import { dirname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';

const [sourceDir, outDir] = process.argv.slice(2).map((p) => resolve(p));
if (!sourceDir || !outDir) {
  console.error('usage: node build.mjs SOURCE_DIR OUT_DIR');
  process.exit(2);
}
const nodeModules = join(dirname(fileURLToPath(import.meta.url)), 'node_modules');
mkdirSync(outDir, { recursive: true });
await build({
  entryPoints: { main: join(sourceDir, 'src/main.js'), ply_worker: join(sourceDir, 'src/ply_worker.js') },
  bundle: true,
  format: 'esm',
  target: 'es2020',
  minify: true,
  sourcemap: false,
  nodePaths: [nodeModules],
  outdir: outDir,
  logLevel: 'warning',
  legalComments: 'linked',
});
copyFileSync(join(sourceDir, 'index.html'), join(outDir, 'index.html'));

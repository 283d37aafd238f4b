// Shared by the viewer tests and the frame-rate benchmark: runs `terramesh view` on a run folder
// and drives Debian's chromium (no browser download) through playwright-core.
import { spawn } from 'node:child_process';
import { mkdtempSync, readFileSync, readdirSync, rmSync } from 'node:fs';
import { createRequire } from 'node:module';
import { tmpdir } from 'node:os';
import { join } from 'node:path';

export const CHROMIUM = process.env.TERRAMESH_CHROMIUM || '/usr/bin/chromium';
export const CHROMIUM_ARGS = [
  '--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
  '--disable-background-networking', '--disable-component-update', '--disable-sync',
  // WebGL on the CPU: SwiftShader (newer Chromium wants it asked for explicitly).
  '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
];

/** playwright-core from the build tree's npm folder (tests/viewer/CMakeLists.txt). */
export function playwright() {
  const modules = process.env.TERRAMESH_VIEWER_TEST_MODULES;
  if (!modules) throw new Error('TERRAMESH_VIEWER_TEST_MODULES is not set (run through ctest)');
  return createRequire(join(modules, 'package.json'))('playwright-core');
}

/**
 * Starts `terramesh view DIR --port 0 ...` (with `--bundle $TERRAMESH_VIEWER_BUNDLE` when set);
 * resolves {url, port, process} once it prints its URL.
 */
export function startServer(binary, runDir, extraArgs = []) {
  const bundle = process.env.TERRAMESH_VIEWER_BUNDLE ? ['--bundle', process.env.TERRAMESH_VIEWER_BUNDLE] : [];
  return new Promise((resolve, reject) => {
    const child = spawn(binary, ['view', runDir, '--port', '0', ...bundle, ...extraArgs], { stdio: ['ignore', 'pipe', 'pipe'] });
    let output = '';
    const timer = setTimeout(() => reject(new Error(`terramesh view printed no URL in 60 s:\n${output}`)), 60000);
    const onData = (chunk) => {
      output += chunk.toString();
      const match = output.match(/http:\/\/127\.0\.0\.1:(\d+)\//);
      if (match) {
        clearTimeout(timer);
        resolve({ url: match[0], port: Number(match[1]), process: child, output: () => output });
      }
    };
    child.stdout.on('data', onData);
    child.stderr.on('data', onData);
    child.on('exit', (code) => { clearTimeout(timer); reject(new Error(`terramesh view exited with ${code}:\n${output}`)); });
  });
}

export function stopServer(server) {
  if (server && server.process.exitCode === null) {
    server.process.removeAllListeners('exit');
    server.process.kill('SIGTERM');
  }
}

/** A fresh headless chromium profile; returns {context, profile, close}. */
export async function launchBrowser() {
  const profile = mkdtempSync(join(tmpdir(), 'terramesh-chromium-'));
  const { chromium } = playwright();
  const context = await chromium.launchPersistentContext(profile, {
    executablePath: CHROMIUM, headless: true, args: CHROMIUM_ARGS,
    viewport: { width: 1100, height: 800 },
  });
  return {
    context,
    profile,
    close: async () => { await context.close(); rmSync(profile, { recursive: true, force: true }); },
  };
}

/** Opens the viewer and waits until it has drawn the final map; collects console errors. */
export async function openViewer(context, url, timeoutMs = 120000) {
  const page = await context.newPage();
  const errors = [];
  page.on('console', (message) => { if (message.type() === 'error') errors.push(message.text()); });
  page.on('pageerror', (error) => errors.push(String(error)));
  page.on('requestfailed', (request) => errors.push(`request failed: ${request.url()}`));
  await page.goto(url);
  await page.waitForFunction(() => document.body.dataset.ready, null, { timeout: timeoutMs });
  const ready = await page.evaluate(() => document.body.dataset.ready);
  if (ready !== 'true') throw new Error(`viewer failed: ${await page.textContent('#status')}; ${errors.join('; ')}`);
  return { page, errors };
}

/**
 * `terramesh view DIR` with a fresh browser on its page: resolves {server, browser, viewer}
 * (viewer: openViewer's {page, errors}).
 */
export async function startSession(binary, dir, serverArgs = []) {
  const server = await startServer(binary, dir, serverArgs);
  const browser = await launchBrowser();
  return { server, browser, viewer: await openViewer(browser.context, server.url) };
}

/** Ends what startSession started (whatever of it started) and removes the folder `work`. */
export async function endSession(session, work) {
  if (session.browser) await session.browser.close();
  stopServer(session.server);
  if (work) rmSync(work, { recursive: true, force: true });
}

/** Waits for two animation frames (the on-demand render and its compositing). */
export async function settle(page) {
  await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
}

/**
 * CPU seconds (user + system) used so far by the chromium started with `profile` and all its
 * descendants (renderer, GPU process with SwiftShader, utilities), from /proc; for the frame-rate
 * benchmark on a shared machine, where wall time depends on the other users.
 */
export function chromiumCpuSeconds(profile) {
  const ticksPerSecond = 100;  // USER_HZ on Linux
  const procs = new Map();
  for (const pid of readdirSync('/proc').filter((name) => /^\d+$/.test(name))) {
    try {
      const stat = readFileSync(`/proc/${pid}/stat`, 'latin1');
      const fields = stat.slice(stat.lastIndexOf(')') + 2).split(' ');
      // fields[1] = ppid, fields[11] = utime, fields[12] = stime (stat fields 4, 14, 15)
      procs.set(pid, { ppid: fields[1], ticks: Number(fields[11]) + Number(fields[12]),
        root: readFileSync(`/proc/${pid}/cmdline`, 'latin1').includes(`--user-data-dir=${profile}`) });
    } catch {
      // the process ended between the listing and the read
    }
  }
  const inTree = (pid, depth = 0) => {
    const p = procs.get(pid);
    return Boolean(p) && depth < 64 && (p.root || inTree(p.ppid, depth + 1));
  };
  let ticks = 0;
  for (const [pid, p] of procs) if (inTree(pid)) ticks += p.ticks;
  return ticks / ticksPerSecond;
}

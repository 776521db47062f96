// Fixtures of the studio's browser tests. `studio`: a temporary copy of
// missions/ (plus the test's own files) served by its own `strata studio`
// on a loopback port the server picks, stopped by its pid after the test.
// `page`: a tab on that studio that reaches nothing but loopback, accepts
// dialogs unless a test says otherwise, and fails the test on any uncaught
// error in the page.
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { spawn, spawnSync } from 'node:child_process';
import { fileURLToPath } from 'node:url';
import { test as base, expect } from '@playwright/test';
import { patient } from './patience.mjs';

export { patient };

const here = path.dirname(fileURLToPath(import.meta.url));
export const repo = path.resolve(here, '..', '..');
export const STRATA = path.resolve(process.env.STRATA || path.join(repo, 'build', 'dev', 'strata'));
export const OUT = path.resolve(process.env.STRATA_E2E_OUT || path.join(repo, 'build', 'dev', 'tests', 'e2e-artifacts'));
const WEB_ROOT = process.env.STRATA_WEB_ROOT ? path.resolve(process.env.STRATA_WEB_ROOT) : null;
export const TANK = 'missions/tank/tank.coral';
export const STUCK = 'stuck_phase.coral';

fs.mkdirSync(OUT, { recursive: true });

// A figure for the report (not an assertion): printed and kept in OUT/figures.txt.
export function figure(name, value) {
  const line = `figure: ${name}: ${value}`;
  console.log(line);
  fs.appendFileSync(path.join(OUT, 'figures.txt'), `${new Date().toISOString()} ${line}\n`);
}

async function startStudio(dir) {
  const args = ['studio', dir, '--listen', '127.0.0.1:0', ...(WEB_ROOT ? ['--web-root', WEB_ROOT] : [])];
  // No LeakSanitizer scan at the studio's exit (a sanitizer build): its exit
  // is not checked here (stopped by TERM, then KILL), and the scan of its
  // heap held each test's teardown 0.1-1 s. Leaks are the server tests' to
  // find (studio_test, in-process).
  const env = { ...process.env, ASAN_OPTIONS: [process.env.ASAN_OPTIONS, 'detect_leaks=0'].filter(Boolean).join(':') };
  const proc = spawn(STRATA, args, { env, stdio: ['ignore', 'pipe', 'pipe'] });
  let err = '';
  proc.stderr.on('data', (c) => { err += c; if (err.length > 20000) err = err.slice(-10000); });
  const url = await new Promise((resolve, reject) => {
    let buf = '';
    const t = setTimeout(() => reject(new Error(`no URL from strata studio in ${patient(15)} s; stderr: ${err.slice(-500)}`)),
      patient(15000));
    proc.stdout.on('data', (c) => {
      buf += c;
      if (!buf.includes('\n')) return;
      clearTimeout(t);
      const m = /^(http:\/\/127\.0\.0\.1:\d+)/.exec(buf.split('\n')[0].trim());
      m ? resolve(m[1]) : reject(new Error(`first line is not a URL: ${buf.split('\n')[0]}`));
    });
    proc.once('exit', (code) => { clearTimeout(t); reject(new Error(`strata studio exited ${code}: ${err.slice(-500)}`)); });
  });
  return { proc, url, stderr: () => err };
}

// Stops the process by its pid: TERM, then KILL after 5 s.
async function stopPid(proc) {
  if (proc.exitCode !== null || proc.signalCode !== null) return;
  const gone = new Promise((r) => proc.once('exit', r));
  try { process.kill(proc.pid, 'SIGTERM'); } catch { return; }
  const t = setTimeout(() => { try { process.kill(proc.pid, 'SIGKILL'); } catch { /* gone */ } }, 5000);
  await gone;
  clearTimeout(t);
}

export const test = base.extend({
  // Files the test wants in the folder before the studio starts: {relative path: text}.
  files: [{}, { option: true }],
  studio: async ({ files }, use) => {
    const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'strata-e2e-'));
    fs.cpSync(path.join(repo, 'missions'), path.join(dir, 'missions'), { recursive: true });
    fs.copyFileSync(path.join(repo, 'tests', 'verify', 'stuck_phase.coral'), path.join(dir, STUCK));
    for (const [p, text] of Object.entries(files)) {
      fs.mkdirSync(path.dirname(path.join(dir, p)), { recursive: true });
      fs.writeFileSync(path.join(dir, p), text);
    }
    const s = await startStudio(dir);
    try {
      await use({
        url: s.url, dir, pid: s.proc.pid,
        file: (p) => path.join(dir, p),
        read: (p) => fs.readFileSync(path.join(dir, p), 'utf8'),
        write: (p, text) => fs.writeFileSync(path.join(dir, p), text),
        // A finished lockstep run's log, for replay. With maxSimTime the run
        // is cut there (an abort, exit 1): a long mission's first part is
        // log enough. No wall-clock limit of its own: the test's bounds it.
        runLog(mission, log, maxSimTime) {
          const args = ['run', path.join(dir, mission), '--log', path.join(dir, log)];
          if (maxSimTime) args.push('--max-sim-time', String(maxSimTime));
          const r = spawnSync(STRATA, args, { encoding: 'utf8' });
          const ok = r.status === 0 || (maxSimTime && r.status === 1);
          if (!ok) throw new Error(`strata run ${mission}: exit ${r.status}: ${(r.stderr || '').slice(-400)}`);
        },
      });
    } finally {
      await stopPid(s.proc);
      fs.rmSync(dir, { recursive: true, force: true });
    }
  },
  page: async ({ page, studio }, use) => {
    const errors = [];
    page.on('pageerror', (e) => errors.push(e.message));
    page.on('dialog', (d) => d.accept());
    // Loopback only: the browser refuses any other host (playwright.config.mjs).
    page.studio = studio;
    await use(page);
    // The tabs closed before their studio is stopped, as a user would: an
    // idle keep-alive connection from the browser held the studio's stop()
    // (cpp-httplib 0.11 waits out its 5 s keep-alive timeout) and the test
    // with it, 0.5-4.5 s a test.
    await page.context().close();
    expect(errors, 'uncaught errors in the page').toEqual([]);
  },
});
export { expect };

// ------------------------------------------------------------ helpers in the page

// The value of expr, evaluated with s = window.__studio and cy = window.__cy.
export const studio = (page, expr) => page.evaluate(`(() => { const s = window.__studio, cy = window.__cy; return ${expr}; })()`);

// Waits (polling, bounded: patient(ms), patience.mjs) until expr is true in the page.
export async function waitFor(page, expr, ms = 10000, what) {
  try {
    await page.waitForFunction(`(() => { const s = window.__studio, cy = window.__cy; try { return !!(${expr}); } catch { return false; } })()`, null, { timeout: patient(ms), polling: 50 });
  } catch {
    const err = await studio(page, 's && s.lastError').catch(() => null);
    throw new Error(`timed out after ${patient(ms)} ms waiting for ${what || expr}${err ? `; page error: ${err}` : ''}`);
  }
}

// Opens the page and a file from the list; waits until its net is drawn.
export async function openPage(page, file = TANK, net = null) {
  await page.goto(page.studio.url);
  await page.locator(`#file-list li[data-path="${file}"]`).click();
  await waitFor(page, `s.path === '${file}' && s.busy === 0 && cy.nodes().length > 0${net ? ` && s.net === '${net}'` : ''}`, 15000, `${file} drawn`);
}

// The rendered position of a node, in page coordinates.
export async function nodePoint(page, id) {
  const p = await page.evaluate((id) => { const n = window.__cy.getElementById(id); return n.nonempty() ? n.renderedPosition() : null; }, id);
  if (!p) throw new Error(`no node ${id} on the canvas`);
  const box = await page.locator('#cy').boundingBox();
  return { x: box.x + p.x, y: box.y + p.y };
}

#!/usr/bin/env node
// End-to-end test of the studio page: Debian's chromium driven by
// playwright-core against `strata studio DIR --port 0`.
// DIR is a temporary copy of missions/, so saves never touch the repository.
//
// usage: node web/e2e/studio.e2e.mjs --strata PATH_TO_STRATA --out ARTIFACT_DIR
//          [--web-root DIR] [--headed] [--keep] [--verbose]
// Exits 0 when every check passed; prints one line per check and a summary
// `e2e: N passed, M failed`.
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { spawn, spawnSync } from 'node:child_process';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';

const here = path.dirname(fileURLToPath(import.meta.url));
const repo = path.resolve(here, '..', '..');
const argv = process.argv.slice(2);
const opt = (name, def) => { const i = argv.indexOf(name); return i >= 0 && i + 1 < argv.length ? argv[i + 1] : def; };
const flag = (name) => argv.includes(name);
const STRATA = path.resolve(opt('--strata', path.join(repo, 'build', 'dev', 'strata')));
const OUT = path.resolve(opt('--out', path.join(os.tmpdir(), 'strata-e2e')));
// The page under test: the one built into strata, or --web-root DIR.
const WEB_ROOT = opt('--web-root', null);
const CHROMIUM = opt('--chromium', '/usr/bin/chromium');
const TOTAL_MS = 85000;
const T0 = Date.now();

fs.mkdirSync(OUT, { recursive: true });
const results = [];
let server = null, browser = null, dir = null;

function log(...a) { console.log(`[${((Date.now() - T0) / 1000).toFixed(1)}s]`, ...a); }

async function cleanup() {
  try { if (browser) await Promise.race([browser.close(), new Promise((r) => setTimeout(r, 5000))]); } catch { /* closing */ }
  if (server && server.exitCode === null) {
    try { server.kill('SIGTERM'); } catch { /* gone */ }
    await new Promise((r) => { const t = setTimeout(() => { try { server.kill('SIGKILL'); } catch { /* gone */ } r(); }, 3000); server.once('exit', () => { clearTimeout(t); r(); }); });
  }
  if (dir && !flag('--keep')) fs.rmSync(dir, { recursive: true, force: true });
}

function summary() {
  const passed = results.filter((r) => r.ok).length;
  const failed = results.length - passed;
  console.log(`e2e: ${passed} passed, ${failed} failed`);
  return failed;
}

const watchdog = setTimeout(async () => {
  console.log(`FAIL  whole run: over ${TOTAL_MS / 1000} s`);
  results.push({ name: 'time limit', ok: false });
  summary();
  await cleanup();
  process.exit(1);
}, TOTAL_MS);

async function check(name, fn) {
  const t = Date.now();
  try {
    const detail = await fn();
    results.push({ name, ok: true });
    console.log(`ok    ${name}${detail ? ` — ${detail}` : ''} (${Date.now() - t} ms)`);
    return true;
  } catch (e) {
    results.push({ name, ok: false });
    console.log(`FAIL  ${name}: ${e && e.message ? e.message.split('\n').slice(0, 6).join('\n      ') : e}`);
    return false;
  }
}

function assert(c, m) { if (!c) throw new Error(m); }

// ---------------------------------------------------------------- server
function hasStudio() {
  if (!fs.existsSync(STRATA)) return false;
  const r = spawnSync(STRATA, ['studio', '--help'], { encoding: 'utf8', timeout: 10000 });
  return r.status === 0 && /studio/i.test(r.stdout) && /--port/.test(r.stdout);
}

function startServer(real) {
  if (!real) throw new Error(`${STRATA} has no working 'studio' command`);
  const cmd = STRATA;
  const args = ['studio', dir, '--port', '0', ...(WEB_ROOT ? ['--web-root', path.resolve(WEB_ROOT)] : [])];
  server = spawn(cmd, args, { stdio: ['ignore', 'pipe', 'pipe'] });
  let errText = '';
  server.stderr.on('data', (c) => { errText += c; if (flag('--verbose')) process.stderr.write(c); });
  return new Promise((resolve, reject) => {
    let buf = '';
    const t = setTimeout(() => reject(new Error(`no URL from the server in 15 s; stderr: ${errText.slice(-500)}`)), 15000);
    server.stdout.on('data', (c) => {
      buf += c;
      const line = buf.split('\n')[0];
      if (buf.includes('\n')) {
        clearTimeout(t);
        const m = /^(http:\/\/127\.0\.0\.1:\d+)/.exec(line.trim());
        m ? resolve(m[1]) : reject(new Error(`first line is not a URL: ${line}`));
      }
    });
    server.once('exit', (code) => { clearTimeout(t); reject(new Error(`server exited ${code}: ${errText.slice(-500)}`)); });
  });
}

// ---------------------------------------------------------------- helpers in the page
const studio = (page, expr) => page.evaluate(`(() => { const s = window.__studio; return ${expr}; })()`);
async function waitFor(page, expr, ms, what) {
  try {
    await page.waitForFunction(`(() => { const s = window.__studio, cy = window.__cy; try { return !!(${expr}); } catch { return false; } })()`, null, { timeout: ms, polling: 50 });
  } catch {
    const err = await studio(page, 's && s.lastError').catch(() => null);
    throw new Error(`timed out after ${ms} ms waiting for ${what || expr}${err ? `; page error: ${err}` : ''}`);
  }
}
// The rendered position of a node, in page coordinates.
async function nodePoint(page, id) {
  const p = await page.evaluate((id) => { const n = window.__cy.getElementById(id); return n.nonempty() ? n.renderedPosition() : null; }, id);
  assert(p, `no node ${id} on the canvas`);
  const box = await page.locator('#cy').boundingBox();
  return { x: box.x + p.x, y: box.y + p.y };
}

// The node's point once the canvas has settled (a layout animating or the
// canvas resizing moves it): two reads 100 ms apart that agree, 4 s at most.
async function stablePoint(page, id) {
  let p = await nodePoint(page, id);
  for (let i = 0; i < 40; i++) {
    await page.waitForTimeout(100);
    const q = await nodePoint(page, id);
    if (Math.abs(q.x - p.x) < 0.5 && Math.abs(q.y - p.y) < 0.5) return q;
    p = q;
  }
  return p;
}

// ---------------------------------------------------------------- the tests
async function main() {
  dir = fs.mkdtempSync(path.join(os.tmpdir(), 'strata-e2e-'));
  fs.cpSync(path.join(repo, 'missions'), path.join(dir, 'missions'), { recursive: true });
  const TANK = 'missions/tank/tank.coral';
  // A phase that fails verification, for the counterexample player.
  const STUCK = 'stuck_phase.coral';
  fs.copyFileSync(path.join(repo, 'tests', 'verify', 'stuck_phase.coral'), path.join(dir, STUCK));
  const tankFile = path.join(dir, TANK);
  // A phase file two tabs edit at once (issue 17: the second save dropped
  // the first's change).
  const TABS = 'missions/tank/two_tabs.coral';
  fs.copyFileSync(path.join(dir, 'missions/tank/initialize.coral'), path.join(dir, TABS));

  // A finished run's log, for replay (lockstep, a fraction of a second).
  let haveLog = false;
  if (fs.existsSync(STRATA)) {
    const r = spawnSync(STRATA, ['run', tankFile, '--log', path.join(dir, 'tank-run.jsonl')], { encoding: 'utf8', timeout: 30000 });
    haveLog = r.status === 0 && fs.existsSync(path.join(dir, 'tank-run.jsonl'));
  }

  const real = hasStudio();
  let url;
  const okServer = await check('server starts (strata studio)', async () => {
    url = await startServer(real);
    return url;
  });
  if (!okServer) return;

  const pageErrors = [];
  await check('chromium starts', async () => {
    browser = await chromium.launch({
      executablePath: CHROMIUM, headless: !flag('--headed'), timeout: 20000,
      args: ['--no-sandbox', '--disable-gpu', '--disable-background-networking', '--disable-component-update', '--disable-sync', '--no-first-run'],
    });
    return CHROMIUM;
  });
  if (!browser) return;
  const context = await browser.newContext({ viewport: { width: 1500, height: 950 } });
  // Loopback only: any other host is refused.
  await context.route((u) => !/^http:\/\/127\.0\.0\.1[:/]/.test(u.toString()) && !u.toString().startsWith('data:'), (route) => route.abort());
  const page = await context.newPage();
  page.setDefaultTimeout(10000);
  page.on('pageerror', (e) => pageErrors.push(e.message));
  page.on('dialog', (d) => d.accept());

  const opened = await check('open the tank mission: the mission net and its phases are drawn', async () => {
    await page.goto(url, { timeout: 15000 });
    await page.locator(`#file-list li[data-path="${TANK}"]`).click({ timeout: 10000 });
    await waitFor(page, `s.path === '${TANK}' && s.net === 'tank' && cy.nodes().length > 5`, 10000, 'the tank net on the canvas');
    const info = await page.evaluate(() => {
      const cy = window.__cy;
      const s = window.__studio;
      return {
        nets: s.model.nets.map((n) => n.name),
        begin: cy.getElementById('p:begin').data('tokens'),
        exitClosed: cy.getElementById('p:closed').hasClass('exit'),
        phase1: cy.getElementById('t:phase1').data('label'),
        netList: [...document.querySelectorAll('#net-list li')].map((li) => li.dataset.net),
      };
    });
    for (const n of ['tank', 'initialize', 'dive_from_surface', 'submerge_to_depth', 'return_to_surface']) assert(info.nets.includes(n) && info.netList.includes(n), `net ${n} missing: ${info.netList}`);
    assert(info.begin === 1, `begin holds ${info.begin} tokens, not 1`);
    assert(info.exitClosed, 'exit closed is not drawn as an exit');
    assert(/PHASE initialize/.test(info.phase1), `phase1 label: ${info.phase1}`);
    // A phase net from the list.
    await page.locator('#net-list li[data-net="dive_from_surface"]').click();
    await waitFor(page, "s.net === 'dive_from_surface' && cy.getElementById('t:check_depth').nonempty()", 5000, 'phase 2 drawn');
    const lab = await page.evaluate(() => window.__cy.getElementById('t:check_depth').data('label'));
    assert(/ASK depth_reached/.test(lab), `check_depth label: ${lab}`);
    await page.locator('#net-list li[data-net="tank"]').click();
    await waitFor(page, "s.net === 'tank'", 5000);
    return `${info.nets.length} nets`;
  });
  if (!opened) return;

  await check('add a place from the toolbar', async () => {
    await page.locator('#new-name').fill('logbook');
    await page.locator('#btn-add-place').click();
    await waitFor(page, "cy.getElementById('p:logbook').nonempty() && s.dirty && s.busy === 0", 10000, 'place logbook');
    assert(/\blogbook\b/.test(await studio(page, 's.text')), 'the text has no logbook');
    assert(!(await page.locator('#dirty-mark').isHidden()), 'unsaved state not shown');
    return 'logbook';
  });

  let arcHow = '';
  await check('draw an arc shutdown -> logbook with edgehandles (place-place refused)', async () => {
    await page.locator('button.mode[data-mode="arc"]').click();
    // Refused: place to place.
    let a = await stablePoint(page, 'p:logbook'), b = await stablePoint(page, 'p:begin');
    await page.mouse.move(a.x, a.y); await page.mouse.down();
    await page.mouse.move((a.x + b.x) / 2, (a.y + b.y) / 2, { steps: 5 }); await page.mouse.move(b.x, b.y, { steps: 5 });
    await page.mouse.up();
    await page.waitForTimeout(300);
    assert(await studio(page, "window.__cy.edges('[source = \"p:logbook\"]').empty() && !/wait\\s*\\{[^}]*\\blogbook\\b/.test(s.text)"), 'the refused drag drew an arc from logbook');
    // Accepted: transition to place.
    a = await stablePoint(page, 't:shutdown'); b = await stablePoint(page, 'p:logbook');
    await page.mouse.move(a.x, a.y); await page.mouse.down();
    await page.mouse.move((a.x + b.x) / 2, (a.y + b.y) / 2, { steps: 8 }); await page.mouse.move(b.x, b.y, { steps: 8 });
    await page.mouse.up();
    await waitFor(page, "cy.getElementById('a:t:shutdown>p:logbook').nonempty() && s.busy === 0", 6000, 'the dragged arc shutdown -> logbook');
    arcHow = 'dragged with edgehandles';
    await page.locator('button.mode[data-mode="select"]').click();
    return arcHow;
  });

  await check('pick a TACTIC action from the catalogue, then remove it', async () => {
    await page.locator('#btn-add-transition').click();
    await waitFor(page, "cy.getElementById('t:t1').nonempty() && s.busy === 0", 8000, 'transition t1');
    await page.evaluate(() => { window.__cy.elements().unselect(); window.__cy.getElementById('t:t1').select(); });
    await page.locator('#pick-kind').selectOption('EXEC');
    await page.locator('#pick-target').selectOption('sleep');
    await page.locator('#pick-arg-0').fill('2');
    await page.locator('#pick-out-0').selectOption('logbook');
    await page.locator('#pick-add').click();
    await waitFor(page, "/TACTIC\\(EXEC, sleep\\(2\\), logbook\\)/.test(s.text) && s.busy === 0", 8000, 'the action in the text');
    const label = await page.evaluate(() => window.__cy.getElementById('t:t1').data('label'));
    assert(/EXEC sleep\(2\)/.test(label), `label ${label}`);
    await page.evaluate(() => { window.__cy.elements().unselect(); window.__cy.getElementById('t:t1').select(); });
    await page.locator('#btn-delete').click();
    await waitFor(page, "cy.getElementById('t:t1').empty() && !/\\bt1\\b/.test(s.text) && s.busy === 0", 8000, 't1 deleted');
    return label.split('\n').join(' / ');
  });

  await check('save writes the .coral text and the layout; they read back', async () => {
    await page.locator('#btn-save').click();
    await waitFor(page, '!s.dirty && s.busy === 0', 10000, 'saved');
    const text = fs.readFileSync(tankFile, 'utf8');
    assert(/place[^;]*\blogbook\b[^;]*;/.test(text), 'no place logbook in the saved file');
    assert(/transition\s+shutdown\s*\{[^}]*\}?[\s\S]*?signal\s*\{[^}]*\blogbook\b/.test(text.slice(text.indexOf('transition shutdown'))), 'no signal { logbook } in shutdown');
    const layout = JSON.parse(fs.readFileSync(tankFile + '.layout.json', 'utf8'));
    assert(layout.tank && layout.tank.logbook && typeof layout.tank.logbook.x === 'number', 'no position of logbook in the layout');
    return `${text.length} bytes, layout of ${Object.keys(layout).length} net(s)`;
  });

  await check('reload: the place, the arc and the positions are back', async () => {
    const before = await page.evaluate(() => window.__cy.getElementById('p:logbook').position());
    await page.reload({ timeout: 15000 });
    await page.locator(`#file-list li[data-path="${TANK}"]`).click({ timeout: 10000 });
    await waitFor(page, `s.path === '${TANK}' && cy.getElementById('p:logbook').nonempty() && cy.getElementById('a:t:shutdown>p:logbook').nonempty()`, 10000, 'logbook after reload');
    const after = await page.evaluate(() => window.__cy.getElementById('p:logbook').position());
    assert(Math.abs(after.x - before.x) < 1 && Math.abs(after.y - before.y) < 1, `logbook moved: ${JSON.stringify(before)} -> ${JSON.stringify(after)}`);
    assert(!(await studio(page, 's.dirty')), 'dirty after reload');
    return `logbook at (${after.x.toFixed(0)}, ${after.y.toFixed(0)})`;
  });

  await check('two tabs save one file: the stale one gets 412, says so, and offers Reload', async () => {
    const tabs = [];
    for (let i = 0; i < 2; i++) {
      const tab = await context.newPage();
      tab.setDefaultTimeout(10000);
      tab.on('dialog', (d) => d.accept());
      await tab.goto(url, { timeout: 15000 });
      await tab.locator(`#file-list li[data-path="${TABS}"]`).click({ timeout: 10000 });
      await waitFor(tab, `s.path === '${TABS}' && s.net === 'initialize' && s.busy === 0`, 10000, `tab ${i + 1} open`);
      tabs.push(tab);
    }
    try {
      const [one, two] = tabs;
      assert(await one.evaluate(() => window.__studio.applyOp({ op: 'add_place', net: 'initialize', name: 'from_tab_one' })), 'tab one: edit refused');
      assert(await one.evaluate(() => window.__studio.save()), `tab one: save failed: ${await studio(one, 's.lastError')}`);
      assert(await two.evaluate(() => window.__studio.applyOp({ op: 'add_place', net: 'initialize', name: 'from_tab_two' })), 'tab two: edit refused');
      assert(!(await two.evaluate(() => window.__studio.save())), 'tab two: the stale save went through');
      const text = fs.readFileSync(path.join(dir, TABS), 'utf8');
      assert(/from_tab_one/.test(text) && !/from_tab_two/.test(text), 'the file does not hold tab one\'s change alone');
      const shown = await two.locator('#edit-msg').textContent();
      assert(/changed since you opened it/.test(shown), `tab two says: ${shown}`);
      await two.locator('#btn-reload').click();
      await waitFor(two, "!s.dirty && s.busy === 0 && /from_tab_one/.test(s.text)", 10000, 'tab two reloaded');
      return 'tab two refused with 412, then reloaded tab one\'s version';
    } finally {
      for (const tab of tabs) await tab.close();
    }
  });

  await check('verify lists the properties', async () => {
    await page.locator('#btn-verify').click();
    await waitFor(page, 's.verify && (s.verify.nets || s.verify.error)', 20000, 'verification');
    const v = await studio(page, 's.verify');
    assert(!v.error, v.error);
    const n = await page.locator('#verify-body li.prop').count();
    assert(n > 0, 'no property listed');
    return `${v.nets.length} nets, ${n} properties, ok=${v.ok}`;
  });

  await check('run nominal at speed 10: the live view reaches the end, the chart fills', async () => {
    await page.locator('#run-scenario').selectOption('nominal');
    await page.locator('#run-speed').fill('10');
    await page.locator('#btn-run').click();
    await waitFor(page, "s.runStatus !== 'idle'", 10000, 'the run to start');
    await waitFor(page, "s.runStatus !== 'running' && s.runEnded", 45000, 'run_end');
    const r = await page.evaluate(() => {
      const s = window.__studio;
      return { status: s.runStatus, ended: s.runEnded, tank: s.markings.tank, tele: s.telemetryCount, reports: s.reports.length, view: s.view };
    });
    assert(r.status === 'completed' && r.ended.outcome === 'completed', `run ended ${JSON.stringify(r.ended)}`);
    assert(r.tank && r.tank.closed === 1, `final marking of tank: ${JSON.stringify(r.tank)}`);
    assert(r.tele > 10, `only ${r.tele} telemetry points`);
    // The canvas shows the exact final marking of the mission net.
    await page.locator('#net-list li[data-net="tank"]').click();
    await waitFor(page, "s.net === 'tank' && cy.getElementById('p:closed').data('tokens') === 1", 5000, 'closed drawn with one token');
    const chartPts = await page.evaluate(() => document.querySelectorAll('#chart canvas').length);
    assert(chartPts > 0, 'no chart canvas');
    await page.screenshot({ path: path.join(OUT, 'studio-run.png') });
    return `exit ${r.ended.exit}, marking ${JSON.stringify(r.tank)}, ${r.tele} telemetry points, screenshot ${path.join(OUT, 'studio-run.png')}`;
  });

  if (haveLog) {
    await check('replay a mission log with the slider', async () => {
      await page.locator('#btn-refresh').click();
      await page.locator('#log-list li[data-path="tank-run.jsonl"]').click({ timeout: 8000 });
      await waitFor(page, "s.replay && s.replay.length > 10 && s.view === 'replay'", 8000, 'replay loaded');
      const n = await studio(page, 's.replay.length');
      await page.locator('#replay-slider').fill(String(n));
      await waitFor(page, 's.markings.tank && s.markings.tank.closed === 1', 5000, 'closed at the end of the replay');
      await page.locator('#replay-slider').fill('3');
      await waitFor(page, '!(s.markings.tank && s.markings.tank.closed)', 5000, 'closed empty early in the replay');
      // Previous and next step from firing to firing.
      await page.locator('#replay-slider').fill('0');
      await page.locator('#replay-next').click();
      const first = await studio(page, 's.replay.pos');
      assert(first > 0 && (await studio(page, `s.replayKinds[${first - 1}]`)) === 'fired', `next stopped at ${first}, not after a firing`);
      await page.locator('#replay-next').click();
      const second = await studio(page, 's.replay.pos');
      assert(second > first && (await studio(page, `s.replayKinds[${second - 1}]`)) === 'fired', `second next at ${second}`);
      await page.locator('#replay-prev').click();
      assert((await studio(page, 's.replay.pos')) === first, 'previous did not come back to the first firing');
      await page.locator('#replay-slider').fill(String(n));
      await page.screenshot({ path: path.join(OUT, 'studio-replay.png') });
      return `${n} events, firings at ${first} and ${second}`;
    });
  }

  await check('a counterexample plays on its net', async () => {
    await page.locator('#btn-refresh').click();
    await page.locator(`#file-list li[data-path="${STUCK}"]`).click({ timeout: 8000 });
    await waitFor(page, `s.path === '${STUCK}' && cy.getElementById('p:not_reached').nonempty()`, 10000, 'stuck_phase open');
    await page.locator('#btn-verify').click();
    await waitFor(page, 's.verify && s.verify.nets && s.verify.nets.some((n) => n.name === "stuck_phase")', 20000, 'verification of stuck_phase');
    const play = page.locator('#verify-body li.prop[data-key="no_deadlock"] button.play-cex');
    await play.click();
    await waitFor(page, "s.view === 'cex' && s.cex && s.cex.i === 0", 5000, 'the player at its start');
    const steps = await studio(page, 's.cex.length');
    assert(steps === 6, `${steps} steps, the verifier's shortest sequence has 6`);
    await waitFor(page, "cy.getElementById('p:start').data('tokens') === 1", 5000, 'start marked at step 0');
    for (let i = 0; i < steps; i++) await page.locator('#cex-next').click();
    await waitFor(page, "s.cex.i === 6 && cy.getElementById('p:not_reached').data('tokens') === 1 && !cy.getElementById('p:start').data('tokens')", 5000, 'not_reached marked at the end');
    await page.locator('#cex-prev').click();
    await waitFor(page, "s.cex.i === 5 && !cy.getElementById('p:not_reached').data('tokens')", 5000, 'one step back');
    const text = await page.locator('#cex-text').textContent();
    assert(/check_depth/.test(text), `step 5 reads "${text}"`);
    await page.locator('#cex-close').click();
    return `${steps} steps; step 5: ${text}`;
  });

  await check('a sonar search run shows the newest scan beside the net', async () => {
    const SEARCH = 'missions/sonar_search/sonar_search.coral';
    await page.locator(`#file-list li[data-path="${SEARCH}"]`).click({ timeout: 8000 });
    await waitFor(page, `s.path === '${SEARCH}' && s.scenarios.includes('target_absent')`, 10000, 'sonar_search open with its scenarios');
    await page.locator('#run-scenario').selectOption('nominal');
    await page.locator('#run-speed').fill('40');
    await page.locator('#btn-run').click();
    await waitFor(page, 's.sonar.frames > 0', 30000, 'a first scan on the page');
    await waitFor(page, "s.runStatus !== 'running' && s.runEnded", 30000, 'run_end');
    const r = await page.evaluate(() => {
      const img = document.querySelector('#sonar-img');
      return { ended: window.__studio.runEnded, frames: window.__studio.sonar.frames, shown: !document.querySelector('#sonar-box').hidden,
               w: img.naturalWidth, info: document.querySelector('#sonar-info').textContent };
    });
    assert(r.ended.outcome === 'completed', `run ended ${JSON.stringify(r.ended)}`);
    assert(r.shown && r.w > 0, `the scan is not shown (width ${r.w})`);
    await page.screenshot({ path: path.join(OUT, 'studio-sonar.png') });
    return `${r.frames} scans seen, ${r.info}`;
  });

  await check('no uncaught error in the page', async () => {
    assert(pageErrors.length === 0, pageErrors.join('; '));
  });
}

try {
  await main();
} catch (e) {
  results.push({ name: 'harness', ok: false });
  console.log(`FAIL  harness: ${e.stack || e}`);
}
clearTimeout(watchdog);
await cleanup();
const failed = summary();
process.exit(failed ? 1 : 0);

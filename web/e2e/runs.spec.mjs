// Abort and Hard stop, the run's end as a banner (also after a reload), the
// breadcrumb, the run list from runs/ and its replay with play/pause, the
// chart's cursor and phase bands; a PROLOG mission shown as text and run.
import path from 'node:path';
import { test, expect, studio, waitFor, openPage, OUT, TANK } from './fixtures.mjs';

const DEPTH = "(() => { const t = s.state.rs.telemetry; return t.length ? t[t.length - 1][1] : 0; })()";

// Opens the tank mission, runs nominal at ×1 (at ×10 the whole run takes
// 2.5 s: too short a window to stop it at depth on a loaded machine), waits
// until the vehicle is below 1 m.
async function runToDepth(page) {
  await openPage(page);
  await expect(page.locator('#btn-abort')).toBeDisabled();
  await expect(page.locator('#btn-stop')).toBeDisabled();
  await page.locator('#run-scenario').selectOption('nominal');
  await page.locator('#run-speed').fill('1');
  await page.locator('#btn-run').click();
  await waitFor(page, "s.runStatus === 'running'", 15000, 'the run to start');
  await expect(page.locator('#btn-abort')).toBeEnabled();
  await expect(page.locator('#btn-stop')).toBeEnabled();
  await waitFor(page, `${DEPTH} > 1`, 60000, 'the vehicle below 1 m');
}

test('Abort at depth: banner aborted, surfaced, final depth < 0.15 m; it stays after a reload; the run is listed and replays with play and pause', async ({ page }) => {
  await runToDepth(page);
  // The breadcrumb: mission ▸ active phase; a crumb opens its net.
  await waitFor(page, 's.breadcrumb.length >= 2', 10000, 'a breadcrumb mission ▸ phase');
  await expect(page.locator('#breadcrumb')).toBeVisible();
  expect(await studio(page, 's.breadcrumb[0]')).toBe('tank');
  await page.locator('#breadcrumb .crumb[data-net="tank"]').click();
  await waitFor(page, "s.net === 'tank' && !s.state.follow", 5000, 'the mission net opened from the breadcrumb');

  await page.locator('#btn-abort').click();
  await waitFor(page, "s.runEnded && s.runStatus !== 'running'", 90000, 'run_end after Abort');
  const b = await studio(page, 's.banner');
  expect(b.outcome).toBe('aborted');
  expect(b.surfaced).toBe(true);
  // The vehicle calls itself surfaced at 0.15 m or less (src/vehicle/params.h
  // surface_depth_m); an Abort in submerge_to_depth ends at 0.11-0.13 m.
  expect(b.depth).toBeLessThan(0.15);
  expect(b.log).toMatch(/runs\/\d{8}T\d{6}Z-tank\.coral\.jsonl$/);
  const banner = page.locator('#run-banner');
  await expect(banner).toBeVisible();
  await expect(banner).toContainText('aborted');
  await expect(banner).toContainText('Surfaced');
  await expect(banner).toContainText(b.log);
  await expect(page.locator('#btn-abort')).toBeDisabled();
  await expect(page.locator('#breadcrumb')).toBeHidden();
  await page.screenshot({ path: path.join(OUT, 'studio-abort.png') });

  // The run list (refreshed after run_end): newest first, this run's log.
  await waitFor(page, `s.runs.length >= 1 && s.runs[0].path === ${JSON.stringify(b.log)}`, 10000, 'the run in the run list');
  await expect(page.locator(`#run-list li[data-path="${b.log}"]`)).toBeVisible();

  // A reload: the snapshot carries the run's end.
  await page.reload();
  await waitFor(page, "s.banner && s.banner.outcome === 'aborted'", 15000, 'the banner after a reload');
  await expect(page.locator('#run-banner')).toContainText('aborted');
  await page.locator(`#file-list li[data-path="${TANK}"]`).click();
  await waitFor(page, `s.path === '${TANK}' && s.runs.length >= 1`, 15000, 'the mission and its runs after the reload');

  // Replay it: the slider, then play and pause.
  await page.locator(`#run-list li[data-path="${b.log}"]`).click();
  await waitFor(page, `s.replay && s.replay.path === ${JSON.stringify(b.log)} && s.replay.length > 10 && s.view === 'replay'`, 15000, 'the run replayed');
  const n = await studio(page, 's.replay.length');
  // Phases as bands: drawn with the chart's next frame, not with the replay's state.
  await waitFor(page, 's.chart.bands > 0', 5000, 'the phases drawn as bands on the chart');
  await page.locator('#replay-slider').fill(String(Math.floor(n / 2)));
  await waitFor(page, `s.replay.pos === ${Math.floor(n / 2)} && s.chart.cursor != null && s.chart.cursorX != null`, 5000, 'the slider moved, the cursor on the chart');
  const mid = await studio(page, 's.chart.cursorX');
  await page.locator('#replay-slider').fill('0');
  await waitFor(page, 's.replay.pos === 0 && s.chart.cursor == null', 5000, 'the slider at 0');
  await page.locator('#replay-play').click();
  await waitFor(page, 's.replay.playing && s.replay.pos > 0', 5000, 'playing');
  await expect(page.locator('#replay-play')).toHaveText('pause');
  await waitFor(page, 's.chart.cursorX != null', 5000, 'the cursor while playing');
  await page.locator('#replay-play').click();
  await waitFor(page, '!s.replay.playing', 3000, 'paused');
  const at = await studio(page, 's.replay.pos');
  await page.waitForTimeout(600);
  expect(await studio(page, 's.replay.pos')).toBe(at);   // paused: it does not move
  expect(at).toBeLessThan(n);
  expect(await studio(page, 's.chart.cursorX')).toBeLessThan(mid);
  await page.screenshot({ path: path.join(OUT, 'studio-replay-play.png') });
});

test('Hard stop asks, then the banner says the vehicle was not surfaced and its last depth', async ({ page }) => {
  await runToDepth(page);
  page.removeAllListeners('dialog');
  const asked = [];
  page.on('dialog', (d) => { asked.push(d.message()); d.accept(); });
  await expect(page.locator('#btn-stop')).toHaveText('Hard stop');
  await page.locator('#btn-stop').click();
  await waitFor(page, "s.runEnded && s.runStatus !== 'running'", 60000, 'run_end after the hard stop');
  expect(asked.length).toBe(1);
  expect(asked[0]).toMatch(/NOT surfaced/);
  const b = await studio(page, 's.banner');
  expect(b.hard).toBe(true);
  expect(b.surfaced).toBe(false);
  expect(b.outcome).toBe('failed');
  expect(b.depth).toBeGreaterThan(0.5);
  const banner = page.locator('#run-banner');
  await expect(banner).toContainText('HARD STOP');
  await expect(banner).toContainText('vehicle was NOT surfaced');
  await expect(banner).toContainText(`last depth ${b.depth.toFixed(2)} m`);
  await page.screenshot({ path: path.join(OUT, 'studio-hard-stop.png') });
});

test('tank.pl is listed as PROLOG, opens as read-only text with no graph, and runs to run_end completed', async ({ page }) => {
  const PL = 'missions/tank/tank.pl';
  await page.goto(page.studio.url);
  const item = page.locator(`#file-list li[data-path="${PL}"]`);
  await expect(item).toHaveAttribute('data-kind', 'prolog');
  await item.click();
  await waitFor(page, `s.path === '${PL}' && s.busy === 0 && s.model && s.model.kind === 'prolog'`, 15000, 'tank.pl open');
  expect(await studio(page, 's.readOnly')).toBe(true);
  expect(await studio(page, 'cy.nodes().length')).toBe(0);
  await expect(page.locator('#canvas-note')).toBeVisible();
  await expect(page.locator('#canvas-note')).toContainText('PROLOG mission');
  await waitFor(page, 's.paneText === s.text', 5000, 'the text in the pane (a frame after the open)');
  expect((await studio(page, 's.text')).length).toBeGreaterThan(20);
  // Typing does not change it.
  const before = await studio(page, 's.text');
  await page.locator('#text-pane .cm-content').click();
  await page.keyboard.type('zzz');
  expect(await studio(page, 's.text')).toBe(before);
  expect(await studio(page, 's.dirty')).toBe(false);
  await expect(page.locator('#btn-save')).toBeDisabled();
  await page.locator('#run-speed').fill('10');
  await expect(page.locator('#btn-run')).toBeEnabled();
  await page.locator('#btn-run').click();
  await waitFor(page, "s.runStatus !== 'idle'", 15000, 'the PROLOG run to start');
  await waitFor(page, "s.runEnded && s.runStatus !== 'running'", 120000, 'run_end of tank.pl');
  const b = await studio(page, 's.banner');
  expect(b.outcome).toBe('completed');
  await expect(page.locator('#run-banner')).toContainText('completed');
  await expect(page.locator('#canvas-note')).toBeVisible();
});

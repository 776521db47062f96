// Verify, run, replay, counterexamples and sonar: the live side of the page.
import path from 'node:path';
import { test, expect, studio, waitFor, openPage, nodePoint, OUT, STUCK } from './fixtures.mjs';

test('verify lists the properties', async ({ page }) => {
  await openPage(page);
  await page.locator('#btn-verify').click();
  await waitFor(page, 's.verify && (s.verify.nets || s.verify.error)', 30000, 'verification');
  const v = await studio(page, 's.verify');
  expect(v.error).toBeUndefined();
  expect(await page.locator('#verify-body li.prop').count()).toBeGreaterThan(0);
});

test('run nominal at ×10: the live view reaches the end with the final marking, the chart fills', async ({ page }) => {
  await openPage(page);
  await page.locator('#run-scenario').selectOption('nominal');
  await page.locator('#run-speed').fill('10');
  await page.locator('#btn-run').click();
  await waitFor(page, "s.runStatus !== 'idle'", 10000, 'the run to start');
  await waitFor(page, "s.runStatus !== 'running' && s.runEnded", 60000, 'run_end');
  const r = await page.evaluate(() => {
    const s = window.__studio;
    return { status: s.runStatus, ended: s.runEnded, tank: s.markings.tank, tele: s.telemetryCount };
  });
  expect(r.status).toBe('completed');
  expect(r.ended.outcome).toBe('completed');
  expect(r.tank && r.tank.closed).toBe(1);
  expect(r.tele).toBeGreaterThan(10);
  await page.locator('#net-list li[data-net="tank"]').click();
  await waitFor(page, "s.net === 'tank' && cy.getElementById('p:closed').data('tokens') === 1", 5000, 'closed drawn with one token');
  expect(await page.locator('#chart canvas').count()).toBeGreaterThan(0);
  expect(await studio(page, 's.map.shown')).toBe(false);  // a tank run has no x-y track
  await expect(page.locator('#map-box')).toBeHidden();
  await page.screenshot({ path: path.join(OUT, 'studio-run.png') });
  // A net picked by the user stops the following; double-click a PHASE
  // transition opens its net with the run's marking.
  await expect(page.locator('#follow')).toBeChecked();
  await page.evaluate(() => { const cy = window.__cy; cy.center(cy.getElementById('t:phase2')); });
  const p = await nodePoint(page, 't:phase2');
  await page.mouse.dblclick(p.x, p.y);
  await waitFor(page, "s.net === 'dive_from_surface' && s.view === 'live'", 5000, 'phase 2 opened in the live view');
  await expect(page.locator('#follow')).not.toBeChecked();
  const marked = await studio(page, "Object.keys(s.markings.dive_from_surface || {}).filter((k) => s.markings.dive_from_surface[k] > 0)");
  expect(marked.length).toBeGreaterThan(0);
  for (const place of marked) expect(await studio(page, `cy.getElementById('p:${place}').data('tokens')`)).toBeGreaterThan(0);
});

test('replay a mission log with the slider, and step it from firing to firing', async ({ page }) => {
  page.studio.runLog('missions/tank/tank.coral', 'tank-run.jsonl');
  await page.goto(page.studio.url);
  await page.locator('#log-list li[data-path="tank-run.jsonl"]').click();
  await waitFor(page, "s.replay && s.replay.length > 10 && s.view === 'replay'", 10000, 'replay loaded');
  const n = await studio(page, 's.replay.length');
  await page.locator('#replay-slider').fill(String(n));
  await waitFor(page, 's.markings.tank && s.markings.tank.closed === 1', 5000, 'closed at the end of the replay');
  await page.locator('#replay-slider').fill('3');
  await waitFor(page, '!(s.markings.tank && s.markings.tank.closed)', 5000, 'closed empty early in the replay');
  await page.locator('#replay-slider').fill('0');
  await page.locator('#replay-next').click();
  const first = await studio(page, 's.replay.pos');
  expect(first).toBeGreaterThan(0);
  expect(await studio(page, `s.replayKinds[${first - 1}]`)).toBe('fired');
  await page.locator('#replay-next').click();
  const second = await studio(page, 's.replay.pos');
  expect(second).toBeGreaterThan(first);
  expect(await studio(page, `s.replayKinds[${second - 1}]`)).toBe('fired');
  await page.locator('#replay-prev').click();
  expect(await studio(page, 's.replay.pos')).toBe(first);
  await page.locator('#replay-slider').fill(String(n));
  await page.screenshot({ path: path.join(OUT, 'studio-replay.png') });
  await page.locator('#replay-close').click();
  await waitFor(page, "!s.replay && s.view !== 'replay'", 3000, 'replay closed');
});

test('a survey replay shows the map: the whole track, the vehicle moving with the slider', async ({ page }) => {
  page.studio.runLog('missions/survey/survey.coral', 'survey-run.jsonl', 600);  // the launch and the first leg
  await page.goto(page.studio.url);
  await page.locator('#log-list li[data-path="survey-run.jsonl"]').click();
  await waitFor(page, "s.replay && s.replay.length > 10 && s.view === 'replay' && s.map.shown && s.map.drawn", 60000, 'replay with its map');  // a 600 s survey log: slow under ASan beside the other worker
  await expect(page.locator('#map-box')).toBeVisible();
  const end = await studio(page, 's.map.drawn');
  expect(end.points).toBeGreaterThan(100);
  expect(end.vehicle).not.toBeNull();
  await page.screenshot({ path: path.join(OUT, 'studio-map.png') });
  const n = await studio(page, 's.replay.length');
  await page.locator('#replay-slider').fill(String(Math.floor(n / 3)));
  await waitFor(page, `s.map.drawn && s.map.drawn.vehicle && (s.map.drawn.vehicle[0] !== ${end.vehicle[0]} || s.map.drawn.vehicle[1] !== ${end.vehicle[1]})`, 20000, 'the vehicle moved back along the track');
  expect((await studio(page, 's.map.drawn')).points).toBe(end.points);  // the whole track stays
  await page.locator('#replay-close').click();
  await waitFor(page, "!s.replay && !s.map.shown", 10000, 'no map once the replay is closed');
});

// The map during a live open-water run, not only in a replay (issue 20):
// the track grows and the vehicle moves while the run goes, and the whole
// track stays after its end. One short leg of the survey's phases (300 s
// of simulated time, 15 s at x20): the whole survey at x200 left the real
// time vehicle's wall-clock timeouts at the mercy of the machine's load.
const SHORT_LEG = `// One short leg of the survey, for the live map.
import "../missions/survey/survey_phases.coral";

mission short_leg {
  place begin = 1;
  place ready, leg_done, recovered, aborted, surfaced;
  exit closed, closed_after_abort;
  transition prepare  { wait { begin }     action { PHASE(launch, ready) } }
  transition go       { wait { ready }     action { PHASE(leg(0, 0, 120, 0), leg_done, aborted) } }
  transition come_up  { wait { leg_done }  action { PHASE(recover, recovered) } }
  transition shutdown { wait { recovered } action { TACTIC(OOD, shutdown_network, closed) } }
  transition abort_mission { wait { aborted } action { PHASE(emergency_surface, surfaced) } }
  transition shutdown_after_abort { wait { surfaced } action { TACTIC(OOD, shutdown_network, closed_after_abort) } }
}
`;
const OPEN_WATER = 'seed = 1\n[world]\nkind = "open_water"\n[seabed]\nkind = "flat"\ndepth_m = 25.0\n[vehicle]\nheading_deg = 90.0\n';

test.describe('a short survey leg', () => {
  test.use({ files: { 'short_leg/short_leg.coral': SHORT_LEG, 'short_leg/scenarios/nominal.toml': OPEN_WATER } });

  test('a survey run shows the map live: the track grows while it runs', async ({ page }) => {
    await openPage(page, 'short_leg/short_leg.coral');
    await page.locator('#run-speed').fill('20');
    await page.locator('#btn-run').click();
    await waitFor(page, "s.runStatus === 'running' && s.map.shown && s.map.drawn && s.map.drawn.points > 5", 30000, 'the live map');
    await expect(page.locator('#map-box')).toBeVisible();
    const early = await studio(page, 's.map.drawn');
    await waitFor(page, `s.runStatus === 'running' && s.map.drawn.points > ${early.points + 20} && (s.map.drawn.vehicle[0] !== ${early.vehicle[0]} || s.map.drawn.vehicle[1] !== ${early.vehicle[1]})`, 30000, 'the track grown and the vehicle moved, while the run goes');
    await waitFor(page, "s.runStatus !== 'running' && s.runEnded", 120000, 'run_end');
    expect((await studio(page, 's.runEnded')).outcome).toBe('completed');
    const end = await studio(page, 's.map.drawn');
    expect(end.points).toBeGreaterThan(100);
    expect(await studio(page, 's.map.shown')).toBe(true);
  });
});

test('a counterexample plays on its net: to the stall and one step back', async ({ page }) => {
  await openPage(page, STUCK);
  await waitFor(page, "cy.getElementById('p:not_reached').nonempty()", 5000, 'stuck_phase drawn');
  await page.locator('#btn-verify').click();
  await waitFor(page, 's.verify && s.verify.nets && s.verify.nets.some((n) => n.name === "stuck_phase")', 30000, 'verification of stuck_phase');
  await page.locator('#verify-body li.prop[data-key="no_deadlock"] button.play-cex').click();
  await waitFor(page, "s.view === 'cex' && s.cex && s.cex.i === 0", 5000, 'the player at its start');
  expect(await studio(page, 's.cex.length')).toBe(6);
  await waitFor(page, "cy.getElementById('p:start').data('tokens') === 1", 5000, 'start marked at step 0');
  for (let i = 0; i < 6; i++) await page.locator('#cex-next').click();
  await waitFor(page, "s.cex.i === 6 && cy.getElementById('p:not_reached').data('tokens') === 1 && !cy.getElementById('p:start').data('tokens')", 5000, 'not_reached marked at the end');
  await page.locator('#cex-prev').click();
  await waitFor(page, "s.cex.i === 5 && !cy.getElementById('p:not_reached').data('tokens')", 5000, 'one step back');
  await expect(page.locator('#cex-text')).toContainText('check_depth');
  await page.locator('#cex-close').click();
  await waitFor(page, "!s.cex && s.view === 'edit'", 3000, 'the player closed');
});

// Issue 39: "follow" opened a long phase net at its start, and the action
// in flight, at its far end, was off screen.
function longPhase(n) {
  let text = 'net long {\n  place p0 = 1;\n';
  for (let i = 1; i <= n; i++) text += `  place p${i};\n`;
  text += '  exit done;\n';
  for (let i = 1; i <= n; i++) text += `  transition t${i} { wait { p${i - 1} } signal { p${i} } }\n`;
  text += `  transition last { wait { p${n} } action { TACTIC(EXEC, sleep(30), done) } }\n}\n`;
  text += 'mission follows { place begin = 1, over; exit closed;\n';
  text += '  transition go { wait { begin } action { PHASE(long, over) } }\n';
  text += '  transition end { wait { over } signal { closed } } }\n';
  return text;
}

test.describe('a long phase net', () => {
  test.use({ files: { 'long/long.coral': longPhase(40) } });

  test('followed into it, the action in flight is in view', async ({ page }) => {
    await openPage(page, 'long/long.coral');
    await page.locator('#run-speed').fill('2');
    await page.locator('#btn-run').click();
    await waitFor(page, "s.net === 'long' && s.inFlight.some((a) => a.transition === 'last')", 30000, 'followed into long, sleep in flight');
    await waitFor(page, `(() => { const n = cy.getElementById('t:last'); if (n.empty()) return false;
      const p = n.renderedPosition(); return p.x >= 0 && p.y >= 0 && p.x <= cy.width() && p.y <= cy.height(); })()`, 5000, 'the transition in flight in view');
    await page.locator('#btn-abort').click();
    await waitFor(page, 's.runEnded != null', 60000, 'the run ended');
  });
});

// Issue 38: a mission's `require` shows its worst path on the nets, the
// player moving into the phase each step runs in.
const HELD = `net hold(s) { place a = 1; exit done;
  transition nap { wait { a } action { TACTIC(EXEC, sleep(s), done) } } }
mission held { require "fault system_problem -> exec surface within 2";
  place begin = 1, held, up; exit closed, aborted;
  transition hold { wait { begin } action { PHASE(hold(5), held) } }
  transition check { wait { held } action { TACTIC(ASK, system_problem, up, closed) } }
  transition close { wait { up } action { TACTIC(EXEC, surface, aborted) } } }
`;

test.describe('a requirement', () => {
  test.use({ files: { 'held/held.coral': HELD } });

  test('its worst path plays on the nets, into the phase and back', async ({ page }) => {
    await openPage(page, 'held/held.coral');
    await page.locator('#btn-verify').click();
    await waitFor(page, 's.verify && s.verify.nets && s.verify.nets.some((n) => n.name === "held")', 30000, 'verification of held');
    const req = page.locator('#verify-body li.prop[data-key="requirement"]');
    await expect(req).toContainText('at worst 5.2 s, past 2 s');
    await req.locator('button.play-cex').click();
    await waitFor(page, "s.view === 'cex' && s.cex && s.cex.i === 0 && s.netName === 'held'", 5000, 'the player at its start');
    await expect(page.locator('#cex-title')).toContainText('the worst path');
    const length = await studio(page, 's.cex.length');
    await page.locator('#cex-next').click();  // the mission calls the phase
    await page.locator('#cex-next').click();  // in the phase: nap fires
    await waitFor(page, "s.netName === 'hold' && s.cex.i === 2 && cy.getElementById('t:nap').hasClass('cex')", 5000, 'the player in the phase, at nap');
    await page.locator('#cex-next').click();  // the fault starts: still in the phase
    await waitFor(page, "s.netName === 'hold' && s.cex.i === 3", 5000, 'the fault, in the phase');
    for (let i = 3; i < length; i++) await page.locator('#cex-next').click();
    await waitFor(page, `s.netName === 'held' && s.cex.i === ${length} && cy.getElementById('t:close').hasClass('cex')`, 5000, 'back on the mission, at close');
    await expect(page.locator('#cex-text')).toContainText('5.2 s: held: fire close: EXEC surface');
  });
});

test('a sonar search run shows the newest scan beside the net', async ({ page }) => {
  const SEARCH = 'missions/sonar_search/sonar_search.coral';
  await openPage(page, SEARCH);
  await waitFor(page, "s.scenarios.includes('target_absent')", 10000, 'the scenarios of sonar_search');
  await page.locator('#run-scenario').selectOption('nominal');
  await page.locator('#run-speed').fill('40');
  await page.locator('#btn-run').click();
  await waitFor(page, 's.sonar.frames > 0', 40000, 'a first scan on the page');
  await waitFor(page, "s.runStatus !== 'running' && s.runEnded", 40000, 'run_end');
  const r = await page.evaluate(() => {
    const img = document.querySelector('#sonar-img');
    return { ended: window.__studio.runEnded, shown: !document.querySelector('#sonar-box').hidden, w: img.naturalWidth };
  });
  expect(r.ended.outcome).toBe('completed');
  expect(r.shown).toBe(true);
  expect(r.w).toBeGreaterThan(0);
  await page.screenshot({ path: path.join(OUT, 'studio-sonar.png') });
});

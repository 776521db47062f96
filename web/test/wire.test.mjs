// The page's wiring of issue 17's server side, without a browser: the run's
// end (banner, also from a snapshot after a reload), Abort and Hard stop,
// the breadcrumb, the run list, replay play/pause and the chart's cursor and
// phase bands, changes on disk, PROLOG missions as text, scenarios.
//   node --test web/test/
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { createStore, reduce, initialState, dirty, runBanner, runGoing, breadcrumb, chartData, scenarioList, isProlog, editable } from '../src/store.js';
import { createEffects } from '../src/effects.js';

function model(text = 'net n { place a = 1; place b; transition t { wait { a } signal { b } } }', extra = {}) {
  return {
    path: 'm.coral', text, etag: '"v1"', layout_etag: '"l1"', layout: null, scenarios: ['nominal'], diagnostics: [], kind: 'coral', read_only: false,
    nets: [
      { name: 'n', kind: 'mission', file: 'm.coral', editable: true, exits: [], places: [{ name: 'a', initial: 1 }, { name: 'b', initial: 0 }],
        transitions: [{ name: 't', inputs: [{ place: 'a', weight: 1 }], outputs: [{ place: 'b', weight: 1 }], actions: [] }] },
      { name: 'ph', kind: 'phase', file: 'm.coral', editable: true, exits: [], places: [{ name: 'x', initial: 0 }], transitions: [] },
      { name: 'sub', kind: 'phase', file: 'm.coral', editable: true, exits: [], places: [{ name: 'y', initial: 0 }], transitions: [] }],
    ...extra,
  };
}
const opened = (m = model()) => reduce(initialState(), { type: 'file/opened', path: 'm.coral', model: m });
const ev = (s, name, data) => reduce(s, { type: 'run/event', name, data });
const hardEnd = { outcome: 'failed', exit: '', reason: 'hard stop from the studio', phase: 'ph', stopped_by: 'studio', stop: 'hard',
  exit_code: 1, final_depth_m: 1.25, surfaced: false, log: 'runs/20261125T214638Z-m.jsonl', t: 40 };
const abortEnd = { outcome: 'aborted', exit: '', reason: 'aborted from the studio', phase: 'ph', stopped_by: 'studio', stop: 'abort',
  exit_code: 2, final_depth_m: 0.02, surfaced: true, log: 'runs/x.jsonl', t: 60 };

test('run_end: the banner says the outcome, the phase, the reason and the log; Abort and Hard stop only while it goes', () => {
  let s = ev(opened(), 'run_start', { run: 1, mission: 'm.coral', scenario: 'nominal', speed: 10 });
  assert.equal(runGoing(s), true);
  assert.equal(runBanner(s), null);
  s = ev(s, 'run_end', abortEnd);
  assert.equal(runGoing(s), false);
  const b = runBanner(s);
  assert.equal(b.outcome, 'aborted');
  assert.equal(b.surfaced, true);
  assert.equal(b.hard, false);
  assert.match(b.lines[0], /^aborted in phase ph/);
  assert.ok(b.lines.includes('aborted from the studio'));
  assert.ok(b.lines.some((l) => /^Surfaced; final depth 0\.02 m/.test(l)));
  assert.ok(b.lines.includes('log: runs/x.jsonl'));
  // It stays in the editor view; closed, it is gone until the next run's end.
  s = reduce(s, { type: 'view/set', view: 'edit' });
  assert.ok(runBanner(s));
  s = reduce(s, { type: 'banner/close' });
  assert.equal(runBanner(s), null);
  s = ev(ev(s, 'run_start', { run: 2 }), 'run_end', { ...abortEnd, outcome: 'completed', stop: '', stopped_by: '' });
  assert.equal(runBanner(s).outcome, 'completed');
});

test('a hard stop\'s banner says plainly the vehicle was not surfaced, and its last depth', () => {
  let s = ev(opened(), 'run_start', { run: 1 });
  s = ev(s, 'run_end', hardEnd);
  const b = runBanner(s);
  assert.equal(b.hard, true);
  assert.equal(b.surfaced, false);
  assert.match(b.lines[0], /HARD STOP/);
  assert.ok(b.lines.some((l) => /vehicle was NOT surfaced.*last depth 1\.25 m/.test(l)), b.lines.join('\n'));
});

test('the banner after a reload: the snapshot carries the last run\'s end', () => {
  let s = reduce(initialState(), { type: 'run/event', name: 'snapshot', data: { run: 4, mission: 'm.coral', nets: model().nets, instances: [], final: [{ instance: 1, net: 'n', parent: 0, marking: { b: 1 }, exit: '', cancelled: false }], telemetry: [[1, 0.5, 1]], ended: hardEnd } });
  const b = runBanner(s);
  assert.ok(b);
  assert.equal(b.hard, true);
  assert.equal(runGoing(s), false);
  assert.deepEqual(s.rs.markings.n, { b: 1 });   // the final marking kept after the run
  // A replay opened meanwhile keeps the live run's banner.
  s = reduce(s, { type: 'replay/opened', path: 'r.jsonl', events: [['run_start', { run: 1 }]] });
  assert.equal(runBanner(s).hard, true);
});

test('the breadcrumb: mission ▸ active phase while the run goes, back up as phases end, none after', () => {
  let s = ev(opened(), 'run_start', { run: 1 });
  assert.deepEqual(breadcrumb(s), []);
  s = ev(s, 'phase_start', { instance: 1, parent: 0, net: 'n', marking: { a: 1 }, t: 0 });
  s = ev(s, 'phase_start', { instance: 2, parent: 1, net: 'ph', marking: { x: 1 }, t: 1 });
  s = ev(s, 'phase_start', { instance: 3, parent: 2, net: 'sub', marking: { y: 1 }, t: 2 });
  assert.deepEqual(breadcrumb(s).map((c) => c.net), ['n', 'ph', 'sub']);
  s = ev(s, 'phase_end', { instance: 3, net: 'sub', exit: 'done', t: 3 });
  assert.deepEqual(breadcrumb(s).map((c) => c.net), ['n', 'ph']);
  // A crumb clicked opens its net (and stops following).
  s = reduce(s, { type: 'net/show', name: 'n', user: true });
  assert.equal(s.netName, 'n');
  assert.equal(s.follow, false);
  s = ev(s, 'run_end', { outcome: 'completed' });
  assert.deepEqual(breadcrumb(s), []);
  // From a snapshot mid-run: the deepest instance.
  const t = reduce(initialState(), { type: 'run/event', name: 'snapshot', data: { run: 2, mission: 'm.coral', nets: model().nets,
    instances: [{ instance: 2, net: 'ph', parent: 1, marking: {} }, { instance: 1, net: 'n', parent: 0, marking: {} }] } });
  assert.deepEqual(breadcrumb(t).map((c) => c.net), ['n', 'ph']);
});

test('the run list: the open mission\'s runs; another mission\'s answer is dropped; a new file starts empty', () => {
  let s = opened();
  const runs = [{ path: 'runs/b.jsonl', mission_file: 'm.coral', started: '2026-11-25T21:46:38Z', bytes: 10 }, { path: 'runs/a.jsonl' }];
  s = reduce(s, { type: 'runs/loaded', mission: 'm.coral', runs });
  assert.deepEqual(s.runs.list.map((r) => r.path), ['runs/b.jsonl', 'runs/a.jsonl']);
  assert.equal(reduce(s, { type: 'runs/loaded', mission: 'other.coral', runs: [] }), s);
  s = reduce(s, { type: 'file/opened', path: 'm.coral', model: model() });
  assert.equal(s.runs.list.length, 2);   // the same file read again keeps its list
  s = reduce(s, { type: 'file/opened', path: 'o.coral', model: model() });
  assert.deepEqual(s.runs.list, []);
});

const replayEvents = [
  ['run_start', { run: 1 }],
  ['phase_start', { instance: 1, parent: 0, net: 'n', marking: { a: 1 }, t: 0 }],
  ['telemetry', { t: 1, depth: 0.5, setpoint: 1 }],
  ['phase_start', { instance: 2, parent: 1, net: 'ph', marking: { x: 1 }, t: 1.5 }],
  ['fired', { instance: 1, net: 'n', transition: 't', marking: { b: 1 }, enabled: [], t: 2 }],
  ['telemetry', { t: 3, depth: 1.5, setpoint: 2 }],
  ['phase_end', { instance: 2, net: 'ph', exit: 'done', t: 3.5 }],
  ['fired', { instance: 1, net: 'n', transition: 'u', marking: { a: 1 }, enabled: [], t: 4 }],
  ['telemetry', { t: 5, depth: 0, setpoint: 0 }],
  ['run_end', { outcome: 'completed', t: 6 }],
];

test('replay play/pause: play from the end starts at 0, a tick steps to the next firing, pause stops, the end stops', () => {
  let s = reduce(opened(), { type: 'replay/opened', path: 'r.jsonl', events: replayEvents });
  assert.equal(s.replay.playing, false);
  assert.equal(reduce(s, { type: 'replay/tick' }), s);   // not playing: nothing
  s = reduce(s, { type: 'replay/play' });
  assert.equal(s.replay.playing, true);
  assert.equal(s.replay.pos, 0);
  s = reduce(s, { type: 'replay/tick' });
  assert.equal(s.replay.pos, 5);   // just after the first firing
  assert.deepEqual(s.rs.markings.n, { b: 1 });
  s = reduce(s, { type: 'replay/pause' });
  assert.equal(s.replay.playing, false);
  assert.equal(reduce(s, { type: 'replay/tick' }).replay.pos, 5);
  s = reduce(s, { type: 'replay/play' });   // from where it was
  assert.equal(s.replay.pos, 5);
  s = reduce(s, { type: 'replay/tick' });
  assert.equal(s.replay.pos, 8);
  assert.deepEqual(s.rs.markings.n, { a: 1 });
  s = reduce(s, { type: 'replay/tick' });
  assert.equal(s.replay.pos, replayEvents.length);
  assert.equal(s.replay.playing, false);   // the end
  assert.equal(s.rs.status, 'completed');
  // Stepping forward gives what seeking gives.
  const seek = reduce(s, { type: 'replay/seek', pos: 5 });
  assert.deepEqual(seek.rs.markings, reduce(reduce(reduce(s, { type: 'replay/seek', pos: 0 }), { type: 'replay/play' }), { type: 'replay/tick' }).rs.markings);
});

test('effects: play runs a bounded timer that pauses itself at the end; pause stops it', async () => {
  const store = createStore(reduce(opened(), { type: 'replay/opened', path: 'r.jsonl', events: replayEvents }));
  const timers = new Map();
  let id = 0;
  const fx = createEffects(store, {}, { setInterval: (f) => { timers.set(++id, f); return id; }, clearInterval: (t) => timers.delete(t) });
  fx.playReplay();
  assert.equal(timers.size, 1);
  const tick = [...timers.values()][0];
  tick();
  assert.equal(store.getState().replay.pos, 5);
  fx.pauseReplay();
  assert.equal(timers.size, 0);
  assert.equal(store.getState().replay.playing, false);
  fx.playReplay();
  const tick2 = [...timers.values()][0];
  for (let i = 0; i < 50 && timers.size; i++) tick2();
  assert.equal(timers.size, 0);   // stopped by itself at the end
  assert.equal(store.getState().replay.pos, replayEvents.length);
  assert.equal(store.getState().replay.playing, false);
});

test('the chart: phase spans as bands; in a replay the whole log with a cursor at the position', () => {
  let s = ev(opened(), 'run_start', { run: 1 });
  for (const [n, d] of replayEvents.slice(1, 7)) s = ev(s, n, d);
  const live = chartData(s);
  assert.equal(live.cursor, null);
  const ph = live.phases.find((p) => p.net === 'ph');
  assert.deepEqual([ph.t0, ph.t1], [1.5, 3.5]);
  assert.equal(live.phases.find((p) => p.net === 'n').t1, null);   // still running
  s = reduce(s, { type: 'replay/opened', path: 'r.jsonl', events: replayEvents });
  s = reduce(s, { type: 'replay/seek', pos: 4 });
  const r = chartData(s);
  assert.equal(r.telemetry.length, 3);   // the whole log's, not up to the position
  assert.equal(r.cursor, 1.5);
  assert.equal(r.phases.find((p) => p.net === 'n').t1, 6);   // closed by run_end
  assert.equal(chartData(reduce(s, { type: 'replay/seek', pos: 6 })).cursor, 3);
  assert.equal(chartData(reduce(s, { type: 'replay/seek', pos: 0 })).cursor, null);
});

test('file_changed: the open file without unsaved edits is reloaded; our own version is no news; another file refreshes the lists', () => {
  const s = opened();
  assert.equal(reduce(s, { type: 'disk/changed', path: 'm.coral', etag: '"v1"' }), s);
  const r = reduce(s, { type: 'disk/changed', path: 'm.coral', etag: '"v2"' });
  assert.equal(r.disk.what, 'reload');
  assert.equal(r.conflict, null);
  assert.equal(reduce(s, { type: 'disk/changed', path: 'm.coral.layout.json', etag: '"l2"' }).disk.what, 'reload');
  assert.equal(reduce(s, { type: 'disk/changed', path: 'm.coral.layout.json', etag: '"l1"' }), s);
  assert.equal(reduce(s, { type: 'disk/changed', path: 'other.coral', etag: '"x"' }).disk.what, 'list');
  assert.equal(reduce(s, { type: 'disk/changed', path: 'm.coral', etag: null }).disk.what, 'gone');
});

test('file_changed with unsaved edits: the conflict (Reload / Keep mine) with the new version', () => {
  let s = reduce(opened(), { type: 'model/edited', path: 'm.coral', model: model('MINE') });
  assert.equal(dirty(s), true);
  s = reduce(s, { type: 'disk/changed', path: 'm.coral', etag: '"v2"' });
  assert.equal(s.disk.what, 'conflict');
  assert.equal(s.conflict.disk, true);
  assert.equal(s.conflict.etag, '"v2"');
  assert.equal(s.text, 'MINE');   // nothing lost
  s = reduce(s, { type: 'conflict/keep-mine' });
  assert.equal(s.etag, '"v2"');   // the next save is made over the new version
});

// The race that failed the keep-mine browser test under load: tab one saves
// the text, then its layout; tab two (unsaved edits) hears of each on its own.
// The layout's notice must not put tab two's old text version back into the
// conflict, nor the text's notice drop the 412's layout version, or Keep mine
// saves over a version that is no longer on disk and gets a second 412.
test('keep mine after a 412 and a later layout notice saves over both new versions', () => {
  let s = reduce(opened(), { type: 'model/edited', path: 'm.coral', model: model('MINE') });
  s = reduce(s, { type: 'save/conflict', path: 'm.coral', theirs: 'THEIRS', etag: '"v2"', layoutEtag: '"l1"' });
  s = reduce(s, { type: 'disk/changed', path: 'm.coral.layout.json', etag: '"l2"' });
  assert.equal(s.conflict.etag, '"v2"');
  assert.equal(s.conflict.layoutEtag, '"l2"');
  assert.equal(s.conflict.theirs, 'THEIRS');   // their text did not change
  s = reduce(s, { type: 'conflict/keep-mine' });
  assert.equal(s.etag, '"v2"');
  assert.equal(s.layoutEtag, '"l2"');
});

test('keep mine after a 412 and the notice of the text it already holds keeps the 412\'s layout version', () => {
  let s = reduce(opened(), { type: 'model/edited', path: 'm.coral', model: model('MINE') });
  s = reduce(s, { type: 'save/conflict', path: 'm.coral', theirs: 'THEIRS', etag: '"v2"', layoutEtag: '"l2"' });
  const before = s;
  s = reduce(s, { type: 'disk/changed', path: 'm.coral', etag: '"v2"' });
  assert.equal(s, before);   // the version the conflict shows: no news
  s = reduce(s, { type: 'disk/changed', path: 'm.coral', etag: '"v3"' });   // a newer one is
  assert.equal(s.conflict.etag, '"v3"');
  assert.equal(s.conflict.layoutEtag, '"l2"');
  assert.equal(s.conflict.theirs, null);   // read again by the effects
  s = reduce(s, { type: 'conflict/keep-mine' });
  assert.equal(s.etag, '"v3"');
  assert.equal(s.layoutEtag, '"l2"');
});

function fakeApi(over = {}) {
  const calls = [];
  const api = { calls };
  const base = {
    mission: (p) => model(p === 'm.coral' && calls.filter((c) => c[0] === 'mission').length > 1 ? 'ON DISK' : undefined, { etag: calls.filter((c) => c[0] === 'mission').length > 1 ? '"v2"' : '"v1"' }),
    edit: (p, text, op) => model(`${text}+${op.name}`),
    files: () => ({ files: ['m.coral'], missions: [{ path: 'm.coral', kind: 'coral' }, { path: 't.pl', kind: 'prolog' }], logs: [] }),
    runs: () => ({ runs: [] }),
    abort: () => ({ ok: true }),
    stop: () => ({ ok: true }),
    ...over,
  };
  for (const [k, f] of Object.entries(base)) api[k] = async (...a) => { calls.push([k, ...a]); return f(...a); };
  return api;
}

test('effects: file_changed reloads a clean open file and says so; with edits shows the conflict with their text', async () => {
  const store = createStore();
  const api = fakeApi();
  const fx = createEffects(store, api);
  await fx.openFile('m.coral');
  await fx.fileChanged({ path: 'm.coral', etag: '"v2"' });
  assert.equal(store.getState().text, 'ON DISK');
  assert.equal(store.getState().etag, '"v2"');
  assert.match(store.getState().message.text, /changed on disk: reloaded/);
  await fx.applyOp({ op: 'add_place', net: 'n', name: 'q' });
  await fx.fileChanged({ path: 'm.coral', etag: '"v3"' });
  const s = store.getState();
  assert.equal(s.text, 'ON DISK+q');
  assert.equal(s.conflict.theirs, 'ON DISK');
  assert.match(s.message.text, /changed on disk while you have unsaved edits/);
  // Another file: the lists again.
  const before = api.calls.filter((c) => c[0] === 'files').length;
  await fx.fileChanged({ path: 'other.coral', etag: '"o"' });
  assert.equal(api.calls.filter((c) => c[0] === 'files').length, before + 1);
});

test('effects: the run list is read when a mission opens; Hard stop asks and is not sent when refused; Abort is sent', async () => {
  const store = createStore();
  let answer = false;
  const api = fakeApi({ runs: () => ({ runs: [{ path: 'runs/r1.jsonl', started: 'x', bytes: 1 }] }) });
  const fx = createEffects(store, api, { confirm: () => answer });
  await fx.openFile('m.coral');
  await new Promise((r) => setImmediate(r));
  assert.deepEqual(store.getState().runs.list.map((r) => r.path), ['runs/r1.jsonl']);
  assert.equal(await fx.stop(), false);
  assert.equal(api.calls.filter((c) => c[0] === 'stop').length, 0);
  answer = true;
  assert.equal(await fx.stop(), true);
  assert.equal(api.calls.filter((c) => c[0] === 'stop').length, 1);
  await fx.abort();
  assert.equal(api.calls.filter((c) => c[0] === 'abort').length, 1);
});

test('a .pl mission: listed with its kind, opened as read-only text, no graph, not editable; Run is allowed', async () => {
  let s = reduce(initialState(), { type: 'files/loaded', files: ['m.coral'], missions: [{ path: 'm.coral', kind: 'coral' }, { path: 't.pl', kind: 'prolog' }], logs: [] });
  assert.deepEqual(s.missions.map((m) => m.kind), ['coral', 'prolog']);
  const pl = { path: 't.pl', kind: 'prolog', read_only: true, text: 'mission(x).', etag: '"p"', layout: null, layout_etag: null, nets: [], scenarios: ['nominal'], check: 'done', diagnostics: [] };
  s = reduce(s, { type: 'file/opened', path: 't.pl', model: pl });
  assert.equal(s.readOnly, true);
  assert.equal(isProlog(s), true);
  assert.equal(s.netName, null);
  assert.equal(editable(s), false);
  assert.equal(reduce(s, { type: 'text/typed', text: 'changed' }), s);   // typing does nothing
  // The effects open it read-only and run it.
  const store = createStore();
  const api = fakeApi({ mission: () => pl, run: () => ({ ok: true }) });
  const fx = createEffects(store, api);
  await fx.openFile('t.pl');
  assert.equal(store.getState().readOnly, true);
  assert.equal(await fx.save(), false);
  await fx.run('nominal', 10);
  assert.deepEqual(api.calls.find((c) => c[0] === 'run'), ['run', 't.pl', 'nominal', 10]);
});

test('scenarios: nominal first, then the mission\'s; nominal alone without a scenarios folder', () => {
  assert.deepEqual(scenarioList(opened(model(undefined, { scenarios: ['leak', 'nominal', 'z'] }))), ['nominal', 'leak', 'z']);
  assert.deepEqual(scenarioList(opened(model(undefined, { scenarios: [] }))), ['nominal']);
  assert.deepEqual(scenarioList(initialState()), ['nominal']);
});

test('effects: the news of our own save does not reload the file', async () => {
  const store = createStore();
  const api = fakeApi({ saveFile: () => ({ ok: true, etag: '"mine"' }), saveLayout: () => ({ ok: true, etag: '"lmine"' }) });
  const fx = createEffects(store, api);
  await fx.openFile('m.coral');
  await fx.fileChanged({ path: 'm.coral', etag: '"v2"' });   // another program: reloaded
  await fx.applyOp({ op: 'add_place', net: 'n', name: 'q' });
  assert.equal(await fx.save(), true);
  const reads = api.calls.filter((c) => c[0] === 'mission').length;
  await fx.fileChanged({ path: 'm.coral', etag: '"mine"' });
  await fx.fileChanged({ path: 'm.coral.layout.json', etag: '"lmine"' });
  assert.equal(api.calls.filter((c) => c[0] === 'mission').length, reads);
  assert.equal(store.getState().text, 'ON DISK+q');
  assert.match(store.getState().message.text, /^saved/);
});

test('the breadcrumb and bands with the server\'s numbering: the mission net is instance 0, its own parent', () => {
  let s = ev(opened(), 'run_start', { run: 1 });
  s = ev(s, 'phase_start', { instance: 0, parent: 0, net: 'n', depth: 0, marking: {}, t: 0 });
  s = ev(s, 'phase_start', { instance: 1, parent: 0, net: 'ph', depth: 1, marking: {}, t: 0 });
  assert.deepEqual(breadcrumb(s).map((c) => c.net), ['n', 'ph']);
  s = ev(s, 'phase_end', { instance: 1, net: 'ph', exit: 'complete', t: 0.2 });
  assert.deepEqual(breadcrumb(s).map((c) => c.net), ['n']);
  s = ev(s, 'phase_start', { instance: 2, parent: 0, net: 'sub', depth: 1, marking: {}, t: 0.2 });
  assert.deepEqual(breadcrumb(s).map((c) => c.net), ['n', 'sub']);
  assert.deepEqual(chartData(s).phases.map((p) => [p.net, p.depth]), [['n', 0], ['ph', 1], ['sub', 1]]);
  s = ev(s, 'phase_end', { instance: 2, net: 'sub', exit: 'complete', t: 1 });
  s = ev(s, 'phase_end', { instance: 0, net: 'n', exit: 'closed', t: 1 });
  assert.deepEqual(breadcrumb(s), []);
});

test('phase_end: its PHASE action and the dropped ones are no longer in flight', () => {
  let s = ev(opened(), 'run_start', { run: 1 });
  s = ev(s, 'phase_start', { instance: 0, parent: 0, net: 'n', depth: 0, marking: {}, t: 0 });
  s = ev(s, 'action_start', { id: 5, instance: 0, transition: 't', kind: 'phase', primitive: 'ph', t: 0 });
  s = ev(s, 'phase_start', { instance: 1, parent: 0, net: 'ph', depth: 1, marking: {}, t: 0 });
  s = ev(s, 'action_start', { id: 6, instance: 1, transition: 'x', kind: 'ask', primitive: 'p', t: 0 });
  s = ev(s, 'action_start', { id: 7, instance: 0, transition: 'u', kind: 'exec', primitive: 'q', t: 0 });
  s = ev(s, 'phase_end', { instance: 1, net: 'ph', exit: 'abort', cancelled: true, action: 5, dropped: [6], t: 1 });
  assert.deepEqual(Object.keys(s.rs.inFlight), ['7']);
});

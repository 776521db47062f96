// The page's store without a browser: the reducer, the store's order of
// notifications, and the effects against a fake API.
//   node --test web/test/
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { createStore, reduce, initialState, dirty, displayNets, currentNet, tokensFor, editable, layoutByName, kMaxUndo } from '../src/store.js';
import { createEffects } from '../src/effects.js';

// A mission model as GET /api/mission gives it: one editable net a -> t -> b.
function model(text = 'net n { place a = 1; place b; transition t { wait { a } signal { b } } }', extra = {}) {
  return {
    path: 'm.coral', text, etag: '"v1"', layout_etag: null, layout: null, scenarios: [], diagnostics: [],
    nets: [{ name: 'n', kind: 'mission', file: 'm.coral', editable: true, exits: [],
      places: [{ name: 'a', initial: 1, line: 1 }, { name: 'b', initial: 0, line: 1 }],
      transitions: [{ name: 't', priority: 0, line: 1, inputs: [{ place: 'a', weight: 1 }], outputs: [{ place: 'b', weight: 1 }], actions: [] }] }],
    ...extra,
  };
}
const opened = (m = model()) => reduce(initialState(), { type: 'file/opened', path: 'm.coral', model: m });

test('a file opened: its text, version, net; nothing to save', () => {
  const s = opened();
  assert.equal(s.path, 'm.coral');
  assert.equal(s.etag, '"v1"');
  assert.equal(s.netName, 'n');
  assert.equal(dirty(s), false);
  assert.equal(editable(s), true);
  assert.deepEqual(s.undo, []);
});

test('an edit: the new text, one undo entry, the element selected, positions follow a rename', () => {
  let s = opened();
  s = reduce(s, { type: 'positions/set', net: 'n', positions: { 'p:a': { x: 1, y: 2 } }, replace: true });
  const m2 = model('TEXT2');
  s = reduce(s, { type: 'model/edited', path: 'm.coral', model: m2, op: { op: 'rename_place', net: 'n', name: 'a', to: 'z' } });
  assert.equal(s.text, 'TEXT2');
  assert.equal(dirty(s), true);
  assert.equal(s.undo.length, 1);
  assert.equal(s.selected, 'p:z');
  assert.deepEqual(s.positions.n['p:z'], { x: 1, y: 2 });
  assert.equal(s.positions.n['p:a'], undefined);
});

test('undo and redo walk the texts; undo to the saved text is clean again', () => {
  let s = opened();
  const t0 = s.text;
  s = reduce(s, { type: 'model/edited', path: 'm.coral', model: model('T1') });
  s = reduce(s, { type: 'model/edited', path: 'm.coral', model: model('T2') });
  s = reduce(s, { type: 'undo' });
  assert.equal(s.text, 'T1');
  assert.equal(s.checking, true);   // its model is asked for
  s = reduce(s, { type: 'undo' });
  assert.equal(s.text, t0);
  assert.equal(dirty(s), false);
  assert.equal(reduce(s, { type: 'undo' }), s);   // nothing more to undo
  s = reduce(s, { type: 'redo' });
  s = reduce(s, { type: 'redo' });
  assert.equal(s.text, 'T2');
  assert.equal(s.redo.length, 0);
  // A new edit after an undo drops the redo entries.
  s = reduce(reduce(s, { type: 'undo' }), { type: 'model/edited', path: 'm.coral', model: model('T3') });
  assert.deepEqual(s.redo, []);
});

test('the undo stack is bounded', () => {
  let s = opened();
  for (let i = 0; i < kMaxUndo + 20; i++) s = reduce(s, { type: 'model/edited', path: 'm.coral', model: model(`T${i}`) });
  assert.equal(s.undo.length, kMaxUndo);
});

test('typing: one undo entry per burst; a stale check is dropped; a text that does not compile keeps the nets', () => {
  let s = opened();
  const t0 = s.text;
  s = reduce(s, { type: 'text/typed', text: t0 + ' ' });
  s = reduce(s, { type: 'text/typed', text: t0 + '  ' });
  assert.equal(s.undo.length, 1);
  assert.equal(s.undo[0], t0);
  // The answer for an older text is dropped.
  const stale = reduce(s, { type: 'model/checked', path: 'm.coral', text: t0 + ' ', model: model('x', { nets: [] }) });
  assert.equal(stale, s);
  // A broken text: its diagnostics, the last nets still drawn.
  const broken = { ...model('x'), nets: [], diagnostics: [{ severity: 'error', line: 1, col: 1, message: 'expected net' }] };
  s = reduce(s, { type: 'model/checked', path: 'm.coral', text: t0 + '  ', model: broken });
  assert.equal(s.checking, false);
  assert.equal(s.model.broken, true);
  assert.equal(s.model.nets[0].name, 'n');
  assert.equal(s.model.diagnostics.length, 1);
  s = reduce(s, { type: 'typing/end' });
  s = reduce(s, { type: 'text/typed', text: 'other' });
  assert.equal(s.undo.length, 2);
});

test('a file that does not parse opens with no net, its text and its errors', () => {
  const s = opened({ ...model('net {'), nets: [], diagnostics: [{ severity: 'error', line: 1, col: 5, message: 'expected a name' }] });
  assert.equal(s.text, 'net {');
  assert.equal(s.netName, null);
  assert.equal(currentNet(s), null);
  assert.equal(s.model.diagnostics.length, 1);
});

test('save: clean; a 412: their version kept, keep-mine saves over it', () => {
  let s = reduce(opened(), { type: 'model/edited', path: 'm.coral', model: model('MINE') });
  s = reduce(s, { type: 'save/conflict', path: 'm.coral', theirs: 'THEIRS', etag: '"v2"', layoutEtag: '"l2"' });
  assert.equal(s.conflict.theirs, 'THEIRS');
  assert.equal(s.etag, '"v1"');
  s = reduce(s, { type: 'conflict/keep-mine' });
  assert.equal(s.etag, '"v2"');
  assert.equal(s.layoutEtag, '"l2"');
  assert.equal(s.conflict, null);
  s = reduce(s, { type: 'file/saved', path: 'm.coral', text: 'MINE', etag: '"v3"', layoutEtag: '"l3"', layoutSaved: true });
  assert.equal(dirty(s), false);
  assert.equal(s.etag, '"v3"');
});

test('positions moved by the user make the layout dirty; a layout does not', () => {
  let s = opened();
  s = reduce(s, { type: 'positions/set', net: 'n', positions: { 'p:a': { x: 0, y: 0 } }, replace: true });
  assert.equal(dirty(s), false);
  s = reduce(s, { type: 'positions/set', net: 'n', positions: { 'p:a': { x: 5, y: 0 } }, user: true });
  assert.equal(dirty(s), true);
  assert.deepEqual(layoutByName(s), { n: { a: { x: 5, y: 0 } } });
});

test('the live run: snapshot and run_start switch to the live view; follow shows the phase; run_end keeps the final marking', () => {
  let s = opened(model(undefined, {
    nets: [...model().nets, { name: 'ph', kind: 'phase', file: 'm.coral', editable: true, exits: [], places: [{ name: 'x', initial: 0 }], transitions: [] }],
  }));
  s = reduce(s, { type: 'run/event', name: 'run_start', data: { run: 1, mission: 'm.coral', scenario: 'nominal', speed: 10 } });
  assert.equal(s.view, 'live');
  assert.equal(s.rs.status, 'running');
  s = reduce(s, { type: 'run/event', name: 'phase_start', data: { instance: 2, parent: 1, net: 'ph', marking: { x: 1 } } });
  assert.equal(s.netName, 'ph');
  assert.deepEqual(tokensFor(s, 'ph'), { x: 1 });
  // The user picks a net: following stops, the run's events leave it there.
  s = reduce(s, { type: 'net/show', name: 'n', user: true });
  assert.equal(s.follow, false);
  s = reduce(s, { type: 'run/event', name: 'fired', data: { instance: 2, net: 'ph', transition: 'go', marking: {}, enabled: [] } });
  assert.equal(s.netName, 'n');   // follow off: the user's net stays
  s = reduce(s, { type: 'follow/set', follow: true });
  assert.equal(s.netName, 'ph');  // on again: the run's latest phase
  s = reduce(s, { type: 'run/event', name: 'telemetry', data: { t: 1, depth: 0.5, setpoint: 1 } });
  s = reduce(s, { type: 'run/event', name: 'fired', data: { instance: 1, net: 'n', transition: 't', marking: { b: 1 }, enabled: [] } });
  s = reduce(s, { type: 'run/event', name: 'run_end', data: { outcome: 'completed', exit: 0 } });
  assert.equal(s.rs.status, 'completed');
  assert.deepEqual(s.rs.markings.n, { b: 1 });
  assert.equal(s.rs.telemetry.length, 1);
  // The editor view shows the initial marking again.
  s = reduce(s, { type: 'view/set', view: 'edit' });
  assert.equal(tokensFor(s, 'n'), null);
});

test('a run event does not change the state it came to (the views compare by reference)', () => {
  const s = reduce(opened(), { type: 'run/event', name: 'run_start', data: { run: 1 } });
  const before = JSON.stringify(s.rs.markings);
  const s2 = reduce(s, { type: 'run/event', name: 'fired', data: { instance: 1, net: 'n', transition: 't', marking: { b: 1 }, enabled: ['t'] } });
  assert.equal(JSON.stringify(s.rs.markings), before);
  assert.notEqual(s2.rs, s.rs);
});

test('replay: opened at its end, seek, firing steps, close brings the live run back', () => {
  let s = reduce(opened(), { type: 'run/event', name: 'run_start', data: { run: 7 } });
  const live = s.rs;
  const events = [['run_start', { run: 1 }], ['fired', { instance: 1, net: 'n', transition: 't', marking: { b: 1 }, enabled: [] }],
    ['telemetry', { t: 1, depth: 1, setpoint: 1 }], ['fired', { instance: 1, net: 'n', transition: 'u', marking: { a: 1 }, enabled: [] }]];
  s = reduce(s, { type: 'replay/opened', path: 'r.jsonl', events });
  assert.equal(s.view, 'replay');
  assert.equal(s.replay.pos, 4);
  assert.deepEqual(s.rs.markings.n, { a: 1 });
  s = reduce(s, { type: 'replay/seek', pos: 2 });
  assert.deepEqual(s.rs.markings.n, { b: 1 });
  // Live events while a replay is shown go to the live run, not the replay.
  s = reduce(s, { type: 'run/event', name: 'telemetry', data: { t: 2, depth: 1, setpoint: 1 } });
  assert.deepEqual(s.rs.markings.n, { b: 1 });
  s = reduce(s, { type: 'replay/close' });
  assert.equal(s.replay, null);
  assert.equal(s.rs.run, live.run);
  assert.equal(s.view, 'live');
});

test('a counterexample plays on its net: forward, back, close', () => {
  let s = opened();
  s = reduce(s, { type: 'cex/play', net: 'n', key: 'no_deadlock', steps: [{ kind: 'fire', transition: 't', text: 'fire t' }] });
  assert.equal(s.view, 'cex');
  assert.deepEqual(tokensFor(s, 'n'), { a: 1 });
  s = reduce(s, { type: 'cex/go', i: 5 });
  assert.equal(s.cex.i, 1);
  assert.deepEqual(tokensFor(s, 'n'), { b: 1 });
  s = reduce(s, { type: 'cex/close' });
  assert.equal(s.cex, null);
  assert.equal(s.view, 'edit');
  // A net not in this load is not played.
  assert.equal(reduce(s, { type: 'cex/play', net: 'nope', key: 'k', steps: [] }), s);
});

test('a requirement\'s worst path moves into the phase each step runs in, one instance at a time', () => {
  const ph = { name: 'ph', kind: 'phase', file: 'm.coral', editable: true, exits: ['done'],
    places: [{ name: 'x', initial: 1, line: 2 }, { name: 'done', initial: 0, line: 2 }],
    transitions: [{ name: 'go', priority: 0, line: 2, inputs: [{ place: 'x', weight: 1 }], outputs: [{ place: 'done', weight: 1 }], actions: [] }] };
  const base = model();
  let s = opened({ ...base, nets: [...base.nets, ph] });
  const steps = [
    { kind: 'fire', transition: 't', instance: 'n', net: 'n', marks: [], text: 'n: fire t' },
    { kind: 'pass', transition: '', t_s: 0, marks: [], text: '0.0 s: the fault starts' },
    { kind: 'fire', transition: 'go', instance: 'n/ph#1', net: 'ph', t_s: 0, marks: [], text: 'n/ph#1: fire go' },
    { kind: 'pass', transition: '', t_s: 1.1, marks: [], text: '1.1 s: 1.1 s of waiting' },
    { kind: 'answer', transition: 'go', instance: 'n/ph#2', net: 'ph', t_s: 1.1, marks: ['x'], text: 'n/ph#2: an answer marks x' },
  ];
  s = reduce(s, { type: 'cex/play', net: 'n', key: 'requirement', steps });
  assert.equal(s.netName, 'n');
  assert.deepEqual(tokensFor(s, 'n'), { a: 1 });
  s = reduce(s, { type: 'cex/go', i: 2 });  // the fault: still on the mission
  assert.equal(s.netName, 'n');
  assert.deepEqual(tokensFor(s, 'n'), { b: 1 });
  s = reduce(s, { type: 'cex/go', i: 3 });  // into the phase's first call
  assert.equal(s.netName, 'ph');
  assert.deepEqual(tokensFor(s, 'ph'), { done: 1 });
  assert.equal(tokensFor(s, 'n'), null);
  s = reduce(s, { type: 'cex/go', i: 4 });  // time passing stays there
  assert.equal(s.netName, 'ph');
  s = reduce(s, { type: 'cex/go', i: 5 });  // a second call starts from the net's initial marking
  assert.deepEqual(tokensFor(s, 'ph'), { x: 2 });
  s = reduce(s, { type: 'cex/go', i: 4 });
  assert.deepEqual(tokensFor(s, 'ph'), { done: 1 });
  s = reduce(s, { type: 'cex/go', i: 0 });
  assert.equal(s.netName, 'n');
});

test('a page with no file shows the run\'s nets', () => {
  const s = reduce(initialState(), { type: 'run/event', name: 'snapshot', data: { run: 3, mission: 'x.coral', nets: model().nets, instances: [] } });
  assert.equal(displayNets(s)[0].name, 'n');
  assert.equal(s.netName, 'n');
  assert.equal(s.view, 'live');
});

test('unknown actions are bugs', () => {
  assert.throws(() => reduce(initialState(), { type: 'no/such' }), /unknown action/);
});

test('the store: a dispatch from a subscriber is done after every subscriber saw the state before it', () => {
  const store = createStore();
  const seen = [];
  store.subscribe((s, p, a) => { seen.push(`A:${a.type}`); if (a.type === 'mode/set') store.dispatch({ type: 'follow/set', follow: false }); });
  store.subscribe((s, p, a) => { seen.push(`B:${a.type}:${s.follow}`); });
  store.dispatch({ type: 'mode/set', mode: 'arc' });
  assert.deepEqual(seen, ['A:mode/set', 'B:mode/set:true', 'A:follow/set', 'B:follow/set:false']);
  assert.equal(store.getState().follow, false);
});

test('the store: a subscriber that throws does not stop the others or the queue, and the error comes out', () => {
  const store = createStore();
  let b = 0;
  store.subscribe((s, p, a) => { if (a.type === 'mode/set') { store.dispatch({ type: 'follow/set', follow: false }); throw new Error('view bug'); } });
  store.subscribe(() => { b++; });
  assert.throws(() => store.dispatch({ type: 'mode/set', mode: 'arc' }), /view bug/);
  assert.equal(b, 2);
  assert.equal(store.getState().follow, false);
});

// ------------------------------------------------------------ effects, with a fake API

function fakeApi(over = {}) {
  const calls = [];
  const api = {
    calls,
    mission: async (p) => { calls.push(['mission', p]); return model(); },
    edit: async (p, text, op) => { calls.push(['edit', op.op]); return model(`${text}+${op.name}`); },
    check: async (p, text) => { calls.push(['check', text]); return model(text); },
    saveFile: async (p, text, etag) => { calls.push(['saveFile', text, etag]); return { ok: true, etag: '"v9"' }; },
    saveLayout: async (p, l, etag) => { calls.push(['saveLayout', etag]); return { ok: true, etag: '"l9"' }; },
    ...over,
  };
  for (const k of Object.keys(over)) { const f = over[k]; api[k] = async (...a) => { calls.push([k, ...a]); return f(...a); }; }
  return api;
}

test('effects: switching file with unsaved edits asks; a no keeps the edits', async () => {
  const store = createStore();
  const api = fakeApi();
  let asked = 0, answer = false;
  const fx = createEffects(store, api, { confirm: () => { asked++; return answer; } });
  await fx.openFile('m.coral');
  await fx.applyOp({ op: 'add_place', net: 'n', name: 'q' });
  assert.equal(dirty(store.getState()), true);
  assert.equal(await fx.openFile('other.coral'), false);
  assert.equal(asked, 1);
  assert.equal(store.getState().path, 'm.coral');
  answer = true;
  assert.equal(await fx.openFile('other.coral'), true);
  assert.equal(store.getState().path, 'other.coral');
});

test('effects: a mission asked for ahead (pointer over it, or down) is taken by the click on it, once; not by another file, nor by a reload; the open file is not asked for ahead', async () => {
  const store = createStore();
  const api = fakeApi();
  const fx = createEffects(store, api);
  const asks = () => api.calls.filter((c) => c[0] === 'mission').length;
  fx.prefetch('m.coral');
  fx.prefetch('m.coral');   // pressed again: one request
  assert.equal(asks(), 1);
  assert.equal(await fx.openFile('m.coral'), true);
  assert.equal(asks(), 1);
  assert.equal(await fx.openFile('m.coral'), true);   // opened again: read again
  assert.equal(asks(), 2);
  fx.prefetch('other.coral');
  assert.equal(await fx.openFile('m.coral'), true);   // another file's answer is not taken
  assert.equal(asks(), 4);
  fx.prefetch('m.coral');                            // the open file: not asked for
  assert.equal(asks(), 4);
  assert.equal(await fx.reload(), true);              // a reload reads the file itself
  assert.equal(asks(), 5);
  fx.prefetch('other.coral');
  assert.equal(await fx.reload(), true);              // ... whatever was asked for ahead
  assert.equal(asks(), 7);
});

test('effects: typing is checked once it pauses, with the last text', async () => {
  const store = createStore();
  const api = fakeApi();
  const fx = createEffects(store, api);
  await fx.openFile('m.coral');
  fx.textTyped('a');
  fx.textTyped('ab');
  fx.textTyped('abc');
  await fx.flushCheck();
  const checks = api.calls.filter((c) => c[0] === 'check');
  assert.deepEqual(checks, [['check', 'abc']]);
  assert.equal(store.getState().checking, false);
  assert.equal(store.getState().model.text, 'abc');
});

test('effects: an op after typing is made on the typed text', async () => {
  const store = createStore();
  const api = fakeApi();
  const fx = createEffects(store, api);
  await fx.openFile('m.coral');
  fx.textTyped('typed');
  await fx.applyOp({ op: 'add_place', net: 'n', name: 'q' });
  assert.equal(store.getState().text, 'typed+q');
});

test('effects: save sends the text with the version read; a 412 fetches theirs; keep mine saves over it', async () => {
  const store = createStore();
  let refuse = true, reads = 0;
  const api = fakeApi({
    saveFile: (p, text, etag) => {
      if (refuse) { const e = new Error('412: changed'); e.status = 412; throw e; }
      return { ok: true, etag: '"v3"' };
    },
    mission: () => (reads++ === 0 ? model() : { ...model('THEIRS'), etag: '"v2"', layout_etag: '"l2"' }),
  });
  const fx = createEffects(store, api);
  await fx.openFile('m.coral');
  await fx.applyOp({ op: 'add_place', net: 'n', name: 'q' });
  assert.equal(await fx.save(), false);
  const c = store.getState().conflict;
  assert.equal(c.theirs, 'THEIRS');
  refuse = false;
  assert.equal(await fx.keepMine(), true);
  const saves = api.calls.filter((x) => x[0] === 'saveFile');
  assert.equal(saves[0][3], '"v1"');   // the first try: the version read then
  assert.equal(saves[1][3], '"v2"');   // keep mine: their version
  assert.equal(saves[1][2], store.getState().text);
  assert.equal(dirty(store.getState()), false);
});

test('effects: two saves at once send one PUT (a second with the same version would be refused)', async () => {
  const store = createStore();
  const api = fakeApi();
  const fx = createEffects(store, api);
  await fx.openFile('m.coral');
  await fx.applyOp({ op: 'add_place', net: 'n', name: 'q' });
  const [a, b] = await Promise.all([fx.save(), fx.save()]);
  assert.equal(a, true);
  assert.equal(b, true);
  assert.equal(api.calls.filter((c) => c[0] === 'saveFile').length, 1);
});

test('effects: the open file clicked again with unsaved edits asks before reading it again', async () => {
  const store = createStore();
  let asked = 0;
  const fx = createEffects(store, fakeApi(), { confirm: () => { asked++; return false; } });
  await fx.openFile('m.coral');
  await fx.applyOp({ op: 'add_place', net: 'n', name: 'q' });
  assert.equal(await fx.openFile('m.coral'), false);
  assert.equal(asked, 1);
  assert.equal(dirty(store.getState()), true);
});

// Issue 39: a clean tab reloading after another tab's save (two file_changed
// events, the text's and the layout's) said "your edit is kept": it had none.
test('effects: two reloads for one save elsewhere, in a clean tab, reload quietly', async () => {
  const store = createStore();
  let version = 1;
  const api = fakeApi({ mission: async () => model(`net n { place a = 1; place b; transition t { wait { a } signal { b } } } // v${version}`, { etag: `"v${version}"` }) });
  const said = [];
  store.subscribe((st, prev) => { if (st.message !== (prev && prev.message) && st.message && st.message.text) said.push([st.message.text, st.message.error]); });
  const fx = createEffects(store, api);
  await fx.openFile('m.coral');
  version = 2;
  await Promise.all([fx.fileChanged({ path: 'm.coral', etag: '"v2"' }), fx.fileChanged({ path: 'm.coral.layout.json', etag: '"l2"' })]);
  assert.equal(dirty(store.getState()), false);
  assert.match(store.getState().text, /\/\/ v2$/);
  assert.equal(said.filter(([t]) => /your edit is kept/.test(t)).length, 0, JSON.stringify(said));
});

// Issue 39: a save whose layout file was a link out (403) left the page
// "unsaved", then a conflict of 0 lines, and said nothing of the 403.
test('effects: a save whose layout is refused keeps the text saved and says why', async () => {
  const store = createStore();
  const refused = Object.assign(new Error("'m.coral.layout.json': a link out of the folder"), { status: 403 });
  const api = fakeApi({ saveLayout: async () => { throw refused; } });
  const fx = createEffects(store, api);
  await fx.openFile('m.coral');
  await fx.applyOp({ op: 'add_place', net: 'n', name: 'q' });
  assert.equal(await fx.save(), false);
  const s = store.getState();
  assert.equal(s.etag, '"v9"');                      // the text's new version is ours
  assert.equal(s.savedText, s.text);                 // the text is not unsaved
  assert.equal(s.conflict, null);
  assert.match(s.message.text, /saved m\.coral, but not its layout .*a link out of the folder/);
  assert.equal(s.message.error, true);
});

test('effects: keep mine reads the versions on disk first: a layout saved since is saved over; a text saved again is shown, not overwritten', async () => {
  const store = createStore();
  let onDisk = { text: 'THEIRS', etag: '"v2"', layout: '"l2"' };
  const api = fakeApi({
    saveFile: (p, text, etag) => {
      if (etag !== onDisk.etag) { const e = new Error('412: changed'); e.status = 412; throw e; }
      return { ok: true, etag: '"v9"' };
    },
    saveLayout: (p, l, etag) => {
      if (etag !== onDisk.layout) { const e = new Error('412: changed'); e.status = 412; throw e; }
      return { ok: true, etag: '"l9"' };
    },
    mission: () => ({ ...model(onDisk.text), etag: onDisk.etag, layout_etag: onDisk.layout }),
  });
  const fx = createEffects(store, api);
  await fx.openFile('m.coral');
  onDisk = { text: 'THEIRS', etag: '"v2"', layout: '"l2"' };
  await fx.applyOp({ op: 'add_place', net: 'n', name: 'q' });
  store.dispatch({ type: 'save/conflict', path: 'm.coral', theirs: 'THEIRS', etag: '"v2"', layoutEtag: '"l1"' });
  // The layout's notice has not come: the conflict still holds l1.
  onDisk = { text: 'THEIRS', etag: '"v2"', layout: '"l3"' };
  assert.equal(await fx.keepMine(), true);
  assert.equal(store.getState().conflict, null);
  assert.equal(dirty(store.getState()), false);
  // A text saved again after the conflict was shown: not saved over unseen.
  await fx.applyOp({ op: 'add_place', net: 'n', name: 'r' });
  store.dispatch({ type: 'save/conflict', path: 'm.coral', theirs: 'SECOND', etag: '"v10"', layoutEtag: '"l9"' });
  onDisk = { text: 'THIRD', etag: '"v11"', layout: '"l9"' };
  const saves = api.calls.filter((x) => x[0] === 'saveFile').length;
  assert.equal(await fx.keepMine(), false);
  assert.equal(api.calls.filter((x) => x[0] === 'saveFile').length, saves);
  assert.equal(store.getState().conflict.theirs, 'THIRD');
  assert.equal(store.getState().conflict.etag, '"v11"');
  assert.match(store.getState().message.text, /changed again/);
  assert.equal(await fx.keepMine(), true);   // now over the version shown
});

// Keep mine's re-read of the versions on disk takes a while; what happens
// meanwhile (review of the keep-mine race fix).
function keepMineRig(onRead) {
  const store = createStore();
  const disk = { text: 'THEIRS', etag: '"v2"', layout: '"l2"' };
  const api = fakeApi({
    saveFile: (p, text, etag) => {
      if (etag !== disk.etag) { const e = new Error('412: changed'); e.status = 412; throw e; }
      disk.text = text; disk.etag = '"v9"';
      return { ok: true, etag: disk.etag };
    },
    saveLayout: (p, l, etag) => {
      if (disk.layout == null ? etag != null : etag !== disk.layout) { const e = new Error('412: changed'); e.status = 412; throw e; }
      disk.layout = '"l9"';
      return { ok: true, etag: disk.layout };
    },
    mission: () => { const m = { ...model(disk.text), etag: disk.etag, layout_etag: disk.layout }; if (onRead.now) onRead.now(store, disk); return m; },
  });
  return { store, disk, api, fx: createEffects(store, api) };
}
async function inConflict(rig) {
  const { store, fx } = rig;
  await fx.openFile('m.coral');
  await fx.applyOp({ op: 'add_place', net: 'n', name: 'q' });
  store.dispatch({ type: 'save/conflict', path: 'm.coral', theirs: 'THEIRS', etag: '"v2"', layoutEtag: '"l2"' });
}

test('keep mine: a newer text saved while it re-reads is shown, not saved over unseen', async () => {
  const hook = {};
  const rig = keepMineRig(hook);
  await inConflict(rig);
  // Another tab saves THIRD while the re-read is on its way; its notice comes first.
  hook.now = (store, disk) => { disk.text = 'THIRD'; disk.etag = '"v3"'; store.dispatch({ type: 'disk/changed', path: 'm.coral', etag: '"v3"' }); hook.now = null; };
  const saves = rig.api.calls.filter((x) => x[0] === 'saveFile').length;
  assert.equal(await rig.fx.keepMine(), false);
  assert.equal(rig.api.calls.filter((x) => x[0] === 'saveFile').length, saves);
  assert.equal(rig.disk.text, 'THIRD');
  assert.match(rig.store.getState().message.text, /changed again/);
});

test('keep mine: Reload while it re-reads leaves the reloaded file alone', async () => {
  const hook = {};
  const rig = keepMineRig(hook);
  await inConflict(rig);
  hook.now = (store) => { store.dispatch({ type: 'conflict/dismiss' }); hook.now = null; };
  const saves = rig.api.calls.filter((x) => x[0] === 'saveFile').length;
  assert.equal(await rig.fx.keepMine(), false);
  assert.equal(rig.api.calls.filter((x) => x[0] === 'saveFile').length, saves);
});

test('keep mine: a layout file deleted on disk is written anew, not refused for ever', async () => {
  const rig = keepMineRig({});
  await inConflict(rig);
  rig.disk.layout = null;   // deleted
  assert.equal(await rig.fx.keepMine(), true);
  assert.equal(rig.store.getState().conflict, null);
  assert.equal(rig.disk.layout, '"l9"');
  const layoutSaves = rig.api.calls.filter((x) => x[0] === 'saveLayout');
  assert.equal(layoutSaves[layoutSaves.length - 1][3], null);   // no If-Match
});

test('keep mine: a failed re-read saves over the versions the conflict holds (the server still checks them)', async () => {
  const rig = keepMineRig({});
  await inConflict(rig);
  rig.api.mission = async () => { throw new Error('offline'); };
  assert.equal(await rig.fx.keepMine(), true);
  assert.equal(rig.disk.text.includes('q'), true);
});

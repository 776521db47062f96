// The page's one store: every piece of page state lives here, and changes
// only by dispatching an action to reduce(). Data goes one way: server
// answers and events, and the user's actions, become actions; the views
// subscribe and draw from the state they are given. Nothing here touches
// the DOM, so it runs (and is tested) under plain Node.
//
// State objects are not mutated: reduce() returns a new state whose
// unchanged parts are the same objects, so a view compares references to
// know what to draw again. One exception, for speed during long runs: the
// run's telemetry and reports arrays are append-only and shared between
// versions (a view compares their length).
import { emptyRun, applyEvent, chainOf } from './runstate.js';
import { placeId, transId, displayNets, currentNet, editable, dirty, nextFiring, positionsFromLayout, cexFocus } from './selectors.js';
export * from './selectors.js';

export const kMaxUndo = 200;

export function initialState() {
  return {
    files: [], logs: [], root: null,
    missions: [],        // {path, kind: 'coral'|'prolog'}: the missions under the folder
    runs: { mission: null, list: [] },   // the open mission's studio runs (GET /api/runs), newest first
    bannerClosed: null,  // the run_end whose banner the user closed
    disk: null,          // {path, etag, what, seq}: the last change on disk told (file_changed)
    path: null,          // the open file
    model: null,         // its mission model (the nets of the last text that compiled)
    text: null,          // the text: the source of truth
    savedText: null,     // the text as it is on disk (as last read or saved)
    etag: null,          // the version of the file read (If-Match on save)
    layoutEtag: null,    // the same for its layout file
    layoutDirty: false,  // positions moved since the last save
    checking: false,     // a typed text waits for its model
    undo: [],            // texts before each edit, newest last
    redo: [],            // texts undone, newest last
    typing: false,       // the current undo entry is a burst of typing
    netName: null,       // the net on the canvas
    positions: {},       // net -> node id -> {x, y}
    viewports: {},       // net -> {zoom, pan: {x, y}}, as the user left it
    pendingPos: null,    // where the next new node goes
    selected: null,      // the element id selected on the canvas
    focus: null,         // {id, from, to, seq}: an element and a text range to show (a diagnostic clicked)
    primitives: [],
    mode: 'select',      // select | place | transition | arc
    view: 'edit',        // edit | live | replay | cex
    follow: true,        // follow the run's phases
    rs: emptyRun(),      // the run shown (live, or the replay's)
    live: null,          // the live run, kept while a replay is shown
    replay: null,        // {path, mission, events, pos, playing, full: {telemetry, phases, track}}
    verify: null,        // the last verification result
    cex: null,           // {net, key, steps, i}
    conflict: null,      // {path, theirs, etag, layoutEtag}: a save refused with 412
    sonar: { frames: 0, mtime: null, frame: null, error: null },
    panels: { left: 220, right: 320, text: 360 },  // widths in px
    readOnly: false,     // the open file is shown as text only (not CORAL)
    sse: 'closed',
    message: { text: '', error: false },
    lastError: null,
    busy: 0,
  };
}

// The element a successful op leaves selected.
export function selectedAfter(op) {
  switch (op.op) {
    case 'add_place': case 'set_initial': return placeId(op.name);
    case 'rename_place': return placeId(op.to);
    case 'add_transition': return transId(op.name);
    case 'rename_transition': return transId(op.to);
    case 'set_actions': return transId(op.transition);
    default: return null;
  }
}

// Positions follow renames and deletions of the op.
function positionsAfterOp(positions, op) {
  const pos = { ...(positions[op.net] || {}) };
  const move = (from, to) => { if (pos[from]) { pos[to] = pos[from]; delete pos[from]; } };
  if (op.op === 'rename_place') move(placeId(op.name), placeId(op.to));
  if (op.op === 'rename_transition') move(transId(op.name), transId(op.to));
  if (op.op === 'delete_place') delete pos[placeId(op.name)];
  if (op.op === 'delete_transition') delete pos[transId(op.name)];
  return { ...positions, [op.net]: pos };
}

// The net to draw after a new model: the one drawn when it is still there.
function pickNet(nets, current, fresh) {
  if (!fresh && current && nets.some((n) => n.name === current)) return current;
  const mission = nets.find((n) => n.kind === 'mission' && n.editable) || nets.find((n) => n.editable) || nets.find((n) => n.kind === 'mission') || nets[0];
  return mission ? mission.name : null;
}

// The model kept when text does not compile: the last nets drawn, with the new diagnostics.
function mergeModel(prev, model) {
  if (model.nets && model.nets.length === 0 && prev && prev.nets && prev.nets.length) return { ...model, nets: prev.nets, broken: true };
  return model;
}

// While a run or replay is shown with follow on, the canvas shows the net
// of the run's latest phase.
function follow(s) {
  if (!s.follow || s.view === 'edit' || s.view === 'cex') return s;
  const n = s.rs.currentNet;
  if (n && n !== s.netName && displayNets(s).some((x) => x.name === n)) return { ...s, netName: n, selected: null };
  return s;
}

function pushUndo(s, text) {
  if (text == null) return s.undo;
  const u = s.undo.length >= kMaxUndo ? s.undo.slice(1) : s.undo.slice();
  u.push(text);
  return u;
}

function replayRun(events, k) {
  const rs = emptyRun();
  for (let i = 0; i < k; i++) applyEvent(rs, events[i][0], events[i][1]);
  return rs;
}

// The replay's run at event k: onwards from the run shown when k is ahead.
function replayTo(rs, r, k) {
  if (k < r.pos) return replayRun(r.events, k);
  if (k === r.pos) return rs;
  const n = cloneRun(rs);
  n.telemetry = rs.telemetry.slice();
  n.track = rs.track.slice();
  n.reports = rs.reports.slice();
  for (let i = r.pos; i < k; i++) applyEvent(n, r.events[i][0], r.events[i][1]);
  return n;
}

// A copy of rs that applyEvent may change without touching rs (the
// append-only telemetry and reports arrays stay shared).
function cloneRun(rs) {
  return { ...rs, instances: { ...rs.instances }, markings: { ...rs.markings }, enabled: { ...rs.enabled }, inFlight: { ...rs.inFlight } };
}

// ---------------------------------------------------------------- the run, its end, replay

// The live run (kept aside while a replay is shown).
export function liveRun(s) { return s.replay ? (s.live || emptyRun()) : s.rs; }

// Abort and Hard stop: while the live run goes.
export function runGoing(s) { return liveRun(s).status === 'running'; }

const fmtDepth = (m) => (typeof m === 'number' ? `${m.toFixed(2)} m` : 'unknown');

// The banner over the canvas for the live run's end (run_end, or the
// snapshot's `ended` after a reload); null when there is none or the user
// closed it. lines: what the banner says, first the outcome.
export function runBanner(s) {
  const e = liveRun(s).ended;
  if (!e || e === s.bannerClosed) return null;
  const hard = e.stop === 'hard';
  const lines = [];
  lines.push(`${hard ? 'HARD STOP — ' : ''}${e.outcome || 'ended'}${e.phase ? ` in phase ${e.phase}` : ''}${e.exit ? ` (exit ${e.exit})` : ''}`);
  if (e.reason) lines.push(e.reason);
  if (hard) lines.push(`The vehicle was NOT surfaced: nothing more was sent to it; last depth ${fmtDepth(e.final_depth_m)}.`);
  else if (e.stop === 'abort' || e.surfaced) lines.push(`${e.surfaced ? 'Surfaced' : 'Not surfaced'}; final depth ${fmtDepth(e.final_depth_m)}.`);
  else if (typeof e.final_depth_m === 'number') lines.push(`Final depth ${fmtDepth(e.final_depth_m)}.`);
  lines.push(e.log ? `log: ${e.log}` : 'no log');
  return { outcome: e.outcome || 'ended', hard, surfaced: !!e.surfaced, depth: e.final_depth_m ?? null, phase: e.phase || '',
    reason: e.reason || '', log: e.log || '', lines, ended: e };
}

// The breadcrumb while the run shown goes: the mission net, then each
// phase down to the active one ([{net, instance}]).
export function breadcrumb(s) {
  const rs = s.rs;
  if (rs.status !== 'running' || rs.active == null) return [];
  return chainOf(rs, rs.active).map((i) => ({ net: rs.instances[i].net, instance: i }));
}

// The depth chart: the run's telemetry and phase spans; in a replay the
// whole log's, with a cursor at the replay's position (its latest time).
export function chartData(s) {
  if (s.view === 'replay' && s.replay) return { telemetry: s.replay.full.telemetry, phases: s.replay.full.phases, cursor: s.replay.pos > 0 ? s.rs.t : null };
  return { telemetry: s.rs.telemetry, phases: s.rs.phases, cursor: null };
}

// What the map panel draws: the track ([t, x, y] points) and the vehicle
// (the latest point, or in a replay the point at the replay's position, none
// at its start). An empty track (a tank run) hides the panel.
export function mapData(s) {
  const last = (track) => (track.length ? track[track.length - 1] : null);
  if (s.view === 'replay' && s.replay) {
    const track = s.replay.full.track || [];
    return { track, vehicle: s.replay.pos > 0 ? last(s.rs.track) : null };
  }
  return { track: s.rs.track, vehicle: last(s.rs.track) };
}

// The scenarios to offer: nominal first, then the mission's scenarios/.
export function scenarioList(s) {
  return ['nominal', ...((s.model && s.model.scenarios) || []).filter((n) => n !== 'nominal')];
}

// A mission read as text only (PROLOG rules): no graph.
export function isProlog(s) { return !!(s.model && s.model.kind === 'prolog'); }

export function missionPaths(s) { return s.missions.length ? s.missions.map((m) => m.path) : s.files; }

// ---------------------------------------------------------------- the reducer
export function reduce(s, a) {
  switch (a.type) {
    case 'files/loaded':
      return { ...s, files: a.files || [], logs: a.logs || [], root: a.root ?? s.root, unlisted: a.unlisted || null,
        missions: a.missions || (a.files || []).map((p) => ({ path: p, kind: 'coral' })) };
    case 'runs/loaded':
      if (a.mission !== s.path) return s;
      return { ...s, runs: { mission: a.mission, list: a.runs || [] } };
    case 'banner/close':
      return liveRun(s).ended ? { ...s, bannerClosed: liveRun(s).ended } : s;

    // A file changed on disk (file_changed). The open file: reload it when
    // it has no unsaved edits, else the conflict (as after a 412: Reload or
    // Keep mine); the same bytes we hold (our own save) are no news. Another
    // file: the lists are read again. `disk.what` tells the effects which.
    case 'disk/changed': {
      const seq = (s.disk ? s.disk.seq : 0) + 1;
      const layout = s.path != null && a.path === `${s.path}.layout.json`;
      if (s.path != null && (a.path === s.path || layout)) {
        const mine = layout ? s.layoutEtag : s.etag;
        if (a.etag != null && a.etag === mine) return s;
        if (a.etag == null && !layout) return { ...s, disk: { path: a.path, etag: null, what: 'gone', seq } };
        if (dirty(s)) {
          // A conflict shown already holds the newest versions known of the
          // text and of the layout: a notice changes only its own file's, so
          // Keep mine saves over what is on disk, not over our old version.
          const c = s.conflict;
          if (c && a.etag === (layout ? c.layoutEtag : c.etag)) return s;
          return { ...s, disk: { path: a.path, etag: a.etag, what: 'conflict', seq },
            conflict: { path: s.path, theirs: layout && c ? c.theirs : null, disk: true,
              etag: layout ? (c ? c.etag : s.etag) : a.etag, layoutEtag: layout ? a.etag : (c ? c.layoutEtag : s.layoutEtag) } };
        }
        return { ...s, disk: { path: a.path, etag: a.etag, what: 'reload', seq } };
      }
      return { ...s, disk: { path: a.path, etag: a.etag, what: 'list', seq } };
    }
    case 'primitives/loaded':
      return { ...s, primitives: a.primitives || [] };
    case 'busy':
      return { ...s, busy: Math.max(0, s.busy + a.delta) };
    case 'message':
      return { ...s, message: { text: a.text || '', error: !!a.error }, lastError: a.error ? a.text : s.lastError };
    case 'sse':
      return { ...s, sse: a.state };
    case 'panel/resize':
      return { ...s, panels: { ...s.panels, [a.panel]: Math.max(a.min ?? 120, Math.min(a.max ?? 1200, Math.round(a.px))) } };
    case 'sonar': {
      const o = s.sonar;
      const fresh = a.mtime != null && a.mtime !== o.mtime;
      return { ...s, sonar: { frames: o.frames + (fresh ? 1 : 0), mtime: fresh ? a.mtime : o.mtime, frame: a.frame ?? o.frame, error: a.error ?? null } };
    }

    // A file read from disk: a fresh start of the editor.
    case 'file/opened': {
      const m = a.model;
      const nets = m.nets || [];
      const n = {
        ...s, path: a.path, model: m, text: m.text ?? '', savedText: m.text ?? '', etag: m.etag || null,
        layoutEtag: m.layout_etag || null, layoutDirty: false, checking: false, undo: [], redo: [], typing: false,
        readOnly: !!a.readOnly || !!m.read_only,
        runs: s.runs.mission === a.path ? s.runs : { mission: a.path, list: [] },
        positions: positionsFromLayout(m), viewports: {}, pendingPos: null, selected: null, focus: null,
        netName: pickNet(nets, null, true), cex: null, verify: null, conflict: null,
        view: a.keepView || s.view !== 'cex' ? s.view : 'edit',
        message: { text: '', error: false },
      };
      return n;
    }

    // The model of an edit op (POST /api/edit): its text replaces ours.
    case 'model/edited': {
      if (a.path !== s.path) return s;
      const model = mergeModel(s.model, a.model);
      const op = a.op;
      return {
        ...s, model, text: a.model.text ?? s.text, checking: false,
        undo: pushUndo(s, s.text), redo: [], typing: false,
        positions: op && op.net ? positionsAfterOp(s.positions, op) : s.positions,
        pendingPos: op && (op.op === 'add_place' || op.op === 'add_transition') ? (a.at || null) : s.pendingPos,
        selected: (op && selectedAfter(op)) || s.selected,
        netName: pickNet(model.nets || [], s.netName, false),
        view: s.view === 'cex' ? 'edit' : s.view, cex: s.view === 'cex' ? null : s.cex,
      };
    }

    // Text typed in the text pane: the text changes now, its model comes
    // later (model/checked). One undo entry per burst of typing.
    case 'text/typed': {
      if (a.text === s.text || s.path == null || s.readOnly) return s;
      return { ...s, text: a.text, checking: true, undo: s.typing ? s.undo : pushUndo(s, s.text), redo: s.typing ? s.redo : [], typing: true };
    }
    // The model of a text (POST /api/check); stale answers (the text moved on) are dropped.
    case 'model/checked': {
      if (a.path !== s.path || a.text !== s.text) return s;
      const model = mergeModel(s.model, { ...a.model, text: a.text });
      return { ...s, model, checking: false, netName: pickNet(model.nets || [], s.netName, false) };
    }
    case 'typing/end':
      return s.typing ? { ...s, typing: false } : s;

    case 'undo': {
      if (!s.undo.length) return s;
      const text = s.undo[s.undo.length - 1];
      return { ...s, text, undo: s.undo.slice(0, -1), redo: [...s.redo, s.text], typing: false, checking: true };
    }
    case 'redo': {
      if (!s.redo.length) return s;
      const text = s.redo[s.redo.length - 1];
      return { ...s, text, redo: s.redo.slice(0, -1), undo: pushUndo(s, s.text), typing: false, checking: true };
    }

    case 'file/saved':
      if (a.path !== s.path) return s;
      return { ...s, savedText: a.text, etag: a.etag ?? s.etag, layoutEtag: a.layoutEtag ?? s.layoutEtag,
        layoutDirty: a.layoutSaved ? false : s.layoutDirty, conflict: null };
    // A save refused with 412: their text and version, for Reload or merge by text.
    case 'save/conflict':
      if (a.path !== s.path) return s;
      // layoutEtag: undefined when not known (then ours is saved against); null: no layout file on disk.
      return { ...s, conflict: { path: a.path, theirs: a.theirs ?? null, etag: a.etag ?? null, layoutEtag: a.layoutEtag, disk: !!a.disk } };
    // Keep mine: the next save is made over their version.
    case 'conflict/keep-mine':
      if (!s.conflict) return s;
      return { ...s, etag: s.conflict.etag ?? s.etag, layoutEtag: s.conflict.layoutEtag === undefined ? s.layoutEtag : s.conflict.layoutEtag, conflict: null };
    case 'conflict/dismiss':
      return { ...s, conflict: null };

    // A net chosen by the user while a run or replay is followed stops the
    // following: the user's net stays on the canvas, with the run's marking.
    case 'net/show': {
      if (!displayNets(s).some((n) => n.name === a.name) || a.name === s.netName) return s;
      const stop = a.user && s.follow && (s.view === 'live' || s.view === 'replay');
      return { ...s, netName: a.name, selected: null, follow: stop ? false : s.follow };
    }
    case 'mode/set':
      return { ...s, mode: a.mode };
    case 'select':
      return a.id === s.selected ? s : { ...s, selected: a.id };
    case 'focus':
      return { ...s, focus: { id: a.id ?? null, net: a.net ?? null, from: a.from ?? null, to: a.to ?? null, seq: (s.focus ? s.focus.seq : 0) + 1 },
        netName: a.net && displayNets(s).some((n) => n.name === a.net) ? a.net : s.netName, selected: a.id ?? s.selected };

    // Positions: dragged nodes, a layout, new nodes placed.
    case 'positions/set': {
      const cur = s.positions[a.net] || {};
      const pos = a.replace ? { ...a.positions } : { ...cur, ...a.positions };
      return { ...s, positions: { ...s.positions, [a.net]: pos }, layoutDirty: s.layoutDirty || !!a.user, pendingPos: a.placed ? null : s.pendingPos };
    }
    case 'positions/clear':
      return { ...s, positions: { ...s.positions, [a.net]: {} }, viewports: { ...s.viewports, [a.net]: undefined }, layoutDirty: s.path != null };
    case 'viewport/set':
      return { ...s, viewports: { ...s.viewports, [a.net]: { zoom: a.zoom, pan: { x: a.pan.x, y: a.pan.y } } } };

    case 'view/set': {
      let n = { ...s, view: a.view };
      if (a.view !== 'cex') n.cex = null;
      if (a.view !== 'replay' && s.replay) n = { ...n, replay: null, rs: s.live || emptyRun(), live: null };
      return follow(n);
    }
    case 'follow/set':
      return follow({ ...s, follow: !!a.follow });

    // One event of GET /api/events.
    case 'run/event': {
      let n = s;
      if (s.replay && (a.name === 'run_start' || a.name === 'snapshot')) n = { ...n, replay: null, rs: n.live || emptyRun(), live: null };
      if (n.replay) return { ...n, live: applyEvent(cloneRun(n.live || emptyRun()), a.name, a.data) };
      n = { ...n, rs: applyEvent(cloneRun(n.rs), a.name, a.data) };
      if (a.name === 'run_start' || (a.name === 'snapshot' && a.data && a.data.run != null)) {
        n = { ...n, view: 'live', cex: null };
        if (!n.model && n.rs.nets && n.rs.nets.length) n.netName = pickNet(n.rs.nets, n.netName, false);
      }
      return follow(n);
    }
    case 'run/started':
      return follow({ ...s, view: 'live', cex: null, replay: null, rs: s.replay ? (s.live || emptyRun()) : s.rs, live: null });

    case 'replay/opened': {
      const events = a.events || [];
      const rs = replayRun(events, events.length);
      return follow({ ...s, live: s.replay ? s.live : s.rs,
        replay: { path: a.path, mission: a.mission ?? null, events, pos: events.length, playing: false, full: { telemetry: rs.telemetry, phases: rs.phases, track: rs.track } },
        rs, view: 'replay', cex: null });
    }
    case 'replay/seek': {
      if (!s.replay) return s;
      const k = Math.max(0, Math.min(s.replay.events.length, a.pos | 0));
      return follow({ ...s, replay: { ...s.replay, pos: k }, rs: replayTo(s.rs, s.replay, k) });
    }
    // Play steps the replay from firing to firing (replay/tick, on a timer
    // in the effects); from the end it starts again at 0. Pause stops it.
    case 'replay/play': {
      if (!s.replay || s.replay.playing) return s;
      const k = s.replay.pos >= s.replay.events.length ? 0 : s.replay.pos;
      return follow({ ...s, replay: { ...s.replay, pos: k, playing: true }, rs: k === s.replay.pos ? s.rs : replayRun(s.replay.events, k) });
    }
    case 'replay/pause':
      if (!s.replay || !s.replay.playing) return s;
      return { ...s, replay: { ...s.replay, playing: false } };
    case 'replay/tick': {
      const r = s.replay;
      if (!r || !r.playing) return s;
      const k = nextFiring(r.events, r.pos);
      return follow({ ...s, replay: { ...r, pos: k, playing: k < r.events.length }, rs: replayTo(s.rs, r, k) });
    }
    case 'replay/close':
      if (!s.replay) return s;
      return { ...s, replay: null, rs: s.live || emptyRun(), live: null, view: (s.live && s.live.status !== 'idle') ? 'live' : 'edit' };

    case 'verify/start':
      return { ...s, verify: { pending: true } };
    case 'verify/result':
      return { ...s, verify: a.result };
    case 'cex/play': {
      if (!displayNets(s).some((n) => n.name === a.net)) return s;
      let n = s.replay ? { ...s, replay: null, rs: s.live || emptyRun(), live: null } : s;
      n = { ...n, view: 'cex', netName: a.net, cex: { net: a.net, key: a.key, steps: a.steps, i: 0 } };
      return n;
    }
    case 'cex/go': {
      if (!s.cex) return s;
      const cex = { ...s.cex, i: Math.max(0, Math.min(s.cex.steps.length, a.i)) };
      // A worst path moves into the phase its step runs in, when that net is in the load.
      const at = cexFocus(cex).net;
      return { ...s, cex, netName: displayNets(s).some((n) => n.name === at) ? at : s.cex.net };
    }
    case 'cex/close':
      return { ...s, cex: null, view: s.rs.status === 'idle' ? 'edit' : 'live' };

    default:
      throw new Error(`unknown action ${a.type}`);
  }
}

// The store: getState, dispatch, subscribe. A dispatch made while the
// subscribers are being told of a change is queued and done after them, so
// every subscriber sees each state in order.
export function createStore(state = initialState()) {
  const subs = new Set();
  const queue = [];
  let notifying = false;
  function dispatch(action) {
    queue.push(action);
    if (notifying) return;
    notifying = true;
    // A subscriber that throws is a bug: the others are still told, the
    // queued actions still done, and the first error thrown at the end.
    let error = null;
    try {
      while (queue.length) {
        const act = queue.shift();
        const prev = state;
        state = reduce(state, act);
        if (state === prev) continue;
        for (const f of [...subs]) {
          try { f(state, prev, act); } catch (e) { if (!error) error = e; }
        }
      }
    } finally {
      notifying = false;
      queue.length = 0;
    }
    if (error) throw error;
  }
  return {
    getState: () => state,
    dispatch,
    subscribe(f) { subs.add(f); return () => subs.delete(f); },
  };
}

// What the page does with the server: each effect calls the JSON API
// (docs/studio.md) and dispatches what came back to the store. Effects
// never draw; views never call the API. `ui.confirm(text)` asks the user
// (window.confirm in the page, a stub in tests).
import { dirty, editable, displayNets, layoutByName } from './store.js';

export const kCheckDelayMs = 300;

export function createEffects(store, api, ui = {}) {
  const { dispatch, getState } = store;
  const confirm = ui.confirm || (() => true);
  const say = (text, error = false) => dispatch({ type: 'message', text, error });

  async function busy(fn) {
    dispatch({ type: 'busy', delta: 1 });
    try { return await fn(); } finally { dispatch({ type: 'busy', delta: -1 }); }
  }

  async function loadFiles() {
    try {
      const f = await api.files();
      dispatch({ type: 'files/loaded', files: f.files, logs: f.logs, root: f.root });
    } catch (e) { say(`files: ${e.message}`, true); }
  }

  async function loadPrimitives() {
    try {
      const p = await api.primitives();
      dispatch({ type: 'primitives/loaded', primitives: (p && p.primitives) || [] });
    } catch (e) { say(`primitives: ${e.message}`, true); }
  }

  // Opens path; with unsaved edits to another file, asks first. Returns
  // whether the file is open.
  async function openFile(path, { keepView = false, force = false } = {}) {
    const s = getState();
    // Also for the open file itself: opening it again reads it from disk.
    if (!force && dirty(s) && s.path) {
      if (!confirm(`Discard the unsaved changes to ${s.path}?`)) return false;
    }
    return busy(async () => {
      try {
        const model = await api.mission(path);
        dispatch({ type: 'file/opened', path, model, keepView: !!keepView, readOnly: !/\.coral$/.test(path) });
        return true;
      } catch (e) {
        say(`open ${path}: ${e.message}`, true);
        return false;
      }
    });
  }

  // Applies one edit op (docs/studio.md "Edits"); at: where a new node goes.
  async function applyOp(op, at) {
    const s = getState();
    if (!s.path || !s.model) { say('open a file first', true); return false; }
    if (op.net === s.netName && !editable(s)) { say(`${s.netName} is not declared in ${s.path}: open its own file to edit it`, true); return false; }
    if (s.checking) await flushCheck();
    return busy(async () => {
      const before = getState();
      try {
        const model = await api.edit(before.path, before.text, op);
        if (getState().text !== before.text) { say(`${op.op}: the text changed meanwhile; not applied`, true); return false; }
        dispatch({ type: 'model/edited', path: before.path, model, op, at });
        const errs = (model.diagnostics || []).filter((d) => d.severity === 'error').length;
        say(`${op.op}: done${errs ? `, ${errs} error(s)` : ''}`);
        return true;
      } catch (e) {
        say(`${op.op}: ${e.message}`, true);
        return false;
      }
    });
  }

  // ------------------------------------------------------------ the text
  // Typed text is checked once typing pauses for kCheckDelayMs; the model
  // of the last text wins (older answers are dropped by the reducer).
  let checkTimer = null;
  let checking = null;
  function textTyped(text) {
    dispatch({ type: 'text/typed', text });
    clearTimeout(checkTimer);
    checkTimer = setTimeout(() => { checkTimer = null; checkNow(); }, kCheckDelayMs);
  }
  async function checkNow() {
    const s = getState();
    if (!s.path || s.text == null) return;
    const { path, text } = s;
    const p = (async () => {
      try {
        const model = await api.check(path, text);
        dispatch({ type: 'model/checked', path, text, model });
      } catch (e) { say(`check: ${e.message}`, true); }
    })();
    checking = p;
    await busy(() => p);
    if (checking === p) checking = null;
  }
  // Waits for the check of the current text (typed, or undone).
  async function flushCheck() {
    if (checkTimer) { clearTimeout(checkTimer); checkTimer = null; await checkNow(); }
    else if (checking) await checking;
    if (getState().checking) await checkNow();
  }
  function endTyping() { dispatch({ type: 'typing/end' }); }

  async function undo() { const s = getState(); if (!s.undo.length) return; dispatch({ type: 'undo' }); await checkNow(); }
  async function redo() { const s = getState(); if (!s.redo.length) return; dispatch({ type: 'redo' }); await checkNow(); }

  // ------------------------------------------------------------ save
  // One save at a time: a second one made with the same version would be refused (412).
  let saving = null;
  async function save() {
    const s0 = getState();
    if (!s0.path || s0.text == null || s0.readOnly) return false;
    if (saving) return saving;
    saving = busy(async () => {
      const s = getState();
      const { path, text } = s;
      try {
        // Each save names the version it was made from: a file saved since
        // (by another tab, or on disk) is refused with 412, not overwritten.
        const r = await api.saveFile(path, text, s.etag);
        const l = await api.saveLayout(path, layoutByName(getState()), s.layoutEtag);
        dispatch({ type: 'file/saved', path, text, etag: r.etag, layoutEtag: l.etag, layoutSaved: true });
        say(`saved ${path}`);
        return true;
      } catch (e) {
        if (e.status === 412) {
          let theirs = null, etag = null, layoutEtag = null;
          try { const m = await api.mission(path); theirs = m.text; etag = m.etag; layoutEtag = m.layout_etag; } catch { /* shown without their text */ }
          dispatch({ type: 'save/conflict', path, theirs, etag, layoutEtag });
          say(`not saved: ${path} changed since you opened it (another tab or program saved it). ` +
              'Reload it (your edits here are dropped), or compare and keep yours over it.', true);
        } else {
          say(`save: ${e.message}`, true);
        }
        return false;
      }
    });
    try { return await saving; } finally { saving = null; }
  }
  // Merge by text: the user keeps their text over the new version.
  async function keepMine() { dispatch({ type: 'conflict/keep-mine' }); return save(); }
  async function reload() { const p = getState().path; if (p) return openFile(p, { force: true }); return false; }

  // ------------------------------------------------------------ run, replay, verify
  async function run(scenario, speed) {
    const s = getState();
    if (!s.path) return;
    if (dirty(s)) say('note: the run uses the file as saved; unsaved edits are not in it');
    try {
      const r = await api.run(s.path, scenario, speed);
      dispatch({ type: 'run/started' });
      if (!dirty(s)) say(`run ${r && r.run != null ? r.run : ''} started (${scenario}, ×${speed})`);
    } catch (e) {
      say(e.status === 409 ? 'a run is going already' : `run: ${e.message}`, true);
    }
  }
  async function stop() {
    try { await api.stop(); say('stop sent'); } catch (e) { say(`stop: ${e.message}`, true); }
  }

  async function openReplay(path) {
    try {
      const r = await api.replay(path);
      const s = getState();
      if (r.mission && r.mission !== s.path && s.files.includes(r.mission)) await openFile(r.mission, { keepView: true });
      dispatch({ type: 'replay/opened', path, mission: r.mission, events: (r.events || []).map(eventOf) });
    } catch (e) { say(`replay ${path}: ${e.message}`, true); }
  }

  async function verify() {
    const s = getState();
    if (!s.path) return;
    dispatch({ type: 'verify/start' });
    try {
      dispatch({ type: 'verify/result', result: await api.verify(s.path, s.text) });
    } catch (e) {
      dispatch({ type: 'verify/result', result: { error: e.message } });
    }
  }

  // A page opened on a run of a mission it has no model of (`strata run --studio`).
  async function adoptRunMission() {
    const s = getState();
    const m = s.rs.mission;
    if (!s.model && m && s.files.includes(m)) await openFile(m, { keepView: true });
  }

  // ------------------------------------------------------------ the event stream
  const EVENTS = ['snapshot', 'run_start', 'phase_start', 'phase_end', 'fired', 'action_start', 'action_finish', 'telemetry', 'report', 'run_end'];
  function connect(EventSourceImpl) {
    const es = new EventSourceImpl('/api/events');
    es.onopen = () => dispatch({ type: 'sse', state: 'open' });
    es.onerror = () => dispatch({ type: 'sse', state: 'error' });
    for (const name of EVENTS) {
      es.addEventListener(name, (ev) => {
        let data;
        try { data = JSON.parse(ev.data); } catch { return; }
        dispatch({ type: 'run/event', name, data });
        if (name === 'run_start' || name === 'snapshot') adoptRunMission();
      });
    }
    return es;
  }

  // The newest sonar scan, asked once a second while the studio has a sonar folder.
  function startSonar(setTimeoutImpl = setTimeout) {
    const tick = async () => {
      try {
        const s = await api.sonar();
        if (!s.dir) return;  // this studio has no sonar: stop asking
        dispatch({ type: 'sonar', mtime: s.latest ? s.latest.mtime_ms : null, frame: s.frame || null });
      } catch (e) { dispatch({ type: 'sonar', error: e.message }); }
      setTimeoutImpl(tick, 1000);
    };
    tick();
  }

  return { loadFiles, loadPrimitives, openFile, applyOp, textTyped, checkNow, flushCheck, endTyping, undo, redo,
    save, keepMine, reload, run, stop, openReplay, verify, connect, startSonar, say, displayNets: () => displayNets(getState()) };
}

// A replay event ({event, data} or a flat log line) as [name, data].
export function eventOf(e) {
  const name = e.event ?? e.type ?? e.name;
  let data = e.data;
  if (data === undefined) { data = { ...e }; delete data.event; delete data.type; }
  return [name, data];
}

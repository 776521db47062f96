// What the page does with the server: each effect calls the JSON API
// (docs/studio.md) and dispatches what came back to the store. Effects
// never draw; views never call the API. `ui.confirm(text)` asks the user
// (window.confirm in the page, a stub in tests).
import { applyModelPatch } from './patch.js';
import { dirty, editable, displayNets, layoutByName, missionPaths } from './store.js';

export const kCheckDelayMs = 300;
// How long a mission asked for ahead of a click (prefetch) is taken by openFile.
export const kAheadMs = 1000;

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
      dispatch({ type: 'files/loaded', files: f.files, logs: f.logs, root: f.root, missions: f.missions, unlisted: f.unlisted });
    } catch (e) { say(`files: ${e.message}`, true); }
  }

  // The open mission's studio runs (runs/ beside it), newest first.
  async function loadRuns() {
    const p = getState().path;
    if (!p) return;
    try {
      const r = await api.runs(p);
      dispatch({ type: 'runs/loaded', mission: p, runs: (r && r.runs) || [] });
    } catch (e) { say(`runs: ${e.message}`, true); }
  }

  async function loadPrimitives() {
    try {
      const p = await api.primitives();
      dispatch({ type: 'primitives/loaded', primitives: (p && p.primitives) || [] });
    } catch (e) { say(`primitives: ${e.message}`, true); }
  }

  // A mission asked for when the pointer comes onto it in the file list,
  // or goes down on it: the click follows (a tenth of a second or more for
  // a user), and openFile takes the answer when it is for the same path and
  // under kAheadMs old. The open file is not asked for ahead (a click on it
  // reads it again, after any save of this page).
  let ahead = null;
  function prefetch(path) {
    if (path === getState().path) return;
    if (ahead && ahead.path === path && Date.now() - ahead.at < kAheadMs) return;
    const answer = api.mission(path);
    answer.catch(() => { /* openFile says it, if it takes it */ });
    ahead = { path, at: Date.now(), answer };
  }

  // Opens path; with unsaved edits to another file, asks first. Returns
  // whether the file is open.
  async function openFile(path, { keepView = false, force = false } = {}) {
    const s = getState();
    const pre = !force && ahead && ahead.path === path && Date.now() - ahead.at < kAheadMs ? ahead.answer : null;
    ahead = null;
    // Also for the open file itself: opening it again reads it from disk.
    if (!force && dirty(s) && s.path) {
      if (!confirm(`Discard the unsaved changes to ${s.path}?`)) return false;
    }
    const textBefore = s.text;
    return busy(async () => {
      try {
        const model = await (pre || api.mission(path));
        // A reload for a change on disk (force) that the user's edit
        // overtook: the edit is kept (their save meets the new version: 412).
        // Only an edit counts: another reload that came first (the layout's
        // news after the text's, from one save in another tab) leaves the
        // text changed but nothing unsaved.
        const now = getState();
        if (force && now.path === path && now.text !== textBefore && dirty(now)) {
          say(`${path} changed on disk while you were editing it: your edit is kept; saving it will ask`, true);
          return false;
        }
        dispatch({ type: 'file/opened', path, model, keepView: !!keepView, readOnly: !/\.coral$/.test(path) });
        loadRuns();
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
        // The model held, when it is the server's own (not a broken text's
        // kept nets), is the base the answer may patch.
        const base = before.model && before.model.rev && !before.model.broken ? before.model : null;
        const ans = await api.edit(before.path, before.text, op, base && base.rev);
        const model = ans.patch && base && ans.base === base.rev ? applyModelPatch(base, ans) : ans;
        if (ans.patch && model === ans) throw new Error('the answer patches a model this page does not hold');
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
        // The text is saved: its new version is ours whatever the layout's
        // save says (else our own save came back as a change on disk, a
        // conflict of no line).
        let l;
        try {
          l = await api.saveLayout(path, layoutByName(getState()), s.layoutEtag);
        } catch (e) {
          dispatch({ type: 'file/saved', path, text, etag: r.etag, layoutSaved: false });
          if (e.status === 412) throw e;
          say(`saved ${path}, but not its layout (the positions): ${e.message}`, true);
          return false;
        }
        dispatch({ type: 'file/saved', path, text, etag: r.etag, layoutEtag: l.etag, layoutSaved: true });
        say(`saved ${path}`);
        return true;
      } catch (e) {
        if (e.status === 412) {
          let theirs = null, etag = null, layoutEtag;   // layoutEtag: undefined unless read (null: no layout file)
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
  // Merge by text: the user keeps their text over the new version. The
  // versions on disk are read again first: a layout saved since the conflict
  // was shown (its notice not yet here) is saved over too, and a text saved
  // again since is shown, not overwritten unseen.
  async function keepMine() {
    const { path, conflict: c } = getState();
    if (!path || !c) return false;
    let m = null;
    try { m = await api.mission(path); } catch { /* saved over the versions the conflict holds */ }
    const now = getState().conflict;
    // Reloaded, dismissed or another file opened meanwhile: nothing to keep.
    if (!now || getState().path !== path) return false;
    const again = () => {
      say(`not saved: ${path} changed again since it was shown. Compare again, then Reload or keep yours over it.`, true);
      return false;
    };
    if (m) {
      // Only over the text version the user compared with (c's): a newer one
      // (read now, or told of meanwhile) is shown first, never overwritten.
      if (c.etag != null && (m.etag !== c.etag || (now.etag != null && now.etag !== c.etag))) {
        if (m.etag !== c.etag) dispatch({ type: 'save/conflict', path, theirs: m.text, etag: m.etag, layoutEtag: m.layout_etag, disk: now.disk });
        return again();
      }
      dispatch({ type: 'save/conflict', path, theirs: c.theirs ?? m.text, etag: m.etag, layoutEtag: m.layout_etag, disk: now.disk });
    } else if (now !== c && now.etag !== c.etag) {
      return again();   // not read, and told of a newer text: not saved over unseen
    }
    dispatch({ type: 'conflict/keep-mine' });
    return save();
  }
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
  // Abort: the safe end (surface, then shut down).
  async function abort() {
    try { await api.abort(); say('abort sent: the vehicle is surfaced, then the run ends'); } catch (e) { say(`abort: ${e.message}`, true); }
  }
  // Hard stop: nothing more is sent to the vehicle; asks first.
  async function stop() {
    if (!confirm('Hard stop: nothing more is sent to the vehicle. It is NOT surfaced and is left to its own watchdog. ' +
      'Use Abort to surface it. Stop hard?')) return false;
    try { await api.stop(); say('hard stop sent: the vehicle is not surfaced'); return true; } catch (e) { say(`stop: ${e.message}`, true); return false; }
  }

  // ------------------------------------------------------------ changes on disk
  // A file changed on disk (file_changed): the reducer decides, this does it.
  async function fileChanged(d) {
    if (!d || typeof d.path !== 'string') return;
    if (saving) { try { await saving; } catch { /* said */ } }   // our own save's news carries the etag we get back
    const before = getState().disk;
    dispatch({ type: 'disk/changed', path: d.path, etag: d.etag ?? null });
    const disk = getState().disk;
    if (!disk || disk === before) return;   // no news (our own version)
    const path = getState().path;
    switch (disk.what) {
      case 'reload':
        if (await openFile(path, { keepView: true, force: true })) say(`${path} changed on disk: reloaded`);
        break;
      case 'conflict': {
        let theirs = null, etag = null, layoutEtag;   // layoutEtag: undefined unless read (null: no layout file)
        try { const m = await api.mission(path); theirs = m.text; etag = m.etag; layoutEtag = m.layout_etag; } catch { /* shown without their text */ }
        if (getState().conflict && getState().conflict.disk) dispatch({ type: 'save/conflict', path, theirs, etag, layoutEtag, disk: true });
        say(`${path} changed on disk while you have unsaved edits: Reload it (your edits here are dropped), or keep yours over it.`, true);
        break;
      }
      case 'gone':
        say(`${path} was deleted on disk (or is no longer readable inside the folder)`, true);
        loadFiles();
        break;
      default:
        loadFiles();
    }
  }

  // ------------------------------------------------------------ replay play/pause
  // A bounded timer: one firing a tick, stopped by pause, the end, or
  // at most one tick per event.
  let playTimer = null;
  function stopTimer() { if (playTimer) { clearIntervalImpl(playTimer); playTimer = null; } }
  const setIntervalImpl = ui.setInterval || ((f, ms) => setInterval(f, ms));
  const clearIntervalImpl = ui.clearInterval || ((t) => clearInterval(t));
  function playReplay(ms = 150) {
    const r = getState().replay;
    if (!r) return;
    stopTimer();
    dispatch({ type: 'replay/play' });
    let left = r.events.length + 1;
    playTimer = setIntervalImpl(() => {
      const x = getState().replay;
      if (!x || !x.playing || left-- <= 0) { stopTimer(); if (x && x.playing) dispatch({ type: 'replay/pause' }); return; }
      dispatch({ type: 'replay/tick' });
    }, ms);
  }
  function pauseReplay() { stopTimer(); dispatch({ type: 'replay/pause' }); }

  async function openReplay(path) {
    stopTimer();
    try {
      const r = await api.replay(path);
      const s = getState();
      if (r.mission && r.mission !== s.path && missionPaths(s).includes(r.mission)) await openFile(r.mission, { keepView: true });
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
    if (!s.model && m && missionPaths(s).includes(m)) await openFile(m, { keepView: true });
  }

  // ------------------------------------------------------------ the event stream
  const EVENTS = ['snapshot', 'run_start', 'phase_start', 'phase_end', 'fired', 'action_start', 'action_finish', 'telemetry', 'report', 'run_end', 'file_changed'];
  function connect(EventSourceImpl) {
    const es = new EventSourceImpl('/api/events');
    es.onopen = () => dispatch({ type: 'sse', state: 'open' });
    es.onerror = () => dispatch({ type: 'sse', state: 'error' });
    for (const name of EVENTS) {
      es.addEventListener(name, (ev) => {
        let data;
        try { data = JSON.parse(ev.data); } catch { return; }
        if (name === 'file_changed') { fileChanged(data); return; }
        dispatch({ type: 'run/event', name, data });
        if (name === 'run_start' || name === 'snapshot') adoptRunMission();
        // A run's end: its log is in the run list and the logs now.
        if (name === 'run_end') { loadRuns(); loadFiles(); }
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

  return { loadFiles, loadRuns, loadPrimitives, prefetch, openFile, applyOp, textTyped, checkNow, flushCheck, endTyping, undo, redo,
    save, keepMine, reload, run, abort, stop, fileChanged, playReplay, pauseReplay, openReplay, verify, connect, startSonar, say, displayNets: () => displayNets(getState()) };
}

// A replay event ({event, data} or a flat log line) as [name, data].
export function eventOf(e) {
  const name = e.event ?? e.type ?? e.name;
  let data = e.data;
  if (data === undefined) { data = { ...e }; delete data.event; delete data.type; }
  return [name, data];
}

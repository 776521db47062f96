// The Strata studio page: the editor of CORAL nets and their text, the live
// view of a run, replay of a mission log and the verifier's counterexamples
// played on the net. The contract with the server is docs/studio.md.
//
// Data goes one way: server answers and events, and the user's gestures,
// become actions on the one store (store.js); the views (canvas, text pane,
// inspector, panels) subscribe to it and draw. Effects (effects.js) are the
// only callers of the API. This file wires them together and binds the
// page's buttons.
import './style.css';
import { api } from './api.js';
import { $ } from './dom.js';
import { createStore, dirty, currentNet, prevFiring, nextFiring, runBanner, breadcrumb } from './store.js';
import { createEffects } from './effects.js';
import { createPanels } from './panels.js';
import { watchOpens } from './opentiming.js';

const store = createStore();
const { dispatch, getState } = store;
const fx = createEffects(store, api, { confirm: (t) => window.confirm(t) });
// The panels are made once the file list is drawn (init below).
let panels = null;
// The canvas, the text pane and the inspector (cytoscape and CodeMirror,
// most of the page's code) are loaded after the file list is shown
// (views.js); until then the store keeps what they will draw.
let views = null;

// ---------------------------------------------------------------- buttons and keys
const on = (sel, ev, f) => $(sel).addEventListener(ev, f);
for (const b of document.querySelectorAll('button.mode')) b.addEventListener('click', () => dispatch({ type: 'mode/set', mode: b.dataset.mode }));
store.subscribe((s, p) => {
  if (s.mode !== p.mode) for (const b of document.querySelectorAll('button.mode')) b.classList.toggle('active', b.dataset.mode === s.mode);
});
on('#btn-undo', 'click', () => fx.undo());
on('#btn-redo', 'click', () => fx.redo());
on('#btn-save', 'click', () => fx.save());
on('#btn-verify', 'click', () => fx.verify());
on('#btn-run', 'click', () => fx.run($('#run-scenario').value, Number($('#run-speed').value) || 10));
on('#btn-abort', 'click', () => fx.abort());
on('#btn-stop', 'click', () => fx.stop());
on('#btn-refresh', 'click', () => fx.loadFiles());
on('#follow', 'change', (ev) => dispatch({ type: 'follow/set', follow: ev.target.checked }));
on('#btn-edit-view', 'click', () => dispatch({ type: 'view/set', view: 'edit' }));
on('#btn-live-view', 'click', () => dispatch({ type: 'view/set', view: 'live' }));
on('#replay-slider', 'input', (ev) => dispatch({ type: 'replay/seek', pos: Number(ev.target.value) }));
on('#replay-close', 'click', () => { fx.pauseReplay(); dispatch({ type: 'replay/close' }); });
on('#replay-play', 'click', () => { const r = getState().replay; if (!r) return; if (r.playing) fx.pauseReplay(); else fx.playReplay(); });
on('#replay-prev', 'click', () => { const r = getState().replay; if (r) dispatch({ type: 'replay/seek', pos: prevFiring(r.events, r.pos) }); });
on('#replay-next', 'click', () => { const r = getState().replay; if (r) dispatch({ type: 'replay/seek', pos: nextFiring(r.events, r.pos) }); });
on('#cex-prev', 'click', () => { const c = getState().cex; if (c) dispatch({ type: 'cex/go', i: c.i - 1 }); });
on('#cex-next', 'click', () => { const c = getState().cex; if (c) dispatch({ type: 'cex/go', i: c.i + 1 }); });
on('#cex-close', 'click', () => dispatch({ type: 'cex/close' }));
let cexTimer = null;
on('#cex-play', 'click', () => {
  if (cexTimer) { clearInterval(cexTimer); cexTimer = null; return; }
  const c = getState().cex;
  if (!c) return;
  if (c.i >= c.steps.length) dispatch({ type: 'cex/go', i: 0 });
  cexTimer = setInterval(() => {
    const x = getState().cex;
    if (!x || x.i >= x.steps.length) { clearInterval(cexTimer); cexTimer = null; return; }
    dispatch({ type: 'cex/go', i: x.i + 1 });
  }, 700);
});

const inForm = (t) => t && (/^(INPUT|SELECT|TEXTAREA)$/.test(t.tagName) || (t.closest && t.closest('.cm-editor')));
document.addEventListener('keydown', (ev) => {
  const mod = ev.ctrlKey || ev.metaKey;
  if (mod && ev.key.toLowerCase() === 's') { ev.preventDefault(); fx.save(); return; }
  if (inForm(ev.target)) return;   // the text pane has its own keys
  if (mod && ev.key.toLowerCase() === 'z') { ev.preventDefault(); if (ev.shiftKey) fx.redo(); else fx.undo(); return; }
  if (mod && ev.key.toLowerCase() === 'y') { ev.preventDefault(); fx.redo(); return; }
  if (ev.key === 'Escape') dispatch({ type: 'mode/set', mode: 'select' });
  if (views) views.key(ev);   // delete, zoom
});
// Leaving the page with unsaved edits asks first.
window.addEventListener('beforeunload', (ev) => { if (dirty(getState())) { ev.preventDefault(); ev.returnValue = ''; } });

// Resizable panels: drag a splitter; widths live in the store.
const kPanelVar = { left: '--left-w', right: '--right-w', text: '--text-w' };
for (const sp of document.querySelectorAll('.splitter')) {
  sp.addEventListener('pointerdown', (ev) => {
    const panel = sp.dataset.panel;
    const x0 = ev.clientX, w0 = getState().panels[panel];
    const sign = panel === 'left' ? 1 : -1;   // the right-hand panels grow leftwards
    sp.setPointerCapture(ev.pointerId);
    sp.classList.add('dragging');
    const move = (e) => dispatch({ type: 'panel/resize', panel, px: w0 + sign * (e.clientX - x0) });
    const up = () => { sp.classList.remove('dragging'); sp.removeEventListener('pointermove', move); sp.removeEventListener('pointerup', up); };
    sp.addEventListener('pointermove', move);
    sp.addEventListener('pointerup', up);
  });
}
const applyPanels = (s, p) => {
  if (p && s.panels === p.panels) return;
  for (const [k, v] of Object.entries(s.panels)) document.body.style.setProperty(kPanelVar[k], `${v}px`);
};
store.subscribe(applyPanels);
applyPanels(getState(), null);

// How long each open from the file list took, click to net drawn (opentiming.js).
const opens = watchOpens(document, $('#cy'), store);

// ---------------------------------------------------------------- test hooks
// Browser tests read the page's state here (the canvas is a <canvas>).
window.__store = store;
window.__studio = {
  get state() { return getState(); },
  get path() { return getState().path; },
  get net() { return getState().netName; },
  get netName() { return getState().netName; },
  get text() { return getState().text; },
  get paneText() { return views && views.text.text; },
  get paneSelection() { return views && views.text.selection; },
  get lintCount() { return views && views.text.lintCount; },
  get dirty() { return dirty(getState()); },
  get model() { return getState().model; },
  get diagnostics() { return (getState().model && getState().model.diagnostics) || []; },
  get markings() { return getState().rs.markings; },
  get enabled() { return getState().rs.enabled; },
  get inFlight() { return Object.values(getState().rs.inFlight); },
  get telemetryCount() { return getState().rs.telemetry.length; },
  get reports() { return getState().rs.reports; },
  get runStatus() { return getState().rs.status; },
  get runEnded() { return getState().rs.ended; },
  get view() { return getState().view; },
  get mode() { return getState().mode; },
  get replay() { const r = getState().replay; return r && { path: r.path, pos: r.pos, length: r.events.length, playing: r.playing }; },
  get banner() { const b = runBanner(getState()); return b && { outcome: b.outcome, hard: b.hard, surfaced: b.surfaced, depth: b.depth, phase: b.phase, log: b.log, lines: b.lines }; },
  get breadcrumb() { return breadcrumb(getState()).map((c) => c.net); },
  get runs() { return getState().runs.list; },
  get missions() { return getState().missions; },
  get readOnly() { return getState().readOnly; },
  get chart() { const c = panels.chart; return { cursor: c.cursor, cursorX: c.cursorX, bands: c.phases.length, points: c.count }; },
  get map() { const m = panels.map; return { shown: !m.box.hidden, drawn: m.drawn }; },
  get replayKinds() { const r = getState().replay; return r && r.events.map((e) => e[0]); },
  get verify() { return getState().verify; },
  get cex() { const c = getState().cex; return c && { net: c.net, i: c.i, length: c.steps.length }; },
  get sse() { return getState().sse; },
  get lastError() { return getState().lastError; },
  get sonar() { return getState().sonar; },
  get scenarios() { return [...document.querySelectorAll('#run-scenario option')].map((o) => o.value); },
  get busy() { return getState().busy; },
  get checking() { return getState().checking; },
  get undoDepth() { return getState().undo.length; },
  get positions() { return getState().positions; },
  get currentNet() { return currentNet(getState()); },
  // The net drawn: {elements, nodes, inParts} (a large net: cytoscape holds the part near the view).
  get drawn() { return views && views.canvas.drawn; },
  // The opens from the file list, click to net drawn, measured in the page (opentiming.js).
  get opens() { return opens.slice(); },
  openFile: (p) => fx.openFile(p),
  showNet: (n) => dispatch({ type: 'net/show', name: n }),
  applyOp: (op, at) => fx.applyOp(op, at),
  save: () => fx.save(),
  setMode: (m) => dispatch({ type: 'mode/set', mode: m }),
};

// ---------------------------------------------------------------- start
// The views' chunk (cytoscape, CodeMirror) is fetched from the start,
// beside the file list, but only run once the list is shown: a
// modulepreload fetches and compiles, it does not run.
function preloadViews() {
  if (!import.meta.env.PROD) return;   // vite's dev server serves the sources
  const l = document.createElement('link');
  l.rel = 'modulepreload';
  l.href = new URL(/* @vite-ignore */ './app-views.js', import.meta.url).href;
  document.head.append(l);
}

// After the next frame is painted (or 100 ms, a tab in the background).
const afterPaint = () => new Promise((resolve) => { requestAnimationFrame(() => setTimeout(resolve, 0)); setTimeout(resolve, 100); });

async function init() {
  preloadViews();
  // The file list first: everything else (the panels, the event stream,
  // sonar, the views, the chart's library) after it is drawn. index.html
  // draws it the moment its answer comes, before the panels are made
  // (tens of ms), when that answer comes first.
  if (window.__filesAnswer) await window.__filesAnswer.catch(() => null);
  panels = createPanels(store, fx);
  await fx.loadFiles();
  // index.html drew the list when it came (panels.js has drawn it again
  // now): page load to file list (the e2e report) is when it was first
  // shown; a file clicked on that list is opened now.
  const early = window.__earlyList;
  window.__studio.filesAt = (early && early.shownAt) ?? performance.now();
  if (early) {
    early.stop();
    if (early.open && !getState().path) fx.openFile(early.open);
  }
  // The list painted before the views' chunk runs (a long task).
  await afterPaint();
  fx.connect(EventSource);
  fx.startSonar();
  // The views after the list is drawn: their chunk is run while the user
  // reads the list.
  const loaded = import('./views.js').then((m) => { views = m.startViews(store, fx); window.__cy = views.cy; window.__studio.viewsAt = performance.now(); });
  // The chart's library once the page is idle (a run's data loads it at
  // once), after the views' warm-up (views.js) and not in the first 2 s
  // after it, when the user is most likely to open a file.
  const idle = (f) => (window.requestIdleCallback ? window.requestIdleCallback(f, { timeout: 3000 }) : setTimeout(f, 500));
  const chartLater = () => setTimeout(() => idle(() => panels.chart.load()), 2000);
  loaded.then(() => views.warmed.then(chartLater), chartLater);
  await fx.loadPrimitives();
  await loaded;
  const want = new URLSearchParams(location.search).get('path');
  if (want && getState().files.includes(want)) await fx.openFile(want);
}
init();

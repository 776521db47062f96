// The Strata studio page: the editor of CORAL nets, the live view of a run,
// replay of a mission log and the verifier's counterexamples played on the net.
// The contract with the server is docs/studio.md.
import './style.css';
import { api } from './api.js';
import { $, state, cy, msg, setDirty } from './context.js';
import { loadFiles, openFile, showNet } from './view.js';
import { setMode, applyOp, save } from './editor.js';
import { setView, renderRunPanels, connect } from './live.js';
import { startSonar } from './sonar.js';

// The canvas follows its box (panels open and close around it).
new ResizeObserver(() => cy.resize()).observe($('#cy'));

window.__cy = cy;
window.__studio = {
  get path() { return state.path; },
  get net() { return state.netName; },
  get netName() { return state.netName; },
  get text() { return state.text; },
  get dirty() { return state.dirty; },
  get model() { return state.model; },
  get diagnostics() { return (state.model && state.model.diagnostics) || []; },
  get markings() { return state.rs.markings; },
  get lastMarking() { return state.rs.markings; },
  get enabled() { return state.rs.enabled; },
  get inFlight() { return Object.values(state.rs.inFlight); },
  get telemetryCount() { return state.rs.telemetry.length; },
  get telemetry() { return state.rs.telemetry; },
  get reports() { return state.rs.reports; },
  get runStatus() { return state.rs.status; },
  get runEnded() { return state.rs.ended; },
  get run() { return state.rs; },
  get view() { return state.view; },
  get mode() { return state.mode; },
  get replay() { return state.replay && { path: state.replay.path, pos: state.replay.pos, length: state.replay.events.length }; },
  get replayKinds() { return state.replay && state.replay.events.map((e) => e[0]); },
  get verify() { return state.verify; },
  get cex() { return state.cex && { net: state.cex.net, i: state.cex.i, length: state.cex.steps.length }; },
  get primitives() { return state.primitives; },
  get sse() { return state.sse; },
  get lastError() { return state.lastError; },
  get sonar() { return state.sonar; },
  get scenarios() { return [...document.querySelectorAll('#run-scenario option')].map((o) => o.value); },
  get busy() { return state.busy; },
  get positions() { return state.positions; },
  openFile: (p) => openFile(p),
  showNet: (n) => showNet(n),
  applyOp: (op, at) => applyOp(op, at),
  save: () => save(),
  setMode: (m) => setMode(m),
};


// ---------------------------------------------------------------- start
async function init() {
  setMode('select');
  setView('edit');
  setDirty(false);
  connect();
  startSonar();
  await loadFiles();
  try {
    const p = await api.primitives();
    state.primitives = (p && p.primitives) || [];
  } catch (e) { msg(`primitives: ${e.message}`, true); }
  const want = new URLSearchParams(location.search).get('path');
  if (want && state.files.includes(want)) await openFile(want);
  renderRunPanels();
}
$('#btn-refresh').addEventListener('click', loadFiles);
init();

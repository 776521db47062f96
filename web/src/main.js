// The Strata studio page: the editor of CORAL nets, the live view of a run,
// replay of a mission log and the verifier's counterexamples played on the net.
// The contract with the server is docs/studio.md.
import './style.css';
import { api } from './api.js';
import { emptyRun, applyEvent } from './runstate.js';
import { createCy, netElements, dagreLayout, diagnosticsByElement, placeId, transId, transitionLabel } from './graph.js';
import { DepthChart } from './chart.js';

const $ = (sel) => document.querySelector(sel);
const el = (tag, attrs = {}, ...kids) => {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (k === 'class') e.className = v;
    else if (k === 'text') e.textContent = v;
    else if (k.startsWith('on')) e.addEventListener(k.slice(2), v);
    else if (v !== undefined && v !== null && v !== false) e.setAttribute(k, v === true ? '' : v);
  }
  for (const kid of kids.flat()) if (kid != null) e.append(kid.nodeType ? kid : document.createTextNode(String(kid)));
  return e;
};

// ---------------------------------------------------------------- page state
const state = {
  files: [], logs: [], root: null,
  path: null,          // the open .coral file
  model: null,         // its mission model
  text: null,          // the current text (source of truth)
  dirty: false,
  netName: null,       // the net on the canvas
  positions: {},       // net -> node id -> {x, y}
  fitted: {},          // net -> bool, viewport fitted once
  primitives: [],
  mode: 'select',      // select | place | transition | arc
  view: 'edit',        // edit | live | replay | cex
  follow: true,        // follow the run's phases
  rs: emptyRun(),      // the live run (or the replay's run state)
  live: emptyRun(),    // kept while a replay is shown
  replay: null,        // {path, mission, events, pos}
  verify: null,        // the last verification result
  cex: null,           // {net, steps, i, markings}
  sse: 'closed',
  lastError: null,
  busy: 0,
};

const cy = createCy($('#cy'));
// Snapping finds the target while dragging; ehcomplete below keeps the arc
// only when the pointer was released on that node, never on a neighbour
// that happens to be a valid target.
const eh = cy.edgehandles({
  canConnect: (s, t) => canConnect(s, t),
  edgeParams: () => ({ data: { kind: 'new' }, classes: 'arc' }),
  hoverDelay: 50, snap: true, snapThreshold: 30, snapFrequency: 15, noEdgeEventsInDraw: true, disableBrowserGestures: true,
});
const chart = new DepthChart($('#chart'));
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
  get verify() { return state.verify; },
  get cex() { return state.cex && { net: state.cex.net, i: state.cex.i, length: state.cex.steps.length }; },
  get primitives() { return state.primitives; },
  get sse() { return state.sse; },
  get lastError() { return state.lastError; },
  get busy() { return state.busy; },
  get positions() { return state.positions; },
  openFile: (p) => openFile(p),
  showNet: (n) => showNet(n),
  applyOp: (op, at) => applyOp(op, at),
  save: () => save(),
  setMode: (m) => setMode(m),
};

// ---------------------------------------------------------------- helpers
function msg(text, isError = false) {
  const m = $('#edit-msg');
  m.textContent = text || '';
  m.classList.toggle('error', !!isError);
  if (isError) state.lastError = text;
}

function setDirty(d) {
  state.dirty = d;
  $('#dirty-mark').hidden = !d;
  $('#btn-save').disabled = !state.path || !d;
  document.title = (d ? '● ' : '') + 'Strata studio' + (state.path ? ` — ${state.path}` : '');
}

function currentNet() {
  const nets = displayNets();
  return nets.find((n) => n.name === state.netName) || null;
}

// The nets shown: the open file's, or the run's when no file is open.
function displayNets() {
  if (state.model && state.model.nets && state.model.nets.length) return state.model.nets;
  if (state.rs.nets) return state.rs.nets;
  return [];
}

function editable() {
  const n = currentNet();
  return !!(n && n.editable && state.model && state.path);
}

function uniqueName(prefix) {
  const net = currentNet();
  const used = new Set([...(net?.places || []).map((p) => p.name), ...(net?.transitions || []).map((t) => t.name), ...(net?.exits || [])]);
  for (let i = 1; ; i++) if (!used.has(prefix + i)) return prefix + i;
}

// ---------------------------------------------------------------- files
async function loadFiles() {
  try {
    const f = await api.files();
    state.files = f.files || [];
    state.logs = f.logs || [];
    state.root = f.root;
  } catch (e) { msg(`files: ${e.message}`, true); }
  const fl = $('#file-list'); fl.replaceChildren();
  for (const p of state.files) {
    fl.append(el('li', { class: p === state.path ? 'active' : '', 'data-path': p, title: p, onclick: () => openFile(p) }, p));
  }
  const ll = $('#log-list'); ll.replaceChildren();
  for (const p of state.logs) {
    ll.append(el('li', { 'data-path': p, title: p, class: state.replay && state.replay.path === p ? 'active' : '', onclick: () => openReplay(p) }, p));
  }
  if (!state.logs.length) ll.append(el('li', { class: 'muted' }, 'none'));
}

async function openFile(path, { keepView = false } = {}) {
  if (state.dirty && state.path && path !== state.path) {
    if (!window.confirm(`Discard the unsaved changes to ${state.path}?`)) return;
  }
  state.busy++;
  try {
    const model = await api.mission(path);
    state.path = path;
    state.positions = {};
    state.fitted = {};
    state.cex = null;
    if (!keepView && state.view === 'cex') state.view = 'edit';
    setModel(model, { fresh: true });
    setDirty(false);
    $('#path-label').textContent = path;
    $('#btn-verify').disabled = false;
    $('#btn-run').disabled = false;
    $('#verify-box').hidden = true;
    state.verify = null;
    for (const li of document.querySelectorAll('#file-list li')) li.classList.toggle('active', li.dataset.path === path);
    msg('');
  } catch (e) {
    msg(`open ${path}: ${e.message}`, true);
  } finally { state.busy--; }
}

// Layout of the model (net -> node name -> {x, y}) into positions by node id.
function positionsFromLayout(model) {
  const out = {};
  const layout = model.layout;
  if (!layout || typeof layout !== 'object') return out;
  for (const net of model.nets || []) {
    const l = layout[net.name];
    if (!l || typeof l !== 'object') continue;
    const pos = {};
    const placeNames = new Set([...(net.places || []).map((p) => p.name), ...(net.exits || [])]);
    const transNames = new Set((net.transitions || []).map((t) => t.name));
    for (const [name, xy] of Object.entries(l)) {
      if (!xy || typeof xy.x !== 'number' || typeof xy.y !== 'number') continue;
      if (placeNames.has(name)) pos[placeId(name)] = { x: xy.x, y: xy.y };
      if (transNames.has(name)) pos[transId(name)] = { x: xy.x, y: xy.y };
    }
    out[net.name] = pos;
  }
  return out;
}

function setModel(model, { fresh = false } = {}) {
  const prev = state.model;
  if (model.nets && model.nets.length === 0 && prev && prev.nets && prev.nets.length && !fresh) {
    // The text does not compile: keep drawing the last nets, show why.
    state.model = { ...model, nets: prev.nets, broken: true };
  } else {
    state.model = model;
  }
  state.text = model.text ?? state.text;
  if (fresh) {
    state.positions = positionsFromLayout(model);
    const nets = state.model.nets || [];
    const mission = nets.find((n) => n.kind === 'mission' && n.editable) || nets.find((n) => n.editable) || nets.find((n) => n.kind === 'mission') || nets[0];
    state.netName = mission ? mission.name : null;
  } else if (!currentNet()) {
    const nets = state.model.nets || [];
    state.netName = nets.length ? nets[0].name : null;
  }
  renderNetList();
  renderDiagnostics();
  renderText();
  renderNet();
}

function renderText() {
  $('#text-view').textContent = state.text || '';
}

function renderNetList() {
  const ul = $('#net-list'); ul.replaceChildren();
  for (const n of displayNets()) {
    const badge = n.kind === 'mission' ? 'mission' : 'phase';
    ul.append(el('li', { class: n.name === state.netName ? 'active' : '', 'data-net': n.name, title: n.file || '', onclick: () => showNet(n.name) },
      el('span', { class: `badge ${badge}` }, badge), ' ', n.name, n.editable ? '' : el('span', { class: 'muted' }, ' (import)')));
  }
}

function showNet(name) {
  if (!displayNets().find((n) => n.name === name)) return false;
  if (name === state.netName) return true;
  rememberPositions();
  state.netName = name;
  renderNetList();
  renderNet();
  return true;
}

// ---------------------------------------------------------------- canvas
function rememberPositions() {
  if (!state.netName) return;
  const pos = state.positions[state.netName] || (state.positions[state.netName] = {});
  cy.nodes().forEach((n) => { if (!n.hasClass('eh-handle') && !n.hasClass('eh-ghost')) pos[n.id()] = { ...n.position() }; });
}

let pendingPos = null; // where the next new node goes (a click on the canvas)

function tokensFor(netName) {
  if (state.view === 'cex' && state.cex && state.cex.net === netName) return state.cex.marking;
  if ((state.view === 'live' || state.view === 'replay') && state.rs.markings[netName]) return state.rs.markings[netName];
  return null;
}

function renderNet() {
  const net = currentNet();
  eh.hide && eh.hide();
  cy.elements().remove();
  renderInspector();
  if (!net) return;
  const els = netElements(net, tokensFor(net.name));
  const pos = state.positions[net.name] || (state.positions[net.name] = {});
  cy.batch(() => { cy.add(els); });
  const nodes = cy.nodes();
  const missing = nodes.filter((n) => !pos[n.id()]);
  if (missing.length === nodes.length) {
    dagreLayout(cy).run();
    nodes.forEach((n) => { pos[n.id()] = { ...n.position() }; });
    state.fitted[net.name] = true;
  } else {
    nodes.forEach((n) => { if (pos[n.id()]) n.position(pos[n.id()]); });
    let k = 0;
    missing.forEach((n) => {
      let p = pendingPos;
      if (!p) {
        // Near its neighbours, else at the centre of the view.
        const nb = n.neighborhood('node').filter((m) => pos[m.id()]);
        if (nb.length) {
          const c = nb.reduce((a, m) => ({ x: a.x + pos[m.id()].x, y: a.y + pos[m.id()].y }), { x: 0, y: 0 });
          p = { x: c.x / nb.length + 70, y: c.y / nb.length };
        } else {
          const ext = cy.extent();
          p = { x: (ext.x1 + ext.x2) / 2, y: (ext.y1 + ext.y2) / 2 };
        }
      }
      const q = freeSpot({ x: p.x + k * 30, y: p.y + k * 30 }, n);
      k++;
      n.position(q);
      pos[n.id()] = q;
    });
    pendingPos = null;
    if (!state.fitted[net.name]) { cy.fit(undefined, 30); state.fitted[net.name] = true; }
  }
  cy.edges().toggleClass('noev', state.mode === 'arc');
  applyDiagnosticClasses();
  updateDynamic(true);
}

// The first point from p (going right, then down) where a new node overlaps no other.
function freeSpot(p, self) {
  const others = cy.nodes().not(self).filter((m) => !m.hasClass('eh-handle'));
  const hits = (q) => others.some((m) => {
    const b = m.boundingBox({ includeLabels: false });
    return q.x > b.x1 - 30 && q.x < b.x2 + 30 && q.y > b.y1 - 30 && q.y < b.y2 + 30;
  });
  for (let ring = 0; ring < 12; ring++) {
    for (const [dx, dy] of [[0, 0], [1, 0], [0, 1], [-1, 0], [0, -1], [1, 1], [-1, 1], [1, -1], [-1, -1]]) {
      const q = { x: p.x + dx * ring * 50, y: p.y + dy * ring * 50 };
      if (!hits(q)) return q;
    }
  }
  return p;
}

function applyDiagnosticClasses() {
  const net = currentNet();
  const map = diagnosticsByElement(state.model, net);
  cy.nodes().removeClass('diag warning').removeData('diag');
  for (const [id, ds] of map) {
    const n = cy.getElementById(id);
    if (!n.nonempty()) continue;
    n.addClass('diag');
    if (ds.every((d) => d.severity !== 'error')) n.addClass('warning');
    n.data('diag', ds.map((d) => `${d.severity}: ${d.message}`).join('\n'));
  }
}

// Token counts and run classes, at most once per animation frame.
let frameQueued = false;
function scheduleFrame() {
  if (frameQueued) return;
  frameQueued = true;
  requestAnimationFrame(() => { frameQueued = false; updateDynamic(false); renderRunPanels(); });
}

function updateDynamic() {
  const net = currentNet();
  if (!net) return;
  const tokens = tokensFor(net.name);
  const inFlightByT = {};
  if (state.view === 'live' || state.view === 'replay') {
    for (const a of Object.values(state.rs.inFlight)) {
      if (a.net !== net.name) continue;
      (inFlightByT[a.transition] || (inFlightByT[a.transition] = [])).push(a.primitive || a.kind);
    }
  }
  const enabled = new Set((state.view === 'live' || state.view === 'replay') ? (state.rs.enabled[net.name] || []) : []);
  const last = (state.view === 'live' || state.view === 'replay') && state.rs.lastFired && state.rs.lastFired.net === net.name ? state.rs.lastFired.transition : null;
  const cexT = state.view === 'cex' && state.cex && state.cex.net === net.name && state.cex.i > 0 ? state.cex.steps[state.cex.i - 1].transition : null;
  const byName = new Map((net.transitions || []).map((t) => [t.name, t]));
  cy.batch(() => {
    cy.nodes('.place').forEach((n) => {
      const place = n.data('name');
      const k = tokens ? (tokens[place] || 0) : (n.data('initial') || 0);
      if (n.data('tokens') !== k) n.data('tokens', k);
      n.toggleClass('marked', k > 0);
    });
    cy.nodes('.transition').forEach((n) => {
      const name = n.data('name');
      n.toggleClass('enabled', enabled.has(name));
      const fl = inFlightByT[name];
      n.toggleClass('inflight', !!fl);
      n.toggleClass('fired', last === name);
      n.toggleClass('cex', cexT === name);
      const t = byName.get(name);
      const base = t ? transitionLabel(t) : name;
      const label = fl ? `${base}\n▶ ${fl.join(', ')}` : base;
      if (n.data('label') !== label) n.data('label', label);
    });
  });
}

// ---------------------------------------------------------------- diagnostics
function renderDiagnostics() {
  const ds = (state.model && state.model.diagnostics) || [];
  $('#diag-count').textContent = ds.length ? `(${ds.length})` : '';
  const ul = $('#diag-list'); ul.replaceChildren();
  if (!ds.length) { ul.append(el('li', { class: 'muted' }, 'none')); return; }
  for (const d of ds) {
    ul.append(el('li', { class: `sev-${d.severity}`, title: (d.notes || []).map((n) => n.message).join('\n'), onclick: () => focusDiagnostic(d) },
      el('b', {}, d.severity), ` ${d.file || ''}:${d.line}:${d.col ?? ''} `, d.message, d.kind ? el('span', { class: 'muted' }, ` [${d.kind}]`) : null));
  }
}

function focusDiagnostic(d) {
  for (const net of displayNets()) {
    const map = diagnosticsByElement(state.model, net);
    for (const [id, ds] of map) {
      if (ds.includes(d)) {
        showNet(net.name);
        const n = cy.getElementById(id);
        cy.elements().unselect();
        n.select();
        cy.animate({ center: { eles: n } }, { duration: 200 });
        return;
      }
    }
  }
}

const tooltip = $('#tooltip');
cy.on('mouseover', 'node', (ev) => {
  const n = ev.target;
  const d = n.data('diag');
  if (!d) return;
  const p = n.renderedPosition();
  const box = $('#cy').getBoundingClientRect();
  tooltip.textContent = d;
  tooltip.style.left = `${box.left + p.x + 18}px`;
  tooltip.style.top = `${box.top + p.y + 18}px`;
  tooltip.hidden = false;
});
cy.on('mouseout', 'node', () => { tooltip.hidden = true; });

// ---------------------------------------------------------------- editing
function canConnect(s, t) {
  if (!editable()) return false;
  if (s.same(t)) return false;
  const a = s.data('kind'), b = t.data('kind');
  if (!((a === 'place' && b === 'transition') || (a === 'transition' && b === 'place'))) return false;
  // One arc each way between a place and a transition.
  return cy.edges(`.arc[source = "${s.id()}"][target = "${t.id()}"]`).empty();
}

let pointer = null;  // where the last drag was, in model coordinates
cy.on('tapdrag', (ev) => { pointer = ev.position; });

cy.on('ehcomplete', (ev, source, target, added) => {
  added.remove();
  const box = target.boundingBox({ includeLabels: false });
  const slack = 6;
  if (!pointer || pointer.x < box.x1 - slack || pointer.x > box.x2 + slack || pointer.y < box.y1 - slack || pointer.y > box.y2 + slack) {
    msg('release the arc on the place or transition it should join', true);
    return;
  }
  const a = source.data('kind'), b = target.data('kind');
  if (!((a === 'place' && b === 'transition') || (a === 'transition' && b === 'place'))) {
    msg('an arc goes from a place to a transition or from a transition to a place', true);
    return;
  }
  applyOp({ op: 'add_arc', net: state.netName, from: source.data('name'), to: target.data('name'), weight: 1 });
});

function setMode(m) {
  state.mode = m;
  for (const b of document.querySelectorAll('button.mode')) b.classList.toggle('active', b.dataset.mode === m);
  if (m === 'arc') eh.enableDrawMode(); else eh.disableDrawMode();
  cy.edges().toggleClass('noev', m === 'arc');
  $('#cy').dataset.mode = m;
}
for (const b of document.querySelectorAll('button.mode')) b.addEventListener('click', () => setMode(b.dataset.mode));

// Applies one edit op (docs/studio.md "Edits"); at: where a new node goes.
async function applyOp(op, at) {
  if (!state.path || !state.model) { msg('open a file first', true); return false; }
  if (!editable() && op.net === state.netName) { msg(`${state.netName} is not declared in ${state.path}: open its own file to edit it`, true); return false; }
  const netName = op.net;
  rememberPositions();
  state.busy++;
  try {
    const model = await api.edit(state.path, state.text, op);
    const pos = state.positions[netName] || (state.positions[netName] = {});
    if (op.op === 'rename_place' && pos[placeId(op.name)]) { pos[placeId(op.to)] = pos[placeId(op.name)]; delete pos[placeId(op.name)]; }
    if (op.op === 'rename_transition' && pos[transId(op.name)]) { pos[transId(op.to)] = pos[transId(op.name)]; delete pos[transId(op.name)]; }
    if (op.op === 'delete_place') delete pos[placeId(op.name)];
    if (op.op === 'delete_transition') delete pos[transId(op.name)];
    if (op.op === 'add_place' || op.op === 'add_transition') pendingPos = at || null;
    const selected = selectedAfter(op);
    if (state.view === 'cex') state.view = 'edit';
    setModel(model);
    setDirty(true);
    if (selected) { const n = cy.getElementById(selected); if (n.nonempty()) n.select(); }
    const errs = (model.diagnostics || []).filter((d) => d.severity === 'error').length;
    msg(`${op.op}: done${errs ? `, ${errs} error(s)` : ''}`);
    return true;
  } catch (e) {
    msg(`${op.op}: ${e.message}`, true);
    return false;
  } finally { state.busy--; }
}

function selectedAfter(op) {
  switch (op.op) {
    case 'add_place': case 'set_initial': return placeId(op.name);
    case 'rename_place': return placeId(op.to);
    case 'add_transition': return transId(op.name);
    case 'rename_transition': return transId(op.to);
    case 'set_actions': return transId(op.transition);
    default: return null;
  }
}

function addNode(kind, at) {
  if (!editable()) { msg('this net is not editable here', true); return; }
  const input = $('#new-name');
  const name = input.value.trim() || uniqueName(kind === 'place' ? 'p' : 't');
  input.value = '';
  if (!/^[A-Za-z_][A-Za-z0-9_]*$/.test(name)) { msg(`'${name}' is not a name (a letter or _, then letters, digits, _)`, true); return; }
  if (kind === 'place') applyOp({ op: 'add_place', net: state.netName, name, initial: 0 }, at);
  else applyOp({ op: 'add_transition', net: state.netName, name }, at);
}

function centre() {
  const e = cy.extent();
  return { x: (e.x1 + e.x2) / 2, y: (e.y1 + e.y2) / 2 };
}

$('#btn-add-place').addEventListener('click', () => addNode('place', centre()));
$('#btn-add-transition').addEventListener('click', () => addNode('transition', centre()));
cy.on('tap', (ev) => {
  if (ev.target !== cy) return;
  if (state.mode === 'place') addNode('place', { ...ev.position });
  else if (state.mode === 'transition') addNode('transition', { ...ev.position });
});

function deleteSelected() {
  const sel = cy.$(':selected');
  if (sel.empty()) { msg('select something to delete', true); return; }
  const e = sel[0];
  const net = state.netName;
  if (e.isNode()) {
    if (e.data('kind') === 'place') applyOp({ op: 'delete_place', net, name: e.data('name') });
    else applyOp({ op: 'delete_transition', net, name: e.data('name') });
  } else if (e.data('kind') === 'arc') {
    applyOp({ op: 'delete_arc', net, from: e.data('from'), to: e.data('to') });
  } else {
    msg('an outcome arrow belongs to the transition\'s action: edit its actions', true);
  }
}
$('#btn-delete').addEventListener('click', deleteSelected);
document.addEventListener('keydown', (ev) => {
  if (ev.target && /^(INPUT|SELECT|TEXTAREA)$/.test(ev.target.tagName)) return;
  if (ev.key === 'Delete' || ev.key === 'Backspace') { if (editable()) deleteSelected(); }
  if (ev.key === 'Escape') setMode('select');
});
$('#btn-relayout').addEventListener('click', () => {
  if (!currentNet()) return;
  state.positions[state.netName] = {};
  renderNet();
  cy.fit(undefined, 30);
  if (state.path) setDirty(true);
});
$('#btn-fit').addEventListener('click', () => cy.fit(undefined, 30));
cy.on('dragfree', 'node', (ev) => {
  const n = ev.target;
  if (!state.netName || n.hasClass('eh-handle')) return;
  (state.positions[state.netName] || (state.positions[state.netName] = {}))[n.id()] = { ...n.position() };
  if (state.path && editable()) setDirty(true);
});

// ---------------------------------------------------------------- inspector
cy.on('select unselect', () => renderInspector());

function field(label, input) { return el('div', { class: 'field' }, el('label', {}, label), input); }

function renderInspector() {
  const body = $('#inspector-body');
  body.replaceChildren();
  const sel = cy.$(':selected');
  const net = currentNet();
  if (!net) { body.append(el('div', { class: 'muted' }, 'No net.')); return; }
  const ed = editable();
  if (sel.empty()) {
    body.append(el('div', {}, el('b', {}, net.name), ` (${net.kind}) `, el('span', { class: 'muted' }, net.file || '')),
      el('div', { class: 'muted' }, `${(net.places || []).length} places, ${(net.transitions || []).length} transitions; exits: ${(net.exits || []).join(', ')}`),
      el('div', { class: 'muted' }, ed ? 'Select an element, or add one with the toolbar.' : 'Read-only here: declared in an imported file.'));
    return;
  }
  const e = sel[0];
  const kind = e.data('kind');
  if (e.data('diag')) body.append(el('pre', { class: 'diag-msg' }, e.data('diag')));
  if (kind === 'place') inspectPlace(body, net, e, ed);
  else if (kind === 'transition') inspectTransition(body, net, e, ed);
  else if (kind === 'arc') inspectArc(body, net, e, ed);
  else body.append(el('div', {}, `${e.data('from')} → ${e.data('to')}`), el('div', { class: 'muted' }, 'Marked by the reply of the transition\'s action (edit its actions).'));
}

function renameRow(net, kind, name, ed) {
  const input = el('input', { id: 'insp-name', value: name, size: 16, disabled: !ed });
  const go = () => {
    const to = input.value.trim();
    if (!to || to === name) return;
    applyOp({ op: kind === 'place' ? 'rename_place' : 'rename_transition', net: net.name, name, to });
  };
  input.addEventListener('keydown', (ev) => { if (ev.key === 'Enter') go(); });
  return field('name', el('span', {}, input, ed ? el('button', { id: 'insp-rename', onclick: go }, 'Rename') : null));
}

function arcAdder(net, e, ed) {
  if (!ed) return null;
  const isPlace = e.data('kind') === 'place';
  const others = isPlace ? (net.transitions || []).map((t) => t.name) : [...(net.places || []).map((p) => p.name), ...(net.exits || []).filter((x) => !(net.places || []).some((p) => p.name === x))];
  const sel = el('select', { id: 'insp-arc-other' }, others.map((o) => el('option', { value: o }, o)));
  const w = el('input', { id: 'insp-arc-weight', type: 'number', min: 1, step: 1, value: 1, size: 3 });
  const go = () => {
    const o = sel.value;
    if (!o) return;
    const from = e.data('name'), to = o;
    applyOp({ op: 'add_arc', net: net.name, from, to, weight: Number(w.value) || 1 });
  };
  return field(isPlace ? 'arc to transition' : 'arc to place', el('span', {}, sel, ' ×', w, el('button', { id: 'insp-arc-add', onclick: go }, 'Add arc')));
}

function inspectPlace(body, net, e, ed) {
  const name = e.data('name');
  body.append(el('div', {}, el('b', {}, 'place '), name, e.data('exit') ? el('span', { class: 'badge exit' }, 'exit') : null, e.data('line') ? el('span', { class: 'muted' }, ` line ${e.data('line')}`) : null));
  body.append(renameRow(net, 'place', name, ed));
  const init = el('input', { id: 'insp-initial', type: 'number', min: 0, step: 1, value: e.data('initial') || 0, size: 4, disabled: !ed });
  const setInit = () => applyOp({ op: 'set_initial', net: net.name, name, initial: Math.max(0, Math.floor(Number(init.value) || 0)) });
  init.addEventListener('keydown', (ev) => { if (ev.key === 'Enter') setInit(); });
  body.append(field('initial tokens', el('span', {}, init, ed ? el('button', { id: 'insp-set-initial', onclick: setInit }, 'Set') : null)));
  if (state.view !== 'edit') body.append(field('tokens now', el('span', {}, String(e.data('tokens') || 0))));
  const a = arcAdder(net, e, ed); if (a) body.append(a);
  if (ed) body.append(el('button', { class: 'danger', onclick: deleteSelected }, 'Delete place'));
}

function inspectArc(body, net, e, ed) {
  body.append(el('div', {}, el('b', {}, e.hasClass('wait') ? 'wait arc ' : 'signal arc '), `${e.data('from')} → ${e.data('to')}`));
  const w = el('input', { id: 'insp-weight', type: 'number', min: 1, step: 1, value: e.data('weight') || 1, size: 4, disabled: !ed });
  const set = () => applyOp({ op: 'set_weight', net: net.name, from: e.data('from'), to: e.data('to'), weight: Math.max(1, Math.floor(Number(w.value) || 1)) });
  w.addEventListener('keydown', (ev) => { if (ev.key === 'Enter') set(); });
  body.append(field('weight', el('span', {}, w, ed ? el('button', { id: 'insp-set-weight', onclick: set }, 'Set') : null)));
  if (ed) body.append(el('button', { class: 'danger', onclick: deleteSelected }, 'Delete arc'));
}

const OUTCOMES = { EXEC: ['done →'], OOD: ['done →'], ASK: ['yes (1) →', 'no (0) →'], REPORT: [] };

function actionForOp(a) {
  if (a.kind === 'PHASE') return { kind: 'PHASE', target: a.target, outcomes: (a.outcomes || []).slice() };
  return { kind: 'TACTIC', type: a.type, target: a.target ?? '', args: (a.args || []).map(String), text: a.text ?? '', outcomes: (a.outcomes || []).slice() };
}

function inspectTransition(body, net, e, ed) {
  const name = e.data('name');
  const t = (net.transitions || []).find((x) => x.name === name);
  body.append(el('div', {}, el('b', {}, 'transition '), name, t && t.priority ? ` priority ${t.priority}` : '', e.data('line') ? el('span', { class: 'muted' }, ` line ${e.data('line')}`) : null));
  body.append(renameRow(net, 'transition', name, ed));
  const a = arcAdder(net, e, ed); if (a) body.append(a);
  if (!t) return;
  const actions = t.actions || [];
  const list = el('ul', { class: 'list actions', id: 'insp-actions' });
  actions.forEach((act, i) => {
    list.append(el('li', {}, act.label || `${act.kind} ${act.target}`, (act.outcomes || []).length ? el('span', { class: 'muted' }, ` → ${act.outcomes.join(', ')}`) : null,
      ed ? el('button', { class: 'small', title: 'Remove this action', onclick: () => {
        const rest = actions.filter((_, j) => j !== i).map(actionForOp);
        applyOp({ op: 'set_actions', net: net.name, transition: name, actions: rest });
      } }, '×') : null));
  });
  if (!actions.length) list.append(el('li', { class: 'muted' }, 'no action'));
  body.append(el('div', { class: 'sub' }, 'actions'), list);
  if (ed) body.append(actionPicker(net, name, actions));
  if (ed) body.append(el('button', { class: 'danger', onclick: deleteSelected }, 'Delete transition'));
}

// The picker of a new action: a TACTIC from the primitive catalogue (kind,
// primitive, its arguments, the places its reply marks) or a PHASE.
function actionPicker(net, tname, actions) {
  const box = el('div', { class: 'picker', id: 'action-picker' });
  const placeNames = [...new Set([...(net.places || []).map((p) => p.name), ...(net.exits || [])])];
  const placeSelect = (id) => el('select', { class: 'outcome', id }, placeNames.map((p) => el('option', { value: p }, p)));
  const kindSel = el('select', { id: 'pick-kind' }, ['EXEC', 'ASK', 'REPORT', 'OOD', 'PHASE'].map((k) => el('option', { value: k }, k === 'PHASE' ? 'PHASE' : `TACTIC ${k}`)));
  const targetSel = el('select', { id: 'pick-target' });
  const argsBox = el('div', { class: 'args' });
  const outBox = el('div', { class: 'outs' });
  const phases = displayNets().filter((n) => n.kind === 'phase');
  const fill = () => {
    const k = kindSel.value;
    targetSel.replaceChildren();
    if (k === 'PHASE') for (const p of phases) targetSel.append(el('option', { value: p.name }, p.name));
    else for (const p of state.primitives.filter((p) => (p.kind || '').toUpperCase() === k)) targetSel.append(el('option', { value: p.name, title: p.doc || '' }, p.name));
    targetSel.hidden = k === 'REPORT';
    fillArgs();
  };
  const fillArgs = () => {
    const k = kindSel.value;
    argsBox.replaceChildren();
    outBox.replaceChildren();
    if (k === 'PHASE') {
      const ph = phases.find((p) => p.name === targetSel.value);
      (ph ? ph.exits || [] : []).forEach((x, i) => outBox.append(field(`exit ${x} →`, placeSelect(`pick-out-${i}`))));
      return;
    }
    const prim = k === 'REPORT' ? state.primitives.find((p) => (p.kind || '') === 'report') : state.primitives.find((p) => p.name === targetSel.value);
    if (k === 'REPORT') {
      argsBox.append(field('text', el('input', { id: 'pick-text', size: 28, placeholder: 'a line for the operator' })));
    } else if (prim) {
      (prim.args || []).forEach((a, i) => {
        const isNum = a.type !== 'string';
        const inp = el('input', { id: `pick-arg-${i}`, class: 'arg', 'data-type': isNum ? 'number' : 'string', type: isNum ? 'number' : 'text', step: 'any',
          min: a.min ?? undefined, max: a.max ?? undefined, value: a.default ?? (a.min ?? (isNum ? 1 : '')), size: 8 });
        argsBox.append(field(`${a.name}${a.unit ? ` (${a.unit})` : ''}`, inp));
      });
      if (prim.doc) argsBox.append(el('div', { class: 'muted small' }, prim.doc));
    }
    (OUTCOMES[k] || []).forEach((lab, i) => outBox.append(field(lab, placeSelect(`pick-out-${i}`))));
  };
  kindSel.addEventListener('change', fill);
  targetSel.addEventListener('change', fillArgs);
  const add = () => {
    const k = kindSel.value;
    const outcomes = [...outBox.querySelectorAll('select.outcome')].map((s) => s.value);
    let act;
    if (k === 'PHASE') {
      if (!targetSel.value) { msg('no phase net to call', true); return; }
      act = { kind: 'PHASE', target: targetSel.value, outcomes };
    } else if (k === 'REPORT') {
      act = { kind: 'TACTIC', type: 'REPORT', target: '', args: [], text: box.querySelector('#pick-text').value, outcomes };
    } else {
      if (!targetSel.value) { msg(`no ${k} primitive in the catalogue`, true); return; }
      const args = [];
      for (const inp of argsBox.querySelectorAll('input.arg')) {
        if (inp.dataset.type === 'number') {
          if (inp.value === '' || !Number.isFinite(Number(inp.value))) { msg('an argument is not a number', true); return; }
          if ((inp.min !== '' && Number(inp.value) < Number(inp.min)) || (inp.max !== '' && Number(inp.value) > Number(inp.max))) { msg(`argument out of range [${inp.min}, ${inp.max}]`, true); return; }
          args.push(String(Number(inp.value)));
        } else args.push(inp.value);
      }
      act = { kind: 'TACTIC', type: k, target: targetSel.value, args, text: '', outcomes };
    }
    applyOp({ op: 'set_actions', net: net.name, transition: tname, actions: [...actions.map(actionForOp), act] });
  };
  box.append(el('div', { class: 'sub' }, 'add an action'), field('kind', kindSel), field('call', targetSel), argsBox, outBox,
    el('button', { id: 'pick-add', onclick: add }, 'Add action'));
  fill();
  return box;
}

// ---------------------------------------------------------------- save
function layoutByName() {
  rememberPositions();
  const out = {};
  for (const net of displayNets()) {
    const pos = state.positions[net.name];
    if (!pos) continue;
    const m = {};
    for (const [id, xy] of Object.entries(pos)) {
      const name = id.slice(2);
      m[name] = { x: Math.round(xy.x * 10) / 10, y: Math.round(xy.y * 10) / 10 };
    }
    out[net.name] = m;
  }
  return out;
}

async function save() {
  if (!state.path || state.text == null) return false;
  state.busy++;
  try {
    await api.saveFile(state.path, state.text);
    await api.saveLayout(state.path, layoutByName());
    setDirty(false);
    msg(`saved ${state.path}`);
    return true;
  } catch (e) {
    msg(`save: ${e.message}`, true);
    return false;
  } finally { state.busy--; }
}
$('#btn-save').addEventListener('click', save);
document.addEventListener('keydown', (ev) => { if ((ev.ctrlKey || ev.metaKey) && ev.key === 's') { ev.preventDefault(); save(); } });
window.addEventListener('beforeunload', (ev) => { if (state.dirty) { ev.preventDefault(); ev.returnValue = ''; } });

// ---------------------------------------------------------------- live view
function setView(v) {
  state.view = v;
  document.body.dataset.view = v;
  updateDynamic();
  renderRunPanels();
}

function renderRunPanels() {
  const rs = state.rs;
  const status = $('#run-status');
  status.textContent = state.view === 'replay' ? `replay: ${rs.status}` : rs.status;
  status.className = `status ${rs.status}`;
  const out = $('#run-outcome');
  if (rs.ended) {
    out.textContent = `${rs.ended.outcome}${rs.ended.exit ? ` (exit ${rs.ended.exit})` : ''}${rs.ended.reason ? `: ${rs.ended.reason}` : ''}${rs.ended.t != null ? ` at t=${rs.ended.t}` : ''}`;
    out.className = `outcome ${rs.ended.outcome}`;
  } else if (rs.status === 'running') {
    out.textContent = `running ${rs.mission || ''}${rs.scenario ? ` (${rs.scenario}, ×${rs.speed})` : ''}`;
    out.className = 'outcome running';
  } else { out.textContent = 'no run'; out.className = 'muted'; }
  const fl = $('#inflight-list'); fl.replaceChildren();
  for (const a of Object.values(rs.inFlight)) fl.append(el('li', {}, `▶ ${a.kind || ''} ${a.primitive || ''}`, el('span', { class: 'muted' }, ` ${a.net || ''}/${a.transition || ''}`)));
  const rl = $('#report-log');
  if (rl.childElementCount !== rs.reports.length) {
    rl.replaceChildren(...rs.reports.map((r) => el('li', {}, el('span', { class: 'muted' }, r.t != null ? `${Number(r.t).toFixed(1)} ` : ''), r.text)));
    rl.scrollTop = rl.scrollHeight;
  }
  chart.update(rs.telemetry);
}

function followRun() {
  if (!state.follow || state.view === 'edit' || state.view === 'cex') return;
  const n = state.rs.currentNet;
  if (n && n !== state.netName && displayNets().find((x) => x.name === n)) showNet(n);
}

const EVENTS = ['snapshot', 'run_start', 'phase_start', 'phase_end', 'fired', 'action_start', 'action_finish', 'telemetry', 'report', 'run_end'];
let es = null;
function connect() {
  es = new EventSource('/api/events');
  const conn = $('#conn-status');
  es.onopen = () => { state.sse = 'open'; conn.className = 'conn open'; conn.title = 'event stream: connected'; };
  es.onerror = () => { state.sse = 'error'; conn.className = 'conn error'; conn.title = 'event stream: reconnecting'; };
  for (const name of EVENTS) {
    es.addEventListener(name, (ev) => {
      let d;
      try { d = JSON.parse(ev.data); } catch { return; }
      onLiveEvent(name, d);
    });
  }
}

async function onLiveEvent(name, d) {
  if (state.replay && (name === 'run_start' || name === 'snapshot')) closeReplay();
  const target = state.replay ? state.live : state.rs;
  applyEvent(target, name, d);
  if (state.replay) return;
  if (name === 'run_start' || (name === 'snapshot' && d.run != null)) {
    if (state.view === 'cex') state.cex = null;
    setView('live');
    if (!state.model && d.mission) adoptRunMission(d.mission);
    renderNetList();
  }
  if (name === 'phase_start' || name === 'phase_end' || name === 'fired' || name === 'snapshot') followRun();
  scheduleFrame();
}

// A page opened on a run of a mission it has no file of (`strata run --studio`).
async function adoptRunMission(mission) {
  if (state.files.includes(mission)) { await openFile(mission, { keepView: true }); return; }
  const nets = state.rs.nets || [];
  if (nets.length) {
    state.netName = (nets.find((n) => n.kind === 'mission') || nets[0]).name;
    $('#path-label').textContent = `${mission} (run)`;
    renderNetList();
    renderNet();
  }
}

$('#btn-run').addEventListener('click', async () => {
  if (!state.path) return;
  const scenario = $('#run-scenario').value;
  const speed = Number($('#run-speed').value) || 10;
  if (state.dirty) msg('note: the run uses the file as saved; unsaved edits are not in it');
  try {
    const r = await api.run(state.path, scenario, speed);
    if (state.replay) closeReplay();
    setView('live');
    msg(`run ${r && r.run != null ? r.run : ''} started (${scenario}, ×${speed})`);
  } catch (e) {
    msg(e.status === 409 ? 'a run is going already' : `run: ${e.message}`, true);
  }
});
$('#btn-stop').addEventListener('click', async () => {
  try { await api.stop(); msg('stop sent'); } catch (e) { msg(`stop: ${e.message}`, true); }
});
$('#follow').addEventListener('change', (ev) => { state.follow = ev.target.checked; followRun(); });
$('#btn-edit-view').addEventListener('click', () => { state.cex = null; setView('edit'); if (state.replay) closeReplay(); });
$('#btn-live-view').addEventListener('click', () => { if (state.replay) closeReplay(); state.cex = null; setView('live'); followRun(); });

// ---------------------------------------------------------------- replay
function eventOf(e) {
  const name = e.event ?? e.type ?? e.name;
  let data = e.data;
  if (data === undefined) { data = { ...e }; delete data.event; delete data.type; }
  return [name, data];
}

async function openReplay(path) {
  try {
    const r = await api.replay(path);
    if (!state.replay) state.live = state.rs;
    state.replay = { path, mission: r.mission, events: (r.events || []).map(eventOf), pos: 0 };
    if (r.mission && r.mission !== state.path && state.files.includes(r.mission)) await openFile(r.mission, { keepView: true });
    const box = $('#replay-box');
    box.hidden = false;
    $('#replay-name').textContent = `${path} (${state.replay.events.length} events)`;
    const s = $('#replay-slider');
    s.max = String(state.replay.events.length);
    s.value = String(state.replay.events.length);
    for (const li of document.querySelectorAll('#log-list li')) li.classList.toggle('active', li.dataset.path === path);
    setView('replay');
    replayTo(state.replay.events.length);
  } catch (e) { msg(`replay ${path}: ${e.message}`, true); }
}

function replayTo(k) {
  const r = state.replay;
  if (!r) return;
  k = Math.max(0, Math.min(r.events.length, k));
  r.pos = k;
  const rs = emptyRun();
  for (let i = 0; i < k; i++) applyEvent(rs, r.events[i][0], r.events[i][1]);
  if (!rs.nets && r.events.length) rs.nets = null;
  state.rs = rs;
  $('#replay-pos').textContent = `${k} / ${r.events.length}`;
  const cur = k > 0 ? r.events[k - 1] : null;
  $('#replay-event').textContent = cur ? `${cur[0]} ${JSON.stringify(cur[1]).slice(0, 240)}` : '(start)';
  if ($('#replay-slider').value !== String(k)) $('#replay-slider').value = String(k);
  followRun();
  updateDynamic();
  renderRunPanels();
}

function closeReplay() {
  state.replay = null;
  state.rs = state.live;
  $('#replay-box').hidden = true;
  for (const li of document.querySelectorAll('#log-list li')) li.classList.remove('active');
  setView(state.rs.status === 'idle' ? 'edit' : 'live');
}

$('#replay-slider').addEventListener('input', (ev) => replayTo(Number(ev.target.value)));
$('#replay-close').addEventListener('click', closeReplay);
$('#replay-prev').addEventListener('click', () => state.replay && replayTo(prevFiring(state.replay.pos)));
$('#replay-next').addEventListener('click', () => state.replay && replayTo(nextFiring(state.replay.pos)));
function nextFiring(k) { const ev = state.replay.events; for (let i = k; i < ev.length; i++) if (ev[i][0] === 'fired') return i + 1; return ev.length; }
function prevFiring(k) { const ev = state.replay.events; for (let i = k - 2; i >= 0; i--) if (ev[i][0] === 'fired') return i + 1; return 0; }

// ---------------------------------------------------------------- verify
$('#btn-verify').addEventListener('click', async () => {
  if (!state.path) return;
  const box = $('#verify-box'), body = $('#verify-body');
  box.hidden = false;
  body.replaceChildren(el('div', { class: 'muted' }, 'verifying…'));
  try {
    const res = await api.verify(state.path, state.text);
    state.verify = res;
    renderVerify(res);
  } catch (e) {
    body.replaceChildren(el('div', { class: 'error' }, e.message));
    state.verify = { error: e.message };
  }
});

function renderVerify(res) {
  const body = $('#verify-body');
  body.replaceChildren(el('div', { class: res.ok ? 'ok' : 'error', id: 'verify-summary' }, res.ok ? 'all properties hold' : 'some properties fail'));
  for (const net of res.nets || []) {
    const ul = el('ul', { class: 'list small props' });
    for (const p of net.properties || []) {
      const li = el('li', { class: `prop ${p.status}`, 'data-key': p.key }, el('b', {}, p.status === 'holds' ? '✓ ' : p.status === 'fails' ? '✗ ' : '? '), `${p.key}: `, p.message || '');
      if (p.counterexample && (p.counterexample.steps || []).length) {
        li.append(' ', el('button', { class: 'small play-cex', onclick: () => playCex(net.name, p) }, '▶ play'));
      }
      ul.append(li);
    }
    body.append(el('div', { class: 'vnet' }, el('b', {}, `${net.ok ? '✓' : '✗'} ${net.name}`), el('span', { class: 'muted' }, ` ${net.states ?? '?'} states`)), ul);
  }
}

// Plays a counterexample on its net: the marking from the initial one,
// a firing takes its wait arcs and puts its signal arcs, an answer marks.
function playCex(netName, prop) {
  if (!showNet(netName)) { msg(`net ${netName} is not in this load`, true); return; }
  const steps = prop.counterexample.steps;
  state.cex = { net: netName, key: prop.key, steps, i: 0, marking: null, timer: null };
  if (state.replay) closeReplay();
  setView('cex');
  cexGo(0);
  const box = $('#cex-box');
  box.hidden = false;
  $('#cex-title').textContent = `${netName}: ${prop.key}`;
}

function cexMarking(netName, steps, i) {
  const net = displayNets().find((n) => n.name === netName);
  const m = {};
  for (const p of net.places || []) if (p.initial) m[p.name] = p.initial;
  const tr = new Map((net.transitions || []).map((t) => [t.name, t]));
  for (let k = 0; k < i; k++) {
    const s = steps[k];
    if (s.kind === 'fire') {
      const t = tr.get(s.transition);
      if (t) {
        for (const a of t.inputs || []) m[a.place] = (m[a.place] || 0) - (a.weight ?? 1);
        for (const a of t.outputs || []) m[a.place] = (m[a.place] || 0) + (a.weight ?? 1);
      }
    } else {
      for (const p of s.marks || []) m[p] = (m[p] || 0) + 1;
    }
  }
  for (const k of Object.keys(m)) if (m[k] <= 0) delete m[k];
  return m;
}

function cexGo(i) {
  const c = state.cex;
  if (!c) return;
  c.i = Math.max(0, Math.min(c.steps.length, i));
  c.marking = cexMarking(c.net, c.steps, c.i);
  if (state.netName !== c.net) showNet(c.net);
  $('#cex-pos').textContent = `${c.i} / ${c.steps.length}`;
  $('#cex-text').textContent = c.i > 0 ? `${c.i}. ${c.steps[c.i - 1].text}` : '(initial marking)';
  updateDynamic();
}
$('#cex-prev').addEventListener('click', () => state.cex && cexGo(state.cex.i - 1));
$('#cex-next').addEventListener('click', () => state.cex && cexGo(state.cex.i + 1));
$('#cex-play').addEventListener('click', () => {
  const c = state.cex;
  if (!c) return;
  if (c.timer) { clearInterval(c.timer); c.timer = null; return; }
  if (c.i >= c.steps.length) cexGo(0);
  c.timer = setInterval(() => {
    if (!state.cex || state.cex.i >= state.cex.steps.length) { clearInterval(c.timer); c.timer = null; return; }
    cexGo(state.cex.i + 1);
  }, 700);
});
$('#cex-close').addEventListener('click', () => {
  if (state.cex && state.cex.timer) clearInterval(state.cex.timer);
  state.cex = null;
  $('#cex-box').hidden = true;
  setView(state.rs.status === 'idle' ? 'edit' : 'live');
});

// ---------------------------------------------------------------- start
async function init() {
  setMode('select');
  setView('edit');
  setDirty(false);
  connect();
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

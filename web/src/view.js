// Files, nets on the canvas, and the checker's diagnostics on them.
import { api } from './api.js';
import { netElements, dagreLayout, diagnosticsByElement, placeId, transId, transitionLabel } from './graph.js';
import { $, el, state, cy, eh, msg, setDirty, currentNet, displayNets } from './context.js';
import { centre, renderInspector } from './editor.js';
import { renderRunPanels, openReplay } from './live.js';

// ---------------------------------------------------------------- files
export async function loadFiles() {
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

export async function openFile(path, { keepView = false } = {}) {
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
    state.etag = model.etag || null;              // sent back as If-Match on save
    state.layoutEtag = model.layout_etag || null;
    setDirty(false);
    $('#path-label').textContent = path;
    fillScenarios(model.scenarios);
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

// The scenarios beside the mission, nominal first (the built-in one when
// the folder has none of that name).
function fillScenarios(names) {
  const select = $('#run-scenario');
  const keep = select.value;
  const list = ['nominal', ...(names || []).filter((n) => n !== 'nominal')];
  select.replaceChildren(...list.map((n) => el('option', {}, n)));
  select.value = list.includes(keep) ? keep : 'nominal';
}

// Layout of the model (net -> node name -> {x, y}) into positions by node id.
export function positionsFromLayout(model) {
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

export function setModel(model, { fresh = false } = {}) {
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

export function renderText() {
  $('#text-view').textContent = state.text || '';
}

export function renderNetList() {
  const ul = $('#net-list'); ul.replaceChildren();
  for (const n of displayNets()) {
    const badge = n.kind === 'mission' ? 'mission' : 'phase';
    ul.append(el('li', { class: n.name === state.netName ? 'active' : '', 'data-net': n.name, title: n.file || '', onclick: () => showNet(n.name) },
      el('span', { class: `badge ${badge}` }, badge), ' ', n.name, n.editable ? '' : el('span', { class: 'muted' }, ' (import)')));
  }
}

export function showNet(name) {
  if (!displayNets().find((n) => n.name === name)) return false;
  if (name === state.netName) return true;
  rememberPositions();
  state.netName = name;
  renderNetList();
  renderNet();
  return true;
}

// ---------------------------------------------------------------- canvas
export function rememberPositions() {
  if (!state.netName) return;
  const pos = state.positions[state.netName] || (state.positions[state.netName] = {});
  cy.nodes().forEach((n) => { if (!n.hasClass('eh-handle') && !n.hasClass('eh-ghost')) pos[n.id()] = { ...n.position() }; });
}


export function tokensFor(netName) {
  if (state.view === 'cex' && state.cex && state.cex.net === netName) return state.cex.marking;
  if ((state.view === 'live' || state.view === 'replay') && state.rs.markings[netName]) return state.rs.markings[netName];
  return null;
}

export function renderNet() {
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
      let p = state.pendingPos;
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
    state.pendingPos = null;
    if (!state.fitted[net.name]) { cy.fit(undefined, 30); state.fitted[net.name] = true; }
  }
  cy.edges().toggleClass('noev', state.mode === 'arc');
  applyDiagnosticClasses();
  updateDynamic(true);
}

// The first point from p (going right, then down) where a new node overlaps no other.
export function freeSpot(p, self) {
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

export function applyDiagnosticClasses() {
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
export function scheduleFrame() {
  if (frameQueued) return;
  frameQueued = true;
  requestAnimationFrame(() => { frameQueued = false; updateDynamic(false); renderRunPanels(); });
}

export function updateDynamic() {
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
export function renderDiagnostics() {
  const ds = (state.model && state.model.diagnostics) || [];
  $('#diag-count').textContent = ds.length ? `(${ds.length})` : '';
  const ul = $('#diag-list'); ul.replaceChildren();
  if (!ds.length) { ul.append(el('li', { class: 'muted' }, 'none')); return; }
  for (const d of ds) {
    ul.append(el('li', { class: `sev-${d.severity}`, title: (d.notes || []).map((n) => n.message).join('\n'), onclick: () => focusDiagnostic(d) },
      el('b', {}, d.severity), ` ${d.file || ''}:${d.line}:${d.col ?? ''} `, d.message, d.kind ? el('span', { class: 'muted' }, ` [${d.kind}]`) : null));
  }
}

export function focusDiagnostic(d) {
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

export const tooltip = $('#tooltip');
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

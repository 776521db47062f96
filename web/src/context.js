// The studio page's shared context: DOM helpers, the page state, the
// cytoscape instance with its arc drawing (edgehandles), the depth chart.
import { emptyRun } from './runstate.js';
import { createCy } from './graph.js';
import { DepthChart } from './chart.js';

export const $ = (sel) => document.querySelector(sel);
export const el = (tag, attrs = {}, ...kids) => {
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
export const state = {
  files: [], logs: [], root: null,
  path: null,          // the open .coral file
  model: null,         // its mission model
  text: null,          // the current text (source of truth)
  etag: null,          // the version of the file read (If-Match on save)
  layoutEtag: null,    // the same for its layout file
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
  pendingPos: null, // where the next new node goes (a click on the canvas)
};

export const cy = createCy($('#cy'));
export function canConnect(s, t) {
  if (!editable()) return false;
  if (s.same(t)) return false;
  const a = s.data('kind'), b = t.data('kind');
  if (!((a === 'place' && b === 'transition') || (a === 'transition' && b === 'place'))) return false;
  // One arc each way between a place and a transition.
  return cy.edges(`.arc[source = "${s.id()}"][target = "${t.id()}"]`).empty();
}

// Snapping finds the target while dragging; ehcomplete (editor.js) keeps the arc
// only when the pointer was released on that node, never on a neighbour
// that happens to be a valid target.
export const eh = cy.edgehandles({
  canConnect: (s, t) => canConnect(s, t),
  edgeParams: () => ({ data: { kind: 'new' }, classes: 'arc' }),
  hoverDelay: 50, snap: true, snapThreshold: 30, snapFrequency: 15, noEdgeEventsInDraw: true, disableBrowserGestures: true,
});
export const chart = new DepthChart($('#chart'));

// ---------------------------------------------------------------- helpers
export function msg(text, isError = false) {
  const m = $('#edit-msg');
  m.textContent = text || '';
  m.classList.toggle('error', !!isError);
  if (isError) state.lastError = text;
}

export function setDirty(d) {
  state.dirty = d;
  $('#dirty-mark').hidden = !d;
  $('#btn-save').disabled = !state.path || !d;
  document.title = (d ? '● ' : '') + 'Strata studio' + (state.path ? ` — ${state.path}` : '');
}

export function currentNet() {
  const nets = displayNets();
  return nets.find((n) => n.name === state.netName) || null;
}

// The nets shown: the open file's, or the run's when no file is open.
export function displayNets() {
  if (state.model && state.model.nets && state.model.nets.length) return state.model.nets;
  if (state.rs.nets) return state.rs.nets;
  return [];
}

export function editable() {
  const n = currentNet();
  return !!(n && n.editable && state.model && state.path);
}

export function uniqueName(prefix) {
  const net = currentNet();
  const used = new Set([...(net?.places || []).map((p) => p.name), ...(net?.transitions || []).map((t) => t.name), ...(net?.exits || [])]);
  for (let i = 1; ; i++) if (!used.has(prefix + i)) return prefix + i;
}

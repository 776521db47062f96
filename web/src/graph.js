// Drawing one net with cytoscape: places as circles with their tokens, exits
// as double circles, transitions as bars with their actions below, arcs
// labelled with their weight when it is not 1, the places a TACTIC or PHASE
// marks later as dashed arrows.
import cytoscape from 'cytoscape';
import edgehandles from 'cytoscape-edgehandles';
import { placeId, transId } from './store.js';

cytoscape.use(edgehandles);
export { placeId, transId };

const tokenSvgCache = new Map();
// The tokens of a place, drawn inside its circle: dots up to 4, else a number.
function tokenSvg(n) {
  if (tokenSvgCache.has(n)) return tokenSvgCache.get(n);
  let body = '';
  const dot = (x, y) => `<circle cx="${x}" cy="${y}" r="5" fill="#111"/>`;
  if (n <= 0) body = '';
  else if (n === 1) body = dot(20, 20);
  else if (n === 2) body = dot(13, 20) + dot(27, 20);
  else if (n === 3) body = dot(20, 12) + dot(13, 26) + dot(27, 26);
  else if (n === 4) body = dot(13, 13) + dot(27, 13) + dot(13, 27) + dot(27, 27);
  else body = `<text x="20" y="26" font-size="17" font-family="sans-serif" font-weight="bold" text-anchor="middle" fill="#111">${n}</text>`;
  const svg = `<svg xmlns="http://www.w3.org/2000/svg" width="40" height="40" viewBox="0 0 40 40">${body}</svg>`;
  const uri = 'data:image/svg+xml;utf8,' + encodeURIComponent(svg);
  tokenSvgCache.set(n, uri);
  return uri;
}

export const style = [
  // Cheap styles for nets of thousands of elements (issue 17): no function
  // mappers, labels skipped when zoomed out below 5 px, one-line place
  // labels not wrapped, a token image only on marked places, straight
  // edges except where two edges join the same nodes.
  { selector: 'node', style: { 'font-size': 11, 'min-zoomed-font-size': 5 } },
  { selector: 'node.place', style: {
    shape: 'ellipse', width: 40, height: 40, 'background-color': '#fff', 'border-width': 2, 'border-color': '#333',
    label: 'data(name)', 'text-valign': 'bottom', 'text-margin-y': 3,
  } },
  { selector: 'node.place.marked', style: { 'background-image': 'data(img)', 'background-fit': 'contain', 'background-clip': 'none' } },
  { selector: 'node.place.exit', style: { 'border-style': 'double', 'border-width': 6, 'border-color': '#1d5fa8', color: '#1d5fa8' } },
  // Nets flow left to right (layout.js): transitions are upright bars, labels below.
  { selector: 'node.transition', style: {
    shape: 'rectangle', width: 12, height: 46, 'background-color': '#333', 'border-width': 0,
    label: 'data(label)', 'text-wrap': 'wrap', 'text-max-width': 220, 'text-valign': 'bottom', 'text-halign': 'center', 'text-margin-y': 3, 'text-justification': 'center',
    'text-background-color': '#fff', 'text-background-opacity': 0.8, 'text-background-padding': 1,
  } },
  // Enabled: a colour, not a size (a size changed moves the ends of every
  // edge of the node: most of a live view's redraw).
  { selector: 'node.transition.enabled', style: { 'background-color': '#2e9d3a' } },
  { selector: 'node.transition.inflight', style: { 'background-color': '#e8a317', 'border-width': 3, 'border-color': '#b57b00' } },
  { selector: 'node.transition.fired', style: { 'underlay-color': '#2e9d3a', 'underlay-opacity': 0.35, 'underlay-padding': 6 } },
  { selector: 'node.transition.cex', style: { 'background-color': '#c2185b', 'underlay-color': '#c2185b', 'underlay-opacity': 0.3, 'underlay-padding': 8 } },
  { selector: 'node.place.marked', style: { 'background-color': '#fff6d5' } },
  { selector: 'node.diag', style: { 'border-width': 3, 'border-color': '#d00', 'border-style': 'solid', 'underlay-color': '#d00', 'underlay-opacity': 0.25, 'underlay-padding': 5 } },
  { selector: 'node.diag.warning', style: { 'border-color': '#e08a00', 'underlay-color': '#e08a00' } },
  { selector: 'node.transition.diag', style: { 'background-color': '#d00' } },
  { selector: 'node:selected', style: { 'overlay-color': '#1d5fa8', 'overlay-opacity': 0.25, 'overlay-padding': 6 } },
  { selector: 'edge', style: {
    width: 1.6, 'line-color': '#555', 'target-arrow-color': '#555', 'target-arrow-shape': 'triangle',
    'curve-style': 'straight', 'arrow-scale': 1.1,
  } },
  { selector: 'edge.pair', style: { 'curve-style': 'bezier' } },
  { selector: 'edge.weighted', style: {
    label: 'data(label)', 'font-size': 12, 'font-weight': 'bold',
    'text-background-color': '#fff', 'text-background-opacity': 1, 'text-background-padding': 2, color: '#a00',
  } },
  { selector: 'edge.outcome', style: { 'line-style': 'dashed', 'line-color': '#8a8a8a', 'target-arrow-color': '#8a8a8a', width: 1.2 } },
  { selector: 'edge:selected', style: { 'line-color': '#1d5fa8', 'target-arrow-color': '#1d5fa8', width: 3 } },
  { selector: 'edge.noev', style: { events: 'no' } },
  { selector: '.eh-handle', style: { 'background-color': '#1d5fa8', width: 12, height: 12, shape: 'ellipse', 'overlay-opacity': 0, 'border-width': 8, 'border-opacity': 0 } },
  { selector: '.eh-hover', style: { 'background-color': '#1d5fa8' } },
  { selector: '.eh-source', style: { 'border-width': 3, 'border-color': '#1d5fa8' } },
  { selector: '.eh-target', style: { 'border-width': 3, 'border-color': '#1d5fa8' } },
  { selector: '.eh-preview, .eh-ghost-edge', style: { 'background-color': '#1d5fa8', 'line-color': '#1d5fa8', 'target-arrow-color': '#1d5fa8', 'source-arrow-color': '#1d5fa8' } },
  { selector: '.eh-ghost-edge.eh-preview-active', style: { opacity: 0 } },
];

export function createCy(container) {
  return cytoscape({
    container, style, elements: [], minZoom: 0.05, maxZoom: 4,
    boxSelectionEnabled: false, selectionType: 'single',
  });
}

// The transition's label: its name, its priority when not 0, then one line per action.
export function transitionLabel(t) {
  const head = t.priority ? `${t.name} [${t.priority}]` : t.name;
  return [head, ...(t.actions || []).map((a) => a.label || `${a.kind === 'PHASE' ? 'PHASE' : a.type} ${a.target}`)].join('\n');
}

// A cache of element specs for netElements, kept by the canvas across
// renders of one net: a place or transition whose fields are the ones last
// seen gets the very spec objects of last time (an edit's patch keeps each
// transition's inputs, outputs and actions arrays, also when its line
// moved), so the canvas's diff of a large net compares references.
// Specs are shared: never change them (cytoscape gets copies).
export function createElementCache() { return { net: null, places: new Map(), transitions: new Map() }; }

function placeSpec(p, n, isExit) {
  return { group: 'nodes', data: { id: placeId(p.name), kind: 'place', name: p.name, tokens: n, img: tokenSvg(n), initial: p.initial || 0, exit: isExit },
    classes: 'place' + (isExit ? ' exit' : '') + (n > 0 ? ' marked' : '') };
}

// The node of t and its arcs (outcome arcs to every outcome; those to no
// place are dropped by netElements with the other dangling edges). Arcs that
// join t to the same place (either way) are curved apart: 'pair' (every edge
// joins a place and a transition, so only a transition's own edges can share
// their two nodes; both are dropped, or neither, when the place is missing).
function transitionSpecs(t) {
  const out = [{ group: 'nodes', data: { id: transId(t.name), kind: 'transition', name: t.name, label: transitionLabel(t), priority: t.priority || 0 },
    classes: 'transition' }];
  for (const a of t.inputs || []) {
    out.push({ group: 'edges', data: { id: `a:${placeId(a.place)}>${transId(t.name)}`, kind: 'arc', source: placeId(a.place), target: transId(t.name),
      from: a.place, to: t.name, weight: a.weight ?? 1, label: (a.weight ?? 1) !== 1 ? String(a.weight) : '' }, classes: (a.weight ?? 1) !== 1 ? 'arc wait weighted' : 'arc wait' });
  }
  for (const a of t.outputs || []) {
    out.push({ group: 'edges', data: { id: `a:${transId(t.name)}>${placeId(a.place)}`, kind: 'arc', source: transId(t.name), target: placeId(a.place),
      from: t.name, to: a.place, weight: a.weight ?? 1, label: (a.weight ?? 1) !== 1 ? String(a.weight) : '' }, classes: (a.weight ?? 1) !== 1 ? 'arc signal weighted' : 'arc signal' });
  }
  const seen = new Set();
  (t.actions || []).forEach((act, i) => {
    for (const o of act.outcomes || []) {
      const key = `${i}:${o}`;
      if (seen.has(key)) continue;
      seen.add(key);
      out.push({ group: 'edges', data: { id: `o:${transId(t.name)}>${placeId(o)}:${i}`, kind: 'outcome', source: transId(t.name), target: placeId(o),
        from: t.name, to: o, label: '' }, classes: 'outcome' });
    }
  });
  if (out.length > 2) {
    const count = new Map();
    const other = (e) => (e.data.source === out[0].data.id ? e.data.target : e.data.source);
    for (let i = 1; i < out.length; i++) { const k = other(out[i]); count.set(k, (count.get(k) || 0) + 1); }
    for (let i = 1; i < out.length; i++) if (count.get(other(out[i])) > 1) out[i].classes += ' pair';
  }
  return out;
}

// Cytoscape elements of net (a mission-model net). tokens: place -> n, or
// null for the initial marking. cache: createElementCache(), or none.
export function netElements(net, tokens, cache = null) {
  const els = [];
  const places = new Map();
  for (const p of net.places || []) places.set(p.name, p);
  for (const x of net.exits || []) if (!places.has(x)) places.set(x, { name: x, initial: 0, exit: true, line: null });
  if (cache && cache.net !== net.name) { cache.net = net.name; cache.places = new Map(); cache.transitions = new Map(); }
  const nextPlaces = cache ? new Map() : null, nextTransitions = cache ? new Map() : null;
  const exits = new Set(net.exits || []);
  for (const p of places.values()) {
    const isExit = !!(p.exit || exits.has(p.name));
    const n = tokens ? (tokens[p.name] || 0) : (p.initial || 0);
    const initial = p.initial || 0;
    const c = cache && cache.places.get(p.name);
    const hit = c && c.n === n && c.isExit === isExit && c.initial === initial;
    const e = hit ? c.el : placeSpec(p, n, isExit);
    if (cache) nextPlaces.set(p.name, hit ? c : { n, isExit, initial, el: e });
    els.push(e);
  }
  for (const t of net.transitions || []) {
    const c = cache && cache.transitions.get(t.name);
    const hit = c && c.priority === t.priority && c.inputs === t.inputs && c.outputs === t.outputs && c.actions === t.actions;
    const specs = hit ? c.els : transitionSpecs(t);
    if (cache) nextTransitions.set(t.name, hit ? c : { priority: t.priority, inputs: t.inputs, outputs: t.outputs, actions: t.actions, els: specs });
    for (const e of specs) els.push(e);
  }
  if (cache) { cache.places = nextPlaces; cache.transitions = nextTransitions; }
  // Drop edges to nodes that do not exist (a model of a broken text; an
  // outcome that is no place of the net).
  const ids = new Set();
  for (const e of els) if (e.group === 'nodes') ids.add(e.data.id);
  return els.filter((e) => e.group === 'nodes' || (ids.has(e.data.source) && ids.has(e.data.target)));
}

export { tokenSvg };
// Kept here for the views that import it from graph.js.
export { diagnosticsByElement } from './diag.js';

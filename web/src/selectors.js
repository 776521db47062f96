// The store's selectors (store.js): what the views and the reducer read
// from a state, as pure functions of it: the nets shown, the net drawn,
// whether it may be edited or has unsaved changes, the marking drawn (a
// counterexample's, the run's), replay steps, and layout positions. Nothing
// here changes a state or touches the DOM.

export const placeId = (name) => `p:${name}`;
export const transId = (name) => `t:${name}`;

// The nets shown: the open file's, or the run's when no file is open.
const kNoNets = Object.freeze([]);
export function displayNets(s) {
  if (s.model && s.model.nets && s.model.nets.length) return s.model.nets;
  if (s.rs.nets) return s.rs.nets;
  return kNoNets;
}

export function currentNet(s) {
  return displayNets(s).find((n) => n.name === s.netName) || null;
}

export function editable(s) {
  const n = currentNet(s);
  return !!(n && n.editable && s.model && s.path && !s.readOnly);
}

export function dirty(s) {
  return s.path != null && (s.text !== s.savedText || s.layoutDirty);
}

export function uniqueName(s, prefix) {
  const net = currentNet(s);
  const used = new Set([...(net?.places || []).map((p) => p.name), ...(net?.transitions || []).map((t) => t.name), ...(net?.exits || [])]);
  for (let i = 1; i <= used.size + 1; i++) if (!used.has(prefix + i)) return prefix + i;
  return prefix + (used.size + 2);
}

// Where a counterexample stands after its first c.i steps: {net, instance}.
// A verifier's counterexample stays on its net (instance null); a
// requirement's worst path (its steps carry `instance` and `net`) moves into
// the phase each step runs in, and a step of time passing stays where the
// step before it was.
export function cexFocus(c) {
  for (let k = Math.min(c.i, c.steps.length) - 1; k >= 0; k--) {
    const st = c.steps[k];
    if (st.instance && st.net) return { net: st.net, instance: st.instance };
  }
  const first = c.steps.find((st) => st.instance && st.net);
  return first && first.net === c.net ? { net: c.net, instance: first.instance } : { net: c.net, instance: null };
}

// The marking drawn on net: a counterexample's, the run's, or null (the initial marking).
export function tokensFor(s, netName) {
  if (s.view === 'cex' && s.cex) {
    const f = cexFocus(s.cex);
    if (f.net !== netName) return null;
    if (!f.instance) return cexMarking(s, netName, s.cex.steps, s.cex.i);
    // Only the steps of this instance, from its net's initial marking.
    const mine = s.cex.steps.slice(0, s.cex.i).filter((st) => st.instance === f.instance);
    return cexMarking(s, netName, mine, mine.length);
  }
  if ((s.view === 'live' || s.view === 'replay') && s.rs.markings[netName]) return s.rs.markings[netName];
  return null;
}

// The marking after the first i steps of a counterexample: from the initial
// one, a firing takes its wait arcs and puts its signal arcs, an answer marks.
export function cexMarking(s, netName, steps, i) {
  const net = displayNets(s).find((n) => n.name === netName);
  const m = {};
  if (!net) return m;
  for (const p of net.places || []) if (p.initial) m[p.name] = p.initial;
  const tr = new Map((net.transitions || []).map((t) => [t.name, t]));
  for (let k = 0; k < i; k++) {
    const st = steps[k];
    if (st.kind === 'pass') continue;  // time passing, the fault starting: no token moves
    if (st.kind === 'fire') {
      const t = tr.get(st.transition);
      if (t) {
        for (const a of t.inputs || []) m[a.place] = (m[a.place] || 0) - (a.weight ?? 1);
        for (const a of t.outputs || []) m[a.place] = (m[a.place] || 0) + (a.weight ?? 1);
      }
    } else {
      for (const p of st.marks || []) m[p] = (m[p] || 0) + 1;
    }
  }
  for (const k of Object.keys(m)) if (m[k] <= 0) delete m[k];
  return m;
}

// Replay steps: the event index just after the next (previous) firing.
export function nextFiring(events, k) { for (let i = k; i < events.length; i++) if (events[i][0] === 'fired') return i + 1; return events.length; }
export function prevFiring(events, k) { for (let i = k - 2; i >= 0; i--) if (events[i][0] === 'fired') return i + 1; return 0; }

// Layout file (net -> node name -> {x, y}) into positions by node id.
export function positionsFromLayout(model) {
  const out = {};
  const layout = model && model.layout;
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

// Positions by id back into the layout file's form, for the nets shown.
export function layoutByName(s) {
  const out = {};
  for (const net of displayNets(s)) {
    const pos = s.positions[net.name];
    if (!pos) continue;
    const m = {};
    for (const [id, xy] of Object.entries(pos)) m[id.slice(2)] = { x: Math.round(xy.x * 10) / 10, y: Math.round(xy.y * 10) / 10 };
    out[net.name] = m;
  }
  return out;
}

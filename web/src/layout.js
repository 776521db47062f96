// The layered layout of a net, left to right: every loop and traversal
// here is iterative (an explicit stack or queue), so a net of any size is
// laid out without recursion (dagre's recursive DFS overflowed the stack on
// a 1,000-transition chain, issue 17). Steps: break cycles (iterative DFS),
// rank by longest path (Kahn's order), order each rank by barycentres (a
// few sweeps), then x by rank with room for the widest label, y from the
// neighbours in the rank before, pushed apart to not overlap.
//
// Pure: takes a mission-model net, returns node id -> {x, y}. The node and
// label sizes match graph.js's style.
import { placeId, transId } from './store.js';

export const kRankGap = 34;   // between the label boxes of two ranks
export const kNodeGap = 16;   // between two nodes of one rank
const kCharW = 6.4;           // an 11 px label's mean character width
const kLineH = 14;

function labelBox(lines) {
  const w = Math.max(0, ...lines.map((l) => l.length)) * kCharW;
  return { w, h: lines.length * kLineH };
}

// Nodes and edges of net: [{id, w, h}], [[from, to]] by index.
export function netGraph(net) {
  const nodes = [];
  const index = new Map();
  const add = (id, w, h) => { if (!index.has(id)) { index.set(id, nodes.length); nodes.push({ id, w, h }); } };
  const placeNames = [...(net.places || []).map((p) => p.name), ...(net.exits || [])];
  for (const name of placeNames) {
    const lb = labelBox([name]);
    add(placeId(name), Math.max(40, lb.w), 40 + 3 + lb.h);
  }
  for (const t of net.transitions || []) {
    const lines = [t.priority ? `${t.name} [${t.priority}]` : t.name, ...(t.actions || []).map((a) => a.label || `${a.kind} ${a.target}`)];
    const lb = labelBox(lines);
    add(transId(t.name), Math.max(14, lb.w), 46 + 3 + lb.h);
  }
  const edges = [];
  const edge = (a, b) => { const i = index.get(a), j = index.get(b); if (i !== undefined && j !== undefined && i !== j) edges.push([i, j]); };
  for (const t of net.transitions || []) {
    for (const a of t.inputs || []) edge(placeId(a.place), transId(t.name));
    for (const a of t.outputs || []) edge(transId(t.name), placeId(a.place));
    for (const act of t.actions || []) for (const o of act.outcomes || []) edge(transId(t.name), placeId(o));
  }
  return { nodes, edges };
}

export function layeredLayout(net) {
  const { nodes, edges } = netGraph(net);
  const n = nodes.length;
  const out = {};
  if (!n) return out;
  const succ = Array.from({ length: n }, () => []);
  const indeg = new Array(n).fill(0);
  for (const [a, b] of edges) { succ[a].push(b); indeg[b]++; }

  // 1. Break cycles: an iterative DFS from the sources first (then any node
  // left, in declaration order); an edge to a node on the stack is reversed.
  const state = new Uint8Array(n);  // 0 new, 1 on the stack, 2 done
  const dag = Array.from({ length: n }, () => []);
  const starts = [...nodes.keys()].sort((a, b) => (indeg[a] === 0 ? 0 : 1) - (indeg[b] === 0 ? 0 : 1) || a - b);
  const order = [];  // DFS discovery order, the first ordering within ranks
  for (const s of starts) {
    if (state[s]) continue;
    const stack = [[s, 0]];
    state[s] = 1; order.push(s);
    while (stack.length) {
      const top = stack[stack.length - 1];
      const [v, i] = top;
      if (i >= succ[v].length) { state[v] = 2; stack.pop(); continue; }
      top[1]++;
      const w = succ[v][i];
      if (state[w] === 1) dag[w].push(v);          // a back edge, reversed
      else {
        dag[v].push(w);
        if (state[w] === 0) { state[w] = 1; order.push(w); stack.push([w, 0]); }
      }
    }
  }

  // 2. Ranks: longest path from the sources, in Kahn's topological order.
  const din = new Array(n).fill(0);
  for (let v = 0; v < n; v++) for (const w of dag[v]) din[w]++;
  const rank = new Array(n).fill(0);
  const queue = [];
  for (let v = 0; v < n; v++) if (din[v] === 0) queue.push(v);
  for (let q = 0; q < queue.length; q++) {
    const v = queue[q];
    for (const w of dag[v]) {
      if (rank[v] + 1 > rank[w]) rank[w] = rank[v] + 1;
      if (--din[w] === 0) queue.push(w);
    }
  }
  // A sink pulled next to its only predecessor keeps exits near their transition.
  const pred = Array.from({ length: n }, () => []);
  for (let v = 0; v < n; v++) for (const w of dag[v]) pred[w].push(v);

  // 3. Order within ranks: discovery order, then barycentre sweeps.
  const nranks = Math.max(...rank) + 1;
  const ranks = Array.from({ length: nranks }, () => []);
  for (const v of order) ranks[rank[v]].push(v);
  const pos = new Float64Array(n);
  const renumber = (r) => ranks[r].forEach((v, i) => { pos[v] = i; });
  for (let r = 0; r < nranks; r++) renumber(r);
  // (A rank of one node has nothing to order: a chain of 10,000 nodes made
  // 80,000 maps here.)
  const bary = new Float64Array(n);
  const sweep = (r, nb) => {
    if (ranks[r].length < 2) return;
    for (const v of ranks[r]) {
      const ns = nb[v];
      let sum = 0;
      for (const w of ns) sum += pos[w];
      bary[v] = ns.length ? sum / ns.length : pos[v];
    }
    ranks[r].sort((a, b) => bary[a] - bary[b]);
    renumber(r);
  };
  for (let it = 0; it < 4; it++) {
    for (let r = 1; r < nranks; r++) sweep(r, pred);
    for (let r = nranks - 2; r >= 0; r--) sweep(r, dag);
  }

  // 4. x: ranks side by side, each as wide as its widest node or label.
  const x = new Array(nranks);
  let cur = 0;
  for (let r = 0; r < nranks; r++) {
    const half = Math.max(...ranks[r].map((v) => nodes[v].w)) / 2;
    if (r > 0) cur += half;
    x[r] = cur;
    cur += half + kRankGap;
  }
  // y: a node wants the mean y of its predecessors; nodes of a rank keep
  // their order and do not overlap.
  const y = new Float64Array(n);
  for (let r = 0; r < nranks; r++) {
    const vs = ranks[r];
    const want = vs.map((v) => {
      const ps = pred[v].filter((p) => rank[p] < r);
      return ps.length ? ps.reduce((a, p) => a + y[p], 0) / ps.length : null;
    });
    let prevBottom = -Infinity;
    let free = 0;
    vs.forEach((v, i) => {
      const h = nodes[v].h;
      let c = want[i] ?? (Number.isFinite(prevBottom) ? prevBottom + kNodeGap + h / 2 : free);
      if (c - h / 2 < prevBottom + kNodeGap) c = prevBottom + kNodeGap + h / 2;
      y[v] = c;
      prevBottom = c + h / 2;
      free = prevBottom;
    });
  }
  // Node centres: the label hangs below the node, so the box's centre is
  // above it by half the label's height.
  for (let v = 0; v < n; v++) {
    const node = nodes[v];
    const shapeH = node.id.startsWith('t:') ? 46 : 40;
    out[node.id] = { x: Math.round(x[rank[v]] * 10) / 10, y: Math.round((y[v] - node.h / 2 + shapeH / 2) * 10) / 10 };
  }
  return out;
}

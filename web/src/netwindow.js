// A large net shown in parts (issue 17: a 5,000-transition net opens in
// seconds): cytoscape's cost is per element it holds (styling, label
// sizes, bounding boxes, drawing), so for a net of more than kLargeNet
// elements the canvas gives it only the elements near the view, and swaps
// them as the view moves. This file decides which; canvas.js does it.

// Elements (nodes and edges, netElements) above which a net is shown in
// parts: a 300-place phase net (600 elements) redrawn at each firing of a
// live run made tasks of 0.1-0.3 s under load.
export const kLargeNet = 500;
// The part shown reaches this fraction of the view's size beyond each edge of it.
export const kMargin = 0.5;

// The box around extent (cytoscape's, model coordinates) whose elements are shown.
export function windowBox(extent, margin = kMargin) {
  const mx = (extent.x2 - extent.x1) * margin, my = (extent.y2 - extent.y1) * margin;
  return { x1: extent.x1 - mx, y1: extent.y1 - my, x2: extent.x2 + mx, y2: extent.y2 + my };
}

// The ids of the elements to show: the nodes whose position (pos: id ->
// {x, y}) is in box, every edge with an end among them, and the other end
// of such an edge (so no edge is drawn to nowhere); a node not yet placed
// (no position) is not shown, nor its edges. els: netElements specs.
export function windowIds(els, pos, box) {
  const ids = new Set();
  const inside = (id) => { const p = pos[id]; return !!p && p.x >= box.x1 && p.x <= box.x2 && p.y >= box.y1 && p.y <= box.y2; };
  const edges = [];
  for (const e of els) {
    if (e.group === 'nodes') { if (inside(e.data.id)) ids.add(e.data.id); } else edges.push(e);
  }
  const ends = [];
  for (const e of edges) {
    const s = ids.has(e.data.source), t = ids.has(e.data.target);
    if ((!s && !t) || !pos[e.data.source] || !pos[e.data.target]) continue;
    ids.add(e.data.id);
    if (!s) ends.push(e.data.source);
    if (!t) ends.push(e.data.target);
  }
  for (const id of ends) ids.add(id);
  return ids;
}

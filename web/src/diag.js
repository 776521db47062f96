// Diagnostics placed on the elements of a net: pure (no cytoscape), so the
// panels can use it before the canvas is loaded.
import { placeId, transId } from './store.js';

// Diagnostics placed on elements: a diagnostic of file F at line L goes to the
// element of a net of F whose line is the last one at or before L (a place
// named in the message is preferred among several on that line).
function sameFile(a, b) {
  if (!a || !b) return false;
  const na = String(a).replace(/\\/g, '/').replace(/^\.\//, '');
  const nb = String(b).replace(/\\/g, '/').replace(/^\.\//, '');
  return na === nb || na.endsWith('/' + nb) || nb.endsWith('/' + na);
}

export function diagnosticsByElement(model, net) {
  const out = new Map(); // element id -> [diag]
  if (!model || !net) return out;
  const candidates = [];
  for (const p of net.places || []) if (p.line) candidates.push({ id: placeId(p.name), name: p.name, line: p.line });
  for (const t of net.transitions || []) if (t.line) candidates.push({ id: transId(t.name), name: t.name, line: t.line });
  candidates.sort((a, b) => a.line - b.line);
  if (!candidates.length) return out;
  // The net's own extent: from its first element to the next net of the same file.
  const first = candidates[0].line;
  const sameFileNets = (model.nets || []).filter((n) => n !== net && sameFile(n.file, net.file));
  let end = Infinity;
  for (const n of sameFileNets) {
    const lines = [...(n.places || []), ...(n.transitions || [])].map((e) => e.line || 0).filter((l) => l > 0);
    const nfirst = Math.min(...lines);
    if (nfirst > first && nfirst < end) end = nfirst - 1;
  }
  for (const d of model.diagnostics || []) {
    if (!sameFile(d.file, net.file) && !(d.file == null && sameFile(model.path, net.file))) continue;
    if (d.line < first - 1 || d.line > end) continue;
    let best = null;
    for (const c of candidates) if (c.line <= d.line) best = c.line;
    if (best == null) best = first;
    let hits = candidates.filter((c) => c.line === best);
    if (hits.length > 1) {
      const named = hits.filter((c) => (d.message || '').includes(`'${c.name}'`));
      if (named.length) hits = named;
    }
    for (const h of hits) {
      if (!out.has(h.id)) out.set(h.id, []);
      out.get(h.id).push(d);
    }
  }
  return out;
}

// The first open of a mission, made cheaper before it happens (issue 17:
// tank mission open). The first time the page draws a net and shows a text,
// most of the work is the browser compiling and tuning the code of
// cytoscape, CodeMirror and the page's own drawing for the first time, and
// filling its font and glyph caches; later opens take a fraction of it.
// While the page is idle after the views are made, and before any file is
// opened, this draws a small net like a mission's (a marked place, an exit,
// transitions with actions, weighted, outcome and paired arcs) with the
// page's own cytoscape, its canvases hidden (cytoscape keeps caches of its
// own), and a CORAL text with a diagnostic in an editor of its own outside
// the window; both are thrown away after a frame or two. Nothing of it
// reaches the store.
//
// Each step is its own idle task; when the user opens a file (stop() is
// true), the steps not started are dropped.
import { netElements } from './graph.js';
import { layeredLayout } from './layout.js';
import { warmTextPane, warmLint } from './textpane.js';

// A small net with every kind of element a mission's nets have.
const kNet = {
  name: 'warm', kind: 'mission', editable: true, exits: ['closed'],
  places: [
    { name: 'begin', initial: 1, line: 2 }, { name: 'ready', initial: 0, line: 3 },
    { name: 'many', initial: 5, line: 3 }, { name: 'aborted', initial: 0, line: 3 },
  ],
  transitions: [
    { name: 'phase1', priority: 0, line: 5, inputs: [{ place: 'begin', weight: 1 }], outputs: [],
      actions: [{ kind: 'PHASE', target: 'initialize', label: 'PHASE initialize', args: [], outcomes: ['ready', 'aborted'] }] },
    { name: 'count', priority: 2, line: 6, inputs: [{ place: 'ready', weight: 1 }], outputs: [{ place: 'many', weight: 2 }, { place: 'ready', weight: 1 }],
      actions: [{ kind: 'TACTIC', type: 'REPORT', target: 'report', label: 'TACTIC(REPORT, "a report")', args: [], outcomes: [] }] },
    { name: 'shutdown', priority: 0, line: 7, inputs: [{ place: 'many', weight: 5 }, { place: 'aborted', weight: 1 }], outputs: [],
      actions: [{ kind: 'TACTIC', type: 'OOD', target: 'shutdown_network', label: 'TACTIC(OOD, shutdown_network, closed)', args: [], outcomes: ['closed'] }] },
  ],
};

const kText = `// A text like a mission's, for the editor's first draw.
mission warm {
  place begin = 1;
  place ready, many = 5, aborted;
  exit closed;
  transition phase1 { wait { begin } action { PHASE(initialize, ready, aborted) } }
  transition count priority 2 { wait { ready } signal { many * 2, ready } action { TACTIC(REPORT, "a report") } }
  transition shutdown { wait { many * 5, aborted } action { TACTIC(OOD, shutdown_network, closed) } }
}
`;

const idle = (f) => (window.requestIdleCallback ? window.requestIdleCallback(f, { timeout: 2000 }) : setTimeout(f, 50));
const frame = () => new Promise((resolve) => { requestAnimationFrame(() => setTimeout(resolve, 0)); setTimeout(resolve, 200); });

// A box outside the window, of the size of a small net's view.
function offscreen(w, h) {
  const box = document.createElement('div');
  box.setAttribute('aria-hidden', 'true');
  box.style.cssText = `position:fixed;left:-${w + 100}px;top:0;width:${w}px;height:${h}px;overflow:hidden;pointer-events:none;`;
  document.body.append(box);
  return box;
}

// The steps, each a short task followed by a frame (cytoscape draws at
// its frames): the net is added to the page's own cytoscape (canvas.js's
// warm(), its canvases hidden) a few elements at a time, so that no frame
// is long (the first one compiles most of cytoscape's drawing); then the
// text, in an editor of its own.
function steps(canvas) {
  const pos = layeredLayout(kNet);
  const els = netElements(kNet, null).map((e) => ({ ...e, data: { ...e.data }, ...(e.group === 'nodes' ? { position: { x: pos[e.data.id].x + 60, y: pos[e.data.id].y + 60 } } : {}) }));
  const node = (id) => els.filter((e) => e.data.id === id);
  const groups = [
    node('p:begin'),                                              // a place, its token
    [...node('t:phase1'), ...node('p:ready'), ...node('p:aborted')], // a transition's wrapped label, more places
    els.filter((e) => e.group === 'nodes' && !e.data.id.match(/^(p:begin|t:phase1|p:ready|p:aborted)$/)),
    els.filter((e) => e.group === 'edges'),                       // arcs, weights, outcomes, pairs
  ];
  const out = groups.map((g) => () => { canvas.warm(g); return frame(); });
  out.push(() => { canvas.endWarm(); return Promise.resolve(); });
  let box = null, view = null;
  out.push(() => { box = offscreen(360, 300); view = warmTextPane(box, ''); return frame(); });
  out.push(() => { view.dispatch({ changes: { from: 0, insert: kText } }); return frame(); });
  out.push(() => { warmLint(view); return frame(); });
  out.push(() => { view.destroy(); box.remove(); view = null; return Promise.resolve(); });
  // Whatever was left when stopped.
  const cleanup = () => { canvas.endWarm(); if (view) { view.destroy(); box.remove(); } };
  return { out, cleanup };
}

// Runs the steps at idle times, each unless stop() is true by then.
// Resolves when done (or stopped); never throws.
export function warmUp(canvas, stop) {
  const { out, cleanup } = steps(canvas);
  return new Promise((resolve) => {
    const done = () => { try { cleanup(); } catch { /* a warm-up only */ } resolve(); };
    const next = () => {
      const step = out.shift();
      if (!step || stop()) { done(); return; }
      idle(() => {
        if (stop()) { done(); return; }
        let p;
        try { p = step(); } catch { done(); return; }
        p.then(next, done);
      });
    };
    next();
  });
}

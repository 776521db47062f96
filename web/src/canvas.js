// The net canvas (cytoscape): draws the current net of the store, its
// marking and run classes, in parts for a large net (netwindow.js); places
// the nodes that have no position; remembers each net's viewport. The
// user's gestures on it (drag a node, draw an arc, click, double-click)
// are gestures.js's. It keeps no page state of its own: positions and
// viewports go to the store.
import { netElements, createElementCache, createCy, diagnosticsByElement, transitionLabel, tokenSvg } from './graph.js';
import { layeredLayout } from './layout.js';
import { currentNet, tokensFor, cexFocus } from './store.js';
import { bindGestures, viewCentre } from './gestures.js';
import { kLargeNet, windowBox, windowIds } from './netwindow.js';

// Fit never zooms out below this: labels stay readable (11 px font ×
// 0.82 ≈ 9 px), and the user scrolls a net larger than the view.
export const kMinFitZoom = 0.82;
export const kZoomStep = 1.25;

export function createCanvas(container, store, fx) {
  const { dispatch, getState } = store;
  const cy = createCy(container);
  // A large net draws a texture of itself while panning and zooming.
  const setLarge = (large) => { const r = cy.renderer(); r.textureOnViewport = large; r.hideEdgesOnViewport = large; };
  let drawnNet = null;      // the net object drawn
  // A net of more than kLargeNet elements is shown in parts (netwindow.js):
  // part.pos has the position of each of its nodes, shown or not; cytoscape
  // holds only the elements near the view.
  let part = null;
  let drawnName = null;
  let dynamicQueued = false;

  const { eh, addNode, quietly } = bindGestures(cy, container, store, fx);
  const centre = () => viewCentre(cy);

  // The viewport, once still for 150 ms, is remembered for the net; a net
  // shown in parts shows the part in view.
  let vpTimer = null;
  let windowTimer = null;
  cy.on('viewport', () => {
    if (part && !windowTimer) windowTimer = setTimeout(() => { windowTimer = null; showWindow(); }, 60);
    clearTimeout(vpTimer);
    vpTimer = setTimeout(() => {
      const s = getState();
      if (s.netName && drawnName === s.netName) dispatch({ type: 'viewport/set', net: s.netName, zoom: cy.zoom(), pan: { ...cy.pan() } });
    }, 150);
  });
  new ResizeObserver(() => cy.resize()).observe(container);

  // Fit the net, but never below kMinFitZoom: a large net is shown from its
  // start (left), centred vertically when it fits. The box is taken from the
  // node positions (labels hang below, within the padding): cytoscape's own
  // fit measures every label and edge, seconds on a 10,000-node net.
  // Centres the view on the net's first action in flight, when it is out of view.
  function showInFlight(s, net, pos) {
    const a = Object.values(s.rs.inFlight || {}).find((f) => f.net === net.name && f.transition);
    if (!a) return;
    const id = `t:${a.transition}`;
    const node = cy.getElementById(id);
    const p = node.nonempty() ? node.position() : (pos && pos[id]) || (part && part.pos[id]);
    if (!p) return;
    const zoom = cy.zoom(), pan = cy.pan(), w = cy.width(), h = cy.height();
    const x = p.x * zoom + pan.x, y = p.y * zoom + pan.y;
    if (x >= 40 && x <= w - 40 && y >= 40 && y <= h - 40) return;
    cy.pan({ x: w / 2 - p.x * zoom, y: h / 2 - p.y * zoom });
  }

  function fitReadable() {
    const points = nodePoints(null);
    if (!points.length) return;
    let x1 = Infinity, y1 = Infinity, x2 = -Infinity, y2 = -Infinity;
    for (const p of points) {
      if (p.x < x1) x1 = p.x; if (p.x > x2) x2 = p.x;
      if (p.y < y1) y1 = p.y; if (p.y > y2) y2 = p.y;
    }
    x1 -= 40; x2 += 80; y1 -= 40; y2 += 70;   // half a node; a label's width right and height below
    const w = cy.width(), h = cy.height(), pad = 20;
    const fit = Math.min((w - 2 * pad) / (x2 - x1), (h - 2 * pad) / (y2 - y1), 2);
    const zoom = Math.max(kMinFitZoom, Math.min(cy.maxZoom(), fit));
    const panX = fit >= kMinFitZoom ? (w - (x2 - x1) * zoom) / 2 - x1 * zoom : pad - x1 * zoom;
    const panY = (y2 - y1) * zoom <= h - 2 * pad ? (h - (y2 - y1) * zoom) / 2 - y1 * zoom : pad - y1 * zoom;
    cy.viewport({ zoom, pan: { x: panX, y: panY } });
  }
  // The positions of the net's nodes but the one of id skip: all of them
  // for a net shown in parts, else cytoscape's (edgehandles' own aside).
  function nodePoints(skip) {
    const out = [];
    if (part) {
      for (const [id, e] of drawnEls) if (e.group === 'nodes' && id !== skip && part.pos[id]) out.push(part.pos[id]);
      return out;
    }
    cy.nodes().forEach((m) => { if (m.id() !== skip && !m.hasClass('eh-handle') && !m.hasClass('eh-ghost')) out.push(m.position()); });
    return out;
  }
  function zoomBy(k) {
    cy.zoom({ level: Math.max(cy.minZoom(), Math.min(cy.maxZoom(), cy.zoom() * k)), renderedPosition: { x: cy.width() / 2, y: cy.height() / 2 } });
  }

  // ------------------------------------------------------------ drawing
  // show: a net shown in parts shows the part in view again even when no
  // position changed (its elements did).
  function placeNodes(s, net, show = false) {
    if (part) { placeParts(s, net, show); return; }
    const pos = s.positions[net.name] || {};
    const nodes = cy.nodes();
    const missing = [];
    cy.batch(() => {
      nodes.forEach((n) => {
        const p = pos[n.id()];
        if (!p) { missing.push(n); return; }
        const q = n.position();
        if (q.x !== p.x || q.y !== p.y) n.position(p);
      });
    });
    if (!missing.length) return;
    const out = {};
    if (missing.length === nodes.length) {
      // A net never laid out: the layered layout, left to right.
      const laid = layeredLayout(net);
      cy.batch(() => nodes.forEach((n) => { const p = laid[n.id()]; if (p) { n.position(p); out[n.id()] = p; } }));
      dispatch({ type: 'positions/set', net: net.name, positions: out, replace: true });
      return;
    }
    // New nodes: where the user asked, else beside their neighbours, else the centre.
    let k = 0;
    for (const n of missing) {
      let p = s.pendingPos;
      if (!p) {
        const nb = n.neighborhood('node').filter((m) => pos[m.id()]);
        if (nb.length) {
          const c = nb.reduce((a, m) => ({ x: a.x + pos[m.id()].x, y: a.y + pos[m.id()].y }), { x: 0, y: 0 });
          p = { x: c.x / nb.length + 70, y: c.y / nb.length };
        } else p = centre();
      }
      const q = freeSpot({ x: p.x + k * 30, y: p.y + k * 30 }, n.id());
      k++;
      n.position(q);
      out[n.id()] = q;
    }
    dispatch({ type: 'positions/set', net: net.name, positions: out, placed: true });
  }

  // placeNodes for a net shown in parts: part.pos follows the store, nodes
  // without a position are placed as placeNodes does, and what is shown
  // follows.
  function placeParts(s, net, show) {
    const pos = s.positions[net.name] || {};
    const missing = [], moved = [];
    let nodes = 0;
    for (const [id, e] of drawnEls) {
      if (e.group !== 'nodes') continue;
      nodes++;
      const p = pos[id];
      if (!p) { missing.push(id); continue; }
      const q = part.pos[id];
      if (!q || q.x !== p.x || q.y !== p.y) { part.pos[id] = { x: p.x, y: p.y }; moved.push(id); }
    }
    if (moved.length) cy.batch(() => { for (const id of moved) { const n = cy.getElementById(id); if (n.nonempty()) n.position({ ...part.pos[id] }); } });
    if (missing.length && missing.length === nodes) {
      const laid = layeredLayout(net);
      part.pos = { ...laid };
      dispatch({ type: 'positions/set', net: net.name, positions: laid, replace: true });
      cy.batch(() => cy.nodes().forEach((n) => { const p = part.pos[n.id()]; if (p) n.position({ ...p }); }));
    } else if (missing.length) {
      const out = {};
      let k = 0;
      for (const id of missing) {
        let p = s.pendingPos;
        if (!p) {
          const nb = [];
          for (const e of drawnEls.values()) {
            if (e.group !== 'edges') continue;
            const other = e.data.source === id ? e.data.target : e.data.target === id ? e.data.source : null;
            if (other && part.pos[other]) nb.push(part.pos[other]);
          }
          if (nb.length) {
            const c = nb.reduce((a, m) => ({ x: a.x + m.x, y: a.y + m.y }), { x: 0, y: 0 });
            p = { x: c.x / nb.length + 70, y: c.y / nb.length };
          } else p = centre();
        }
        const q = freeSpot({ x: p.x + k * 30, y: p.y + k * 30 }, id);
        k++;
        part.pos[id] = q;
        out[id] = q;
      }
      dispatch({ type: 'positions/set', net: net.name, positions: out, placed: true });
    }
    // (The positions this dispatched come back here: nothing moved, and
    // the part in view is as it was.)
    if (show || moved.length || missing.length) showWindow();
  }

  // The elements near the view brought into cytoscape, the others out (a
  // net shown in parts); those brought in get the run's classes, the
  // diagnostics and the selection.
  function showWindow() {
    if (!part) return;
    const s = getState();
    const want = windowIds(drawnEls.values(), part.pos, windowBox(cy.extent()));
    const arc = s.mode === 'arc';
    const nodes = [], edges = [];
    cy.batch(() => {
      cy.elements().filter((x) => drawnEls.has(x.id()) && !want.has(x.id())).remove();
      for (const id of want) {
        if (cy.getElementById(id).nonempty()) continue;
        const e = drawnEls.get(id);
        if (e.group === 'nodes') nodes.push({ ...e, data: { ...e.data }, position: { ...part.pos[id] } });
        else edges.push({ ...e, data: { ...e.data }, classes: arc ? `${e.classes} noev` : e.classes });
      }
      if (nodes.length || edges.length) cy.add([...nodes, ...edges]);
    });
    if (!nodes.length && !edges.length) return;
    const net = currentNet(s);
    if (net) { updateDynamic(s); applyDiagnostics(s, net); }
    if (s.selected && want.has(s.selected)) quietly(() => cy.getElementById(s.selected).select());
  }

  // The first point from p (rings of 50 around it) where a new node is 55 px
  // or more from every other node in x or y (by their positions: measuring
  // the boxes of a 10,000-node net is slow).
  function freeSpot(p, selfId) {
    const xs = [], ys = [];
    for (const q of nodePoints(selfId)) { xs.push(q.x); ys.push(q.y); }
    const hits = (q) => { for (let i = 0; i < xs.length; i++) if (Math.abs(xs[i] - q.x) < 55 && Math.abs(ys[i] - q.y) < 55) return true; return false; };
    for (let ring = 0; ring < 12; ring++) {
      for (const [dx, dy] of [[0, 0], [1, 0], [0, 1], [-1, 0], [0, -1], [1, 1], [-1, 1], [1, -1], [-1, -1]]) {
        const q = { x: p.x + dx * ring * 50, y: p.y + dy * ring * 50 };
        if (!hits(q)) return q;
      }
    }
    return p;
  }

  function applyDiagnostics(s, net) {
    const map = diagnosticsByElement(s.model, net);
    cy.batch(() => {
      cy.nodes('.diag').removeClass('diag warning').removeData('diag');
      for (const [id, ds] of map) {
        const n = cy.getElementById(id);
        if (!n.nonempty()) continue;
        n.addClass('diag');
        if (ds.every((d) => d.severity !== 'error')) n.addClass('warning');
        n.data('diag', ds.map((d) => `${d.severity}: ${d.message}`).join('\n'));
      }
    });
  }

  // Token counts and run classes.
  function updateDynamic(s) {
    const net = currentNet(s);
    if (!net) return;
    const tokens = tokensFor(s, net.name);
    const running = s.view === 'live' || s.view === 'replay';
    const inFlightByT = {};
    if (running) {
      for (const a of Object.values(s.rs.inFlight)) {
        if (a.net !== net.name) continue;
        (inFlightByT[a.transition] || (inFlightByT[a.transition] = [])).push(a.primitive || a.kind);
      }
    }
    const enabled = new Set(running ? (s.rs.enabled[net.name] || []) : []);
    const last = running && s.rs.lastFired && s.rs.lastFired.net === net.name ? s.rs.lastFired.transition : null;
    const cexT = s.view === 'cex' && s.cex && cexFocus(s.cex).net === net.name && s.cex.i > 0 ? s.cex.steps[s.cex.i - 1].transition : null;
    const byName = new Map((net.transitions || []).map((t) => [t.name, t]));
    // Only what changed is touched: a class or data set restyles the element.
    const toggle = (n, cls, on) => { if (n.hasClass(cls) !== on) n.toggleClass(cls, on); };
    cy.batch(() => {
      cy.nodes().forEach((n) => {
        const name = n.data('name');
        if (n.data('kind') === 'place') {
          const k = tokens ? (tokens[name] || 0) : (n.data('initial') || 0);
          if (n.data('tokens') !== k) n.data({ tokens: k, img: tokenSvg(k) });
          toggle(n, 'marked', k > 0);
          return;
        }
        if (n.data('kind') !== 'transition') return;
        const fl = inFlightByT[name];
        toggle(n, 'enabled', enabled.has(name));
        toggle(n, 'inflight', !!fl);
        toggle(n, 'fired', last === name);
        toggle(n, 'cex', cexT === name);
        const t = byName.get(name);
        const base = t ? transitionLabel(t) : name;
        const label = fl ? `${base}\n▶ ${fl.join(', ')}` : base;
        if (n.data('label') !== label) n.data('label', label);
      });
    });
  }

  // The drawn net brought to net's elements: the new elements are compared
  // with the ones last drawn (plain objects, no cytoscape calls), and only
  // what differs is removed, added or changed, so an edit of a large net
  // touches a few elements, and the selection and positions stay.
  const kBaseClasses = ['place', 'exit', 'transition', 'arc', 'wait', 'signal', 'outcome', 'weighted', 'pair'];
  let drawnEls = new Map();   // id -> the element spec drawn (netElements)
  // The specs of the net drawn, kept across its renders (graph.js): an
  // element an edit left alone is the same spec, compared by reference.
  const specCache = createElementCache();
  // Cytoscape keeps the data object it is given (and changes it): it gets copies.
  const copy = (e) => ({ ...e, data: { ...e.data } });
  const byId = (els) => new Map(els.map((e) => [e.data.id, e]));
  function syncElements(s, net) {
    const els = netElements(net, tokensFor(s, net.name), specCache);
    const want = byId(els);
    const gone = [];
    for (const id of drawnEls.keys()) if (!want.has(id)) gone.push(id);
    const add = [];
    cy.batch(() => {
      for (const id of gone) { const e = cy.getElementById(id); if (e.nonempty()) e.remove(); }
      for (const w of els) {
        const d = drawnEls.get(w.data.id);
        if (d === w || (d && d.classes === w.classes && sameData(d.data, w.data))) continue;
        const e = cy.getElementById(w.data.id);
        if (e.empty()) { if (!part) add.push(copy(w)); continue; }   // in parts: showWindow adds it
        for (const [k, v] of Object.entries(w.data)) if (k !== 'id' && k !== 'source' && k !== 'target' && e.data(k) !== v) e.data(k, v);
        const cls = new Set(w.classes.split(' '));
        for (const c of kBaseClasses) if (e.hasClass(c) !== cls.has(c)) e.toggleClass(c, cls.has(c));
      }
      if (add.length) cy.add(add);
    });
    drawnEls = want;
  }
  function sameData(a, b) {
    for (const k in b) if (a[k] !== b[k]) return false;
    for (const k in a) if (!(k in b)) return false;
    return true;
  }

  function render(s, prev) {
    const net = currentNet(s);
    // Any file open ends the warm-up at once (warm.js stops at its next
    // step): a PROLOG mission has no net, and kept its hidden elements till then.
    if (warming && (net || s.netName || s.path != null)) endWarm();
    const switched = s.netName !== drawnName || !drawnNet !== !net;
    const changed = net !== drawnNet;
    const rebuilt = switched || changed;
    if (switched) {
      // Leaving a net: its viewport is remembered.
      if (drawnName && drawnName !== s.netName && !cy.elements().empty()) dispatch({ type: 'viewport/set', net: drawnName, zoom: cy.zoom(), pan: { ...cy.pan() } });
      if (eh.hide) eh.hide();
      cy.elements().remove();
      drawnEls = new Map();
      part = null;
      drawnNet = net; drawnName = s.netName;
      if (net) {
        const els = netElements(net, tokensFor(s, net.name), specCache);
        const large = els.length > kLargeNet;
        setLarge(large);
        // Nodes are added at their positions (each position set afterwards
        // is an event): the stored ones, or the layered layout's.
        let pos = s.positions[net.name] || {};
        let laid = null;
        if (!els.some((e) => e.group === 'nodes' && pos[e.data.id])) pos = laid = layeredLayout(net);
        drawnEls = byId(els);
        if (large) {
          // In parts: the view first, then the elements near it.
          part = { pos: {} };
          for (const e of els) if (e.group === 'nodes' && pos[e.data.id]) part.pos[e.data.id] = { ...pos[e.data.id] };
        } else {
          cy.add(els.map((e) => {
            const c = copy(e);
            if (e.group === 'nodes' && pos[e.data.id]) c.position = { ...pos[e.data.id] };
            return c;
          }));
        }
        const vp = s.viewports[net.name];
        // (A dispatch from a view is applied after this render.)
        if (laid) dispatch({ type: 'positions/set', net: net.name, positions: laid, replace: true });
        else if (!large) placeNodes(s, net);
        if (vp) cy.viewport({ zoom: vp.zoom, pan: vp.pan }); else fitReadable();
        // Followed into a net by a run: its action in flight in view (a long
        // phase net opened at its start had it off screen).
        if (!vp && s.follow && (s.view === 'live' || s.view === 'replay')) showInFlight(s, net, pos);
        if (large && !laid) placeNodes(s, net, true);   // places what has no position, then shows the part in view
        else if (large) showWindow();
        applyDiagnostics(s, net);
      }
    } else if (changed) {
      drawnNet = net;
      syncElements(s, net);
      placeNodes(s, net, true);
      applyDiagnostics(s, net);
    } else if (net && prev && s.positions[net.name] !== prev.positions[net.name]) {
      placeNodes(s, net);
    }
    if (net && prev && !rebuilt && s.model !== prev.model) applyDiagnostics(s, net);
    // Following a run: a new action in flight in this net comes into view.
    if (net && prev && !rebuilt && s.follow && (s.view === 'live' || s.view === 'replay') && s.rs.inFlight !== prev.rs.inFlight) {
      showInFlight(s, net, null);
      if (part) showWindow();
    }
    if (!prev || s.mode !== prev.mode || rebuilt) {
      if (s.mode === 'arc') eh.enableDrawMode(); else eh.disableDrawMode();
      // Every edge when the mode or the net changes; after an edit, only
      // edges added in arc mode (a class set on 10,000 edges restyles them).
      // (Elements added after a switch have no noev: a class set on each edge of a large net is a restyle of each.)
      if (!prev || s.mode !== prev.mode || (switched && s.mode === 'arc')) cy.edges().toggleClass('noev', s.mode === 'arc');
      else if (s.mode === 'arc') cy.edges(':not(.noev)').addClass('noev');
      container.dataset.mode = s.mode;
    }
    // Selection follows the store (looked at only when it or the net
    // changed: a selector over every element, at each event of a run, was
    // most of the page's work in the live view).
    if (!prev || s.selected !== prev.selected || rebuilt) {
      const sel = cy.$(':selected');
      const want = s.selected;
      quietly(() => {
        if (want && (sel.length !== 1 || sel[0].id() !== want)) {
          const n = cy.getElementById(want);
          cy.elements().unselect();
          if (n.nonempty()) n.select();
        } else if (!want && sel.nonempty()) sel.unselect();
      });
    }
    if (s.focus && (!prev || s.focus !== prev.focus) && s.focus.id) {
      const n = cy.getElementById(s.focus.id);
      const p = part && part.pos[s.focus.id];
      if (n.nonempty()) cy.animate({ center: { eles: n } }, { duration: 200 });
      else if (p) cy.animate({ pan: { x: cy.width() / 2 - p.x * cy.zoom(), y: cy.height() / 2 - p.y * cy.zoom() } }, { duration: 200 });
    }
    // Markings at most once per animation frame (a run sends many events).
    if (rebuilt) updateDynamic(s);
    else if (!prev || s.rs !== prev.rs || s.view !== prev.view || s.cex !== prev.cex) {
      if (!dynamicQueued) {
        dynamicQueued = true;
        requestAnimationFrame(() => { dynamicQueued = false; updateDynamic(getState()); });
      }
    }
    if (rebuilt && net) tellPainted(s.path, s.netName);
  }

  // A net given to cytoscape: once cytoscape has rendered it, in a task
  // after that frame, `netpainted` on the container ({path, net, rendered,
  // at}: performance.now() when cytoscape had drawn it, in the frame, and
  // in the task after), for opentiming.js.
  // (A task of the highest priority where there is one: a plain one waited
  // behind the page's other tasks, 10-30 ms in traces.)
  const afterTask = (f) => {
    if (globalThis.scheduler && scheduler.postTask) { scheduler.postTask(f, { priority: 'user-blocking' }); return; }
    const ch = new MessageChannel(); ch.port1.onmessage = f; ch.port2.postMessage(null);
  };
  function tellPainted(path, net) {
    cy.one('render', () => {
      const rendered = performance.now();
      afterTask(() => container.dispatchEvent(new CustomEvent('netpainted', { detail: { path, net, rendered, at: performance.now() } })));
    });
  }

  // ------------------------------------------------------------ warm-up
  // warm.js's small net drawn by this cytoscape, its canvases hidden,
  // before any net is shown: the first net the user opens then finds
  // cytoscape's own caches (styles, label sizes, images, textures) filled
  // (its first frame took 4 times a later one's). warm(els) adds els (a
  // few at a time: each frame then stays short; they can be neither
  // selected nor dragged); endWarm() removes them and shows the canvases,
  // called by warm.js when done and by the first render of a net.
  let warming = null;
  const canvases = (visible) => { for (const c of container.querySelectorAll('canvas')) c.style.visibility = visible ? '' : 'hidden'; };
  function endWarm() {
    if (!warming) return;
    const w = warming;
    warming = null;
    cy.batch(() => { w.forEach((e) => { if (e.inside()) e.remove(); }); });
    canvases(true);
  }
  // Whether els were added (not once a net is shown).
  function warm(els) {
    const s = getState();
    if (drawnNet || s.path != null || s.netName || (!warming && cy.elements().nonempty())) return false;
    if (!warming) { canvases(false); warming = cy.collection(); }
    const added = cy.add(els);
    added.unselectify();
    added.ungrabify();
    warming = warming.union(added);
    return true;
  }

  store.subscribe(render);
  render(getState(), null);

  return {
    cy, addNode, centre, fitReadable, zoomBy, warm, endWarm,
    // The net drawn: its elements, and whether cytoscape holds only a part of them.
    get drawn() { return { elements: drawnEls.size, nodes: [...drawnEls.values()].filter((e) => e.group === 'nodes').length, inParts: !!part }; },
    relayout() {
      const s = getState();
      if (!currentNet(s)) return;
      dispatch({ type: 'positions/clear', net: s.netName });
    },
  };
}

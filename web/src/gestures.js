// The user's gestures on the net canvas turned into actions: an arc drawn
// by dragging (edgehandles), a node added by a click in the place or
// transition mode, a PHASE transition opened by a double-click, a node
// dragged, the selection, a node's diagnostics as a tooltip. The drawing of
// the store's net is canvas.js's; this file only dispatches and applies
// ops, and draws nothing but the tooltip.
import { currentNet, editable, uniqueName } from './store.js';

// The centre of cy's view, in model coordinates.
export function viewCentre(cy) {
  const e = cy.extent();
  return { x: (e.x1 + e.x2) / 2, y: (e.y1 + e.y2) / 2 };
}

// Binds the gestures of cy (drawn in container). Returns eh (edgehandles,
// whose draw mode follows the store's mode), addNode(kind, at, name), and
// quietly(f): runs f, a change of cytoscape's selection that follows the
// store, without sending it back to the store.
export function bindGestures(cy, container, store, fx) {
  const { dispatch, getState } = store;

  const canConnect = (s, t) => {
    if (!editable(getState())) return false;
    if (s.same(t)) return false;
    const a = s.data('kind'), b = t.data('kind');
    if (!((a === 'place' && b === 'transition') || (a === 'transition' && b === 'place'))) return false;
    return cy.edges(`.arc[source = "${s.id()}"][target = "${t.id()}"]`).empty();  // one arc each way
  };
  const eh = cy.edgehandles({
    canConnect,
    edgeParams: () => ({ data: { kind: 'new' }, classes: 'arc' }),
    hoverDelay: 50, snap: true, snapThreshold: 30, snapFrequency: 15, noEdgeEventsInDraw: true, disableBrowserGestures: true,
  });

  // Where the pointer was released, taken from the pointer events in the
  // capture phase, before edgehandles ends the drag on mouseup: the arc is
  // kept only when released on the node it joins, never on a neighbour the
  // snapping found.
  let released = null;
  window.addEventListener('pointerdown', () => { released = null; }, true);
  window.addEventListener('pointerup', (e) => { released = { x: e.clientX, y: e.clientY }; }, true);
  const releasePoint = () => {
    if (!released) return null;
    const rect = container.getBoundingClientRect();
    const pan = cy.pan(), zoom = cy.zoom();
    return { x: (released.x - rect.left - pan.x) / zoom, y: (released.y - rect.top - pan.y) / zoom };
  };

  cy.on('ehcomplete', (ev, source, target, added) => {
    added.remove();
    const p = releasePoint();
    const box = target.boundingBox({ includeLabels: false });
    const slack = 6;
    if (!p || p.x < box.x1 - slack || p.x > box.x2 + slack || p.y < box.y1 - slack || p.y > box.y2 + slack) {
      fx.say('release the arc on the place or transition it should join', true);
      return;
    }
    fx.applyOp({ op: 'add_arc', net: getState().netName, from: source.data('name'), to: target.data('name'), weight: 1 });
  });

  cy.on('tap', (ev) => {
    if (ev.target !== cy) return;
    const s = getState();
    if (s.mode === 'place' || s.mode === 'transition') {
      // The name field counts in these modes too (it was ignored): used once, then cleared.
      const input = document.getElementById('new-name');
      const name = input ? input.value.trim() : '';
      if (input) input.value = '';
      addNode(s.mode, { ...ev.position }, name);
    }
  });
  // Double-click a PHASE transition: open the phase's net.
  cy.on('dbltap', 'node.transition', (ev) => {
    const s = getState();
    const t = (currentNet(s)?.transitions || []).find((x) => x.name === ev.target.data('name'));
    const phase = t && (t.actions || []).find((a) => a.kind === 'PHASE');
    if (phase) dispatch({ type: 'net/show', name: phase.target, user: true });
  });
  cy.on('dragfree', 'node', (ev) => {
    const n = ev.target;
    const s = getState();
    if (!s.netName || n.hasClass('eh-handle')) return;
    dispatch({ type: 'positions/set', net: s.netName, positions: { [n.id()]: { ...n.position() } }, user: !!(s.path && editable(s)) });
  });
  // The user's selection goes to the store; the canvas's own (following
  // the store, quietly) is not sent back.
  let syncing = false;
  cy.on('select', (ev) => { if (!syncing) dispatch({ type: 'select', id: ev.target.id() }); });
  cy.on('unselect', () => { if (!syncing && cy.$(':selected').empty()) dispatch({ type: 'select', id: null }); });
  const quietly = (f) => {
    syncing = true;
    try { f(); } finally { syncing = false; }
  };

  // A node's diagnostics as a tooltip.
  const tooltip = document.querySelector('#tooltip');
  cy.on('mouseover', 'node', (ev) => {
    const d = ev.target.data('diag');
    if (!d || !tooltip) return;
    const p = ev.target.renderedPosition();
    const box = container.getBoundingClientRect();
    tooltip.textContent = d;
    tooltip.style.left = `${box.left + p.x + 18}px`;
    tooltip.style.top = `${box.top + p.y + 18}px`;
    tooltip.hidden = false;
  });
  cy.on('mouseout', 'node', () => { if (tooltip) tooltip.hidden = true; });

  // A place or a transition added to the net shown, at `at` (model
  // coordinates; the view's centre by default), named `name` or a fresh name.
  function addNode(kind, at, name) {
    const s = getState();
    if (!editable(s)) { fx.say('this net is not editable here', true); return; }
    const n = name || uniqueName(s, kind === 'place' ? 'p' : 't');
    if (!/^[A-Za-z_][A-Za-z0-9_]*$/.test(n)) { fx.say(`'${n}' is not a name (a letter or _, then letters, digits, _)`, true); return; }
    const op = kind === 'place' ? { op: 'add_place', net: s.netName, name: n, initial: 0 } : { op: 'add_transition', net: s.netName, name: n };
    fx.applyOp(op, at || viewCentre(cy));
  }

  return { eh, addNode, quietly };
}

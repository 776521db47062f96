// The page's heavy views, loaded by main.js after the file list is shown
// (their own chunk: cytoscape, CodeMirror): the canvas, the text pane and
// the inspector, subscribed to the store like the others; the toolbar's
// canvas buttons, its keys (delete, zoom) and the wheel.
import { $ } from './dom.js';
import { editable } from './store.js';
import { createCanvas, kZoomStep } from './canvas.js';
import { createTextPane } from './textpane.js';
import { createInspector, deleteSelection } from './inspector.js';
import { warmUp } from './warm.js';

// The wheel zooms a useful step: 1.15× for a mouse notch (100 px), smoothly
// for a touchpad's small deltas. Taken before cytoscape's own handler, whose
// "inaccurate device" scaling made a notch 0.8%.
export const kWheelPerPx = Math.log(1.15) / 100;

export function startViews(store, fx) {
  const { getState } = store;
  const canvas = createCanvas($('#cy'), store, fx);
  const text = createTextPane($('#text-pane'), store, fx);
  createInspector(store, fx, canvas);
  const cy = canvas.cy;

  const on = (sel, ev, f) => $(sel).addEventListener(ev, f);
  on('#btn-add-place', 'click', () => { const i = $('#new-name'); const n = i.value.trim(); i.value = ''; canvas.addNode('place', canvas.centre(), n); });
  on('#btn-add-transition', 'click', () => { const i = $('#new-name'); const n = i.value.trim(); i.value = ''; canvas.addNode('transition', canvas.centre(), n); });
  on('#btn-delete', 'click', () => deleteSelection(store, fx, canvas));
  on('#btn-relayout', 'click', () => { canvas.relayout(); canvas.fitReadable(); });
  on('#btn-fit', 'click', () => canvas.fitReadable());
  on('#btn-zoom-in', 'click', () => canvas.zoomBy(kZoomStep));
  on('#btn-zoom-out', 'click', () => canvas.zoomBy(1 / kZoomStep));

  $('#cy-wrap').addEventListener('wheel', (ev) => {
    ev.preventDefault();
    ev.stopPropagation();
    const px = ev.deltaY * (ev.deltaMode === 1 ? 33 : ev.deltaMode === 2 ? 800 : 1);
    const k = Math.exp(-px * kWheelPerPx);
    const rect = $('#cy').getBoundingClientRect();
    const level = Math.max(cy.minZoom(), Math.min(cy.maxZoom(), cy.zoom() * k));
    cy.zoom({ level, renderedPosition: { x: ev.clientX - rect.left, y: ev.clientY - rect.top } });
  }, { capture: true, passive: false });
  const zoomLabel = () => { $('#zoom-label').textContent = `${Math.round(cy.zoom() * 100)}%`; };
  cy.on('zoom', zoomLabel);
  zoomLabel();

  // The page's keys that act on the canvas (main.js passes them on, outside forms).
  function key(ev) {
    if ((ev.key === 'Delete' || ev.key === 'Backspace') && editable(getState())) deleteSelection(store, fx, canvas);
    if (ev.key === '+' || ev.key === '=') canvas.zoomBy(kZoomStep);
    if (ev.key === '-') canvas.zoomBy(1 / kZoomStep);
  }
  // The first open made cheaper while the page waits for it (warm.js):
  // dropped once a file is opened or a run is shown.
  const warmed = warmUp(canvas, () => getState().path != null || getState().netName != null);
  return { canvas, text, cy, key, warmed };
}

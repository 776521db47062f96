// How long the user waits for a file they click in the file list (issue
// 17: tank mission open ≤ 100 ms), measured by the page itself: from the
// click's event time to the task after the frame in which the canvas first
// drew the file's net (canvas.js sends `netpainted` on its container once
// cytoscape has rendered a net it was given, in a task after that frame).
// The browser tests report it beside their own figure, which also counts
// Playwright's click and polling.
//
// Each open is a performance measure named 'strata:open' (its detail as
// below) and an entry of the list returned (the last kKept): {path, net,
// down, click, opened, rendered, painted, ms}, times in performance.now()'s
// milliseconds: `down` the pointerdown's (null if not seen), `opened` when
// the store took the file (its answer had come), `rendered`
// when cytoscape had drawn the net (in the frame: the frame's layout,
// paint and commit come after it), `painted` the task after that frame;
// ms = painted - click. A click made before main.js ran (on index.html's
// early list) is not measured.
export const kKept = 20;

export function watchOpens(doc, canvasBox, store) {
  const opens = [];
  let down = null;      // the last pointerdown on a file: {path, at}
  let pending = null;   // the last click on a file not yet drawn
  const fileOf = (ev) => {
    const li = ev.target && ev.target.closest && ev.target.closest('#file-list li[data-path]');
    return li ? li.dataset.path : null;
  };
  doc.addEventListener('pointerdown', (ev) => {
    const path = fileOf(ev);
    down = path ? { path, at: ev.timeStamp } : null;
  }, true);
  doc.addEventListener('click', (ev) => {
    const path = fileOf(ev);
    if (!path) return;
    pending = { path, down: down && down.path === path ? down.at : null, click: ev.timeStamp, opened: null };
  }, true);
  store.subscribe((s, prev) => {
    if (pending && pending.opened == null && s.path === pending.path && s.model !== prev.model) pending.opened = performance.now();
  });
  canvasBox.addEventListener('netpainted', (ev) => {
    const { path, net, rendered, at } = ev.detail;
    if (!pending || pending.path !== path || at < pending.click) return;
    const o = { ...pending, net, rendered, painted: at, ms: at - pending.click };
    pending = null;
    performance.measure('strata:open', { start: o.click, end: o.painted, detail: o });
    opens.push(o);
    if (opens.length > kKept) opens.shift();
  });
  return opens;
}

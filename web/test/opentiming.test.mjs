// The page's own timing of an open from the file list (opentiming.js):
// from the click event's time to the canvas's `netpainted` of that file.
//   node --test web/test/
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { watchOpens, kKept } from '../src/opentiming.js';
import { createStore } from '../src/store.js';

// Stand-ins for the document and the canvas's box: their listeners, called by hand.
function target() {
  const on = {};
  return { on, addEventListener(type, f) { on[type] = f; } };
}
const onFile = (path, timeStamp) => ({ timeStamp, target: { closest: (sel) => (sel.includes('#file-list') ? { dataset: { path } } : null) } });
const elsewhere = (timeStamp) => ({ timeStamp, target: { closest: () => null } });
const painted = (path, net, rendered, at) => ({ detail: { path, net, rendered, at } });
const model = (text) => ({ text, nets: [{ name: 'tank', places: [], transitions: [] }] });

test('opentiming: an open is timed from the click to the paint of that file\'s net, once; the pointerdown and the store\'s taking are kept', () => {
  const doc = target(), box = target(), store = createStore();
  const opens = watchOpens(doc, box, store);
  doc.on.pointerdown(onFile('tank.coral', 100));
  doc.on.click(onFile('tank.coral', 104));
  store.dispatch({ type: 'file/opened', path: 'tank.coral', model: model('a') });
  const beforePaint = opens.length;
  box.on.netpainted(painted('other.coral', 'x', 120, 130));   // another file's net: not this open
  box.on.netpainted(painted('tank.coral', 'tank', 150, 170));
  box.on.netpainted(painted('tank.coral', 'tank', 180, 190)); // drawn again: already timed
  assert.equal(beforePaint, 0);
  assert.equal(opens.length, 1);
  const o = opens[0];
  assert.deepEqual([o.path, o.net, o.down, o.click, o.rendered, o.painted, o.ms], ['tank.coral', 'tank', 100, 104, 150, 170, 66]);
  assert.equal(typeof o.opened, 'number');
});

test('opentiming: a click elsewhere times nothing, a paint from before the click ends nothing, and only the last kKept opens are kept', () => {
  const doc = target(), box = target(), store = createStore();
  const opens = watchOpens(doc, box, store);
  doc.on.click(elsewhere(10));
  box.on.netpainted(painted('tank.coral', 'tank', 20, 30));
  assert.equal(opens.length, 0);
  doc.on.click(onFile('tank.coral', 50));
  box.on.netpainted(painted('tank.coral', 'tank', 40, 45));   // before the click
  assert.equal(opens.length, 0);
  for (let i = 0; i < kKept + 3; i++) {
    doc.on.click(onFile('tank.coral', 1000 * i + 100));
    box.on.netpainted(painted('tank.coral', 'tank', 1000 * i + 150, 1000 * i + 160));
  }
  assert.equal(opens.length, kKept);
  assert.equal(opens[0].click, 3100);
  assert.equal(opens[0].down, null);
});

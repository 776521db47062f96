// Which elements of a large net the canvas shows (netwindow.js).
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { windowIds, windowBox } from '../src/netwindow.js';

const node = (id) => ({ group: 'nodes', data: { id } });
const edge = (source, target) => ({ group: 'edges', data: { id: `${source}>${target}`, source, target } });

test('the nodes in the box, their edges, and the far ends of those edges', () => {
  // a chain p0 -> t1 -> p1 -> t2 -> p2 along x, 100 apart
  const els = [node('p0'), node('t1'), node('p1'), node('t2'), node('p2'), edge('p0', 't1'), edge('t1', 'p1'), edge('p1', 't2'), edge('t2', 'p2')];
  const pos = { p0: { x: 0, y: 0 }, t1: { x: 100, y: 0 }, p1: { x: 200, y: 0 }, t2: { x: 300, y: 0 }, p2: { x: 400, y: 0 } };
  assert.deepEqual([...windowIds(els, pos, { x1: 150, y1: -10, x2: 250, y2: 10 })].sort(),
    ['p1', 'p1>t2', 't1', 't1>p1', 't2'].sort());
  assert.equal(windowIds(els, pos, { x1: 1000, y1: 0, x2: 2000, y2: 10 }).size, 0);
  // A node without a position is never shown (it is placed first).
  assert.deepEqual([...windowIds(els, { p1: pos.p1 }, { x1: -1e9, y1: -1e9, x2: 1e9, y2: 1e9 })], ['p1']);
});

test('the box reaches half the view beyond each edge', () => {
  assert.deepEqual(windowBox({ x1: 0, y1: 0, x2: 100, y2: 50 }), { x1: -50, y1: -25, x2: 150, y2: 75 });
});

// The layered layout (layout.js) without a browser.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { layeredLayout } from '../src/layout.js';

// A chain p0 -> t1 -> p1 -> ... -> tN -> pN.
export function chain(n) {
  const places = [{ name: 'p0', initial: 1 }];
  const transitions = [];
  for (let i = 1; i <= n; i++) {
    places.push({ name: `p${i}`, initial: 0 });
    transitions.push({ name: `t${i}`, inputs: [{ place: `p${i - 1}`, weight: 1 }], outputs: [{ place: `p${i}`, weight: 1 }], actions: [] });
  }
  return { name: 'chain', places, transitions, exits: [] };
}

test('a 5,000-transition chain is laid out (no recursion that grows with the net), left to right on one line', () => {
  const pos = layeredLayout(chain(5000));
  assert.equal(Object.keys(pos).length, 10001);
  let x = -Infinity;
  for (let i = 0; i <= 5000; i++) {
    const p = pos[`p:p${i}`];
    assert.ok(p.x > x, `p${i} is not right of the node before it`);
    x = p.x;
    if (i) assert.ok(pos[`t:t${i}`].x < p.x && pos[`t:t${i}`].x > pos[`p:p${i - 1}`].x);
  }
  const ys = new Set(Object.values(pos).filter((_, i) => i % 2 === 0).map((p) => Math.round(p.y)));
  assert.ok(ys.size <= 2, `a chain should stay on one line, got ${ys.size} heights`);
});

test('a cycle is laid out; the loop-back arc goes right to left once', () => {
  const net = { name: 'c', exits: [], places: [{ name: 'a', initial: 1 }, { name: 'b' }],
    transitions: [{ name: 'go', inputs: [{ place: 'a' }], outputs: [{ place: 'b' }] }, { name: 'back', inputs: [{ place: 'b' }], outputs: [{ place: 'a' }] }] };
  const pos = layeredLayout(net);
  assert.ok(pos['p:a'].x < pos['t:go'].x && pos['t:go'].x < pos['p:b'].x && pos['p:b'].x < pos['t:back'].x);
});

test('nodes of one rank do not overlap, and a branch opens downwards', () => {
  const net = { name: 'b', exits: ['yes', 'no'], places: [{ name: 's', initial: 1 }],
    transitions: [{ name: 'ask', inputs: [{ place: 's' }], outputs: [], actions: [{ kind: 'TACTIC', type: 'ASK', target: 'q', label: 'ASK q', outcomes: ['yes', 'no'] }] }] };
  const pos = layeredLayout(net);
  assert.equal(pos['p:yes'].x, pos['p:no'].x);
  assert.ok(Math.abs(pos['p:yes'].y - pos['p:no'].y) >= 40 + 14, 'yes and no overlap');
});

test('an empty net has no positions', () => {
  assert.deepEqual(layeredLayout({ name: 'e', places: [], transitions: [], exits: [] }), {});
});

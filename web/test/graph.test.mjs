// The canvas's element specs (graph.js netElements): with a cache, an
// element an edit left alone is the very spec of the last render, also when
// the patch moved its line; what changed is new; the result is the same as
// without a cache.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { netElements, createElementCache } from '../src/graph.js';

const place = (name, initial = 0) => ({ name, initial, exit: false, line: 1 });
const tr = (name, from, to, line, actions = []) => ({ name, priority: 0, line, inputs: [{ place: from, weight: 1 }], outputs: [{ place: to, weight: 1 }], actions });
const chainNet = (n) => ({
  name: 'chain', exits: ['done'],
  places: Array.from({ length: n }, (_, i) => place(`p${i}`, i === 0 ? 1 : 0)),
  transitions: Array.from({ length: n }, (_, i) => tr(`t${i}`, `p${i}`, i + 1 < n ? `p${i + 1}` : 'done', 10 + i)),
});
const plain = (els) => els.map((e) => ({ group: e.group, data: e.data, classes: e.classes }));

test('netElements with a cache: unchanged elements keep their specs, changed ones are new', () => {
  const cache = createElementCache();
  const net = chainNet(50);
  const a = netElements(net, null, cache);
  assert.deepEqual(plain(a), plain(netElements(net, null)));
  // An edit's patch: a place added, every transition's line shifted (new
  // objects, same arrays), one transition's actions changed.
  const moved = net.transitions.map((t) => ({ ...t, line: t.line + 1 }));
  moved[7] = { ...moved[7], actions: [{ kind: 'TACTIC', type: 'EXEC', target: 'sleep', args: ['1'], outcomes: ['p9'], label: 'EXEC sleep(1)' }] };
  const net2 = { ...net, places: [...net.places, place('extra')], transitions: moved };
  const b = netElements(net2, null, cache);
  assert.deepEqual(plain(b), plain(netElements(net2, null)));
  const byId = (els) => new Map(els.map((e) => [e.data.id, e]));
  const A = byId(a), B = byId(b);
  assert.equal(B.get('t:t3'), A.get('t:t3'));
  assert.equal(B.get('p:p3'), A.get('p:p3'));
  assert.equal(B.get('a:p:p3>t:t3'), A.get('a:p:p3>t:t3'));
  assert.notEqual(B.get('t:t7'), A.get('t:t7'));
  assert.match(B.get('t:t7').data.label, /EXEC sleep\(1\)/);
  assert.ok(B.has('p:extra') && B.has('o:t:t7>p:p9:0'));
  // Tokens change a place's spec; the initial marking again gives a new one equal to the first.
  const c = netElements(net2, { p3: 2 }, cache);
  assert.notEqual(byId(c).get('p:p3'), A.get('p:p3'));
  assert.equal(byId(c).get('p:p3').data.tokens, 2);
});

test('netElements: outcomes to no place dropped, arcs sharing two nodes curved (once, also from the cache)', () => {
  const cache = createElementCache();
  const net = { name: 'n', exits: [], places: [place('a', 1), place('b')], transitions: [
    { ...tr('t', 'a', 'b', 3), actions: [{ kind: 'TACTIC', type: 'ASK', target: 'x', outcomes: ['b', 'nowhere'], label: 'ASK x' }] },
  ] };
  const ids = (els) => els.filter((e) => e.group === 'edges').map((e) => `${e.data.id} ${e.classes}`);
  const want = ['a:p:a>t:t arc wait', 'a:t:t>p:b arc signal pair', 'o:t:t>p:b:0 outcome pair'];
  assert.deepEqual(ids(netElements(net, null, cache)), want);
  assert.deepEqual(ids(netElements(net, null, cache)), want);   // not 'pair pair'
  assert.deepEqual(ids(netElements(net, null)), want);
});

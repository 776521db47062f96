// The page's side of edits answered with a patch (patch.js): the patch the
// server sends (src/studio/model_patch.h; the same cases as its
// model_patch_test.cpp) applied to the model held gives the model the
// server would have sent whole, and what did not change keeps its object.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { applyModelPatch } from '../src/patch.js';

const place = (name, line) => ({ name, initial: 0, exit: false, line });
const transition = (name, line, input) => ({ name, priority: 0, line, inputs: [{ place: input, weight: 1 }], outputs: [], actions: [] });
const net = (name, places, transitions, extra = {}) => ({ name, kind: 'mission', file: 'm.coral', editable: true, exits: [], places, transitions, ...extra });

test('a place added: one insert, and the lines below move by one', () => {
  const other = net('imported', [place('q', 7)], [transition('u', 9, 'q')], { editable: false, file: 'lib.coral' });
  const before = { path: 'm.coral', rev: 'r1', diagnostics: [], layout: null,
    text: 'net m {\n  place a;\n  transition t { wait { a } }\n}\n',
    nets: [net('m', [place('a', 2)], [transition('t', 3, 'a')]), other] };
  const ans = { rev: 'r2', base: 'r1', patch: {
    text: { at: 2, remove: 0, insert: ['  place b;'] }, shift: { from: 3, by: 1 }, fields: {}, drop: [],
    nets: [{ from: 0, shift: true, places: { at: 1, remove: 0, insert: [place('b', 3)] } }, { from: 1, shift: false }] } };
  const after = applyModelPatch(before, ans);
  assert.deepEqual(after, { path: 'm.coral', rev: 'r2', diagnostics: [], layout: null,
    text: 'net m {\n  place a;\n  place b;\n  transition t { wait { a } }\n}\n',
    nets: [net('m', [place('a', 2), place('b', 3)], [transition('t', 4, 'a')]), other] });
  assert.equal(after.nets[1], before.nets[1], 'a net the edit left alone is the same object');
  assert.equal(after.nets[0].places[0], before.nets[0].places[0], 'a place above the edit is the same object');
  assert.deepEqual(before.nets[0].places, [place('a', 2)], 'the old model is not changed');
  assert.equal(before.nets[0].transitions[0].line, 3);
});

test('changed members and new nets come whole, gone members go', () => {
  const before = { path: 'm.coral', rev: 'r1', text: 'a\n', diagnostics: [], layout: null, nets: [net('m', [], [])] };
  const diag = [{ severity: 'error', message: 'x' }];
  const ans = { rev: 'r2', base: 'r1', patch: {
    text: { at: 2, remove: 0, insert: [] }, shift: { from: 3, by: 0 }, fields: { diagnostics: diag }, drop: ['layout'],
    nets: [{ from: 0, shift: false, fields: { exits: ['done'] } }, { net: { name: 'n2', places: [] } }] } };
  assert.deepEqual(applyModelPatch(before, ans), { path: 'm.coral', rev: 'r2', text: 'a\n', diagnostics: diag,
    nets: [net('m', [], [], { exits: ['done'] }), { name: 'n2', places: [] }] });
});

test('a rename: the middle of an array replaced, a net dropped, lines removed', () => {
  const before = { path: 'm.coral', rev: 'r1', text: 'x\ny\nz\nw', diagnostics: [],
    nets: [net('gone', [], []), net('m', [place('a', 1), place('b', 2), place('c', 3)], [transition('t', 4, 'b')])] };
  const ans = { rev: 'r2', base: 'r1', patch: {
    text: { at: 1, remove: 2, insert: ['Y'] }, shift: { from: 4, by: -1 }, fields: {}, drop: [],
    nets: [{ from: 1, shift: true, places: { at: 1, remove: 2, insert: [place('B', 2)] },
      transitions: { at: 0, remove: 1, insert: [transition('t', 3, 'B')] } }] } };
  const after = applyModelPatch(before, ans);
  assert.equal(after.text, 'x\nY\nw');
  assert.deepEqual(after.nets, [net('m', [place('a', 1), place('B', 2)], [transition('t', 3, 'B')])]);
});

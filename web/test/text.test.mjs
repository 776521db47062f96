// The text side: CORAL tokens, diagnostics as text ranges and lint marks, the line diff.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { StringStream } from '@codemirror/language';
import { coralStream, diagnosticRange, lintDiagnostics } from '../src/coral_lang.js';
import { lineDiff, kMaxCells, commonPrefix, commonSuffix } from '../src/diff.js';

function tokens(line, st = coralStream.startState()) {
  const s = new StringStream(line, 2, 2);
  const out = [];
  while (!s.eol()) {
    const style = coralStream.token(s, st);
    if (style) out.push(`${style}:${s.current()}`);
    s.start = s.pos;
  }
  return out;
}

test('CORAL tokens: keywords, TACTIC and its kind, primitives, places, strings, numbers, comments', () => {
  assert.deepEqual(tokens('transition t priority 2 { action { TACTIC(EXEC, sleep(1), done) } } // why'), [
    'keyword:transition', 'variableName:t', 'keyword:priority', 'number:2', 'punctuation:{', 'keyword:action', 'punctuation:{',
    'macroName:TACTIC', 'punctuation:(', 'atom:EXEC', 'punctuation:,', 'function:sleep', 'punctuation:(', 'number:1', 'punctuation:)',
    'punctuation:,', 'variableName:done', 'punctuation:)', 'punctuation:}', 'punctuation:}', 'comment:// why']);
  assert.deepEqual(tokens('REPORT, "a \\"quoted\\" text")').slice(0, 3), ['atom:REPORT', 'punctuation:,', 'string:"a \\"quoted\\" text"']);
});

test('a block comment spans lines', () => {
  const st = coralStream.startState();
  assert.deepEqual(tokens('place a; /* one', st), ['keyword:place', 'variableName:a', 'punctuation:;', 'comment:/* one']);
  assert.deepEqual(tokens('two */ place b;', st), ['comment:two */', 'keyword:place', 'variableName:b', 'punctuation:;']);
});

test('a diagnostic\'s range: its span, else the word at its start, clamped to the text', () => {
  const text = 'net n {\n  place start = 1;\n}\n';
  assert.deepEqual(diagnosticRange(text, { line: 2, col: 9, end_line: 2, end_col: 14 }), { from: 16, to: 21 });
  assert.equal(text.slice(16, 21), 'start');
  assert.deepEqual(diagnosticRange(text, { line: 2, col: 3 }), { from: 10, to: 15 });
  const past = diagnosticRange(text, { line: 99, col: 99 });
  assert.ok(past.from <= text.length && past.to <= text.length);
});

test('lint marks: only the file\'s own diagnostics, with their severity', () => {
  const text = 'net n {\n  place x;\n}\n';
  const m = { diagnostics: [
    { file: 'dir/m.coral', severity: 'error', line: 2, col: 9, message: 'unused', kind: 'Unused' },
    { file: 'other.coral', severity: 'error', line: 1, col: 1, message: 'elsewhere' },
    { file: 'dir/m.coral', severity: 'warning', line: 1, col: 5, message: 'w' }] };
  const d = lintDiagnostics(text, m, 'dir/m.coral');
  assert.equal(d.length, 2);
  assert.equal(d[0].severity, 'error');
  assert.equal(text.slice(d[0].from, d[0].to), 'x');
  assert.match(d[0].message, /\[Unused\]/);
  assert.equal(d[1].severity, 'warning');
});

test('line diff: kept, removed and added lines in order', () => {
  const rows = lineDiff('a\nb\nc\nd', 'a\nB\nc\nd\ne');
  assert.deepEqual(rows.map((r) => r.op + r.text), [' a', '-b', '+B', ' c', ' d', '+e']);
  assert.deepEqual(lineDiff('same', 'same').map((r) => r.op), [' ']);
});

test('line diff: a middle too large for the table is shown whole', () => {
  const n = Math.ceil(Math.sqrt(kMaxCells)) + 10;
  const a = Array.from({ length: n }, (_, i) => `a${i}`).join('\n');
  const b = Array.from({ length: n }, (_, i) => `b${i}`).join('\n');
  const rows = lineDiff(a, b);
  assert.equal(rows.filter((r) => r.op === '-').length, n);
  assert.equal(rows.filter((r) => r.op === '+').length, n);
});

test('the span an edit changed: common prefix and suffix, as a loop over characters finds them', () => {
  const naive = (x, y) => {
    let a = 0;
    const n = Math.min(x.length, y.length);
    while (a < n && x[a] === y[a]) a++;
    let b = 0;
    while (b < n - a && x[x.length - 1 - b] === y[y.length - 1 - b]) b++;
    return [a, b];
  };
  let seed = 7;
  const rnd = (k) => { seed = (seed * 1103515245 + 12345) % 2147483648; return seed % k; };
  const word = () => Array.from({ length: rnd(12) }, () => 'ab\n'[rnd(3)]).join('');
  for (let i = 0; i < 3000; i++) {
    const x = word(), y = word();
    const a = commonPrefix(x, y);
    assert.deepEqual([a, commonSuffix(x, y, Math.min(x.length, y.length) - a)], naive(x, y), JSON.stringify([x, y]));
  }
  const lines = Array.from({ length: 5000 }, (_, i) => `  place p${i};`);
  const before = lines.join('\n');
  const after = [...lines.slice(0, 2500), '  place extra;', ...lines.slice(2500)].join('\n');
  const a = commonPrefix(before, after);
  const b = commonSuffix(before, after, before.length - a);
  assert.equal(after.slice(a, after.length - b), 'extra;\n  place ');
});

// CORAL for CodeMirror 6: a stream tokenizer (docs/language.md's words,
// comments, strings and numbers) and the checker's diagnostics as lint
// marks. Pure functions of text, kept apart from the editor view so they
// can be tested under Node.
import { StreamLanguage } from '@codemirror/language';

export const kKeywords = new Set(['net', 'mission', 'place', 'exit', 'transition', 'wait', 'action', 'signal', 'priority', 'import', 'data']);
export const kBuiltins = new Set(['TACTIC', 'PHASE']);
export const kKinds = new Set(['EXEC', 'ASK', 'REPORT', 'OOD']);

export const coralStream = {
  name: 'coral',
  startState: () => ({ inComment: false }),
  token(stream, st) {
    if (!st.inComment) {
      if (stream.eatSpace()) return null;
      if (stream.match('//')) { stream.skipToEnd(); return 'comment'; }
      if (stream.match('/*')) st.inComment = true;
    }
    if (st.inComment) {
      if (stream.skipTo('*/')) { stream.next(); stream.next(); st.inComment = false; } else stream.skipToEnd();
      return 'comment';
    }
    if (stream.match(/^"(?:[^"\\]|\\.)*"?/)) return 'string';
    if (stream.match(/^-?\d+(?:\.\d+)?/)) return 'number';
    const w = stream.match(/^[A-Za-z_][A-Za-z0-9_]*/);
    if (w) {
      const word = w[0];
      if (kKeywords.has(word)) return 'keyword';
      if (kBuiltins.has(word)) return 'macroName';
      if (kKinds.has(word)) return 'atom';
      return stream.peek() === '(' ? 'function' : 'variableName';
    }
    if (stream.match(/^[{}();,=*]/)) return 'punctuation';
    stream.next();
    return null;
  },
  languageData: { commentTokens: { line: '//', block: { open: '/*', close: '*/' } } },
};

export const coral = StreamLanguage.define(coralStream);

function sameFile(a, b) {
  if (!a || !b) return false;
  const na = String(a).replace(/\\/g, '/').replace(/^\.\//, '');
  const nb = String(b).replace(/\\/g, '/').replace(/^\.\//, '');
  return na === nb || na.endsWith('/' + nb) || nb.endsWith('/' + na);
}

// Offsets of the starts of each line of text.
export function lineStarts(text) {
  const out = [0];
  for (let i = text.indexOf('\n'); i >= 0; i = text.indexOf('\n', i + 1)) out.push(i + 1);
  return out;
}

// The text range {from, to} of a diagnostic (1-based line and column;
// end_line/end_col when given, else the word at the start).
export function diagnosticRange(text, d, starts = lineStarts(text)) {
  if (!d || !d.line) return null;
  const off = (line, col) => {
    const l = Math.max(1, Math.min(starts.length, line));
    const s = starts[l - 1];
    const e = l < starts.length ? starts[l] - 1 : text.length;
    return Math.max(s, Math.min(e, s + Math.max(1, col || 1) - 1));
  };
  const from = off(d.line, d.col);
  let to = d.end_line ? off(d.end_line, d.end_col) : from;
  if (to <= from) {
    const m = /^[A-Za-z0-9_]+/.exec(text.slice(from));
    to = Math.min(text.length, from + (m ? m[0].length : 1));
  }
  return { from, to };
}

// The diagnostics of the model that belong to path, as @codemirror/lint wants them.
export function lintDiagnostics(text, model, path) {
  const out = [];
  if (!model || !text) return out;
  const starts = lineStarts(text);
  for (const d of model.diagnostics || []) {
    if (d.file != null && !sameFile(d.file, path)) continue;
    const r = diagnosticRange(text, d, starts);
    if (!r) continue;
    out.push({ from: r.from, to: r.to, severity: d.severity === 'error' ? 'error' : d.severity === 'warning' ? 'warning' : 'info',
      message: d.message + (d.kind ? ` [${d.kind}]` : ''), source: 'strata check' });
  }
  return out;
}

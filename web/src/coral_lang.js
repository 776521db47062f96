// CORAL for CodeMirror 6: a stream tokenizer (docs/language.md's words,
// comments, strings and numbers) and the checker's diagnostics as lint
// marks. Pure functions of text, kept apart from the editor view so they
// can be tested under Node.
import { StreamLanguage } from '@codemirror/language';
import { lineStarts, diagnosticRange } from './textrange.js';

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

export { lineStarts, diagnosticRange };


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

// Text ranges of the checker's diagnostics: pure (no CodeMirror), so the
// panels can use them before the text pane is loaded.

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

// The text pane: CodeMirror 6 on the open file's text, the source of truth.
// What the user types goes to the store (fx.textTyped), which has it
// checked; the store's text (an op on the graph, undo, a reload) replaces
// the pane's; the checker's diagnostics are lint marks.
import { EditorView, keymap, lineNumbers, highlightActiveLine, drawSelection } from '@codemirror/view';
import { EditorState, Compartment, Annotation } from '@codemirror/state';
import { defaultKeymap, indentWithTab } from '@codemirror/commands';
import { syntaxHighlighting, defaultHighlightStyle, bracketMatching } from '@codemirror/language';
import { setDiagnostics, lintGutter } from '@codemirror/lint';
import { coral, lintDiagnostics } from './coral_lang.js';
import { commonPrefix, commonSuffix } from './diff.js';

const fromStore = Annotation.define();

// What the pane shows (gutters, highlighting, lint marks) but its keys and
// handlers: the pane's, and warm.js's editor of its own.
const display = () => [lineNumbers(), highlightActiveLine(), drawSelection(), bracketMatching(),
  coral, syntaxHighlighting(defaultHighlightStyle), lintGutter()];

// An editor like the pane, on text (warm.js: drawn before the first file
// is opened), and a lint mark on its first word.
export function warmTextPane(parent, text) {
  return new EditorView({ parent, state: EditorState.create({ doc: text, extensions: [display(), EditorState.readOnly.of(true)] }) });
}
export function warmLint(view) {
  const at = view.state.doc.toString().indexOf('mission');
  if (at >= 0) view.dispatch(setDiagnostics(view.state, [{ from: at, to: at + 7, severity: 'error', message: 'warm' }]));
}

export function createTextPane(parent, store, fx) {
  const { getState } = store;
  const readOnly = new Compartment();
  // The pane's text as a string, kept beside the editor's (its doc made
  // into a string is a copy of the whole file at every render).
  let docText = '';
  const view = new EditorView({
    parent,
    state: EditorState.create({
      doc: '',
      extensions: [
        display(),
        // Undo is the page's (one stack of texts for graph and text edits);
        // Ctrl-S is the page's keydown handler (main.js).
        keymap.of([
          { key: 'Mod-z', run: () => { fx.undo(); return true; } },
          { key: 'Mod-Shift-z', run: () => { fx.redo(); return true; } },
          { key: 'Mod-y', run: () => { fx.redo(); return true; } },
          indentWithTab, ...defaultKeymap]),
        readOnly.of(EditorState.readOnly.of(true)),
        EditorView.updateListener.of((u) => {
          if (!u.docChanged || deferred || u.transactions.some((t) => t.annotation(fromStore))) return;
          docText = u.state.doc.toString();
          fx.textTyped(docText);
        }),
        EditorView.domEventHandlers({ blur: () => { fx.endTyping(); } }),
      ],
    }),
  });

  // A file opened is put in the pane after the frame that draws its net
  // (the editor's part of the open, 4-22 ms in the store's notification,
  // and its own layout in that frame, came before the net was seen).
  // Meanwhile the pane shows the file before; what is typed there then is
  // dropped (the file's text replaces it).
  let drawn = null;     // the state the pane shows
  let deferred = false;
  const afterFrame = (f) => requestAnimationFrame(() => { const ch = new MessageChannel(); ch.port1.onmessage = f; ch.port2.postMessage(null); });
  function render(s) {
    if (deferred) return;
    if (drawn && s.path !== drawn.path && s.path != null) {
      deferred = true;
      afterFrame(() => { deferred = false; show(getState()); });
      return;
    }
    show(s);
  }
  function show(s) {
    const prev = drawn;
    drawn = s;
    const text = s.text ?? '';
    const doc = docText;
    const effects = [];
    if (!prev || s.readOnly !== prev.readOnly || s.path !== prev.path) {
      effects.push(readOnly.reconfigure(EditorState.readOnly.of(s.path == null || s.readOnly)));
    }
    if (text !== doc) {
      // Keep the cursor where it was, as near as the new text allows.
      const head = Math.min(view.state.selection.main.head, text.length);
      // Only the span that differs is replaced (an edit of a large file
      // changes a line or two of it).
      const a = commonPrefix(doc, text);
      const b = commonSuffix(doc, text, Math.min(doc.length, text.length) - a);
      view.dispatch({ changes: { from: a, to: doc.length - b, insert: text.slice(a, text.length - b) }, selection: { anchor: head }, annotations: fromStore.of(true), effects });
      docText = text;
    } else if (effects.length) view.dispatch({ effects });
    if (!prev || s.model !== prev.model || text !== doc) {
      // Marks only for the text the model is of (a typed text waits for its check).
      const diags = s.checking ? [] : lintDiagnostics(text, s.model, s.path);
      view.dispatch(setDiagnostics(view.state, diags));
    }
    if (s.focus && (!prev || s.focus !== prev.focus) && s.focus.from != null) {
      const to = Math.min(s.focus.to ?? s.focus.from, view.state.doc.length);
      const from = Math.min(s.focus.from, to);
      view.dispatch({ selection: { anchor: from, head: to }, scrollIntoView: true });
    }
  }
  store.subscribe(render);
  render(getState());
  return {
    view,
    get text() { return view.state.doc.toString(); },
    get selection() { const m = view.state.selection.main; return { from: m.from, to: m.to }; },
    get lintCount() { let n = 0; view.dom.querySelectorAll('.cm-lintRange').forEach(() => n++); return n; },
  };
}

// Editing: modes, ops sent to POST /api/edit, the inspector and the
// action picker, saving text and layout.
import { api } from './api.js';
import { placeId, transId } from './graph.js';
import { $, el, state, cy, eh, msg, setDirty, currentNet, displayNets, editable, uniqueName } from './context.js';
import { setModel, rememberPositions, renderNet, openFile } from './view.js';

// ---------------------------------------------------------------- editing

// Where the pointer was released, in the page's coordinates. Taken from
// the pointer events themselves, in the capture phase, so it is there before
// edgehandles ends the drag on mouseup: Cytoscape's last 'tapdrag' may be an
// earlier point of the drag when the page is busy.
let released = null;
window.addEventListener('pointerdown', () => { released = null; }, true);
window.addEventListener('pointerup', (e) => { released = { x: e.clientX, y: e.clientY }; }, true);

// The release point in the canvas's model coordinates.
function releasePoint() {
  if (!released) return null;
  const rect = cy.container().getBoundingClientRect();
  const pan = cy.pan(), zoom = cy.zoom();
  return { x: (released.x - rect.left - pan.x) / zoom, y: (released.y - rect.top - pan.y) / zoom };
}

cy.on('ehcomplete', (ev, source, target, added) => {
  added.remove();
  const pointer = releasePoint();
  const box = target.boundingBox({ includeLabels: false });
  const slack = 6;
  if (!pointer || pointer.x < box.x1 - slack || pointer.x > box.x2 + slack || pointer.y < box.y1 - slack || pointer.y > box.y2 + slack) {
    msg('release the arc on the place or transition it should join', true);
    return;
  }
  const a = source.data('kind'), b = target.data('kind');
  if (!((a === 'place' && b === 'transition') || (a === 'transition' && b === 'place'))) {
    msg('an arc goes from a place to a transition or from a transition to a place', true);
    return;
  }
  applyOp({ op: 'add_arc', net: state.netName, from: source.data('name'), to: target.data('name'), weight: 1 });
});

export function setMode(m) {
  state.mode = m;
  for (const b of document.querySelectorAll('button.mode')) b.classList.toggle('active', b.dataset.mode === m);
  if (m === 'arc') eh.enableDrawMode(); else eh.disableDrawMode();
  cy.edges().toggleClass('noev', m === 'arc');
  $('#cy').dataset.mode = m;
}
for (const b of document.querySelectorAll('button.mode')) b.addEventListener('click', () => setMode(b.dataset.mode));

// Applies one edit op (docs/studio.md "Edits"); at: where a new node goes.
export async function applyOp(op, at) {
  if (!state.path || !state.model) { msg('open a file first', true); return false; }
  if (!editable() && op.net === state.netName) { msg(`${state.netName} is not declared in ${state.path}: open its own file to edit it`, true); return false; }
  const netName = op.net;
  rememberPositions();
  state.busy++;
  try {
    const model = await api.edit(state.path, state.text, op);
    const pos = state.positions[netName] || (state.positions[netName] = {});
    if (op.op === 'rename_place' && pos[placeId(op.name)]) { pos[placeId(op.to)] = pos[placeId(op.name)]; delete pos[placeId(op.name)]; }
    if (op.op === 'rename_transition' && pos[transId(op.name)]) { pos[transId(op.to)] = pos[transId(op.name)]; delete pos[transId(op.name)]; }
    if (op.op === 'delete_place') delete pos[placeId(op.name)];
    if (op.op === 'delete_transition') delete pos[transId(op.name)];
    if (op.op === 'add_place' || op.op === 'add_transition') state.pendingPos = at || null;
    const selected = selectedAfter(op);
    if (state.view === 'cex') state.view = 'edit';
    setModel(model);
    setDirty(true);
    if (selected) { const n = cy.getElementById(selected); if (n.nonempty()) n.select(); }
    const errs = (model.diagnostics || []).filter((d) => d.severity === 'error').length;
    msg(`${op.op}: done${errs ? `, ${errs} error(s)` : ''}`);
    return true;
  } catch (e) {
    msg(`${op.op}: ${e.message}`, true);
    return false;
  } finally { state.busy--; }
}

export function selectedAfter(op) {
  switch (op.op) {
    case 'add_place': case 'set_initial': return placeId(op.name);
    case 'rename_place': return placeId(op.to);
    case 'add_transition': return transId(op.name);
    case 'rename_transition': return transId(op.to);
    case 'set_actions': return transId(op.transition);
    default: return null;
  }
}

export function addNode(kind, at) {
  if (!editable()) { msg('this net is not editable here', true); return; }
  const input = $('#new-name');
  const name = input.value.trim() || uniqueName(kind === 'place' ? 'p' : 't');
  input.value = '';
  if (!/^[A-Za-z_][A-Za-z0-9_]*$/.test(name)) { msg(`'${name}' is not a name (a letter or _, then letters, digits, _)`, true); return; }
  if (kind === 'place') applyOp({ op: 'add_place', net: state.netName, name, initial: 0 }, at);
  else applyOp({ op: 'add_transition', net: state.netName, name }, at);
}

export function centre() {
  const e = cy.extent();
  return { x: (e.x1 + e.x2) / 2, y: (e.y1 + e.y2) / 2 };
}

$('#btn-add-place').addEventListener('click', () => addNode('place', centre()));
$('#btn-add-transition').addEventListener('click', () => addNode('transition', centre()));
cy.on('tap', (ev) => {
  if (ev.target !== cy) return;
  if (state.mode === 'place') addNode('place', { ...ev.position });
  else if (state.mode === 'transition') addNode('transition', { ...ev.position });
});

export function deleteSelected() {
  const sel = cy.$(':selected');
  if (sel.empty()) { msg('select something to delete', true); return; }
  const e = sel[0];
  const net = state.netName;
  if (e.isNode()) {
    if (e.data('kind') === 'place') applyOp({ op: 'delete_place', net, name: e.data('name') });
    else applyOp({ op: 'delete_transition', net, name: e.data('name') });
  } else if (e.data('kind') === 'arc') {
    applyOp({ op: 'delete_arc', net, from: e.data('from'), to: e.data('to') });
  } else {
    msg('an outcome arrow belongs to the transition\'s action: edit its actions', true);
  }
}
$('#btn-delete').addEventListener('click', deleteSelected);
document.addEventListener('keydown', (ev) => {
  if (ev.target && /^(INPUT|SELECT|TEXTAREA)$/.test(ev.target.tagName)) return;
  if (ev.key === 'Delete' || ev.key === 'Backspace') { if (editable()) deleteSelected(); }
  if (ev.key === 'Escape') setMode('select');
});
$('#btn-relayout').addEventListener('click', () => {
  if (!currentNet()) return;
  state.positions[state.netName] = {};
  renderNet();
  cy.fit(undefined, 30);
  if (state.path) setDirty(true);
});
$('#btn-fit').addEventListener('click', () => cy.fit(undefined, 30));
cy.on('dragfree', 'node', (ev) => {
  const n = ev.target;
  if (!state.netName || n.hasClass('eh-handle')) return;
  (state.positions[state.netName] || (state.positions[state.netName] = {}))[n.id()] = { ...n.position() };
  if (state.path && editable()) setDirty(true);
});

// ---------------------------------------------------------------- inspector
cy.on('select unselect', () => renderInspector());

export function field(label, input) { return el('div', { class: 'field' }, el('label', {}, label), input); }

export function renderInspector() {
  const body = $('#inspector-body');
  body.replaceChildren();
  const sel = cy.$(':selected');
  const net = currentNet();
  if (!net) { body.append(el('div', { class: 'muted' }, 'No net.')); return; }
  const ed = editable();
  if (sel.empty()) {
    body.append(el('div', {}, el('b', {}, net.name), ` (${net.kind}) `, el('span', { class: 'muted' }, net.file || '')),
      el('div', { class: 'muted' }, `${(net.places || []).length} places, ${(net.transitions || []).length} transitions; exits: ${(net.exits || []).join(', ')}`),
      el('div', { class: 'muted' }, ed ? 'Select an element, or add one with the toolbar.' : 'Read-only here: declared in an imported file.'));
    return;
  }
  const e = sel[0];
  const kind = e.data('kind');
  if (e.data('diag')) body.append(el('pre', { class: 'diag-msg' }, e.data('diag')));
  if (kind === 'place') inspectPlace(body, net, e, ed);
  else if (kind === 'transition') inspectTransition(body, net, e, ed);
  else if (kind === 'arc') inspectArc(body, net, e, ed);
  else body.append(el('div', {}, `${e.data('from')} → ${e.data('to')}`), el('div', { class: 'muted' }, 'Marked by the reply of the transition\'s action (edit its actions).'));
}

export function renameRow(net, kind, name, ed) {
  const input = el('input', { id: 'insp-name', value: name, size: 16, disabled: !ed });
  const go = () => {
    const to = input.value.trim();
    if (!to || to === name) return;
    applyOp({ op: kind === 'place' ? 'rename_place' : 'rename_transition', net: net.name, name, to });
  };
  input.addEventListener('keydown', (ev) => { if (ev.key === 'Enter') go(); });
  return field('name', el('span', {}, input, ed ? el('button', { id: 'insp-rename', onclick: go }, 'Rename') : null));
}

export function arcAdder(net, e, ed) {
  if (!ed) return null;
  const isPlace = e.data('kind') === 'place';
  const others = isPlace ? (net.transitions || []).map((t) => t.name) : [...(net.places || []).map((p) => p.name), ...(net.exits || []).filter((x) => !(net.places || []).some((p) => p.name === x))];
  const sel = el('select', { id: 'insp-arc-other' }, others.map((o) => el('option', { value: o }, o)));
  const w = el('input', { id: 'insp-arc-weight', type: 'number', min: 1, step: 1, value: 1, size: 3 });
  const go = () => {
    const o = sel.value;
    if (!o) return;
    const from = e.data('name'), to = o;
    applyOp({ op: 'add_arc', net: net.name, from, to, weight: Number(w.value) || 1 });
  };
  return field(isPlace ? 'arc to transition' : 'arc to place', el('span', {}, sel, ' ×', w, el('button', { id: 'insp-arc-add', onclick: go }, 'Add arc')));
}

export function inspectPlace(body, net, e, ed) {
  const name = e.data('name');
  body.append(el('div', {}, el('b', {}, 'place '), name, e.data('exit') ? el('span', { class: 'badge exit' }, 'exit') : null, e.data('line') ? el('span', { class: 'muted' }, ` line ${e.data('line')}`) : null));
  body.append(renameRow(net, 'place', name, ed));
  const init = el('input', { id: 'insp-initial', type: 'number', min: 0, step: 1, value: e.data('initial') || 0, size: 4, disabled: !ed });
  const setInit = () => applyOp({ op: 'set_initial', net: net.name, name, initial: Math.max(0, Math.floor(Number(init.value) || 0)) });
  init.addEventListener('keydown', (ev) => { if (ev.key === 'Enter') setInit(); });
  body.append(field('initial tokens', el('span', {}, init, ed ? el('button', { id: 'insp-set-initial', onclick: setInit }, 'Set') : null)));
  if (state.view !== 'edit') body.append(field('tokens now', el('span', {}, String(e.data('tokens') || 0))));
  const a = arcAdder(net, e, ed); if (a) body.append(a);
  if (ed) body.append(el('button', { class: 'danger', onclick: deleteSelected }, 'Delete place'));
}

export function inspectArc(body, net, e, ed) {
  body.append(el('div', {}, el('b', {}, e.hasClass('wait') ? 'wait arc ' : 'signal arc '), `${e.data('from')} → ${e.data('to')}`));
  const w = el('input', { id: 'insp-weight', type: 'number', min: 1, step: 1, value: e.data('weight') || 1, size: 4, disabled: !ed });
  const set = () => applyOp({ op: 'set_weight', net: net.name, from: e.data('from'), to: e.data('to'), weight: Math.max(1, Math.floor(Number(w.value) || 1)) });
  w.addEventListener('keydown', (ev) => { if (ev.key === 'Enter') set(); });
  body.append(field('weight', el('span', {}, w, ed ? el('button', { id: 'insp-set-weight', onclick: set }, 'Set') : null)));
  if (ed) body.append(el('button', { class: 'danger', onclick: deleteSelected }, 'Delete arc'));
}

export const OUTCOMES = { EXEC: ['done →'], OOD: ['done →'], ASK: ['yes (1) →', 'no (0) →'], REPORT: [] };

export function actionForOp(a) {
  if (a.kind === 'PHASE') return { kind: 'PHASE', target: a.target, outcomes: (a.outcomes || []).slice() };
  return { kind: 'TACTIC', type: a.type, target: a.target ?? '', args: (a.args || []).map(String), text: a.text ?? '', outcomes: (a.outcomes || []).slice() };
}

export function inspectTransition(body, net, e, ed) {
  const name = e.data('name');
  const t = (net.transitions || []).find((x) => x.name === name);
  body.append(el('div', {}, el('b', {}, 'transition '), name, t && t.priority ? ` priority ${t.priority}` : '', e.data('line') ? el('span', { class: 'muted' }, ` line ${e.data('line')}`) : null));
  body.append(renameRow(net, 'transition', name, ed));
  const a = arcAdder(net, e, ed); if (a) body.append(a);
  if (!t) return;
  const actions = t.actions || [];
  const list = el('ul', { class: 'list actions', id: 'insp-actions' });
  actions.forEach((act, i) => {
    list.append(el('li', {}, act.label || `${act.kind} ${act.target}`, (act.outcomes || []).length ? el('span', { class: 'muted' }, ` → ${act.outcomes.join(', ')}`) : null,
      ed ? el('button', { class: 'small', title: 'Remove this action', onclick: () => {
        const rest = actions.filter((_, j) => j !== i).map(actionForOp);
        applyOp({ op: 'set_actions', net: net.name, transition: name, actions: rest });
      } }, '×') : null));
  });
  if (!actions.length) list.append(el('li', { class: 'muted' }, 'no action'));
  body.append(el('div', { class: 'sub' }, 'actions'), list);
  if (ed) body.append(actionPicker(net, name, actions));
  if (ed) body.append(el('button', { class: 'danger', onclick: deleteSelected }, 'Delete transition'));
}

// The picker of a new action: a TACTIC from the primitive catalogue (kind,
// primitive, its arguments, the places its reply marks) or a PHASE.
export function actionPicker(net, tname, actions) {
  const box = el('div', { class: 'picker', id: 'action-picker' });
  const placeNames = [...new Set([...(net.places || []).map((p) => p.name), ...(net.exits || [])])];
  const placeSelect = (id) => el('select', { class: 'outcome', id }, placeNames.map((p) => el('option', { value: p }, p)));
  const kindSel = el('select', { id: 'pick-kind' }, ['EXEC', 'ASK', 'REPORT', 'OOD', 'PHASE'].map((k) => el('option', { value: k }, k === 'PHASE' ? 'PHASE' : `TACTIC ${k}`)));
  const targetSel = el('select', { id: 'pick-target' });
  const argsBox = el('div', { class: 'args' });
  const outBox = el('div', { class: 'outs' });
  const phases = displayNets().filter((n) => n.kind === 'phase');
  const fill = () => {
    const k = kindSel.value;
    targetSel.replaceChildren();
    if (k === 'PHASE') for (const p of phases) targetSel.append(el('option', { value: p.name }, p.name));
    else for (const p of state.primitives.filter((p) => (p.kind || '').toUpperCase() === k)) targetSel.append(el('option', { value: p.name, title: p.doc || '' }, p.name));
    targetSel.hidden = k === 'REPORT';
    fillArgs();
  };
  const fillArgs = () => {
    const k = kindSel.value;
    argsBox.replaceChildren();
    outBox.replaceChildren();
    if (k === 'PHASE') {
      const ph = phases.find((p) => p.name === targetSel.value);
      (ph ? ph.exits || [] : []).forEach((x, i) => outBox.append(field(`exit ${x} →`, placeSelect(`pick-out-${i}`))));
      return;
    }
    const prim = k === 'REPORT' ? state.primitives.find((p) => (p.kind || '') === 'report') : state.primitives.find((p) => p.name === targetSel.value);
    if (k === 'REPORT') {
      argsBox.append(field('text', el('input', { id: 'pick-text', size: 28, placeholder: 'a line for the operator' })));
    } else if (prim) {
      (prim.args || []).forEach((a, i) => {
        const isNum = a.type !== 'string';
        const inp = el('input', { id: `pick-arg-${i}`, class: 'arg', 'data-type': isNum ? 'number' : 'string', type: isNum ? 'number' : 'text', step: 'any',
          min: a.min ?? undefined, max: a.max ?? undefined, value: a.default ?? (a.min ?? (isNum ? 1 : '')), size: 8 });
        argsBox.append(field(`${a.name}${a.unit ? ` (${a.unit})` : ''}`, inp));
      });
      if (prim.doc) argsBox.append(el('div', { class: 'muted small' }, prim.doc));
    }
    (OUTCOMES[k] || []).forEach((lab, i) => outBox.append(field(lab, placeSelect(`pick-out-${i}`))));
  };
  kindSel.addEventListener('change', fill);
  targetSel.addEventListener('change', fillArgs);
  const add = () => {
    const k = kindSel.value;
    const outcomes = [...outBox.querySelectorAll('select.outcome')].map((s) => s.value);
    let act;
    if (k === 'PHASE') {
      if (!targetSel.value) { msg('no phase net to call', true); return; }
      act = { kind: 'PHASE', target: targetSel.value, outcomes };
    } else if (k === 'REPORT') {
      act = { kind: 'TACTIC', type: 'REPORT', target: '', args: [], text: box.querySelector('#pick-text').value, outcomes };
    } else {
      if (!targetSel.value) { msg(`no ${k} primitive in the catalogue`, true); return; }
      const args = [];
      for (const inp of argsBox.querySelectorAll('input.arg')) {
        if (inp.dataset.type === 'number') {
          if (inp.value === '' || !Number.isFinite(Number(inp.value))) { msg('an argument is not a number', true); return; }
          if ((inp.min !== '' && Number(inp.value) < Number(inp.min)) || (inp.max !== '' && Number(inp.value) > Number(inp.max))) { msg(`argument out of range [${inp.min}, ${inp.max}]`, true); return; }
          args.push(String(Number(inp.value)));
        } else args.push(inp.value);
      }
      act = { kind: 'TACTIC', type: k, target: targetSel.value, args, text: '', outcomes };
    }
    applyOp({ op: 'set_actions', net: net.name, transition: tname, actions: [...actions.map(actionForOp), act] });
  };
  box.append(el('div', { class: 'sub' }, 'add an action'), field('kind', kindSel), field('call', targetSel), argsBox, outBox,
    el('button', { id: 'pick-add', onclick: add }, 'Add action'));
  fill();
  return box;
}

// ---------------------------------------------------------------- save
export function layoutByName() {
  rememberPositions();
  const out = {};
  for (const net of displayNets()) {
    const pos = state.positions[net.name];
    if (!pos) continue;
    const m = {};
    for (const [id, xy] of Object.entries(pos)) {
      const name = id.slice(2);
      m[name] = { x: Math.round(xy.x * 10) / 10, y: Math.round(xy.y * 10) / 10 };
    }
    out[net.name] = m;
  }
  return out;
}

export async function save() {
  if (!state.path || state.text == null) return false;
  state.busy++;
  try {
    // Each save names the version it was made from: a file saved since (by
    // another tab, or on disk) is refused with 412 instead of overwritten.
    state.etag = (await api.saveFile(state.path, state.text, state.etag)).etag;
    state.layoutEtag = (await api.saveLayout(state.path, layoutByName(), state.layoutEtag)).etag;
    setDirty(false);
    msg(`saved ${state.path}`);
    return true;
  } catch (e) {
    if (e.status === 412) {
      const path = state.path;
      msg(`not saved: ${path} changed since you opened it (another tab or program saved it). ` +
          'Reload it to see that version (your edits here are dropped), or copy them first. ', true);
      $('#edit-msg').append(el('button', { id: 'btn-reload', onclick: () => { setDirty(false); openFile(path); } }, 'Reload'));
    } else {
      msg(`save: ${e.message}`, true);
    }
    return false;
  } finally { state.busy--; }
}
$('#btn-save').addEventListener('click', save);
document.addEventListener('keydown', (ev) => { if ((ev.ctrlKey || ev.metaKey) && ev.key === 's') { ev.preventDefault(); save(); } });
window.addEventListener('beforeunload', (ev) => { if (state.dirty) { ev.preventDefault(); ev.returnValue = ''; } });

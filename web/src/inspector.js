// The inspector: the selected place, transition or arc of the canvas, with
// the forms that edit it (rename, initial tokens, weight, arcs, actions
// from the primitive catalogue). It draws from the store and sends ops
// through the effects; the element's drawn data comes from the canvas.
import { el, $ } from './dom.js';
import { currentNet, displayNets, editable } from './store.js';

// Above this many, the arc list's options are made when it is opened.
const kEagerOptions = 200;

export function createInspector(store, fx, canvas) {
  const { getState } = store;
  const cy = canvas.cy;
  const say = (t, e) => fx.say(t, e);
  const deleteSelected = () => deleteSelection(store, fx, canvas);

  const lineOf = (list, name) => ((list || []).find((x) => x.name === name) || {}).line;
  function field(label, input) { return el('div', { class: 'field' }, el('label', {}, label), input); }

  function renderInspector(s) {
    const body = $('#inspector-body');
    body.replaceChildren();
    const sel = s.selected ? cy.getElementById(s.selected) : cy.collection();
    const net = currentNet(s);
    if (!net) { body.append(el('div', { class: 'muted' }, 'No net.')); return; }
    const ed = editable(s);
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

  function renameRow(net, kind, name, ed) {
    const input = el('input', { id: 'insp-name', value: name, size: 16, disabled: !ed });
    const go = () => {
      const to = input.value.trim();
      if (!to || to === name) return;
      fx.applyOp({ op: kind === 'place' ? 'rename_place' : 'rename_transition', net: net.name, name, to });
    };
    input.addEventListener('keydown', (ev) => { if (ev.key === 'Enter') go(); });
    return field('name', el('span', {}, input, ed ? el('button', { id: 'insp-rename', onclick: go }, 'Rename') : null));
  }

  function arcAdder(net, e, ed) {
    if (!ed) return null;
    const isPlace = e.data('kind') === 'place';
    const placeNames = new Set((net.places || []).map((p) => p.name));
    const others = isPlace ? (net.transitions || []).map((t) => t.name) : [...placeNames, ...(net.exits || []).filter((x) => !placeNames.has(x))];
    // Options built plainly: a place of a 5,000-transition net lists them
    // all, when the list is first opened (building 5,000 options took 0.2 s
    // of each edit that selects a new place).
    const sel = el('select', { id: 'insp-arc-other' });
    const fill = () => { if (sel.options.length < others.length) { sel.replaceChildren(); for (const o of others) sel.add(new Option(o, o)); } };
    if (others.length <= kEagerOptions) fill();
    else {
      sel.add(new Option(`${others.length} ${isPlace ? 'transitions' : 'places'}…`, ''));
      for (const ev of ['pointerdown', 'focus', 'keydown']) sel.addEventListener(ev, fill);
    }
    const w = el('input', { id: 'insp-arc-weight', type: 'number', min: 1, step: 1, value: 1, size: 3 });
    const go = () => {
      const o = sel.value;
      if (!o) return;
      const from = e.data('name'), to = o;
      fx.applyOp({ op: 'add_arc', net: net.name, from, to, weight: Number(w.value) || 1 });
    };
    return field(isPlace ? 'arc to transition' : 'arc to place', el('span', {}, sel, ' ×', w, el('button', { id: 'insp-arc-add', onclick: go }, 'Add arc')));
  }

  function inspectPlace(body, net, e, ed) {
    const name = e.data('name');
    body.append(el('div', {}, el('b', {}, 'place '), name, e.data('exit') ? el('span', { class: 'badge exit' }, 'exit') : null, lineOf(net.places, name) ? el('span', { class: 'muted' }, ` line ${lineOf(net.places, name)}`) : null));
    body.append(renameRow(net, 'place', name, ed));
    const init = el('input', { id: 'insp-initial', type: 'number', min: 0, step: 1, value: e.data('initial') || 0, size: 4, disabled: !ed });
    const setInit = () => fx.applyOp({ op: 'set_initial', net: net.name, name, initial: Math.max(0, Math.floor(Number(init.value) || 0)) });
    init.addEventListener('keydown', (ev) => { if (ev.key === 'Enter') setInit(); });
    body.append(field('initial tokens', el('span', {}, init, ed ? el('button', { id: 'insp-set-initial', onclick: setInit }, 'Set') : null)));
    if (getState().view !== 'edit') body.append(field('tokens now', el('span', {}, String(e.data('tokens') || 0))));
    const a = arcAdder(net, e, ed); if (a) body.append(a);
    if (ed) body.append(el('button', { class: 'danger', onclick: deleteSelected }, 'Delete place'));
  }

  function inspectArc(body, net, e, ed) {
    body.append(el('div', {}, el('b', {}, e.hasClass('wait') ? 'wait arc ' : 'signal arc '), `${e.data('from')} → ${e.data('to')}`));
    const w = el('input', { id: 'insp-weight', type: 'number', min: 1, step: 1, value: e.data('weight') || 1, size: 4, disabled: !ed });
    const set = () => fx.applyOp({ op: 'set_weight', net: net.name, from: e.data('from'), to: e.data('to'), weight: Math.max(1, Math.floor(Number(w.value) || 1)) });
    w.addEventListener('keydown', (ev) => { if (ev.key === 'Enter') set(); });
    body.append(field('weight', el('span', {}, w, ed ? el('button', { id: 'insp-set-weight', onclick: set }, 'Set') : null)));
    if (ed) body.append(el('button', { class: 'danger', onclick: deleteSelected }, 'Delete arc'));
  }

  const OUTCOMES = { EXEC: ['done →'], OOD: ['done →'], ASK: ['yes (1) →', 'no (0) →'], REPORT: [] };

  function actionForOp(a) {
    // A PHASE keeps its arguments (a phase with parameters): an edit of the
    // transition must not drop them.
    if (a.kind === 'PHASE') return { kind: 'PHASE', target: a.target, args: (a.args || []).map(String), outcomes: (a.outcomes || []).slice() };
    return { kind: 'TACTIC', type: a.type, target: a.target ?? '', args: (a.args || []).map(String), text: a.text ?? '', outcomes: (a.outcomes || []).slice() };
  }

  function inspectTransition(body, net, e, ed) {
    const name = e.data('name');
    const t = (net.transitions || []).find((x) => x.name === name);
    body.append(el('div', {}, el('b', {}, 'transition '), name, t && t.priority ? ` priority ${t.priority}` : '', t && t.line ? el('span', { class: 'muted' }, ` line ${t.line}`) : null));
    body.append(renameRow(net, 'transition', name, ed));
    const a = arcAdder(net, e, ed); if (a) body.append(a);
    if (!t) return;
    const actions = t.actions || [];
    const list = el('ul', { class: 'list actions', id: 'insp-actions' });
    actions.forEach((act, i) => {
      list.append(el('li', {}, act.label || `${act.kind} ${act.target}`, (act.outcomes || []).length ? el('span', { class: 'muted' }, ` → ${act.outcomes.join(', ')}`) : null,
        ed ? el('button', { class: 'small', title: 'Remove this action', onclick: () => {
          const rest = actions.filter((_, j) => j !== i).map(actionForOp);
          fx.applyOp({ op: 'set_actions', net: net.name, transition: name, actions: rest });
        } }, '×') : null));
    });
    if (!actions.length) list.append(el('li', { class: 'muted' }, 'no action'));
    body.append(el('div', { class: 'sub' }, 'actions'), list);
    if (ed) body.append(actionPicker(net, name, actions));
    if (ed) body.append(el('button', { class: 'danger', onclick: deleteSelected }, 'Delete transition'));
  }

  // The picker of a new action: a TACTIC from the primitive catalogue (kind,
  // primitive, its arguments, the places its reply marks) or a PHASE.
  function actionPicker(net, tname, actions) {
    const box = el('div', { class: 'picker', id: 'action-picker' });
    const placeNames = [...new Set([...(net.places || []).map((p) => p.name), ...(net.exits || [])])];
    const placeSelect = (id) => el('select', { class: 'outcome', id }, placeNames.map((p) => el('option', { value: p }, p)));
    const kindSel = el('select', { id: 'pick-kind' }, ['EXEC', 'ASK', 'REPORT', 'OOD', 'PHASE'].map((k) => el('option', { value: k }, k === 'PHASE' ? 'PHASE' : `TACTIC ${k}`)));
    const targetSel = el('select', { id: 'pick-target' });
    const argsBox = el('div', { class: 'args' });
    const outBox = el('div', { class: 'outs' });
    const phases = displayNets(getState()).filter((n) => n.kind === 'phase');
    const fill = () => {
      const k = kindSel.value;
      targetSel.replaceChildren();
      if (k === 'PHASE') for (const p of phases) targetSel.append(el('option', { value: p.name }, p.name));
      else for (const p of getState().primitives.filter((p) => (p.kind || '').toUpperCase() === k)) targetSel.append(el('option', { value: p.name, title: p.doc || '' }, p.name));
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
      const prim = k === 'REPORT' ? getState().primitives.find((p) => (p.kind || '') === 'report') : getState().primitives.find((p) => p.name === targetSel.value);
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
        if (!targetSel.value) { say('no phase net to call', true); return; }
        act = { kind: 'PHASE', target: targetSel.value, outcomes };
      } else if (k === 'REPORT') {
        act = { kind: 'TACTIC', type: 'REPORT', target: '', args: [], text: box.querySelector('#pick-text').value, outcomes };
      } else {
        if (!targetSel.value) { say(`no ${k} primitive in the catalogue`, true); return; }
        const args = [];
        for (const inp of argsBox.querySelectorAll('input.arg')) {
          if (inp.dataset.type === 'number') {
            if (inp.value === '' || !Number.isFinite(Number(inp.value))) { say('an argument is not a number', true); return; }
            if ((inp.min !== '' && Number(inp.value) < Number(inp.min)) || (inp.max !== '' && Number(inp.value) > Number(inp.max))) { say(`argument out of range [${inp.min}, ${inp.max}]`, true); return; }
            args.push(String(Number(inp.value)));
          } else args.push(inp.value);
        }
        act = { kind: 'TACTIC', type: k, target: targetSel.value, args, text: '', outcomes };
      }
      fx.applyOp({ op: 'set_actions', net: net.name, transition: tname, actions: [...actions.map(actionForOp), act] });
    };
    box.append(el('div', { class: 'sub' }, 'add an action'), field('kind', kindSel), field('call', targetSel), argsBox, outBox,
      el('button', { id: 'pick-add', onclick: add }, 'Add action'));
    fill();
    return box;
  }

  let last = null;
  store.subscribe((s, prev) => {
    const key = [s.selected, currentNet(s), s.primitives, s.view, editable(s)];
    if (last && key.every((k, i) => k === last[i])) return;
    last = key;
    renderInspector(s);
  });
  renderInspector(getState());
}

// Deletes the selected element by its op.
export function deleteSelection(store, fx, canvas) {
  const s = store.getState();
  const e = s.selected ? canvas.cy.getElementById(s.selected) : null;
  if (!e || e.empty()) { fx.say('select something to delete', true); return; }
  const net = s.netName;
  if (e.isNode()) {
    if (e.data('kind') === 'place') fx.applyOp({ op: 'delete_place', net, name: e.data('name') });
    else fx.applyOp({ op: 'delete_transition', net, name: e.data('name') });
  } else if (e.data('kind') === 'arc') {
    fx.applyOp({ op: 'delete_arc', net, from: e.data('from'), to: e.data('to') });
  } else {
    fx.say('an outcome arrow belongs to the transition\'s action: edit its actions', true);
  }
}

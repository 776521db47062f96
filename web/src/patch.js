// An edit's answer as a patch of the model the page holds (POST /api/edit
// with `base`; docs/studio.md "Edits", src/studio/model_patch.h): the new
// model is built from the old one, and every net, place and transition the
// edit did not change is the very object it was, so the views redraw only
// what changed.

// The model of answer `ans` ({rev, base, patch}) applied to `base` (the
// model whose rev is ans.base).
export function applyModelPatch(base, ans) {
  const p = ans.patch;
  const model = { ...base };
  for (const k of p.drop || []) delete model[k];
  Object.assign(model, p.fields || {});
  model.text = spliceText(base.text ?? '', p.text);
  model.rev = ans.rev;
  const shift = p.shift && p.shift.by ? p.shift : null;
  model.nets = (p.nets || []).map((e) => (e.net ? e.net : patchNet(base.nets[e.from], e, e.shift ? shift : null)));
  return model;
}

function spliceText(text, t) {
  if (!t) return text;
  const lines = text.split('\n');
  lines.splice(t.at, t.remove, ...t.insert);
  return lines.join('\n');
}

function patchNet(old, e, shift) {
  if (!e.fields && !e.places && !e.transitions && !shift) return old;
  const net = { ...old, ...(e.fields || {}) };
  for (const key of ['places', 'transitions']) {
    let arr = old[key] || [];
    if (shift) arr = arr.map((x) => (typeof x.line === 'number' && x.line >= shift.from ? { ...x, line: x.line + shift.by } : x));
    if (e[key]) {
      arr = arr === old[key] ? arr.slice() : arr;
      arr.splice(e[key].at, e[key].remove, ...e[key].insert);
    }
    net[key] = arr;
  }
  return net;
}

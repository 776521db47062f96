// Edits answered with a patch (docs/studio.md "Edits"): the page sends the
// rev of the model it holds and applies the patch that comes back. After
// each edit the page's model must be the model the server gives whole: the
// same edit asked without a base, and a check of the page's text.
import { test, expect, studio, openPage, TANK } from './fixtures.mjs';

const kOps = [
  { op: 'add_place', net: 'tank', name: 'logbook', initial: 2 },
  { op: 'add_transition', net: 'tank', name: 'note' },
  { op: 'add_arc', net: 'tank', from: 'logbook', to: 'note', weight: 3 },
  { op: 'set_actions', net: 'tank', transition: 'note', actions: [{ kind: 'TACTIC', type: 'EXEC', target: 'sleep', args: ['2'], outcomes: ['logbook'] }] },
  { op: 'rename_place', net: 'tank', name: 'logbook', to: 'journal' },
  { op: 'set_initial', net: 'tank', name: 'begin', initial: 0 },   // the text above the other nets' lines
  { op: 'delete_transition', net: 'tank', name: 'note' },
  { op: 'delete_place', net: 'tank', name: 'journal' },
];

test('each edit answered with a patch gives the model the server sends whole', async ({ page }) => {
  // The page's own edits (with a base) and whether each was answered with a patch.
  const answers = [];
  page.on('response', (r) => {
    if (!r.url().endsWith('/api/edit')) return;
    const body = JSON.parse(r.request().postData());
    if (body.base) answers.push(r.json().then((a) => ({ base: body.base, patch: !!a.patch })));
  });
  await openPage(page, TANK, 'tank');
  let patched = 0;
  for (const op of kOps) {
    const before = await studio(page, '({ text: s.text, rev: s.model.rev })');
    const ok = await page.evaluate((o) => window.__studio.applyOp(o), op);
    expect(ok, JSON.stringify(op)).toBe(true);
    const got = await page.evaluate(async ({ o, text }) => {
      const post = async (url, body) => (await fetch(url, { method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify(body) })).json();
      const full = await post('/api/edit', { path: window.__studio.path, text, op: o });
      const check = await post('/api/check', { path: window.__studio.path, text: window.__studio.text });
      const drop = (m) => { const c = { ...m }; delete c.rev; return c; };
      return { mine: drop(window.__studio.model), full: drop(full), check: drop(check) };
    }, { o: op, text: before.text });
    expect(got.mine, JSON.stringify(op)).toEqual(got.full);
    expect(got.mine, JSON.stringify(op)).toEqual(got.check);
    const a = await answers[answers.length - 1];
    expect(a.base).toBe(before.rev);
    if (a.patch) patched++;
  }
  expect(answers.length).toBe(kOps.length);
  expect(patched, 'every edit answered with a patch').toBe(kOps.length);
});

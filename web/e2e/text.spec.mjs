// Text and graph as one: the CodeMirror pane and the canvas edit one text.
import { test, expect, studio, waitFor, openPage, nodePoint, TANK } from './fixtures.mjs';

// Puts the pane's cursor just after `word` on the first line holding `line`, as a user would with the keys.
async function cursorAfter(page, line, word) {
  const row = page.locator('#text-pane .cm-line', { hasText: line }).first();
  await row.click();
  await page.keyboard.press('Home');
  const text = await row.textContent();
  const lead = text.length - text.trimStart().length;   // Home stops at the indentation
  const at = text.indexOf(word) + word.length;
  for (let i = lead; i < at; i++) await page.keyboard.press('ArrowRight');
}

test('typing in the text pane updates the graph once the text compiles; a graph edit replaces the text', async ({ page }) => {
  await openPage(page);
  await cursorAfter(page, 'place begin = 1;', 'place begin = 1;');
  await page.keyboard.press('End');
  await page.keyboard.press('Enter');
  await page.keyboard.type('place typed_place = 2;');
  await waitFor(page, "cy.getElementById('p:typed_place').nonempty() && !s.checking && s.busy === 0", 10000, 'the typed place on the canvas');
  expect(await studio(page, "cy.getElementById('p:typed_place').data('tokens')")).toBe(2);
  expect(await studio(page, 's.dirty')).toBe(true);
  // A graph edit: the pane shows the server's new text.
  await page.evaluate(() => window.__studio.applyOp({ op: 'rename_place', net: 'tank', name: 'typed_place', to: 'renamed_place' }));
  await waitFor(page, "cy.getElementById('p:renamed_place').nonempty() && s.busy === 0", 8000, 'the rename');
  await expect(page.locator('#text-pane .cm-content')).toContainText('place renamed_place = 2;');
  expect(await studio(page, 's.paneText === s.text')).toBe(true);
  // One undo takes the rename back, a second the typing.
  await page.locator('#btn-undo').click();
  await waitFor(page, "cy.getElementById('p:typed_place').nonempty() && !s.checking && s.busy === 0", 8000, 'undo of the rename');
  await page.locator('#btn-undo').click();
  await waitFor(page, "cy.getElementById('p:typed_place').empty() && !s.checking && s.busy === 0 && !s.dirty", 8000, 'undo of the typing');
});

test('a typo: squiggles in the text, the error listed; clicking it selects the element and its text', async ({ page }) => {
  await openPage(page);
  await cursorAfter(page, 'TACTIC(OOD, shutdown_network, closed) }', 'shutdown_network');
  for (let i = 0; i < 3; i++) await page.keyboard.press('Backspace');
  await page.keyboard.type('rk');   // shutdown_netwrk
  await waitFor(page, '/shutdown_netwrk/.test(s.text) && !s.checking && s.busy === 0 && s.diagnostics.some((d) => d.severity === "error")', 10000, 'the error of the typo');
  await waitFor(page, 's.lintCount > 0', 5000, 'a lint mark in the pane');
  await expect(page.locator('#text-pane .cm-lintRange-error').first()).toBeVisible();
  // The net is still drawn (the last one that compiled).
  expect(await studio(page, "cy.getElementById('t:shutdown').nonempty()")).toBe(true);
  await page.evaluate(() => { window.__cy.elements().unselect(); });
  await page.locator('#diag-list li.sev-error').first().click();
  await waitFor(page, "s.state.selected === 't:shutdown' && cy.getElementById('t:shutdown').selected()", 5000, 'shutdown selected');
  const sel = await studio(page, 's.paneSelection');
  const text = await studio(page, 's.text');
  expect(sel.to).toBeGreaterThan(sel.from);
  expect(text.slice(sel.from, sel.to)).toMatch(/shutdown_netwrk/);
  // The element carries the error: red, and its tooltip says why.
  expect(await studio(page, "cy.getElementById('t:shutdown').hasClass('diag')")).toBe(true);
  await waitFor(page, "cy.animated() === false", 3000, 'the canvas still');
  const p = await nodePoint(page, 't:shutdown');
  await page.mouse.move(p.x, p.y);
  await expect(page.locator('#tooltip')).toBeVisible();
  await expect(page.locator('#tooltip')).toContainText('error');
});

const BROKEN = 'net broken {\n  place a = 1\n  place b;\n  transition t { wait { a } signal { b } }\n}\n';

test.describe('a file that does not parse', () => {
  test.use({ files: { 'broken.coral': BROKEN } });

  test('opens in the text pane with its errors, is fixed there, and saves the pane\'s text', async ({ page }) => {
    await page.goto(page.studio.url);
    await page.locator('#file-list li[data-path="broken.coral"]').click();
    await waitFor(page, "s.path === 'broken.coral' && s.busy === 0", 10000, 'broken.coral open');
    // (The pane takes an opened file's text a frame after the net is drawn.)
    await waitFor(page, 's.paneText === s.text', 5000, 'the text in the pane');
    expect(await studio(page, 's.paneText')).toBe(BROKEN);
    expect(await studio(page, 'cy.nodes().length')).toBe(0);
    await expect(page.locator('#diag-list li.sev-error').first()).toContainText("expected ';'");
    await waitFor(page, 's.lintCount > 0', 5000, 'a lint mark');
    await cursorAfter(page, 'place a = 1', 'place a = 1');
    await page.keyboard.type(';');
    await waitFor(page, "cy.getElementById('p:a').nonempty() && cy.getElementById('t:t').nonempty() && !s.checking && s.busy === 0", 10000, 'the net once it compiles');
    expect(await studio(page, 's.diagnostics.filter((d) => d.severity === "error").length')).toBe(0);
    await page.keyboard.press('Control+s');
    await waitFor(page, '!s.dirty && s.busy === 0', 10000, 'saved');
    expect(await studio(page, 's.state.conflict === null && !s.state.message.error')).toBe(true);
    expect(page.studio.read('broken.coral')).toBe(BROKEN.replace('place a = 1', 'place a = 1;'));
  });
});

test('save sends the pane\'s text as typed', async ({ page }) => {
  await openPage(page);
  await cursorAfter(page, 'place begin = 1;', 'place begin = 1;');
  await page.keyboard.press('End');
  await page.keyboard.type('   // typed note');
  await waitFor(page, '/typed note/.test(s.text) && !s.checking && s.busy === 0', 10000, 'the typed comment checked');
  await page.locator('#btn-save').click();
  await waitFor(page, '!s.dirty && s.busy === 0', 10000, 'saved');
  expect(page.studio.read(TANK)).toMatch(/place begin = 1; {3}\/\/ typed note/);
});

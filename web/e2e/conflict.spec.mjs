// No lost work: two tabs on one file, Reload or keep mine after a 412, and
// leaving or switching with unsaved edits asks first.
import fs from 'node:fs';
import { test, expect, studio, waitFor, openPage, patient, TANK } from './fixtures.mjs';

const TABS = 'missions/tank/two_tabs.coral';

async function twoTabs(page) {
  fs.copyFileSync(page.studio.file('missions/tank/initialize.coral'), page.studio.file(TABS));
  const two = await page.context().newPage();
  two.on('dialog', (d) => d.accept());
  for (const tab of [page, two]) {
    await tab.goto(page.studio.url);
    await tab.locator(`#file-list li[data-path="${TABS}"]`).click();
    await waitFor(tab, `s.path === '${TABS}' && s.net === 'initialize' && s.busy === 0`, 10000, 'the tab open');
  }
  // Both tabs edit before the first saves: were tab two's edit made after
  // the save, the server's notice of the change on disk could reload tab two
  // (no unsaved edits yet) while its edit is in flight, and the edit would be
  // dropped as made on an old text (seen under load in the asan run).
  expect(await page.evaluate(() => window.__studio.applyOp({ op: 'add_place', net: 'initialize', name: 'from_tab_one' }))).toBe(true);
  expect(await two.evaluate(() => window.__studio.applyOp({ op: 'add_place', net: 'initialize', name: 'from_tab_two' }))).toBe(true);
  expect(await page.evaluate(() => window.__studio.save())).toBe(true);
  // Tab two learns of tab one's save either from its own save (412) or,
  // first, from the server's notice of the change on disk (polled every
  // 0.5 s), which shows the same conflict and disables Save: both are
  // the conflict this test is about.
  if (!(await studio(two, '!!s.state.conflict'))) {
    await two.locator('#btn-save').click({ timeout: patient(5000) }).catch(async (e) => {
      if (!(await studio(two, '!!s.state.conflict'))) throw e;
    });
  }
  await waitFor(two, "s.state.conflict && s.busy === 0", 10000, 'the conflict shown');
  return two;
}

test('two tabs save one file: the stale save gets 412, says so, and Reload brings the first tab\'s version', async ({ page }) => {
  const two = await twoTabs(page);
  const text = page.studio.read(TABS);
  expect(text).toMatch(/from_tab_one/);
  expect(text).not.toMatch(/from_tab_two/);
  await expect(two.locator('#edit-msg')).toContainText(/changed since you opened it|changed on disk/);
  // The diff shows their line (−) and mine (+).
  await expect(two.locator('#conflict-diff')).toContainText('from_tab_one');
  await expect(two.locator('#conflict-diff')).toContainText('from_tab_two');
  await two.locator('#btn-reload').click();
  await waitFor(two, '!s.dirty && s.busy === 0 && /from_tab_one/.test(s.text) && !/from_tab_two/.test(s.text)', 10000, 'tab two reloaded');
  await expect(two.locator('#conflict-box')).toBeHidden();
  await two.close();
});

test('after a 412, keep mine saves my text over the new version', async ({ page }) => {
  const two = await twoTabs(page);
  await two.locator('#btn-keep-mine').click();
  await waitFor(two, '!s.dirty && s.busy === 0 && !s.state.conflict', 10000, 'tab two saved');
  const text = page.studio.read(TABS);
  expect(text).toMatch(/from_tab_two/);
  expect(text).not.toMatch(/from_tab_one/);
  await two.close();
});

test('switching file with unsaved edits asks; dismissing keeps the edits', async ({ page }) => {
  await openPage(page);
  await page.evaluate(() => window.__studio.applyOp({ op: 'add_place', net: 'tank', name: 'unsaved_one' }));
  await waitFor(page, 's.dirty && s.busy === 0', 8000, 'an unsaved edit');
  page.removeAllListeners('dialog');
  const asked = [];
  page.on('dialog', (d) => { asked.push(d.message()); d.dismiss(); });
  await page.locator('#file-list li[data-path="missions/tank/initialize.coral"]').click();
  await expect.poll(() => asked.length, { timeout: patient(5000) }).toBe(1);
  expect(asked[0]).toMatch(/Discard the unsaved changes/);
  expect(await studio(page, 's.path')).toBe(TANK);
  expect(await studio(page, '/unsaved_one/.test(s.text)')).toBe(true);
  // The open file clicked again (it would be read from disk) asks too.
  await page.locator(`#file-list li[data-path="${TANK}"]`).click();
  await expect.poll(() => asked.length, { timeout: patient(5000) }).toBe(2);
  expect(await studio(page, '/unsaved_one/.test(s.text) && s.dirty')).toBe(true);
  page.removeAllListeners('dialog');
  page.on('dialog', (d) => { asked.push(d.message()); d.accept(); });
  await page.locator('#file-list li[data-path="missions/tank/initialize.coral"]').click();
  await waitFor(page, "s.path === 'missions/tank/initialize.coral' && s.busy === 0", 8000, 'the other file open');
  expect(asked.length).toBe(3);
});

test('leaving the page with unsaved edits asks first (beforeunload)', async ({ page }) => {
  await openPage(page);
  await page.evaluate(() => window.__studio.applyOp({ op: 'add_place', net: 'tank', name: 'unsaved_two' }));
  await waitFor(page, 's.dirty && s.busy === 0', 8000, 'an unsaved edit');
  page.removeAllListeners('dialog');
  const kinds = [];
  page.on('dialog', (d) => { kinds.push(d.type()); d.dismiss(); });
  await page.evaluate(() => { document.body.click(); });   // a user gesture, which beforeunload needs
  await page.mouse.click(5, 5);
  await page.close({ runBeforeUnload: true });
  await expect.poll(() => kinds.length, { timeout: patient(5000) }).toBe(1);
  expect(kinds[0]).toBe('beforeunload');
});

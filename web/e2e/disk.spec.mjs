// Changes on disk (file_changed): the open file, clean, is read again; with
// unsaved edits the conflict (Reload / Keep mine) is shown, nothing lost.
import fs from 'node:fs';
import { test, expect, studio, waitFor, patient } from './fixtures.mjs';

const DISK = 'missions/tank/on_disk.coral';

async function openCopy(page) {
  fs.copyFileSync(page.studio.file('missions/tank/initialize.coral'), page.studio.file(DISK));
  await page.goto(page.studio.url);
  await page.locator(`#file-list li[data-path="${DISK}"]`).click();
  await waitFor(page, `s.path === '${DISK}' && s.net === 'initialize' && s.busy === 0`, 15000, 'the file open');
}

// Another program changes the file: a comment at its end.
function changeOnDisk(page, mark) {
  page.studio.write(DISK, `${page.studio.read(DISK)}\n// ${mark}\n`);
}

test('a file changed on disk while open without unsaved edits is read again, and the page says so', async ({ page }) => {
  await openCopy(page);
  changeOnDisk(page, 'changed_by_another_program');
  await waitFor(page, "/changed_by_another_program/.test(s.text) && !s.dirty && s.busy === 0", 10000, 'the file read again');
  expect(await studio(page, 's.paneText')).toMatch(/changed_by_another_program/);
  await expect(page.locator('#edit-msg')).toContainText('changed on disk: reloaded');
  await expect(page.locator('#conflict-box')).toBeHidden();
  // Our own save is no news: no reload, no conflict.
  expect(await page.evaluate(() => window.__studio.applyOp({ op: 'add_place', net: 'initialize', name: 'saved_here' }))).toBe(true);
  expect(await page.evaluate(() => window.__studio.save())).toBe(true);
  await expect(page.locator('#edit-msg')).toContainText('saved');
  // The watcher's next look: a change written after the save (the layout
  // file) is told, so any word about our save has come before it.
  page.studio.write(`${DISK}.layout.json`, '{}\n');
  await waitFor(page, `s.state.disk && s.state.disk.path === '${DISK}.layout.json'`, 10000, 'the watcher\'s next look');
  expect(await studio(page, '!s.state.conflict && !s.dirty')).toBe(true);
  expect(await studio(page, 's.text')).toMatch(/saved_here/);
});

test('a file changed on disk while it has unsaved edits: the conflict, Reload takes the file, Keep mine saves over it', async ({ page }) => {
  await openCopy(page);
  expect(await page.evaluate(() => window.__studio.applyOp({ op: 'add_place', net: 'initialize', name: 'unsaved_here' }))).toBe(true);
  await waitFor(page, 's.dirty && s.busy === 0', 5000, 'an unsaved edit');
  changeOnDisk(page, 'first_change');
  await waitFor(page, 's.state.conflict && s.state.conflict.theirs != null', 10000, 'the conflict shown');
  await expect(page.locator('#conflict-box')).toBeVisible();
  await expect(page.locator('#edit-msg')).toContainText('changed on disk while you have unsaved edits');
  await expect(page.locator('#conflict-diff')).toContainText('first_change');
  await expect(page.locator('#conflict-diff')).toContainText('unsaved_here');
  expect(await studio(page, 's.text')).toMatch(/unsaved_here/);   // nothing lost
  await page.locator('#btn-reload').click();
  await waitFor(page, '!s.dirty && s.busy === 0 && /first_change/.test(s.text) && !/unsaved_here/.test(s.text)', 10000, 'Reload took the file');
  await expect(page.locator('#conflict-box')).toBeHidden();
  // Again, and keep mine this time.
  expect(await page.evaluate(() => window.__studio.applyOp({ op: 'add_place', net: 'initialize', name: 'mine_kept' }))).toBe(true);
  changeOnDisk(page, 'second_change');
  await waitFor(page, 's.state.conflict && s.state.conflict.theirs != null', 10000, 'the conflict again');
  await page.locator('#btn-keep-mine').click();
  await waitFor(page, '!s.dirty && s.busy === 0 && !s.state.conflict', 10000, 'mine saved');
  const text = page.studio.read(DISK);
  expect(text).toMatch(/mine_kept/);
  expect(text).not.toMatch(/second_change/);
});

test('an imported file changed on disk: the lists are read again, the open file is left as it is', async ({ page }) => {
  await page.goto(page.studio.url);
  await page.locator('#file-list li[data-path="missions/tank/tank.coral"]').click();
  await waitFor(page, "s.path === 'missions/tank/tank.coral' && s.busy === 0 && cy.nodes().length > 0", 15000, 'tank open');
  // A file made after the list was read is not in it until the lists are read again.
  // (No watcher looks for new files: nothing is told, so nothing to wait for.)
  page.studio.write('missions/tank/made_later.coral', page.studio.read('missions/tank/initialize.coral'));
  await expect(page.locator('#file-list li[data-path="missions/tank/made_later.coral"]')).toHaveCount(0);
  const text = await studio(page, 's.text');
  const imp = 'missions/tank/initialize.coral';
  page.studio.write(imp, `${page.studio.read(imp)}\n// changed import\n`);
  await expect(page.locator('#file-list li[data-path="missions/tank/made_later.coral"]')).toHaveCount(1, { timeout: patient(10000) });
  expect(await studio(page, 's.text')).toBe(text);
  expect(await studio(page, "s.path")).toBe('missions/tank/tank.coral');
});

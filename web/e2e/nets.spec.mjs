// Readable nets: labels legible at fit, zoom buttons and wheel, a viewport
// per net, resizable panels, double-click into a phase, and a 5,000-transition net.
import { test, expect, studio, waitFor, openPage, nodePoint, figure } from './fixtures.mjs';

const kFont = 11;       // graph.js's node label size
const kReadable = 9;    // px: the smallest label the fit may show

test('labels stay readable at fit, in the mission net and in a phase net', async ({ page }) => {
  await openPage(page, 'missions/tank/tank.coral', 'tank');
  expect(kFont * (await studio(page, 'cy.zoom()'))).toBeGreaterThanOrEqual(kReadable);
  for (const net of ['dive_from_surface', 'submerge_to_depth']) {
    await page.locator(`#net-list li[data-net="${net}"]`).click();
    await waitFor(page, `s.net === '${net}' && cy.nodes().length > 5`, 5000, net);
    expect(kFont * (await studio(page, 'cy.zoom()'))).toBeGreaterThanOrEqual(kReadable);
    await page.locator('#btn-fit').click();
    expect(kFont * (await studio(page, 'cy.zoom()'))).toBeGreaterThanOrEqual(kReadable);
  }
  // Left to right: the mission's phases in order along x.
  await page.locator('#net-list li[data-net="tank"]').click();
  await waitFor(page, "s.net === 'tank'", 5000);
  const xs = await studio(page, "['t:phase1', 't:phase2', 't:phase3', 't:phase4'].map((id) => cy.getElementById(id).position().x)");
  for (let i = 1; i < xs.length; i++) expect(xs[i]).toBeGreaterThan(xs[i - 1]);
});

test('zoom buttons and the wheel zoom a useful step', async ({ page }) => {
  await openPage(page);
  const z0 = await studio(page, 'cy.zoom()');
  await page.locator('#btn-zoom-in').click();
  const z1 = await studio(page, 'cy.zoom()');
  expect(z1 / z0).toBeCloseTo(1.25, 2);
  await page.locator('#btn-zoom-out').click();
  expect(await studio(page, 'cy.zoom()')).toBeCloseTo(z0, 3);
  const box = await page.locator('#cy').boundingBox();
  await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
  await page.mouse.wheel(0, -100);   // one notch up
  await waitFor(page, `cy.zoom() > ${z0 * 1.05}`, 3000, 'the wheel to zoom in');
  const z2 = await studio(page, 'cy.zoom()');
  expect(z2 / z0).toBeGreaterThan(1.1);
  expect(z2 / z0).toBeLessThan(1.3);
});

test('each net keeps its viewport', async ({ page }) => {
  await openPage(page);
  await page.locator('#btn-zoom-in').click();
  await page.locator('#btn-zoom-in').click();
  await page.evaluate(() => { window.__cy.panBy({ x: -120, y: 40 }); });
  const vp = await studio(page, '({ zoom: cy.zoom(), pan: cy.pan() })');
  await page.locator('#net-list li[data-net="initialize"]').click();
  await waitFor(page, "s.net === 'initialize'", 5000);
  await page.locator('#net-list li[data-net="tank"]').click();
  await waitFor(page, "s.net === 'tank'", 5000);
  const back = await studio(page, '({ zoom: cy.zoom(), pan: cy.pan() })');
  expect(back.zoom).toBeCloseTo(vp.zoom, 4);
  expect(back.pan.x).toBeCloseTo(vp.pan.x, 1);
  expect(back.pan.y).toBeCloseTo(vp.pan.y, 1);
});

test('panels resize by their splitters', async ({ page }) => {
  await openPage(page);
  for (const [panel, sel, dx, sign] of [['text', '#text-pane', -120, 1], ['left', '#left', 80, 1], ['right', '#right', -60, 1]]) {
    const w0 = (await page.locator(sel).boundingBox()).width;
    const sp = await page.locator(`.splitter[data-panel="${panel}"]`).boundingBox();
    await page.mouse.move(sp.x + sp.width / 2, sp.y + sp.height / 2);
    await page.mouse.down();
    await page.mouse.move(sp.x + sp.width / 2 + dx, sp.y + sp.height / 2, { steps: 4 });
    await page.mouse.up();
    const w1 = (await page.locator(sel).boundingBox()).width;
    expect(Math.abs(w1 - w0 - sign * Math.abs(dx))).toBeLessThan(3);
  }
  // The canvas follows its box.
  await waitFor(page, "Math.abs(cy.width() - document.querySelector('#cy').clientWidth) < 2", 3000, 'the canvas resized');
});

test('double-click a PHASE transition opens the phase\'s net', async ({ page }) => {
  await openPage(page);
  await page.evaluate(() => { const cy = window.__cy; cy.center(cy.getElementById('t:phase2')); });
  const p = await nodePoint(page, 't:phase2');
  await page.mouse.dblclick(p.x, p.y);
  await waitFor(page, "s.net === 'dive_from_surface' && cy.getElementById('t:check_depth').nonempty()", 5000, 'the phase net');
  await expect(page.locator('#net-list li.active')).toContainText('dive_from_surface');
});

function chain(n) {
  const lines = [`// a generated chain of ${n} transitions`, 'net chain {', '  place p0 = 1;'];
  for (let i = 1; i < n; i++) lines.push(`  place p${i};`);
  lines.push('  exit done;');
  for (let i = 1; i < n; i++) lines.push(`  transition t${i} { wait { p${i - 1} } signal { p${i} } }`);
  lines.push(`  transition t${n} { wait { p${n - 1} } signal { done } }`, '}');
  return lines.join('\n') + '\n';
}

test.describe('a 5,000-transition net', () => {
  test.use({ files: { 'chain.coral': chain(5000) } });

  test('opens, is readable, and takes an edit', async ({ page }) => {
    await page.goto(page.studio.url);
    await waitFor(page, 'document.querySelector(\'#file-list li[data-path="chain.coral"]\')', 10000, 'the file list');
    const t0 = await page.evaluate(() => performance.now());
    await page.locator('#file-list li[data-path="chain.coral"]').click();
    // Shown in parts: the page holds the 10,001 nodes, cytoscape the ones near the view.
    await waitFor(page, "s.path === 'chain.coral' && s.busy === 0 && s.drawn.nodes === 10001 && s.drawn.inParts && cy.nodes().length > 0", 60000, 'the chain drawn');
    const t1 = await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => r(performance.now()))));
    figure('5,000-transition net open (click to first frame drawn)', `${Math.round(t1 - t0)} ms`);
    expect(kFont * (await studio(page, 'cy.zoom()'))).toBeGreaterThanOrEqual(kReadable);
    // Laid out left to right: the chain's start in view, its end far right.
    const ends = await studio(page, "['p:p0', 'p:p4999', 'p:done'].map((id) => s.positions.chain[id].x)");
    expect(ends[0]).toBeLessThan(ends[1]);
    expect(ends[1]).toBeLessThan(ends[2]);
    // The part in view is drawn, the far end is not; it comes in when the view gets there.
    expect(await studio(page, "cy.getElementById('p:p0').nonempty() && cy.getElementById('p:p4999').empty() && cy.nodes().length < 1000")).toBe(true);
    await page.evaluate(() => { const cy = window.__cy; cy.pan({ x: cy.width() / 2 - window.__studio.positions.chain['p:p4999'].x * cy.zoom(), y: cy.pan().y }); });
    await waitFor(page, "cy.getElementById('p:p4999').nonempty() && cy.getElementById('t:t5000').nonempty() && cy.getElementById('p:p0').empty()", 10000, 'the far end shown');
    expect(await studio(page, "cy.getElementById('p:p4999').position().x")).toBe(ends[1]);
    await page.locator('#btn-fit').click();
    // An edit round trip on this net.
    const e0 = await page.evaluate(() => performance.now());
    expect(await page.evaluate(() => window.__studio.applyOp({ op: 'add_place', net: 'chain', name: 'extra' }))).toBe(true);
    await waitFor(page, "cy.getElementById('p:extra').nonempty() && s.busy === 0", 30000, 'the new place');
    const e1 = await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => r(performance.now()))));
    figure('5,000-transition net: edit round trip (add_place, to first frame)', `${Math.round(e1 - e0)} ms`);
    // Still interactive: a wheel notch zooms.
    const z0 = await studio(page, 'cy.zoom()');
    const box = await page.locator('#cy').boundingBox();
    await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
    await page.mouse.wheel(0, 100);
    await waitFor(page, `cy.zoom() < ${z0 * 0.95}`, 5000, 'the wheel to zoom out');
  });
});

// A hostile repository and hostile pages (issue 17, point 1): links planted
// in the folder are not followed, imports from outside show none of the
// file, a scenario is a name and never a path, another web page cannot
// start a run, and a request for another Host (DNS rebinding) is refused.
// Each test also does the allowed thing, so a check that passed for the
// wrong reason would show.
import fs from 'node:fs';
import http from 'node:http';
import os from 'node:os';
import path from 'node:path';
import { test, expect, studio, waitFor, openPage, figure, TANK } from './fixtures.mjs';

const VICTIM_TEXT = '// outside the studio\'s folder: never to be read or written\nnet victim { place p = 1; }\n';

// A folder outside the studio's, removed after the test.
function outside() {
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'strata-e2e-outside-'));
  fs.writeFileSync(path.join(dir, 'victim.coral'), VICTIM_TEXT);
  fs.writeFileSync(path.join(dir, 'victim2'), 'untouched\n');
  return dir;
}

// GET with a Host header of our choosing (a browser cannot send one).
function getWithHost(url, route, host) {
  const u = new URL(url);
  return new Promise((resolve, reject) => {
    const req = http.request({ hostname: u.hostname, port: u.port, path: route, headers: { Host: host } }, (res) => {
      let body = '';
      res.on('data', (c) => { body += c; });
      res.on('end', () => resolve({ status: res.statusCode, body }));
    });
    req.on('error', reject);
    req.setTimeout(10000, () => req.destroy(new Error('no answer in 10 s')));
    req.end();
  });
}

// What the page's own fetch gets (the browser adds the page's Origin).
const pageFetch = (page, url, init) => page.evaluate(async ([u, i]) => {
  const r = await fetch(u, i);
  return { status: r.status, body: await r.text() };
}, [url, init]);

test('links planted in the folder are not followed: a linked mission is neither listed, read nor written, and a save writes the real file', async ({ page }) => {
  const out = outside();
  try {
    const tank = page.studio.file('missions/tank');
    fs.symlinkSync(path.join(out, 'victim.coral'), path.join(tank, 'linked.coral'));
    // The old fixed temporary name, planted as a link: a save must not follow it.
    fs.symlinkSync(path.join(out, 'victim2'), path.join(tank, 'initialize.coral.strata-tmp'));
    await openPage(page, 'missions/tank/initialize.coral', 'initialize');
    expect(await studio(page, 's.state.files')).not.toContain('missions/tank/linked.coral');
    const read = await pageFetch(page, '/api/mission?path=missions/tank/linked.coral');
    expect(read.status).toBe(403);
    expect(read.body).not.toContain('victim');
    const write = await pageFetch(page, '/api/file?path=missions/tank/linked.coral', { method: 'PUT', headers: { 'Content-Type': 'text/plain' }, body: 'net x { place q = 1; }\n' });
    expect(write.status).toBe(403);
    // The allowed thing: an edit saved from the page lands in the real file.
    expect(await page.evaluate(() => window.__studio.applyOp({ op: 'add_place', net: 'initialize', name: 'saved_through_the_sandbox' }))).toBe(true);
    await waitFor(page, 's.dirty && s.busy === 0', 5000, 'the edit');
    await page.locator('#btn-save').click();
    await waitFor(page, '!s.dirty && s.busy === 0', 10000, 'the save');
    expect(page.studio.read('missions/tank/initialize.coral')).toContain('saved_through_the_sandbox');
    expect(fs.lstatSync(page.studio.file('missions/tank/initialize.coral')).isSymbolicLink()).toBe(false);
    expect(fs.readFileSync(path.join(out, 'victim.coral'), 'utf8')).toBe(VICTIM_TEXT);
    expect(fs.readFileSync(path.join(out, 'victim2'), 'utf8')).toBe('untouched\n');
  } finally {
    fs.rmSync(out, { recursive: true, force: true });
  }
});

test('imports from outside the folder are refused in the page, showing none of the file', async ({ page }) => {
  const out = outside();
  try {
    const rel = path.relative(page.studio.file('missions/tank'), path.join(out, 'victim.coral'));
    page.studio.write('missions/tank/evil.coral',
      `import "/etc/passwd";\nimport "${rel}";\nimport "initialize.coral";\nmission evil {\n  place begin = 1;\n  exit done;\n  transition t { wait { begin } action { PHASE(initialize) => { done } } }\n}\n`);
    await page.goto(page.studio.url);
    await page.locator('#file-list li[data-path="missions/tank/evil.coral"]').click();
    await waitFor(page, "s.path === 'missions/tank/evil.coral' && s.busy === 0 && s.diagnostics.length > 0", 15000, 'the diagnostics');
    const diags = await studio(page, 's.diagnostics.map((d) => d.message).join("\\n")');
    expect(diags).toMatch(/passwd/);                 // the import is named ...
    expect(diags).toMatch(/victim\.coral/);
    const shown = await page.locator('body').innerText();
    for (const secret of ['root:', 'daemon:', '/bin/bash', '/usr/sbin/nologin', 'never to be read', 'place p']) {
      expect(diags, `a diagnostic quotes ${secret}`).not.toContain(secret);   // ... none of its text
      expect(shown, `the page shows ${secret}`).not.toContain(secret);
    }
  } finally {
    fs.rmSync(out, { recursive: true, force: true });
  }
});

test('a scenario is a name from the mission\'s scenarios/, never a path', async ({ page }) => {
  await openPage(page, TANK);
  const listed = await studio(page, 's.scenarios');
  expect(listed).toContain('nominal');
  for (const name of listed) expect(name).toMatch(/^[A-Za-z0-9_-]+$/);
  for (const scenario of ['../../../../../../etc/passwd', '/etc/passwd', 'scenarios/../../../etc/hostname', '..']) {
    const r = await pageFetch(page, '/api/run', { method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify({ path: TANK, scenario, speed: 10 }) });
    expect(r.status, scenario).toBeGreaterThanOrEqual(400);
    expect(r.status, scenario).toBeLessThan(500);
    expect(r.body, scenario).not.toMatch(/root:|daemon:|nologin/);
    expect(JSON.parse(r.body).error, scenario).toBeTruthy();
  }
  expect(fs.existsSync(page.studio.file('missions/tank/runs')), 'no run was started').toBe(false);
});

test('another web page cannot start a run (a cross-origin text/plain POST needs no preflight): 403, and the studio\'s own page can', async ({ page, browser }) => {
  const url = page.studio.url;
  // The other page, served for real from another loopback port (a page
  // Playwright made up would count as public, and Chromium's own local
  // network checks would stop the request before the studio saw it).
  const server = http.createServer((req, res) => { res.writeHead(200, { 'Content-Type': 'text/html' }); res.end('<!doctype html><title>evil</title><p>hello</p>'); });
  await new Promise((r) => server.listen(0, '127.0.0.1', r));
  const evil = await browser.newPage();
  try {
    await evil.goto(`http://127.0.0.1:${server.address().port}/evil.html`);
    // no-cors: the browser sends it, with Origin http://127.0.0.1:1, and hides the answer.
    const sent = await evil.evaluate(async ([u, tank]) => {
      const body = JSON.stringify({ path: tank, scenario: 'nominal', speed: 10 });
      await fetch(`${u}/api/run`, { method: 'POST', mode: 'no-cors', headers: { 'Content-Type': 'text/plain' }, body });
      // A PUT needs a CORS preflight, which the studio does not answer: the browser refuses it.
      const put = await fetch(`${u}/api/file?path=${encodeURIComponent(tank)}`, { method: 'PUT', headers: { 'Content-Type': 'text/plain' }, body: 'owned' })
        .then(() => 'sent', () => 'refused by the browser');
      return put;
    }, [url, TANK]);
    // The no-cors fetch was awaited: the studio has answered it. No run
    // started (the own run below is the only log), and the file is intact.
    expect(sent).toBe('refused by the browser');
    expect(page.studio.read(TANK)).not.toBe('owned');
  } finally {
    await evil.close();
    await new Promise((r) => server.close(r));
  }
  // The studio's own page: the same request starts the run.
  await openPage(page, TANK);
  const own = await pageFetch(page, '/api/run', { method: 'POST', headers: { 'Content-Type': 'text/plain' }, body: JSON.stringify({ path: TANK, scenario: 'nominal', speed: 10 }) });
  expect(own.status, own.body).toBe(202);
  await waitFor(page, 's.runEnded != null', 60000, 'the run\'s end');
  // One log: the page's run. A run started by the other page would have
  // left a second (or made this one 409, had it still been going).
  expect(fs.readdirSync(page.studio.file('missions/tank/runs')).filter((f) => f.endsWith('.jsonl'))).toHaveLength(1);
});

test('a request naming another Host (DNS rebinding) is refused; the studio\'s own addresses are served', async ({ page }) => {
  const port = new URL(page.studio.url).port;
  for (const host of [`evil.example:${port}`, 'evil.example', `127.0.0.2:${port}`]) {
    const r = await getWithHost(page.studio.url, '/api/files', host);
    expect(r.status, host).toBe(403);
    expect(JSON.parse(r.body).error, host).toMatch(/not this studio/);
  }
  for (const host of [`127.0.0.1:${port}`, `localhost:${port}`]) {
    const r = await getWithHost(page.studio.url, '/api/files', host);
    expect(r.status, host).toBe(200);
  }
});

// Issue 39: a page on another loopback port holding 16 iframes of
// /api/events used up the browser's six connections to the studio, and a
// studio tab in that browser never loaded its file list.
test('another page\'s iframes of the event stream are refused, and a studio tab in that browser loads', async ({ page, browser }) => {
  const url = page.studio.url;
  let frames = '';
  for (let i = 0; i < 16; i++) frames += `<iframe src="${url}/api/events"></iframe>`;
  const server = http.createServer((req, res) => { res.writeHead(200, { 'Content-Type': 'text/html' }); res.end(`<!doctype html><title>evil</title>${frames}`); });
  await new Promise((r) => server.listen(0, '127.0.0.1', r));
  const context = page.context();
  const evil = await context.newPage();
  try {
    // Every iframe's answer: the studio's 403, not a stream that never ends.
    const refused = [];
    evil.on('response', (r) => { if (r.url().endsWith('/api/events')) refused.push(r.status()); });
    await evil.goto(`http://127.0.0.1:${server.address().port}/evil.html`, { waitUntil: 'load' });
    expect(refused).toHaveLength(16);
    expect(new Set(refused)).toEqual(new Set([403]));
    // The studio's own tab, in the same browser, with the other page open.
    await page.goto(url);
    await waitFor(page, 's.state.files.length > 0', 30000, 'the file list');
    await expect(page.locator(`#file-list li[data-path="${TANK}"]`)).toBeVisible();
  } finally {
    await evil.close();
    await new Promise((r) => server.close(r));
  }
});

// GET held open, or answered: resolves with the status once the headers come.
function openGet(url, route) {
  const u = new URL(url);
  return new Promise((resolve) => {
    const req = http.get({ hostname: u.hostname, port: u.port, path: route, agent: false }, (res) => {
      resolve({ status: res.statusCode, req, res });
      if (res.statusCode !== 200 || route !== '/api/events') res.resume();
    });
    req.on('error', (e) => resolve({ status: 0, error: e.message, req }));
    req.setTimeout(60000, () => req.destroy(new Error('no answer in 60 s')));
  });
}

// The studio's peak memory (VmHWM), in MB.
function peakMb(pid) {
  const m = /VmHWM:\s+(\d+) kB/.exec(fs.readFileSync(`/proc/${pid}/status`, 'utf8'));
  return m ? Number(m[1]) / 1024 : NaN;
}

// Issue 39's target: 200 event streams asked for and held, 1,000 GETs at
// once from a local process; a studio tab still loads its file list, and
// the server's memory stays under 200 MB (a sanitizer's build is bigger:
// there it is only reported).
test('under load (200 streams held, 1,000 GETs at once) a tab loads its file list and the server stays small', async ({ page }) => {
  const url = page.studio.url;
  const streams = await Promise.all(Array.from({ length: 200 }, () => openGet(url, '/api/events')));
  const held = streams.filter((s) => s.status === 200).length;
  expect(held).toBe(16);  // --max-streams
  expect(streams.filter((s) => s.status === 503)).toHaveLength(184);
  try {
    const alone = Date.now();
    expect((await openGet(url, '/api/files')).status).toBe(200);
    figure('load: GET /api/files with the streams at their cap (ms)', Date.now() - alone);
    const started = Date.now();
    const burst = Promise.all(Array.from({ length: 1000 }, () => openGet(url, '/api/files')));
    await page.goto(url);
    await waitFor(page, 's.state.files.length > 0', 60000, 'the file list, under load');
    const tab = Date.now() - started;
    const answers = await burst;
    const ok = answers.filter((a) => a.status === 200).length;
    figure('load: file list in the tab (ms, from the burst)', tab);
    figure('load: the burst\'s GETs answered 200', `${ok} of 1000, in ${Date.now() - started} ms`);
    expect(ok).toBe(1000);
    const mb = peakMb(page.studio.pid);
    figure('load: the studio\'s peak memory (MB)', mb.toFixed(1));
    if (process.env.STRATA_SANITIZED !== '1') expect(mb).toBeLessThan(200);
  } finally {
    for (const s of streams) s.req.destroy();
  }
});

// The tests' browser reaches nothing but loopback (playwright.config.mjs's
// flags; fixtures.mjs's promise): a page's request to any other address or
// name is refused at once, by the browser, and the studio is still reached.
import { test, expect, figure, patient } from './fixtures.mjs';

test('a request from the page to anything but 127.0.0.1 is refused fast; the studio is reached', async ({ page }) => {
  const failed = new Map();
  page.on('requestfailed', (r) => failed.set(r.url(), r.failure().errorText));
  await page.goto(page.studio.url);
  const away = ['http://10.255.255.1/', 'http://example.com/', 'https://example.com/', 'http://[2001:db8::1]/', 'http://localhost/'];
  const got = await page.evaluate(async ({ urls, bound }) => {
    const out = {};
    for (const u of [...urls, '/api/files']) {
      const t = performance.now();
      // (no-cors: an answer from another origin would still resolve it)
      const r = await Promise.race([
        fetch(u, { mode: 'no-cors', cache: 'no-store' }).then(() => 'answered', () => 'refused'),
        new Promise((res) => setTimeout(() => res('still waiting'), bound)),
      ]);
      out[u] = { r, ms: Math.round(performance.now() - t) };
    }
    return out;
  }, { urls: away, bound: patient(3000) });
  for (const u of away) {
    expect(got[u].r, `${u}: ${failed.get(u) || ''}`).toBe('refused');
    // Refused by the flags (no name, or the dead proxy), not by chance nor
    // by a timeout: how fast is a figure, not an assertion (a busy machine
    // is slower; the limit above only ends a request left waiting).
    expect(failed.get(u), u).toMatch(/ERR_NAME_NOT_RESOLVED|ERR_PROXY_CONNECTION_FAILED/);
  }
  figure('loopback: slowest refusal (ms)', Math.max(...away.map((u) => got[u].ms)));
  expect(got['/api/files'].r).toBe('answered');
});

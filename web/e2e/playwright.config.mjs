// The studio's browser tests (@playwright/test) on Debian's chromium; never
// a downloaded browser. Each test starts its own `strata studio` on a copy
// of missions/ (fixtures.mjs), so tests are independent and run in any order.
//
//   cd web && STRATA=../build/dev/strata npx playwright test -c e2e/playwright.config.mjs
//
// Environment: STRATA (the binary; default build/dev/strata), STRATA_WEB_ROOT
// (serve a page from disk instead of the embedded one), STRATA_E2E_OUT (the
// screenshots, figures and Playwright's output), STRATA_E2E_WORKERS (1 or 2),
// STRATA_E2E_PATIENCE (how many times the written limits to wait: patience.mjs).
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { defineConfig } from '@playwright/test';
import { patient } from './patience.mjs';

const here = path.dirname(fileURLToPath(import.meta.url));
const out = path.resolve(process.env.STRATA_E2E_OUT || path.join(here, '..', '..', 'build', 'dev', 'tests', 'e2e-artifacts'));

export default defineConfig({
  testDir: here,
  testMatch: /.*\.spec\.mjs$/,
  outputDir: path.join(out, 'results'),
  workers: Math.max(1, Math.min(2, Number(process.env.STRATA_E2E_WORKERS) || 2)),
  fullyParallel: true,
  retries: 0,
  timeout: patient(75_000),
  globalTimeout: 900_000,
  expect: { timeout: patient(15_000) },
  reporter: [['list']],
  use: {
    headless: true,
    viewport: { width: 1500, height: 950 },
    actionTimeout: patient(15_000),
    navigationTimeout: patient(15_000),   // an ASan strata on a loaded machine
    launchOptions: {
      executablePath: process.env.STRATA_CHROMIUM || '/usr/bin/chromium',
      args: ['--no-sandbox', '--disable-gpu', '--disable-background-networking', '--disable-component-update', '--disable-sync', '--no-first-run',
        // Loopback only, refused by the browser itself (loopback.spec.mjs):
        // every name and address but 127.0.0.1 resolves to nothing, and
        // whatever is not loopback goes to a proxy whose name resolves to
        // nothing (Chromium never sends loopback to a proxy). Playwright's
        // request routing did this before, at 30-300 ms a request under load.
        '--host-resolver-rules=MAP * ~NOTFOUND , EXCLUDE 127.0.0.1', '--proxy-server=http://no-proxy.invalid:9'],
    },
  },
});

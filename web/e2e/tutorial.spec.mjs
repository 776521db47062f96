// The tutorials' studio step, followed as written (issue 40): the document's
// files and commands run first (tests/doc_run.py, as the doc tests run them),
// then each `$ strata studio ...` line of a ```console block runs as written
// in the same folder, and the test does what the text around it says: open
// the address it prints, pick the mission in the file list, press Run, and
// see the run end as the document says it does.
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { spawn, spawnSync } from 'node:child_process';
import { test, expect } from '@playwright/test';
import { repo, STRATA, waitFor, studio, patient } from './fixtures.mjs';

// The studio steps of a document: the command, and the address pattern it
// shows (its `...` matching what varies).
function studioSteps(doc) {
  const lines = fs.readFileSync(path.join(repo, 'docs', doc), 'utf8').split('\n');
  const steps = [];
  let inConsole = false;
  for (let i = 0; i < lines.length; ++i) {
    if (lines[i].startsWith('```')) { inConsole = !inConsole && lines[i].startsWith('```console'); continue; }
    if (!inConsole || !lines[i].startsWith('$ strata studio ')) continue;
    const shown = (lines[i + 1] || '').trim();
    const rx = new RegExp(`^${shown.split('...').map((p) => p.replace(/[.*+?^${}()|[\]\\]/g, '\\$&')).join('.*')}$`);
    steps.push({ line: i + 1, command: lines[i].slice(2), address: rx });
  }
  return steps;
}

// Runs the document's files and commands in a folder of its own.
function followDocument(doc) {
  const work = fs.mkdtempSync(path.join(os.tmpdir(), 'strata-tutorial-'));
  const r = spawnSync('python3', [path.join(repo, 'tests', 'doc_run.py'), path.join(repo, 'docs', doc),
    '--strata', STRATA, '--source', repo, '--work', work], { encoding: 'utf8' });
  expect(r.status, `${doc} as written:\n${r.stdout}${r.stderr}`).toBe(0);
  return work;
}

// Starts the step's command as the reader would type it, in the folder;
// resolves with the process and the first line it prints.
async function startAsWritten(command, cwd) {
  const env = { ...process.env, PATH: `${path.dirname(STRATA)}${path.delimiter}${process.env.PATH}`, HOME: path.join(cwd, 'home') };
  for (const v of ['XDG_CONFIG_HOME', 'XDG_STATE_HOME', 'XDG_DATA_HOME', 'STRATA_CONFIG', 'STRATA_LOG_DIR']) delete env[v];
  // exec: the studio is the shell's process, so its pid stops it.
  const proc = spawn('bash', ['-c', `exec ${command}`], { cwd, env, stdio: ['ignore', 'pipe', 'pipe'] });
  let err = '';
  proc.stderr.on('data', (c) => { err += c; if (err.length > 20000) err = err.slice(-10000); });
  const first = await new Promise((resolve, reject) => {
    let buf = '';
    const t = setTimeout(() => reject(new Error(`\`${command}\` printed no line in ${patient(30)} s; stderr: ${err.slice(-500)}`)),
      patient(30000));
    proc.stdout.on('data', (c) => {
      buf += c;
      if (!buf.includes('\n')) return;
      clearTimeout(t);
      resolve(buf.split('\n')[0].trim());
    });
    proc.once('exit', (code) => { clearTimeout(t); reject(new Error(`\`${command}\` exited ${code}: ${err.slice(-500)}`)); });
  });
  return { proc, first, stderr: () => err };
}

async function stop(proc) {
  if (proc.exitCode !== null || proc.signalCode !== null) return;
  const gone = new Promise((r) => proc.once('exit', r));
  process.kill(proc.pid, 'SIGTERM');
  const t = setTimeout(() => { try { process.kill(proc.pid, 'SIGKILL'); } catch { /* gone */ } }, 5000);
  await gone;
  clearTimeout(t);
}

// Each tutorial's studio step: the mission it opens, and what the text
// says to set before Run.
const tutorials = [
  { doc: 'tutorial-first-mission.md', command: 'strata studio first', mission: 'first.coral', speed: null, map: false },
  { doc: 'tutorial-first-survey.md', command: 'strata studio out_and_back', mission: 'out_and_back.coral', speed: '100', map: true },
];

for (const t of tutorials) {
  test(`${t.doc}, studio step included, runs as written`, async ({ page }) => {
    const steps = studioSteps(t.doc);
    expect(steps.map((s) => s.command)).toEqual([t.command]);
    const work = followDocument(t.doc);
    const errors = [];
    page.on('pageerror', (e) => errors.push(e.message));
    const s = await startAsWritten(steps[0].command, work);
    try {
      expect(s.first, `${t.doc}:${steps[0].line}: the address printed`).toMatch(steps[0].address);
      // "Open the address, pick MISSION in the file list, (set the speed) and press Run."
      await page.goto(s.first);
      await page.locator(`#file-list li[data-path="${t.mission}"]`).click();
      await waitFor(page, `s.path === '${t.mission}' && s.busy === 0 && cy.nodes().length > 0`, 30000, `${t.mission} drawn`);
      expect(await studio(page, 's.lastError || null'), 'no error opening the mission').toBeNull();
      if (t.speed) await page.locator('#run-speed').fill(t.speed);
      await page.locator('#btn-run').click();
      await waitFor(page, "s.runStatus !== 'idle'", 15000, 'the run to start');
      await waitFor(page, "s.runStatus !== 'running' && s.runEnded", 120000, 'the run to end');
      const ended = await studio(page, '({ status: s.runStatus, outcome: s.runEnded.outcome, exit: s.runEnded.exit })');
      // "... and the Run panel ends with `completed (exit closed)`."
      expect(ended).toMatchObject({ status: 'completed', outcome: 'completed', exit: 'closed' });
      await expect(page.locator('#run-outcome')).toContainText('completed (exit closed)');
      // The survey's text: "The map draws the track".
      expect(await studio(page, 's.map.shown')).toBe(t.map);
    } finally {
      await page.context().close();   // before the studio stops (fixtures.mjs: keep-alive)
      await stop(s.proc);
      fs.rmSync(work, { recursive: true, force: true });
    }
    expect(errors, 'uncaught errors in the page').toEqual([]);
  });
}

// A replay of a run made with --answers: the scripted answers in its log
// reach the replay's log pane, marked as scripted.
//   node --test web/test/
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { emptyRun, applyEvent, scriptedText } from '../src/runstate.js';
import { reduce, initialState } from '../src/store.js';
import { eventOf } from '../src/effects.js';

// As GET /api/replay gives them (src/studio/replay.cpp).
const wire = [
  { event: 'run_start', data: { run: 1 } },
  { event: 'report', data: { text: 'starting', t: 0.2 } },
  { event: 'scripted_answer', data: { answer_index: 0, step: 3, net: 'dive_from_surface', transition: 'check_filter', action: 'ask', primitive: 'filter_on', vehicle: 0, answer: 1, t: 1.5 } },
  { event: 'scripted_answer', data: { answer_index: 1, step: 5, net: '', transition: '', action: 'exec', primitive: 'submerge', vehicle: 1, answer: 1, t: 2 } },
  { event: 'scripted_phase', data: { answer_index: 2, step: 6, net: 'tank', transition: 'dive', phase: 'dive_from_surface', exit: 'abort', t: 2.5 } },
  { event: 'answers_diverged', data: { reason: 'exec x was called', used: 3, t: 3 } },
  { event: 'run_end', data: { outcome: 'failed', t: 4 } },
];

test('scripted answers are lines of the log pane, marked scripted, in time order with the reports', () => {
  const rs = emptyRun();
  for (const e of wire) applyEvent(rs, ...eventOf(e));
  assert.equal(rs.events, wire.length - 1, 'every event after run_start (which starts the count) counted: none ignored');
  assert.deepEqual(rs.reports.map((r) => [r.t, !!r.scripted]), [[0.2, false], [1.5, true], [2, true], [2.5, true], [3, true]]);
  assert.equal(rs.reports[1].text, 'ASK filter_on answered 1; the vehicle said 0 (dive_from_surface/check_filter, step 3)');
  assert.equal(rs.reports[2].text, 'EXEC submerge answered 1, as the vehicle did (step 5)');
  assert.equal(rs.reports[3].text, 'phase dive_from_surface ended at abort, as scripted (tank/dive, step 6)');
  assert.equal(rs.reports[4].text, 'the run left the script after 3 answers: exec x was called');
});

test('a replay opened on such a log shows them up to its position only', () => {
  const events = wire.map(eventOf);
  let s = reduce(initialState(), { type: 'replay/opened', path: 'r.jsonl', events });
  assert.equal(s.rs.reports.filter((r) => r.scripted).length, 4);
  s = reduce(s, { type: 'replay/seek', pos: 3 });
  assert.deepEqual(s.rs.reports.map((r) => r.text), ['starting', scriptedText('scripted_answer', events[2][1])]);
  assert.equal(s.rs.reports[1].scripted, true);
});

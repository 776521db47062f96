// The map panel's geometry and data (issue 20): the track from the
// telemetry's x and y, live and in a replay; none for a tank run.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { mapFrame, scaleBar, kMinSpan_m } from '../src/map.js';
import { emptyRun, applyEvent } from '../src/runstate.js';
import { mapData, reduce, initialState } from '../src/store.js';

test('mapFrame: one scale for both axes, north up, the box centred', () => {
  // A 250 x 60 m lawnmower in a 300 x 200 canvas with 10 px of margin:
  // x limits the scale (280 / 250 px per metre).
  const f = mapFrame([[0, 0, 0], [1, 250, 0], [2, 250, 60], [3, 0, 60]], 300, 200, 10);
  assert.equal(f.k, 280 / 250);
  assert.deepEqual(f.toPx(0, 0), [10, 100 + 30 * f.k]);
  assert.deepEqual(f.toPx(250, 60), [290, 100 - 30 * f.k]);
  const [, yNorth] = f.toPx(0, 60);
  const [, ySouth] = f.toPx(0, 0);
  assert.ok(yNorth < ySouth, 'north is up');
  assert.deepEqual(f.bounds, { x0: 0, x1: 250, y0: 0, y1: 60 });
});

test('mapFrame: a vehicle at rest is shown in the least span, not magnified; no points, no frame', () => {
  const f = mapFrame([[0, 5, 5], [1, 5, 5]], 120, 120, 10);
  assert.equal(f.k, 100 / kMinSpan_m);
  assert.deepEqual(f.toPx(5, 5), [60, 60]);
  assert.equal(mapFrame([], 100, 100), null);
});

test('scaleBar: 1, 2 or 5 times a power of ten, no longer than asked', () => {
  assert.equal(scaleBar(73), 50);
  assert.equal(scaleBar(20), 20);
  assert.equal(scaleBar(1.9), 1);
  assert.equal(scaleBar(0.3), 0.2);
  assert.equal(scaleBar(0), 0);
});

test('the run keeps a track from the samples that have x and y, and none for a tank run', () => {
  const rs = emptyRun();
  applyEvent(rs, 'telemetry', { t: 1, depth: 0.5, setpoint: null });
  assert.deepEqual(rs.track, []);
  applyEvent(rs, 'telemetry', { t: 2, depth: 0.5, setpoint: null, x: 10, y: -4 });
  applyEvent(rs, 'telemetry', { t: 3, depth: 0.6, setpoint: 1, x: 11, y: null });
  assert.deepEqual(rs.track, [[2, 10, -4]]);
  assert.equal(rs.telemetry.length, 3, 'the depth chart still gets every sample');
  // A snapshot's rows carry x and y after the setpoint.
  applyEvent(rs, 'snapshot', { run: 1, telemetry: [[1, 0.1, null], [2, 0.2, null, 3.5, 7], [3, 0.3, 1, 4, 8]] });
  assert.deepEqual(rs.track, [[2, 3.5, 7], [3, 4, 8]]);
  assert.equal(rs.telemetry.length, 3);
});

test('mapData: live, the latest point; in a replay, the whole track and the point at the replay position', () => {
  let s = initialState();
  assert.deepEqual(mapData(s), { track: [], vehicle: null });
  s = reduce(s, { type: 'run/event', name: 'run_start', data: { run: 1, mission: 'survey.coral' } });
  s = reduce(s, { type: 'run/event', name: 'telemetry', data: { t: 1, depth: 0, x: 0, y: 0 } });
  s = reduce(s, { type: 'run/event', name: 'telemetry', data: { t: 2, depth: 0, x: 1, y: 2 } });
  assert.deepEqual(mapData(s), { track: [[1, 0, 0], [2, 1, 2]], vehicle: [2, 1, 2] });

  const events = [['run_start', { run: 1 }], ['telemetry', { t: 1, depth: 0, x: 0, y: 0 }],
    ['telemetry', { t: 2, depth: 1, x: 5, y: 0 }], ['telemetry', { t: 3, depth: 1, x: 10, y: 0 }]];
  s = reduce(s, { type: 'replay/opened', path: 'runs/a.jsonl', events });
  assert.deepEqual(mapData(s).vehicle, [3, 10, 0]);
  s = reduce(s, { type: 'replay/seek', pos: 2 });
  const m = mapData(s);
  assert.equal(m.track.length, 3, 'the whole track of the log');
  assert.deepEqual(m.vehicle, [1, 0, 0], 'where the vehicle was at the replay position');
  s = reduce(s, { type: 'replay/seek', pos: 3 });
  assert.deepEqual(mapData(s).vehicle, [2, 5, 0]);
  s = reduce(s, { type: 'replay/seek', pos: 0 });
  assert.equal(mapData(s).vehicle, null);
  assert.equal(mapData(s).track.length, 3);
});

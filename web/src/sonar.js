// The newest sonar scan beside the net (docs/studio.md, "Sonar"): while the
// studio has a sonar folder, it asks GET /api/sonar once a second and shows
// latest.png whenever the Sonar Manager has written a newer one.
import { api } from './api.js';
import { $, state } from './context.js';

state.sonar = { frames: 0, mtime: null, frame: null, error: null };

function describe(f) {
  if (!f) return '';
  if (f.event === 'end') return `end: ${f.frames ?? '?'} frames, ${f.pings ?? '?'} pings, ${(f.lost_pings ?? 0) + (f.queue_drops ?? 0)} lost`;
  const t = typeof f.t === 'number' ? f.t.toFixed(1) : (typeof f.time_s === 'number' ? f.time_s.toFixed(1) : '?');
  const target = f.target ? `target ${Number(f.target.range_m ?? 0).toFixed(1)} m away` : 'no target';
  const walls = Array.isArray(f.walls) ? `${f.walls.length} walls` : '';
  return `frame ${f.frame ?? '?'} at ${t} s · ${walls} · ${target}`;
}

async function poll() {
  try {
    const s = await api.sonar();
    if (!s.dir) return false;  // this studio has no sonar: stop asking
    state.sonar.error = null;
    if (s.latest && s.latest.mtime_ms !== state.sonar.mtime) {
      state.sonar.mtime = s.latest.mtime_ms;
      state.sonar.frames++;
      $('#sonar-img').src = `/api/sonar/latest.png?m=${s.latest.mtime_ms}`;
      $('#sonar-box').hidden = false;
    }
    if (s.frame) {
      state.sonar.frame = s.frame;
      $('#sonar-info').textContent = describe(s.frame);
    }
  } catch (e) {
    state.sonar.error = e.message;
  }
  return true;
}

export function startSonar() {
  const tick = async () => { if (await poll()) setTimeout(tick, 1000); };
  tick();
}

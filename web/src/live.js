// The live view of a run (Server-Sent Events), replay of a mission log,
// and the verifier's counterexamples played on the net.
import { api } from './api.js';
import { emptyRun, applyEvent } from './runstate.js';
import { $, el, state, chart, msg, displayNets } from './context.js';
import { openFile, renderNetList, showNet, renderNet, scheduleFrame, updateDynamic } from './view.js';

// ---------------------------------------------------------------- live view
export function setView(v) {
  state.view = v;
  document.body.dataset.view = v;
  updateDynamic();
  renderRunPanels();
}

export function renderRunPanels() {
  const rs = state.rs;
  const status = $('#run-status');
  status.textContent = state.view === 'replay' ? `replay: ${rs.status}` : rs.status;
  status.className = `status ${rs.status}`;
  const out = $('#run-outcome');
  if (rs.ended) {
    out.textContent = `${rs.ended.outcome}${rs.ended.exit ? ` (exit ${rs.ended.exit})` : ''}${rs.ended.reason ? `: ${rs.ended.reason}` : ''}${rs.ended.t != null ? ` at t=${rs.ended.t}` : ''}`;
    out.className = `outcome ${rs.ended.outcome}`;
  } else if (rs.status === 'running') {
    out.textContent = `running ${rs.mission || ''}${rs.scenario ? ` (${rs.scenario}, ×${rs.speed})` : ''}`;
    out.className = 'outcome running';
  } else { out.textContent = 'no run'; out.className = 'muted'; }
  const fl = $('#inflight-list'); fl.replaceChildren();
  for (const a of Object.values(rs.inFlight)) fl.append(el('li', {}, `▶ ${a.kind || ''} ${a.primitive || ''}`, el('span', { class: 'muted' }, ` ${a.net || ''}/${a.transition || ''}`)));
  const rl = $('#report-log');
  if (rl.childElementCount !== rs.reports.length) {
    rl.replaceChildren(...rs.reports.map((r) => el('li', {}, el('span', { class: 'muted' }, r.t != null ? `${Number(r.t).toFixed(1)} ` : ''), r.text)));
    rl.scrollTop = rl.scrollHeight;
  }
  chart.update(rs.telemetry);
}

export function followRun() {
  if (!state.follow || state.view === 'edit' || state.view === 'cex') return;
  const n = state.rs.currentNet;
  if (n && n !== state.netName && displayNets().find((x) => x.name === n)) showNet(n);
}

export const EVENTS = ['snapshot', 'run_start', 'phase_start', 'phase_end', 'fired', 'action_start', 'action_finish', 'telemetry', 'report', 'run_end'];
let es = null;
export function connect() {
  es = new EventSource('/api/events');
  const conn = $('#conn-status');
  es.onopen = () => { state.sse = 'open'; conn.className = 'conn open'; conn.title = 'event stream: connected'; };
  es.onerror = () => { state.sse = 'error'; conn.className = 'conn error'; conn.title = 'event stream: reconnecting'; };
  for (const name of EVENTS) {
    es.addEventListener(name, (ev) => {
      let d;
      try { d = JSON.parse(ev.data); } catch { return; }
      onLiveEvent(name, d);
    });
  }
}

export async function onLiveEvent(name, d) {
  if (state.replay && (name === 'run_start' || name === 'snapshot')) closeReplay();
  const target = state.replay ? state.live : state.rs;
  applyEvent(target, name, d);
  if (state.replay) return;
  if (name === 'run_start' || (name === 'snapshot' && d.run != null)) {
    if (state.view === 'cex') state.cex = null;
    setView('live');
    if (!state.model && d.mission) adoptRunMission(d.mission);
    renderNetList();
  }
  if (name === 'phase_start' || name === 'phase_end' || name === 'fired' || name === 'snapshot') followRun();
  scheduleFrame();
}

// A page opened on a run of a mission it has no file of (`strata run --studio`).
export async function adoptRunMission(mission) {
  if (state.files.includes(mission)) { await openFile(mission, { keepView: true }); return; }
  const nets = state.rs.nets || [];
  if (nets.length) {
    state.netName = (nets.find((n) => n.kind === 'mission') || nets[0]).name;
    $('#path-label').textContent = `${mission} (run)`;
    renderNetList();
    renderNet();
  }
}

$('#btn-run').addEventListener('click', async () => {
  if (!state.path) return;
  const scenario = $('#run-scenario').value;
  const speed = Number($('#run-speed').value) || 10;
  if (state.dirty) msg('note: the run uses the file as saved; unsaved edits are not in it');
  try {
    const r = await api.run(state.path, scenario, speed);
    if (state.replay) closeReplay();
    setView('live');
    msg(`run ${r && r.run != null ? r.run : ''} started (${scenario}, ×${speed})`);
  } catch (e) {
    msg(e.status === 409 ? 'a run is going already' : `run: ${e.message}`, true);
  }
});
$('#btn-stop').addEventListener('click', async () => {
  try { await api.stop(); msg('stop sent'); } catch (e) { msg(`stop: ${e.message}`, true); }
});
$('#follow').addEventListener('change', (ev) => { state.follow = ev.target.checked; followRun(); });
$('#btn-edit-view').addEventListener('click', () => { state.cex = null; setView('edit'); if (state.replay) closeReplay(); });
$('#btn-live-view').addEventListener('click', () => { if (state.replay) closeReplay(); state.cex = null; setView('live'); followRun(); });

// ---------------------------------------------------------------- replay
export function eventOf(e) {
  const name = e.event ?? e.type ?? e.name;
  let data = e.data;
  if (data === undefined) { data = { ...e }; delete data.event; delete data.type; }
  return [name, data];
}

export async function openReplay(path) {
  try {
    const r = await api.replay(path);
    if (!state.replay) state.live = state.rs;
    state.replay = { path, mission: r.mission, events: (r.events || []).map(eventOf), pos: 0 };
    if (r.mission && r.mission !== state.path && state.files.includes(r.mission)) await openFile(r.mission, { keepView: true });
    const box = $('#replay-box');
    box.hidden = false;
    $('#replay-name').textContent = `${path} (${state.replay.events.length} events)`;
    const s = $('#replay-slider');
    s.max = String(state.replay.events.length);
    s.value = String(state.replay.events.length);
    for (const li of document.querySelectorAll('#log-list li')) li.classList.toggle('active', li.dataset.path === path);
    setView('replay');
    replayTo(state.replay.events.length);
  } catch (e) { msg(`replay ${path}: ${e.message}`, true); }
}

export function replayTo(k) {
  const r = state.replay;
  if (!r) return;
  k = Math.max(0, Math.min(r.events.length, k));
  r.pos = k;
  const rs = emptyRun();
  for (let i = 0; i < k; i++) applyEvent(rs, r.events[i][0], r.events[i][1]);
  if (!rs.nets && r.events.length) rs.nets = null;
  state.rs = rs;
  $('#replay-pos').textContent = `${k} / ${r.events.length}`;
  const cur = k > 0 ? r.events[k - 1] : null;
  $('#replay-event').textContent = cur ? `${cur[0]} ${JSON.stringify(cur[1]).slice(0, 240)}` : '(start)';
  if ($('#replay-slider').value !== String(k)) $('#replay-slider').value = String(k);
  followRun();
  updateDynamic();
  renderRunPanels();
}

export function closeReplay() {
  state.replay = null;
  state.rs = state.live;
  $('#replay-box').hidden = true;
  for (const li of document.querySelectorAll('#log-list li')) li.classList.remove('active');
  setView(state.rs.status === 'idle' ? 'edit' : 'live');
}

$('#replay-slider').addEventListener('input', (ev) => replayTo(Number(ev.target.value)));
$('#replay-close').addEventListener('click', closeReplay);
$('#replay-prev').addEventListener('click', () => state.replay && replayTo(prevFiring(state.replay.pos)));
$('#replay-next').addEventListener('click', () => state.replay && replayTo(nextFiring(state.replay.pos)));
export function nextFiring(k) { const ev = state.replay.events; for (let i = k; i < ev.length; i++) if (ev[i][0] === 'fired') return i + 1; return ev.length; }
export function prevFiring(k) { const ev = state.replay.events; for (let i = k - 2; i >= 0; i--) if (ev[i][0] === 'fired') return i + 1; return 0; }

// ---------------------------------------------------------------- verify
$('#btn-verify').addEventListener('click', async () => {
  if (!state.path) return;
  const box = $('#verify-box'), body = $('#verify-body');
  box.hidden = false;
  body.replaceChildren(el('div', { class: 'muted' }, 'verifying…'));
  try {
    const res = await api.verify(state.path, state.text);
    state.verify = res;
    renderVerify(res);
  } catch (e) {
    body.replaceChildren(el('div', { class: 'error' }, e.message));
    state.verify = { error: e.message };
  }
});

export function renderVerify(res) {
  const body = $('#verify-body');
  body.replaceChildren(el('div', { class: res.ok ? 'ok' : 'error', id: 'verify-summary' }, res.ok ? 'all properties hold' : 'some properties fail'));
  for (const net of res.nets || []) {
    const ul = el('ul', { class: 'list small props' });
    for (const p of net.properties || []) {
      const li = el('li', { class: `prop ${p.status}`, 'data-key': p.key }, el('b', {}, p.status === 'holds' ? '✓ ' : p.status === 'fails' ? '✗ ' : '? '), `${p.key}: `, p.message || '');
      if (p.counterexample && (p.counterexample.steps || []).length) {
        li.append(' ', el('button', { class: 'small play-cex', onclick: () => playCex(net.name, p) }, '▶ play'));
      }
      ul.append(li);
    }
    body.append(el('div', { class: 'vnet' }, el('b', {}, `${net.ok ? '✓' : '✗'} ${net.name}`), el('span', { class: 'muted' }, ` ${net.states ?? '?'} states`)), ul);
  }
}

// Plays a counterexample on its net: the marking from the initial one,
// a firing takes its wait arcs and puts its signal arcs, an answer marks.
export function playCex(netName, prop) {
  if (!showNet(netName)) { msg(`net ${netName} is not in this load`, true); return; }
  const steps = prop.counterexample.steps;
  state.cex = { net: netName, key: prop.key, steps, i: 0, marking: null, timer: null };
  if (state.replay) closeReplay();
  setView('cex');
  cexGo(0);
  const box = $('#cex-box');
  box.hidden = false;
  $('#cex-title').textContent = `${netName}: ${prop.key}`;
}

export function cexMarking(netName, steps, i) {
  const net = displayNets().find((n) => n.name === netName);
  const m = {};
  for (const p of net.places || []) if (p.initial) m[p.name] = p.initial;
  const tr = new Map((net.transitions || []).map((t) => [t.name, t]));
  for (let k = 0; k < i; k++) {
    const s = steps[k];
    if (s.kind === 'fire') {
      const t = tr.get(s.transition);
      if (t) {
        for (const a of t.inputs || []) m[a.place] = (m[a.place] || 0) - (a.weight ?? 1);
        for (const a of t.outputs || []) m[a.place] = (m[a.place] || 0) + (a.weight ?? 1);
      }
    } else {
      for (const p of s.marks || []) m[p] = (m[p] || 0) + 1;
    }
  }
  for (const k of Object.keys(m)) if (m[k] <= 0) delete m[k];
  return m;
}

export function cexGo(i) {
  const c = state.cex;
  if (!c) return;
  c.i = Math.max(0, Math.min(c.steps.length, i));
  c.marking = cexMarking(c.net, c.steps, c.i);
  if (state.netName !== c.net) showNet(c.net);
  $('#cex-pos').textContent = `${c.i} / ${c.steps.length}`;
  $('#cex-text').textContent = c.i > 0 ? `${c.i}. ${c.steps[c.i - 1].text}` : '(initial marking)';
  updateDynamic();
}
$('#cex-prev').addEventListener('click', () => state.cex && cexGo(state.cex.i - 1));
$('#cex-next').addEventListener('click', () => state.cex && cexGo(state.cex.i + 1));
$('#cex-play').addEventListener('click', () => {
  const c = state.cex;
  if (!c) return;
  if (c.timer) { clearInterval(c.timer); c.timer = null; return; }
  if (c.i >= c.steps.length) cexGo(0);
  c.timer = setInterval(() => {
    if (!state.cex || state.cex.i >= state.cex.steps.length) { clearInterval(c.timer); c.timer = null; return; }
    cexGo(state.cex.i + 1);
  }, 700);
});
$('#cex-close').addEventListener('click', () => {
  if (state.cex && state.cex.timer) clearInterval(state.cex.timer);
  state.cex = null;
  $('#cex-box').hidden = true;
  setView(state.rs.status === 'idle' ? 'edit' : 'live');
});

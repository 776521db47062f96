// The panels around the canvas: header, file, log and net lists,
// diagnostics, messages, the run (outcome, actions in flight, reports, the
// depth chart and, in open water, the map of the track), replay, verification, counterexamples, sonar, and a save's
// conflict. Each draws from the store when its part of the state changed.
import { $, el } from './dom.js';
import { DepthChart } from './chart.js';
import { TrackMap } from './map.js';
import { diagnosticsByElement } from './diag.js';
import { displayNets, dirty, runGoing, runBanner, breadcrumb, chartData, mapData, scenarioList, isProlog } from './store.js';
import { diagnosticRange } from './textrange.js';
import { lineDiff } from './diff.js';

export function createPanels(store, fx) {
  const { getState, dispatch } = store;
  const chart = new DepthChart($('#chart'));
  const map = new TrackMap($('#map-box'), $('#map'));

  // The header follows the store at every action (a run's events, busy):
  // only what changed is written (a text or attribute written again, even
  // the same, makes the browser restyle and lay out the page).
  const put = (node, key, value) => { if (node[key] !== value) node[key] = value; };
  function header(s) {
    const d = dirty(s);
    put($('#path-label'), 'textContent', s.path ? (s.readOnly ? `${s.path} (read-only)` : s.path) : (s.rs.mission ? `${s.rs.mission} (run)` : 'no file'));
    put($('#dirty-mark'), 'hidden', !d);
    put($('#btn-save'), 'disabled', !s.path || !d || s.readOnly);
    put($('#btn-verify'), 'disabled', !s.path || s.readOnly);
    put($('#btn-run'), 'disabled', !s.path);
    const going = runGoing(s);
    put($('#btn-abort'), 'disabled', !going);
    put($('#btn-stop'), 'disabled', !going);
    put($('#btn-undo'), 'disabled', !s.undo.length || s.readOnly);
    put($('#btn-redo'), 'disabled', !s.redo.length || s.readOnly);
    put(document, 'title', (d ? '● ' : '') + 'Strata studio' + (s.path ? ` — ${s.path}` : ''));
    const m = $('#edit-msg');
    if (m.dataset.text !== s.message.text || m.classList.contains('error') !== s.message.error) {
      m.dataset.text = s.message.text;
      m.textContent = s.message.text;
      m.classList.toggle('error', s.message.error);
    }
    const conn = $('#conn-status');
    put(conn, 'className', `conn ${s.sse}`);
    put(conn, 'title', s.sse === 'open' ? 'event stream: connected' : s.sse === 'error' ? 'event stream: reconnecting' : 'event stream');
    if (document.body.dataset.view !== s.view) document.body.dataset.view = s.view;
    put($('#follow'), 'checked', s.follow);
  }

  function files(s) {
    const fl = $('#file-list'); fl.replaceChildren();
    const list = s.missions.length ? s.missions : s.files.map((p) => ({ path: p, kind: 'coral' }));
    for (const { path: p, kind } of list) {
      fl.append(el('li', { class: p === s.path ? 'active' : '', 'data-path': p, 'data-kind': kind, title: kind === 'prolog' ? `${p} (PROLOG mission: text only)` : p, onpointerenter: () => fx.prefetch(p), onpointerdown: () => fx.prefetch(p), onclick: () => fx.openFile(p) },
        p, kind === 'prolog' ? el('span', { class: 'badge prolog' }, ' PROLOG') : null));
    }
    // Files the server could not name (not UTF-8): said, not listed.
    if (s.unlisted) fl.append(el('li', { class: 'muted', id: 'unlisted' }, `not listed: ${s.unlisted}`));
    const ll = $('#log-list'); ll.replaceChildren();
    for (const p of s.logs) ll.append(el('li', { 'data-path': p, title: p, class: s.replay && s.replay.path === p ? 'active' : '', onclick: () => fx.openReplay(p) }, p));
    if (!s.logs.length) ll.append(el('li', { class: 'muted' }, 'none'));
  }

  // The open mission's studio runs, newest first; a click replays one.
  function runs(s) {
    const ul = $('#run-list'); ul.replaceChildren();
    $('#runs-of').textContent = s.path ? `of ${s.path.split('/').pop()}` : '';
    for (const r of s.runs.list) {
      ul.append(el('li', { 'data-path': r.path, title: r.path, class: s.replay && s.replay.path === r.path ? 'active' : '', onclick: () => fx.openReplay(r.path) },
        r.started || r.path.split('/').pop(), el('span', { class: 'muted' }, ` ${Math.round((r.bytes || 0) / 1024)} KB`)));
    }
    if (!s.runs.list.length) ul.append(el('li', { class: 'muted' }, s.path ? 'none' : 'open a mission'));
  }

  // The run's end over the canvas: outcome, phase, reason, hard stop, log.
  function banner(s) {
    const box = $('#run-banner');
    const b = runBanner(s);
    box.hidden = !b;
    if (!b) { box.replaceChildren(); box.dataset.outcome = ''; return; }
    box.className = `${b.outcome}${b.hard ? ' hard' : ''}`;
    box.dataset.outcome = b.outcome;
    box.replaceChildren(
      el('button', { class: 'small banner-close', title: 'close', onclick: () => dispatch({ type: 'banner/close' }) }, '×'),
      ...b.lines.map((t, i) => el('div', { class: i === 0 ? 'banner-outcome' : b.hard && /NOT surfaced/.test(t) ? 'banner-hard' : t.startsWith('log:') ? 'banner-log mono small' : '' }, t)));
  }

  // During a run: mission ▸ phase ▸ ... (a crumb opens its net).
  function crumbs(s) {
    const box = $('#breadcrumb');
    const c = breadcrumb(s);
    box.hidden = !c.length;
    const key = c.map((x) => x.net).join('>') + `|${s.netName}`;
    if (box.dataset.key === key) return;
    box.dataset.key = key;
    const parts = [];
    c.forEach((x, i) => {
      if (i) parts.push(' ▸ ');
      parts.push(el('span', { class: `crumb${i === c.length - 1 ? ' active' : ''}`, 'data-net': x.net, onclick: () => dispatch({ type: 'net/show', name: x.net, user: true }) }, x.net));
    });
    box.replaceChildren(...parts);
  }

  // A PROLOG mission: text only.
  function note(s) {
    const box = $('#canvas-note');
    const p = isProlog(s);
    box.hidden = !p;
    if (p) box.textContent = `${s.path} is a PROLOG mission: shown as text, read-only (no graph). Run runs it on the studio's PROLOG thread.`;
  }

  function nets(s) {
    const ul = $('#net-list'); ul.replaceChildren();
    for (const n of displayNets(s)) {
      const badge = n.kind === 'mission' ? 'mission' : 'phase';
      ul.append(el('li', { class: n.name === s.netName ? 'active' : '', 'data-net': n.name, title: n.file || '', onclick: () => dispatch({ type: 'net/show', name: n.name, user: true }) },
        el('span', { class: `badge ${badge}` }, badge), ' ', n.name, n.editable ? '' : el('span', { class: 'muted' }, ' (import)')));
    }
  }

  // A diagnostic clicked: its element on the canvas and its range in the text.
  function focusDiagnostic(d) {
    const s = getState();
    let id = null, net = null;
    for (const n of displayNets(s)) {
      for (const [eid, ds] of diagnosticsByElement(s.model, n)) if (ds.includes(d)) { id = eid; net = n.name; break; }
      if (id) break;
    }
    const r = diagnosticRange(s.text || '', d);
    dispatch({ type: 'focus', id, net, from: r ? r.from : null, to: r ? r.to : null });
  }

  function diagnostics(s) {
    const ds = (s.model && s.model.diagnostics) || [];
    $('#diag-count').textContent = ds.length ? `(${ds.length})` : '';
    const ul = $('#diag-list'); ul.replaceChildren();
    if (!ds.length) { ul.append(el('li', { class: 'muted' }, s.model && !s.model.nets?.length && s.path && !s.readOnly ? 'the text does not compile' : 'none')); return; }
    for (const d of ds) {
      ul.append(el('li', { class: `sev-${d.severity}`, title: (d.notes || []).map((n) => n.message).join('\n'), onclick: () => focusDiagnostic(d) },
        el('b', {}, d.severity), ` ${d.file || ''}:${d.line}:${d.col ?? ''} `, d.message, d.kind ? el('span', { class: 'muted' }, ` [${d.kind}]`) : null));
    }
  }

  function run(s) {
    const rs = s.rs;
    const status = $('#run-status');
    status.textContent = s.view === 'replay' ? `replay: ${rs.status}` : rs.status;
    status.className = `status ${rs.status}`;
    const out = $('#run-outcome');
    if (rs.ended) {
      out.textContent = `${rs.ended.outcome}${rs.ended.exit ? ` (exit ${rs.ended.exit})` : ''}${rs.ended.reason ? `: ${rs.ended.reason}` : ''}${rs.ended.t != null ? ` at t=${rs.ended.t}` : ''}${rs.ended.mission_t != null && rs.ended.t != null && rs.ended.mission_t < rs.ended.t - 1e-6 ? ` (the mission ended at t=${rs.ended.mission_t}; then the safe end)` : ''}`;
      out.className = `outcome ${rs.ended.outcome}`;
    } else if (rs.status === 'running') {
      out.textContent = `running ${rs.mission || ''}${rs.scenario ? ` (${rs.scenario}, ×${rs.speed})` : ''}`;
      out.className = 'outcome running';
    } else { out.textContent = 'no run'; out.className = 'muted'; }
    const fl = $('#inflight-list'); fl.replaceChildren();
    for (const a of Object.values(rs.inFlight)) fl.append(el('li', {}, `▶ ${a.kind || ''} ${a.primitive || ''}`, el('span', { class: 'muted' }, ` ${a.net || ''}/${a.transition || ''}`)));
    const rl = $('#report-log');
    if (rl.childElementCount !== rs.reports.length) {
      rl.replaceChildren(...rs.reports.map((r) => el('li', r.scripted ? { class: 'scripted', title: 'a scripted answer (--answers), not the vehicle\'s' } : {},
        el('span', { class: 'muted' }, r.t != null ? `${Number(r.t).toFixed(1)} ` : ''), r.scripted ? el('b', { class: 'scripted-tag' }, 'scripted ') : null, r.text)));
      rl.scrollTop = rl.scrollHeight;
    }
    chart.update(chartData(s));
    map.update(mapData(s));
    banner(s);
    crumbs(s);
  }

  function replay(s) {
    const r = s.replay;
    $('#replay-box').hidden = !r;
    for (const li of document.querySelectorAll('#log-list li')) li.classList.toggle('active', !!r && li.dataset.path === r.path);
    if (!r) return;
    $('#replay-name').textContent = `${r.path} (${r.events.length} events)`;
    const sl = $('#replay-slider');
    sl.max = String(r.events.length);
    if (sl.value !== String(r.pos)) sl.value = String(r.pos);
    $('#replay-pos').textContent = `${r.pos} / ${r.events.length}`;
    $('#replay-play').textContent = r.playing ? 'pause' : 'play';
    const cur = r.pos > 0 ? r.events[r.pos - 1] : null;
    $('#replay-event').textContent = cur ? `${cur[0]} ${JSON.stringify(cur[1]).slice(0, 240)}` : '(start)';
  }

  function verify(s) {
    const box = $('#verify-box'), body = $('#verify-body');
    const res = s.verify;
    box.hidden = !res;
    if (!res) return;
    if (res.pending) { body.replaceChildren(el('div', { class: 'muted' }, 'verifying…')); return; }
    if (res.error) { body.replaceChildren(el('div', { class: 'error' }, res.error)); return; }
    // ok: nothing blocks a run; all_hold: not even a warning (one_safe, no_dead).
    const allHold = res.all_hold ?? res.ok;
    const summary = allHold ? 'all properties hold' : res.ok ? 'safe to run, with warnings' : 'some properties fail';
    body.replaceChildren(el('div', { class: res.ok ? 'ok' : 'error', id: 'verify-summary' }, summary));
    for (const net of res.nets || []) {
      const ul = el('ul', { class: 'list small props' });
      for (const p of net.properties || []) {
        const warning = p.blocking === false && p.status !== 'holds';
        const where = p.at && p.at.line ? `${p.at.file}:${p.at.line}:${p.at.col}` : '';
        const li = el('li', { class: `prop ${p.status}${warning ? ' warning' : ''}`, 'data-key': p.key, title: where },
          el('b', {}, p.status === 'holds' ? '✓ ' : warning ? '! ' : p.status === 'fails' ? '✗ ' : '? '), `${p.key}: `, p.message || '');
        if (p.counterexample && (p.counterexample.steps || []).length) {
          li.append(' ', el('button', { class: 'small play-cex', onclick: () => {
            if (!displayNets(getState()).some((n) => n.name === net.name)) { fx.say(`net ${net.name} is not in this load`, true); return; }
            dispatch({ type: 'cex/play', net: net.name, key: p.key, steps: p.counterexample.steps });
          } }, '▶ play'));
        }
        ul.append(li);
      }
      body.append(el('div', { class: 'vnet' }, el('b', {}, `${net.ok ? '✓' : '✗'} ${net.name}`), el('span', { class: 'muted' }, ` ${net.states ?? '?'} states`)), ul);
    }
  }

  function cex(s) {
    const c = s.cex;
    $('#cex-box').hidden = !c;
    if (!c) return;
    const timed = c.steps.some((st) => st.instance);
    $('#cex-title').textContent = timed ? `${c.net}: ${c.key}, the worst path` : `${c.net}: ${c.key}`;
    $('#cex-pos').textContent = `${c.i} / ${c.steps.length}`;
    $('#cex-text').textContent = c.i > 0 ? `${c.i}. ${c.steps[c.i - 1].text}` : '(initial marking)';
  }

  function sonar(s) {
    const so = s.sonar;
    if (so.mtime != null) {
      const src = `/api/sonar/latest.png?m=${so.mtime}`;
      const img = $('#sonar-img');
      if (img.getAttribute('src') !== src) img.setAttribute('src', src);
      $('#sonar-box').hidden = false;
    }
    $('#sonar-info').textContent = describeSonar(so.frame);
  }

  // A save refused with 412: Reload, or keep mine over their version, with both texts compared.
  function conflict(s) {
    const box = $('#conflict-box');
    const c = s.conflict;
    box.hidden = !c;
    if (!c) { box.replaceChildren(); return; }
    const rows = c.theirs == null ? [] : lineDiff(c.theirs, s.text || '');
    const changed = rows.filter((r) => r.op !== ' ').length;
    box.replaceChildren(
      el('div', {}, el('b', {}, `${c.path} changed since you opened it.`), ` ${changed} line(s) differ between the file now (−) and your text (+).`),
      el('div', { class: 'conflict-actions' },
        el('button', { id: 'btn-reload', onclick: () => fx.reload() }, 'Reload (drop my edits)'),
        el('button', { id: 'btn-keep-mine', disabled: c.etag == null, onclick: () => fx.keepMine() }, 'Keep mine (save over it)'),
        el('button', { id: 'btn-conflict-close', class: 'small', onclick: () => dispatch({ type: 'conflict/dismiss' }) }, 'close')),
      el('pre', { id: 'conflict-diff', class: 'mono small' }, rows.filter((r, i) => r.op !== ' ' || rows.slice(Math.max(0, i - 2), i + 3).some((x) => x.op !== ' '))
        .map((r) => el('div', { class: r.op === '-' ? 'del' : r.op === '+' ? 'add' : '' }, `${r.op} ${r.text}`))));
  }

  let prev = null;
  function render(s) {
    const p = prev;
    prev = s;
    header(s);
    if (!p || s.files !== p.files || s.missions !== p.missions || s.logs !== p.logs) files(s);
    else if (s.path !== p.path) for (const li of document.querySelectorAll('#file-list li')) li.className = li.dataset.path === s.path ? 'active' : '';
    if (!p || displayNets(s) !== displayNets(p) || s.netName !== p.netName) nets(s);
    if (!p || s.model !== p.model) diagnostics(s);
    if (!p || s.rs !== p.rs || s.view !== p.view || s.live !== p.live || s.bannerClosed !== p.bannerClosed || s.netName !== p.netName || s.replay !== p.replay) scheduleRun();
    if (!p || s.runs !== p.runs || s.path !== p.path || s.replay !== p.replay) runs(s);
    if (!p || s.model !== p.model) note(s);
    if (!p || s.replay !== p.replay) replay(s);
    if (!p || s.verify !== p.verify) verify(s);
    if (!p || s.cex !== p.cex) cex(s);
    if (!p || s.sonar !== p.sonar) sonar(s);
    if (!p || s.conflict !== p.conflict || (s.conflict && s.text !== p.text)) conflict(s);
    if (!p || s.model !== p.model) fillScenarios(s);
  }
  // The run panels at most once per animation frame.
  let runQueued = false;
  function scheduleRun() {
    if (runQueued) return;
    runQueued = true;
    requestAnimationFrame(() => { runQueued = false; run(getState()); });
  }
  // The scenarios beside the mission, nominal first.
  function fillScenarios(s) {
    const select = $('#run-scenario');
    const keep = select.value;
    const list = scenarioList(s);
    if ([...select.options].map((o) => o.value).join() === list.join()) return;
    select.replaceChildren(...list.map((n) => el('option', {}, n)));
    select.value = list.includes(keep) ? keep : 'nominal';
  }
  store.subscribe(render);
  render(getState());
  return { chart, map };
}

export function describeSonar(f) {
  if (!f) return '';
  if (f.event === 'end') return `end: ${f.frames ?? '?'} frames, ${f.pings ?? '?'} pings, ${(f.lost_pings ?? 0) + (f.queue_drops ?? 0)} lost`;
  const t = typeof f.t === 'number' ? f.t.toFixed(1) : (typeof f.time_s === 'number' ? f.time_s.toFixed(1) : '?');
  const target = f.target ? `target ${Number(f.target.range_m ?? 0).toFixed(1)} m away` : 'no target';
  const walls = Array.isArray(f.walls) ? `${f.walls.length} walls` : '';
  return `frame ${f.frame ?? '?'} at ${t} s · ${walls} · ${target}`;
}

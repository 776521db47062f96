// The state of a run as the events of GET /api/events (or of a replay) build
// it: one reducer for the live view and for replay, so both show the same.

export function emptyRun() {
  return {
    run: null, mission: null, scenario: null, speed: null, nets: null,
    status: 'idle',            // idle | running | completed | aborted | failed
    ended: null,               // the run_end data
    instances: {},             // instance -> {net, parent}
    markings: {},              // net name -> {place: n}, the last marking seen
    enabled: {},               // net name -> [transition]
    inFlight: {},              // action id -> {id, instance, net, transition, kind, primitive}
    telemetry: [],             // [t, depth, setpoint]
    track: [],                 // [t, x, y]: the vehicle's estimated position, from the samples that have one (open water)
    reports: [],               // {t, text, scripted}: REPORTs, and a --answers run's scripted answers (scripted true)
    lastFired: null,           // {net, transition, index, t}
    currentNet: null,          // the net of the latest phase_start / fired
    active: null,              // the instance of the deepest phase running
    phases: [],                // {instance, net, parent, t0, t1}: each phase's span (t1 null while it runs); copied on change
    t: null,                   // the time of the latest event that had one
    events: 0,
  };
}

// x and y of a sample: both finite numbers, or no position (a tank run).
function isPosition(x, y) { return Number.isFinite(x) && Number.isFinite(y); }

function netOf(rs, instance, fallback) {
  const inst = rs.instances[instance];
  return (inst && inst.net) || fallback || null;
}

// Applies one event (name, data) to rs; returns rs. Unknown events are ignored.
export function applyEvent(rs, name, d) {
  rs.events++;
  if (d && typeof d.t === 'number') rs.t = d.t;
  switch (name) {
    case 'snapshot': {
      const fresh = emptyRun();
      Object.assign(rs, fresh);
      rs.run = d.run ?? null;
      rs.mission = d.mission ?? null;
      rs.nets = d.nets || null;
      for (const i of d.instances || []) {
        rs.instances[i.instance] = { net: i.net, parent: i.parent };
        rs.markings[i.net] = { ...(i.marking || {}) };
        rs.currentNet = i.net;
      }
      for (const a of d.in_flight || []) {
        rs.inFlight[a.id] = { ...a, net: netOf(rs, a.instance) };
      }
      // The final markings of the instances that ended (kept after the run).
      for (const f of d.final || []) if (f.net && !rs.markings[f.net]) rs.markings[f.net] = { ...(f.marking || {}) };
      // The deepest instance still running is the active phase.
      let depth = -1;
      for (const i of d.instances || []) {
        const k = chainOf(rs, i.instance).length;
        if (k > depth) { depth = k; rs.active = i.instance; }
      }
      rs.telemetry = (d.telemetry || []).map((p) => [p[0], p[1], p[2]]);
      rs.track = (d.telemetry || []).filter((p) => isPosition(p[3], p[4])).map((p) => [p[0], p[3], p[4]]);
      if (rs.telemetry.length) rs.t = rs.telemetry[rs.telemetry.length - 1][0];
      rs.reports = (d.reports || []).slice();
      if (d.ended) { rs.ended = d.ended; rs.status = d.ended.outcome || 'ended'; rs.active = null; }
      else rs.status = d.run != null ? 'running' : 'idle';
      break;
    }
    case 'run_start': {
      const keep = emptyRun();
      Object.assign(rs, keep);
      rs.run = d.run ?? null;
      rs.mission = d.mission ?? null;
      rs.scenario = d.scenario ?? null;
      rs.speed = d.speed ?? null;
      rs.nets = d.nets || null;
      rs.status = 'running';
      break;
    }
    case 'phase_start': {
      rs.instances[d.instance] = { net: d.net, parent: d.parent };
      rs.markings[d.net] = { ...(d.marking || {}) };
      rs.enabled[d.net] = [];
      rs.currentNet = d.net;
      rs.active = d.instance;
      rs.phases = [...rs.phases, { instance: d.instance, net: d.net, parent: d.parent ?? null, depth: d.depth ?? null, t0: d.t ?? rs.t, t1: null }];
      if (rs.status === 'idle') rs.status = 'running';
      break;
    }
    case 'phase_end': {
      const parent = rs.instances[d.instance] && rs.instances[d.instance].parent;
      const pnet = netOf(rs, parent);
      if (pnet && pnet !== d.net) rs.currentNet = pnet;
      if (d.net) rs.enabled[d.net] = [];
      // The PHASE action that started it, and the net's dropped actions, are no longer in flight.
      if (d.action) delete rs.inFlight[d.action];
      for (const id of d.dropped || []) delete rs.inFlight[id];
      if (rs.active === d.instance) rs.active = parent !== d.instance ? (parent ?? null) : null;
      rs.phases = rs.phases.map((p) => (p.instance === d.instance && p.t1 == null ? { ...p, t1: d.t ?? rs.t, exit: d.exit ?? null } : p));
      break;
    }
    case 'fired': {
      const net = d.net || netOf(rs, d.instance);
      if (d.instance != null && net && !rs.instances[d.instance]) rs.instances[d.instance] = { net, parent: null };
      rs.markings[net] = { ...(d.marking || {}) };
      rs.enabled[net] = (d.enabled || []).slice();
      rs.lastFired = { net, transition: d.transition, index: d.index, t: d.t };
      rs.currentNet = net;
      break;
    }
    case 'action_start': {
      rs.inFlight[d.id] = { id: d.id, instance: d.instance, net: netOf(rs, d.instance), transition: d.transition,
        kind: d.kind, primitive: d.primitive, t: d.t };
      break;
    }
    case 'action_finish': {
      const a = rs.inFlight[d.id];
      delete rs.inFlight[d.id];
      const net = netOf(rs, d.instance, a && a.net);
      if (net && d.marking) rs.markings[net] = { ...d.marking };
      break;
    }
    case 'telemetry':
      rs.telemetry.push([d.t, d.depth, d.setpoint]);
      if (isPosition(d.x, d.y)) rs.track.push([d.t, d.x, d.y]);
      break;
    case 'report':
      rs.reports.push({ t: d.t, text: d.text });
      break;
    case 'scripted_answer':
    case 'scripted_phase':
    case 'answers_diverged':
      // Only a replay has these: the log of a run made with --answers.
      rs.reports.push({ t: d.t, text: scriptedText(name, d), scripted: true });
      break;
    case 'run_end':
      rs.ended = d;
      rs.status = d.outcome || 'ended';
      rs.inFlight = {};
      rs.active = null;
      rs.phases = rs.phases.map((p) => (p.t1 == null ? { ...p, t1: d.t ?? rs.t } : p));
      break;
    default:
      rs.events--;
  }
  return rs;
}

// The instances from the root (the mission net) down to instance.
export function chainOf(rs, instance) {
  const out = [];
  const seen = new Set();
  // The mission net's instance is its own parent (0 and 0).
  for (let i = instance; i != null && rs.instances[i] && !seen.has(i); i = rs.instances[i].parent) {
    seen.add(i);
    out.unshift(i);
  }
  return out;
}

// One line for a scripted answer of a --answers run (docs/mission-log.md):
// what the mission was told, what the vehicle said, and where.
export function scriptedText(name, d) {
  const where = [d.net && d.transition ? `${d.net}/${d.transition}` : d.net || d.transition, d.step ? `step ${d.step}` : '']
    .filter(Boolean).join(', ');
  const at = where ? ` (${where})` : '';
  if (name === 'scripted_answer') {
    const told = d.answer === d.vehicle ? `answered ${d.answer}, as the vehicle did` : `answered ${d.answer}; the vehicle said ${d.vehicle}`;
    return `${String(d.action || '').toUpperCase()} ${d.primitive || ''} ${told}${at}`;
  }
  if (name === 'scripted_phase') return `phase ${d.phase || ''} ended at ${d.exit || ''}, as scripted${at}`;
  return `the run left the script after ${d.used ?? 0} answers: ${d.reason || ''}`;
}

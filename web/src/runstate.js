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
    reports: [],               // {t, text}
    lastFired: null,           // {net, transition, index, t}
    currentNet: null,          // the net of the latest phase_start / fired
    events: 0,
  };
}

function netOf(rs, instance, fallback) {
  const inst = rs.instances[instance];
  return (inst && inst.net) || fallback || null;
}

// Applies one event (name, data) to rs; returns rs. Unknown events are ignored.
export function applyEvent(rs, name, d) {
  rs.events++;
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
      rs.telemetry = (d.telemetry || []).map((p) => [p[0], p[1], p[2]]);
      rs.reports = (d.reports || []).slice();
      if (d.ended) { rs.ended = d.ended; rs.status = d.ended.outcome || 'ended'; }
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
      if (rs.status === 'idle') rs.status = 'running';
      break;
    }
    case 'phase_end': {
      const parent = rs.instances[d.instance] && rs.instances[d.instance].parent;
      const pnet = netOf(rs, parent);
      if (pnet && pnet !== d.net) rs.currentNet = pnet;
      if (d.net) rs.enabled[d.net] = [];
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
      break;
    case 'report':
      rs.reports.push({ t: d.t, text: d.text });
      break;
    case 'run_end':
      rs.ended = d;
      rs.status = d.outcome || 'ended';
      rs.inFlight = {};
      break;
    default:
      rs.events--;
  }
  return rs;
}

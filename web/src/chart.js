// Depth and setpoint against time (uPlot), depth axis pointing down; the
// run's phases as shaded bands (phase_start..phase_end) and, in a replay, a
// cursor at the replay's time.
//
// uPlot is its own chunk, imported by load(): main.js asks once the views
// are shown and the page is idle, update() at once when it has something to
// draw; until then update() keeps the last data.
import 'uplot/dist/uPlot.min.css';

const kBandColours = ['rgba(29, 95, 168, 0.10)', 'rgba(210, 105, 30, 0.12)', 'rgba(46, 125, 50, 0.12)', 'rgba(106, 27, 154, 0.10)'];

export class DepthChart {
  constructor(el) {
    this.el = el;
    this.plot = null;
    this.count = -1;
    this.telemetry = null;
    this.phases = [];     // the bands drawn: {net, t0, t1}
    this.cursor = null;   // the time of the cursor, or null
    this.cursorX = null;  // where it was drawn (canvas px), for the tests
    this.uPlot = null;    // the library, once loaded
    this.loading = null;
    this.pending = null;  // the data of update() before the library came
  }

  // Imports uPlot (once) and draws what update() was given meanwhile.
  load() {
    if (!this.loading) {
      this.loading = import('uplot').then((m) => {
        this.uPlot = m.default;
        const d = this.pending;
        this.pending = null;
        if (d) this.update(d);
      });
    }
    return this.loading;
  }

  // Whether the plot exists (made on first use once uPlot is loaded).
  ensure() {
    if (this.plot) return true;
    if (!this.uPlot) return false;
    const uPlot = this.uPlot;
    const w = Math.max(300, this.el.clientWidth || 600);
    const h = Math.max(100, (this.el.clientHeight || 200) - 40);
    this.plot = new uPlot({
      width: w, height: h,
      legend: { show: true, live: false },
      cursor: { drag: { x: false, y: false } },
      scales: { x: { time: false }, m: { dir: -1, auto: true, range: (u, min, max) => [Math.min(0, min), Math.max(1, max) * 1.05] } },
      axes: [
        { label: 't (s)', size: 30, labelSize: 14 },
        { scale: 'm', label: 'depth (m)', size: 46, labelSize: 14 },
      ],
      series: [
        { label: 't' },
        { label: 'depth', scale: 'm', stroke: '#1d5fa8', width: 2 },
        { label: 'setpoint', scale: 'm', stroke: '#d2691e', width: 1.5, dash: [6, 4] },
      ],
      hooks: {
        drawClear: [(u) => this.drawBands(u)],
        draw: [(u) => this.drawCursor(u)],
      },
    }, [[], [], []], this.el);
    this.resizeObs = new ResizeObserver(() => this.resize());
    this.resizeObs.observe(this.el);
    return true;
  }

  resize() {
    if (!this.plot) return;
    const w = Math.max(300, this.el.clientWidth);
    const h = Math.max(100, this.el.clientHeight - 40);
    this.plot.setSize({ width: w, height: h });
  }

  // Phases under the curves: one band per phase (nested ones overlap).
  drawBands(u) {
    const { ctx, bbox } = u;
    if (!this.phases.length || u.scales.x.min == null) return;
    ctx.save();
    ctx.beginPath();
    ctx.rect(bbox.left, bbox.top, bbox.width, bbox.height);
    ctx.clip();
    ctx.font = `${Math.round(10 * devicePixelRatio)}px sans-serif`;
    ctx.textBaseline = 'top';
    this.phases.forEach((p, i) => {
      const t1 = p.t1 ?? u.scales.x.max;
      const x0 = u.valToPos(p.t0, 'x', true), x1 = u.valToPos(t1, 'x', true);
      if (!(x1 > x0)) return;
      ctx.fillStyle = kBandColours[i % kBandColours.length];
      ctx.fillRect(x0, bbox.top, x1 - x0, bbox.height);
      ctx.fillStyle = '#556';
      if (x1 - x0 > 30 * devicePixelRatio) ctx.fillText(p.net, x0 + 3, bbox.top + 2 + (i % 3) * 12 * devicePixelRatio, x1 - x0 - 6);
    });
    ctx.restore();
  }

  drawCursor(u) {
    this.cursorX = null;
    if (this.cursor == null || u.scales.x.min == null) return;
    const { ctx, bbox } = u;
    const x = u.valToPos(this.cursor, 'x', true);
    if (!(x >= bbox.left - 1 && x <= bbox.left + bbox.width + 1)) return;
    this.cursorX = x;
    ctx.save();
    ctx.strokeStyle = '#c2185b';
    ctx.lineWidth = 2 * devicePixelRatio;
    ctx.beginPath();
    ctx.moveTo(x, bbox.top);
    ctx.lineTo(x, bbox.top + bbox.height);
    ctx.stroke();
    ctx.restore();
  }

  // {telemetry: [[t, depth, setpoint], ...], phases: [{net, parent, t0, t1}], cursor: t | null}
  // (an array alone is the telemetry).
  update(data) {
    if (!this.ensure()) {
      this.pending = data;
      const d = Array.isArray(data) ? { telemetry: data } : data;
      if ((d.telemetry && d.telemetry.length) || (d.phases && d.phases.length) || d.cursor != null) this.load();
      return;
    }
    const { telemetry: points, phases = [], cursor = null } = Array.isArray(data) ? { telemetry: data } : data;
    // Bands: the phases (not the mission net, which spans the whole run).
    const bands = phases.filter((p) => typeof p.t0 === 'number' && (p.depth != null ? p.depth > 0 : p.parent != null && p.parent !== p.instance));
    const extras = bands.length !== this.phases.length || bands.some((b, i) => b.t1 !== this.phases[i].t1 || b.net !== this.phases[i].net) || cursor !== this.cursor;
    this.phases = bands;
    this.cursor = cursor;
    if (points === this.telemetry && points.length === this.count && points.length !== 0) {
      if (extras) this.plot.redraw(false, false);
      return;
    }
    this.telemetry = points;
    this.count = points.length;
    const t = new Array(points.length), d = new Array(points.length), s = new Array(points.length);
    for (let i = 0; i < points.length; i++) { t[i] = points[i][0]; d[i] = points[i][1]; s[i] = points[i][2] ?? null; }
    this.plot.setData([t, d, s]);
  }
}

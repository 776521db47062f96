// Depth and setpoint against time (uPlot), depth axis pointing down.
import uPlot from 'uplot';
import 'uplot/dist/uPlot.min.css';

export class DepthChart {
  constructor(el) {
    this.el = el;
    this.plot = null;
    this.count = -1;
  }

  ensure() {
    if (this.plot) return;
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
    }, [[], [], []], this.el);
    this.resizeObs = new ResizeObserver(() => this.resize());
    this.resizeObs.observe(this.el);
  }

  resize() {
    if (!this.plot) return;
    const w = Math.max(300, this.el.clientWidth);
    const h = Math.max(100, this.el.clientHeight - 40);
    this.plot.setSize({ width: w, height: h });
  }

  // points: [[t, depth, setpoint], ...]
  update(points) {
    this.ensure();
    if (points.length === this.count && points.length !== 0) return;
    this.count = points.length;
    const t = new Array(points.length), d = new Array(points.length), s = new Array(points.length);
    for (let i = 0; i < points.length; i++) { t[i] = points[i][0]; d[i] = points[i][1]; s[i] = points[i][2] ?? null; }
    this.plot.setData([t, d, s]);
  }
}

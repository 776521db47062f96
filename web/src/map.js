// The map panel of the live view and of a replay (issue 20): the vehicle's
// track in the horizontal plane, x east and y north, north up, equal scales,
// and the vehicle where it is (live: the latest sample; replay: the sample at
// the replay's position). Drawn on a plain canvas; shown only while the run
// has positions (open water; a tank run has none and the panel is hidden).

// The least span the map shows, in metres: a vehicle at rest is a dot in a
// 10 m square, not a speck magnified to fill the panel.
export const kMinSpan_m = 10;

// How points ([t, x, y]) fit a width x height canvas with pad pixels of
// margin: one scale for both axes (pixels per metre), the points' box
// centred. toPx(x, y) gives canvas pixels, y pointing down (north up).
// null without points.
export function mapFrame(points, width, height, pad = 12) {
  let x0 = Infinity, x1 = -Infinity, y0 = Infinity, y1 = -Infinity;
  for (const p of points) {
    if (!p) continue;
    x0 = Math.min(x0, p[1]); x1 = Math.max(x1, p[1]);
    y0 = Math.min(y0, p[2]); y1 = Math.max(y1, p[2]);
  }
  if (!(x1 >= x0) || !(y1 >= y0)) return null;
  const cx = (x0 + x1) / 2, cy = (y0 + y1) / 2;
  const spanX = Math.max(kMinSpan_m, x1 - x0), spanY = Math.max(kMinSpan_m, y1 - y0);
  const k = Math.max(1e-9, Math.min((width - 2 * pad) / spanX, (height - 2 * pad) / spanY));
  return {
    k,
    bounds: { x0, x1, y0, y1 },
    toPx: (x, y) => [width / 2 + (x - cx) * k, height / 2 - (y - cy) * k],
  };
}

// A round length for the scale bar: 1, 2 or 5 times a power of ten metres,
// the largest not longer than most_m.
export function scaleBar(most_m) {
  if (!(most_m > 0)) return 0;
  const p = 10 ** Math.floor(Math.log10(most_m));
  for (const m of [5, 2, 1]) if (m * p <= most_m) return m * p;
  return p;
}

export class TrackMap {
  constructor(box, canvas) {
    this.box = box;
    this.canvas = canvas;
    this.track = null;
    this.count = -1;
    this.vehicle = null;
    this.size = '';
    this.drawn = null;  // for the tests: {points, vehicle: [px, py] | null}
  }

  // {track: [[t, x, y], ...], vehicle: [t, x, y] | null}
  update({ track, vehicle }) {
    const show = !!(track && track.length);
    if (this.box.hidden === show) this.box.hidden = !show;
    if (!show) {
      this.track = null;
      this.count = -1;
      this.drawn = null;
      return;
    }
    const dpr = globalThis.devicePixelRatio || 1;
    const w = Math.max(60, Math.round((this.box.clientWidth || 200) * dpr));
    const h = Math.max(60, Math.round((this.box.clientHeight || 160) * dpr));
    const size = `${w}x${h}`;
    if (track === this.track && track.length === this.count && vehicle === this.vehicle && size === this.size) return;
    this.track = track;
    this.count = track.length;
    this.vehicle = vehicle;
    this.size = size;
    this.draw(w, h, dpr);
  }

  draw(w, h, dpr) {
    const c = this.canvas;
    if (c.width !== w) c.width = w;
    if (c.height !== h) c.height = h;
    const ctx = c.getContext('2d');
    if (!ctx) return;
    const f = mapFrame(this.track, w, h, 14 * dpr);
    ctx.clearRect(0, 0, w, h);
    if (!f) return;
    // The track: the estimated position, sample by sample.
    ctx.strokeStyle = '#1d5fa8';
    ctx.lineWidth = 1.5 * dpr;
    ctx.beginPath();
    this.track.forEach((p, i) => {
      const [px, py] = f.toPx(p[1], p[2]);
      if (i === 0) ctx.moveTo(px, py); else ctx.lineTo(px, py);
    });
    ctx.stroke();
    // The start, hollow; the vehicle, filled.
    const [sx, sy] = f.toPx(this.track[0][1], this.track[0][2]);
    ctx.strokeStyle = '#556';
    ctx.beginPath();
    ctx.arc(sx, sy, 3 * dpr, 0, 2 * Math.PI);
    ctx.stroke();
    let at = null;
    if (this.vehicle) {
      at = f.toPx(this.vehicle[1], this.vehicle[2]);
      ctx.fillStyle = '#c2185b';
      ctx.beginPath();
      ctx.arc(at[0], at[1], 4.5 * dpr, 0, 2 * Math.PI);
      ctx.fill();
    }
    // A scale bar and north.
    const bar_m = scaleBar((w / 3) / f.k);
    const bar = bar_m * f.k;
    ctx.strokeStyle = '#333';
    ctx.fillStyle = '#333';
    ctx.lineWidth = dpr;
    ctx.beginPath();
    ctx.moveTo(6 * dpr, h - 6 * dpr);
    ctx.lineTo(6 * dpr + bar, h - 6 * dpr);
    ctx.stroke();
    ctx.font = `${Math.round(10 * dpr)}px sans-serif`;
    ctx.textBaseline = 'bottom';
    ctx.fillText(`${bar_m} m`, 6 * dpr, h - 8 * dpr);
    ctx.textBaseline = 'top';
    ctx.fillText('N ↑', w - 26 * dpr, 3 * dpr);
    this.drawn = { points: this.track.length, vehicle: at };
  }
}

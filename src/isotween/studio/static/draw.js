// Drawing sequences and drawings on a canvas: a view (fit, zoom, pan) and filled/stroked paths.
export const PALETTE = ["#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#17becf",
  "#bcbd22", "#7f7f7f"];

export class View {
  constructor(canvas) {
    this.canvas = canvas;
    this.box = [0, 0, 1, 1];
    this.yDown = false;
    this.zoom = 1;
    this.pan = [0, 0];
  }
  fit(box, yDown) {
    this.box = box;
    this.yDown = yDown;
    this.zoom = 1;
    this.pan = [0, 0];
  }
  // world (x, y) -> canvas pixels
  transform() {
    const [x0, y0, x1, y1] = this.box;
    const w = this.canvas.width, h = this.canvas.height;
    const s = 0.8 * Math.min(w / Math.max(x1 - x0, 1e-12), h / Math.max(y1 - y0, 1e-12)) * this.zoom;
    const cx = (x0 + x1) / 2, cy = (y0 + y1) / 2;
    const sy = this.yDown ? s : -s;
    return { s, sx: s, sy, ox: w / 2 + this.pan[0] - s * cx, oy: h / 2 + this.pan[1] - sy * cy };
  }
  toScreen(x, y) {
    const t = this.transform();
    return [t.ox + t.sx * x, t.oy + t.sy * y];
  }
  toWorld(px, py) {
    const t = this.transform();
    return [(px - t.ox) / t.sx, (py - t.oy) / t.sy];
  }
}

export function bbox(values) {
  let x0 = Infinity, y0 = Infinity, x1 = -Infinity, y1 = -Infinity;
  for (let i = 0; i < values.length; i += 2) {
    const x = values[i], y = values[i + 1];
    if (x < x0) x0 = x; if (x > x1) x1 = x; if (y < y0) y0 = y; if (y > y1) y1 = y;
  }
  return [x0, y0, x1, y1];
}

// one frame's path set: `xy(i)` -> [px, py] of vertex i
export function tracePaths(g, paths, xy) {
  for (const [idx, closed] of paths) {
    if (!idx.length) continue;
    g.moveTo(...xy(idx[0]));
    for (let k = 1; k < idx.length; k++) g.lineTo(...xy(idx[k]));
    if (closed) g.closePath();
  }
}

// a frame of a sequence view (groups with per-frame paint) drawn with vertices `v` (flat x, y)
export function drawFrame(g, view, seq, v, k, { alpha = 1, outlineOnly = false, mesh = false, edges = null } = {}) {
  const t = view.transform();
  const xy = (i) => [t.ox + t.sx * v[2 * i], t.oy + t.sy * v[2 * i + 1]];
  g.save();
  g.globalAlpha = alpha;
  seq.groups.forEach((group, n) => {
    const closed = group.paths.some(([, c]) => c);
    g.beginPath();
    tracePaths(g, group.paths, xy);
    const fill = group.fill[k] ?? (closed ? PALETTE[n % PALETTE.length] + "cc" : null);
    if (fill && !outlineOnly) { g.fillStyle = fill; g.fill("evenodd"); }
    g.strokeStyle = group.stroke[k] ?? "#1b1b1b";
    g.lineWidth = group.width[k] ? Math.max(0.5, group.width[k] * t.s) : 1.2;
    g.stroke();
  });
  if (mesh && edges) {
    g.beginPath();
    for (let e = 0; e < edges.length; e += 2) { g.moveTo(...xy(edges[e])); g.lineTo(...xy(edges[e + 1])); }
    g.strokeStyle = "rgba(0,0,0,0.35)"; g.lineWidth = 0.5; g.stroke();
  }
  g.restore();
}

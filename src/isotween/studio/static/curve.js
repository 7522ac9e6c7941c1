// A cubic-bezier easing editor on a small canvas: two draggable control points.
export class CurveEditor {
  constructor(canvas, onChange) {
    this.canvas = canvas;
    this.onChange = onChange;
    this.value = [0, 0, 1, 1];
    this.drag = -1;
    canvas.addEventListener("pointerdown", (e) => this.down(e));
    canvas.addEventListener("pointermove", (e) => this.move(e));
    canvas.addEventListener("pointerup", () => this.up());
    this.draw();
  }
  toScreen(x, y) {
    const m = 14, s = this.canvas.width - 2 * m;
    return [m + x * s, this.canvas.height - m - y * s];
  }
  fromScreen(px, py) {
    const m = 14, s = this.canvas.width - 2 * m;
    const clamp = (v) => Math.min(1, Math.max(0, v));
    return [clamp((px - m) / s), clamp((this.canvas.height - m - py) / s)];
  }
  local(e) {
    const r = this.canvas.getBoundingClientRect();
    return [(e.clientX - r.left) * this.canvas.width / r.width, (e.clientY - r.top) * this.canvas.height / r.height];
  }
  down(e) {
    const [px, py] = this.local(e);
    const d = [0, 1].map((k) => {
      const [x, y] = this.toScreen(this.value[2 * k], this.value[2 * k + 1]);
      return Math.hypot(px - x, py - y);
    });
    this.drag = d[0] < d[1] ? 0 : 1;
    this.canvas.setPointerCapture(e.pointerId);
    this.move(e);
  }
  move(e) {
    if (this.drag < 0) return;
    const [x, y] = this.fromScreen(...this.local(e));
    this.value[2 * this.drag] = Math.round(x * 100) / 100;
    this.value[2 * this.drag + 1] = Math.round(y * 100) / 100;
    this.draw();
  }
  up() {
    if (this.drag < 0) return;
    this.drag = -1;
    this.onChange([...this.value]);
  }
  set(value) {
    this.value = [...value];
    this.draw();
  }
  draw() {
    const g = this.canvas.getContext("2d");
    const [x1, y1, x2, y2] = this.value;
    g.clearRect(0, 0, this.canvas.width, this.canvas.height);
    g.strokeStyle = "#ddd";
    g.strokeRect(...this.toScreen(0, 1), this.canvas.width - 28, this.canvas.height - 28);
    g.strokeStyle = "#999";
    g.beginPath(); g.moveTo(...this.toScreen(0, 0)); g.lineTo(...this.toScreen(x1, y1));
    g.moveTo(...this.toScreen(1, 1)); g.lineTo(...this.toScreen(x2, y2)); g.stroke();
    g.strokeStyle = "#1f5fa8"; g.lineWidth = 2;
    g.beginPath(); g.moveTo(...this.toScreen(0, 0));
    g.bezierCurveTo(...this.toScreen(x1, y1), ...this.toScreen(x2, y2), ...this.toScreen(1, 1)); g.stroke();
    g.lineWidth = 1; g.fillStyle = "#c0392b";
    for (const [x, y] of [[x1, y1], [x2, y2]]) {
      const [px, py] = this.toScreen(x, y);
      g.beginPath(); g.arc(px, py, 5, 0, 2 * Math.PI); g.fill();
    }
  }
}

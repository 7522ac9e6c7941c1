// Morph the drawings benchmark's pairs with GSAP's MorphSVGPlugin, headless (no DOM), with its defaults.
// Usage: node gsap_drawings.js PAIRS.json FRAMES > OUT.jsonl
// PAIRS.json: [{"id": k, "a": source path data, "b": target path data}], the path data of every
// subpath of the drawing as isotween reads it (M ... L ... Z). The approach of benchmarks/gsap_run.js
// (branch motionbench): the morph is what `gsap.to(path, {morphSVG: target})` does to a <path>
// element, on a plain object holding the path data (the plugin's `prop` option), with a linear ease
// so that frame k is time k / (FRAMES - 1); here all pairs run in one process.
// Prints one JSON line per pair: {id, ok, error?, seconds, frames?: [frame][subpath]
// {closed, points: [x0, y0, cx1, cy1, cx2, cy2, x1, y1, ...]}} (cubic Beziers).
"use strict";
const fs = require("fs");
const path = require("path");

const pairs = JSON.parse(fs.readFileSync(process.argv[2], "utf8"));
const frames = parseInt(process.argv[3] || "21", 10);
const modules = path.join(__dirname, ".corpus", "node_modules");
const load = (name) => require(require.resolve(name, { paths: [modules] }));
const { gsap } = load("gsap");
const { MorphSVGPlugin } = load("gsap/MorphSVGPlugin");
MorphSVGPlugin.headless = true; // register without a window: the plugin then needs no DOM for `prop` targets
gsap.registerPlugin(MorphSVGPlugin);

for (const p of pairs) {
  const out = { id: p.id };
  const t0 = process.hrtime.bigint();
  try {
    const obj = { d: p.a };
    const tween = gsap.to(obj, { morphSVG: { shape: p.b, prop: "d" }, duration: 1, ease: "none", paused: true });
    out.frames = [];
    for (let k = 0; k < frames; k++) {
      tween.progress(k / (frames - 1));
      const raw = MorphSVGPlugin.stringToRawPath(obj.d);
      out.frames.push(raw.map((seg) => ({ closed: !!seg.closed, points: Array.from(seg) })));
    }
    tween.kill();
    out.ok = true;
  } catch (err) {
    out.ok = false;
    out.error = String(err && err.message ? err.message : err);
  }
  out.seconds = Number(process.hrtime.bigint() - t0) / 1e9;
  process.stdout.write(JSON.stringify(out) + "\n");
}

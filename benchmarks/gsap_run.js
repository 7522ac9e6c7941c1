// Morph one drawing pair with GSAP's MorphSVGPlugin, headless (no DOM), with its defaults.
// Usage: node gsap_run.js PAIR.json FRAMES > OUT.json
// PAIR.json: {"a": source path data, "b": target path data, "modules": node_modules folder}.
// The morph is what `gsap.to(path, {morphSVG: target})` does to a <path> element, on a plain
// object holding the path data (the plugin's `prop` option), with a linear ease so that frame
// k is time k / (FRAMES - 1). Prints {ok, error?, seconds, frames?: [frame][subpath]
// {closed, points: [x0, y0, cx1, cy1, cx2, cy2, x1, y1, ...]}} (cubic Beziers, as the
// plugin's stringToRawPath gives them).
"use strict";
const fs = require("fs");
const path = require("path");

const pair = JSON.parse(fs.readFileSync(process.argv[2], "utf8"));
const frames = parseInt(process.argv[3] || "21", 10);
// resolved through the package's exports map (its dist/ builds), as `require("gsap/MorphSVGPlugin")` would
const load = (name) => require(require.resolve(name, { paths: [pair.modules] }));
const { gsap } = load("gsap");
const { MorphSVGPlugin } = load("gsap/MorphSVGPlugin");

const out = {};
const t0 = process.hrtime.bigint();
try {
  MorphSVGPlugin.headless = true; // register without a window: the plugin then needs no DOM for `prop` targets
  gsap.registerPlugin(MorphSVGPlugin);
  const obj = { d: pair.a };
  const tween = gsap.to(obj, { morphSVG: { shape: pair.b, prop: "d" }, duration: 1, ease: "none", paused: true });
  out.frames = [];
  for (let k = 0; k < frames; k++) {
    tween.progress(k / (frames - 1));
    const raw = MorphSVGPlugin.stringToRawPath(obj.d);
    out.frames.push(raw.map((seg) => ({ closed: !!seg.closed, points: Array.from(seg) })));
  }
  out.ok = true;
} catch (err) {
  out.ok = false;
  out.error = String(err && err.message ? err.message : err);
}
out.seconds = Number(process.hrtime.bigint() - t0) / 1e9;
out.version = MorphSVGPlugin.version;
process.stdout.write(JSON.stringify(out) + "\n");

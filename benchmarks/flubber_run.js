// Morph the benchmark's drawing pairs with flubber, the web's common shape tweener.
// Usage: node flubber_run.js PAIRS.json FRAMES > OUT.jsonl
// PAIRS.json: [{"id": k, "a": [ring, ...], "b": [ring, ...], "seg": max segment length}],
// each ring a list of [x, y]. Every subpath is passed as its own ring, which is how
// flubber morphs drawings of several pieces: one ring each side -> interpolate;
// equal counts -> interpolateAll (in order); one into several -> separate; several
// into one -> combine. Several into a different several has no flubber call.
// Prints one JSON line per pair: {id, ok, mode, error?, seconds, frames?: [frame][ring][point]}.
"use strict";
const fs = require("fs");
const path = require("path");
const flubber = require(path.join(__dirname, ".corpus", "node_modules", "flubber"));

const pairs = JSON.parse(fs.readFileSync(process.argv[2], "utf8"));
const frames = parseInt(process.argv[3] || "9", 10);

for (const p of pairs) {
  const opts = { string: false, single: false, maxSegmentLength: p.seg };
  const na = p.a.length, nb = p.b.length;
  let mode = null;
  const out = { id: p.id };
  const t0 = process.hrtime.bigint();
  try {
    let fns;
    if (na === 1 && nb === 1) {
      mode = "interpolate";
      fns = [flubber.interpolate(p.a[0], p.b[0], opts)];
    } else if (na === nb) {
      mode = "interpolateAll";
      fns = flubber.interpolateAll(p.a, p.b, opts);
    } else if (na === 1) {
      mode = "separate";
      fns = flubber.separate(p.a[0], p.b, opts);
    } else if (nb === 1) {
      mode = "combine";
      fns = flubber.combine(p.a, p.b[0], opts);
    } else {
      throw new Error(`no flubber call morphs ${na} rings into ${nb}`);
    }
    out.frames = [];
    for (let k = 0; k < frames; k++) {
      const t = k / (frames - 1);
      out.frames.push(fns.map((f) => f(t)));
    }
    out.ok = true;
  } catch (err) {
    out.ok = false;
    out.error = String(err && err.message ? err.message : err);
  }
  out.mode = mode;
  out.seconds = Number(process.hrtime.bigint() - t0) / 1e9;
  process.stdout.write(JSON.stringify(out) + "\n");
}

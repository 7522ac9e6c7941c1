// isotween studio: the page. State lives on the server; this module draws it and sends the user's actions.
import { ApiError, download, get, post, postJson, unpack } from "./api.js";
import { CurveEditor } from "./curve.js";
import { bbox, drawFrame, PALETTE, tracePaths, View } from "./draw.js";

const $ = (id) => document.getElementById(id);
const stage = $("stage");
const view = new View(stage);
const S = {
  state: null, seq: null, frames: null, edges: null, frame: 0, playing: false, lastTick: 0,
  preview: null, drag: null, pins: new Set(), request: 0, busy: 0, corrPick: null, showing: "morph",
  timings: [], lastEditMs: null,
};
window.__studio = S;  // for tests and benchmarks

// ------------------------------------------------------------------ messages and requests
function message(text, error = false) {
  const el = $("message");
  el.textContent = text || "";
  el.classList.toggle("error", !!error);
}

async function watchProgress(id) {
  await new Promise((r) => setTimeout(r, 300));
  while (S.busy && S.request === id) {
    try {
      const p = await get("api/progress");
      if (S.busy && S.request === id && p.stage !== "idle") {
        message(`solving: ${p.stage}${p.iteration !== undefined ? `, iteration ${p.iteration}` : ""}…`);
      }
    } catch (e) { /* the answer of the request itself reports errors */ }
    await new Promise((r) => setTimeout(r, 250));
  }
}

// an action that changes the session: newer actions supersede older ones
async function act(path, body) {
  const id = ++S.request;
  S.busy++;
  watchProgress(id);
  const started = performance.now();
  try {
    const answer = await postJson(path, body);
    if (id !== S.request || answer.superseded) return null;  // a newer action replaced this one
    setState(answer);
    message(answer.notes?.length ? answer.notes.join("; ") : `solved in ${Math.round(performance.now() - started)} ms`);
    if (answer.preview) {  // outlines shown at once; the meshes follow (dropped if a newer action comes first)
      message("outline preview: meshing the filled regions…");
      setTimeout(() => { if (S.request === id) act("api/refine"); }, 0);
    }
    return answer;
  } catch (e) {
    if (id === S.request) {
      message(e instanceof ApiError ? e.message : `error: ${e}`, true);
      syncControls();
    }
    return null;
  } finally {
    S.busy--;
  }
}

// ------------------------------------------------------------------ state
function setState(state) {
  const previousCount = S.seq?.count;
  S.state = state;
  $("undo").disabled = !state.undo;
  $("redo").disabled = !state.redo;
  const doc = state.document;
  $("drop-hint").hidden = !!doc;
  $("view-which").querySelector("[value=transfer]").disabled = !state.transfer;
  if (!state.transfer && S.showing === "transfer") { S.showing = "morph"; $("view-which").value = "morph"; }
  if (!doc) { draw(); return; }
  syncControls();
  $("third-name").textContent = state.third_name ? `onto ${state.third_name}` : "";
  $("corr-summary").textContent = state.correspondence.summary;
  useSequence(S.showing === "transfer" ? state.transfer : state.sequence, previousCount);
  drawCorrespondence();
  if (!state.preview) S.finalAt = performance.now();  // drawn: the final morph (not an outline preview)
}

// the option controls show the session's document (also after a refused change)
function syncControls() {
  const doc = S.state?.document;
  if (!doc) return;
  $("frames").value = doc.options.frames;
  $("method").value = doc.options.method;
  $("strokes").value = doc.options.strokes;
  $("fit").checked = !!doc.options.fit;
  $("points").value = doc.options.points ?? "";
  $("roi").value = doc.options.roi;
  const curves = segmentCurves();
  const segments = curves.length;
  const pick = $("easing-segment");
  if (pick.options.length !== segments) {
    pick.replaceChildren(...curves.map((_, j) => new Option(`segment ${j + 1}`, String(j))));
  }
  pick.hidden = segments < 2;
  const current = curves[Math.min(Number(pick.value) || 0, segments - 1)];
  curve.set(current);
  $("easing-text").textContent = `cubic-bezier(${current.join(", ")})`;
}

function useSequence(seq, previousCount) {
  const drawing = `${S.showing}:${S.state.document.inputs.join(",")}:${S.state.document.third}`;
  const fresh = !S.seq || S.seq.n !== seq.n || S.seq.count !== seq.count || previousCount === undefined ||
    drawing !== S.drawing;
  S.drawing = drawing;
  S.seq = seq;
  S.frames = unpack(seq.frames);
  S.edges = unpack(seq.edges, Int32Array);
  S.preview = null;
  if (fresh) {
    S.pins.clear();
    const b = bbox(S.frames);
    view.fit(b, seq.y_down);
  }
  S.frame = Math.min(S.frame, seq.count - 1);
  $("scrub").max = seq.count - 1;
  $("scrub").value = S.frame;
  $("keys").replaceChildren(...seq.keys.map((k) => {
    const mark = document.createElement("span");
    mark.style.left = `${(100 * k) / Math.max(seq.count - 1, 1)}%`;
    mark.title = `key frame ${k}`;
    return mark;
  }));
  draw();
}

function frameVertices(k) {
  const n2 = 2 * S.seq.n;
  return S.frames.subarray(k * n2, (k + 1) * n2);
}

// ------------------------------------------------------------------ drawing
function resize() {
  const r = stage.getBoundingClientRect();
  const ratio = window.devicePixelRatio || 1;
  stage.width = Math.max(1, Math.round(r.width * ratio));
  stage.height = Math.max(1, Math.round(r.height * ratio));
  draw();
}

function draw() {
  const g = stage.getContext("2d");
  g.clearRect(0, 0, stage.width, stage.height);
  if (!S.seq) return;
  const k = S.frame;
  if ($("onion").checked) {
    for (const [d, a] of [[-2, 0.12], [-1, 0.25], [1, 0.25], [2, 0.12]]) {
      const j = k + d;
      if (j >= 0 && j < S.seq.count) drawFrame(g, view, S.seq, frameVertices(j), j, { alpha: a, outlineOnly: true });
    }
  }
  const v = S.preview && S.preview.frame === k ? S.preview.vertices : frameVertices(k);
  drawFrame(g, view, S.seq, v, k, { mesh: $("show-mesh").checked, edges: S.edges });
  const ratio = window.devicePixelRatio || 1;
  g.fillStyle = "#c0392b";
  for (const i of [...S.pins, ...(S.drag ? [S.drag.vertex] : [])]) {
    const [x, y] = view.toScreen(v[2 * i], v[2 * i + 1]);
    g.beginPath(); g.arc(x, y, 5 * ratio, 0, 2 * Math.PI); g.fill();
  }
  $("frame-label").textContent = `frame ${k + 1} / ${S.seq.count}${S.seq.keys.includes(k) ? " (key)" : ""}`;
  S.drawn = performance.now();
}

// ------------------------------------------------------------------ playback
function tick(now) {
  if (S.playing && S.seq) {
    const duration = Math.max(0.1, Number($("duration").value) || 1.5) * 1000;
    const step = duration / Math.max(S.seq.count - 1, 1);
    if (now - S.lastTick >= step) {
      S.lastTick = now;
      let k = S.frame + 1;
      if (k >= S.seq.count) {
        if ($("loop").checked) k = 0;
        else { k = S.seq.count - 1; setPlaying(false); }
      }
      S.frame = k;
      $("scrub").value = k;
      draw();
    }
  }
  requestAnimationFrame(tick);
}

function setPlaying(on) {
  S.playing = on;
  $("play").textContent = on ? "Pause" : "Play";
}

// ------------------------------------------------------------------ editing: drag handle points
function pointer(e) {
  const r = stage.getBoundingClientRect();
  return [(e.clientX - r.left) * stage.width / r.width, (e.clientY - r.top) * stage.height / r.height];
}

function nearestVertex(px, py) {
  const v = frameVertices(S.frame);
  const t = view.transform();
  let best = -1, bestD = 12 * (window.devicePixelRatio || 1);
  for (let i = 0; i < S.seq.n; i++) {
    const d = Math.hypot(t.ox + t.sx * v[2 * i] - px, t.oy + t.sy * v[2 * i + 1] - py);
    if (d < bestD) { bestD = d; best = i; }
  }
  return best;
}

function handles() {
  const v = frameVertices(S.frame);
  const list = [...S.pins].filter((i) => i !== S.drag.vertex).map((i) => [i, v[2 * i], v[2 * i + 1]]);
  list.push([S.drag.vertex, ...S.drag.to]);
  return list;
}

async function sendPreview() {
  if (!S.drag || S.drag.inFlight) return;
  S.drag.inFlight = true;
  S.drag.dirty = false;
  const frame = S.frame;
  try {
    const answer = await postJson("api/deform", { frame, handles: handles(), anchor: S.drag.vertex });
    if (S.drag && answer.frame === S.frame) {
      S.preview = { frame, vertices: unpack(answer.vertices) };
      draw();
    }
  } catch (e) {
    message(e.message, true);
  } finally {
    if (S.drag) {
      S.drag.inFlight = false;
      if (S.drag.dirty) sendPreview();
    }
  }
}

stage.addEventListener("pointerdown", (e) => {
  if (!S.seq) return;
  const [px, py] = pointer(e);
  if (e.button === 1 || e.button === 2) {
    S.panning = { from: [px, py], pan: [...view.pan] };
    stage.setPointerCapture(e.pointerId);
    return;
  }
  if (S.showing !== "morph") { message("switch the view to 'morph' to edit frames"); return; }
  if (S.state?.preview) { message("the meshes are being solved; drag again in a moment"); return; }
  const i = nearestVertex(px, py);
  if (i < 0) {
    S.panning = { from: [px, py], pan: [...view.pan] };
    stage.setPointerCapture(e.pointerId);
    return;
  }
  if (e.shiftKey) {
    if (S.pins.has(i)) S.pins.delete(i); else S.pins.add(i);
    draw();
    return;
  }
  setPlaying(false);
  const v = frameVertices(S.frame);
  S.drag = { vertex: i, to: [v[2 * i], v[2 * i + 1]], moved: false };
  stage.setPointerCapture(e.pointerId);
});

stage.addEventListener("pointermove", (e) => {
  const [px, py] = pointer(e);
  if (S.panning) {
    view.pan = [S.panning.pan[0] + px - S.panning.from[0], S.panning.pan[1] + py - S.panning.from[1]];
    draw();
    return;
  }
  if (!S.drag) return;
  S.drag.to = view.toWorld(px, py);
  S.drag.moved = true;
  S.drag.dirty = true;
  sendPreview();
});

stage.addEventListener("pointerup", async () => {
  if (S.panning) { S.panning = null; return; }
  if (!S.drag) return;
  const drag = S.drag;
  if (!drag.moved) { S.drag = null; draw(); return; }
  const body = { frame: S.frame, handles: handles(), anchor: drag.vertex };
  const released = performance.now();
  S.drag = null;
  const answer = await act("api/edit", body);
  if (answer) {
    await new Promise((r) => requestAnimationFrame(() => r()));
    S.lastEditMs = performance.now() - released;
    S.timings.push(S.lastEditMs);
    message(`frame ${body.frame + 1} is a key now; re-solved and drawn in ${Math.round(S.lastEditMs)} ms`);
  } else {
    S.preview = null;
    draw();
  }
});

stage.addEventListener("contextmenu", (e) => e.preventDefault());
stage.addEventListener("wheel", (e) => {
  e.preventDefault();
  const [px, py] = pointer(e);
  const before = view.toWorld(px, py);
  view.zoom *= Math.exp(-e.deltaY * 0.0015);
  const after = view.toScreen(...before);
  view.pan = [view.pan[0] + px - after[0], view.pan[1] + py - after[1]];
  draw();
}, { passive: false });

// ------------------------------------------------------------------ correspondence view
const corrViews = [new View($("corr-0")), new View($("corr-1"))];

function drawCorrespondence() {
  const corr = S.state?.correspondence;
  corrViews.forEach((cv, side) => {
    const g = cv.canvas.getContext("2d");
    g.clearRect(0, 0, cv.canvas.width, cv.canvas.height);
    if (!corr) return;
    const input = corr.inputs[side];
    const all = input.items.flatMap((it) => it.rings.flat(2));
    cv.fit(bbox(all), input.y_down);
    const t = cv.transform();
    const xy = (p) => [t.ox + t.sx * p[0], t.oy + t.sy * p[1]];
    cv.paths = [];
    input.items.forEach((item) => {
      const path = new Path2D();
      for (const ring of item.rings) {
        path.moveTo(...xy(ring[0]));
        for (const p of ring.slice(1)) path.lineTo(...xy(p));
        if (item.kind !== "line") path.closePath();
      }
      const pair = item.kind === "region" ? corr.pairs.findIndex((p) => p[side] === item.index) : -1;
      const picked = S.corrPick && S.corrPick.side === side && S.corrPick.index === item.index;
      if (item.kind === "region") {
        g.fillStyle = pair >= 0 ? PALETTE[pair % PALETTE.length] + "88" : "#cccccc88";
        g.fill(path, "evenodd");
        cv.paths.push({ path, index: item.index });
      }
      g.strokeStyle = picked ? "#000" : "#555";
      g.lineWidth = picked ? 2.5 : 1;
      g.stroke(path);
    });
    corr.rings.forEach((ring, r) => {
      const pts = side === 0 ? ring.source : ring.target;
      pts.forEach((p, k) => {
        g.fillStyle = PALETTE[(r + k) % PALETTE.length];
        g.beginPath(); g.arc(...xy(p), k === 0 ? 4.5 : 2.5, 0, 2 * Math.PI); g.fill();
        if (k === 0) { g.strokeStyle = "#000"; g.stroke(); }
      });
    });
    (S.state.document.landmarks || []).forEach((pair, n) => {
      const [x, y] = xy(pair[side]);
      g.strokeStyle = "#000"; g.lineWidth = 1.5;
      g.beginPath(); g.moveTo(x - 4, y - 4); g.lineTo(x + 4, y + 4); g.moveTo(x + 4, y - 4); g.lineTo(x - 4, y + 4);
      g.stroke();
      g.fillStyle = "#000"; g.fillText(String(n + 1), x + 5, y - 5);
    });
    if (S.corrPick?.side === side && S.corrPick.point) {
      const [x, y] = xy(S.corrPick.point);
      g.strokeStyle = "#c0392b"; g.beginPath(); g.arc(x, y, 6, 0, 2 * Math.PI); g.stroke();
    }
  });
}

function corrClick(side, e) {
  const corr = S.state?.correspondence;
  if (!corr) return;
  const cv = corrViews[side];
  const r = cv.canvas.getBoundingClientRect();
  const px = (e.clientX - r.left) * cv.canvas.width / r.width, py = (e.clientY - r.top) * cv.canvas.height / r.height;
  const mode = document.querySelector("input[name=corr-mode]:checked").value;
  const doc = S.state.document;
  if (mode === "landmark") {
    const point = cv.toWorld(px, py);
    if (!S.corrPick || S.corrPick.side === side || !S.corrPick.point) {
      S.corrPick = { side, point };
      drawCorrespondence();
      message(`now click the matching point on the ${side === 0 ? "target" : "source"}`);
      return;
    }
    const pair = side === 1 ? [S.corrPick.point, point] : [point, S.corrPick.point];
    S.corrPick = null;
    drawCorrespondence();  // a refused landmark (off the drawing) leaves no pick behind; its message says why
    act("api/hints", { landmarks: [...doc.landmarks, pair], quick: true });
    return;
  }
  const g = cv.canvas.getContext("2d");
  const hit = (cv.paths || []).find((p) => g.isPointInPath(p.path, px, py, "evenodd"));
  if (!hit) return;
  if (!S.corrPick || S.corrPick.side === side || S.corrPick.point) {
    const existing = doc.pairs.findIndex((p) => p[side] === hit.index);
    if (existing >= 0 && S.corrPick?.side === side && S.corrPick.index === hit.index) {  // second click: unpair
      S.corrPick = null;
      act("api/hints", { pairs: doc.pairs.filter((_, n) => n !== existing), quick: true });
      return;
    }
    S.corrPick = { side, index: hit.index };
    drawCorrespondence();
    message(`region ${hit.index} picked: click its partner on the ${side === 0 ? "target" : "source"} (click it again to unpair)`);
    return;
  }
  const pair = side === 1 ? [S.corrPick.index, hit.index] : [hit.index, S.corrPick.index];
  S.corrPick = null;
  act("api/hints", { pairs: [...doc.pairs.filter((p) => p[0] !== pair[0] && p[1] !== pair[1]), pair], quick: true });
}

corrViews.forEach((cv, side) => cv.canvas.addEventListener("click", (e) => corrClick(side, e)));
$("clear-hints").onclick = () => act("api/hints", { pairs: [], landmarks: [], quick: true });

// ------------------------------------------------------------------ opening files
async function upload(files) {
  const form = new FormData();
  for (const f of files) form.append("file", f, f.name);
  return postJson("api/upload", form);
}

async function openFiles(files, role) {
  files = [...files];
  if (!files.length) return null;
  try {
    if (role === "project") return act("api/project", await files[0].text());
    if (role !== "third" && files.length > 2) files.sort((a, b) => a.name.localeCompare(b.name, undefined, { numeric: true }));
    const { ids } = await upload(files);
    const answer = await act("api/open", { inputs: ids, role, quick: true });
    if (answer) setPlaying(true);
    return answer;
  } catch (e) {
    message(e.message, true);
    return null;
  }
}

$("open-files").onchange = (e) => { openFiles(e.target.files); e.target.value = ""; };
$("open-third").onchange = (e) => { openFiles(e.target.files, "third"); e.target.value = ""; };
$("open-project").onchange = (e) => { openFiles(e.target.files, "project"); e.target.value = ""; };
$("drop-third").onclick = () => act("api/third", { input: null });
$("example").onchange = async (e) => {
  const name = e.target.value;
  e.target.value = "";
  if (name && await act("api/open", { example: name, quick: true })) setPlaying(true);
};
$("cli-files").onchange = (e) => {
  const files = S.state.files;
  const k = Number(e.target.value);
  if (e.target.value !== "") act("api/open", { paths: [files[k], files[(k + 1) % files.length]], quick: true });
};
document.addEventListener("dragover", (e) => { e.preventDefault(); document.body.classList.add("dragging"); });
document.addEventListener("dragleave", () => document.body.classList.remove("dragging"));
document.addEventListener("drop", (e) => {
  e.preventDefault();
  document.body.classList.remove("dragging");
  const files = [...e.dataTransfer.files];
  const project = files.length === 1 && files[0].name.endsWith("project.json");
  const lone = files.length === 1 && S.state?.document && !/\.(npz|json)$/i.test(files[0].name);
  openFiles(files, project ? "project" : lone ? "third" : undefined);
});

// ------------------------------------------------------------------ options, undo, export, projects
function setOptions(options) { return act("api/options", options); }

// the easing of every segment between keyframes (one cubic-bezier each)
function segmentCurves() {
  const doc = S.state.document;
  const segments = doc.inputs.length - 1;
  const easing = doc.options.easing;
  const list = Array.isArray(easing[0]) ? easing : [easing];
  return Array.from({ length: segments }, (_, j) => list[Math.min(j, list.length - 1)]);
}

function setEasing(value) {
  const curves = segmentCurves();
  if (curves.length === 1) return setOptions({ easing: value });
  curves[Number($("easing-segment").value) || 0] = value;
  return setOptions({ easing: curves });
}

const curve = new CurveEditor($("curve"), setEasing);
$("easing-preset").onchange = (e) => setEasing(e.target.value.split(",").map(Number));
$("easing-segment").onchange = () => { if (S.state?.document) setState(S.state); };
$("frames").onchange = (e) => setOptions({ frames: Math.round(Number(e.target.value)) });
$("method").onchange = (e) => setOptions({ method: e.target.value });
$("strokes").onchange = (e) => setOptions({ strokes: e.target.value });
$("fit").onchange = (e) => setOptions({ fit: e.target.checked });
$("points").onchange = (e) => setOptions({ points: e.target.value === "" ? null : Math.round(Number(e.target.value)) });
$("roi").onchange = (e) => setOptions({ roi: Number(e.target.value) });
$("undo").onclick = () => act("api/undo");
$("redo").onclick = () => act("api/redo");
$("clear-edits").onclick = () => act("api/clear_edits");
$("fit").onclick = () => { if (S.seq) { view.fit(bbox(S.frames), S.seq.y_down); draw(); } };
$("onion").onchange = draw;
$("show-mesh").onchange = draw;
$("view-which").onchange = (e) => {
  S.showing = e.target.value;
  if (S.state?.document) useSequence(S.showing === "transfer" ? S.state.transfer : S.state.sequence);
};
$("play").onclick = () => setPlaying(!S.playing);
$("scrub").oninput = (e) => { setPlaying(false); S.frame = Number(e.target.value); draw(); };

$("export").onclick = async () => {
  const kind = $("export-kind").value;
  message(`exporting ${kind}…`);
  try {
    const response = await post("api/export", {
      kind, fps: Number($("export-fps").value), size: Number($("export-size").value), which: S.showing,
      duration: Math.max(0.1, Number($("duration").value) || 1.5),  // the motion lasts as long as it plays here
      bounce: $("export-bounce").checked, hold: Number($("export-hold").value), background: $("export-background").value,
    });
    const name = (response.headers.get("content-disposition") || "").match(/filename="([^"]+)"/)?.[1] || `isotween.${kind}`;
    download(await response.blob(), name);
    message(`exported ${name}`);
  } catch (e) {
    message(e.message, true);
  }
};

$("save-project").onclick = async () => {
  try {
    const response = await fetch("api/project", { headers: { "X-Isotween-Token": new URLSearchParams(location.search).get("token") } });
    if (!response.ok) throw new ApiError((await response.json()).error);
    download(await response.blob(), "isotween-project.json");
    message("project saved");
  } catch (e) {
    message(e.message, true);
  }
};

document.addEventListener("keydown", (e) => {
  if (e.target instanceof HTMLInputElement && e.target.type !== "range" && e.target.type !== "checkbox") return;
  if (e.key === " ") { e.preventDefault(); setPlaying(!S.playing); }
  else if ((e.ctrlKey || e.metaKey) && e.key.toLowerCase() === "z") { e.preventDefault(); act(e.shiftKey ? "api/redo" : "api/undo"); }
  else if (e.key === "ArrowRight" && S.seq) { S.frame = Math.min(S.frame + 1, S.seq.count - 1); $("scrub").value = S.frame; draw(); }
  else if (e.key === "ArrowLeft" && S.seq) { S.frame = Math.max(S.frame - 1, 0); $("scrub").value = S.frame; draw(); }
});

// ------------------------------------------------------------------ test and benchmark helpers
S.vertexOnPage = (k, i) => {
  const n2 = 2 * S.seq.n;
  const v = S.frames.subarray(k * n2, (k + 1) * n2);
  const [x, y] = view.toScreen(v[2 * i], v[2 * i + 1]);
  const r = stage.getBoundingClientRect();
  return [r.left + (x * r.width) / stage.width, r.top + (y * r.height) / stage.height];
};
S.corrOnPage = (side, x, y) => {  // a drawing's point in the correspondence view, in page pixels
  const cv = corrViews[side];
  const [px, py] = cv.toScreen(x, y);
  const r = cv.canvas.getBoundingClientRect();
  return [r.left + (px * r.width) / cv.canvas.width, r.top + (py * r.height) / cv.canvas.height];
};
S.setFrame = (k) => { setPlaying(false); S.frame = k; $("scrub").value = k; draw(); };
S.act = act;
// an action timed from the request to the animation frame after the answer is drawn, and (when the answer
// was an outline preview) to the final morph drawn: {first, final} in ms, null when refused
S.timed = async (path, body) => {
  const started = performance.now();
  const answer = await act(path, body);
  await new Promise((r) => requestAnimationFrame(() => r()));
  if (!answer) return null;
  const first = performance.now() - started;
  while (S.state.preview) await new Promise((r) => setTimeout(r, 2));
  return { first, final: answer.preview ? S.finalAt - started : first };
};

// ------------------------------------------------------------------ start
async function start() {
  const state = await get("api/state");
  for (const m of state.methods) $("method").append(new Option(m, m));
  for (const e of state.examples) {
    const o = new Option(e.name, e.name);
    o.title = e.description;
    $("example").append(o);
  }
  for (const k of state.export_kinds) $("export-kind").append(new Option(k, k));
  if (state.files.length) {
    $("cli-files").hidden = false;
    $("cli-files").append(new Option("Command-line files…", ""));
    state.files.forEach((f, k) => $("cli-files").append(new Option(f.split(/[\\/]/).pop(), String(k))));
  }
  window.addEventListener("resize", resize);
  resize();
  setState(state);
  if (state.document) setPlaying(true);
  if (state.document && state.notes?.length) message(state.notes.join("; "));  // files named on the command line
  requestAnimationFrame(tick);
  S.ready = true;
}

start().catch((e) => message(`the studio could not start: ${e.message}`, true));

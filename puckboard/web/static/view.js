// The web view: draws the scene and a frame, live from the server's event stream or, in a
// replay (replay.js), from a recorded run. Plain JavaScript, no libraries: it must work
// offline, from a file, on a projector and on a phone.
"use strict";

const FAILURES = new Set(["collision", "lost_line", "parallel_driving", "stuck", "turned_back"]);
// state.player is the replay's player (replay.js) when the page replays a recording;
// state.previous the run a served world's restore ended ({t, trails}), shown as such;
// state.spots where each robot's name was put last (kept while it stays clear)
var state = { scene: null, frame: null, trails: {}, run: null, previous: null, details: {}, selected: null,
              view: null, player: null, spots: {} };
const canvas = document.getElementById("arena");
const ctx = canvas.getContext("2d");

function $(id) { return document.getElementById(id); }

function el(tag, attrs, text) {
  const node = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs || {})) node.setAttribute(k, v);
  if (text !== undefined) node.textContent = text;
  return node;
}

// -- geometry: world metres to canvas pixels, keeping the aspect ratio ------------------------
function fit() {
  const ratio = window.devicePixelRatio || 1;
  if (state.scene) {  // one column (a phone): the arena only as tall as the scene needs
    const [x0, y0, x1, y1] = state.scene.bounds, pad = 0.12 * Math.max(x1 - x0, y1 - y0);
    const tall = canvas.clientWidth * (y1 - y0 + pad) / (x1 - x0 + pad);
    canvas.style.height = matchMedia("(max-width: 800px)").matches ? `${Math.round(Math.min(tall, 0.6 * innerHeight))}px` : "";
  }
  const w = canvas.clientWidth, h = canvas.clientHeight;
  canvas.width = Math.round(w * ratio);
  canvas.height = Math.round(h * ratio);
  if (!state.scene) return;
  const [x0, y0, x1, y1] = state.scene.bounds;
  const pad = 0.06 * Math.max(x1 - x0, y1 - y0);
  const sx = w / (x1 - x0 + 2 * pad), sy = h / (y1 - y0 + 2 * pad);
  const s = Math.min(sx, sy) * ratio;
  const cx = (x0 + x1) / 2, cy = (y0 + y1) / 2;
  state.view = { s, ox: canvas.width / 2 - s * cx, oy: canvas.height / 2 + s * cy, ratio };
}

function px(x, y) { const v = state.view; return [v.ox + v.s * x, v.oy - v.s * y]; }

// -- drawing ------------------------------------------------------------------------------------
function draw() {
  const sc = state.scene;
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  if (!sc || !state.view) return;
  const v = state.view;
  if (sc.arena) {
    const [ax, ay] = px(sc.arena.xmin, sc.arena.ymax), [bx, by] = px(sc.arena.xmax, sc.arena.ymin);
    ctx.fillStyle = sc.floor; ctx.fillRect(ax, ay, bx - ax, by - ay);
    ctx.strokeStyle = sc.arena.colour; ctx.lineWidth = 4 * v.ratio; ctx.strokeRect(ax, ay, bx - ax, by - ay);
  }
  if (sc.track) {
    ctx.strokeStyle = sc.track.colour; ctx.lineWidth = Math.max(1, sc.track.width * v.s);
    ctx.lineJoin = "round"; ctx.beginPath();
    sc.track.points.forEach(([x, y], i) => { const [u, w] = px(x, y); i ? ctx.lineTo(u, w) : ctx.moveTo(u, w); });
    if (sc.track.closed) ctx.closePath();
    ctx.stroke();
  }
  for (const ob of sc.obstacles) {
    ctx.fillStyle = ob.colour; ctx.beginPath();
    if (ob.circle) { const [u, w] = px(ob.circle[0], ob.circle[1]); ctx.arc(u, w, ob.circle[2] * v.s, 0, 2 * Math.PI); }
    else ob.polygon.forEach(([x, y], i) => { const [u, w] = px(x, y); i ? ctx.lineTo(u, w) : ctx.moveTo(u, w); });
    ctx.fill();
  }
  const dummyBoxes = sc.dummies.map(d => {
    const [u, w] = px(d.x, d.y), r = 8 * v.ratio;
    ctx.strokeStyle = "#444"; ctx.lineWidth = 2 * v.ratio; ctx.beginPath();
    ctx.moveTo(u - r, w); ctx.lineTo(u + r, w); ctx.moveTo(u, w - r); ctx.lineTo(u, w + r); ctx.stroke();
    const box = label(d.name, u + r, w - r, "#444");
    return [Math.min(box[0], u - r), Math.min(box[1], w - r), Math.max(box[2], u + r), Math.max(box[3], w + r)];
  });
  const frame = state.frame;
  if (state.previous) {  // the previous run's trails: faded and dashed, under everything
    ctx.setLineDash([6 * v.ratio, 6 * v.ratio]); ctx.globalAlpha = 0.35; ctx.lineWidth = 2 * v.ratio;
    for (const spec of sc.robots) {
      const trail = state.previous.trails[spec.name] || [];
      ctx.strokeStyle = spec.colour; ctx.beginPath();
      trail.forEach(([x, y], k) => { const [u, w] = px(x, y); k ? ctx.lineTo(u, w) : ctx.moveTo(u, w); });
      ctx.stroke();
    }
    ctx.setLineDash([]); ctx.globalAlpha = 1;
  }
  const names = [];  // robot names, placed once every body is drawn
  sc.robots.forEach((spec, i) => {
    const trail = state.trails[spec.name] || [];
    if (trail.length > 1) {
      ctx.strokeStyle = spec.colour; ctx.globalAlpha = 0.55; ctx.lineWidth = 2.5 * v.ratio; ctx.beginPath();
      trail.forEach(([x, y], k) => { const [u, w] = px(x, y); k ? ctx.lineTo(u, w) : ctx.moveTo(u, w); });
      ctx.stroke(); ctx.globalAlpha = 1;
    }
    if (!frame) return;
    const r = frame.robots[i];
    if (!r || r.pose[0] === null || r.pose[1] === null) return;  // no pose known (a real robot)
    const [x, y, th] = r.pose, c = Math.cos(th), s = Math.sin(th);
    if (r.prox) {  // IR readings: a ray from each sensor that sees something
      ctx.lineWidth = 3 * v.ratio; ctx.strokeStyle = "#D55E00";
      spec.sensors.forEach(([sx, sy, sh], k) => {
        const d = r.prox[k];
        if (!(d < spec.range)) return;
        const wx = x + c * sx - s * sy, wy = y + s * sx + c * sy, h = th + sh;
        const [u0, w0] = px(wx, wy), [u1, w1] = px(wx + d * Math.cos(h), wy + d * Math.sin(h));
        ctx.beginPath(); ctx.moveTo(u0, w0); ctx.lineTo(u1, w1); ctx.stroke();
      });
    }
    const [u, w] = px(x, y);
    ctx.fillStyle = spec.colour; ctx.strokeStyle = state.selected === spec.name ? "#000" : "#222";
    ctx.lineWidth = (state.selected === spec.name ? 5 : 2.5) * v.ratio;
    ctx.beginPath(); ctx.arc(u, w, spec.radius * v.s, 0, 2 * Math.PI); ctx.fill(); ctx.stroke();
    const [hu, hw] = px(x + spec.radius * c, y + spec.radius * s);
    ctx.strokeStyle = "#fff"; ctx.lineWidth = 3 * v.ratio; ctx.beginPath(); ctx.moveTo(u, w); ctx.lineTo(hu, hw); ctx.stroke();
    names.push({ text: spec.name, u, w, r: spec.radius * v.s, colour: spec.colour });
  });
  placeNames(names, dummyBoxes);
}

function labelFont() { return `600 ${Math.round(16 * state.view.ratio)}px system-ui, sans-serif`; }

function label(text, u, w, colour) {
  const v = state.view;
  ctx.font = labelFont();
  ctx.lineWidth = 4 * v.ratio; ctx.strokeStyle = "rgba(255,255,255,0.85)"; ctx.strokeText(text, u, w);
  ctx.fillStyle = colour; ctx.fillText(text, u, w);
  const m = ctx.measureText(text);  // the box the letters cover, halo included
  const halo = 2 * v.ratio;
  return [u - halo, w - m.actualBoundingBoxAscent - halo, u + m.width + halo, w + m.actualBoundingBoxDescent + halo];
}

// -- robot names: beside their robot, covering no obstacle, robot or other name -------------------
// Eight spots around the body, tried in this order after the one the name had last (so a
// name stays put while its spot is clear); where none is clear, the one covering least.
const SPOTS = ["upper right", "upper left", "lower right", "lower left", "above", "below", "right", "left"];

function placeNames(names, taken) {
  const v = state.view, halo = 2 * v.ratio, gap = 4 * v.ratio;
  const shapes = taken.map(box => ({ box }));
  for (const ob of state.scene.obstacles) {
    if (ob.circle) { const [u, w] = px(ob.circle[0], ob.circle[1]); shapes.push({ u, w, r: ob.circle[2] * v.s }); }
    else shapes.push({ poly: ob.polygon.map(([x, y]) => px(x, y)) });
  }
  for (const n of names) shapes.push({ u: n.u, w: n.w, r: n.r + halo, own: n.text });  // every spot clears its own
  ctx.font = labelFont();
  for (const n of names) {
    const m = ctx.measureText(n.text), tw = m.width;
    const asc = m.actualBoundingBoxAscent, desc = m.actualBoundingBoxDescent;
    const right = n.u + n.r + gap, left = n.u - n.r - gap - tw, mid = n.u - tw / 2;
    const at = {  // each spot's text origin (left end of the baseline)
      "upper right": [right, n.w - n.r], "upper left": [left, n.w - n.r],
      "lower right": [right, n.w + n.r + asc], "lower left": [left, n.w + n.r + asc],
      above: [mid, n.w - n.r - gap - desc], below: [mid, n.w + n.r + gap + asc],
      right: [right, n.w + (asc - desc) / 2], left: [left, n.w + (asc - desc) / 2],
    };
    let best = null;
    for (const spot of [state.spots[n.text], ...SPOTS]) {
      if (!spot) continue;
      const [x, y] = at[spot], box = [x - halo, y - asc - halo, x + tw + halo, y + desc + halo];
      const off = box[0] < 0 || box[1] < 0 || box[2] > canvas.width || box[3] > canvas.height;
      const cost = shapes.filter(sh => sh.own !== n.text && covers(box, sh)).length + (off ? 1 : 0);
      if (!best || cost < best.cost) best = { spot, x, y, box, cost };
      if (!cost) break;
    }
    state.spots[n.text] = best.spot;
    shapes.push({ box: best.box });
    label(n.text, best.x, best.y, n.colour);
  }
}

// Does the box [left, top, right, bottom] cover any of a shape: a box, a disc or a polygon?
function covers([x0, y0, x1, y1], sh) {
  const hit = ([u, w]) => u >= x0 && u <= x1 && w >= y0 && w <= y1;
  if (sh.box) return x0 < sh.box[2] && sh.box[0] < x1 && y0 < sh.box[3] && sh.box[1] < y1;
  if (sh.poly) {  // a corner of the box inside it, or a point of its outline inside the box
    if ([[x0, y0], [x1, y0], [x0, y1], [x1, y1]].some(c => insidePolygon(c, sh.poly))) return true;
    return sh.poly.some((a, k) => {
      const b = sh.poly[(k + 1) % sh.poly.length], steps = Math.ceil(Math.hypot(b[0] - a[0], b[1] - a[1]) / 2) + 1;
      for (let j = 0; j <= steps; j++) if (hit([a[0] + (b[0] - a[0]) * j / steps, a[1] + (b[1] - a[1]) * j / steps])) return true;
      return false;
    });
  }
  const u = Math.max(x0, Math.min(sh.u, x1)), w = Math.max(y0, Math.min(sh.w, y1));
  return Math.hypot(u - sh.u, w - sh.w) < sh.r;
}

function insidePolygon([u, w], poly) {
  let inside = false;
  for (let k = 0, j = poly.length - 1; k < poly.length; j = k++) {
    const [ua, wa] = poly[k], [ub, wb] = poly[j];
    if ((wa > w) !== (wb > w) && u < ua + (w - wa) * (ub - ua) / (wb - wa)) inside = !inside;
  }
  return inside;
}

// -- the side panel -------------------------------------------------------------------------------
function showScene(sc) {
  state.scene = sc;
  $("title").textContent = `${sc.name} — ${sc.driver}`;
  const body = $("robots").tBodies[0];
  body.replaceChildren();
  for (const spec of sc.robots) {
    const row = el("tr", { "data-robot": spec.name });
    const name = el("td"); const sw = el("span", { class: "swatch" }); sw.style.background = spec.colour;
    name.append(sw, spec.name);
    row.append(name, el("td", { class: "layer-cell" }), el("td", { class: "wheels" }), el("td", { class: "driver" }));
    row.addEventListener("click", () => select(spec.name));
    body.append(row);
  }
  fit(); draw();
}

function liveFrame(f) {
  // a frame of another run than the trails': the served world's scene was restored, and
  // the robots start new trails where they now are
  if (state.run !== null && f.run !== state.run) state.trails = {};
  state.run = f.run;
  if (!f.previous) state.previous = null;
  else if (!state.previous || state.previous.run !== f.previous.run) loadPrevious(f.previous.run);
  for (const r of f.robots) {
    const trail = state.trails[r.name] || (state.trails[r.name] = []);
    const last = trail[trail.length - 1];
    if (!last || Math.hypot(last[0] - r.pose[0], last[1] - r.pose[1]) > 0.005) trail.push([r.pose[0], r.pose[1]]);
  }
  showFrame(f);
  refreshDetails();
}

// A served world whose scene was restored shows the run that ended as the previous run.
async function loadPrevious(run) {
  if (state.loadingPrevious === run) return;
  state.loadingPrevious = run;
  const d = await fetchJson("/trails.json");
  state.loadingPrevious = null;
  if (d && d.previous && d.previous.run === run && state.frame && state.frame.previous) { state.previous = d.previous; draw(); }
}

function showFrame(f) {
  state.frame = f;
  const previous = f.previous || null;  // the events and verdict are the previous run's
  $("time").textContent = `t = ${f.t.toFixed(1)} s`;
  $("rtf").textContent = f.rtf === null ? "" : `${f.rtf.toFixed(1)}× real time`;
  $("status").textContent = previous ? `${f.status} · scene restored` : f.status;
  const rows = $("robots").tBodies[0].rows;
  f.robots.forEach((r, i) => {
    const row = rows[i]; if (!row) return;
    const layer = row.querySelector(".layer-cell");
    layer.replaceChildren();
    if (r.layer) { const tag = el("span", { class: "layer" }, r.layer); paint(tag, r.layer_colour); layer.append(tag); }
    else layer.textContent = "—";
    row.querySelector(".wheels").textContent = r.wheels ? `${r.wheels[0].toFixed(2)} / ${r.wheels[1].toFixed(2)}` : "—";
    row.querySelector(".driver").textContent = r.driver;
  });
  const list = $("events");
  $("events-title").textContent = previous ? `Events of the previous run (ended at ${previous.t.toFixed(1)} s)` : "Events";
  const shown = JSON.stringify([previous, f.events]);
  if (state.player) state.player.markEvents(f.t);
  else if (list.dataset.shown !== shown) {
    list.dataset.shown = shown;
    list.replaceChildren(...f.events.map(eventItem));
  }
  const verdict = $("verdict");
  if (f.verdict) {
    verdict.hidden = false;
    verdict.className = (f.verdict.success ? "success" : "failure") + (previous ? " previous" : "");
    const said = f.verdict.success ? "SUCCESS" : `FAILED: ${f.verdict.text}${f.verdict.robot ? " (" + f.verdict.robot + ")" : ""}`;
    verdict.textContent = previous ? `previous run: ${said}` : said;
  } else verdict.hidden = true;
  draw();
}

// "5.0 s  left: left the line": the robot's name in its colour and set off by a colon, so
// robots called left and right never read as part of the event's words
function eventItem(e) {
  const item = el("li", { class: FAILURES.has(e.kind) ? "failure" : "", "data-t": e.t }, `${e.t.toFixed(1)} s  `);
  if (e.robot) {
    const spec = state.scene && state.scene.robots.find(r => r.name === e.robot);
    const who = el("span", { class: "who" }, e.robot);
    if (spec) who.style.color = spec.colour;
    item.append(who, ": ");
  }
  item.append(e.text);
  return item;
}

// Black or white text, whichever contrasts more with the colour (WCAG's relative
// luminance): white on the light layer colours (orange #E69F00) washes out on a
// projector. The same rule as text_colour in puckboard/viz/style.py (the tree's PNG).
function textOn(hex) {
  const lin = c => (c <= 0.04045 ? c / 12.92 : Math.pow((c + 0.055) / 1.055, 2.4));
  const [r, g, b] = [1, 3, 5].map(i => lin(parseInt(hex.slice(i, i + 2), 16) / 255));
  const L = 0.2126 * r + 0.7152 * g + 0.0722 * b;
  return (L + 0.05) * (L + 0.05) > 0.0525 ? "#000000" : "#ffffff";
}

function paint(element, colour) {
  element.style.background = colour;
  element.style.color = textOn(colour);
}

function select(name) {
  state.selected = name;
  for (const row of $("robots").tBodies[0].rows) row.classList.toggle("selected", row.dataset.robot === name);
  $("panel").hidden = !name;
  if (name) { $("panel-title").textContent = name; refreshDetails(); }
  draw();
}

async function refreshDetails() {
  if (!state.selected) return;
  if (state.player) { showDetails(state.player.details(state.selected)); return; }
  if (state.detailsPending) return;  // one request at a time; the next frame asks again
  state.detailsPending = true;
  try {
    const all = await (await fetch("/details.json", { cache: "no-store" })).json();
    const d = all && all[state.selected];
    if (d) showDetails(d);
  } catch (err) { /* the next frame tries again */ } finally { state.detailsPending = false; }
}

function showDetails(d) {
  $("panel-source").textContent = `from the ${d.source}`;
  $("keys").tBodies[0].replaceChildren(...d.keys.map(k => {
    const row = el("tr", { class: k.status, "data-key": k.key });
    row.append(el("td", {}, k.key), el("td", {}, k.value), el("td", {}, k.age === null ? "—" : k.age.toFixed(2)));
    return row;
  }));
  drawTimeline(d.timeline, d.end, d.cursor);
  showTree(d.tree);
}

// The arbitration timeline: one colour band per layer in control; in a replay the whole
// run with a cursor at the current time (click it to jump there).
function drawTimeline(changes, end, cursor) {
  const tl = $("timeline"), ratio = window.devicePixelRatio || 1;
  tl.width = tl.clientWidth * ratio; tl.height = 36 * ratio;
  end = Math.max(end !== undefined ? end : (state.frame ? state.frame.t : 0), 1e-3);
  const g = tl.getContext("2d");
  g.clearRect(0, 0, tl.width, tl.height);
  changes.forEach((c, i) => {
    const t1 = i + 1 < changes.length ? changes[i + 1].t : end;
    g.fillStyle = c.colour; g.fillRect(tl.width * c.t / end, 0, Math.max(1, tl.width * (t1 - c.t) / end), tl.height);
  });
  if (cursor !== undefined && cursor !== null) {
    const u = Math.round(tl.width * cursor / end);
    g.fillStyle = "#000"; g.fillRect(u - ratio, 0, 2 * ratio, tl.height);
    g.fillStyle = "#fff"; g.fillRect(u + ratio, 0, ratio, tl.height);
  }
  tl.dataset.end = end;
}

// -- the behaviour tree: every node's status at this tick, the layer in control marked -----------
const STATUS_WORDS = {
  layer: ["not asked", "does not apply", "applies", "succeeded", "stopped"],
  decorator: ["not asked", "does not apply", "running", "succeeded", "stopped"],
  selector: ["not ticked", "no layer applies", "a layer drives", "succeeded", "stopped"],
  other: ["not ticked", "failure", "running", "success", "stopped"],
};

function inControl(tree) {
  // the layer node that drove: named like the layer in control, and running itself or
  // held by a running decorator above it
  const { nodes, status, active } = tree;
  for (let k = 0; k < nodes.length; k++) {
    if (nodes[k].kind !== "layer" || nodes[k].name !== active || !status[k]) continue;
    for (let a = k; a >= 0; a = nodes[a].parent) if (status[a] === 2) return k;
  }
  return -1;
}

function showTree(tree) {
  const list = $("tree"), note = $("tree-note");
  const nodes = tree && tree.nodes;
  note.hidden = !(tree && tree.note);
  note.textContent = (tree && tree.note) || "";
  $("tree-time").textContent = tree && tree.t !== undefined && tree.t !== null ? `at t = ${tree.t.toFixed(2)} s` : "";
  if (!nodes) { list.replaceChildren(); return; }
  const driver = inControl(tree);
  list.replaceChildren(...nodes.map((n, k) => {
    const code = tree.status[k] || 0;
    const words = STATUS_WORDS[n.kind] || STATUS_WORDS.other;
    let word = words[code] || String(code);
    if (n.kind === "decorator" && code === 2 && nodes[k + 1] && tree.status[k + 1] !== 2) word = "holds the wheels";
    const item = el("li", { class: `node s${code}${k === driver ? " in-control" : ""}`, "data-node": n.name,
                            "data-status": code, "data-kind": n.kind });
    item.style.paddingLeft = `${0.3 + 1.3 * n.depth}em`;
    const sw = el("span", { class: "swatch" });
    sw.style.background = n.kind === "layer" ? (n.colour || "#999") : "transparent";
    const name = el("span", { class: "node-name" }, n.name);
    const kind = n.kind === "layer" ? null : el("span", { class: "node-kind" }, n.type + (n.memory ? " (memory)" : ""));
    const badge = el("span", { class: "node-status" }, k === driver ? "in control" : word);
    if (k === driver) paint(badge, n.colour || "#333333");
    item.append(sw, name, ...(kind ? [kind] : []), badge);
    return item;
  }));
}

canvas.addEventListener("click", ev => {
  if (!state.scene || !state.frame || !state.view) return;
  const rect = canvas.getBoundingClientRect(), v = state.view;
  const u = (ev.clientX - rect.left) * v.ratio, w = (ev.clientY - rect.top) * v.ratio;
  const x = (u - v.ox) / v.s, y = (v.oy - w) / v.s;
  let best = null, bestD = Infinity;
  state.frame.robots.forEach((r, i) => {
    const d = Math.hypot(r.pose[0] - x, r.pose[1] - y);
    if (d < bestD && d < 2.5 * state.scene.robots[i].radius) { best = r.name; bestD = d; }
  });
  select(best);
});
$("panel-close").addEventListener("click", () => select(null));
$("timeline").addEventListener("click", ev => {
  if (!state.player) return;
  const tl = $("timeline"), rect = tl.getBoundingClientRect();
  state.player.seekTime(+tl.dataset.end * (ev.clientX - rect.left) / rect.width);
});
window.addEventListener("resize", () => { fit(); draw(); });
// The live panel follows every frame (as soon as the previous answer is in), not a
// timer of its own: on a 500 ms timer its time lagged the header's by up to 0.6 s.

async function fetchJson(url) {
  try {
    const r = await fetch(url, { cache: "no-store" });
    return r.ok ? await r.json() : null;
  } catch (err) { return null; }
}

// -- the source: a recording inlined in the page, one the server replays, or the live stream ------
async function start() {
  const inlined = document.getElementById("replay-data");
  if (inlined) { startReplay(JSON.parse(inlined.textContent)); return; }
  const replay = await fetchJson("/replay.json");
  if (replay) { startReplay(replay); return; }
  const sc = await fetchJson("/scene.json");
  if (sc) showScene(sc);
  const trails = await fetchJson("/trails.json");
  if (trails) { state.trails = trails.trails; state.run = trails.run; state.previous = trails.previous; }
  const source = new EventSource("/stream");
  source.addEventListener("scene", e => showScene(JSON.parse(e.data)));
  source.addEventListener("frame", e => liveFrame(JSON.parse(e.data)));
  source.onopen = () => { $("connection").textContent = "live: updates stream from the simulation (read-only view)"; };
  source.onerror = () => { $("connection").textContent = "connection lost; retrying…"; };
}
document.addEventListener("DOMContentLoaded", start);

// The web view: draws the scene and a frame, live from the server's event stream or, in a
// replay (replay.js), from a recorded run. Plain JavaScript, no libraries: it must work
// offline, from a file, on a projector and on a phone.
"use strict";

const FAILURES = new Set(["collision", "lost_line", "parallel_driving", "stuck", "turned_back"]);
// state.player is the replay's player (replay.js) when the page replays a recording
var state = { scene: null, frame: null, trails: {}, details: {}, selected: null, view: null, player: null };
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
  for (const d of sc.dummies) {
    const [u, w] = px(d.x, d.y), r = 8 * v.ratio;
    ctx.strokeStyle = "#444"; ctx.lineWidth = 2 * v.ratio; ctx.beginPath();
    ctx.moveTo(u - r, w); ctx.lineTo(u + r, w); ctx.moveTo(u, w - r); ctx.lineTo(u, w + r); ctx.stroke();
    label(d.name, u + r, w - r, "#444");
  }
  const frame = state.frame;
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
    label(spec.name, u + spec.radius * v.s + 4 * v.ratio, w - spec.radius * v.s, spec.colour);
  });
}

function label(text, u, w, colour) {
  const v = state.view;
  ctx.font = `600 ${Math.round(16 * v.ratio)}px system-ui, sans-serif`;
  ctx.lineWidth = 4 * v.ratio; ctx.strokeStyle = "rgba(255,255,255,0.85)"; ctx.strokeText(text, u, w);
  ctx.fillStyle = colour; ctx.fillText(text, u, w);
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
  if (state.frame && f.t < state.frame.t) state.trails = {};  // the simulation was restarted
  for (const r of f.robots) {
    const trail = state.trails[r.name] || (state.trails[r.name] = []);
    const last = trail[trail.length - 1];
    if (!last || Math.hypot(last[0] - r.pose[0], last[1] - r.pose[1]) > 0.005) trail.push([r.pose[0], r.pose[1]]);
  }
  showFrame(f);
}

function showFrame(f) {
  state.frame = f;
  $("time").textContent = `t = ${f.t.toFixed(1)} s`;
  $("rtf").textContent = f.rtf === null ? "" : `${f.rtf.toFixed(1)}× real time`;
  $("status").textContent = f.status;
  const rows = $("robots").tBodies[0].rows;
  f.robots.forEach((r, i) => {
    const row = rows[i]; if (!row) return;
    const layer = row.querySelector(".layer-cell");
    layer.replaceChildren();
    if (r.layer) { const tag = el("span", { class: "layer" }, r.layer); tag.style.background = r.layer_colour; layer.append(tag); }
    else layer.textContent = "—";
    row.querySelector(".wheels").textContent = r.wheels ? `${r.wheels[0].toFixed(2)} / ${r.wheels[1].toFixed(2)}` : "—";
    row.querySelector(".driver").textContent = r.driver;
  });
  const list = $("events");
  if (state.player) state.player.markEvents(f.t);
  else if (list.children.length !== f.events.length) {
    list.replaceChildren(...f.events.map(eventItem));
  }
  const verdict = $("verdict");
  if (f.verdict) {
    verdict.hidden = false;
    verdict.className = f.verdict.success ? "success" : "failure";
    verdict.textContent = f.verdict.success ? "SUCCESS" : `FAILED: ${f.verdict.text}${f.verdict.robot ? " (" + f.verdict.robot + ")" : ""}`;
  } else verdict.hidden = true;
  draw();
}

function eventItem(e) {
  return el("li", { class: FAILURES.has(e.kind) ? "failure" : "", "data-t": e.t },
    `${e.t.toFixed(1)} s  ${e.robot || ""} ${e.text}`);
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
  try {
    const all = await (await fetch("/details.json", { cache: "no-store" })).json();
    const d = all && all[state.selected];
    if (d) showDetails(d);
  } catch (err) { /* the next refresh tries again */ }
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
    if (k === driver) badge.style.background = n.colour || "#333";
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
setInterval(() => { if (!state.player) refreshDetails(); }, 500);

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
  state.trails = (await fetchJson("/trails.json")) || {};
  const source = new EventSource("/stream");
  source.addEventListener("scene", e => showScene(JSON.parse(e.data)));
  source.addEventListener("frame", e => liveFrame(JSON.parse(e.data)));
  source.onopen = () => { $("connection").textContent = "live: updates stream from the simulation (read-only view)"; };
  source.onerror = () => { $("connection").textContent = "connection lost; retrying…"; };
}
document.addEventListener("DOMContentLoaded", start);

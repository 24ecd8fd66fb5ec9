// The replay: a recorded run, at any instant. The document (puckboard/web/replay.py) holds
// every control tick of the run; the player builds one tick's frame and hands it to the
// live view's own drawing (view.js), so a replay looks exactly like the live view, plus a
// time slider, play/pause, speed, stepping by one tick (← →) and events to jump to.
"use strict";

function startReplay(data) {
  const player = makePlayer(data);
  state.player = player;
  showScene(data.scene);
  $("title").textContent = `${data.title} — replay`;
  document.title = `puckboard — replay: ${data.title}`;
  $("connection").textContent = "replay of a recorded run (nothing here is live): space plays and pauses, " +
    "← → step one control tick, click an event or the timeline to jump";
  $("events").replaceChildren(...data.events.map(e => {
    const item = eventItem(e);
    item.classList.add("jump");
    item.title = "jump to this moment";
    item.addEventListener("click", () => { player.pause(); player.seekTime(e.t); });
    return item;
  }));
  const slider = $("slider");
  slider.max = Math.max(0, data.t.length - 1);
  $("player").hidden = false;
  fit();
  player.seek(0);
  // a robot chosen from the start: its tree, layers and values show without a click
  // (a newcomer does not know that the robots can be clicked)
  if (data.robots.length) select(data.robots[0].name);
  state.readyAt = performance.now();  // how long the page took to become usable
}

function makePlayer(data) {
  const times = data.t, T = times.length, robots = data.robots;
  const dt = data.dt || (T > 1 ? times[1] - times[0] : 0.05);
  const range = data.prox_range || (data.scene.robots[0] && data.scene.robots[0].range) || 0.05;
  const reads = Object.fromEntries(data.reads.map(r => [r.key, r]));
  const layerName = k => (k >= 0 ? data.layer_names[k] : null);
  const layerColour = name => (name ? data.layer_colours[name] || "#999999" : "#d9d9d9");
  for (const r of robots) for (const n of r.nodes || []) if (n.kind === "layer") n.colour = layerColour(n.name);
  // each robot's trail: a point wherever it had moved 5 mm since the last one, with its tick
  const trails = robots.map(r => {
    const pts = [], ticks = [];
    for (let i = 0; i < T; i++) {
      const x = r.pose[3 * i], y = r.pose[3 * i + 1];
      if (x === null || y === null) continue;
      const last = pts[pts.length - 1];
      if (!last || Math.hypot(x - last[0], y - last[1]) >= 0.005) { pts.push([x, y]); ticks.push(i); }
    }
    return { pts, ticks };
  });
  // each robot's layer changes, for its arbitration timeline
  const timelines = robots.map(r => {
    const out = [];
    for (let i = 0, prev = -2; i < T; i++) {
      if (r.layer[i] === prev) continue;
      prev = r.layer[i];
      out.push({ t: times[i], layer: layerName(prev), colour: layerColour(layerName(prev)) });
    }
    return out;
  });
  // the judge's verdict: the success, or the first failure
  const decisive = data.events.find(e => e.kind === "success" || FAILURES.has(e.kind));

  const p = { data, index: 0, playing: false, speed: 1, playT: times[0] || 0, last: 0, times };

  p.indexAt = function (t) {  // the last tick at or before t
    let lo = 0, hi = T - 1;
    while (lo < hi) { const mid = (lo + hi + 1) >> 1; if (times[mid] <= t + 1e-9) lo = mid; else hi = mid - 1; }
    return lo;
  };

  p.nearest = function (t) {  // the tick closest to t
    const i = p.indexAt(t);
    return i + 1 < T && Math.abs(times[i + 1] - t) < Math.abs(times[i] - t) ? i + 1 : i;
  };

  p.frame = function (i) {
    const t = times[i];
    const bots = robots.map(r => {
      const layer = layerName(r.layer[i]);
      return {
        name: r.name,
        pose: [r.pose[3 * i], r.pose[3 * i + 1], r.pose[3 * i + 2]],
        prox: r.prox.slice(8 * i, 8 * i + 8).map(d => (d === null ? Infinity : d)),
        wheels: r.wheels[2 * i] === null ? null : [r.wheels[2 * i], r.wheels[2 * i + 1]],
        layer, layer_colour: layerColour(layer), driver: "recording",
      };
    });
    // an event is stamped with the time the judge saw it: the pose of the tick at that time
    const end = i === T - 1 ? t + 1.5 * dt : t + 1e-9;
    let verdict = null;
    if (decisive && decisive.t <= end) {
      const success = decisive.kind === "success";
      verdict = { success, failure: success ? null : decisive.kind, robot: decisive.robot, text: decisive.text };
    }
    return {
      t, rtf: null, robots: bots, verdict,
      status: p.playing ? `replay · playing ${p.speed}×` : "replay · paused",
      events: data.events.filter(e => e.t <= end),
    };
  };

  p.seek = function (i) {  // jump there (playing goes on from there)
    i = Math.max(0, Math.min(T - 1, Math.round(i)));
    p.playT = times[i];
    p.show(i);
  };

  p.show = function (i) {
    p.index = i;
    state.trails = {};
    robots.forEach((r, k) => {
      const { pts, ticks } = trails[k];
      let n = 0, hi = ticks.length;  // how many trail points were laid by tick i
      while (n < hi) { const mid = (n + hi) >> 1; if (ticks[mid] <= i) n = mid + 1; else hi = mid; }
      state.trails[r.name] = pts.slice(0, n);
    });
    showFrame(p.frame(i));
    $("slider").value = i;
    $("tick").textContent = `tick ${i + 1} / ${T}`;
    if (state.selected) refreshDetails();
  };

  p.seekTime = function (t) { p.seek(p.nearest(t)); };

  p.step = function (by) { p.pause(); p.seek(p.index + by); };

  p.play = function () {
    if (p.index >= T - 1) p.seek(0);
    p.playing = true;
    p.playT = times[p.index];
    p.last = performance.now();
    $("play").textContent = "❚❚";
    requestAnimationFrame(p.animate);
  };

  p.pause = function () {
    if (!p.playing) return;
    p.playing = false;
    $("play").textContent = "▶";
    p.show(p.index);  // the status line says paused
  };

  p.animate = function (now) {
    if (!p.playing) return;
    p.playT += Math.max(0, now - p.last) / 1000 * p.speed;
    p.last = now;
    const i = p.indexAt(p.playT);
    if (i >= T - 1) { p.show(T - 1); p.pause(); return; }
    if (i !== p.index) p.show(i);
    requestAnimationFrame(p.animate);
  };

  p.markEvents = function (t) {
    const items = $("events").children, end = p.index === T - 1 ? t + 1.5 * dt : t + 1e-9;
    let current = -1;
    data.events.forEach((e, k) => { if (e.t <= end) current = k; });
    data.events.forEach((e, k) => {
      if (!items[k]) return;
      items[k].classList.toggle("future", e.t > end);
      items[k].classList.toggle("current", k === current);
    });
  };

  p.details = function (name) {
    const k = robots.findIndex(r => r.name === name), r = robots[k], i = p.index;
    const layer = layerName(r.layer[i]);
    const keys = r.reads.map(rd => readRow(rd, r, i));
    if (!r.reads.length) {  // an older recording: what it holds, without ages
      const labels = (data.scene.robots[k] || {}).sensor_names || [];
      keys.push({ key: "proximity", value: formatValue({ type: "Proximity", labels }, r.prox.slice(8 * i, 8 * i + 8), range), age: null, status: "" });
      keys.push({ key: "ground", value: formatValue({ type: "Ground" }, r.ground.slice(3 * i, 3 * i + 3), range), age: null, status: "" });
    }
    keys.push({ key: "command/layer", value: layer || "—", age: null, status: "" });
    const w = r.wheels;
    keys.push({ key: "command/wheels", value: w[2 * i] === null ? "—" : formatValue({ type: "WheelCommand" }, [w[2 * i], w[2 * i + 1]], range), age: null, status: "" });
    let tree = { note: r.tree_note, t: times[i] };
    if (r.nodes && r.tree) {
      const K = r.nodes.length, status = [];
      for (let n = 0; n < K; n++) status.push(r.tree.charCodeAt(K * i + n) - 48);
      tree = { nodes: r.nodes, status, active: layer, note: layer && layer.startsWith("(stale") ? "inputs were stale: the layers were not asked" : null, t: times[i] };
    }
    return { source: `recording: tick ${i + 1} of ${T}, what the layers read`, keys, tree,
             timeline: timelines[k], end: times[T - 1], cursor: times[i] };
  };

  function readRow(rd, r, i) {
    const info = reads[rd.key] || { labels: [] }, code = rd.status.charCodeAt(i) - 48;
    const status = code === 1 ? "fresh" : code === 2 ? "stale" : "missing";
    if (status === "missing") return { key: rd.key, value: "—", age: null, status };
    let values = null;
    if (rd.same_as === "proximity") values = r.prox.slice(8 * i, 8 * i + 8);
    else if (rd.same_as === "ground") values = r.ground.slice(3 * i, 3 * i + 3);
    else if (rd.values) { const w = info.labels.length; values = rd.values.slice(w * i, w * i + w); }
    return { key: rd.key, value: formatValue(info, values, range), age: rd.age[i], status };
  }
  return p;
}

// A value as the live view's key table shows it (puckboard.viz.monitor.format_value).
function formatValue(info, v, range) {
  if (!v) return "(not recorded)";
  if (v.some(x => x === null)) return "—";
  const sign = (x, d) => (x >= 0 ? "+" : "") + x.toFixed(d);
  switch (info.type) {
    case "Proximity": {
      const seen = (info.labels || []).map((n, k) => [n, v[k]]).filter(([, d]) => d < range);
      return seen.length ? seen.map(([n, d]) => `${n} ${(100 * d).toFixed(1)}`).join(", ") + " cm"
                         : `nothing within ${+(100 * range).toFixed(2)} cm`;
    }
    case "Ground": return `L ${v[0].toFixed(2)}  C ${v[1].toFixed(2)}  R ${v[2].toFixed(2)}`;
    case "Pose": return `x ${sign(v[0], 3)} m  y ${sign(v[1], 3)} m  θ ${sign(v[2] * 180 / Math.PI, 1)}°`;
    case "WheelCommand": case "WheelSpeeds": return `L ${sign(v[0], 2)}  R ${sign(v[1], 2)} rad/s`;
    default: {
      const labels = info.labels || [];
      const unit = info.unit ? ` ${info.unit}` : "";
      if (v.length === 1) return `${+v[0].toPrecision(4)}${unit}`;
      return v.map((x, k) => `${labels[k] || k} ${+x.toPrecision(4)}`).join("  ") + unit;
    }
  }
}

// -- the controls -----------------------------------------------------------------------------------
$("play").addEventListener("click", () => {
  const p = state.player; if (!p) return;
  if (p.playing) p.pause(); else p.play();
});
$("speed").addEventListener("change", ev => {
  const p = state.player; if (!p) return;
  p.speed = +ev.target.value;
  if (!p.playing) p.seek(p.index);
});
$("slider").addEventListener("input", ev => {
  const p = state.player; if (!p) return;
  p.pause(); p.seek(+ev.target.value);
});
document.addEventListener("keydown", ev => {
  const p = state.player; if (!p) return;
  const tag = ev.target.tagName, own = tag === "INPUT" || tag === "SELECT" || tag === "BUTTON";
  if (ev.key === "ArrowRight" || ev.key === "ArrowLeft") {
    if (ev.target === $("slider") || tag === "SELECT") return;  // the control moves itself
    p.step(ev.key === "ArrowRight" ? 1 : -1); ev.preventDefault();
  } else if (ev.key === " " && !own) {
    if (p.playing) p.pause(); else p.play();
    ev.preventDefault();
  } else if (ev.key === "Home" && !own) p.seek(0);
  else if (ev.key === "End" && !own) p.seek(p.times.length - 1);
});

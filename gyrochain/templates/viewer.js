// The offline viewer of `python -m gyrochain animate … -o FILE.html`.
// The page carries the primitives of every frame in the fixed frame ê⁰ (ê⁰₁ down, along gravity),
// made by gyrochain/view/scene.py; this script only projects, sorts and paints them, as the raster
// renderer of gyrochain/view/animate.py does: an orthographic camera at azimuth az about the vertical
// and elevation el, over the right-handed frame (X, Y, Z) = (x₃, x₂, −x₁).
"use strict";
(function () {
  const D = JSON.parse(document.getElementById("scene-data").textContent);
  const N = D.times.length;
  const scene = document.getElementById("scene");
  const plot = document.getElementById("plot");
  const slider = document.getElementById("time");
  const clock = document.getElementById("clock");
  const button = document.getElementById("play");
  const speed = document.getElementById("speed");
  const readout = document.getElementById("state");
  const dpr = window.devicePixelRatio || 1;
  let W = 640, H = 480;
  // the canvases take the size the page's layout gives them (the window's width), in device pixels
  function fit() {
    for (const c of [scene, plot]) {
      const r = c.getBoundingClientRect();
      c.width = Math.max(1, Math.round(r.width * dpr)); c.height = Math.max(1, Math.round(r.height * dpr));
      c.getContext("2d").setTransform(dpr, 0, 0, dpr, 0, 0);
    }
    W = scene.width / dpr; H = scene.height / dpr;
  }
  fit();
  const ctx = scene.getContext("2d");
  const pctx = plot.getContext("2d");

  const state = { frame: 0, az: D.camera.az, el: D.camera.el, zoom: 1, playing: N > 1, t0: 0, rate: 1 };
  slider.max = String(N - 1);

  // ---- the camera
  let M = null;
  function camera() {
    const ca = Math.cos(state.az), sa = Math.sin(state.az), ce = Math.cos(state.el), se = Math.sin(state.el);
    const d = [ce * ca, ce * sa, se], r = [-sa, ca, 0];
    const u = [d[1] * r[2] - d[2] * r[1], d[2] * r[0] - d[0] * r[2], d[0] * r[1] - d[1] * r[0]];
    // rows right, up, towards the camera, written in ê⁰: (X, Y, Z) = (x₃, x₂, −x₁)
    M = [r, u, d].map(b => [-b[2], b[1], b[0]]);
  }
  const TOP = 8;  // the page shows the name and the clock; the canvas keeps a small margin only
  // the view fits the projection of every key point of every frame (their hull's), as the raster does
  let fitScale = 1, fitCentre = [0, 0];
  function fitView() {
    let lo = [Infinity, Infinity], hi = [-Infinity, -Infinity];
    for (const p of D.hull) {
      for (let i = 0; i < 2; i++) {
        const q = M[i][0] * p[0] + M[i][1] * p[1] + M[i][2] * p[2];
        lo[i] = Math.min(lo[i], q); hi[i] = Math.max(hi[i], q);
      }
    }
    const m = 0.06 * Math.min(W, H), sx = Math.max(hi[0] - lo[0], 1e-9), sy = Math.max(hi[1] - lo[1], 1e-9);
    fitScale = Math.min((W - 2 * m) / sx, (H - TOP - 2 * m) / sy);
    fitCentre = [(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2];
  }
  function project(p) {
    const q = [0, 1, 2].map(i => M[i][0] * p[0] + M[i][1] * p[1] + M[i][2] * p[2]);
    const s = fitScale * state.zoom;
    return [W / 2 + (q[0] - fitCentre[0]) * s, TOP + (H - TOP) / 2 - (q[1] - fitCentre[1]) * s, q[2], s];
  }

  // the clock: enough decimals to change from one frame to the next
  const STEP = D.times.slice(1).reduce((m, t, i) => Math.min(m, t - D.times[i] > 0 ? t - D.times[i] : m), Infinity);
  const DECIMALS = Number.isFinite(STEP) ? Math.max(2, Math.ceil(-Math.log10(STEP) - 1e-9)) : 2;
  // ---- painting one frame
  function rgba(hex, a) {
    const v = [1, 3, 5].map(i => parseInt(hex.slice(i, i + 2), 16));
    return `rgba(${v[0]},${v[1]},${v[2]},${a})`;
  }
  function item(prim, order) {
    const kind = prim[0];
    if (kind === "seg") {
      const a = project(prim[1]), b = project(prim[2]);
      return [(a[2] + b[2]) / 2, order, () => {
        ctx.strokeStyle = prim[3]; ctx.lineWidth = prim[4]; ctx.lineCap = "round";
        ctx.beginPath(); ctx.moveTo(a[0], a[1]); ctx.lineTo(b[0], b[1]); ctx.stroke();
      }];
    }
    if (kind === "dot") {
      const a = project(prim[1]);
      return [a[2], order, () => {
        ctx.fillStyle = prim[3]; ctx.strokeStyle = "#282828"; ctx.lineWidth = 1;
        ctx.beginPath(); ctx.arc(a[0], a[1], Math.max(prim[2] * a[3], 2.5), 0, 2 * Math.PI); ctx.fill(); ctx.stroke();
      }];
    }
    if (kind === "disc") {
      const c = prim[1], u = prim[2], v = prim[3], r = prim[4];
      const pts = [];
      let z = 0;
      for (let j = 0; j < 48; j++) {
        const t = 2 * Math.PI * j / 48, ct = Math.cos(t), st = Math.sin(t);
        const p = project([0, 1, 2].map(i => c[i] + r * (ct * u[i] + st * v[i])));
        pts.push(p); z += p[2] / 48;
      }
      return [z, order, () => {
        ctx.fillStyle = rgba(prim[5], 0.3); ctx.strokeStyle = prim[5]; ctx.lineWidth = 1.5;
        ctx.beginPath(); pts.forEach((p, j) => j ? ctx.lineTo(p[0], p[1]) : ctx.moveTo(p[0], p[1]));
        ctx.closePath(); ctx.fill(); ctx.stroke();
      }];
    }
    if (kind === "plate") {  // the platform's deck: a translucent square c ± a u ± a v
      const c = prim[1], u = prim[2], v = prim[3], a = prim[4];
      const pts = [[-1, -1], [1, -1], [1, 1], [-1, 1]].map(([i, j]) => project([0, 1, 2].map(k => c[k] + a * (i * u[k] + j * v[k]))));
      const z = pts.reduce((s, p) => s + p[2], 0) / 4;
      return [z, order, () => {
        ctx.fillStyle = rgba(prim[5], 0.11); ctx.strokeStyle = rgba(prim[5], 0.6); ctx.lineWidth = 1;
        ctx.beginPath(); pts.forEach((p, j) => j ? ctx.lineTo(p[0], p[1]) : ctx.moveTo(p[0], p[1]));
        ctx.closePath(); ctx.fill(); ctx.stroke();
      }];
    }
    if (kind === "ring") {
      const c = prim[1], u = prim[2], v = prim[3], r = prim[4];
      const pts = [];
      let z = 0;
      for (let j = 0; j < 64; j++) {
        const t = 2 * Math.PI * j / 64, ct = Math.cos(t), st = Math.sin(t);
        const p = project([0, 1, 2].map(i => c[i] + r * (ct * u[i] + st * v[i])));
        pts.push(p); z += p[2] / 64;
      }
      return [z, order, () => {
        ctx.strokeStyle = prim[5]; ctx.lineWidth = 2.5; ctx.lineJoin = "round";
        ctx.beginPath(); pts.forEach((p, j) => j ? ctx.lineTo(p[0], p[1]) : ctx.moveTo(p[0], p[1]));
        ctx.closePath(); ctx.stroke();
      }];
    }
    if (kind === "label") {  // moved outwards from its axes' origin prim[4] until it covers no other label
      const a = project(prim[1]), o = project(prim[4] || [0, 0, 0]);
      return [a[2], order, () => {
        ctx.fillStyle = prim[3]; ctx.font = "12px sans-serif"; ctx.textAlign = "center"; ctx.textBaseline = "middle";
        const w = ctx.measureText(prim[2]).width + 4, h = 14;
        let dx = a[0] - o[0], dy = a[1] - o[1];
        const len = Math.hypot(dx, dy) || 1;
        [dx, dy] = len > 1e-6 ? [dx / len, dy / len] : [0.7071, -0.7071];
        let x = a[0], y = a[1];
        const hits = () => placed.some(b => Math.abs(b[0] - x) < (b[2] + w) / 2 && Math.abs(b[1] - y) < (b[3] + h) / 2);
        for (let j = 0; j < 40 && hits(); j++) { x += 6 * dx; y += 6 * dy; }
        placed.push([x, y, w, h]);
        ctx.fillText(prim[2], x, y);
      }];
    }
    throw new Error("unknown primitive " + kind);
  }

  // ---- a bar through a disc: in pieces, each in front of the disc where it is on the camera's side
  // of the disc's plane (as gyrochain/view/animate.py's occluders and seg_pieces)
  const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
  function occluders(prims) {
    return prims.filter(p => p[0] === "disc").map(p => [p[1], cross(p[2], p[3]), p[4], project(p[1])[2]]);
  }
  function segPieces(p, discs) {
    const view = M[2], out = [], n = 8;
    for (let j = 0; j < n; j++) {
      const a = [0, 1, 2].map(i => p[1][i] + (p[2][i] - p[1][i]) * j / n);
      const b = [0, 1, 2].map(i => p[1][i] + (p[2][i] - p[1][i]) * (j + 1) / n);
      const m = [0, 1, 2].map(i => (a[i] + b[i]) / 2);
      let depth = project(m)[2];
      for (const [c, nrm, r, dc] of discs) {
        const dn = dot(view, nrm);
        if (Math.abs(dn) < 1e-9) continue;
        const f = dot([0, 1, 2].map(i => m[i] - c[i]), nrm) / dn;
        const hit = [0, 1, 2].map(i => m[i] - f * view[i]);
        if (Math.hypot(hit[0] - c[0], hit[1] - c[1], hit[2] - c[2]) <= r) {
          const eps = 1e-9 * Math.max(1, r);
          depth = dot([0, 1, 2].map(i => m[i] - hit[i]), view) > 0 ? Math.max(depth, dc + eps) : Math.min(depth, dc - eps);
        }
      }
      out.push([["seg", a, b, p[3], p[4]], depth]);
    }
    return out;
  }

  let placed = [];  // the labels painted in this frame: [x, y, width, height]
  function draw() {
    placed = [];
    camera();
    fitView();
    const i = state.frame, t = D.times[i];
    ctx.fillStyle = "#ffffff"; ctx.fillRect(0, 0, W, H);
    const items = [];
    // the tip's trace over the last D.trace seconds, fading
    const T = D.tipTimes, eps = 1e-9;
    let j0 = 0, j1 = 0;
    while (j1 < T.length && T[j1] <= t + eps) j1++;
    j0 = j1;
    while (j0 > 0 && T[j0 - 1] >= t - D.trace - eps) j0--;
    const tr = D.tips.slice(j0, j1).map(project);
    for (let j = 0; j + 1 < tr.length; j++) {
      const a = tr[j], b = tr[j + 1], alpha = 0.85 * (j + 1) / (tr.length - 1);
      items.push([Math.min(a[2], b[2]), items.length, () => {
        ctx.strokeStyle = rgba(D.traceColour, alpha); ctx.lineWidth = 1.8;
        ctx.beginPath(); ctx.moveTo(a[0], a[1]); ctx.lineTo(b[0], b[1]); ctx.stroke();
      }]);
    }
    const prims = D.static.concat(D.frames[i]);
    const discs = occluders(prims);
    for (const p of prims) {
      if (p[0] === "seg" && p[4] >= 2 && discs.length) {
        for (const [piece, depth] of segPieces(p, discs)) { const it = item(piece, items.length); it[0] = depth; items.push(it); }
      } else items.push(item(p, items.length));
    }
    items.sort((a, b) => a[0] - b[0] || a[1] - b[1]);
    for (const it of items) it[2]();
    // the direction of gravity (ê⁰₁); the name and the clock are the page's
    ctx.font = "14px sans-serif"; ctx.textAlign = "left"; ctx.textBaseline = "top";
    if (D.gravity) {
      const cx = 34, cy = H - 34, dx = M[0][0], dy = M[1][0], L = Math.hypot(dx, dy);
      ctx.strokeStyle = D.frameColour; ctx.fillStyle = D.frameColour; ctx.lineWidth = 2;
      if (L < 0.2) {
        ctx.beginPath(); ctx.arc(cx, cy, 4, 0, 2 * Math.PI); ctx.stroke();
      } else {
        const ux = dx / L * 20, uy = -dy / L * 20;
        ctx.beginPath(); ctx.moveTo(cx - ux, cy - uy); ctx.lineTo(cx + ux, cy + uy);
        ctx.moveTo(cx + ux, cy + uy); ctx.lineTo(cx + ux - 0.35 * ux - 0.21 * uy, cy + uy - 0.35 * uy + 0.21 * ux);
        ctx.moveTo(cx + ux, cy + uy); ctx.lineTo(cx + ux - 0.35 * ux + 0.21 * uy, cy + uy - 0.35 * uy - 0.21 * ux);
        ctx.stroke();
      }
      ctx.fillText("g", cx + 14, cy - 22);
    }
    slider.value = String(i);
    clock.textContent = `t = ${t.toFixed(DECIMALS)} s`;
    if (D.states) {
      const x = D.states[i], n = x.length / 2, f = v => (v >= 0 ? " " : "") + v.toFixed(4);
      readout.textContent = `φ  = (${x.slice(0, n).map(f).join(", ")}) rad\nφ̇  = (${x.slice(n).map(f).join(", ")}) rad/s`;
    }
    drawPlot();
  }

  // ---- the integral's curve with a cursor and the value at the frame's time: a conserved one as
  // its deviation from the start (relative where the start is not 0), a quantity that is not
  // conserved (the energy where no integral exists) as its value
  function fitText(text, x, y, width) {  // one line, the font shrunk until it fits the canvas
    let size = 12;
    pctx.font = `${size}px sans-serif`;
    while (size > 8 && pctx.measureText(text).width > width) pctx.font = `${--size}px sans-serif`;
    pctx.fillText(text, x, y);
    pctx.font = "12px sans-serif";
  }
  function drawPlot() {
    const w = plot.width / dpr, h = plot.height / dpr, L = 70, R = 12, T = 40, B = 22;
    pctx.fillStyle = "#ffffff"; pctx.fillRect(0, 0, w, h);
    pctx.fillStyle = "#333"; pctx.font = "12px sans-serif"; pctx.textBaseline = "top"; pctx.textAlign = "left";
    if (!D.integral) { pctx.fillText("no integral plotted (the trajectory has no rates)", L, T); return; }
    const v = D.integral.values, unit = D.integral.unit, v0 = v[0], conserved = D.integral.conserved !== false;
    const ts = D.integral.times || D.times, tf = D.times[state.frame];
    let i = 0;  // the sample at the frame's time (the integral may be sampled finer than the frames)
    while (i + 1 < ts.length && ts[i + 1] <= tf + 1e-9) i++;
    const t0 = D.times[0], t1 = D.times[N - 1] > t0 ? D.times[N - 1] : t0 + 1;
    const relative = conserved && Math.abs(v0) > 0, s = relative ? Math.abs(v0) : 1;
    const d = conserved ? v.map(y => (y - v0) / s) : v, ref = conserved ? 0 : v0;
    let lo = Math.min(ref, ...d), hi = Math.max(ref, ...d);
    const half = Math.max((hi - lo) / 2, 1e-16 * Math.max(1, Math.abs(ref))), mid = (lo + hi) / 2;
    lo = mid - 1.15 * half; hi = mid + 1.15 * half;
    // plain numbers where they fit (0.62, -9, 6), powers of ten only beyond (3.1e-12)
    const e = x => (x === 0 ? "0" : Math.abs(x) >= 1e-3 && Math.abs(x) < 1e5 ? String(Number(x.toPrecision(2))) : x.toExponential(1));
    const wide = w - 8;
    fitText(`${D.integral.label}: ${v0.toPrecision(8)} ${unit} at t = ${t0.toFixed(2)} s`, 4, 4, wide);
    fitText(conserved
      ? (relative ? "relative deviation (I(t) − I(0)) / |I(0)|" : `deviation I(t) − I(0) (${unit})`) + `: ${e(d[i])} at t = ${tf.toFixed(2)} s`
      : `its value (${unit}): ${v[i].toPrecision(6)} ${unit} at t = ${tf.toFixed(2)} s; dashed: the start`, 4, 20, wide);
    const X = t => L + (t - t0) / (t1 - t0) * (w - L - R), Y = y => T + (hi - y) / (hi - lo) * (h - T - B);
    pctx.strokeStyle = "#bbb"; pctx.lineWidth = 1; pctx.strokeRect(L, T, w - L - R, h - T - B);
    pctx.setLineDash([3, 3]); pctx.beginPath(); pctx.moveTo(L, Y(ref)); pctx.lineTo(w - R, Y(ref)); pctx.stroke();
    pctx.setLineDash([]);
    pctx.textAlign = "right"; pctx.textBaseline = "middle";
    pctx.fillText(e(hi), L - 4, T); pctx.fillText(e(lo), L - 4, h - B);
    if (Y(ref) - T > 12 && h - B - Y(ref) > 12) pctx.fillText(e(ref), L - 4, Y(ref));
    pctx.textBaseline = "top";
    pctx.textAlign = "left"; pctx.fillText(`${t0.toFixed(2)} s`, L, h - B + 4);
    pctx.textAlign = "right"; pctx.fillText(`${t1.toFixed(2)} s`, w - R, h - B + 4);
    pctx.strokeStyle = "#0072B2"; pctx.lineWidth = 1.5; pctx.beginPath();
    d.forEach((y, j) => j ? pctx.lineTo(X(ts[j]), Y(y)) : pctx.moveTo(X(ts[j]), Y(y)));
    pctx.stroke();
    const x = X(tf);
    pctx.strokeStyle = "#C0392B"; pctx.beginPath(); pctx.moveTo(x, T); pctx.lineTo(x, h - B); pctx.stroke();
  }

  // ---- playing, the slider, turning and zooming
  function setFrame(i) { state.frame = Math.max(0, Math.min(N - 1, i | 0)); draw(); }
  function play() {
    if (N < 2) return;
    state.playing = true; button.textContent = "Pause";
    state.t0 = performance.now() / 1000 - (D.times[state.frame] - D.times[0]) / state.rate;
  }
  function pause() { state.playing = false; button.textContent = "Play"; }
  function tick() {
    if (state.playing) {
      const span = D.times[N - 1] - D.times[0];
      let t = (performance.now() / 1000 - state.t0) * state.rate;
      if (t > span) { state.t0 += span / state.rate; t -= span; }
      let i = state.frame;
      if (D.times[i] - D.times[0] > t) i = 0;
      while (i + 1 < N && D.times[i + 1] - D.times[0] <= t) i++;
      if (i !== state.frame) setFrame(i);
    }
    requestAnimationFrame(tick);
  }
  button.addEventListener("click", () => state.playing ? pause() : play());
  slider.addEventListener("input", () => { pause(); setFrame(Number(slider.value)); });
  speed.addEventListener("change", () => {
    const playing = state.playing;
    state.rate = Number(speed.value);
    if (playing) play();  // restart the clock at the frame shown, at the new rate
  });
  document.addEventListener("keydown", e => {
    if (e.target !== document.body) return;
    if (e.code === "Space") { e.preventDefault(); state.playing ? pause() : play(); }
    if (e.code === "ArrowRight" || e.code === "ArrowLeft") {
      e.preventDefault(); pause(); setFrame(state.frame + (e.code === "ArrowRight" ? 1 : -1));
    }
    if (e.code === "Home" || e.code === "End") { e.preventDefault(); pause(); setFrame(e.code === "Home" ? 0 : N - 1); }
  });
  scene.addEventListener("dblclick", () => { state.az = D.camera.az; state.el = D.camera.el; state.zoom = 1; draw(); });
  let drag = null;
  scene.addEventListener("pointerdown", e => { drag = [e.clientX, e.clientY]; scene.setPointerCapture(e.pointerId); scene.style.cursor = "grabbing"; });
  scene.addEventListener("pointermove", e => {
    if (!drag) return;
    state.az -= (e.clientX - drag[0]) * 0.01;
    state.el = Math.max(-1.55, Math.min(1.55, state.el + (e.clientY - drag[1]) * 0.01));
    drag = [e.clientX, e.clientY];
    draw();
  });
  const release = () => { drag = null; scene.style.cursor = "grab"; };
  scene.addEventListener("pointerup", release);
  scene.addEventListener("pointercancel", release);
  scene.addEventListener("wheel", e => {
    e.preventDefault();
    state.zoom = Math.max(0.1, Math.min(20, state.zoom * Math.exp(-e.deltaY * 0.001)));
    draw();
  }, { passive: false });

  // for scripts and tests: the viewer's state and controls
  window.gyroViewer = {
    get frame() { return state.frame; }, get time() { return D.times[state.frame]; },
    get az() { return state.az; }, get el() { return state.el; }, get zoom() { return state.zoom; },
    get playing() { return state.playing; }, get rate() { return state.rate; }, frames: N, setFrame, play, pause,
    project: p => { camera(); fitView(); return project(p).slice(0, 2); },  // a fixed-frame point → canvas px
  };
  // the legend: what the marks are, as gyrochain/view/scene.py read them off the primitives
  const SYMBOLS = { bar: ["━", "#555"], link: ["─", "#555"], ring: ["◯", "#555"], dot: ["●", "#555"], disc: ["◍", "#555"],
                    deck: ["▭", D.platformColour], deck_only: ["▭", D.platformColour], triad: ["⅄", D.frameColour], trace: ["┄", D.traceColour] };
  const legend = document.getElementById("legend");
  if (D.caption) { const c = document.createElement("em"); c.textContent = D.caption + ". "; legend.append(c); }
  D.legend.forEach(([sym, text], j) => {
    if (j) legend.append(" · ");
    if (sym === "bodymap") {  // the colour map from body 1 to body n, then its words
      const s = document.createElement("span");
      s.className = "sym"; s.style.display = "inline-block"; s.style.width = "3em"; s.style.height = "0.8em";
      s.style.background = `linear-gradient(to right, ${D.bodyColours.filter((_, i) => i % 4 === 0 || i === D.bodyColours.length - 1).join(", ")})`;
      legend.append(s, " " + text);
      return;
    }
    if (sym === "bodies") {
      text.split(" ").forEach((word, i) => {
        const s = document.createElement("span");
        s.textContent = (i ? " " : "") + word;
        if (i) s.style.color = D.bodyColours[i - 1];
        legend.append(s);
      });
      return;
    }
    const s = document.createElement("span");
    s.className = "sym"; s.textContent = SYMBOLS[sym][0]; s.style.color = SYMBOLS[sym][1];
    legend.append(s, " " + text);
  });
  window.addEventListener("resize", () => { fit(); draw(); });
  if (state.playing) play(); else button.textContent = "Play";
  draw();
  requestAnimationFrame(tick);
})();

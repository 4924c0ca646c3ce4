// mybot web controller page: joystick/keyboard driving with a dead man, mode switch, live map
// view and navigation goals. Talks JSON over one websocket (see the mybot_web README).
"use strict";

const $ = (id) => document.getElementById(id);
const clamp = (v, lo, hi) => Math.min(hi, Math.max(lo, v));

// ---------------------------------------------------------------- connection
const conn = {
  ws: null, info: null, authed: false, state: null, map: null, mapImage: null,
  trail: [], trailFrame: null, lastSent: null, clientId: null,
};
window.mybotWeb = conn;  // read by the browser tests (conn.view is set below)

function setStatus(state, text) {
  const el = $("status");
  el.dataset.state = state;
  el.textContent = text;
}

function showMessage(text) {
  $("message").textContent = text;
}

function send(obj) {
  if (conn.ws && conn.ws.readyState === WebSocket.OPEN) {
    conn.ws.send(JSON.stringify(obj));
    conn.lastSent = obj;
    return true;
  }
  return false;
}

function connect() {
  const scheme = location.protocol === "https:" ? "wss" : "ws";
  const ws = new WebSocket(`${scheme}://${location.host}/ws`);
  conn.ws = ws;
  setStatus("connecting", "connecting…");
  ws.onmessage = (ev) => {
    let msg;
    try { msg = JSON.parse(ev.data); } catch { return; }
    handlers[msg.type]?.(msg);
  };
  ws.onclose = () => {
    // The server zeroes our output on close; forget what we held so nothing resumes by itself.
    releaseAll(false);
    conn.authed = false;
    setStatus("disconnected", "disconnected – retrying");
    setTimeout(connect, 1000);
  };
}

const handlers = {
  hello(msg) {
    conn.info = msg;
    conn.clientId = msg.client;
    conn.authed = msg.authed;
    conn.trail = [];
    for (let i = 0; i + 1 < msg.trail.length; i += 2) conn.trail.push([msg.trail[i], msg.trail[i + 1]]);
    conn.trailFrame = msg.trail_frame;
    setupControls(msg);
    setMode(msg.mode);
    if (msg.auth_required && !msg.authed) {
      const fromUrl = new URLSearchParams(location.search).get("token");
      if (fromUrl) send({ type: "auth", token: fromUrl });
    }
    updateAuthUi();
  },
  auth(msg) {
    conn.authed = msg.authed;
    updateAuthUi();
    showMessage("");
  },
  error(msg) {
    showMessage(msg.message);
  },
  async map(msg) {
    try {
      conn.mapImage = await decodeMap(msg);
      const first = !conn.map;
      conn.map = msg;
      if (first) fitView();
      requestDraw();
    } catch (e) {
      showMessage(`map could not be decoded: ${e}`);
    }
  },
  state(msg) {
    conn.state = msg;
    if (msg.pose) addTrail(msg.frame, msg.pose[0], msg.pose[1]);
    if (msg.mode !== currentMode) setMode(msg.mode);
    updatePanel(msg);
    if ($("follow").checked && msg.pose) { view.cx = msg.pose[0]; view.cy = msg.pose[1]; }
    if (!view.fitted && msg.pose) fitView();
    requestDraw();
  },
};

function updateAuthUi() {
  const needs = conn.info?.auth_required && !conn.authed;
  $("auth").hidden = !needs;
  setStatus("connected", needs ? "connected – view only (token needed to drive)" : "connected");
  for (const id of ["mode-manual", "mode-autonomous", "cancel"]) $(id).disabled = needs;
}

$("auth").addEventListener("submit", (ev) => {
  ev.preventDefault();
  send({ type: "auth", token: $("token").value });
});

// ---------------------------------------------------------------- driving
// Held inputs are sent every send_period while any is active; letting go sends "stop" at
// once. The server zeroes the robot if the stream stops (dead man) or the socket closes.
const held = { stick: null, rotate: null, keys: new Set() };
let sendTimer = null;
let wasActive = false;

class Stick {
  constructor(el, onChange) {
    this.el = el; this.knob = el.querySelector(".knob"); this.onChange = onChange;
    this.pointer = null; this.value = null;
    el.addEventListener("pointerdown", (e) => this.down(e));
    el.addEventListener("pointermove", (e) => this.move(e));
    for (const t of ["pointerup", "pointercancel", "lostpointercapture"]) {
      el.addEventListener(t, (e) => this.up(e));
    }
  }
  down(e) {
    if (this.pointer !== null) return;
    this.pointer = e.pointerId;
    this.el.setPointerCapture(e.pointerId);
    this.el.classList.add("active");
    this.move(e);
    e.preventDefault();
  }
  move(e) {
    if (e.pointerId !== this.pointer) return;
    const r = this.el.getBoundingClientRect();
    const rx = r.width / 2, ry = r.height / 2;
    let x = (e.clientX - r.left - rx) / (rx - 32 > 8 ? rx - 32 : rx);
    let y = (e.clientY - r.top - ry) / (ry - 32 > 8 ? ry - 32 : ry);
    const n = Math.hypot(x, y);
    if (n > 1) { x /= n; y /= n; }
    if (ry < rx / 2) y = 0;  // the rotation strip is one-dimensional
    this.value = { x, y };
    this.knob.style.transform = `translate(${x * (rx - 32)}px, ${y * Math.max(ry - 32, 0)}px)`;
    this.onChange(this.value);
  }
  up(e) {
    if (e.pointerId !== this.pointer) return;
    this.pointer = null;
    this.value = null;
    this.el.classList.remove("active");
    this.knob.style.transform = "";
    this.onChange(null);
  }
  reset() {
    if (this.pointer !== null && this.el.hasPointerCapture(this.pointer)) {
      this.el.releasePointerCapture(this.pointer);
    }
    this.pointer = null; this.value = null;
    this.el.classList.remove("active");
    this.knob.style.transform = "";
  }
}

const stick = new Stick($("stick"), (v) => { held.stick = v; inputChanged(); });
const rotateStick = new Stick($("rotate"), (v) => { held.rotate = v; inputChanged(); });

function setupControls(info) {
  $("rotate").hidden = !info.holonomic;
  $("keys").textContent = info.holonomic
    ? "Keys: W/S forward/back, A/D left/right, Q/E rotate, Space stop"
    : "Keys: W/S or ↑/↓ forward/back, A/D or ←/→ turn, Space stop";
  clearInterval(sendTimer);
  sendTimer = setInterval(sendDrive, 1000 * info.send_period);
  buildModules(info.modules);
}

const KEYMAP = {
  KeyW: "fwd", ArrowUp: "fwd", KeyS: "back", ArrowDown: "back",
  KeyA: "left", ArrowLeft: "left", KeyD: "right", ArrowRight: "right",
  KeyQ: "ccw", KeyE: "cw",
};

window.addEventListener("keydown", (e) => {
  if (e.target instanceof HTMLInputElement && e.target.type !== "range") return;
  if (e.code === "Space") { releaseAll(true); e.preventDefault(); return; }
  const k = KEYMAP[e.code];
  if (!k) return;
  e.preventDefault();
  if (!held.keys.has(k)) { held.keys.add(k); inputChanged(); }
});
window.addEventListener("keyup", (e) => {
  const k = KEYMAP[e.code];
  if (k && held.keys.delete(k)) inputChanged();
});
// Losing focus or hiding the page is letting go.
window.addEventListener("blur", () => releaseAll(true));
document.addEventListener("visibilitychange", () => { if (document.hidden) releaseAll(true); });
window.addEventListener("pagehide", () => releaseAll(true));

function command() {
  const holo = !!conn.info?.holonomic;
  const k = held.keys;
  let vx = (k.has("fwd") ? 1 : 0) - (k.has("back") ? 1 : 0);
  let vy = 0, wz = 0;
  if (holo) {
    vy = (k.has("left") ? 1 : 0) - (k.has("right") ? 1 : 0);
    wz = (k.has("ccw") ? 1 : 0) - (k.has("cw") ? 1 : 0);
  } else {
    wz = (k.has("left") ? 1 : 0) - (k.has("right") ? 1 : 0);
  }
  if (held.stick) {
    vx += -held.stick.y;
    if (holo) vy += -held.stick.x; else wz += -held.stick.x;
  }
  if (held.rotate) wz += -held.rotate.x;
  const active = held.keys.size > 0 || held.stick !== null || held.rotate !== null;
  const s = $("speed").value / 100;
  const r = (v) => Math.round(clamp(v * s, -1, 1) * 1000) / 1000;
  return { active, vx: r(vx), vy: r(vy), wz: r(wz) };
}

function sendDrive() {
  if (!conn.authed) return;
  const c = command();
  if (c.active) {
    send({ type: "drive", vx: c.vx, vy: c.vy, wz: c.wz });
    wasActive = true;
  } else if (wasActive) {
    send({ type: "stop" });
    wasActive = false;
  }
}

function inputChanged() {
  sendDrive();  // react at once instead of at the next period
}

function releaseAll(sendStop) {
  held.keys.clear(); held.stick = null; held.rotate = null;
  stick.reset(); rotateStick.reset();
  if (sendStop && wasActive) send({ type: "stop" });
  wasActive = false;
}

$("speed").addEventListener("input", () => { $("speed-out").textContent = `${$("speed").value} %`; });

// ---------------------------------------------------------------- mode and goals
let currentMode = null;
function setMode(mode) {
  currentMode = mode;
  $("mode-manual").setAttribute("aria-pressed", String(mode === "manual"));
  $("mode-autonomous").setAttribute("aria-pressed", String(mode === "autonomous"));
}
$("mode-manual").addEventListener("click", () => { if (send({ type: "mode", mode: "manual" })) setMode("manual"); });
$("mode-autonomous").addEventListener("click", () => { if (send({ type: "mode", mode: "autonomous" })) setMode("autonomous"); });
$("cancel").addEventListener("click", () => send({ type: "cancel" }));

// ---------------------------------------------------------------- live view
const canvas = $("map");
const ctx = canvas.getContext("2d");
const view = { cx: 0, cy: 0, scale: 50, fitted: false };  // scale: CSS pixels per metre
conn.view = view;
let drawPending = false;
let goalDrag = null;
let panDrag = null;

function addTrail(frame, x, y) {
  if (frame !== conn.trailFrame) { conn.trail = []; conn.trailFrame = frame; }
  const last = conn.trail[conn.trail.length - 1];
  if (!last || Math.hypot(x - last[0], y - last[1]) >= 0.05) {
    conn.trail.push([x, y]);
    if (conn.trail.length > 5000) conn.trail.splice(0, conn.trail.length - 5000);
  }
}

async function decodeMap(msg) {
  const bin = Uint8Array.from(atob(msg.data), (c) => c.charCodeAt(0));
  const stream = new Blob([bin]).stream().pipeThrough(new DecompressionStream("deflate"));
  const cells = new Uint8Array(await new Response(stream).arrayBuffer());
  if (cells.length !== msg.width * msg.height) throw new Error("size mismatch");
  const img = new ImageData(msg.width, msg.height);
  for (let i = 0; i < cells.length; i++) {
    const v = cells[i];
    // map_server's colours: free white, occupied black, unknown grey.
    const g = v === 255 ? 128 : Math.round(255 - (Math.min(v, 100) * 255) / 100);
    img.data[4 * i] = g; img.data[4 * i + 1] = g; img.data[4 * i + 2] = v === 255 ? 140 : g;
    img.data[4 * i + 3] = 255;
  }
  const off = new OffscreenCanvas(msg.width, msg.height);
  off.getContext("2d").putImageData(img, 0, 0);
  return off;
}

function fitView() {
  const w = canvas.clientWidth || 1, h = canvas.clientHeight || 1;
  if (conn.map) {
    const m = conn.map;
    const mw = m.width * m.resolution, mh = m.height * m.resolution;
    view.cx = m.origin[0] + mw / 2; view.cy = m.origin[1] + mh / 2;
    view.scale = Math.min(w / mw, h / mh) * 0.95;
    view.fitted = true;
  } else if (conn.state?.pose) {
    view.cx = conn.state.pose[0]; view.cy = conn.state.pose[1];
    view.scale = Math.min(w, h) / 6;
    view.fitted = true;
  }
  requestDraw();
}
$("fit").addEventListener("click", fitView);

function toWorld(px, py) {
  const r = canvas.getBoundingClientRect();
  return [view.cx + (px - r.left - r.width / 2) / view.scale,
          view.cy - (py - r.top - r.height / 2) / view.scale];
}

canvas.addEventListener("wheel", (e) => {
  e.preventDefault();
  const [wx, wy] = toWorld(e.clientX, e.clientY);
  const f = Math.exp(-e.deltaY * 0.0015);
  view.scale = clamp(view.scale * f, 2, 2000);
  const [nx, ny] = toWorld(e.clientX, e.clientY);
  view.cx += wx - nx; view.cy += wy - ny;  // keep the point under the cursor fixed
  requestDraw();
}, { passive: false });
canvas.addEventListener("contextmenu", (e) => e.preventDefault());
canvas.addEventListener("pointerdown", (e) => {
  canvas.setPointerCapture(e.pointerId);
  if (e.button === 1 || e.button === 2) {
    panDrag = { x: e.clientX, y: e.clientY, cx: view.cx, cy: view.cy };
    $("follow").checked = false;
    return;
  }
  const [x, y] = toWorld(e.clientX, e.clientY);
  goalDrag = { x, y, px: e.clientX, py: e.clientY, yaw: null };
});
canvas.addEventListener("pointermove", (e) => {
  if (panDrag) {
    view.cx = panDrag.cx - (e.clientX - panDrag.x) / view.scale;
    view.cy = panDrag.cy + (e.clientY - panDrag.y) / view.scale;
    requestDraw();
  } else if (goalDrag && Math.hypot(e.clientX - goalDrag.px, e.clientY - goalDrag.py) > 8) {
    const [x, y] = toWorld(e.clientX, e.clientY);
    goalDrag.yaw = Math.atan2(y - goalDrag.y, x - goalDrag.x);
    requestDraw();
  }
});
canvas.addEventListener("pointerup", () => {
  if (panDrag) { panDrag = null; return; }
  if (!goalDrag) return;
  const g = goalDrag;
  goalDrag = null;
  let yaw = g.yaw;
  if (yaw === null) {
    // A plain click: face the direction of travel.
    const p = conn.state?.pose;
    yaw = p ? Math.atan2(g.y - p[1], g.x - p[0]) : 0;
  }
  const r3 = (v) => Math.round(v * 1000) / 1000;
  if (!send({ type: "goal", x: r3(g.x), y: r3(g.y), yaw: r3(yaw) })) showMessage("not connected");
  requestDraw();
});
canvas.addEventListener("pointercancel", () => { goalDrag = null; panDrag = null; requestDraw(); });
new ResizeObserver(() => requestDraw()).observe(canvas);

function requestDraw() {
  if (drawPending) return;
  drawPending = true;
  requestAnimationFrame(() => { drawPending = false; draw(); });
}

function polyline(flat, close = false) {
  ctx.beginPath();
  for (let i = 0; i + 1 < flat.length; i += 2) {
    if (i === 0) ctx.moveTo(flat[i], flat[i + 1]); else ctx.lineTo(flat[i], flat[i + 1]);
  }
  if (close) ctx.closePath();
}

function arrow(x, y, yaw, len, color) {
  ctx.save();
  ctx.translate(x, y); ctx.rotate(yaw);
  ctx.strokeStyle = color; ctx.fillStyle = color; ctx.lineWidth = 3 / view.scale;
  ctx.beginPath(); ctx.moveTo(0, 0); ctx.lineTo(len, 0); ctx.stroke();
  ctx.beginPath(); ctx.moveTo(len, 0); ctx.lineTo(len * 0.7, len * 0.2); ctx.lineTo(len * 0.7, -len * 0.2);
  ctx.closePath(); ctx.fill();
  ctx.restore();
}

function draw() {
  const dpr = window.devicePixelRatio || 1;
  const w = canvas.clientWidth, h = canvas.clientHeight;
  if (canvas.width !== Math.round(w * dpr) || canvas.height !== Math.round(h * dpr)) {
    canvas.width = Math.round(w * dpr); canvas.height = Math.round(h * dpr);
  }
  ctx.setTransform(1, 0, 0, 1, 0, 0);
  ctx.fillStyle = "#0d1117";
  ctx.fillRect(0, 0, canvas.width, canvas.height);
  // World (metres, y up) -> screen pixels.
  const s = view.scale * dpr;
  ctx.setTransform(s, 0, 0, -s, canvas.width / 2 - view.cx * s, canvas.height / 2 + view.cy * s);
  const px = 1 / view.scale;  // one CSS pixel in metres

  // A map in another frame than the views (e.g. "map" before localisation publishes
  // map -> odom) would be drawn in the wrong place: leave it out and say so.
  if (conn.map && conn.mapImage && mapDrawable()) {
    const m = conn.map;
    ctx.save();
    ctx.translate(m.origin[0], m.origin[1]); ctx.rotate(m.origin[2]);
    ctx.scale(m.resolution, m.resolution);
    ctx.imageSmoothingEnabled = false;
    ctx.drawImage(conn.mapImage, 0, 0);  // row 0 at the origin, growing +y: the grid's order
    ctx.restore();
  } else {
    drawGrid(px);
  }
  const st = conn.state;
  if (conn.trail.length > 1) {
    ctx.strokeStyle = "#58a6ff"; ctx.lineWidth = 2 * px;
    polyline(conn.trail.flat()); ctx.stroke();
  }
  if (st?.path?.length) {
    ctx.strokeStyle = "#3fb950"; ctx.lineWidth = 3 * px;
    polyline(st.path); ctx.stroke();
  }
  if (st?.scan?.length) {
    ctx.fillStyle = "#f85149";
    const d = 3 * px;
    for (let i = 0; i + 1 < st.scan.length; i += 2) ctx.fillRect(st.scan[i] - d / 2, st.scan[i + 1] - d / 2, d, d);
  }
  if (st?.goal) arrow(st.goal.x, st.goal.y, st.goal.yaw, 0.5, "#d2a8ff");
  if (goalDrag && goalDrag.yaw !== null) arrow(goalDrag.x, goalDrag.y, goalDrag.yaw, 0.5, "#f0f6fc");
  if (st?.pose) {
    const [x, y, yaw] = st.pose;
    ctx.save();
    ctx.translate(x, y); ctx.rotate(yaw);
    ctx.fillStyle = "rgba(47, 129, 247, 0.35)"; ctx.strokeStyle = "#2f81f7"; ctx.lineWidth = 2 * px;
    ctx.beginPath(); ctx.moveTo(0.3, 0); ctx.lineTo(-0.2, 0.15); ctx.lineTo(-0.2, -0.15); ctx.closePath();
    ctx.fill(); ctx.stroke();
    ctx.restore();
  }
}

function mapDrawable() {
  const f = conn.map.frame.replace(/^\//, "");
  return !conn.state?.frame || !f || f === conn.state.frame;
}

function drawGrid(px) {
  // 1 m grid around the view when there is no map yet.
  const r = canvas.getBoundingClientRect();
  const hw = r.width / 2 / view.scale, hh = r.height / 2 / view.scale;
  ctx.strokeStyle = "#21262d"; ctx.lineWidth = px;
  ctx.beginPath();
  for (let x = Math.floor(view.cx - hw); x <= view.cx + hw; x++) { ctx.moveTo(x, view.cy - hh); ctx.lineTo(x, view.cy + hh); }
  for (let y = Math.floor(view.cy - hh); y <= view.cy + hh; y++) { ctx.moveTo(view.cx - hw, y); ctx.lineTo(view.cx + hw, y); }
  ctx.stroke();
}

// ---------------------------------------------------------------- side panel
const fmt = (v, digits, unit) => (v === null || v === undefined ? "–"
  : `${v.toFixed(digits)}${unit === "°" ? "" : " "}${unit}`);
const moduleCanvases = new Map();

function buildModules(names) {
  const box = $("modules");
  box.replaceChildren();
  moduleCanvases.clear();
  for (const n of names) {
    const fig = document.createElement("figure");
    const c = document.createElement("canvas");
    c.width = 90; c.height = 90;
    const cap = document.createElement("figcaption");
    cap.textContent = n;
    fig.append(c, cap);
    box.append(fig);
    moduleCanvases.set(n, { canvas: c, caption: cap });
  }
}

function updatePanel(st) {
  $("pose").textContent = st.pose
    ? `${st.pose[0].toFixed(2)}, ${st.pose[1].toFixed(2)} m, ${(st.pose[2] * 180 / Math.PI).toFixed(0)}°`
    : "unknown";
  let frameText = st.frame ? `frame: ${st.frame}` : "no pose";
  if (conn.map && !mapDrawable()) frameText += ` (map is in ${conn.map.frame}: not shown)`;
  $("frame").textContent = frameText;
  $("battery").textContent = fmt(st.battery, 2, "V");
  $("cpu").textContent = st.cpu === null ? "–" : `${st.cpu.toFixed(0)} % (${st.cpu_source})`;
  $("rostime").textContent = fmt(st.time, 1, "s");
  $("goal").textContent = st.goal
    ? `goal ${st.goal.x.toFixed(2)}, ${st.goal.y.toFixed(2)}: ${st.goal.status}` : "no goal";
  $("driver").textContent = st.driver === null ? ""
    : st.driver === conn.clientId ? "You are driving." : "Another page is driving.";
  for (const m of st.modules) {
    const e = moduleCanvases.get(m.name);
    if (!e) continue;
    e.caption.textContent = `${m.name}: ${fmt(m.angle === null ? null : m.angle * 180 / Math.PI, 0, "°")}, ${fmt(m.speed, 2, "m/s")}`;
    drawModule(e.canvas, m);
  }
}

function drawModule(c, m) {
  const g = c.getContext("2d");
  g.clearRect(0, 0, c.width, c.height);
  g.strokeStyle = "#444c56"; g.lineWidth = 2;
  g.beginPath(); g.arc(45, 45, 40, 0, 2 * Math.PI); g.stroke();
  if (m.angle === null) return;
  // Robot frame drawn with x up (forward), y left, like the map when the robot faces up.
  g.save(); g.translate(45, 45); g.rotate(-m.angle - Math.PI / 2);
  const len = 12 + 24 * Math.min(1, Math.abs(m.speed ?? 0));
  g.fillStyle = "#2f81f7"; g.fillRect(-8, -5, 16, 10);
  g.strokeStyle = (m.speed ?? 0) < 0 ? "#f85149" : "#3fb950"; g.lineWidth = 3;
  g.beginPath(); g.moveTo(0, 0); g.lineTo(Math.sign(m.speed || 1) * len, 0); g.stroke();
  g.restore();
}

connect();
requestDraw();

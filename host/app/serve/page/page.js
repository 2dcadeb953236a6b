// The live view's behaviour: pulls JPEG frames one after another (the next is asked for when the
// last has arrived, so a slow link drops frames instead of queueing them), orbits on drag, zooms
// on the wheel, polls the status and the probes. Coloured by speed or pressure it shows the colour
// map and its range (automatic or typed in). Served by clsph view (status mode "view") it shows a
// timeline of the run's frames instead of the run's buttons. Plain JavaScript, nothing loaded
// from elsewhere.
"use strict";

const view = document.getElementById("view");
const viewport = document.getElementById("viewport");
const message = document.getElementById("message");
const statusBar = document.getElementById("status");
const canvas = document.getElementById("probes");
const legend = document.getElementById("probe_legend");

let home = null;     // the scene's camera as an orbit (GET /api/camera)
let orbit = null;    // the camera now
let ended = false;   // the run has ended: no more frames
let viewing = false; // clsph view: frames of a run's directory, picked on the timeline
let lastShown = "";  // the URL of the image on screen (clsph view: the same one is not asked again)
const colourSelect = document.getElementById("colour");
const legendBox = document.getElementById("legend");
const rangeLo = document.getElementById("range_lo"), rangeHi = document.getElementById("range_hi");
const timeline = document.getElementById("timeline"), frameLabel = document.getElementById("frame_label");
let frameTimes = [];

function fmtTime(s) {
  if (s === null || s === undefined || !isFinite(s)) return "–";
  if (s < 60) return s.toFixed(0) + " s";
  if (s < 3600) return Math.floor(s / 60) + " min " + Math.round(s % 60) + " s";
  return Math.floor(s / 3600) + " h " + Math.round((s % 3600) / 60) + " min";
}

// --- frames -------------------------------------------------------------------------------
function frameSize() {
  // The image the viewport shows at the screen's resolution, within the server's limits.
  const r = viewport.getBoundingClientRect();
  const scale = Math.min(window.devicePixelRatio || 1, 2);
  let w = Math.max(16, Math.round(r.width * scale)), h = Math.max(16, Math.round(r.height * scale));
  const cap = Math.min(1, 1280 / w, 1280 / h);
  return [Math.max(16, Math.round(w * cap)), Math.max(16, Math.round(h * cap))];
}

// A range end typed in: a finite number, or null (automatic); anything else is marked and left out.
function rangeEnd(input) {
  const text = input.value.trim();
  const v = Number(text);
  const ok = text === "" || isFinite(v);
  input.style.borderColor = ok ? "" : "#ff7b8a";
  return text !== "" && ok ? v : null;
}

function byField() { return colourSelect.value === "speed" || colourSelect.value === "pressure"; }

function frameUrl() {
  const [w, h] = frameSize();
  const q = new URLSearchParams({az: orbit.az.toFixed(3), el: orbit.el.toFixed(3), dist: orbit.dist.toPrecision(6), w, h,
                                 colour: colourSelect.value});
  if (byField()) {
    const lo = rangeEnd(rangeLo), hi = rangeEnd(rangeHi);
    if (lo !== null) q.set("lo", String(lo));
    if (hi !== null) q.set("hi", String(hi));
  }
  if (viewing) q.set("frame", timeline.value);
  return "frame.jpg?" + q.toString();
}

// The legend: the colour map as a gradient between the range's ends; the automatic ends as the
// fields' placeholders.
function showLegend(range) {
  legendBox.hidden = !byField();
  document.getElementById("range_unit").textContent = colourSelect.value === "speed" ? "m/s" : "Pa";
  if (home && home.colour_map) {
    const stops = home.colour_map.map(c => "rgb(" + c.map(x => Math.round(255 * x)).join(",") + ")");
    document.getElementById("ramp").style.background = "linear-gradient(to right, " + stops.join(", ") + ")";
  }
  if (range) {
    const [lo, hi] = range.split(" ").map(Number);
    rangeLo.placeholder = "auto " + lo.toPrecision(3);
    rangeHi.placeholder = "auto " + hi.toPrecision(3);
  }
}
colourSelect.addEventListener("change", () => showLegend(null));

let shown = null;  // the object URL on screen
async function pullFrames() {
  while (!ended) {
    try {
      const wanted = frameUrl();
      if (viewing && wanted === lastShown) {  // a still picture: nothing to ask for until it changes
        await new Promise(r => setTimeout(r, 100));
        continue;
      }
      const res = await fetch(wanted, {cache: "no-store"});
      if (!res.ok) {
        const body = await res.json().catch(() => ({error: res.statusText}));
        message.textContent = body.error || ("HTTP " + res.status);
        await new Promise(r => setTimeout(r, 500));
        continue;
      }
      const range = res.headers.get("X-Colour-Range");
      if (range) showLegend(range);
      const frame = res.headers.get("X-Frame");
      if (frame) {
        const [i, t] = frame.split(" ").map(Number);
        frameLabel.textContent = "frame " + i + " of " + frameTimes.length + ", t = " + t.toPrecision(4) + " s";
      }
      const url = URL.createObjectURL(await res.blob());
      lastShown = wanted;
      view.src = url;
      if (shown) URL.revokeObjectURL(shown);
      shown = url;
      message.textContent = "";
    } catch (e) {
      message.textContent = "the run is not reachable (it may have ended)";
      await new Promise(r => setTimeout(r, 1000));
    }
  }
}

// --- camera ---------------------------------------------------------------------------------
let drag = null;
viewport.addEventListener("pointerdown", e => {
  drag = {x: e.clientX, y: e.clientY};
  viewport.setPointerCapture(e.pointerId);
  viewport.classList.add("dragging");
});
viewport.addEventListener("pointermove", e => {
  if (!drag || !orbit) return;
  orbit.az -= (e.clientX - drag.x) * 0.3;
  orbit.el = Math.max(-home.max_el, Math.min(home.max_el, orbit.el + (e.clientY - drag.y) * 0.3));
  drag = {x: e.clientX, y: e.clientY};
});
function endDrag() { drag = null; viewport.classList.remove("dragging"); }
viewport.addEventListener("pointerup", endDrag);
viewport.addEventListener("pointercancel", endDrag);
viewport.addEventListener("wheel", e => {
  e.preventDefault();
  if (!orbit) return;
  const d = orbit.dist * Math.exp(e.deltaY * 0.001);
  orbit.dist = Math.max(home.scene_size * 0.01, Math.min(home.scene_size * 100, d));
}, {passive: false});
document.getElementById("reset").onclick = () => { orbit = Object.assign({}, home); };

// --- the run's controls ---------------------------------------------------------------------
async function post(path) {
  try {
    const res = await fetch(path, {method: "POST"});
    if (res.ok) showStatus(await res.json());
  } catch (e) { /* the status poll says so */ }
}
document.getElementById("pause").onclick = () => post("api/pause");
document.getElementById("resume").onclick = () => post("api/resume");
document.getElementById("step").onclick = () => post("api/step");
document.getElementById("write").onclick = () => post("api/write");

// clsph view: the timeline follows the frames listed (at its right end it follows a growing run).
function showViewStatus(s) {
  viewing = true;
  for (const id of ["pause", "resume", "step", "write"]) document.getElementById(id).hidden = true;
  document.getElementById("timeline_bar").hidden = false;
  const atEnd = Number(timeline.value) >= Number(timeline.max);
  frameTimes = s.times;
  timeline.max = String(Math.max(0, s.frames - 1));
  if (atEnd) timeline.value = timeline.max;
  const parts = ["viewing " + s.dir, s.frames + " frames"];
  if (frameTimes.length) parts.push("t = " + frameTimes[0].toPrecision(4) + " to " + frameTimes[frameTimes.length - 1].toPrecision(4) + " s");
  if (s.devices.length) parts.push("rendered on " + s.devices.join(", "));
  statusBar.textContent = parts.join(" · ");
  ended = false;
}

function showStatus(s) {
  if (s.mode === "view") return showViewStatus(s);
  const parts = [];
  parts.push(s.state);
  parts.push("t = " + s.time.toPrecision(5) + " s" + (s.until !== null ? " of " + s.until + " s" : ""));
  parts.push("step " + s.step + (s.step_limit !== null ? " (limit " + s.step_limit + ")" : ""));
  parts.push(s.steps_per_second.toFixed(1) + " steps/s");
  parts.push(s.particles.toLocaleString("en") + " particles");
  if (s.devices.length) {
    const total = s.devices.reduce((a, d) => a + d.particles, 0) || 1;
    parts.push(s.devices.map(d => d.device + " " + (100 * d.particles / total).toFixed(0) + "% (" + d.interaction + ")").join(", "));
  }
  parts.push("ETA " + fmtTime(s.eta_seconds));
  if (s.written) parts.push("wrote " + s.written);
  statusBar.textContent = parts.join(" · ");
  document.getElementById("pause").disabled = s.paused;
  document.getElementById("resume").disabled = !s.paused;
  document.getElementById("step").disabled = !s.paused;
  ended = !["setting up", "running", "paused"].includes(s.state);
}

async function pollStatus() {
  try {
    const res = await fetch("api/status", {cache: "no-store"});
    showStatus(await res.json());
  } catch (e) {
    statusBar.textContent = "the run is not reachable (it may have ended)";
  }
  setTimeout(pollStatus, 500);
}

// --- probes ---------------------------------------------------------------------------------
const colours = ["#6fb3ff", "#ffb86b", "#8be28b", "#ff7b8a", "#c89bff", "#f3e36b", "#6be3d9", "#d0d0d0"];
let probeNames = [], probeRows = [];

function drawProbes() {
  const ctx = canvas.getContext("2d");
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  legend.textContent = "";
  if (!probeNames.length) {
    ctx.fillStyle = "#888";
    ctx.fillText("no probes in this scene", 10, 20);
    return;
  }
  const n = Math.min(probeNames.length, colours.length);
  const band = canvas.height / n;
  const t0 = probeRows.length ? probeRows[0][0] : 0, t1 = probeRows.length ? probeRows[probeRows.length - 1][0] : 1;
  for (let k = 0; k < n; ++k) {
    // Each probe on its own band and scale (pressures in Pa and heights in m side by side).
    let lo = Infinity, hi = -Infinity;
    for (const r of probeRows) { const v = r[k + 1]; if (v !== null && isFinite(v)) { lo = Math.min(lo, v); hi = Math.max(hi, v); } }
    const top = k * band + 4, h = band - 8;
    ctx.strokeStyle = "#2a3038";
    ctx.strokeRect(0.5, top + 0.5, canvas.width - 1, h);
    if (!isFinite(lo)) {  // no finite sample yet (a pressure probe out of the fluid)
      const line = document.createElement("div");
      line.style.color = colours[k];
      line.textContent = probeNames[k] + ": –";
      legend.appendChild(line);
      continue;
    }
    if (hi === lo) { hi += 1e-9; lo -= 1e-9; }
    ctx.strokeStyle = colours[k];
    ctx.beginPath();
    let pen = false;
    for (const r of probeRows) {
      const v = r[k + 1];
      if (v === null || !isFinite(v)) { pen = false; continue; }
      const x = (t1 > t0 ? (r[0] - t0) / (t1 - t0) : 0) * (canvas.width - 2) + 1;
      const y = top + h - (v - lo) / (hi - lo) * h;
      if (pen) ctx.lineTo(x, y); else ctx.moveTo(x, y);
      pen = true;
    }
    ctx.stroke();
    const last = probeRows.length ? probeRows[probeRows.length - 1][k + 1] : null;
    const line = document.createElement("div");
    line.style.color = colours[k];
    line.textContent = probeNames[k] + ": " + (last === null ? "–" : Number(last).toPrecision(4)) +
                       "  [" + lo.toPrecision(3) + ", " + hi.toPrecision(3) + "]";
    legend.appendChild(line);
  }
}

async function pollProbes() {
  try {
    const after = probeRows.length ? probeRows[probeRows.length - 1][0] : -1;
    const res = await fetch("api/probes?after=" + after, {cache: "no-store"});
    const p = await res.json();
    probeNames = p.names;
    probeRows = probeRows.concat(p.rows);
    if (probeRows.length > 8000) probeRows = probeRows.filter((_, i) => i % 2 === 0);
    drawProbes();
  } catch (e) { /* the status poll says so */ }
  if (!ended) setTimeout(pollProbes, 1000);
}

// --- start ----------------------------------------------------------------------------------
(async function start() {
  pollStatus();
  for (;;) {
    try {
      home = await (await fetch("api/camera")).json();
      break;
    } catch (e) {
      await new Promise(r => setTimeout(r, 1000));
    }
  }
  orbit = Object.assign({}, home);
  showLegend(null);
  pollProbes();
  pullFrames();
})();

// rigd's overlay page: live data over the WebSocket (proto SampleBatch, StateEvent,
// ModelInfo, CameraFrame), run control over the HTTP API, and the model-lab view.
"use strict";

const MAX_POINTS = 30000;  // live plot history per series
const PHASE_COLORS = {approach: "#eceff1", insert: "#fff3e0", hold: "#f3e5f5", retract: "#e8f5e9", none: "#ffffff"};
const CATALOGUE = ["rate_dependence", "iop_stiffness", "shaft_friction", "rig_compliance", "sensor_drift",
                   "spatial_ripple", "mains_interference", "stick_slip", "stress_relaxation"];

// What the browser tests read (window.rig): counts of what is drawn, the state, the lab's figures.
const rig = window.rig = {samples: 0, modelPoints: 0, residualPoints: 0, frames: 0, state: "", runId: 0,
                          events: [], lab: {before: null, after: null, verdict: null, plots: null},
                          mesh: {frames: 0, points: 0, punctured: false, maxDepth: 0, firstT: null, lastT: null}, haptic: null};
const live = {x: [], force: [], model: [], t: [], residual: [], phases: [], curve: null};
let token = sessionStorage.getItem("rigd-token") || "";

const $ = id => document.getElementById(id);
const fmt = (v, d) => (v === null || v === undefined || Number.isNaN(v)) ? "—" : Number(v).toFixed(d);

async function api(path, body) {
  const headers = {"Content-Type": "application/json"};
  if (token) headers.Authorization = "Bearer " + token;
  const response = await fetch(path, body === undefined ? {headers} : {method: "POST", headers, body: JSON.stringify(body)});
  if (response.status === 401) {
    token = prompt("rigd asks for its API token") || "";
    sessionStorage.setItem("rigd-token", token);
    throw new Error("not authorised");
  }
  const json = await response.json();
  if (!response.ok) throw new Error(json.error || json.result || response.statusText);
  return json;
}

// ---------------------------------------------------------------- live plots
const forcePlot = new uPlot({
  width: Math.min(window.innerWidth - 80, 1400), height: 340, scales: {x: {time: false}},
  series: [{label: "x [mm]"}, {label: "measured [N]", stroke: "#1565c0", width: 1},
           {label: "model [N]", stroke: "#e65100", width: 2, dash: [8, 4]}],
  axes: [{label: "displacement from the corneal surface [mm]"}, {label: "force [N]"}],
}, [[], [], []], $("plot-force"));

const shadePhases = u => {
  const ctx = u.ctx;
  for (const p of live.phases) {
    const x0 = u.valToPos(p.t0, "x", true), x1 = u.valToPos(p.t1, "x", true);
    ctx.fillStyle = PHASE_COLORS[p.phase] || "#fff";
    ctx.fillRect(x0, u.bbox.top, Math.max(1, x1 - x0), u.bbox.height);
  }
};
const residualPlot = new uPlot({
  width: Math.min(window.innerWidth - 80, 1400), height: 240, scales: {x: {time: false}},
  hooks: {drawClear: [shadePhases]},
  series: [{label: "t [s]"}, {label: "residual [N]", stroke: "#c62828", width: 1}],
  axes: [{label: "loop time [s]"}, {label: "measured − model [N]"}],
}, [[], []], $("plot-residual"));

function trim(array) { if (array.length > MAX_POINTS) array.splice(0, array.length - MAX_POINTS); }

function addSamples(b) {
  if (b.run_id && b.run_id !== rig.runId) {  // a new run: start the plots afresh
    rig.runId = b.run_id;
    for (const key of ["x", "force", "model", "t", "residual", "phases"]) live[key].length = 0;
    rig.samples = rig.modelPoints = rig.residualPoints = 0;
    backfill(b.run_id, b.t_s[0]);
  }
  if (!b.run_id) return;  // between runs only the readings move
  for (let i = 0; i < b.t_s.length; ++i) {
    live.x.push(b.x_mm[i]);
    live.force.push(b.force_N[i]);
    live.model.push(b.model_N[i]);
    live.t.push(b.t_s[i]);
    live.residual.push(b.residual_N[i]);
    const last = live.phases[live.phases.length - 1];
    if (last && last.phase === b.phase[i]) last.t1 = b.t_s[i];
    else live.phases.push({phase: b.phase[i], t0: b.t_s[i], t1: b.t_s[i]});
    rig.samples++;
    if (b.model_N[i] !== null) rig.modelPoints++;
    if (b.residual_N[i] !== null) rig.residualPoints++;
  }
  for (const key of ["x", "force", "model", "t", "residual"]) trim(live[key]);
}

// Opened mid-run: fetch what the archive already has of this run (measured only).
async function backfill(runId, firstLiveT) {
  try {
    const past = await api(`/api/runs/${runId}/samples`);
    if (rig.runId !== runId || !past.t_s.length) return;
    const offset = firstLiveT - past.t_s[past.t_s.length - 1];  // archive t starts at 0; the stream at loop time
    const keep = past.t_s.map((t, i) => i).filter(i => past.t_s[i] + offset < firstLiveT);
    live.x.unshift(...keep.map(i => past.x_mm[i]));
    live.force.unshift(...keep.map(i => past.force_N[i]));
    live.model.unshift(...keep.map(() => null));
    live.t.unshift(...keep.map(i => past.t_s[i] + offset));
    live.residual.unshift(...keep.map(() => null));
    scheduleRedraw();
  } catch (e) { /* the live stream goes on regardless */ }
}

let redrawPending = false;
function scheduleRedraw() {
  if (redrawPending) return;
  redrawPending = true;
  setTimeout(() => {
    redrawPending = false;
    forcePlot.setData([live.x, live.force, live.model], true);
    residualPlot.setData([live.t, live.residual], true);
  }, 100);
}

// ---------------------------------------------------------------- stream
function onMessage(event) {
  const m = JSON.parse(event.data);
  if (m.type === "samples") {
    addSamples(m);
    scheduleRedraw();
  } else if (m.type === "event") {
    rig.events.push(m);
    const li = document.createElement("li");
    li.textContent = `${fmt(m.t_s, 3)} s  ${m.kind}: ${m.message}`;
    $("events").prepend(li);
  } else if (m.type === "model") {
    if (m.warnings && (!live.curve || live.curve.file !== m.file)) {
      m.warnings.forEach(w => { const li = document.createElement("li"); li.className = "warn"; li.textContent = "model: " + w; $("events").prepend(li); });
    }
    live.curve = m;
  } else if (m.type === "mesh") {
    if (window.rigHaptics) window.rigHaptics.onMesh(m);
  } else if (m.type === "frame") {
    $("camera").src = "data:image/jpeg;base64," + m.jpeg_base64;
    rig.frames++;
  }
}

function connect() {
  const url = `${location.protocol === "https:" ? "wss" : "ws"}://${location.host}/ws${token ? "?token=" + encodeURIComponent(token) : ""}`;
  const ws = new WebSocket(url);
  ws.onopen = () => { $("conn").textContent = "live"; $("conn").className = "pill on"; };
  ws.onclose = () => { $("conn").textContent = "offline"; $("conn").className = "pill off"; setTimeout(connect, 1000); };
  ws.onmessage = onMessage;
}

// ---------------------------------------------------------------- status
async function refreshStatus() {
  try {
    const s = await api("/api/status");
    rig.state = s.state;
    $("state").textContent = s.state + (s.phase !== "none" ? " · " + s.phase : "");
    $("state").className = "state " + s.state;
    $("fault").textContent = s.fault === "none" ? "" : s.fault;
    $("r-position").textContent = fmt(s.position_mm, 3) + " mm";
    $("r-force").textContent = fmt(s.force_N, 4) + " N";
    $("r-iop").textContent = `${fmt(s.iop_mmHg, 2)} mmHg (target ${fmt(s.iop_target_mmHg, 1)}${s.iop_settled ? ", settled" : ""})`;
    $("r-velocity").textContent = fmt(s.velocity_mm_s, 3) + " mm/s";
    $("r-ready").textContent = (s.homed ? "homed" : "not homed") + " / " + (s.tared ? "tared" : "not tared");
    $("r-loop").textContent = `${fmt(s.loop.rate_hz, 0)} Hz, jitter p99 ${fmt(s.loop.jitter_p99_us, 0)} µs, overruns ${s.loop.overruns}`;
    const i = s.interlocks;
    $("interlocks").innerHTML = [["home limit", i.home_limit], ["end limit", i.end_limit], ["e-stop", i.estop_input],
                                 ["DAQ link down", !i.link_ok]]
      .map(([name, on]) => `<span class="${on ? "on" : ""}">${name}${on ? " ●" : ""}</span>`).join("") +
      `<span class="${s.motor_enabled ? "motor" : ""}">motor ${s.motor_enabled ? "on" : "off"}</span>`;
    rig.motorEnabled = s.motor_enabled;
  } catch (e) { $("fault").textContent = String(e.message || e); }
}

async function command(name) {
  try { const r = await api("/api/" + name, {}); $("run-message").textContent = `${name}: ${r.result}`; }
  catch (e) { $("run-message").textContent = `${name}: ${e.message}`; }
  refreshStatus();
}

$("stop").onclick = () => command("stop");
$("estop").onclick = () => command("estop");
$("b-home").onclick = () => { if (confirm("Home the carriage? It will move to the home switch and park.")) command("home"); };
$("b-tare").onclick = () => command("tare");
$("b-reset").onclick = () => command("reset");

$("run-form").onsubmit = async event => {
  event.preventDefault();
  const f = new FormData(event.target);
  const body = {eye_id: f.get("eye_id"), iop_mmHg: +f.get("iop_mmHg"), velocity_mm_s: +f.get("velocity_mm_s"),
                depth_mm: +f.get("depth_mm"), hold_s: +f.get("hold_s"), post_mortem_h: +f.get("post_mortem_h")};
  if (f.get("operator")) body.operator = f.get("operator");
  const meta = {};
  for (const line of String(f.get("meta")).split("\n")) {
    const at = line.indexOf("=");
    if (at > 0) meta[line.slice(0, at).trim()] = line.slice(at + 1).trim();
  }
  if (Object.keys(meta).length) body.meta = meta;
  if (!confirm(`Start the cut?\n\nEye ${body.eye_id}: IOP ${body.iop_mmHg} mmHg, ${body.velocity_mm_s} mm/s, ${body.depth_mm} mm deep.\nThe keratome will move into the eye.`)) return;
  try { const r = await api("/api/run", body); $("run-message").textContent = `run ${r.run_id}: ${r.result}`; }
  catch (e) { $("run-message").textContent = "refused: " + e.message; }
};

// ---------------------------------------------------------------- model lab
document.querySelectorAll(".tab").forEach(tab => tab.onclick = () => {
  document.querySelectorAll(".tab").forEach(t => t.classList.toggle("active", t === tab));
  document.querySelectorAll(".view").forEach(v => v.classList.toggle("hidden", v.id !== "view-" + tab.dataset.view));
  if (tab.dataset.view === "lab") loadRuns();
  if (tab.dataset.view === "haptics" && window.rigHaptics) window.rigHaptics.refresh();
});

async function loadRuns() {
  const list = await api("/api/runs");
  $("lab-runs").innerHTML = "<tr><th></th><th>run</th><th>eye</th><th>IOP</th><th>v</th><th>samples</th><th>outcome</th></tr>" +
    list.runs.filter(r => r.samples > 0).map(r => `<tr><td><input type="checkbox" class="run-pick" value="${r.run_id}" checked></td>` +
      `<td>${r.run_id}</td><td>${r.eye_id}</td><td>${fmt(r.iop_mmHg, 1)}</td><td>${fmt(r.velocity_mm_s, 1)}</td><td>${r.samples}</td><td>${r.outcome}</td></tr>`).join("");
  $("effects").innerHTML = CATALOGUE.map(e => `<label><input type="checkbox" class="effect-pick" value="${e}"> ${e}</label>`).join("");
}

const pickedRuns = () => [...document.querySelectorAll(".run-pick:checked")].map(c => +c.value);
const pickedEffects = () => [...document.querySelectorAll(".effect-pick:checked")].map(c => c.value);

let phasePlot = null;
function drawPhases(before, after) {
  const phases = before.map(p => p.segment);
  const afterBy = Object.fromEntries((after || []).map(p => [p.segment, p.rmse_N]));
  const xs = phases.map((_, i) => i);
  const data = [xs, before.map(p => p.rmse_N), phases.map(p => afterBy[p] ?? null)];
  if (phasePlot) phasePlot.destroy();
  phasePlot = new uPlot({
    width: Math.min(window.innerWidth - 80, 1000), height: 280, scales: {x: {time: false, range: [-0.5, phases.length - 0.5]}},
    series: [{}, {label: "before [N]", fill: "#90a4ae", stroke: "#546e7a", paths: uPlot.paths.bars({size: [0.35], align: -1})},
             {label: "after [N]", fill: "#66bb6a", stroke: "#2e7d32", paths: uPlot.paths.bars({size: [0.35], align: 1})}],
    axes: [{values: (u, vals) => vals.map(v => phases[v] || "")}, {label: "RMSE [N]"}],
  }, data, $("plot-phases"));
}

async function labCall(action, body) {
  $("lab-summary").textContent = action + "…";
  try { return await api("/api/lab/" + action, body); }
  catch (e) { $("lab-summary").textContent = action + ": " + e.message; throw e; }
}

// The "where does it fail" plots (web/lab_plots.js, the same the HTML report draws).
function drawLabPlots(result, action) {
  const series = result.series;
  rigLabPlots($("lab-plots"), series, uPlot, {width: Math.min(window.innerWidth - 80, 1000)});
  rig.lab.plots = series ? {action, runs: series.runs.length, holds: series.hold.length, after: series.after !== undefined,
                            depthBins: series.depth.x_mm.length,
                            retractionBins: series.depth.retraction_N.filter(v => v !== null).length,
                            canvases: $("lab-plots").querySelectorAll("canvas").length} : null;
}

$("b-refresh").onclick = loadRuns;
$("b-compare").onclick = async () => {
  const c = await labCall("compare", {runs: pickedRuns()});
  drawPhases(c.by_phase, null);
  drawLabPlots(c, "compare");
  $("lab-summary").textContent = `${c.model}: RMSE ${fmt(c.overall.rmse_N, 4)} N (noise floor ${fmt(c.noise_floor_N, 4)} N)`;
};
$("b-diagnose").onclick = async () => {
  const d = await labCall("diagnose", {runs: pickedRuns(), effects: pickedEffects()});
  rig.lab.verdict = d.verdict;
  drawLabPlots(d, "diagnose");
  $("diagnosis").innerHTML = "<tr><th>effect</th><th>CV RMSE [N]</th><th>gain</th><th>significant</th><th>evidence</th></tr>" +
    d.candidates.map(c => `<tr class="${c.significant ? "significant" : ""}"><td>${c.effect}</td><td>${fmt(c.cv_rmse_N, 4)}</td>` +
      `<td>${fmt(c.gain_pct, 1)} %</td><td>${c.significant ? "yes" : "no"}</td><td>${c.evidence}</td></tr>`).join("");
  $("lab-summary").textContent = `verdict: ${d.verdict} (baseline CV RMSE ${fmt(d.baseline.cv_rmse_N, 4)} N)`;
  if (d.verdict !== "none") document.querySelectorAll(".effect-pick").forEach(c => { if (c.value === d.verdict) c.checked = true; });
};
$("b-fit").onclick = async () => {
  const f = await labCall("fit", {runs: pickedRuns(), effects: pickedEffects()});
  rig.lab.before = f.before.cv_rmse_N;
  rig.lab.after = f.after.cv_rmse_N;
  drawPhases(f.before.by_phase, f.after.by_phase);
  drawLabPlots(f, "fit");
  const fall = 100 * (1 - f.after.cv_rmse_N / f.before.cv_rmse_N);
  $("lab-summary").textContent = `CV RMSE ${fmt(f.before.cv_rmse_N, 4)} N → ${fmt(f.after.cv_rmse_N, 4)} N (${fmt(-fall, 1)} %), noise floor ${fmt(f.noise_floor_N, 4)} N`;
};

connect();
refreshStatus();
setInterval(refreshStatus, 500);

// rigd's overlay page: live data over the WebSocket (proto SampleBatch, StateEvent,
// ModelInfo, CameraFrame), run control over the HTTP API, and the model-lab view.
"use strict";

const PHASE_COLORS = {approach: "#eceff1", insert: "#fff3e0", hold: "#f3e5f5", retract: "#e8f5e9", none: "#ffffff"};
const CATALOGUE = ["rate_dependence", "iop_stiffness", "shaft_friction", "rig_compliance", "sensor_drift",
                   "spatial_ripple", "mains_interference", "stick_slip", "stress_relaxation"];

// What the browser tests read (window.rig): counts of what is drawn, the state, the lab's figures.
const rig = window.rig = {samples: 0, modelPoints: 0, residualPoints: 0, frames: 0, state: "", runId: 0,
                          events: [], banner: "", lab: {before: null, after: null, verdict: null, plots: null},
                          mesh: {frames: 0, points: 0, punctured: false, maxDepth: 0, firstT: null, lastT: null}, haptic: null};
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
const plotWidth = () => Math.min(window.innerWidth - 80, 1400);
// uPlot ranges x from the first and last values (it expects x sorted); a cut's x goes in
// and back out, so the range comes from the data's own extremes.
let forceXRange = [0, 1], drawnPoints = 0;
const forcePlot = new uPlot({
  width: plotWidth(), height: 340, scales: {x: {time: false, range: () => forceXRange}}, legend: {live: false},
  series: [{label: "x [mm]"}, {label: "measured [N]", stroke: "#1565c0", width: 1},
           {label: "model [N]", stroke: "#e65100", width: 2, dash: [8, 4]}],
  axes: [{label: "displacement from the corneal surface [mm]", values: rigTicks}, {label: "force [N]", values: rigTicks, size: 60}],
}, [[], [], []], $("plot-force"));

// Phase spans of the shown run, from the samples' phases.
function phaseSpans(d) {
  const spans = [];
  for (let i = 0; i < d.t.length; ++i) {
    const last = spans[spans.length - 1];
    if (last && last.phase === d.phase[i]) last.t1 = d.t[i];
    else spans.push({phase: d.phase[i], t0: d.t[i], t1: d.t[i]});
  }
  return spans;
}
let spans = [];
const shadePhases = u => {
  const ctx = u.ctx;
  for (const p of spans) {
    const x0 = u.valToPos(p.t0, "x", true), x1 = u.valToPos(p.t1, "x", true);
    ctx.fillStyle = PHASE_COLORS[p.phase] || "#fff";
    ctx.fillRect(x0, u.bbox.top, Math.max(1, x1 - x0), u.bbox.height);
  }
};
const residualPlot = new uPlot({
  width: plotWidth(), height: 240, scales: {x: {time: false}}, legend: {live: false},
  hooks: {drawClear: [shadePhases], setCursor: [u => showCursor(u.cursor.idx)]},
  series: [{label: "t [s]"}, {label: "residual [N]", stroke: "#c62828", width: 1}],
  axes: [{label: "loop time [s]", values: rigTicks}, {label: "measured − model [N]", values: rigTicks, size: 60}],
}, [[], []], $("plot-residual"));

// What the browser tests read from the plots themselves (not from the stream).
function plotted() {
  // As drawn at the last redraw (the arrays grow in between).
  const [x, force, model] = forcePlot.data.map(column => column.slice(0, drawnPoints));
  const d = rigRun.view.data;
  let peak = -Infinity, peakX = null, duplicates = 0, holes = 0, xMin = Infinity, xMax = -Infinity, modelMax = -Infinity;
  for (let i = 0; i < x.length; ++i) {  // loops, not Math.max(...): a long run has more samples than a call has arguments
    if (force[i] > peak) { peak = force[i]; peakX = x[i]; }
    xMin = Math.min(xMin, x[i]); xMax = Math.max(xMax, x[i]);
    if (model[i] !== null && Number.isFinite(model[i])) modelMax = Math.max(modelMax, model[i]);
  }
  for (let i = 1; i < drawnPoints; ++i) { if (d.cycle[i] <= d.cycle[i - 1]) duplicates++; else if (d.cycle[i] !== d.cycle[i - 1] + 1) holes++; }
  return {runId: rigRun.view.runId, points: x.length, xMin, xMax, peakN: peak, peakX,
          modelPoints: model.filter(v => v !== null && Number.isFinite(v)).length, modelMax,
          xScale: [forcePlot.scales.x.min, forcePlot.scales.x.max],
          firstCycle: d.cycle[0], lastCycle: d.cycle[drawnPoints - 1], duplicates, holes,
          phases: [...new Set(d.phase)], gapsAccepted: rigRun.view.gaps};
}
rig.plotted = plotted;

function extent(values) {
  let lo = Infinity, hi = -Infinity;
  for (const v of values) if (Number.isFinite(v)) { lo = Math.min(lo, v); hi = Math.max(hi, v); }
  return lo <= hi ? [lo, hi > lo ? hi : lo + 1] : [0, 1];
}

let redrawPending = false;
function scheduleRedraw() {
  if (redrawPending) return;
  redrawPending = true;
  setTimeout(() => {
    redrawPending = false;
    const d = rigRun.view.data;
    spans = phaseSpans(d);
    forceXRange = extent(d.x);
    drawnPoints = d.x.length;
    forcePlot.setData([d.x, d.force, d.model], true);
    residualPlot.setData([d.t, d.residual], true);
    rig.samples = d.t.length;
    rig.modelPoints = rig.residualPoints = d.model.filter(v => v !== null && Number.isFinite(v)).length;
    rig.runId = rigRun.view.runId;
    drawEvents();
    drawRunCaption();
  }, 100);
}
rigRun.onChange(scheduleRedraw);

// The cursor on the residual plot: the sample's readings and the camera frame at it.
let frameShown = null;
async function showCursor(i) {
  const d = rigRun.view.data;
  if (i === null || i === undefined || i >= d.t.length) return;
  $("cursor").textContent = `cycle ${d.cycle[i]} · t ${fmt(d.t[i], 3)} s · x ${fmt(d.x[i], 3)} mm · ` +
    `measured ${fmt(d.force[i], 4)} N · model ${fmt(d.model[i], 4)} N · ${d.phase[i]}`;
  const f = rigRun.frameAt(d.cycle[i]);
  if (!f || !rigRun.view.runId || (frameShown && frameShown.run === rigRun.view.runId && frameShown.no === f.frame_no)) return;
  frameShown = {run: rigRun.view.runId, no: f.frame_no};
  const r = await fetch(`/api/runs/${rigRun.view.runId}/frames/${f.frame_no}`,
                        {headers: token ? {Authorization: "Bearer " + token} : {}});
  if (!r.ok) return;
  const w = +r.headers.get("X-Frame-Width"), h = +r.headers.get("X-Frame-Height");
  const grey = new Uint8Array(await r.arrayBuffer());
  const canvas = $("cursor-frame");
  canvas.width = w; canvas.height = h;
  const image = canvas.getContext("2d").createImageData(w, h);
  for (let p = 0; p < w * h; ++p) image.data.set([grey[p], grey[p], grey[p], 255], 4 * p);
  canvas.getContext("2d").putImageData(image, 0, 0);
  $("cursor-frame-caption").textContent = `frame ${f.frame_no}, triggered at cycle ${f.sample_index}`;
  rig.cursorFrames = (rig.cursorFrames || 0) + 1;
}

function drawEvents() {
  const events = rigRun.events();
  rig.events = events;
  $("events").innerHTML = events.length ? events.map(e =>
    `<tr class="ev-${e.kind}"><td>${fmt(e.t_s, 3)} s</td><td>${escapeHtml(e.kind)}</td><td>${escapeHtml(e.message)}</td></tr>`).join("")
    : "<tr><td>no events in this run</td></tr>";
}

function drawRunCaption() {
  const v = rigRun.view, info = v.info;
  const lab = typeof v.runId === "string";  // "lab:UUID": a run of the lab's archive
  const name = lab ? (info ? `${info.rig_id} run ${info.local_run_id} (lab archive)` : "lab archive run") : `run ${v.runId}`;
  $("run-caption").textContent = !v.runId ? "no run in the archive yet" :
    `${name}${info ? ` · eye ${info.eye_id} · ${info.outcome}${info.reason ? ": " + info.reason : ""}` : ""} · ` +
    `${v.data.t.length} samples${v.following ? " · following the rig" : ""}` + (v.gaps ? ` · ${v.gaps} gaps the archive could not fill` : "");
}

const escapeHtml = text => String(text).replace(/[&<>"]/g, c => ({"&": "&amp;", "<": "&lt;", ">": "&gt;", "\"": "&quot;"})[c]);

// The run picker: "follow the rig" or any archived run.
async function loadRunPicker() {
  try {
    const list = await api("/api/runs");
    const labOptions = await labArchiveOptions();  // before the rebuild: the list is replaced in one step
    const keep = $("run-pick").value;
    $("run-pick").innerHTML = `<option value="follow">the rig's current or last run</option>` +
      list.runs.slice().reverse().map(r => `<option value="${r.run_id}">run ${r.run_id} · ${escapeHtml(r.eye_id)} · ` +
        `${r.outcome}${r.reason ? " (" + escapeHtml(r.reason) + ")" : ""} · ${r.samples} samples</option>`).join("") + labOptions;
    $("run-pick").value = [...$("run-pick").options].some(o => o.value === keep) ? keep : "follow";
  } catch (e) { /* the status line says what is wrong */ }
}
// With [lab_archive] on: the lab's runs, of every rig, as "lab:UUID" options.
async function labArchiveOptions() {
  if (!rig.labArchive) return "";
  try {
    const list = await api("/api/lab-archive/runs");
    return `<optgroup label="lab archive (${list.total} runs)">` + list.runs.slice().reverse().map(r =>
      `<option value="lab:${r.run_uuid}">${escapeHtml(r.rig_id)} run ${r.local_run_id} · ${escapeHtml(r.eye_id)}` +
      `${r.eye_lot ? " · lot " + escapeHtml(r.eye_lot) : ""} · ${r.outcome} · ${r.samples} samples</option>`).join("") + "</optgroup>";
  } catch (e) {
    return `<optgroup label="lab archive: ${escapeHtml(e.message || e)}"></optgroup>`;
  }
}
$("run-pick").onchange = () => {
  const v = $("run-pick").value;
  if (v === "follow") rigRun.follow(); else rigRun.show(v.startsWith("lab:") ? v : +v, false);
};
$("run-pick").onfocus = loadRunPicker;

// ---------------------------------------------------------------- stream
function onMessage(event) {
  const m = JSON.parse(event.data);
  if (m.type === "samples") {
    rigRun.onLiveBatch(m);
  } else if (m.type === "event") {
    rigRun.onLiveEvent(m);
    if (m.kind === "run_ended" || m.kind === "run_started") loadRunPicker();
  } else if (m.type === "model") {
    if (m.warnings) $("model-warnings").textContent = m.warnings.map(w => "model: " + w).join("\n");
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
  rig.socket = ws;  // the browser tests drop it to check that a reconnect fills the gap
  ws.onopen = () => {
    $("conn").textContent = "live"; $("conn").className = "pill on";
    // Opened or reconnected: the whole run again from the archive, then the stream.
    if (rigRun.view.following) rigRun.follow().catch(() => {});
    loadRunPicker();
  };
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
    showLabArchive(s.lab_archive);
    const i = s.interlocks, stopped = s.state === "Fault" || s.state === "EStop";
    // Red while the input is active, and while the latched fault names it (until Reset).
    const named = text => stopped && s.fault.includes(text);
    const chips = [["home limit", i.home_limit || named("home limit")], ["end limit", i.end_limit || named("end limit")],
                   ["e-stop", i.estop_input || s.state === "EStop"], ["DAQ link down", !i.link_ok || named("DAQ link lost")]];
    $("interlocks").innerHTML = chips.map(([name, on]) => `<span class="${on ? "tripped" : ""}">${name}${on ? " ●" : ""}</span>`).join("") +
      `<span class="${s.motor_enabled ? "motor" : stopped ? "tripped" : ""}">motor ${s.motor_enabled ? "on" : "off"}</span>`;
    rig.tripped = [...chips.filter(([, on]) => on).map(([name]) => name), ...(stopped && !s.motor_enabled ? ["motor off"] : [])];
    showBanner(s);
    rig.motorEnabled = s.motor_enabled;
  } catch (e) { $("fault").textContent = String(e.message || e); }
}

// The lab archive's replicator (issue 16): shown only when [lab_archive] is on. A backlog is
// normal while a run records; one that grows while "not reachable" is what the lab must see.
function showLabArchive(lab) {
  $("lab-row").classList.toggle("hidden", !lab);
  rig.labArchive = !!lab;
  if (!lab) return;
  const backlog = `backlog ${lab.backlog_samples} samples in ${lab.backlog_runs} runs` +
    (lab.backlog_known ? "" : " (every run not yet confirmed: the server was not reached since rigd started)");
  const cell = $("r-lab");
  cell.textContent = lab.connected ? `connected as ${lab.rig_id}, ${backlog}`
                                   : `NOT REACHABLE as ${lab.rig_id}, ${backlog}${lab.last_error ? " — " + lab.last_error : ""}`;
  cell.className = lab.connected ? "" : "warn";
}

// What stopped the rig and what the technician does next, in words (docs/faults.md).
function nextAction(s) {
  if (s.state === "EStop") return s.interlocks.estop_input ? "Release the e-stop button, then press Reset, then Home."
                                                            : "Press Reset, then Home before the next cut.";
  if (s.state === "Fault") {
    if (!s.interlocks.link_ok || s.fault.includes("DAQ link")) return "Check the DAQ's cable and power; then press Reset, then Home.";
    return "Remove the cause, then press Reset, then Home before the next cut.";
  }
  if (!s.homed && s.state === "Idle") return "Not homed: press Home before a cut.";
  return "";
}
function showBanner(s) {
  const stopped = s.state === "Fault" || s.state === "EStop";
  const action = nextAction(s);
  const text = stopped ? `${s.state === "EStop" ? "E-STOP" : "FAULT"}: ${s.fault}. ${action}` : action;
  $("banner").textContent = text;
  $("banner").className = "banner " + (stopped ? "alarm" : text ? "hint" : "hidden");
  rig.banner = text;
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
    legend: {live: false},
    series: [{label: "phase"}, {label: "before [N]", fill: "#90a4ae", stroke: "#546e7a", paths: uPlot.paths.bars({size: [0.35], align: -1})},
             {label: "after [N]", fill: "#66bb6a", stroke: "#2e7d32", paths: uPlot.paths.bars({size: [0.35], align: 1})}],
    axes: [{label: "phase of the cut", splits: () => xs, values: (u, vals) => vals.map(v => phases[v] || "")},
           {label: "cross-validated RMSE [N]", values: rigTicks, size: 70}],
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

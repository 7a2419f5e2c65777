// The Haptics view: start/stop a haptic playback session in rigd (POST /api/haptic) and draw
// the mass-spring cornea's cross-section from the MeshFrame messages on the WebSocket.
"use strict";

(() => {
  const $ = id => document.getElementById(id);
  const fmt = (v, d) => (v === null || v === undefined || Number.isNaN(v)) ? "—" : Number(v).toFixed(d);
  const SHOWN_DEPTH_MM = 4;  // the tissue dents ~3.5 mm before the puncture
  let pending = null;            // latest frame, drawn on the next animation frame
  let statusTimer = null;

  async function call(path, body) {
    const headers = {"Content-Type": "application/json"};
    const token = sessionStorage.getItem("rigd-token");
    if (token) headers.Authorization = "Bearer " + token;
    const r = await fetch(path, body === undefined ? {headers} : {method: "POST", headers, body: JSON.stringify(body)});
    const json = await r.json();
    if (!r.ok) throw new Error(json.error || r.statusText);
    return json;
  }

  function draw(m) {
    const canvas = $("mesh-canvas"), ctx = canvas.getContext("2d");
    const w = canvas.width, h = canvas.height;
    const xs = m.x_mm, zs = m.z_mm;
    const span = Math.max(...xs.map(Math.abs), 1e-6) * 1.1;
    const scale = Math.min((w / 2) / span, (h - 60) / SHOWN_DEPTH_MM);  // px per mm, true proportions
    const px = x => w / 2 + x * scale;
    const pz = z => 30 + z * scale;
    ctx.clearRect(0, 0, w, h);
    ctx.fillStyle = "#e3f2fd";  // the anterior chamber under the cornea
    ctx.fillRect(0, pz(0), w, h - pz(0));
    ctx.strokeStyle = "#6d4c41";
    ctx.lineWidth = 3;
    ctx.beginPath();
    xs.forEach((x, i) => {
      // Across an opened cut, draw the two edges apart.
      const opened = m.punctured && i > 0 && xs[i - 1] < 0 && x > 0;
      if (i === 0 || opened) ctx.moveTo(px(x), pz(zs[i])); else ctx.lineTo(px(x), pz(zs[i]));
    });
    ctx.stroke();
    ctx.fillStyle = "#6d4c41";
    xs.forEach((x, i) => { ctx.beginPath(); ctx.arc(px(x), pz(zs[i]), 3, 0, 2 * Math.PI); ctx.fill(); });
    ctx.strokeStyle = "#37474f";  // the keratome, on the axis at the tip's depth
    ctx.lineWidth = 2;
    ctx.beginPath();
    ctx.moveTo(px(0), 0);
    ctx.lineTo(px(0), pz(Math.max(0, m.tip_depth_mm)));
    ctx.stroke();
    $("mesh-caption").textContent = `t ${fmt(m.t_s, 2)} s · tip ${fmt(m.tip_depth_mm, 3)} mm · force ${fmt(m.force_N, 4)} N` +
      (m.punctured ? " · punctured: the cut is open" : "");
  }

  function onMesh(m) {
    const mesh = window.rig.mesh;
    mesh.frames++;
    mesh.points = m.x_mm.length;
    mesh.punctured = mesh.punctured || m.punctured;
    mesh.maxDepth = Math.max(mesh.maxDepth, ...m.z_mm);
    if (mesh.firstT === null) mesh.firstT = m.t_s;
    mesh.lastT = m.t_s;
    if (window.rigCornea3d) window.rigCornea3d.onMesh(m);  // the 3D view (cornea3d.js)
    if (pending === null) requestAnimationFrame(() => { draw(pending); pending = null; });
    pending = m;
  }

  function showStatus(s) {
    window.rig.haptic = s;
    if (window.rigCornea3d) window.rigCornea3d.showFidelity(s);
    const rows = [["state", s.state], ["device", s.device], ["source", s.source], ["error", s.error],
                  ["servo rate", s.rate_hz && fmt(s.rate_hz, 1) + " Hz"], ["ticks", s.ticks], ["overruns", s.overruns],
                  ["tick p99", s.tick_p99_us && fmt(s.tick_p99_us, 0) + " µs"],
                  ["felt vs model", s.rmse_vs_model_N !== undefined && `RMSE ${fmt(s.rmse_vs_model_N * 1000, 2)} mN, max ${fmt(s.max_vs_model_N * 1000, 2)} mN`],
                  ["felt vs run", s.rmse_vs_run_N !== undefined && `RMSE ${fmt(s.rmse_vs_run_N * 1000, 2)} mN, max ${fmt(s.max_vs_run_N * 1000, 2)} mN`],
                  ["mesh", s.mesh_vertices && `${s.mesh_vertices} vertices, ${s.mesh_springs} springs`],
                  ["watchdog", s.watchdog_tripped ? "tripped: force turned off" : undefined],
                  ["longest servo gap", s.longest_tick_gap_ms && fmt(s.longest_tick_gap_ms, 1) + " ms"]];
    $("haptic-status").innerHTML = rows.filter(([, v]) => v !== undefined && v !== null && v !== false && v !== "")
      .map(([k, v]) => `<tr><th>${k}</th><td>${String(v).replace(/</g, "&lt;")}</td></tr>`).join("");
  }

  async function refresh() {
    try {
      const s = await call("/api/haptic");
      showStatus(s);
      if (s.state !== "running" && statusTimer !== null) { clearInterval(statusTimer); statusTimer = null; }
    } catch (e) { $("haptic-message").textContent = e.message; }
  }

  $("haptic-form").onsubmit = async event => {
    event.preventDefault();
    const f = new FormData(event.target);
    const body = {device: f.get("device"), source: String(f.get("source")).trim(), velocity_mm_s: +f.get("velocity_mm_s"),
                  iop_mmHg: +f.get("iop_mmHg"), mesh_n: +f.get("mesh_n")};
    Object.assign(window.rig.mesh, {frames: 0, points: 0, punctured: false, maxDepth: 0, firstT: null, lastT: null});
    try {
      showStatus(await call("/api/haptic", body));
      $("haptic-message").textContent = "playing " + body.source;
      if (statusTimer === null) statusTimer = setInterval(refresh, 300);
    } catch (e) { $("haptic-message").textContent = "refused: " + e.message; }
  };
  $("b-haptic-stop").onclick = async () => {
    try { showStatus(await call("/api/haptic/stop", {})); } catch (e) { $("haptic-message").textContent = e.message; }
  };

  window.rigHaptics = {onMesh, refresh};
})();

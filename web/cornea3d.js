// The Haptics tab's 3D view (three.js): the mass-spring cornea as rigd builds it
// (daemon/haptic/mass_spring_cornea.cpp: an n x n grid over a 6 mm patch, stretching,
// shearing and bending springs; n = 13 gives 169 vertices and 886 springs) and the
// keratome, redrawn on every animation frame from the latest MeshFrame. A MeshFrame of a
// mesh up to 1024 vertices carries every vertex (grid_x/y/z_mm): drawn as they are. A finer
// mesh sends only the centre row across the cut (x, depth); the other rows then take the
// same depth profile by distance from the tip (the dent under a round tip) and the rows the
// blade crosses open like the centre row. Beside it: felt force against the model's force.
import * as THREE from "./vendor/three.module.js";

const PATCH_MM = 6.0, BLADE_WIDTH_MM = 2.8, BLADE_THICKNESS_MM = 0.2;
// Springs are drawn as lines up to this many vertices; a finer mesh shows its surface only
// (100,000 lines in a software renderer cost more than a frame), at half resolution.
const MAX_VERTICES_WITH_SPRINGS = 2500;
const $ = id => document.getElementById(id);
const fmt = (v, d) => (v === null || v === undefined || Number.isNaN(v)) ? "—" : Number(v).toFixed(d);

// The spring list of an n x n grid, in the daemon's order and rule.
export function springsOf(n) {
  const springs = [];
  const at = (r, c) => r * n + c;
  for (let r = 0; r < n; ++r) {
    for (let c = 0; c < n; ++c) {
      if (c + 1 < n) springs.push(at(r, c), at(r, c + 1));
      if (r + 1 < n) springs.push(at(r, c), at(r + 1, c));
      if (r + 1 < n && c + 1 < n) springs.push(at(r, c), at(r + 1, c + 1));
      if (r + 1 < n && c > 0) springs.push(at(r, c), at(r + 1, c - 1));
      if (c + 2 < n) springs.push(at(r, c), at(r, c + 2));
      if (r + 2 < n) springs.push(at(r, c), at(r + 2, c));
    }
  }
  return springs;
}

class CorneaView {
  constructor(container) {
    this.container = container;
    this.renderer = new THREE.WebGLRenderer({antialias: false});
    this.renderer.setPixelRatio(1);
    this.renderer.setSize(container.clientWidth || 640, container.clientHeight || 420);
    container.appendChild(this.renderer.domElement);
    this.scene = new THREE.Scene();
    this.scene.background = new THREE.Color(0xf4f6f8);
    this.camera = new THREE.PerspectiveCamera(40, (container.clientWidth || 640) / (container.clientHeight || 420), 0.1, 100);
    this.scene.add(new THREE.AmbientLight(0xffffff, 0.55));
    const light = new THREE.DirectionalLight(0xffffff, 0.9);
    light.position.set(3, 6, 8);
    this.scene.add(light);
    this.turn = 0.6;
    this.tilt = 0.9;
    this.placeCamera();
    this.addKeratome();
    this.frame = null;
    this.stats = {frames: 0, intervals: []};
    let drag = null;
    container.addEventListener("pointerdown", e => { drag = {x: e.clientX, y: e.clientY}; });
    window.addEventListener("pointerup", () => { drag = null; });
    container.addEventListener("pointermove", e => {
      if (!drag) return;
      this.turn += (e.clientX - drag.x) * 0.01;
      this.tilt = Math.min(1.5, Math.max(0.1, this.tilt + (e.clientY - drag.y) * 0.01));
      drag = {x: e.clientX, y: e.clientY};
      this.placeCamera();
      this.moved = true;
    });
    this.setGrid(13);
  }

  placeCamera() {
    const d = 11;
    this.camera.position.set(d * Math.sin(this.turn) * Math.sin(this.tilt), d * Math.cos(this.tilt), d * Math.cos(this.turn) * Math.sin(this.tilt));
    this.camera.lookAt(0, -1, 0);
  }

  // The keratome: a thin blade along the cut (y), its tip at the tip's depth.
  addKeratome() {
    const blade = new THREE.BoxGeometry(BLADE_THICKNESS_MM, 14, BLADE_WIDTH_MM);
    blade.translate(0, 7, 0);  // bottom edge (the tip) at y = 0, long enough to stand out of the cornea
    this.keratome = new THREE.Mesh(blade, new THREE.MeshLambertMaterial({color: 0x607d8b, transparent: true, opacity: 0.85}));
    this.scene.add(this.keratome);
  }

  // A fresh n x n grid at rest. Scene axes: x across the cut, z along it, y up (depth down).
  setGrid(n) {
    if (this.n === n) return;
    this.n = n;
    for (const o of [this.surface, this.lines]) if (o) { this.scene.remove(o); o.geometry.dispose(); }
    const count = n * n, spacing = PATCH_MM / (n - 1), half = PATCH_MM / 2;
    this.rest = new Float32Array(count * 2);
    for (let r = 0; r < n; ++r) for (let c = 0; c < n; ++c) {
      this.rest[2 * (r * n + c)] = c * spacing - half;
      this.rest[2 * (r * n + c) + 1] = r * spacing - half;
    }
    this.positions = new THREE.BufferAttribute(new Float32Array(count * 3), 3);
    this.positions.setUsage(THREE.DynamicDrawUsage);
    const triangles = [];
    for (let r = 0; r + 1 < n; ++r) for (let c = 0; c + 1 < n; ++c) {
      const a = r * n + c, b = a + 1, d = a + n, e = d + 1;
      triangles.push(a, d, b, b, d, e);
    }
    const surface = new THREE.BufferGeometry();
    surface.setAttribute("position", this.positions);
    surface.setIndex(count > 65535 ? new THREE.Uint32BufferAttribute(triangles, 1) : new THREE.Uint16BufferAttribute(triangles, 1));
    // Flat shading: normals from screen-space derivatives, none recomputed on the CPU per frame.
    this.surface = new THREE.Mesh(surface, new THREE.MeshLambertMaterial({color: 0xd7a98c, side: THREE.DoubleSide, flatShading: true}));
    const springs = springsOf(n);
    this.springCount = springs.length / 2;
    const lines = new THREE.BufferGeometry();
    lines.setAttribute("position", this.positions);
    lines.setIndex(count > 65535 ? new THREE.Uint32BufferAttribute(springs, 1) : new THREE.Uint16BufferAttribute(springs, 1));
    this.lines = new THREE.LineSegments(lines, new THREE.LineBasicMaterial({color: 0x5d4037}));
    this.lines.visible = count <= MAX_VERTICES_WITH_SPRINGS;
    this.scene.add(this.surface, this.lines);
    // A mesh finer than the picture (130 x 130 cells over ~400 px: 3 px a cell) is drawn at
    // half resolution, scaled up by the browser: software WebGL's cost is per pixel and per
    // triangle, and a cell still covers a pixel and a half.
    this.renderer.setPixelRatio(count > MAX_VERTICES_WITH_SPRINGS ? 0.5 : 1);
    this.show({x_mm: [], z_mm: [], tip_depth_mm: 0, punctured: false});
  }

  // Vertex positions from a MeshFrame: the daemon's own, or from its centre row (file head).
  deform(m) {
    this.keratome.position.y = -Math.max(0, m.tip_depth_mm || 0);
    const p = this.positions.array;
    this.whole = Boolean(m.grid_z_mm && m.grid_z_mm.length === this.n * this.n);
    if (this.whole) {
      for (let i = 0; i < m.grid_z_mm.length; ++i) {
        p[3 * i] = m.grid_x_mm[i];
        p[3 * i + 1] = -m.grid_z_mm[i];
        p[3 * i + 2] = m.grid_y_mm[i];
      }
      this.positions.needsUpdate = true;
      return;
    }
    const n = this.n, xs = m.x_mm, zs = m.z_mm, rows = xs.length === n;
    const spacing = PATCH_MM / (n - 1), half = PATCH_MM / 2;
    const depthAt = radius => {  // the centre row's depth at a distance from the axis, both sides averaged
      if (!rows) return 0;
      const u = Math.min(n - 1, radius / spacing);
      const c0 = Math.floor(u), f = u - c0, mid = (n - 1) / 2;
      const side = k => (zs[Math.min(n - 1, Math.round(mid + k))] + zs[Math.max(0, Math.round(mid - k))]) / 2;
      return (1 - f) * side(c0) + f * side(Math.min(c0 + 1, n - 1));
    };
    for (let r = 0; r < n; ++r) for (let c = 0; c < n; ++c) {
      const i = r * n + c, x0 = this.rest[2 * i], y0 = this.rest[2 * i + 1];
      const rim = r === 0 || c === 0 || r === n - 1 || c === n - 1;
      const opened = rows && m.punctured && Math.abs(y0) <= BLADE_WIDTH_MM / 2 ? xs[c] - (c * spacing - half) : 0;
      p[3 * i] = x0 + opened;
      p[3 * i + 1] = rim ? 0 : -depthAt(Math.sqrt(x0 * x0 + y0 * y0));
      p[3 * i + 2] = y0;
    }
    this.positions.needsUpdate = true;
  }

  show(m) {
    this.frame = m;
    this.dirty = true;
  }

  // One animation frame: the latest MeshFrame (if new), then the picture.
  render(now) {
    // Drawn only when something changed and the Haptics tab is shown: software WebGL costs
    // a core's share at 60 frames/s, and the Live tab needs the machine.
    const visible = this.container.offsetParent !== null;
    if (visible && !this.wasVisible) this.moved = true;  // the tab was just opened
    this.wasVisible = visible;
    if ((!this.dirty && !this.moved) || !visible) return;
    if (this.dirty) { this.deform(this.frame); this.dirty = false; }
    this.moved = false;
    this.renderer.render(this.scene, this.camera);
    if (this.last !== undefined) this.stats.intervals.push(now - this.last);
    if (this.stats.intervals.length > 2000) this.stats.intervals.shift();
    this.last = now;
    this.stats.frames++;
  }
}

// Felt force (MeshFrame force_N) and the model's force at the same tip depth.
class FeltPlot {
  constructor(el) {
    this.el = el;
    this.depth = []; this.felt = []; this.model = [];
    this.curve = null;
    this.range = [0, 1];
    this.plot = new window.uPlot({
      // x (the tip's depth) goes in and back out: ranged from its extremes, not first/last.
      width: 520, height: 300, scales: {x: {time: false, range: () => this.range}}, legend: {live: false},
      series: [{label: "tip depth [mm]"}, {label: "felt [N]", stroke: "#1565c0", width: 1, points: {show: false}},
               {label: "model [N]", stroke: "#e65100", width: 2, dash: [8, 4], points: {show: false}}],
      axes: [{label: "tip depth below the surface [mm]", values: window.rigTicks}, {label: "force [N]", values: window.rigTicks, size: 60}],
    }, [[], [], []], el);
  }
  async loadModel() {
    try { this.curve = await (await fetch("/api/model")).json(); } catch (e) { this.curve = null; }
  }
  modelAt(x) {
    const c = this.curve;
    if (!c || !c.x_mm || !c.x_mm.length || x < 0) return null;
    const step = c.x_mm[1] - c.x_mm[0], i = Math.min(c.x_mm.length - 1, Math.floor(x / step));
    return c.force_N[i];
  }
  reset() { this.depth.length = this.felt.length = this.model.length = 0; }
  add(m) {
    this.depth.push(m.tip_depth_mm); this.felt.push(m.force_N); this.model.push(this.modelAt(m.tip_depth_mm));
  }
  draw() {
    this.range = [this.depth.reduce((m, v) => Math.min(m, v), 0), this.depth.reduce((m, v) => Math.max(m, v), 0.1)];
    this.plot.setData([this.depth, this.felt, this.model], true);
  }
}

const view = new CorneaView($("cornea3d"));
const felt = new FeltPlot($("plot-felt"));
felt.loadModel();
let feltDirty = false;

function onFrame(now) {
  view.render(now);
  if (feltDirty) { felt.draw(); feltDirty = false; }
  requestAnimationFrame(onFrame);
}
requestAnimationFrame(onFrame);

// Fed by haptics.js with every MeshFrame of the session.
function onMesh(m) {
  if (m.x_mm.length !== view.n) { view.setGrid(m.x_mm.length); felt.reset(); felt.loadModel(); }
  else if (window.rig.mesh.frames === 1) felt.reset();  // a new session's first frame (haptics.js)
  view.show(m);
  window.rig.mesh.whole = Boolean(m.grid_z_mm);
  felt.add(m);
  feltDirty = true;
  $("cornea3d-caption").textContent = `${view.n * view.n} vertices, ${view.springCount} springs` +
    (view.lines.visible ? "" : " (surface only)") + (view.whole ? " as rigd has them" : " (rows from the centre row)") + ` · tip ${fmt(m.tip_depth_mm, 3)} mm · ` +
    `felt ${fmt(m.force_N, 4)} N` + (m.punctured ? " · punctured: the cut is open" : "");
}

function showFidelity(s) {
  if (s.rmse_vs_model_N === undefined) return;
  $("fidelity").textContent = `felt vs model: RMSE ${fmt(s.rmse_vs_model_N * 1000, 2)} mN, max ${fmt(s.max_vs_model_N * 1000, 2)} mN` +
    (s.rmse_vs_run_N !== undefined ? ` · felt vs run: RMSE ${fmt(s.rmse_vs_run_N * 1000, 2)} mN` : "") +
    ` · servo ${fmt(s.rate_hz, 1)} Hz, tick p99 ${fmt(s.tick_p99_us, 0)} µs`;
}

// For the browser test: n x n vertices deformed by a moving synthetic dent every frame for
// ms; the frame intervals measured with requestAnimationFrame timestamps.
async function benchmark(n, ms) {
  view.setGrid(n);
  view.stats = {frames: 0, intervals: []};
  const xs = [], started = performance.now();
  const spacing = PATCH_MM / (n - 1);
  for (let c = 0; c < n; ++c) xs.push(c * spacing - PATCH_MM / 2);
  while (performance.now() - started < ms) {
    const depth = 2 * (1 + Math.sin((performance.now() - started) / 300));
    view.show({x_mm: xs, z_mm: xs.map(x => depth * Math.exp(-(x * x) / 2)), tip_depth_mm: depth, punctured: false});
    await new Promise(r => requestAnimationFrame(r));
  }
  const sorted = view.stats.intervals.slice(1).sort((a, b) => a - b);
  const median = sorted[Math.floor(sorted.length / 2)];
  const elapsed = performance.now() - started;
  return {vertices: n * n, springs: view.springCount, frames: view.stats.frames, seconds: elapsed / 1000,
          fps: view.stats.frames / (elapsed / 1000), medianIntervalMs: median, medianFps: 1000 / median,
          p95IntervalMs: sorted[Math.floor(sorted.length * 0.95)]};
}

window.rigCornea3d = {onMesh, showFidelity, benchmark, view, felt, renderer: () => view.renderer.getContext().getParameter(0x1F01)};

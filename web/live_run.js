// The run on the Live tab, whole: fetched from the archive from its first sample
// (GET /api/runs/ID/stream?from=CYCLE), then followed on the WebSocket by loop cycle, the
// samples' sequence number. A live batch whose first new cycle is not the next one waits
// while the archive fills the gap (the recorder commits every flush interval, so the
// archive may lag the stream by that much); a sample already held is never added twice.
// Used by app.js: rigRun.onLiveBatch(batch), rigRun.onLiveEvent(event), rigRun.show(id).
/* exported rigRun */
"use strict";

const rigRun = (() => {
  const GAP_RETRY_MS = 200;     // the archive's flush interval is 50 ms by default
  const GAP_GIVE_UP_MS = 10000;  // then the gap stays, counted and shown
  const columns = () => ({cycle: [], t: [], x: [], force: [], model: [], residual: [], phase: []});
  const view = {runId: 0, following: true, lastCycle: -1, data: columns(), events: [], liveEvents: [], frames: [],
                info: null, pending: [], filling: false, gaps: 0, duplicatesDropped: 0, generation: 0};
  let listeners = [];

  const notify = () => listeners.forEach(f => f(view));

  function append(cols, i) {
    const d = view.data;
    d.cycle.push(cols.cycle[i]);
    d.t.push(cols.t_s[i]);
    d.x.push(cols.x_mm[i]);
    d.force.push(cols.force_N[i]);
    d.model.push(cols.model_N[i]);
    d.residual.push(cols.residual_N[i]);
    d.phase.push(cols.phase[i]);
    view.lastCycle = cols.cycle[i];
  }

  // Appends the samples after lastCycle; returns false at a gap (nothing appended past it).
  function appendFrom(cols, allowGap) {
    for (let i = 0; i < cols.cycle.length; ++i) {
      const c = cols.cycle[i];
      if (c <= view.lastCycle) { view.duplicatesDropped++; continue; }
      if (view.lastCycle >= 0 && c !== view.lastCycle + 1 && !allowGap) return false;
      if (view.lastCycle >= 0 && c !== view.lastCycle + 1) view.gaps++;
      append(cols, i);
    }
    return true;
  }

  async function getJson(path) {
    const headers = {};
    const token = sessionStorage.getItem("rigd-token");
    if (token) headers.Authorization = "Bearer " + token;
    const r = await fetch(path, {headers});
    const json = await r.json();
    if (!r.ok) throw new Error(json.error || r.statusText);
    return json;
  }

  // Everything the archive holds of the run after lastCycle (in pages).
  async function fetchArchive(generation) {
    for (;;) {
      const lab = typeof view.runId === "string";  // "lab:UUID": the lab's PostgreSQL archive
      const path = lab ? `/api/lab-archive/runs/${view.runId.slice(4)}/stream` : `/api/runs/${view.runId}/stream`;
      const part = await getJson(`${path}?from=${view.lastCycle + 1}`);
      if (generation !== view.generation) return false;
      view.info = part;
      view.events = part.events;
      view.frames = part.frames;
      appendFrom(part, view.lastCycle < 0);
      if (!part.more) return true;
    }
  }

  // Live batches waiting for the archive to reach them.
  async function drain(generation) {
    if (view.filling) return;
    view.filling = true;
    let waitingSince = null;
    try {
      while (view.pending.length && generation === view.generation) {
        const b = view.pending[0];
        const fresh = b.cycle.findIndex(c => c > view.lastCycle);
        const gap = fresh >= 0 && (view.lastCycle < 0 || b.cycle[fresh] !== view.lastCycle + 1);
        const stale = waitingSince !== null && Date.now() - waitingSince > GAP_GIVE_UP_MS;
        if (gap && !stale) {
          waitingSince = waitingSince ?? Date.now();
          await fetchArchive(generation);
          const stillGap = view.lastCycle < 0 || b.cycle[b.cycle.findIndex(c => c > view.lastCycle)] > view.lastCycle + 1;
          if (stillGap) await new Promise(r => setTimeout(r, GAP_RETRY_MS));
          continue;
        }
        // A hole inside the batch (the stream's ring dropped samples): appended up to it,
        // the rest waits for the archive like any gap.
        if (appendFrom(b, stale)) { view.pending.shift(); waitingSince = null; }
        notify();
      }
    } catch (e) {
      console.warn("run archive:", e);
    } finally {
      view.filling = false;
    }
  }

  async function show(runId, following) {
    view.generation++;
    Object.assign(view, {runId, following, lastCycle: -1, data: columns(), events: [], liveEvents: [], frames: [],
                         info: null, pending: [], gaps: 0, duplicatesDropped: 0});
    notify();
    if (!runId) return;
    const generation = view.generation;
    try {
      await fetchArchive(generation);
    } catch (e) {
      console.warn("run archive:", e);
    }
    if (generation === view.generation) { notify(); drain(generation); }
  }

  // The run to follow when the page opens: the one recording, else the last one archived.
  async function follow() {
    const status = await getJson("/api/status");
    let runId = status.run_id;
    if (!runId) {
      const list = await getJson("/api/runs");
      const rigRuns = list.runs.filter(r => r.samples > 0);
      runId = rigRuns.length ? rigRuns[rigRuns.length - 1].run_id : 0;
    }
    await show(runId, true);
  }

  function onLiveBatch(b) {
    if (!view.following || !b.run_id || !b.cycle) return;
    if (b.run_id !== view.runId) { show(b.run_id, true); }
    view.pending.push(b);
    drain(view.generation);
  }

  function onLiveEvent(e) {
    if (!view.following) return;
    if (e.run_id && e.run_id !== view.runId) return;
    view.liveEvents.push(e);
    notify();
    // The run closed: its outcome, reason and last samples from the archive once recorded.
    if (e.kind === "run_ended" || e.kind === "fault") {
      const generation = view.generation;
      setTimeout(() => fetchArchive(generation).then(notify).catch(() => {}), 300);
    }
  }

  // The run's events: the archive's, then the live ones it does not have yet (same time and kind).
  function events() {
    const key = e => `${Number(e.t_s).toFixed(4)}|${e.kind}`;
    const archived = new Set(view.events.map(key));
    const live = view.liveEvents.filter(e => !archived.has(key(e)))
      .map(e => ({t_s: e.t_s, kind: e.kind, message: e.message, live: true}));
    return [...view.events, ...live].sort((a, b) => a.t_s - b.t_s);
  }

  // The camera frame at or before a sample's cycle (null if the run has none).
  function frameAt(cycle) {
    let best = null;
    for (const f of view.frames) if (f.sample_index <= cycle && (!best || f.sample_index > best.sample_index)) best = f;
    return best;
  }

  return {view, show, follow, onLiveBatch, onLiveEvent, events, frameAt, onChange: f => listeners.push(f)};
})();
if (typeof module !== "undefined") module.exports = {rigRun};

// The model lab's "where does it fail" plots, shared by the page's Model lab tab and the
// HTML report (which inlines this file): the signed residual (measured - model) against
// depth with insertion and retraction apart, against time in the hold, and per-run small
// multiples of measured and model force (before/after a fit). `series` is the "series"
// object of the lab's JSON (model/lab/report/report_series.cpp).
/* exported rigLabPlots, rigTicks */
// uPlot axis labels with as many decimals as the tick spacing needs (0.0020, 0.0025, ...
// not "0.002" five times), the same for every tick of an axis.
function rigTicks(u, splits, axisIdx, space, incr) {
  const step = incr || (splits.length > 1 ? Math.abs(splits[1] - splits[0]) : 1);
  let decimals = 0;  // the fewest that show the step exactly (0.25 needs 2)
  while (decimals < 10 && Math.abs(Math.round(step * 10 ** decimals) - step * 10 ** decimals) > 1e-6 * 10 ** decimals) decimals++;
  return splits.map(v => (v === null || v === undefined) ? "" : Number(v).toFixed(decimals));
}
function rigLabPlots(container, series, uPlot, options) {
  const width = (options && options.width) || 1000;
  container.innerHTML = "";
  if (!series || !series.runs) return;
  const hasAfter = series.after !== undefined;
  const section = (title, id, note) => {
    container.insertAdjacentHTML("beforeend", `<h2>${title}</h2>${note ? `<p class="note">${note}</p>` : ""}<div id="${id}" class="lab-plot"></div>`);
    return container.querySelector("#" + id);
  };
  const line = (label, stroke, dash) => ({label, stroke, width: dash ? 2 : 1, dash, spanGaps: false});
  const d = series.depth;
  const depthEl = section("Signed residual against depth", "lab-depth",
    `measured - model, mean per ${d.bin_mm.toFixed(2)} mm; insertion and retraction apart, so hysteresis shows as the curves parting`);
  const depthSeries = [{label: "x [mm]"}, line("insertion, " + series.before, "#1f77b4"), line("retraction, " + series.before, "#d62728")];
  const depthData = [d.x_mm, d.insertion_N, d.retraction_N];
  if (hasAfter) {
    depthSeries.push(line("insertion, " + series.after, "#1f77b4", [6, 4]), line("retraction, " + series.after, "#d62728", [6, 4]));
    depthData.push(d.after_insertion_N, d.after_retraction_N);
  }
  new uPlot({width, height: 300, series: depthSeries, scales: {x: {time: false}}, legend: {live: false},
             axes: [{label: "x [mm]", values: rigTicks}, {label: "residual [N]", values: rigTicks, size: 60}]}, depthData, depthEl);
  if (series.hold.length) {
    const holdEl = section("Signed residual against time in the hold", "lab-hold", "one trace per run; a decay that the model misses shows here");
    series.hold.forEach((h, i) => {
      const s = [{label: "time in hold [s]"}, line(h.label + ", " + series.before, "#9467bd")];
      const data = [h.t_s, h.residual_N];
      if (hasAfter) { s.push(line(h.label + ", " + series.after, "#2ca02c", [6, 4])); data.push(h.after_residual_N); }
      const el = document.createElement("div");
      el.className = "lab-hold-run";
      holdEl.appendChild(el);
      new uPlot({width: Math.min(width, 540), height: 200, title: h.label, series: s, scales: {x: {time: false}}, legend: {live: false},
                 axes: [{label: "t in hold [s]", values: rigTicks}, {label: "residual [N]", values: rigTicks, size: 60}]}, data, el);
    });
  }
  const runsEl = section("Every run: measured and model force", "lab-runs", hasAfter ? "dashed: " + series.after : "");
  runsEl.style.display = "flex";
  runsEl.style.flexWrap = "wrap";
  series.runs.forEach(r => {
    const s = [{label: "t [s]"}, line("measured", "#333"), line(series.before, "#1f77b4")];
    const data = [r.t_s, r.measured_N, r.model_N];
    if (hasAfter) { s.push(line(series.after, "#ff7f0e", [6, 4])); data.push(r.after_N); }
    const el = document.createElement("div");
    el.className = "lab-run";
    runsEl.appendChild(el);
    const rmse = `RMSE ${r.rmse_N.toFixed(4)} N` + (hasAfter ? ` -> ${r.after_rmse_N.toFixed(4)} N` : "");
    new uPlot({width: 360, height: 220, title: `${r.label} (${rmse})`, legend: {show: false}, series: s, scales: {x: {time: false}},
               axes: [{label: "t [s]", values: rigTicks}, {label: "F [N]", values: rigTicks, size: 60}]}, data, el);
  });
}
if (typeof module !== "undefined") module.exports = {rigLabPlots, rigTicks};

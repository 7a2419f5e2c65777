// The Haptics tab's 3D cornea (three.js, web/cornea3d.js): the default mass-spring mesh
// (13 x 13 = 169 vertices, 886 springs) and a 130 x 130 one (16,900 vertices), deformed on
// every animation frame; frame rate from requestAnimationFrame timestamps, printed as a
// figure (lines "FPS |"). The test holds the view to drawing at all (>= 3 frames in 3 s: a
// frozen view draws one; 10 was a rate, missed with 9 under busy-machine on 2026-12-02); the
// 30 frames/s target is checked with --fps-min 30 (a timing target, not for a shared CI
// machine: docs/haptics.md gives the command and the figures). Screenshots go to --artifacts.
import { args, startRig, openPage, until, artifacts, test } from "./harness.mjs";

const a = args();
const shot = artifacts(a.artifacts);
const MEASURE_MS = 3000;
const FPS_MIN = a["fps-min"] === undefined ? null : Number(a["fps-min"]);

await test("Browser.TheCorneaIn3DDrawsTheDefaultAndA16900VertexMeshAndPrintsItsFrameRate", async () => {
  const rig = await startRig(a.bin, a.source);
  const {browser, page} = await openPage(rig.url);
  try {
    await page.click("button[data-view=haptics]");
    await until("the 3D view", () => page.evaluate(() => window.rigCornea3d !== undefined), 10000);
    const renderer = await page.evaluate(() => window.rigCornea3d.renderer());
    for (const [n, name] of [[13, "cornea3d-default-mesh.png"], [130, "cornea3d-16900-vertices.png"]]) {
      const r = await page.evaluate(([side, ms]) => window.rigCornea3d.benchmark(side, ms), [n, MEASURE_MS]);
      console.log(`  FPS | ${r.vertices} vertices, ${r.springs} springs | median ${r.medianFps.toFixed(1)} frames/s ` +
                  `(median interval ${r.medianIntervalMs.toFixed(1)} ms, p95 ${r.p95IntervalMs.toFixed(1)} ms), ` +
                  `mean ${r.fps.toFixed(1)} frames/s over ${r.seconds.toFixed(1)} s | WebGL ${renderer}`);
      await page.locator("#cornea3d").screenshot({path: shot(name)});
      if (n === 13 && (r.vertices !== 169 || r.springs !== 886)) throw new Error(`default mesh ${r.vertices}/${r.springs}`);
      if (!(r.frames >= 3)) throw new Error(`${r.vertices} vertices: ${r.frames} frames drawn in ${r.seconds.toFixed(1)} s`);
      if (FPS_MIN !== null && !(r.medianFps >= FPS_MIN)) throw new Error(`${r.vertices} vertices drawn at ${r.medianFps.toFixed(1)} frames/s (median), under ${FPS_MIN}`);
    }
  } finally {
    await browser.close();
    rig.stop();
  }
});

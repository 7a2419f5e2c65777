// From the page: home, tare, start a cut, see the plot fill with the model curve and the
// residual, press STOP, see the rig stop. Screenshots go to --artifacts.
import { args, startRig, openPage, status, until, artifacts, test } from "./harness.mjs";

const a = args();
const shot = artifacts(a.artifacts);

await test("Browser.ACutStartedFromThePageFillsThePlotsAndStopStopsTheRig", async () => {
  const rig = await startRig(a.bin, a.source);
  const {browser, page} = await openPage(rig.url);
  try {
    await page.click("#b-home");  // confirm() accepted by the harness
    await until("Ready after homing", async () => (await status(rig.url)).state === "Ready", 60000);
    await page.click("#b-tare");
    await until("tared", async () => (await status(rig.url)).tared, 10000);
    await page.fill("input[name=eye_id]", "BROWSER-1");
    await page.fill("textarea[name=meta]", "temperature_C=21");
    await page.click("#b-run");
    await until("the cut past the puncture (3000 samples, model and residual drawn)", () => page.evaluate(
      () => window.rig.samples > 3000 && window.rig.modelPoints > 2000 && window.rig.residualPoints > 2000), 40000);
    const drawn = await page.evaluate(() => ({samples: window.rig.samples, model: window.rig.modelPoints, frames: window.rig.frames}));
    if (drawn.frames < 1) throw new Error("no camera frame reached the page");
    await page.screenshot({path: shot("live-overlay-cutting.png"), fullPage: true});
    await page.click("#stop");
    await until("the rig stopped", async () => { const s = await status(rig.url); return s.state === "Done" && !s.motor_enabled; }, 5000);
    await until("the page shows Done", () => page.evaluate(() => window.rig.state === "Done"), 3000);
    // The recorder closes the run once it has drained the loop's ring (asynchronously).
    let run = null;
    await until("the archive keeps the run as stopped", async () => {
      const runs = await (await fetch(rig.url + "/api/runs")).json();
      run = runs.runs[runs.runs.length - 1];
      return run.outcome === "stopped";
    }, 5000);
    if (run.samples < 3000) throw new Error(`run kept with too few samples: ${JSON.stringify(run)}`);
    await page.screenshot({path: shot("live-overlay-stopped.png"), fullPage: true});
    console.log(`  drawn ${drawn.samples} samples, ${drawn.model} with model and residual, ${drawn.frames} camera frames; run ${run.run_id} ${run.outcome}`);
  } finally {
    await browser.close();
    rig.stop();
  }
});

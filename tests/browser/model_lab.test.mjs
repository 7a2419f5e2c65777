// The model-lab view: runs with friction along the blade (imported into the archive), the
// diagnosis names it, ticking it and refitting makes the error fall.
import { args, startRig, openPage, until, artifacts, test, execFileSync } from "./harness.mjs";
import { mkdtempSync, readdirSync } from "node:fs";
import { tmpdir } from "node:os";
import { join } from "node:path";

const a = args();
const shot = artifacts(a.artifacts);

await test("Browser.TogglingTheMissingEffectInTheModelLabMakesTheErrorFall", async () => {
  const dir = mkdtempSync(join(tmpdir(), "rig-lab-"));
  const rigCli = join(a.bin, "rig");
  execFileSync(rigCli, ["sim", "generate", "--out", join(dir, "runs"), "--effect", "shaft_friction", "--iops", "15,18",
                        "--velocities", "1.5,3", "--depth", "11"], {stdio: "ignore"});
  const files = readdirSync(join(dir, "runs")).map(f => join(dir, "runs", f));
  const archive = join(dir, "archive.sqlite");
  execFileSync(rigCli, ["--archive", archive, "import", ...files], {stdio: "ignore"});
  const rig = await startRig(a.bin, a.source, archive);
  const {browser, page} = await openPage(rig.url);
  try {
    await page.click("button[data-view=lab]");
    await page.waitForSelector(".run-pick");
    await page.click("#b-diagnose");
    await until("the diagnosis", () => page.evaluate(() => window.rig.lab.verdict !== null), 120000);
    const verdict = await page.evaluate(() => window.rig.lab.verdict);
    if (verdict !== "shaft_friction") throw new Error(`diagnosis named ${verdict}`);
    if (!(await page.isChecked(".effect-pick[value=shaft_friction]"))) throw new Error("the verdict was not ticked");
    // The "where does it fail" plots (web/lab_plots.js, as in the HTML report): the signed
    // residual by depth for insertion and retraction, one small multiple per run.
    const diagnosed = await page.evaluate(() => window.rig.lab.plots);
    if (!diagnosed || diagnosed.action !== "diagnose" || diagnosed.runs !== files.length || diagnosed.retractionBins < 20 ||
        diagnosed.canvases < files.length + 1) throw new Error(`diagnosis plots: ${JSON.stringify(diagnosed)}`);
    await page.screenshot({path: shot("model-lab-diagnosis.png"), fullPage: true});
    await page.click("#b-fit");
    await until("the refit", () => page.evaluate(() => window.rig.lab.after !== null), 120000);
    const lab = await page.evaluate(() => window.rig.lab);
    if (!(lab.after < 0.5 * lab.before)) throw new Error(`error did not fall: ${lab.before} -> ${lab.after}`);
    if (!lab.plots || lab.plots.action !== "fit" || !lab.plots.after || lab.plots.runs !== files.length)
      throw new Error(`fit plots lack the before/after overlay: ${JSON.stringify(lab.plots)}`);
    await page.screenshot({path: shot("model-lab-error-falls.png"), fullPage: true});
    console.log(`  verdict ${verdict}; CV RMSE ${lab.before.toFixed(4)} N -> ${lab.after.toFixed(4)} N`);
  } finally {
    await browser.close();
    rig.stop();
  }
});

await test("Browser.TheFitReportDrawsItsPlotsOfflineWithTheBeforeAfterOverlay", async () => {
  const dir = mkdtempSync(join(tmpdir(), "rig-report-"));
  const rigCli = join(a.bin, "rig");
  execFileSync(rigCli, ["sim", "generate", "--out", join(dir, "runs"), "--effect", "shaft_friction", "--iops", "15,18",
                        "--velocities", "2", "--depth", "11", "--hold", "1"], {stdio: "ignore"});
  const env = {...process.env};
  delete env.RIG_WEB_ROOT;  // found from the build tree, as after ./rig setup in a fresh checkout
  const report = join(dir, "fit.html");
  execFileSync(rigCli, ["model", "fit", join(dir, "runs"), "--add", "shaft_friction", "--report", report], {stdio: "ignore", env});
  const {browser, page} = await openPage("file://" + report);
  try {
    const drawn = await page.evaluate(() => ({
      canvases: document.querySelectorAll("#lab-plots canvas").length,
      runs: document.querySelectorAll("#lab-plots .lab-run").length,
      holds: document.querySelectorAll("#lab-plots .lab-hold-run").length,
      legend: [...document.querySelectorAll("#lab-depth .u-legend .u-label")].map(e => e.textContent),
      title: document.getElementById("title").textContent,
    }));
    if (drawn.runs !== 2 || drawn.holds !== 2 || drawn.canvases < 5) throw new Error(`report plots: ${JSON.stringify(drawn)}`);
    if (drawn.legend.filter(l => l.startsWith("retraction")).length !== 2) throw new Error(`no before/after retraction curves: ${drawn.legend}`);
    if (!drawn.title.endsWith("fit")) throw new Error(`title ${drawn.title}`);
    await page.screenshot({path: shot("model-lab-fit-report.png"), fullPage: true});
    console.log(`  report: ${drawn.canvases} plots, depth legend ${drawn.legend.join(" | ")}`);
  } finally {
    await browser.close();
  }
});

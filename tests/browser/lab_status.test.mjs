// The lab archive's replicator as the technician sees it (issue 16): with [lab_archive] on
// and the lab's server out of reach, the Rig panel says so in words, with the reason, and
// the backlog it shows grows by every sample of a cut recorded meanwhile — the same figures
// as rigd's status (proto LabArchiveStatus). A screenshot goes to --artifacts.
import net from "node:net";
import { args, startRig, openPage, status, until, artifacts, test } from "./harness.mjs";

const a = args();
const shot = artifacts(a.artifacts);

const post = (page, path, body) => page.evaluate(async ([p, b]) => {
  const r = await fetch(p, {method: "POST", headers: {"Content-Type": "application/json"}, body: JSON.stringify(b)});
  return {status: r.status, body: await r.json()};
}, [path, body]);

// A loopback port nobody listens on: the lab's server, switched off.
async function closedPort() {
  const server = net.createServer();
  await new Promise(r => server.listen(0, "127.0.0.1", r));
  const port = server.address().port;
  await new Promise(r => server.close(r));
  return port;
}

await test("Browser.TheRigPanelShowsTheLabArchiveOutOfReachWithTheBacklogOfACutRecordedMeanwhile", async () => {
  const port = await closedPort();
  const rig = await startRig(a.bin, a.source, undefined, ["lab_archive.enabled=true",
    `lab_archive.conninfo="host=127.0.0.1 port=${port} user=postgres dbname=lab"`, `lab_archive.rig_id="rig-browser"`,
    `lab_archive.sslmode="disable"`, "lab_archive.retry_max_ms=500"]);
  const {browser, page} = await openPage(rig.url);
  const labText = () => page.evaluate(() => document.getElementById("r-lab").textContent);
  try {
    await until("the lab archive row shown as out of reach", async () =>
      (await page.isVisible("#lab-row")) && (await labText()).startsWith("NOT REACHABLE as rig-browser"), 15000);
    const reason = (await labText()).split(" — ")[1] || "";
    if (reason.length < 5) throw new Error(`no reason given: "${await labText()}"`);
    await post(page, "/api/home", {});
    await until("Ready after homing", async () => (await status(rig.url)).state === "Ready", 60000);
    await post(page, "/api/tare", {});
    await until("tared", async () => (await status(rig.url)).tared, 10000);
    const run = await post(page, "/api/run", {eye_id: "LAB-OUT", iop_mmHg: 15, velocity_mm_s: 4, depth_mm: 6, hold_s: 0});
    if (run.status !== 200) throw new Error(`run refused: ${JSON.stringify(run.body)}`);
    await until("the cut done", async () => (await status(rig.url)).state === "Done", 40000);
    let samples = 0;
    await until("the run archived", async () => {
      const runs = (await (await fetch(rig.url + "/api/runs")).json()).runs;
      const r = runs.find(x => x.run_id === run.body.run_id);
      samples = r && r.outcome === "completed" ? r.samples : 0;
      return samples > 1000;
    }, 10000);
    const expected = `backlog ${samples} samples in 1 runs`;
    try {
      await until(`the page shows "${expected}"`, async () => (await labText()).includes(expected), 10000);
    } catch (e) {
      throw new Error(`${e.message}: it shows "${await labText()}"; status ${JSON.stringify((await status(rig.url)).lab_archive)}`);
    }
    const lab = (await status(rig.url)).lab_archive;
    if (lab.connected !== false || lab.backlog_samples !== samples || lab.samples_shipped !== 0) {
      throw new Error(`status disagrees: ${JSON.stringify(lab)}`);
    }
    if (!(await page.evaluate(() => document.getElementById("r-lab").className === "warn"))) throw new Error("not shown as a warning");
    await page.screenshot({path: shot("lab-archive-out-of-reach.png"), fullPage: true});
    console.log(`  page: "${await labText()}"`);
  } finally {
    await browser.close();
    rig.stop();
  }
});

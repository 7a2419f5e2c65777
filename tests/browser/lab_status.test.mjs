// The lab archive as the technician sees it (issue 16): with [lab_archive] on and the lab's
// server out of reach, the Rig panel says so in words, with the reason, and the backlog it
// shows grows by every sample of a cut recorded meanwhile — the same figures as rigd's status
// (proto LabArchiveStatus). With a real server (a throwaway PostgreSQL 15), the run picker
// lists the lab archive's runs and shows one as the rig's own replay of it, sample for sample.
// Screenshots go to --artifacts.
import { spawn } from "node:child_process";
import net from "node:net";
import { join } from "node:path";
import { args, startRig, openPage, status, until, artifacts, test, homeAndTare } from "./harness.mjs";

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
    await homeAndTare(rig.url, path => post(page, path, {}));
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

// A throwaway PostgreSQL 15 (bin/pg-test-server): its conninfo once it takes connections.
async function startLabServer(bin) {
  const server = spawn(join(bin, "pg-test-server"), [], {stdio: ["pipe", "pipe", "inherit"]});
  const conninfo = await new Promise((resolve, reject) => {
    let seen = "";
    const timer = setTimeout(() => reject(new Error(`pg-test-server: no conninfo within 60 s: ${seen}`)), 60000);
    server.stdout.on("data", d => {
      seen += d.toString();
      const line = seen.split("\n").find(l => l.startsWith("conninfo "));
      if (line) { clearTimeout(timer); resolve(line.slice("conninfo ".length).trim()); }
    });
    server.on("exit", code => reject(new Error(`pg-test-server exited (${code}): ${seen}`)));
  });
  return {conninfo, stop: () => new Promise(r => { server.on("exit", r); server.stdin.end(); })};
}

await test("Browser.ThePickerShowsARunOfTheLabArchiveAsTheRigsOwnSampleForSample", async () => {
  const lab = await startLabServer(a.bin);
  const rig = await startRig(a.bin, a.source, undefined, ["lab_archive.enabled=true", `lab_archive.conninfo="${lab.conninfo}"`,
    `lab_archive.rig_id="rig-picker"`, `lab_archive.sslmode="disable"`, "lab_archive.interval_ms=100"]);
  const {browser, page} = await openPage(rig.url);
  try {
    await homeAndTare(rig.url, path => post(page, path, {}));
    const run = await post(page, "/api/run", {eye_id: "LAB-PICK", iop_mmHg: 15, velocity_mm_s: 4, depth_mm: 6, hold_s: 0,
                                              meta: {eye_lot: "LOT-9"}});
    if (run.status !== 200) throw new Error(`run refused: ${JSON.stringify(run.body)}`);
    await until("the cut done", async () => (await status(rig.url)).state === "Done", 40000);
    await until("the run replicated", async () => {
      const s = (await status(rig.url)).lab_archive;
      return s.connected && s.backlog_known && s.backlog_runs === 0 && s.backlog_samples === 0 && s.samples_shipped > 1000;
    }, 30000);
    const own = await (await fetch(`${rig.url}/api/runs/${run.body.run_id}/stream?limit=1000000`)).json();
    let value = "";
    await until("the picker lists the lab archive's run", async () => {
      await page.focus("#run-pick");  // the picker reloads its lists on focus
      value = await page.evaluate(() => [...document.querySelectorAll("#run-pick optgroup option")]
        .map(o => o.value).find(v => v.startsWith("lab:")) || "");
      return value !== "";
    }, 15000);
    const label = await page.evaluate(v => document.querySelector(`#run-pick option[value="${v}"]`).textContent, value);
    if (!label.includes("rig-picker run") || !label.includes("LAB-PICK") || !label.includes("lot LOT-9")) throw new Error(`option: ${label}`);
    await page.selectOption("#run-pick", value);
    // The rig's own copy of the run was on the plot before, with as many samples: wait for the
    // lab archive's to be fetched and drawn (its first cycle in the view's data).
    await until(`all ${own.cycle.length} samples plotted from the lab archive`, () => page.evaluate(([v, n, first]) => {
      const p = window.rig.plotted();
      return p.runId === v && p.points === n && p.firstCycle === first;
    }, [value, own.cycle.length, own.cycle[0]]), 15000);
    const p = await page.evaluate(() => window.rig.plotted());
    if (p.firstCycle !== own.cycle[0] || p.lastCycle !== own.cycle[own.cycle.length - 1] || p.holes !== 0 || p.duplicates !== 0) {
      throw new Error(`not the run's samples: ${JSON.stringify(p)}`);
    }
    if (Math.abs(p.peakN - Math.max(...own.force_N)) > 1e-9 || !(p.modelPoints > 0.5 * p.points)) throw new Error(`peak/model: ${JSON.stringify(p)}`);
    const caption = await page.textContent("#run-caption");
    if (!caption.includes("rig-picker run") || !caption.includes("(lab archive)") || !caption.includes("LAB-PICK")) throw new Error(`caption: ${caption}`);
    await page.screenshot({path: shot("lab-archive-run-picked.png"), fullPage: true});
    console.log(`  picked ${label}: ${p.points} samples, peak ${p.peakN.toFixed(4)} N; ${caption}`);
  } finally {
    await browser.close();
    rig.stop();
    await lab.stop();
  }
});

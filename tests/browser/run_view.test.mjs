// The Live tab shows the whole run, as a technician sees it: a page opened mid-cut, one
// opened after the cut and one whose stream dropped mid-cut all plot every sample of the run (approach to full depth, the
// puncture peak, the model) with no gap and no duplicate; an old run picked from the list is
// shown the same way; a fault injected through rig-sim's test panel shows its reason in the
// banner and the events, with the tripped chips red. Screenshots go to --artifacts.
import { args, startRig, openPage, status, until, artifacts, test, simPanelWrite, homeAndTare, isTimingFault } from "./harness.mjs";

const a = args();
const shot = artifacts(a.artifacts);
const LINK_DROP_REGISTER = 104;  // proto/include/rig/proto/daq_register_map.hpp sim_panel::kLinkDrop

const started = Date.now();
const stage = what => console.log(`  ${((Date.now() - started) / 1000).toFixed(1)} s: ${what}`);
const post = (page, path, body) => page.evaluate(async ([p, b]) => {
  const r = await fetch(p, {method: "POST", headers: {"Content-Type": "application/json"}, body: JSON.stringify(b)});
  return {status: r.status, body: await r.json()};
}, [path, body]);

// A timing fault of the simulated rig on a busy machine during a cut that is not the test's
// subject: the cut is reset and made again (named ACCIDENTAL, as the C++ harness does).
class AccidentalFault extends Error {}

// Waits on the rig's status; a timeout says where the rig was (a fault under load, ...). A fault
// ends the wait: a timing fault throws AccidentalFault, any other fault fails the test.
async function untilRig(url, what, predicate, timeoutMs) {
  let last = null;
  try {
    await until(what, async () => (last = await status(url)).state === "Fault" || predicate(last), timeoutMs);
  } catch (e) {
    throw new Error(`${e.message}; rig: ${last && `${last.state} ${last.phase}, fault "${last.fault}", x ${(last.position_mm - last.surface_mm).toFixed(2)} mm`}`);
  }
  if (last.state !== "Fault" || predicate(last)) return;
  if (isTimingFault(last.fault)) throw new AccidentalFault(`${what}: ${last.fault}`);
  throw new Error(`${what}: the rig faulted: ${last.fault}`);
}

// Runs one cut's steps; after an accidental timing fault it resets, homes and tares, and runs
// them again (at most 4 times).
async function cutWithRetries(url, send, steps) {
  for (let attempt = 1; ; ++attempt) {
    try {
      return await steps();
    } catch (e) {
      if (!(e instanceof AccidentalFault) || attempt >= 4) throw e;
      console.log(`ACCIDENTAL | a timing fault of the simulated rig, reset and cut again: ${e.message}`);
      await send("/api/reset");
      await homeAndTare(url, send);
    }
  }
}

async function archived(url, runId) {
  const s = await (await fetch(`${url}/api/runs/${runId}/stream`)).json();
  return {count: s.cycle.length, first: s.cycle[0], last: s.cycle[s.cycle.length - 1], peak: Math.max(...s.force_N), outcome: s.outcome};
}

// The page's plotted run against the archive's: every sample, once, in order.
async function checkWholeRun(page, url, runId, depth, what) {
  const truth = await archived(url, runId);
  try {
    await until(`${what}: the page holds all ${truth.count} samples`, () => page.evaluate(
      ([id, n]) => window.rig.plotted().runId === id && window.rig.plotted().points === n, [runId, truth.count]), 15000);
  } catch (e) {
    throw new Error(`${e.message}: ${JSON.stringify(await page.evaluate(() => window.rig.plotted()))} archive ${JSON.stringify(truth)}`);
  }
  const p = await page.evaluate(() => window.rig.plotted());
  const fail = why => { throw new Error(`${what}: ${why}: ${JSON.stringify(p)} archive ${JSON.stringify(truth)}`); };
  if (p.firstCycle !== truth.first || p.lastCycle !== truth.last) fail("not the run's first to last sample");
  if (p.duplicates !== 0 || p.holes !== 0) fail("samples missing or twice");
  if (!(p.xMin < 0) || !(p.xMax > depth - 0.5)) fail("x does not span the approach to full depth");
  if (!(p.xScale[0] <= p.xMin && p.xScale[1] >= p.xMax)) fail("the plot's x axis does not show all of x");
  if (Math.abs(p.peakN - truth.peak) > 1e-9 || !(p.peakN > 0.1)) fail("the puncture peak is not plotted");
  if (!(p.modelPoints > 0.5 * p.points) || !(p.modelMax > 0.1)) fail("no model curve");
  return p;
}

await test("Browser.TheLiveTabShowsTheWholeRunOpenedMidCutOrAfterItAnOldRunAndAFaultsReason", async () => {
  const rig = await startRig(a.bin, a.source);
  const {browser, page} = await openPage(rig.url);
  try {
    if (await page.isVisible("#lab-row")) throw new Error("a lab archive row shown with [lab_archive] off");
    const send = path => post(page, path, {});
    await homeAndTare(rig.url, send);
    const cut = {eye_id: "MID-CUT", iop_mmHg: 15, velocity_mm_s: 4, depth_mm: 12, hold_s: 0, post_mortem_h: 2};
    let midCut = null;
    const runId = await cutWithRetries(rig.url, send, async () => {
      if (midCut) await midCut.close();
      const first = await post(page, "/api/run", cut);
      if (first.status !== 200) throw new Error(`run refused: ${JSON.stringify(first.body)}`);
      stage("cut 1 started");
      await untilRig(rig.url, "mid-cut (6 mm in)", s => s.position_mm - s.surface_mm > 6, 30000);
      midCut = await browser.newPage({viewport: {width: 1400, height: 1500}});
      midCut.on("pageerror", e => console.error(`  page error: ${e.message}`));
      await midCut.goto(rig.url, {waitUntil: "domcontentloaded"});
      // The first page loses its stream mid-cut (as over a flaky network) and reconnects 1 s later.
      await page.evaluate(() => window.rig.socket.close());
      await until("the first page offline", async () => (await page.textContent("#conn")) === "offline", 5000);
      await until("the first page live again", async () => (await page.textContent("#conn")) === "live", 10000);
      stage("the first page reconnected mid-cut");
      await untilRig(rig.url, "the cut done", s => s.state === "Done", 30000);
      return first.body.run_id;
    });
    await until("the run archived as completed", async () => (await archived(rig.url, runId)).outcome === "completed", 5000);
    stage("cut 1 done");
    const opened = await checkWholeRun(midCut, rig.url, runId, cut.depth_mm, "opened mid-cut");
    await midCut.screenshot({path: shot("run-view-opened-mid-cut.png"), fullPage: true});
    await midCut.close();
    const after = await browser.newPage({viewport: {width: 1400, height: 1500}});
    await after.goto(rig.url, {waitUntil: "domcontentloaded"});
    await checkWholeRun(after, rig.url, runId, cut.depth_mm, "opened after the cut");
    await checkWholeRun(page, rig.url, runId, cut.depth_mm, "reconnected mid-cut");
    await after.screenshot({path: shot("run-view-opened-after-cut.png"), fullPage: true});
    console.log(`  run ${runId}: ${opened.points} samples, cycles ${opened.firstCycle}..${opened.lastCycle}, x ${opened.xMin.toFixed(2)}..` +
                `${opened.xMax.toFixed(2)} mm, peak ${opened.peakN.toFixed(4)} N at ${opened.peakX.toFixed(2)} mm, model on ${opened.modelPoints}`);

    const bad = await fetch(`${rig.url}/api/runs/${runId}/stream?from=abc`);
    const badText = await bad.text();
    if (bad.status !== 400 || !badText.includes("'from'")) throw new Error(`?from=abc answered ${bad.status}: ${badText}`);

    // An old run from the picker, while a newer one is the rig's last.
    stage("cut 1 checked on two pages");
    const second = await cutWithRetries(rig.url, send, async () => {
      const started = await post(page, "/api/run", {...cut, eye_id: "NEWER", depth_mm: 6});
      await untilRig(rig.url, "the second cut done", s => s.state === "Done" && s.run_id === 0, 30000);
      return started;
    });
    await until("the picker lists the first run", () => after.evaluate(
      id => [...document.querySelectorAll("#run-pick option")].some(o => o.value === String(id)), runId), 10000);
    await after.selectOption("#run-pick", String(runId));
    await checkWholeRun(after, rig.url, runId, cut.depth_mm, "picked old run");
    const events = await after.evaluate(() => window.rig.events.map(e => e.kind));
    if (!events.includes("run_started") || !events.includes("run_ended")) throw new Error(`old run's events: ${events}`);
    const caption = await after.textContent("#run-caption");
    if (!caption.includes("MID-CUT") || caption.includes("following")) throw new Error(`caption: ${caption}`);
    // The cursor on the residual plot: the sample's readings and its camera frame, if the run has frames.
    const frames = (await (await fetch(`${rig.url}/api/runs/${runId}/stream?from=0&limit=1`)).json()).frames.length;
    const over = await after.locator("#plot-residual .u-over").boundingBox();
    await after.mouse.move(over.x + over.width * 0.6, over.y + over.height / 2);
    await until("the cursor's sample", async () => /cycle \d+/.test(await after.textContent("#cursor")), 5000);
    if (frames > 0) await until("the camera frame at the cursor", () => after.evaluate(() => (window.rig.cursorFrames || 0) >= 1), 5000);
    await after.screenshot({path: shot("run-view-old-run.png"), fullPage: true});
    console.log(`  picked run ${runId} while run ${second.body.run_id} is the last: ${caption}; ${frames} camera frames, ` +
                `cursor: ${await after.textContent("#cursor")}`);

    // A fault mid-cut: the DAQ link drops.
    stage("old run checked");
    const third = await cutWithRetries(rig.url, send, async () => {
      const started = await post(page, "/api/run", {...cut, eye_id: "FAULTED"});
      await untilRig(rig.url, "3 mm into the tissue", s => s.position_mm - s.surface_mm > 3, 30000);
      return started;
    });
    stage("3 mm into cut 3");
    await simPanelWrite(rig.simPort, LINK_DROP_REGISTER, 5);  // 50 ms silent: longer than any tree's link-loss time
    try {
      await until("the banner names the fault and the action", () => page.evaluate(
        () => /DAQ link lost/.test(window.rig.banner) && /cable and power; then press Reset, then Home/.test(window.rig.banner)), 10000);
    } catch (e) {
      throw new Error(`${e.message}: banner "${await page.evaluate(() => window.rig.banner)}", status ${JSON.stringify(await status(rig.url))}`);
    }
    await until("the fault in the run's events", () => page.evaluate(
      () => window.rig.events.some(e => e.kind === "fault" && /DAQ link lost/.test(e.message))), 10000);
    const view = await page.evaluate(() => ({banner: window.rig.banner, tripped: window.rig.tripped, runId: window.rig.plotted().runId,
      chipColour: getComputedStyle(document.querySelector("#interlocks span.tripped")).backgroundColor}));
    if (view.runId !== third.body.run_id) throw new Error(`page shows run ${view.runId}, not the faulted ${third.body.run_id}`);
    if (!view.tripped.includes("DAQ link down") || !view.tripped.includes("motor off")) throw new Error(`chips: ${view.tripped}`);
    if (view.chipColour !== "rgb(198, 40, 40)") throw new Error(`a tripped chip is ${view.chipColour}, not red`);
    await page.screenshot({path: shot("run-view-fault.png"), fullPage: true});
    console.log(`  banner: ${view.banner}; tripped: ${view.tripped.join(", ")}`);
  } finally {
    await browser.close();
    rig.stop();
  }
});

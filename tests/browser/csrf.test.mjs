// Cross-site requests from a foreign page in Chromium cannot move the rig: a page served
// from another origin (another port on the same loopback) tries every request a browser
// lets a page send without asking — a form POST, a text/plain fetch, a JSON fetch (which
// needs a CORS preflight) and a WebSocket — against rigd's default, token-less loopback API.
// The rig must stay where it was, with no run created, and the attempts counted as refused.
// A Stop from the same page still gets through (stopping is never refused).
import { createServer } from "node:http";
import { args, startRig, openPage, status, until, artifacts, test } from "./harness.mjs";

const a = args();
const shot = artifacts(a.artifacts);

function attackerPage(rigUrl) {
  const ws = rigUrl.replace("http://", "ws://") + "/ws";
  return `<!doctype html><title>not rigd</title><body>
<form id="f" method="POST" action="${rigUrl}/api/home" enctype="text/plain" target="sink">
  <input name='{"x":"' value='"}'></form>
<iframe name="sink"></iframe>
<script>
window.results = {};
async function attack() {
  document.getElementById("f").submit();
  const tries = [
    ["plain", fetch("${rigUrl}/api/run", {method: "POST", mode: "no-cors", headers: {"Content-Type": "text/plain"},
      body: JSON.stringify({eye_id: "CSRF", iop_mmHg: 15, velocity_mm_s: 2, depth_mm: 14})})],
    ["form", fetch("${rigUrl}/api/home", {method: "POST", mode: "no-cors",
      headers: {"Content-Type": "application/x-www-form-urlencoded"}, body: "a=b"})],
    ["json", fetch("${rigUrl}/api/home", {method: "POST", headers: {"Content-Type": "application/json"}, body: "{}"})],
  ];
  for (const [name, p] of tries) {
    try { const r = await p; window.results[name] = "sent:" + r.type; } catch (e) { window.results[name] = "blocked:" + e.message; }
  }
  window.results.ws = await new Promise(resolve => {
    const s = new WebSocket("${ws}");
    s.onopen = () => resolve("open");
    s.onerror = () => resolve("refused");
  });
  window.done = true;
}
attack();
</script></body>`;
}

async function metric(url, name) {
  const text = await (await fetch(url + "/metrics")).text();
  const line = text.split("\n").find(l => l.startsWith(name + " "));
  return line ? Number(line.split(" ")[1]) : NaN;
}

await test("Browser.AForeignPageCannotMoveTheRigButCanStopIt", async () => {
  const rig = await startRig(a.bin, a.source);
  const server = createServer((req, res) => { res.setHeader("Content-Type", "text/html"); res.end(attackerPage(rig.url)); });
  await new Promise(r => server.listen(0, "127.0.0.1", r));
  const foreign = `http://127.0.0.1:${server.address().port}/`;
  const {browser, page} = await openPage(foreign);
  try {
    const before = await status(rig.url);
    await until("the foreign page's attempts", () => page.evaluate(() => window.done === true), 15000);
    await new Promise(r => setTimeout(r, 1000));  // give a command that got through time to show
    const after = await status(rig.url);
    const results = await page.evaluate(() => window.results);
    const runs = (await (await fetch(rig.url + "/api/runs")).json()).runs;
    const refused = await metric(rig.url, "rigd_http_cross_site_refused_total");
    await page.screenshot({path: shot("csrf-foreign-page.png"), fullPage: true});
    console.log(`  state ${before.state} -> ${after.state}, runs ${runs.length}, refused ${refused}, page saw ${JSON.stringify(results)}`);
    if (after.state !== before.state) throw new Error(`the rig moved: ${before.state} -> ${after.state}`);
    if (after.motor_enabled) throw new Error("motor enabled by a foreign page");
    if (runs.length !== 0) throw new Error(`a foreign page created runs: ${JSON.stringify(runs)}`);
    if (results.ws === "open") throw new Error("a foreign page opened the live stream");
    if (!(refused >= 3)) throw new Error(`expected >= 3 refused cross-site requests, counted ${refused}`);
    // Stop is never refused, whatever asks for it.
    const requests = await metric(rig.url, "rigd_http_requests_total");
    await page.evaluate(async url => (await fetch(url + "/api/stop", {method: "POST", mode: "no-cors"})).type, rig.url);
    await until("the stop reached rigd", async () => (await metric(rig.url, "rigd_http_requests_total")) > requests + 1, 3000);
    const refusedAfterStop = await metric(rig.url, "rigd_http_cross_site_refused_total");
    if (refusedAfterStop !== refused) throw new Error(`the foreign page's Stop was refused (${refused} -> ${refusedAfterStop})`);
  } finally {
    await browser.close();
    server.close();
    rig.stop();
  }
});

// Shared by the browser tests: rig-sim + rigd as processes, Chromium via playwright-core.
import { spawn, execFileSync } from "node:child_process";
import { mkdtempSync, mkdirSync, readFileSync } from "node:fs";
import { availableParallelism, tmpdir } from "node:os";
import { join } from "node:path";
import net from "node:net";
import { chromium } from "playwright-core";

export function args() {
  const out = {};
  for (let i = 2; i < process.argv.length; i += 2) out[process.argv[i].replace(/^--/, "")] = process.argv[i + 1];
  return out;
}

function waitForLine(child, text, timeoutMs) {
  return new Promise((resolve, reject) => {
    let seen = "";
    const timer = setTimeout(() => reject(new Error(`no "${text}" within ${timeoutMs} ms:\n${seen}`)), timeoutMs);
    const onData = data => {
      seen += data.toString();
      const line = seen.split("\n").find(l => l.includes(text));
      if (line) { clearTimeout(timer); resolve(line); }
    };
    child.stdout.on("data", onData);
    child.stderr.on("data", onData);
    child.on("exit", code => reject(new Error(`process exited (${code}) before "${text}":\n${seen}`)));
  });
}

// A sanitized tree's rigd and rig-sim wake up to ~10 ms late on a loaded machine: they get the
// allowances the C++ tests' rigs get (tests/support/rig_processes.hpp); a release tree keeps
// the shipped 10 ms link-loss time and 15 ms DAQ watchdog.
function sanitizedAllowances() {
  return args().sanitized === "1" ? ["--set", "safety.link_lost_after_ms=25", "--set", "daq.watchdog_ms=30"] : [];
}

// rig-sim and rigd's loop on one CPU, as rig demo and the C++ tests run them
// (daemon/cli/shared_cpu.hpp: a CPU the machine holds still then stops both).
let rigsStarted = 0;
function sharedCpu() {
  const cpus = availableParallelism();
  return cpus < 2 ? [] : [(process.pid + rigsStarted++) % cpus];
}

// extra: further `--set key=value` overrides for rigd.
export async function startRig(bin, source, archive, extra = []) {
  const dir = mkdtempSync(join(tmpdir(), "rig-browser-"));
  archive = archive || join(dir, "archive.sqlite");
  const cpu = sharedCpu();
  const sim = spawn(join(bin, "rig-sim"), ["--port", "0", ...cpu.flatMap(c => ["--cpu", `${c}`])]);
  const simLine = await waitForLine(sim, "listening on", 10000);
  const port = simLine.trim().split(":").pop();
  const rigd = spawn(join(bin, "rigd"), ["--config", join(source, "config/rigd.sim.toml"), "--set", `daq.port=${port}`,
    "--set", "api.port=0", "--set", `archive.path="${archive}"`, "--set", `api.web_root="${join(bin, "../web-root")}"`, ...cpu.flatMap(c => ["--set", `loop.cpu=${c}`]), ...sanitizedAllowances(), ...extra.flatMap(kv => ["--set", kv])]);
  const ready = await waitForLine(rigd, "ready, API on", 20000);
  const url = ready.slice(ready.indexOf("http://")).trim();
  return {url, dir, archive, simPort: +port, stop: () => { rigd.kill("SIGTERM"); sim.kill("SIGTERM"); }};
}

export async function openPage(url) {
  const browser = await chromium.launch({
    executablePath: "/usr/bin/chromium",
    args: ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
           "--disable-background-networking", "--disable-component-update", "--disable-sync"],
  });
  const page = await browser.newPage({viewport: {width: 1400, height: 1500}});
  page.on("dialog", dialog => dialog.accept());  // the page asks before any motion
  page.on("pageerror", e => console.error(`  page error: ${e.message}`));  // a script error fails loudly in the log
  await page.goto(url);
  return {browser, page};
}

export async function status(url) { return (await fetch(url + "/api/status")).json(); }

export async function until(what, predicate, timeoutMs) {
  const end = Date.now() + timeoutMs;
  while (Date.now() < end) {
    if (await predicate()) return;
    await new Promise(r => setTimeout(r, 100));
  }
  throw new Error(`timed out waiting for: ${what}`);
}

// The faults of the loop's timing that the simulated rig can have on a busy machine (the same
// texts as daemon/cli/timing_fault.hpp): named ACCIDENTAL, reset and tried again, as the C++
// harness does, so a slow VM's stall before a test's own subject is not that test's failure.
export function isTimingFault(fault) {
  fault = fault || "";
  return fault.startsWith("DAQ link lost") || fault.startsWith("DAQ watchdog tripped") ||
    fault.startsWith("loop overrun storm") || (fault.startsWith("DAQ write failed") && fault.includes("writes in a row lost"));
}

// Homes and tares the rig through `send(path)` (a POST from the page), at most four tries when a
// timing fault of the simulated rig interrupts; any other fault fails the test.
export async function homeAndTare(url, send) {
  for (let attempt = 1; ; ++attempt) {
    let faulted = "";
    const step = async (path, what, done, timeoutMs) => {
      await send(path);
      await until(what, async () => {
        const s = await status(url);
        if (s.state === "Fault") { faulted = s.fault; return true; }
        return done(s);
      }, timeoutMs);
      return !faulted;
    };
    if (await step("/api/home", "Ready after homing", s => s.state === "Ready", 60000) &&
        await step("/api/tare", "tared", s => s.tared, 10000)) return;
    if (!isTimingFault(faulted) || attempt >= 4) throw new Error(`the rig faulted while preparing: ${faulted}`);
    console.log(`ACCIDENTAL | a timing fault while preparing, reset and retried: ${faulted}`);
    await send("/api/reset");
  }
}

// Writes one holding register of rig-sim's test panel (Modbus TCP, function 6, unit 1):
// the fault injection of tests/integration/fault_matrix_test.cpp (proto sim_panel registers).
export function simPanelWrite(port, register, value) {
  return new Promise((resolve, reject) => {
    const frame = Buffer.from([0, 1, 0, 0, 0, 6, 1, 6, register >> 8, register & 0xff, value >> 8, value & 0xff]);
    const socket = net.connect(port, "127.0.0.1", () => socket.write(frame));
    socket.setTimeout(2000, () => { socket.destroy(); reject(new Error("rig-sim panel: no answer")); });
    socket.on("data", reply => { socket.end(); reply[7] === 6 ? resolve() : reject(new Error(`rig-sim panel refused: ${reply.toString("hex")}`)); });
    socket.on("error", reject);
  });
}

export function artifacts(dir) { mkdirSync(dir, {recursive: true}); return name => join(dir, name); }
export { execFileSync, readFileSync };

// A test: prints "name: ok" or the error; the process exit code carries the verdict.
export async function test(name, body) {
  const started = Date.now();
  try {
    await body();
    console.log(`${name}: ok (${((Date.now() - started) / 1000).toFixed(1)} s)`);
  } catch (e) {
    console.error(`${name}: FAILED: ${e.stack || e}`);
    process.exitCode = 1;
  }
}

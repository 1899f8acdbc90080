// A team's live view on the project's page: Debian's headless Chromium (playwright-core) loads http://127.0.0.1:PORT/
// while a 5 s coop-slam-team run (4 robots, 12 landmarks, seed 3) plays at 2x, either (--mode replay) its log replayed
// by robot 0's team node or (--mode sim) the run itself, `sim_host run coop-slam-team --view PORT` (--view-wait: each
// starts once the page subscribed); the page's own state (window.estView) must hold every robot's truth and estimate,
// close together, and the mapped landmarks; a screenshot of the end is kept.
import { readFileSync } from "node:fs";
import { chromium } from "playwright-core";
import { args, fail, freePort, startNode } from "./view_run.mjs";

const a = args();
const sim = a.mode === "sim";
const browser = await chromium.launch({
  executablePath: "/usr/bin/chromium",
  args: ["--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run", "--disable-background-networking",
         "--disable-component-update", "--disable-sync"],
});
const port = await freePort();
const node = sim
  ? await startNode(a.sim, ["run", "coop-slam-team", "--duration", "5", "--seed", "3", "--out", a.run, "--no-plots",
                            "--quiet", "--view", String(port), "--view-wait", "--view-speed", "2"])
  : await startNode(a.node, [...JSON.parse(readFileSync(a.run + "/run.lcmlog.json")).estimator_node_replays[0].trim()
                               .split(/\s+/), "--view", String(port), "--view-wait", "--replay-speed", "2"]);
const page = await browser.newPage({ viewport: { width: 1000, height: 780 } });
const pageErrors = [];
page.on("pageerror", (e) => pageErrors.push(e.message));
await page.goto(`http://127.0.0.1:${port}/`);

let s = null;
const start = Date.now();
while (Date.now() - start < 30000) {
  s = await page.evaluate(() => {
    const v = window.estView;
    const robots = Object.entries(v.robots).map(([k, r]) => ({ robot: Number(k), color: r.color, truths: r.truthCount,
      estimates: r.estimateCount, errorM: r.errorM, ellipse: r.ellipse.length }));
    return { closed: v.closed, messages: v.messages, channels: v.channels.length, robots, landmarks: v.landmarks.length,
             status: v.status };
  });
  if (s.closed) break;
  await page.waitForTimeout(200);
}
await page.waitForTimeout(300);  // the last frame drawn
const shot = `${a.work}/view-team-page${sim ? "-run" : ""}.png`;
await page.screenshot({ path: shot });
await browser.close();
const { code, output } = await node.exited;
if (code !== 0) fail(`${sim ? "sim_host" : "estimator_node"} exited with ${code}:\n${output}`);
const metrics = JSON.parse(readFileSync(a.run + "/metrics.json"));  // the run's (written at its end in --mode sim)

if (pageErrors.length) fail("page errors: " + pageErrors.join("; "));
if (!s.closed) fail("the run did not end within 30 s");
if (s.channels !== 3 * metrics.robots + 2) fail(`channels ${s.channels}`);
if (s.robots.length !== metrics.robots) fail(`${s.robots.length} robots drawn of ${metrics.robots}`);
if (new Set(s.robots.map((r) => r.color)).size !== s.robots.length) fail("robots share a colour");
for (const r of s.robots) {
  if (r.estimates < 40 || r.truths < 40 || r.ellipse !== 36) fail(`robot ${r.robot}: ${JSON.stringify(r)}`);
  // The run's RMSE is 0.05-0.08 m per robot: 0.3 m at the end fails a robot drawn with another's estimate.
  if (!(r.errorM !== null && r.errorM < 0.3)) fail(`robot ${r.robot}: estimate ${r.errorM} m from its truth at the end`);
}
if (s.landmarks !== metrics.shared.landmarks_mapped) fail(`${s.landmarks} landmarks drawn of ${metrics.shared.landmarks_mapped}`);
if (!s.status || !Array.isArray(s.status.bits)) fail("no status drawn");
console.log(`team page (${sim ? "sim_host run" : "replay"}): ${s.messages} messages, ${s.channels} channels; ` +
            s.robots.map((r) => `robot ${r.robot} (${r.color}) ${r.estimates} estimates, ${r.errorM?.toFixed(3)} m at the end`).join("; ") +
            `; ${s.landmarks} landmarks; screenshot ${shot}`);
if (process.exitCode) console.log("0 passed, 1 failed"); else console.log("1 passed, 0 failed");

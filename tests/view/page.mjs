// The live view's page as a person sees it: Debian's headless Chromium (playwright-core) loads
// http://127.0.0.1:PORT/ while estimator_node replays a 20 s log at 2x from a global start (--view-wait: the replay
// starts once the page subscribed), and the page's own state (window.estView) must show the particle cloud
// converging on the robot; a screenshot of the end is kept.
import { chromium } from "playwright-core";
import { args, fail, freePort, replayOptions, startNode } from "./view_run.mjs";

const a = args();
const { log, rest } = replayOptions(a.options);
// A global start instead of the recorded pose: the cloud starts uniform over the office and must shrink.
const options = [];
for (let i = 0; i < rest.length; ++i) {
  if (rest[i] === "--initial-pose" || rest[i] === "--initial-sigma") ++i;
  else options.push(rest[i]);
}
const browser = await chromium.launch({
  executablePath: "/usr/bin/chromium",
  args: ["--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run", "--disable-background-networking",
         "--disable-component-update", "--disable-sync"],
});
const port = await freePort();
const node = await startNode(a.node, ["--replay", log, "--view", String(port), "--view-wait", "--replay-speed", "2",
                                      "--global", ...options]);
const page = await browser.newPage({ viewport: { width: 1000, height: 780 } });
const pageErrors = [];
page.on("pageerror", (e) => pageErrors.push(e.message));
await page.goto(`http://127.0.0.1:${port}/`);

// Watch the page's state until the run ends (the server closes the socket), at most 40 s.
const seen = [];
const start = Date.now();
const early = `${a.work}/view-page-start.png`;
let earlyTaken = false;
let s = null;
while (Date.now() - start < 40000) {
  s = await page.evaluate(() => {
    const v = window.estView;
    return { closed: v.closed, messages: v.messages, spread: v.particleSpread, spreadMax: v.particleSpreadMax,
             particles: v.particles.length, total: v.particleTotal, errorM: v.errorM, map: v.map, status: v.status,
             channels: v.channels.length };
  });
  if (s.spread !== null) seen.push(s.spread);
  if (s.spread !== null && !earlyTaken) {  // the first cloud the page drew: the global start
    await page.screenshot({ path: early });
    earlyTaken = true;
  }
  if (s.closed) break;
  await page.waitForTimeout(200);
}
const shot = `${a.work}/view-page.png`;
await page.screenshot({ path: shot });
await browser.close();
const { code, output } = await node.exited;
if (code !== 0) fail(`estimator_node exited with ${code}:\n${output}`);

if (pageErrors.length) fail("page errors: " + pageErrors.join("; "));
if (!s.closed) fail("the run did not end within 40 s");
if (s.channels !== 6 || !s.map || s.map.width * s.map.height < 1000) fail(`channels ${s.channels}, map ${JSON.stringify(s.map)}`);
// Uniform over the 20 m x 15 m office the cloud's RMS distance from its mean is ~5 m; converged, a few cm.
if (!(s.spreadMax > 2.0)) fail(`the cloud never spread: largest ${s.spreadMax} m`);
if (!(s.spread < 0.5)) fail(`the cloud did not converge: ${s.spread} m at the end`);
if (!(s.errorM !== null && s.errorM < 0.3)) fail(`estimate ${s.errorM} m from the truth at the end`);
if (!s.status || !Array.isArray(s.status.bits)) fail("no status drawn");
console.log(`page: ${s.messages} messages, ${seen.length} samples of the page's state; particle spread ` +
            `${s.spreadMax?.toFixed(2)} m at most, ${s.spread?.toFixed(3)} m at the end (${s.particles} of ${s.total} ` +
            `particles drawn); estimate ${s.errorM?.toFixed(3)} m from the truth; status ${s.status?.word_hex}`);
console.log(`screenshots: ${early} (the first cloud drawn), ${shot} (the end)`);
if (process.exitCode) console.log("0 passed, 1 failed"); else console.log("1 passed, 0 failed");

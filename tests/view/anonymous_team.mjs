// The anonymous team's live view as Foxglove Studio sees it: @foxglove/ws-protocol's FoxgloveClient subscribes to
// every channel of `sim_host run diffdrive-landmarks --view PORT --view-wait --view-speed 10` (three robots that see
// each other by tag, not by identity, from uniform clouds; 20 s, seed 3), then checks the advertised channels and
// their schemas, that each robot's estimates track its truth with the run's own error (the metrics' RMSE: the filter's
// estimates, not the truth echoed or another robot's), and that the known landmarks appear.
import { readFileSync } from "node:fs";
import { args, fail, freePort, startNode, teamChannels, watch } from "./view_run.mjs";

const a = args();
const port = await freePort();
const node = await startNode(a.sim, ["run", "diffdrive-landmarks", "--duration", "20", "--seed", "3", "--out", a.run,
                                     "--no-plots", "--quiet", "--view", String(port), "--view-wait", "--view-speed",
                                     "10"]);
const { channels, got, code, output } = await watch(port, node);
if (code !== 0) fail(`sim_host exited with ${code}:\n${output}`);

const metrics = JSON.parse(readFileSync(a.run + "/metrics.json"));
const robots = metrics.robots.length, steps = 200;  // 20 s at the team's 10 Hz
const expected = teamChannels(robots);
for (const t of Object.keys(expected)) got[t] ??= [];
for (const [topic, schemaName] of Object.entries(expected)) {
  const ch = [...channels.values()].find((c) => c.topic === topic);
  if (!ch) { fail("not advertised: " + topic); continue; }
  if (ch.schemaName !== schemaName) fail(`${topic}: schema ${ch.schemaName}, expected ${schemaName}`);
  if (!got[topic].length) fail("no message on " + topic);
}
if (robots !== 3 || channels.size !== Object.keys(expected).length)
  fail(`${robots} robots, ${channels.size} channels advertised, expected ${Object.keys(expected).length}`);

// Each estimate against its robot's truth message nearest in time (within 20 ms): from the time the filter said the
// robot localized, the RMSE the run's metrics give (its estimates, not the truth: 1-5 cm at seed 3), and within the
// run's "localized" bound (0.5 m) from the time the metrics give to the end.
const seconds = (m) => m.timestamp.sec + m.timestamp.nsec * 1e-9;
const report = [];
for (let r = 0; r < robots; ++r) {
  const m = metrics.robots[r];
  if (!m.localized) { fail(`robot ${r} not localized in the run: ${JSON.stringify(m)}`); continue; }
  const truths = got[`/robot${r}/truth`].map((x) => ({ t: seconds(x), ...x.pose.position }));
  const estimates = got[`/robot${r}/estimate`].map((x) => ({ t: seconds(x), ...x.pose.position }));
  let k = 0, worstAfter = 0, after = 0, se = 0, n = 0;
  for (const e of estimates) {
    while (k + 1 < truths.length && Math.abs(truths[k + 1].t - e.t) <= Math.abs(truths[k].t - e.t)) ++k;
    if (!truths.length || Math.abs(truths[k].t - e.t) > 0.02) continue;
    const err = Math.hypot(truths[k].x - e.x, truths[k].y - e.y);
    if (e.t >= m.filter_localized_at_s - 1e-6) { se += err * err; ++n; }
    if (e.t >= m.time_to_localize_s - 1e-6) { ++after; worstAfter = Math.max(worstAfter, err); }
  }
  if (estimates.length < 0.9 * steps) fail(`robot ${r}: ${estimates.length} estimates of ${steps} steps`);
  const rmse = Math.sqrt(se / Math.max(1, n));
  if (!(Math.abs(rmse - m.position_rmse_m) <= 0.1 * m.position_rmse_m + 0.002 && rmse > 0.001))
    fail(`robot ${r}: RMSE ${rmse} m over the view's estimates, ${m.position_rmse_m} m in the run's metrics`);
  const expectedAfter = (20 - m.time_to_localize_s) * 10;
  if (after < 0.9 * expectedAfter) fail(`robot ${r}: ${after} estimates after ${m.time_to_localize_s} s of ~${expectedAfter}`);
  if (!(worstAfter < 0.5)) fail(`robot ${r}: ${worstAfter.toFixed(3)} m from its truth after it was localized`);
  report.push(`robot ${r}: ${estimates.length} estimates, RMSE ${rmse.toFixed(4)} m (run ${m.position_rmse_m.toFixed(4)}), ` +
              `localized at ${m.time_to_localize_s} s, worst ${worstAfter.toFixed(3)} m after`);
}
const lastSet = got["/landmarks"].at(-1)?.entities ?? [];
if (lastSet.length !== 14 || !lastSet.every((e) => /^landmark_\d+$/.test(e.id))) fail(`landmarks: ${lastSet.length}`);
if (got["/status"].length < 0.9 * steps) fail(`${got["/status"].length} status messages of ${steps} steps`);
console.log(`foxglove client (diffdrive-landmarks run at 10x): ${channels.size} channels; ${report.join("; ")}; ` +
            `${lastSet.length} landmarks; ${got["/status"].length} status`);
if (process.exitCode) console.log("0 passed, 1 failed"); else console.log("1 passed, 0 failed");

// A team's live view as Foxglove Studio sees it: @foxglove/ws-protocol's FoxgloveClient subscribes to every channel
// of a 5 s coop-slam-team run (4 robots, 12 landmarks, seed 3) at 4x, either (--mode replay) its log replayed by
// `estimator_node --filter coop-ekf --replay LOG --view PORT --view-wait --replay-speed 4` as robot 0's node, or
// (--mode sim) the run itself, `sim_host run coop-slam-team --view PORT --view-wait --view-speed 4`; then checks the
// advertised channels and their schemas, that each robot's estimate messages track its own truth messages, and that
// every mapped landmark appears.
import { readFileSync } from "node:fs";
import { args, fail, freePort, startNode, teamChannels, watch } from "./view_run.mjs";

const a = args();
const sim = a.mode === "sim";
const port = await freePort();
const node = sim
  ? await startNode(a.sim, ["run", "coop-slam-team", "--duration", "5", "--seed", "3", "--out", a.run, "--no-plots",
                            "--quiet", "--view", String(port), "--view-wait", "--view-speed", "4"])
  : await startNode(a.node, [...JSON.parse(readFileSync(a.run + "/run.lcmlog.json")).estimator_node_replays[0].trim()
                               .split(/\s+/), "--view", String(port), "--view-wait", "--replay-speed", "4"]);

const { channels, got, serverName, code, output } = await watch(port, node);
if (code !== 0) fail(`${sim ? "sim_host" : "estimator_node"} exited with ${code}:\n${output}`);

// The run's metrics give the team and its map; its team_estimates.csv (a header and one line per step) the steps.
const metrics = JSON.parse(readFileSync(a.run + "/metrics.json"));
const robots = metrics.robots, landmarks = metrics.shared.landmarks_mapped;
const steps = readFileSync(a.run + "/team_estimates.csv", "utf8").trim().split("\n").length - 1;
const expected = teamChannels(robots);
for (const t of Object.keys(expected)) got[t] ??= [];

// The channels and their schemas.
if (serverName !== (sim ? "sim_host" : "estimator_node")) fail("serverInfo name " + serverName);
for (const [topic, schemaName] of Object.entries(expected)) {
  const ch = [...channels.values()].find((c) => c.topic === topic);
  if (!ch) { fail("not advertised: " + topic); continue; }
  if (ch.schemaName !== schemaName) fail(`${topic}: schema ${ch.schemaName}, expected ${schemaName}`);
  if (ch.encoding !== "json" || ch.schemaEncoding !== "jsonschema") fail(`${topic}: ${ch.encoding}/${ch.schemaEncoding}`);
  const schema = JSON.parse(ch.schema);
  if (schema.title !== schemaName || schema.type !== "object") fail(`${topic}: schema title ${schema.title}`);
  const first = got[topic]?.[0];
  if (!first) { fail("no message on " + topic); continue; }
  for (const key of Object.keys(first)) if (!(key in schema.properties)) fail(`${topic}: field ${key} not in its schema`);
}
if (channels.size !== Object.keys(expected).length) fail(`advertised ${channels.size} channels, expected ${Object.keys(expected).length}`);

// Each robot's estimates track its own truth: each estimate against that robot's truth message nearest in time
// (within 20 ms). The run's own metrics give 0.05-0.08 m position RMSE per robot (README); the bounds fail a robot
// whose estimate is another robot's or lost, not one a little off.
const seconds = (m) => m.timestamp.sec + m.timestamp.nsec * 1e-9;
const report = [];
for (let r = 0; r < robots; ++r) {
  const truths = got[`/robot${r}/truth`].map((m) => ({ t: seconds(m), ...m.pose.position }));
  const estimates = got[`/robot${r}/estimate`].map((m) => ({ t: seconds(m), ...m.pose.position }));
  let k = 0;
  const errors = [];
  for (const e of estimates) {
    while (k + 1 < truths.length && Math.abs(truths[k + 1].t - e.t) <= Math.abs(truths[k].t - e.t)) ++k;
    if (truths.length && Math.abs(truths[k].t - e.t) <= 0.02) errors.push(Math.hypot(truths[k].x - e.x, truths[k].y - e.y));
  }
  const rmse = Math.sqrt(errors.reduce((s, m) => s + m * m, 0) / Math.max(1, errors.length));
  const worst = Math.max(...errors);
  if (estimates.length < 0.9 * steps) fail(`robot ${r}: ${estimates.length} estimates of ${steps} steps`);
  if (errors.length < 0.9 * estimates.length) fail(`robot ${r}: ${errors.length} of ${estimates.length} estimates have a truth within 20 ms`);
  if (!(rmse < 0.2 && worst < 0.5)) fail(`robot ${r}: RMSE ${rmse.toFixed(3)} m, worst ${worst.toFixed(3)} m (bounds 0.2, 0.5 m)`);
  // The ellipse is the robot's: centred on its estimate.
  const ell = got[`/robot${r}/estimate/ellipse`].at(-1)?.entities[0].lines[0].points;
  const last = estimates.at(-1);
  if (!ell || ell.length !== 36 || !last) { fail(`robot ${r}: ellipse`); continue; }
  const cx = ell.reduce((s, p) => s + p.x, 0) / ell.length, cy = ell.reduce((s, p) => s + p.y, 0) / ell.length;
  if (Math.hypot(cx - last.x, cy - last.y) > 0.01) fail(`robot ${r}: ellipse centred ${cx},${cy}, estimate ${last.x},${last.y}`);
  report.push(`robot ${r}: ${estimates.length} estimates, ${truths.length} truths, RMSE ${rmse.toFixed(3)} m, worst ${worst.toFixed(3)} m`);
}

// The landmarks: the last set has every mapped landmark, each an ellipse; the status has the own robot's covariance.
const sets = got["/landmarks"];
const lastSet = sets.at(-1)?.entities ?? [];
if (lastSet.length !== landmarks) fail(`last landmark set has ${lastSet.length} landmarks, expected ${landmarks}`);
if (robots !== 4 || steps < 40) fail(`the run: ${robots} robots, ${steps} steps`);
if (!lastSet.every((e) => /^landmark_\d+$/.test(e.id) && e.lines[0].points.length === 36)) fail("landmark entities");
const status = got["/status"].at(-1);
if (!status || !Array.isArray(status.bits) || status.covariance?.length !== 9) fail("status " + JSON.stringify(status));
if (got["/status"].length < 0.9 * steps) fail(`${got["/status"].length} status messages of ${steps} steps`);
const summary = output.split("\n").find((l) => l.includes("view: ")) || "(no view line)";

console.log(`foxglove client (team ${sim ? "run" : "replay"} at 4x): ${channels.size} channels; ${report.join("; ")}; ` +
            `${sets.length} landmark sets (${lastSet.length} landmarks); ${got["/status"].length} status; ${summary}`);
if (process.exitCode) console.log("0 passed, 1 failed"); else console.log("1 passed, 0 failed");

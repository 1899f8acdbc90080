// What both view tests share: their arguments, a free port, and estimator_node started with --view on it.
import { spawn } from "node:child_process";
import { createServer } from "node:net";

export function args() {
  const a = process.argv.slice(2), out = {};
  for (let i = 0; i + 1 < a.length; i += 2) out[a[i].replace(/^--/, "")] = a[i + 1];
  return out;
}

export function freePort() {
  return new Promise((resolve, reject) => {
    const s = createServer();
    s.once("error", reject);
    s.listen(0, "127.0.0.1", () => {
      const { port } = s.address();
      s.close(() => resolve(port));
    });
  });
}

// The options of `sim_host record`'s sidecar without "--replay LOG" (given separately) as an argument list.
export function replayOptions(options) {
  const words = options.trim().split(/\s+/);
  if (words[0] !== "--replay") throw new Error("sidecar options do not start with --replay: " + options);
  return { log: words[1], rest: words.slice(2) };
}

// Starts estimator_node (or sim_host) and resolves once it serves the view; `exited` resolves with its exit code and
// output.
export async function startNode(exe, argv, seconds = 20) {
  const proc = spawn(exe, argv, { stdio: ["ignore", "pipe", "pipe"] });
  let output = "";
  proc.stdout.on("data", (d) => (output += d));
  proc.stderr.on("data", (d) => (output += d));
  const exited = new Promise((resolve) => proc.on("exit", (code) => resolve({ code, output })));
  const deadline = Date.now() + seconds * 1000;
  while (!output.includes(": live view on")) {
    if (proc.exitCode !== null) throw new Error("estimator_node exited early:\n" + output);
    if (Date.now() > deadline) {
      proc.kill("SIGTERM");
      throw new Error(exe + " did not start its view in " + seconds + " s:\n" + output);
    }
    await new Promise((r) => setTimeout(r, 50));
  }
  return { proc, exited, output: () => output };
}

export function fail(message) {
  console.error("FAIL: " + message);
  process.exitCode = 1;
}

// A Foxglove client (@foxglove/ws-protocol) on ws://127.0.0.1:PORT that subscribes to every channel advertised and
// keeps each topic's decoded JSON messages (with `stamped`, as { t: the message's log time in s, msg }) until the
// server closes the connection at the end of the run, then waits for `node` (startNode's) to exit; fails after
// `seconds`. `onAdvertise(list)` runs after each advertisement's subscriptions.
export async function watch(port, node, { seconds = 60, stamped = false, onAdvertise = () => {} } = {}) {
  const { default: foxglove } = await import("@foxglove/ws-protocol");
  const { default: WebSocket } = await import("ws");
  const { FoxgloveClient } = foxglove;
  const channels = new Map();  // channel id -> channel
  const topicOf = new Map();   // subscription id -> topic
  const got = {};              // topic -> its messages
  let serverName = null;
  const client = new FoxgloveClient({
    ws: new WebSocket(`ws://127.0.0.1:${port}`, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]),
  });
  const closed = new Promise((resolve) => client.on("close", resolve));
  client.on("error", (e) => fail("client error: " + e.message));
  client.on("serverInfo", (info) => (serverName = info.name));
  client.on("advertise", (list) => {
    for (const ch of list) {
      channels.set(ch.id, ch);
      topicOf.set(client.subscribe(ch.id), ch.topic);
    }
    onAdvertise(list);
  });
  const decoder = new TextDecoder();
  client.on("message", ({ subscriptionId, timestamp, data }) => {
    const msg = JSON.parse(decoder.decode(new Uint8Array(data.buffer, data.byteOffset, data.byteLength)));
    (got[topicOf.get(subscriptionId)] ??= []).push(stamped ? { t: Number(timestamp) * 1e-9, msg } : msg);
  });
  const timeout = setTimeout(() => {
    fail(`no end of the run in ${seconds} s`);
    node.proc.kill("SIGTERM");
    client.close();
  }, seconds * 1000);
  await closed;  // the server closes the connection when the run or replay is over
  const { code, output } = await node.exited;
  clearTimeout(timeout);
  return { channels, got, serverName, code, output };
}

// The channels a team's view advertises, topic -> schema name: per robot its truth, estimate and ellipse, then the
// landmarks and the status.
export function teamChannels(robots) {
  const expected = { "/landmarks": "foxglove.SceneUpdate", "/status": "est.Status" };
  for (let r = 0; r < robots; ++r) {
    expected[`/robot${r}/truth`] = "foxglove.PoseInFrame";
    expected[`/robot${r}/estimate`] = "foxglove.PoseInFrame";
    expected[`/robot${r}/estimate/ellipse`] = "foxglove.SceneUpdate";
  }
  return expected;
}

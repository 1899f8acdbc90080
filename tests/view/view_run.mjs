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

// The determinism suite's full-pipeline workload (issue 14, "Determinism"): a recorded stream with faults replayed
// through estimator_node (LCM log reader, the backend's decoding, the HAL gate, the loop port, MCL, the outputs).
// The stream is made at test time by `sim_host record` with a fixed seed (itself deterministic: its bytes are
// checked against a stored digest, so a change of the simulator shows as such and not as a change of the node);
// the replay runs ten times, each output log's bytes hash to the stored digest, and the node's rejects by reason
// equal the sidecar's expected counts. Beside tests/test_determinism.cpp (the firmware's workloads in process).
// A deliberate change of either digest is accepted by updating kRecordDigest / kReplayDigest with the reason in the
// commit (the test prints the new values).
#include <catch2/catch.hpp>

#include <cstdint>
#include <cstdio>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "node_harness.hpp"
#include "scratch_dir.hpp"

namespace {

using namespace est::test;

const std::string kNode = ESTIMATOR_NODE_EXE;
const std::string kSim = SIM_HOST_EXE;

// 15 s of the office with the default fault plan (the shortest run that places all of it), less the classes a
// lockstep replay cannot show: staleness and stamps from the future (its HAL clock is each message's own stamp; the
// sidecar's note says so) and late landmark sightings (counted by an EKF's loop as too old; MCL drops sightings).
const std::string kRecord =
    " record --duration 15 --kidnap-at -1 --burst-at -1 --seed 11 --fault wheel_ticks.stale=0 "
    "--fault wheel_ticks.from_future=0 --fault steering.stale=0 --fault steering.from_future=0 --fault scan.stale=0 "
    "--fault scan.from_future=0 --fault landmarks.stale=0 --fault landmarks.from_future=0 --fault landmarks.late=0";
constexpr std::uint64_t kRecordDigest = 0x5596b4776e921397ull;
constexpr std::uint64_t kReplayDigest = 0x80bd46d74d02c1e9ull;
constexpr int kRuns = 10;

std::uint64_t fnv1a(const std::string& bytes) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (const char c : bytes) {
    h ^= static_cast<std::uint8_t>(c);
    h *= 0x100000001b3ull;
  }
  return h;
}

std::string hex(std::uint64_t v) {
  char b[32];
  std::snprintf(b, sizeof b, "0x%016llxull", static_cast<unsigned long long>(v));
  return b;
}

// The node's count for a sidecar key: hal.<sensor>.<reason>, hal.scan.beams_nan, loop.too_old.
long long node_count(const std::string& summary, const std::string& key) {
  if (key == "loop.too_old") return summary_value(summary, "  loop:", "too_old");
  if (key == "hal.scan.beams_nan") return summary_value(summary, "  beams.scan:", "nan");
  if (key == "hal.scan.beams_below_min") return summary_value(summary, "  beams.scan:", "below_min");
  const std::size_t dot = key.rfind('.');
  if (key.compare(0, 4, "hal.") != 0 || dot <= 4) return -2;
  return summary_value(summary, "  rejects." + key.substr(4, dot - 4) + ":", key.substr(dot + 1));
}

}  // namespace

TEST_CASE("a recorded stream with faults replayed through estimator_node ten times gives the stored digest and "
          "rejects every fault with its reason",
          "[determinism][node]") {
  const ScratchDir dir("est_determinism_node");
  const std::string d = dir.path.string() + "/";
  REQUIRE(run_command(kSim + kRecord + " --out " + d + "run.lcmlog", d + "record.txt") == 0);
  const std::uint64_t recorded = fnv1a(read_text(d + "run.lcmlog"));
  std::printf("recorded stream: %s\n", hex(recorded).c_str());
  CHECK(recorded == kRecordDigest);  // sim_host's recording itself moved: the replay's digest below moves with it

  const nlohmann::json sidecar = nlohmann::json::parse(read_text(d + "run.lcmlog.json"));
  const std::string options = sidecar.at("estimator_node_options").get<std::string>();
  std::uint64_t first = 0;
  std::string summary;
  for (int run = 0; run < kRuns; ++run) {
    const std::string out = d + "out" + std::to_string(run) + ".lcmlog";
    REQUIRE(run_command(kNode + " " + options + " --out " + out, d + "replay.txt") == 0);
    const std::uint64_t h = fnv1a(read_text(out));
    if (run == 0) {
      first = h;
      summary = read_text(d + "replay.txt");
      std::printf("replay: %s\n", hex(h).c_str());
    }
    INFO("run " << run);
    CHECK(h == first);
  }
  CHECK(first == kReplayDigest);

  // Every injected fault counted with its reason; nothing else rejected.
  INFO(summary);
  const std::map<std::string, int> expected = sidecar.at("expected_reject_counts").get<std::map<std::string, int>>();
  REQUIRE(expected.size() >= 10u);
  long long expected_hal = 0;
  for (const auto& [key, n] : expected) {
    INFO(key);
    CHECK(node_count(summary, key) == n);
    if (key.compare(0, 4, "hal.") == 0 && key.find(".beams_") == std::string::npos) expected_hal += n;
  }
  CHECK(summary_value(summary, "  rejects:", "total") == expected_hal);
  if (expected.count("loop.too_old") == 0) CHECK(summary_value(summary, "  loop:", "too_old") == 0);
}

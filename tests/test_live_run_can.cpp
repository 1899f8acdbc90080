// `sim_host run SCENARIO --live --can IFACE --lcm URL` (sim/live_run.hpp) inside tests/vm/run-in-vm, whose kernel has
// vcan0 (this machine's has no CAN): after the lockstep run, the run's sensor streams as estimator.dbc frames on
// vcan0 (can_player, each message at CLOCK_MONOTONIC stamp + a known offset; the landmark sightings on LCM), one
// estimator_node reading the bus, its estimates collected from LCM udpm and scored beside the lockstep's. Skipped
// (exit 77) where vcan0 or udpm is missing (outside the VM).
//
// What must hold, and why these bounds:
//  - bit for bit where the stream is the same: the node records the inputs it handed to the loop (the bus's bits and
//    the kernel's receive stamps), and their lockstep replay gives every live estimate to the bit;
//  - every message accounted for: each frame sent was received (none dropped by the kernel), each message handed to
//    the loop or rejected with a counted reason, each landmark sighting taken;
//  - against the lockstep run of the original stream, a bound: the bus carries 16-bit counters and 1 mm ranges and
//    the node stamps with receive times, so MCL's draws differ from the first scan on and the two estimates differ by
//    about the filter's own spread (HIL test: ~0.05 m tracking error). When the emulated machine kept time (every
//    input delayed under 20 ms on the way, every scan completed), the HIL test's bounds: 95 % of the lockstep's
//    estimates paired by their input, the paired difference under 0.10 m RMS and 0.25 m worst, the RMSE within
//    0.05 m of the lockstep's. When it did not (other builds beside the VM on 2 cores, load 10-12: can_player
//    descheduled for up to 0.2 s, frames out late in bursts, their receive stamps moving encoder increments into
//    later steps, scans past the reassembler's timeout; measured so over five runs: 84-85 % paired, 0.08-0.51 m RMS
//    apart, 0.22-0.74 m worst, the live RMSE 0.07-0.18 m against the lockstep's 0.032 m, and the HIL test's own
//    bounds failing beside it too), the difference from the lockstep run is the emulation's, not the bus's: then only
//    that the live run tracks (75 % of the lockstep's estimates paired, localized, RMSE under 0.3 m; a wrong decoding,
//    a scan off by a beam or ticks cut wrongly, loses the robot by metres), with the figures printed.
// The scenario: kidnapped tracking from its true start with 500 particles for 5 s (the kidnapping is at 12 s), as
// the HIL test's node: 20000 particles cannot keep real time under the VM's emulation (TCG). And with other builds
// beside it on 2 cores the emulated node falls seconds behind the bus, so --node-args gives it what a slower machine
// needs: a receive queue that holds the whole 5 s stream (16 MiB, ~6600 frames would otherwise overflow the default
// ~200 and be dropped), a staleness limit of 10 s, and no rate limit (the emulated scheduler delivers frames in
// bursts). The run waits until the node has published the estimate of the last input (live.json: node_behind_s).
#include <catch2/catch.hpp>
#include <net/if.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "node_harness.hpp"
#include "scratch_dir.hpp"

#ifndef SIM_HOST_EXE
#error "SIM_HOST_EXE must name the sim_host executable"
#endif

namespace {

namespace fs = std::filesystem;
using est::test::slurp;

std::string url_or_skip() {
  if (if_nametoindex("vcan0") == 0) {
    std::fprintf(stderr, "SKIP: no vcan0 here (run through tests/vm/run-in-vm)\n");
    std::fflush(stderr);
    std::_Exit(77);
  }
  return est::test::udpm_url_or_skip();
}

}  // namespace

TEST_CASE("sim_host run kidnapped --live --can vcan0: the node's estimates over CAN are the lockstep replay of its "
          "inputs bit for bit, within a bound of the lockstep run, every frame and input accounted for",
          "[live][can][vm]") {
  const std::string url = url_or_skip();
  const est::test::ScratchDir dir("live_run_can");
  const fs::path out = dir.path / "kidnapped";
  const std::string cmd = std::string("'") + SIM_HOST_EXE +
                          "' run kidnapped --duration 5 --set filter.particles=500 --set filter.start=tracking "
                          "--no-plots --quiet --out '" + out.string() + "' --live --can vcan0 --lcm '" + url +
                          "' --node-args '--max-ticks-per-s 1000000000 --max-age 10000 --can-rcvbuf 16777216' > '" +
                          (dir.path / "run.txt").string() + "' 2>&1";
  const int status = std::system(cmd.c_str());
  const int rc = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  const std::string printed = slurp(dir.path / "run.txt");
  std::printf("%s\n", printed.substr(printed.find("live over CAN")).c_str());
  INFO(printed);
  INFO(slurp(out / "live" / "node.txt"));
  INFO(slurp(out / "live" / "can_player.txt"));
  REQUIRE(rc == 0);
  const nlohmann::json j = nlohmann::json::parse(slurp(out / "live" / "live.json"));
  INFO(j.dump(1));
  const nlohmann::json &k = j.at("lockstep"), &l = j.at("live"), &in = j.at("inputs"), &p = j.at("paired");
  CHECK(j.at("nodes")[0].at("exit_status") == 0);

  // Bit for bit where the stream is the same.
  const nlohmann::json& again = j.at("replay_of_recorded_inputs");
  CHECK(again.at("exit_status") == 0);
  CHECK(again.at("all_identical").get<bool>());
  CHECK(again.at("published").get<double>() >= 0.8 * k.at("estimates").get<double>());
  // What came over LCM udpm is what the node wrote, bit for bit. Not all of it under load: the emulated collector
  // falls behind and its socket overflows (461 of 515 heard in one run at load 10; all of them in the others).
  const nlohmann::json& heard = j.at("heard_on_lcm");
  CHECK(heard.at("identical") == heard.at("estimates"));
  CHECK(heard.at("estimates").get<double>() >= 0.8 * again.at("published").get<double>());

  // Every message accounted for.
  CHECK(in.at("messages_sent").get<int>() == 550);  // 5 s: 500 encoder samples, 50 scans
  CHECK(in.at("frames_sent").get<int>() == 500 * 1 + 50 * 122);
  CHECK(in.at("frames_received") == in.at("frames_sent"));
  // Each message handed to the loop, or rejected by the HAL with a reason, or a scan the reassembler could not
  // complete (a frame past its timeout when the emulation stalls), counted with its reason.
  CHECK(in.at("taken").get<int>() + in.at("rejected").get<int>() + in.at("scans_incomplete").get<int>() ==
        in.at("messages_sent").get<int>());
  CHECK(in.at("scans_incomplete").get<int>() <= 3);  // of 50
  CHECK(in.at("landmarks_taken") == in.at("landmarks_on_lcm"));
  CHECK(in.at("landmarks_on_lcm").get<int>() > 0);
  CHECK(in.at("all_accounted").get<bool>());
  // Rejected inputs are counted; a few stale ones under the emulation at most.
  CHECK(l.at("inputs_rejected").get<double>() <= 0.02 * in.at("messages_sent").get<double>());

  // Within a bound of the lockstep run of the original stream.
  const double n = k.at("estimates").get<double>();
  CHECK(n >= 495.0);
  REQUIRE(l.at("phases").size() == 1u);
  CHECK(l.at("phases")[0].at("localized").get<bool>());
  const bool kept_time = p.at("offset_worst_ms").get<double>() < 20.0 && in.at("scans_incomplete") == 0;
  if (kept_time) {
    CHECK(p.at("matched").get<double>() >= 0.95 * n);
    CHECK(p.at("rms_difference_m").get<double>() < 0.10);
    CHECK(p.at("worst_position_m").get<double>() < 0.25);
    CHECK(l.at("rmse_position_m").get<double>() == Approx(k.at("rmse_position_m").get<double>()).margin(0.05));
  } else {
    WARN("the emulated machine did not keep time (worst input delay " << p.at("offset_worst_ms").get<double>()
         << " ms, " << in.at("scans_incomplete").get<int>() << " scans incomplete): the coarse bound only");
    CHECK(p.at("matched").get<double>() >= 0.75 * n);
    CHECK(l.at("rmse_position_m").get<double>() < 0.3);
  }
  std::printf("live over CAN (%s), kidnapped tracking 5 s: %g of %g estimates paired, RMS difference %.4f m, worst %.4f "
              "m; RMSE %.4f m live, %.4f m lockstep; %g of %g identical to the replay of the recorded inputs\n",
              kept_time ? "kept time" : "did not keep time", p.at("matched").get<double>(), n, p.at("rms_difference_m").get<double>(),
              p.at("worst_position_m").get<double>(), l.at("rmse_position_m").get<double>(),
              k.at("rmse_position_m").get<double>(), again.at("identical").get<double>(),
              again.at("published").get<double>());
}

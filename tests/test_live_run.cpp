// `sim_host run SCENARIO --live --lcm URL` (sim/live_run.hpp) as a user runs it: after the lockstep run, the same
// streams in real time over LCM udpm to estimator_node processes (one per robot), their estimates collected from LCM
// and scored against the truth beside the lockstep figures. Isolated as the other live tests are: udpm with ttl=0
// (this host only) on a port of this process's own, so that parallel runs do not hear each other. Skipped (exit 77)
// where udpm multicast does not work.
//
// The tolerance: live, each node gets the run's inputs in the run's order with the run's relative stamps (aligned to
// its clock at the first message), so its estimates are the lockstep run's to the bit unless the network lost or
// delayed a message, which changes MCL's draws from there on (a few centimetres while tracking). So: at least 95 % of
// the lockstep estimates paired by stamp, the position RMSE within 0.01 m and the time to localize within 0.5 s of
// the lockstep's, every input published taken by the node's LCM input, and at most 2 % of them rejected (stale
// under load) beyond the lockstep's rejects. Measured here: kidnapped 8 s, 800 of 800
// estimates identical to the bit, 920 of 920 inputs; coop-slam-team 5 s, 50 of 50 per robot identical, the team lines
// identical.
#include <catch2/catch.hpp>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <lcm/lcm-cpp.hpp>
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
  return est::test::udpm_url_or_skip();
}

int run(const std::string& args, const fs::path& log) {
  const std::string cmd = std::string("'") + SIM_HOST_EXE + "' run " + args + " > '" + log.string() + "' 2>&1";
  const int rc = std::system(cmd.c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

}  // namespace

TEST_CASE("sim_host run kidnapped --live: estimator_node over udpm in real time gives the lockstep metrics, every "
          "input taken", "[live][process]") {
  const std::string url = url_or_skip();
  const est::test::ScratchDir dir("live_run_robot");
  const fs::path out = dir.path / "kidnapped";
  const int rc = run("kidnapped --duration 8 --no-plots --quiet --out '" + out.string() + "' --live --lcm '" + url + "'",
                     dir.path / "run.txt");
  const std::string printed = slurp(dir.path / "run.txt");
  INFO(printed);
  INFO(slurp(out / "live" / "node.txt"));
  REQUIRE(rc == 0);
  CHECK(printed.find("live against lockstep") != std::string::npos);
  const nlohmann::json j = nlohmann::json::parse(slurp(out / "live" / "live.json"));
  const nlohmann::json &k = j.at("lockstep"), &l = j.at("live");
  const double n = k.at("estimates").get<double>();
  CHECK(n >= 790.0);  // 8 s at 100 Hz
  CHECK(j.at("paired").at("matched").get<double>() >= 0.95 * n);
  CHECK(l.at("rmse_position_m").get<double>() == Approx(k.at("rmse_position_m").get<double>()).margin(0.01));
  REQUIRE(l.at("phases").size() == 1u);
  CHECK(l.at("phases")[0].at("localized").get<bool>());
  CHECK(l.at("phases")[0].at("time_to_localize_s").get<double>() ==
        Approx(k.at("phases")[0].at("time_to_localize_s").get<double>()).margin(0.5));
  CHECK(j.at("inputs").at("all_accounted").get<bool>());
  CHECK(j.at("inputs").at("published").get<int>() > 900);
  // Every input counted: taken, or rejected with a reason. The lockstep run rejects none; live, a machine loaded
  // beside the test (load 7 on 2 cores) made a few late past the gate's 100 ms in the stamp alignment's test.
  CHECK(l.at("inputs_rejected").get<double>() <=
        k.at("inputs_rejected").get<double>() + 0.02 * j.at("inputs").at("published").get<double>());
  CHECK(j.at("nodes")[0].at("exit_status") == 0);
  std::printf("live kidnapped 8 s: %g of %g estimates paired, %g identical; RMSE %.4f m live, %.4f m lockstep\n",
              j.at("paired").at("matched").get<double>(), n, j.at("paired").at("identical").get<double>(),
              l.at("rmse_position_m").get<double>(), k.at("rmse_position_m").get<double>());
}

TEST_CASE("sim_host run coop-slam-team --live: one team node per robot over udpm gives the lockstep estimates",
          "[live][process]") {
  const std::string url = url_or_skip();
  const est::test::ScratchDir dir("live_run_team");
  const fs::path out = dir.path / "team";
  const int rc = run("coop-slam-team --duration 5 --no-plots --quiet --out '" + out.string() + "' --live --lcm '" +
                         url + "'",
                     dir.path / "run.txt");
  INFO(slurp(dir.path / "run.txt"));
  REQUIRE(rc == 0);
  const nlohmann::json j = nlohmann::json::parse(slurp(out / "live" / "live.json"));
  REQUIRE(j.at("robots").size() == 4u);
  for (const nlohmann::json& r : j.at("robots")) {
    INFO(r.dump());
    INFO(slurp(r.at("summary").get<std::string>()));
    CHECK(r.at("estimates_lockstep") == 50);
    CHECK(r.at("paired").get<double>() >= 0.95 * 50);
    CHECK(r.at("rmse_live_m").get<double>() == Approx(r.at("rmse_lockstep_m").get<double>()).margin(0.01));
    CHECK(r.at("own_received") == r.at("own_sent"));
    CHECK(r.at("exit_status") == 0);
  }
}

TEST_CASE("sim_host run --can goes with --live, and a team's live run has no CAN frames", "[live][process]") {
  const est::test::ScratchDir dir("live_run_can_refused");
  CHECK(run("kidnapped --duration 1 --no-plots --quiet --out '" + (dir.path / "a").string() + "' --can vcan0",
            dir.path / "a.txt") != 0);
  CHECK(slurp(dir.path / "a.txt").find("--can and --node-args go with --live") != std::string::npos);
  CHECK(run("coop-slam-team --duration 1 --no-plots --quiet --out '" + (dir.path / "b").string() +
                "' --live --can vcan0 --lcm 'udpm://239.255.76.67:7667?ttl=0'",
            dir.path / "b.txt") != 0);
  CHECK(slurp(dir.path / "b.txt").find("a team's messages have no CAN frames") != std::string::npos);
  CHECK(!fs::exists(dir.path / "b" / "live" / "node_0.txt"));  // no node started
}

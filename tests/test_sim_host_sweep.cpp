// sim_host sweep and aggregate (src/campaign_command.cpp, sim_host/campaign/): a short campaign run with --jobs 2
// gives each seed the metrics of its own `sim_host run`; a failing seed is reported with its seed, exit status and
// log, and the sweep exits non-zero after writing everything; the emitted Slurm batch script, run task by task
// without a scheduler, aggregates to the local sweep's metrics seed for seed.
#include <catch2/catch.hpp>

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "campaign/aggregate.hpp"
#include "scratch_dir.hpp"

#ifndef SIM_HOST_EXE
#error "SIM_HOST_EXE must name the sim_host executable"
#endif

namespace {

namespace fs = std::filesystem;
using est::test::ScratchDir;
using est::test::slurp;

// Runs `command` by the shell with stdout and stderr into `log`; its exit status.
int shell(const std::string& command, const fs::path& log) {
  const int status = std::system((command + " >'" + log.string() + "' 2>&1").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}
int sim_host(const std::string& args, const fs::path& log) {
  return shell(std::string("'") + SIM_HOST_EXE + "' " + args, log);
}

nlohmann::json read_json(const fs::path& p) { return nlohmann::json::parse(slurp(p)); }

// The campaign of these tests: kidnapped, 2 s a seed (a quarter of a second of wall time each).
const std::string kCampaign = "kidnapped --duration 2 --set filter.particles=300";

}  // namespace

TEST_CASE("a sweep aggregates each seed's metrics, which equal the seed's own sim_host run", "[sweep]") {
  ScratchDir d("sim_host_sweep");
  const fs::path out = d.path / "sweep";
  REQUIRE(sim_host("sweep " + kCampaign + " --seeds 3..8 --jobs 2 --out '" + out.string() + "'", d.path / "log") == 0);
  const nlohmann::json a = read_json(out / "aggregate.json");
  CHECK(a["seeds"]["total"] == 6);
  CHECK(a["seeds"]["succeeded"] == 6);
  CHECK(a["failures"].empty());
  CHECK(fs::file_size(out / "aggregate.png") > 0);
  // Not every seed localizes in 2 s with 300 particles: those have no RMSE (-1 in metrics.json), a missing seed.
  const nlohmann::json& rmse = a["metrics"]["accuracy.rmse_position_m"];
  CHECK(rmse["seeds"].get<std::size_t>() + rmse["missing_seeds"].size() == 6);
  CHECK(rmse["min"].get<double>() > 0.0);
  CHECK(rmse["median"].get<double>() <= rmse["p95"].get<double>());
  CHECK(rmse["p95"].get<double>() <= rmse["max"].get<double>());
  CHECK(rmse["worst"]["value"] == rmse["max"]);
  CHECK(a["campaign"]["set"] == nlohmann::json::array({"filter.particles=300"}));
  for (int seed = 3; seed <= 8; ++seed) {
    INFO("seed " << seed);
    const fs::path alone = d.path / ("alone-" + std::to_string(seed));
    REQUIRE(sim_host("run " + kCampaign + " --seed " + std::to_string(seed) + " --quiet --no-plots --out '" +
                         alone.string() + "'",
                     d.path / "run.log") == 0);
    const nlohmann::json own = sim::campaign::flatten_metrics(read_json(alone / "metrics.json"));
    CHECK(a["per_seed"][std::to_string(seed)] == own);
    CHECK(own.size() > 50);
  }
  // Each seed is its own process: different seeds, different runs.
  CHECK(a["per_seed"]["3"] != a["per_seed"]["4"]);
}

TEST_CASE("a failing seed is reported with its seed, exit status and log, and the sweep exits non-zero",
          "[sweep]") {
  ScratchDir d("sim_host_sweep_fail");
  const fs::path out = d.path / "sweep";
  // Seed 5 cannot write its trajectory: a folder stands where its file goes.
  fs::create_directories(out / "seed-5" / "trajectory.csv");
  REQUIRE(sim_host("sweep " + kCampaign + " --seeds 4..7 --jobs 2 --no-plots --out '" + out.string() + "'",
                   d.path / "log") == 1);
  const nlohmann::json a = read_json(out / "aggregate.json");
  CHECK(a["seeds"]["succeeded"] == 3);
  REQUIRE(a["failures"].size() == 1);
  CHECK(a["failures"][0]["seed"] == 5);
  CHECK(a["failures"][0]["exit_status"] == 1);
  CHECK(a["failures"][0]["log"] == (out / "seed-5" / "run.log").string());
  CHECK(slurp(out / "seed-5" / "run.log").find("trajectory.csv") != std::string::npos);
  CHECK(a["per_seed"].contains("4"));
  CHECK(a["metrics"]["loop.outputs"]["seeds"] == 3);
  const std::string said = slurp(d.path / "log");
  INFO(said);
  CHECK(said.find("FAILED seed 5: exit status 1; log " + (out / "seed-5" / "run.log").string()) != std::string::npos);
  // sim_host aggregate on the same folder says the same.
  CHECK(sim_host("aggregate --no-plots '" + out.string() + "'", d.path / "again") == 1);
  CHECK(read_json(out / "aggregate.json") == a);
}

TEST_CASE("a sweep with a refused --set runs nothing", "[sweep]") {
  ScratchDir d("sim_host_sweep_refused");
  const fs::path out = d.path / "sweep";
  CHECK(sim_host("sweep kidnapped --seeds 1..4 --set filter.particles=many --out '" + out.string() + "'",
                 d.path / "log") == 1);
  CHECK(slurp(d.path / "log").find("--set filter.particles=many: filter.particles: expected an integer, got a string") !=
        std::string::npos);
  CHECK(!fs::exists(out));
}

TEST_CASE("the emitted Slurm job array, run task by task, aggregates to the local sweep seed for seed", "[sweep]") {
  ScratchDir d("sim_host_sweep_slurm");
  const fs::path local = d.path / "local", slurm = d.path / "slurm";
  REQUIRE(sim_host("sweep " + kCampaign + " --seeds 2..4 --no-plots --out '" + local.string() + "'", d.path / "log") == 0);
  REQUIRE(sim_host("sweep " + kCampaign + " --seeds 2..4 --emit-slurm '" + slurm.string() + "'", d.path / "log") == 0);
  CHECK(!fs::exists(slurm / "seed-2"));  // nothing ran
  const std::string script = slurp(slurm / "campaign.sbatch");
  CHECK(script.find("#SBATCH --array=2-4\n") != std::string::npos);
  CHECK(script.find("'" + fs::canonical(SIM_HOST_EXE).string() + "' run 'kidnapped' --seed \"$seed\"") !=
        std::string::npos);
  for (int seed = 2; seed <= 4; ++seed)
    REQUIRE(shell("SLURM_ARRAY_TASK_ID=" + std::to_string(seed) + " sh '" + (slurm / "campaign.sbatch").string() + "'",
                  d.path / "task.log") == 0);
  REQUIRE(sim_host("aggregate --no-plots '" + slurm.string() + "'", d.path / "log") == 0);
  const nlohmann::json a = read_json(local / "aggregate.json"), b = read_json(slurm / "aggregate.json");
  CHECK(b["seeds"]["succeeded"] == 3);
  CHECK(a["per_seed"] == b["per_seed"]);
  CHECK(a["metrics"] == b["metrics"]);
}

TEST_CASE("a 2-value grid x 2 seeds runs 4 processes, each equal to its own sim_host run, grouped per value",
          "[sweep]") {
  ScratchDir d("sim_host_sweep_grid");
  const fs::path out = d.path / "sweep";
  const std::string grid = "kidnapped --duration 2 --set filter.particles=200,400";
  REQUIRE(sim_host("sweep " + grid + " --seeds 5..6 --jobs 2 --out '" + out.string() + "'", d.path / "log") == 0);
  const nlohmann::json a = read_json(out / "aggregate.json");
  CHECK(a["seeds"]["total"] == 4);
  CHECK(a["seeds"]["succeeded"] == 4);
  CHECK(fs::file_size(out / "aggregate.png") > 0);
  REQUIRE(a["combinations"].size() == 2);
  for (std::size_t i = 0; i < 2; ++i) {
    const nlohmann::json& k = a["combinations"][i];
    const std::string particles = i == 0 ? "200" : "400";
    CHECK(k["set"]["filter.particles"] == particles);
    CHECK(k["seeds"]["total"] == 2);
    REQUIRE(k["per_seed"].size() == 2);
    for (int seed = 5; seed <= 6; ++seed) {
      INFO("particles " << particles << ", seed " << seed);
      const fs::path alone = d.path / ("alone-" + particles + "-" + std::to_string(seed));
      REQUIRE(sim_host("run kidnapped --duration 2 --set filter.particles=" + particles + " --seed " +
                           std::to_string(seed) + " --quiet --no-plots --out '" + alone.string() + "'",
                       d.path / "run.log") == 0);
      const nlohmann::json own = sim::campaign::flatten_metrics(read_json(alone / "metrics.json"));
      CHECK(k["per_seed"][std::to_string(seed)] == own);
      // The run's own files are the same bits too.
      CHECK(slurp(fs::path(k["dir"].get<std::string>()) / ("seed-" + std::to_string(seed)) / "trajectory.csv") ==
            slurp(alone / "trajectory.csv"));
      // The statistics of a combination are over its own seeds only.
      const nlohmann::json& m = k["metrics"]["loop.outputs"];
      CHECK(m["seeds"] == 2);
    }
  }
  // Different particle counts, different runs (MCL's particle count changes its draws).
  CHECK(a["combinations"][0]["per_seed"]["5"] != a["combinations"][1]["per_seed"]["5"]);
  // The emitted job array runs the same 4 runs, task by task, and aggregates to the same values.
  const fs::path slurm = d.path / "slurm";
  REQUIRE(sim_host("sweep " + grid + " --seeds 5..6 --emit-slurm '" + slurm.string() + "'", d.path / "log") == 0);
  const std::string script = slurp(slurm / "campaign.sbatch");
  CHECK(script.find("#SBATCH --array=0-3\n") != std::string::npos);
  for (int task = 0; task < 4; ++task)
    REQUIRE(shell("SLURM_ARRAY_TASK_ID=" + std::to_string(task) + " sh '" + (slurm / "campaign.sbatch").string() + "'",
                  d.path / "task.log") == 0);
  REQUIRE(sim_host("aggregate --no-plots '" + slurm.string() + "'", d.path / "log") == 0);
  const nlohmann::json b = read_json(slurm / "aggregate.json");
  REQUIRE(b["combinations"].size() == 2);
  for (std::size_t i = 0; i < 2; ++i) {
    CHECK(b["combinations"][i]["per_seed"] == a["combinations"][i]["per_seed"]);
    CHECK(b["combinations"][i]["metrics"] == a["combinations"][i]["metrics"]);
  }
}

TEST_CASE("a grid with a value the scenario refuses runs nothing", "[sweep]") {
  ScratchDir d("sim_host_sweep_grid_refused");
  const fs::path out = d.path / "sweep";
  CHECK(sim_host("sweep kidnapped --seeds 1..2 --set filter.particles=300,many --out '" + out.string() + "'",
                 d.path / "log") == 1);
  CHECK(slurp(d.path / "log").find("--set filter.particles=many: filter.particles: expected an integer") !=
        std::string::npos);
  CHECK(!fs::exists(out));
}

// The sweep and aggregate subcommands: a scenario over a range of seeds (sim_host/campaign/), run here as parallel
// processes or written out as a Slurm job array, and the aggregation of a campaign's folder.
#include <CLI/CLI.hpp>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "campaign/aggregate.hpp"
#include "campaign/campaign.hpp"
#include "campaign/slurm.hpp"
#include "campaign/sweep.hpp"
#include "sim/builtin_scenarios.hpp"
#include "sim/commands.hpp"

namespace sim {
namespace fs = std::filesystem;

void add_sweep_command(CLI::App& app) {
  struct Options {
    std::string scenario, seeds, out, emit_slurm;
    std::vector<std::string> sets;
    std::size_t jobs = 2;
    double duration_s = 0.0;
    bool quiet = false, no_plots = false;
  };
  auto o = std::make_shared<Options>();
  CLI::App* c = app.add_subcommand(
      "sweep",
      "Runs a scenario for each seed of --seeds A..B, each as its own `sim_host run` process (--jobs at a time) into "
      "OUT/seed-N (its stdout and stderr in run.log, its exit code in exit_status), then aggregates every metric of "
      "the runs (mean, median, p95, worst seed) and lists the failed seeds with their logs: OUT/aggregate.json, "
      "OUT/aggregate.png. A --set KEY=V1,V2,... with several values makes a grid: every combination of the values "
      "of such keys runs every seed, into OUT/<combination>/seed-N, aggregated per combination. Exits 1 when a seed failed, after writing everything. --emit-slurm DIR writes the "
      "campaign as a Slurm job array instead (DIR/campaign.sbatch) and runs nothing: `sim_host aggregate DIR` "
      "after it ran.");
  c->add_option("scenario", o->scenario, "NAME of a built-in scenario, or a FILE")->required();
  c->add_option("--seeds", o->seeds, "A..B: the seeds, both included (or one seed N)")->required();
  c->add_option("--jobs,-j", o->jobs, "runs at a time")->capture_default_str()->check(CLI::PositiveNumber);
  c->add_option("--set", o->sets,
                "KEY=VALUE for every run, as sim_host run --set (repeatable); KEY=V1,V2,...: a grid axis, one run of "
                "each seed per value (commas inside [ ], { } or quotes are the value's)")
      ->allow_extra_args(false);
  CLI::Option* duration = c->add_option("--duration", o->duration_s, "each run's duration, s (as sim_host run)");
  c->add_option("--out", o->out, "the campaign's folder (default: runs/sweep-NAME)");
  c->add_option("--emit-slurm", o->emit_slurm, "write the campaign into DIR as a Slurm job array; run nothing");
  c->add_flag("--quiet", o->quiet, "no progress bar on a terminal");
  c->add_flag("--no-plots", o->no_plots, "no aggregate.png (no gnuplot needed)");
  c->callback([o, duration]() {
    campaign::Campaign k;
    try {
      campaign::parse_seed_range(o->seeds, k);
    } catch (const std::invalid_argument& e) {
      throw CLI::ValidationError("--seeds", e.what());
    }
    for (const std::string& kv : o->sets) {
      try {
        campaign::add_set(k, kv);
      } catch (const std::invalid_argument& e) {
        throw CLI::ValidationError("--set", e.what());
      }
    }
    // The scenario and its overrides (every combination's) are checked here, once, before anything runs.
    for (const campaign::Combination& point : k.combinations()) {
      std::vector<ScenarioOverride> overrides;
      for (const std::string& kv : k.sets) overrides.push_back(parse_override(kv));
      for (const std::string& kv : point.sets) overrides.push_back(parse_override(kv));
      ScenarioFile f = load_scenario(o->scenario, overrides);
      if (duration->count() > 0) set_duration(f, o->duration_s);
    }
    if (duration->count() > 0) k.duration_s = o->duration_s;
    k.scenario = find_builtin_scenario(o->scenario) != nullptr ? o->scenario : fs::absolute(o->scenario).string();
    k.sim_host = fs::read_symlink("/proc/self/exe").string();
    const std::string name = fs::path(o->scenario).stem().string();
    if (!o->emit_slurm.empty()) {
      const fs::path dir = fs::absolute(o->emit_slurm).lexically_normal();
      campaign::emit_slurm(k, dir);
      std::cout << "campaign " << k.scenario << ", seeds " << k.first_seed << ".." << k.last_seed << ": "
                << (dir / "campaign.sbatch").string() << " (a job array of " << k.run_count()
                << " tasks) and campaign.json; submit with `sbatch " << (dir / "campaign.sbatch").string()
                << "`, then `sim_host aggregate " << dir.string() << "`\n";
      return;
    }
    const fs::path dir = fs::absolute(o->out.empty() ? "runs/sweep-" + name : o->out).lexically_normal();
    campaign::write_campaign_json(k, dir);
    campaign::run_sweep(k, dir, o->jobs, o->quiet);
    const nlohmann::ordered_json a = campaign::aggregate_campaign(dir, !o->no_plots);
    std::cout << campaign::aggregate_summary(a) << "  -> " << (dir / "aggregate.json").string()
              << (o->no_plots ? "" : ", aggregate.png") << "\n";
    if (a["seeds"]["failed"].get<std::size_t>() > 0) throw CLI::RuntimeError(1);
  });
}

void add_aggregate_command(CLI::App& app) {
  struct Options {
    std::string dir;
    bool no_plots = false;
  };
  auto o = std::make_shared<Options>();
  CLI::App* c = app.add_subcommand(
      "aggregate",
      "Aggregates a campaign's folder (written by sim_host sweep, or by the Slurm job array of sweep --emit-slurm): "
      "DIR/aggregate.json and DIR/aggregate.png, as the local sweep writes them. Exits 1 when a seed failed or "
      "left no result.");
  c->add_option("dir", o->dir, "the campaign's folder (its campaign.json names the seeds)")->required();
  c->add_flag("--no-plots", o->no_plots, "no aggregate.png (no gnuplot needed)");
  c->callback([o]() {
    const fs::path dir = fs::absolute(o->dir).lexically_normal();
    const nlohmann::ordered_json a = campaign::aggregate_campaign(dir, !o->no_plots);
    std::cout << campaign::aggregate_summary(a) << "  -> " << (dir / "aggregate.json").string()
              << (o->no_plots ? "" : ", aggregate.png") << "\n";
    if (a["seeds"]["failed"].get<std::size_t>() > 0) throw CLI::RuntimeError(1);
  });
}

}  // namespace sim

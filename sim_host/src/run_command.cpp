// The run and list subcommands: a scenario file (sim/scenario_file.hpp), built in or from disk, run end to end.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "sim/builtin_scenarios.hpp"
#include "sim/commands.hpp"
#include "sim/scenario_run.hpp"

namespace sim {
namespace {

const char* runner_name(ScenarioRunner r) {
  switch (r) {
    case ScenarioRunner::simulate: return "robot";
    case ScenarioRunner::team: return "team";
    case ScenarioRunner::exercise: return "exercise";
  }
  return "?";
}

}  // namespace

void add_run_command(CLI::App& app) {
  struct Options {
    std::string scenario, out;
    std::vector<std::string> sets;
    std::uint64_t seed = 0;
    double duration_s = 0.0;
    bool quiet = false, no_plots = false, view_wait = false, live = false;
    std::string lcm_url = "udpm://239.255.76.67:7667?ttl=0", node_exe, can_interface, node_args;
    std::uint16_t view_port = 0;
    double view_speed = 1.0;
  };
  auto o = std::make_shared<Options>();
  CLI::App* c = app.add_subcommand(
      "run",
      "Runs a scenario: a built-in one by NAME (sim_host list) or a scenario FILE (TOML; sim_host/scenarios/"
      "example.toml documents every key). A malformed file is refused with FILE:LINE:COLUMN: reason and nothing "
      "runs. Writes the runner's files to --out (a single robot: trajectory.csv, faults.csv, metrics.json and "
      "figures, as simulate) and prints its summary.");
  c->add_option("scenario", o->scenario, "NAME of a built-in scenario, or a FILE")->required();
  CLI::Option* seed = c->add_option("--seed", o->seed, "overrides the scenario's seed");
  c->add_option("--set", o->sets,
                "KEY=VALUE: overrides a key of the scenario by its dotted path in the file (filter.particles=256, "
                "faults.counts.scan.stale=3; repeatable); refused with the key and the reason when the scenario does "
                "not read that key or the value does not fit it")
      ->allow_extra_args(false);
  CLI::Option* duration = c->add_option("--duration", o->duration_s, "overrides the scenario's duration, s");
  c->add_option("--out", o->out, "output directory (created; default: runs/NAME)");
  c->add_flag("--quiet", o->quiet, "no progress line on a terminal");
  c->add_flag("--no-plots", o->no_plots, "skip the PNG figures (no gnuplot needed)");
  c->add_option("--view", o->view_port,
                "serve the live view on localhost:PORT during the run: the page at http://localhost:PORT/, the Foxglove "
                "WebSocket protocol for Foxglove Studio (a single robot, or a team's robots and landmarks; 0: none)")->capture_default_str();
  c->add_option("--view-speed", o->view_speed, "with --view: the run at this many times real time (0: full speed)")
      ->capture_default_str()->check(CLI::NonNegativeNumber);
  c->add_flag("--view-wait", o->view_wait, "with --view: start the run once a viewer has subscribed");
  c->add_flag("--live", o->live,
              "after the lockstep run, run it again in real time against estimator_node processes (one per robot, "
              "the run's node options) fed over LCM (--lcm), their estimates collected from LCM and scored beside the "
              "lockstep figures; OUT/live/ holds the nodes' summaries, their estimates and live.json");
  c->add_option("--lcm", o->lcm_url, "with --live: the LCM URL of the streams and the estimates")->capture_default_str();
  c->add_option("--node-exe", o->node_exe, "with --live: the estimator_node to run (default: beside sim_host)");
  c->add_option("--can", o->can_interface,
                "with --live (a single robot): the sensor streams as estimator.dbc CAN frames on this interface "
                "(can_player beside sim_host; landmark sightings on LCM), the node reading the bus; its estimates "
                "still come back on --lcm");
  c->add_option("--node-args", o->node_args,
                "with --live: options for every node in place of the run's options of the same names (e.g. wider "
                "HAL limits on an emulated machine: '--max-age 2000')");
  c->callback([o, seed, duration]() {
    std::vector<ScenarioOverride> overrides;
    for (const std::string& kv : o->sets) overrides.push_back(parse_override(kv));
    ScenarioFile f = load_scenario(o->scenario, overrides);
    if (seed->count() > 0) {
      f.scenario.seed = o->seed;
      f.exercise_seed = o->seed;
    }
    if (duration->count() > 0) set_duration(f, o->duration_s);
    const std::string out =
        o->out.empty() ? "runs/" + std::filesystem::path(o->scenario).stem().string() : o->out;
    RunOptions ro;
    ro.out = out;
    ro.plots = !o->no_plots;
    ro.quiet = o->quiet;
    ro.view_port = o->view_port;
    ro.view_speed = o->view_speed;
    ro.view_wait = o->view_wait;
    if (o->live) {
      if (o->view_port != 0) throw CLI::ValidationError("--live", "a live run has no --view (the nodes take --view)");
      ro.live_lcm_url = o->lcm_url;
      ro.live.node_exe = o->node_exe;
      ro.live.can_interface = o->can_interface;
      ro.live.node_args = o->node_args;
    } else if (!o->can_interface.empty() || !o->node_args.empty()) {
      throw CLI::ValidationError("--can", "--can and --node-args go with --live");
    }
    run_scenario(f, ro);
  });
}

void add_list_command(CLI::App& app) {
  CLI::App* c = app.add_subcommand("list", "Lists the built-in scenarios of sim_host run: name, runner, description.");
  c->callback([]() {
    std::size_t w = 0;
    for (const BuiltinScenario& b : builtin_scenarios()) w = std::max(w, b.name.size());
    for (const BuiltinScenario& b : builtin_scenarios()) {
      const ScenarioFile f = parse_scenario(b.text, b.path);
      std::printf("%-*s  %-8s  %s\n", static_cast<int>(w), b.name.c_str(), runner_name(f.runner),
                  f.description.c_str());
    }
  });
}

}  // namespace sim

// sim_host: the host simulator and tools, one subcommand each (sim_host --help lists them).
#include <CLI/CLI.hpp>
#include <exception>
#include <iostream>

#include "data/formats.hpp"
#include "data/plot_log.hpp"
#include "sim/commands.hpp"
#include "sim/scenario_file.hpp"

int main(int argc, char** argv) {
  CLI::App app{"sim_host: host simulator and tools for the estimator firmware"};
  app.require_subcommand(1);
  sim::add_run_command(app);
  sim::add_list_command(app);
  sim::add_sweep_command(app);
  sim::add_aggregate_command(app);
  sim::add_sample_motion_command(app);
  sim::add_simulate_command(app);
  sim::add_record_command(app);
  sim::add_learn_beam_model_command(app);
  sim::data::add_import_command(app);
  sim::data::add_eval_command(app);
  sim::data::add_plot_command(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const sim::ScenarioFileError& e) {
    std::cerr << e.what() << "\n";  // FILE:LINE:COLUMN: reason
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "sim_host: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}

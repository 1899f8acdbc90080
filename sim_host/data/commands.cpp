// The import and eval subcommands of sim_host (data/formats.hpp).
#include <CLI/CLI.hpp>

#include "data/formats.hpp"

namespace sim::data {

void add_import_command(CLI::App& app) {
  CLI::App* cmd = app.add_subcommand(
      "import",
      "Import a public dataset into an LCM log that estimator_node --replay and sim_host eval read: its sensor inputs "
      "on the estimator's channels, its reference (ground truth, GPS, corrected poses) on their own");
  cmd->require_subcommand(1);
  add_mrclam_import(*cmd);
  add_victoria_import(*cmd);
  add_carmen_import(*cmd);
  add_tricycle_import(*cmd);
}

void add_eval_command(CLI::App& app) {
  CLI::App* cmd = app.add_subcommand(
      "eval",
      "Evaluate the estimator on a public dataset: import it, replay it through the firmware's loop and compare with "
      "the dataset's reference; prints a table, writes plots and a JSON file");
  cmd->require_subcommand(1);
  add_mrclam_eval(*cmd);
  add_victoria_eval(*cmd);
  add_carmen_eval(*cmd);
  add_tricycle_eval(*cmd);
}

}  // namespace sim::data

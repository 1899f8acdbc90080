#pragma once
// `sim_host import FORMAT INPUT... --out FILE.lcmlog` and `sim_host eval FORMAT INPUT... [--json] [--out DIR]`: one
// subcommand per dataset format, each in its own file (data/<format>.cpp imports, data/<format>_eval.cpp
// evaluates; the import subcommands are in data/import_commands.cpp). Host only.
#include <string>

namespace CLI {
class App;
}  // namespace CLI

namespace sim::data {

void add_import_command(CLI::App& app);
void add_eval_command(CLI::App& app);

// Each format's subcommand under `import` and under `eval`.
void add_mrclam_import(CLI::App& import);
void add_mrclam_eval(CLI::App& eval);
void add_victoria_import(CLI::App& import);
void add_victoria_eval(CLI::App& eval);
void add_carmen_import(CLI::App& import);
void add_carmen_eval(CLI::App& eval);
void add_tricycle_import(CLI::App& import);
void add_tricycle_eval(CLI::App& eval);

}  // namespace sim::data

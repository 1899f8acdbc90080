// --on-error of every importer (data/formats.hpp).
#include <CLI/CLI.hpp>

#include "data/formats.hpp"
#include "data/import_report.hpp"

namespace sim::data {

CLI::Option* add_on_error_option(CLI::App& cmd, OnError& out) {
  return cmd
      .add_option_function<std::string>(
          "--on-error",
          [&out](const std::string& s) {
            if (!parse(s, out)) throw CLI::ValidationError("--on-error", "expected skip or refuse");
          },
          "a malformed line: skip it (reported with its file and line, counted in the summary) or refuse the import")
      ->default_str("skip");
}

}  // namespace sim::data

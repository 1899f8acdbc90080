// PLACEHOLDER until the victoria importer lands (this session).
#include <CLI/CLI.hpp>

#include "data/formats.hpp"

namespace sim::data {

void add_victoria_import(CLI::App&) {}

}  // namespace sim::data

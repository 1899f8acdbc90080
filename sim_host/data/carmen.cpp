// PLACEHOLDER until the carmen importer lands (this session).
#include <CLI/CLI.hpp>

#include "data/formats.hpp"

namespace sim::data {

void add_carmen_import(CLI::App&) {}

}  // namespace sim::data

// PLACEHOLDER until the tricycle importer lands (this session).
#include <CLI/CLI.hpp>

#include "data/formats.hpp"

namespace sim::data {

void add_tricycle_import(CLI::App&) {}

}  // namespace sim::data

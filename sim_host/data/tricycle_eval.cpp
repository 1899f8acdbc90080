// PLACEHOLDER until the tricycle evaluation lands (this session).
#include <CLI/CLI.hpp>

#include "data/formats.hpp"

namespace sim::data {

void add_tricycle_eval(CLI::App&) {}

}  // namespace sim::data

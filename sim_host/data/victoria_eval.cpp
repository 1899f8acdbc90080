// PLACEHOLDER until the victoria evaluation lands (this session).
#include <CLI/CLI.hpp>

#include "data/formats.hpp"

namespace sim::data {

void add_victoria_eval(CLI::App&) {}

}  // namespace sim::data

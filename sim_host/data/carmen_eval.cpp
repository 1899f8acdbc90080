// PLACEHOLDER until the carmen evaluation lands (this session).
#include <CLI/CLI.hpp>

#include "data/formats.hpp"

namespace sim::data {

void add_carmen_eval(CLI::App&) {}

}  // namespace sim::data

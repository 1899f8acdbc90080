// libFuzzer target: scenario files (TOML, sim_host/src/scenario_file.cpp), as `sim_host run FILE` reads them. A
// malformed file must be refused with a ScenarioFileError ("FILE:LINE:COLUMN: reason"); any other exception, a crash,
// a hang or a sanitizer report is a finding. (A control script's CSV file, robot.controls = "PATH", is refused as
// PATH:LINE:COLUMN: reason.) The parser is compiled here with the fuzzer's instrumentation; what it
// calls of the simulator (fault catalogue, team names) comes from the host build's libraries (scripts/fuzz).
#include <cstddef>
#include <cstdint>
#include <regex>
#include <string>

#include "sim/scenario_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const sim::ScenarioFile f = sim::parse_scenario(text, "fuzz.toml");
    (void)f;
  } catch (const sim::ScenarioFileError& e) {
    const std::string what = e.what();
    // A refusal names its place: the file, then a line and a column; a control script's CSV file (robot.controls
    // names its path) is refused at its own place.
    static const std::regex csv_place(R"(^.+:[0-9]+:[0-9]+: (robot\.controls|the control script|cannot read the control).*)");
    const bool csv = what.find("control") != std::string::npos && std::regex_match(what, csv_place);
    if (what.rfind("fuzz.toml:", 0) != 0 && !csv) __builtin_trap();
  }
  return 0;
}

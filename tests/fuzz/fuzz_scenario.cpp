// libFuzzer target: scenario files (TOML, sim_host/src/scenario_file.cpp), as `sim_host run FILE` reads them. A
// malformed file must be refused with a ScenarioFileError ("FILE:LINE:COLUMN: reason"); any other exception, a crash,
// a hang or a sanitizer report is a finding. (A control script's CSV file, robot.controls = "PATH", is refused as
// PATH:LINE:COLUMN: reason.) The parser is compiled here with the fuzzer's instrumentation; what it
// calls of the simulator (fault catalogue, team names) comes from the host build's libraries (scripts/fuzz).
#include <cstddef>
#include <cstdint>
#include <string>

#include "sim/scenario_file.hpp"

namespace {

// PATH:LINE:COLUMN: then one of a control script's reasons, with a non-empty PATH. Checked by hand: std::regex
// (^.+:[0-9]+:[0-9]+: ...) recursed once per character in libstdc++ and overflowed the stack on a 4 KB path (a
// finding of this harness, not of the parser; the input is in the corpus).
bool control_place(const std::string& w) {
  for (const char* reason : {"robot.controls", "the control script", "cannot read the control"}) {
    const std::string tail = std::string(": ") + reason;
    for (std::size_t p = w.find(tail); p != std::string::npos; p = w.find(tail, p + 1)) {
      std::size_t i = p;  // w[0, i) must end with :LINE:COLUMN
      bool ok = true;
      for (int field = 0; field < 2 && ok; ++field) {
        std::size_t j = i;
        while (j > 0 && w[j - 1] >= '0' && w[j - 1] <= '9') --j;
        ok = j < i && j > 0 && w[j - 1] == ':';
        i = j - 1;
      }
      if (ok && i > 0) return true;
    }
  }
  return false;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const sim::ScenarioFile f = sim::parse_scenario(text, "fuzz.toml");
    (void)f;
  } catch (const sim::ScenarioFileError& e) {
    const std::string what = e.what();
    // A refusal names its place: the file, then a line and a column; a control script's CSV file (robot.controls
    // names its path) is refused at its own place.
    const bool csv = what.find("control") != std::string::npos && control_place(what);
    if (what.rfind("fuzz.toml:", 0) != 0 && !csv) __builtin_trap();
  }
  return 0;
}

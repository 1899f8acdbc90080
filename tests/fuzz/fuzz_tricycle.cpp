// libFuzzer target: any bytes as the tricycle calibration set (sim_host/data/tricycle.hpp import_tricycle: the '#'
// header with the parameters' guesses and the encoders' ranges, then "time: T ticks: S T model_pose: ...
// tracker_pose: X Y THETA" records), in memfds. The first byte picks --on-error skip or refuse. A bad line is
// skipped with FILE:LINE or refused naming the file; a file without a record is refused naming it. What was
// imported reads back: as many records as the import counted, stamps increasing, tracked poses finite.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "data/import_report.hpp"
#include "data/tricycle.hpp"
#include "memfd_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const auto mode = (data[0] & 1) != 0 ? sim::data::OnError::refuse : sim::data::OnError::skip;
  static std::FILE* quiet = std::fopen("/dev/null", "w");
  const fuzz::MemFile in("tricycle", data + 1, size - 1);
  const fuzz::MemFile out("tricycle.lcmlog", nullptr, 0);
  sim::data::ImportReport report(mode, quiet, 0);
  sim::data::TricycleImportOptions options;
  try {
    const sim::data::TricycleImport r = sim::data::import_tricycle(in.path(), out.path(), options, report);
    const std::vector<sim::data::TricycleRecord> back = sim::data::read_tricycle_log(out.path());
    if (back.size() != r.records) __builtin_trap();
    std::int64_t last = -1;
    for (const sim::data::TricycleRecord& x : back) {
      if (x.t_ns <= last || !std::isfinite(x.tracker.x) || !std::isfinite(x.tracker.y) ||
          !std::isfinite(x.tracker.theta))
        __builtin_trap();
      last = x.t_ns;
    }
  } catch (const std::runtime_error& e) {
    if (std::string(e.what()).rfind(in.path(), 0) != 0) __builtin_trap();
  }
  return 0;
}

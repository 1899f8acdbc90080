// libFuzzer target: any bytes as a CARMEN log (sim_host/data/carmen.hpp parse_carmen: FLASER, ROBOTLASER1, ODOM,
// PARAM lines, plain or gzipped), through LineReader's zlib path by a memfd (no file on disk; the importer opens
// paths). The first byte picks --on-error skip or refuse. Bad lines are skipped with FILE:LINE or refused naming
// them; a file with no scan is refused naming the file. Every parsed scan has finite, ordered stamps and its line.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "data/carmen.hpp"
#include "data/import_report.hpp"
#include "memfd_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const auto mode = (data[0] & 1) != 0 ? sim::data::OnError::refuse : sim::data::OnError::skip;
  static std::FILE* quiet = std::fopen("/dev/null", "w");
  const fuzz::MemFile file("carmen", data + 1, size - 1);
  const std::string path = file.path();
  sim::data::ImportReport report(mode, quiet, 0);
  sim::data::CarmenImportOptions options;
  try {
    const sim::data::CarmenData d = sim::data::parse_carmen(path, options, report);
    for (const sim::data::CarmenScan& s : d.scans)
      if (s.line == 0 || !std::isfinite(s.geometry.angle_increment_rad)) __builtin_trap();
  } catch (const std::runtime_error& e) {
    if (std::string(e.what()).rfind(path, 0) != 0) __builtin_trap();
  }
  return 0;
}

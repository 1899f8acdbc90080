// libFuzzer target: the datasets' numeric rows (sim_host/data/line_reader.hpp read_numeric_rows, which the MRCLAM
// and Victoria Park importers read every file with) on any bytes, plain or gzipped. The first byte picks the field
// count (1..8), whether time must not go back, and --on-error skip or refuse. The bytes reach LineReader's zlib path
// through a memfd (no file on disk; LineReader opens paths, as the importers do). Every kept row has the field count,
// finite values and a line number in order; a refusal names the file and the line.
#include <sys/mman.h>
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

#include "data/import_report.hpp"
#include "data/line_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::size_t fields = 1 + (data[0] & 7);
  const bool monotonic = (data[0] & 8) != 0;
  const auto mode = (data[0] & 16) != 0 ? sim::data::OnError::refuse : sim::data::OnError::skip;
  static std::FILE* quiet = std::fopen("/dev/null", "w");
  const int fd = memfd_create("rows", 0);
  if (fd < 0) __builtin_trap();
  if (write(fd, data + 1, size - 1) != static_cast<ssize_t>(size - 1)) __builtin_trap();
  const std::string path = "/proc/self/fd/" + std::to_string(fd);
  sim::data::ImportReport report(mode, quiet, 0);
  try {
    const sim::data::NumericRows rows = sim::data::read_numeric_rows(path, fields, report, '#', monotonic);
    if (rows.values.size() != rows.lines.size()) __builtin_trap();
    std::uint64_t last_line = 0;
    double last_t = -INFINITY;
    for (std::size_t i = 0; i < rows.values.size(); ++i) {
      if (rows.values[i].size() != fields || rows.lines[i] <= last_line) __builtin_trap();
      for (double v : rows.values[i])
        if (!std::isfinite(v)) __builtin_trap();
      if (monotonic && rows.values[i][0] < last_t) __builtin_trap();
      last_line = rows.lines[i];
      last_t = rows.values[i][0];
    }
  } catch (const sim::data::ImportError& e) {
    if (mode != sim::data::OnError::refuse || std::string(e.what()).rfind(path + ":", 0) != 0) __builtin_trap();
  } catch (const std::runtime_error& e) {  // a corrupt gzip stream: a read error naming the file
    if (std::string(e.what()).rfind(path + ": read error", 0) != 0) __builtin_trap();
  }
  close(fd);
  return 0;
}

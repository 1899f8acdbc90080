// libFuzzer target: any bytes as the Victoria Park text files (sim_host/data/victoria.hpp import_victoria:
// inputs.dat "t speed steering", measurements.dat "t range angle diameter", gps.dat "t x y"), the input split at its
// first two form feeds into the three files of a folder of this process's own under /dev/shm. The first byte picks
// --on-error skip or refuse. A bad row is skipped with FILE:LINE or refused naming its file; what was imported
// reads back: as many scans as the import counted, every detection and fix finite.
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "data/import_report.hpp"
#include "data/victoria.hpp"
#include "folder_files.hpp"
#include "memfd_file.hpp"

namespace {

const std::string& folder() {
  static const std::string dir = [] {
    const std::string d = "/dev/shm/fuzz_victoria_" + std::to_string(getpid());
    std::filesystem::create_directories(d);
    return d;
  }();
  return dir;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const auto mode = (data[0] & 1) != 0 ? sim::data::OnError::refuse : sim::data::OnError::skip;
  static std::FILE* quiet = std::fopen("/dev/null", "w");
  const char* names[3] = {"inputs.dat", "measurements.dat", "gps.dat"};
  fuzz::write_folder(folder(), names, 3, data, size, 1);
  const fuzz::MemFile out("victoria.lcmlog", nullptr, 0);
  sim::data::ImportReport report(mode, quiet, 0);
  sim::data::VictoriaImportOptions options;
  try {
    const sim::data::VictoriaImport r = sim::data::import_victoria(folder(), out.path(), options, report);
    const sim::data::VictoriaLog back = sim::data::read_victoria_log(out.path());
    if (back.scans.size() != r.scans || back.gps.size() != r.gps) __builtin_trap();
    for (const sim::data::VictoriaScan& s : back.scans)
      for (const sim::data::VictoriaDetection& d : s.trees)
        if (!std::isfinite(d.range) || !std::isfinite(d.bearing) || !std::isfinite(d.diameter)) __builtin_trap();
    for (const sim::data::TimedPose& p : back.gps)
      if (!std::isfinite(p.x) || !std::isfinite(p.y)) __builtin_trap();
  } catch (const std::runtime_error& e) {
    if (std::string(e.what()).rfind(folder(), 0) != 0) __builtin_trap();
  }
  return 0;
}

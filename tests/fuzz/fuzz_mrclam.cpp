// libFuzzer target: any bytes as an MRCLAM dataset folder (sim_host/data/mrclam.hpp import_mrclam, robot 1): the
// input split at its first four form feeds into Barcodes.dat, Landmark_Groundtruth.dat, Robot1_Odometry.dat,
// Robot1_Measurement.dat and Robot1_Groundtruth.dat of a folder of this process's own under /dev/shm. The first byte
// picks --on-error skip or refuse and Dataset 1 (its landmark swap) or 2. A bad row is skipped with FILE:LINE or
// refused naming its file; what was imported reads back finite, stamped in order from 0.
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "data/import_report.hpp"
#include "data/mrclam.hpp"
#include "folder_files.hpp"

namespace {

std::string folder(bool first) {
  const std::string d = "/dev/shm/fuzz_mrclam_" + std::to_string(getpid()) + (first ? "/Dataset1" : "/Dataset2");
  std::filesystem::create_directories(d);
  return d;
}



}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const auto mode = (data[0] & 1) != 0 ? sim::data::OnError::refuse : sim::data::OnError::skip;
  const std::string dir = folder((data[0] & 2) != 0);
  static std::FILE* quiet = std::fopen("/dev/null", "w");
  const char* names[5] = {"Barcodes.dat", "Landmark_Groundtruth.dat", "Robot1_Odometry.dat", "Robot1_Measurement.dat",
                          "Robot1_Groundtruth.dat"};
  fuzz::write_folder(dir, names, 5, data, size, 1);
  const std::string out = dir + "/out.lcmlog";
  sim::data::ImportReport report(mode, quiet, 0);
  sim::data::MrclamImportOptions options;
  options.robots = {1};
  try {
    sim::data::import_mrclam(dir, out, options, report);
    const std::vector<sim::data::MrclamRobotLog> back = sim::data::read_mrclam_log(out, {1});
    if (back.size() != 1u) __builtin_trap();
    std::int64_t last = -1;
    for (const sim::data::MrclamTwist& t : back[0].twists) {
      if (t.t_ns < last || !std::isfinite(t.v) || !std::isfinite(t.w)) __builtin_trap();
      last = t.t_ns;
    }
    for (const auto* s : {&back[0].landmarks, &back[0].robots})
      for (const sim::data::MrclamSighting& m : *s)
        if (m.t_ns < 0 || !std::isfinite(m.range) || !std::isfinite(m.bearing)) __builtin_trap();
  } catch (const std::runtime_error& e) {
    if (std::string(e.what()).rfind(dir, 0) != 0) __builtin_trap();
  }
  return 0;
}

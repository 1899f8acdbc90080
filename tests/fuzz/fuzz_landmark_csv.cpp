// libFuzzer target: any text as a landmark CSV (hal/maps/landmark_file.hpp). Bad input throws with "name:line: "
// or "name: "; what is accepted holds only finite landmarks with distinct signatures, within the map's capacity.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <stdexcept>
#include <string>

#include "est/map/landmark_map.hpp"
#include "hal/maps/landmark_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  static est::LandmarkMapStorage<16> map;
  try {
    hal::maps::parse_landmark_csv(in, "fuzz.csv", map);
    if (map.size() < 1 || map.size() > 16) __builtin_trap();
  } catch (const std::runtime_error& e) {
    if (std::string(e.what()).rfind("fuzz.csv:", 0) != 0) __builtin_trap();
  }
  return 0;
}

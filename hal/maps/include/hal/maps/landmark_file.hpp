#pragma once
// Landmark maps for host programs: a CSV file of landmarks ("x,y,signature" per
// line, metres; blank lines and lines starting with '#' ignored). The line order is the map index a sensor's id
// names. Host only: throws std::runtime_error with the file, the line and the reason.
#include <istream>
#include <string>

#include "est/map/landmark_map.hpp"

namespace hal::maps {

void load_landmark_csv(const std::string& path, est::LandmarkMapBuffer& out);
// The same from a stream; `name` labels the messages (the fuzzer's entry point).
void parse_landmark_csv(std::istream& in, const std::string& name, est::LandmarkMapBuffer& out);

}  // namespace hal::maps

#pragma once
// Landmark maps for host programs: the built-in office's 16 posts, and a CSV file of landmarks ("x,y,signature" per
// line, metres; blank lines and lines starting with '#' ignored). The line order is the map index a sensor's id
// names. Host only: throws std::runtime_error with the file, the line and the reason.
#include <string>

#include "est/map/landmark_map.hpp"

namespace hal::maps {

// The posts of the built-in office (hal/maps/office_map.hpp), signatures 1..16.
void make_office_landmarks(est::LandmarkMapBuffer& out);

void load_landmark_csv(const std::string& path, est::LandmarkMapBuffer& out);

}  // namespace hal::maps

// Landmark map sources (hal/maps/landmark_file.hpp).
#include "hal/maps/landmark_file.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <stdexcept>

namespace hal::maps {

namespace {

const char* to_string(est::MapStatus s) {
  switch (s) {
    case est::MapStatus::nonfinite: return "a coordinate or signature is not finite";
    case est::MapStatus::full: return "more landmarks than the map holds";
    case est::MapStatus::duplicate: return "a signature appears twice";
    default: return "rejected by the landmark map";
  }
}

// Parses one float field ending at ',' or the end; advances p.
bool field(const char*& p, float& out) {
  while (*p == ' ' || *p == '\t') ++p;
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(p, &end);
  if (end == p || errno == ERANGE) return false;
  p = end;
  while (*p == ' ' || *p == '\t' || *p == '\r') ++p;
  if (*p == ',') ++p;
  out = static_cast<float>(v);
  return true;
}

}  // namespace

void load_landmark_csv(const std::string& path, est::LandmarkMapBuffer& out) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open");
  parse_landmark_csv(in, path, out);
}

void parse_landmark_csv(std::istream& in, const std::string& path, est::LandmarkMapBuffer& out) {
  out.clear();
  std::string line;
  int n = 0;
  while (std::getline(in, line)) {
    ++n;
    const std::string where = path + ":" + std::to_string(n) + ": ";
    std::size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    const char* p = line.c_str() + first;
    float v[3] = {0.0f, 0.0f, 0.0f};
    for (float& x : v)
      if (!field(p, x)) throw std::runtime_error(where + "expected x,y,signature (three numbers)");
    if (*p != '\0') throw std::runtime_error(where + "unexpected text after x,y,signature");
    const est::MapStatus s = out.add({v[0], v[1], v[2]});
    if (s != est::MapStatus::ok) throw std::runtime_error(where + to_string(s));
  }
  if (out.size() == 0) throw std::runtime_error(path + ": no landmarks");
}

}  // namespace hal::maps

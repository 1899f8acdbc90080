#include "hal/maps/ros_map_loader.hpp"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <sys/stat.h>

namespace hal::maps {

using est::OccupancyGridBuffer;
using est::MapStatus;

namespace {

[[noreturn]] void fail(const std::string& name, const std::string& why) { throw MapLoadError(name + ": " + why); }

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot open file");
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// PGM header token reader: skips whitespace and '#' comments.
struct Cursor {
  const std::string& s;
  std::size_t i = 0;
  void skip() {
    while (i < s.size()) {
      if (s[i] == '#') {
        while (i < s.size() && s[i] != '\n') ++i;
      } else if (std::isspace(static_cast<unsigned char>(s[i]))) {
        ++i;
      } else {
        break;
      }
    }
  }
  bool integer(long& v) {
    skip();
    const std::size_t start = i;
    while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]))) ++i;
    if (i == start || i - start > 9) return false;
    v = std::strtol(s.substr(start, i - start).c_str(), nullptr, 10);
    return true;
  }
};

std::string trim(const std::string& s) {
  std::size_t a = 0, b = s.size();
  while (a < b && std::isspace(static_cast<unsigned char>(s[a]))) ++a;
  while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1]))) --b;
  return s.substr(a, b - a);
}

std::string unquote(const std::string& s) {
  if (s.size() >= 2 && ((s.front() == '"' && s.back() == '"') || (s.front() == '\'' && s.back() == '\'')))
    return s.substr(1, s.size() - 2);
  return s;
}

double number(const std::string& v, const std::string& key, const std::string& name) {
  const std::string t = trim(v);
  char* end = nullptr;
  const double d = std::strtod(t.c_str(), &end);
  if (t.empty() || end == nullptr || *end != '\0') fail(name, "'" + key + "' is not a number: '" + t + "'");
  if (!std::isfinite(d)) fail(name, "'" + key + "' is not finite");
  return d;
}

bool file_exists(const std::string& p) {
  struct stat st {};
  return ::stat(p.c_str(), &st) == 0;
}

}  // namespace

PgmImage parse_pgm(const std::string& bytes, const std::string& name) {
  if (bytes.size() < 2 || bytes[0] != 'P' || (bytes[1] != '5' && bytes[1] != '2'))
    fail(name, "not a grey PGM (magic P5 or P2 expected)");
  const bool binary = bytes[1] == '5';
  Cursor c{bytes, 2};
  long w = 0, h = 0, maxval = 0;
  if (!c.integer(w) || !c.integer(h) || !c.integer(maxval)) fail(name, "malformed PGM header (width height maxval)");
  if (w <= 0 || h <= 0) fail(name, "PGM width and height must be positive");
  if (w > 16384 || h > 16384) fail(name, "PGM larger than 16384 x 16384");
  if (maxval <= 0 || maxval > 65535) fail(name, "PGM maxval must be in 1..65535");
  PgmImage img;
  img.width = static_cast<std::int32_t>(w);
  img.height = static_cast<std::int32_t>(h);
  img.maxval = static_cast<std::int32_t>(maxval);
  const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  if (binary) {
    // Exactly one whitespace byte separates maxval from the raster.
    if (c.i >= bytes.size() || !std::isspace(static_cast<unsigned char>(bytes[c.i])))
      fail(name, "missing whitespace after PGM maxval");
    ++c.i;
    const std::size_t bpp = maxval > 255 ? 2 : 1;
    const std::size_t need = n * bpp;
    if (bytes.size() - c.i < need)
      fail(name, "truncated PGM raster: " + std::to_string(need) + " bytes expected, " +
                     std::to_string(bytes.size() - c.i) + " present");
    img.pixels.resize(n);  // after the size check: a 20-byte header claiming 16384 x 16384 allocates nothing
    for (std::size_t k = 0; k < n; ++k) {
      const auto b0 = static_cast<unsigned char>(bytes[c.i + k * bpp]);
      unsigned v = b0;
      if (bpp == 2) v = (v << 8) | static_cast<unsigned char>(bytes[c.i + k * bpp + 1]);
      if (v > static_cast<unsigned>(maxval))
        fail(name, "pixel value above maxval at index " + std::to_string(k) + " (byte " +
                       std::to_string(c.i + k * bpp) + ")");
      img.pixels[k] = static_cast<std::uint16_t>(v);
    }
  } else {
    // At least one byte per pixel, checked before the raster is allocated.
    if (bytes.size() - c.i < n)
      fail(name, "truncated or non-numeric P2 raster: " + std::to_string(n) + " pixels expected, " +
                     std::to_string(bytes.size() - c.i) + " bytes present");
    img.pixels.resize(n);
    for (std::size_t k = 0; k < n; ++k) {
      long v = 0;
      if (!c.integer(v))
        fail(name, "truncated or non-numeric P2 raster at pixel " + std::to_string(k) + " (byte " +
                       std::to_string(c.i) + ")");
      if (v > maxval) fail(name, "pixel value above maxval at index " + std::to_string(k));
      img.pixels[k] = static_cast<std::uint16_t>(v);
    }
  }
  return img;
}

PgmImage read_pgm(const std::string& path) { return parse_pgm(read_file(path), path); }

RosMapInfo parse_ros_map_yaml(const std::string& text, const std::string& name) {
  RosMapInfo info;
  bool have_image = false, have_res = false, have_origin = false, have_occ = false, have_free = false;
  std::istringstream in(text);
  std::string line;
  int line_no = 0;
  std::vector<std::string> seen;
  while (std::getline(in, line)) {
    ++line_no;
    const std::string at = name + ":" + std::to_string(line_no);  // the place of what this line holds
    const std::size_t hash = line.find('#');
    if (hash != std::string::npos) line = line.substr(0, hash);
    if (trim(line).empty()) continue;
    const std::size_t colon = line.find(':');
    if (colon == std::string::npos) fail(at, "expected 'key: value'");
    const std::string key = trim(line.substr(0, colon));
    const std::string value = trim(line.substr(colon + 1));
    for (const auto& k : seen)
      if (k == key) fail(at, "duplicate key '" + key + "'");
    seen.push_back(key);
    if (key == "image") {
      info.image = unquote(value);
      if (info.image.empty()) fail(at, "'image' is empty");
      have_image = true;
    } else if (key == "resolution") {
      const double r = number(value, key, at);
      if (!(r > 0.0)) fail(at, "'resolution' must be > 0");
      info.resolution = static_cast<float>(r);
      have_res = true;
    } else if (key == "origin") {
      if (value.size() < 2 || value.front() != '[' || value.back() != ']')
        fail(at, "'origin' must be a list [x, y, yaw]");
      std::vector<double> v;
      std::stringstream ss(value.substr(1, value.size() - 2));
      std::string item;
      while (std::getline(ss, item, ',')) v.push_back(number(item, "origin", at));
      if (v.size() != 3) fail(at, "'origin' must have exactly 3 numbers [x, y, yaw]");
      info.origin_x = static_cast<float>(v[0]);
      info.origin_y = static_cast<float>(v[1]);
      info.origin_yaw = static_cast<float>(v[2]);
      have_origin = true;
    } else if (key == "negate") {
      const double n = number(value, key, at);
      if (n != 0.0 && n != 1.0) fail(at, "'negate' must be 0 or 1");
      info.negate = n == 1.0;
    } else if (key == "occupied_thresh") {
      info.occupied_thresh = number(value, key, at);
      have_occ = true;
    } else if (key == "free_thresh") {
      info.free_thresh = number(value, key, at);
      have_free = true;
    } else if (key == "mode") {
      const std::string m = unquote(value);
      if (m == "trinary") info.mode = MapMode::trinary;
      else if (m == "scale") info.mode = MapMode::scale;
      else if (m == "raw") info.mode = MapMode::raw;
      else fail(at, "unknown 'mode' '" + m + "' (trinary, scale or raw)");
    }
    // Other keys (e.g. a comment-like 'name') are ignored, as map_server does.
  }
  if (!have_image) fail(name, "missing required key 'image'");
  if (!have_res) fail(name, "missing required key 'resolution'");
  if (!have_origin) fail(name, "missing required key 'origin'");
  if (!have_occ) fail(name, "missing required key 'occupied_thresh'");
  if (!have_free) fail(name, "missing required key 'free_thresh'");
  if (info.origin_yaw != 0.0f) fail(name, "origin yaw != 0 is not supported (the grid is axis-aligned)");
  if (!(info.occupied_thresh >= 0.0 && info.occupied_thresh <= 1.0) ||
      !(info.free_thresh >= 0.0 && info.free_thresh <= 1.0))
    fail(name, "thresholds must lie in [0, 1]");
  if (!(info.free_thresh < info.occupied_thresh)) fail(name, "free_thresh must be below occupied_thresh");
  return info;
}

void image_to_grid(const PgmImage& img, const RosMapInfo& info, OccupancyGridBuffer& out, const std::string& name) {
  const MapStatus st = out.configure(img.width, img.height, info.resolution, info.origin_x, info.origin_y);
  if (st == MapStatus::too_large)
    fail(name, "map " + std::to_string(img.width) + " x " + std::to_string(img.height) +
                   " exceeds the grid capacity " + std::to_string(out.capacity_width()) + " x " +
                   std::to_string(out.capacity_height()));
  if (st != MapStatus::ok) fail(name, "grid rejected the map geometry");
  PixelRule rule;
  rule.mode = info.mode;
  rule.negate = info.negate;
  rule.occupied_thresh = info.occupied_thresh;
  rule.free_thresh = info.free_thresh;
  rule.maxval = static_cast<std::uint32_t>(img.maxval);
  for (std::int32_t r = 0; r < img.height; ++r) {
    const std::int32_t cy = ros_map_grid_row(r, img.height);
    for (std::int32_t cx = 0; cx < img.width; ++cx) {
      const std::uint16_t v = img.pixels[static_cast<std::size_t>(r) * static_cast<std::size_t>(img.width) +
                                         static_cast<std::size_t>(cx)];
      const std::uint8_t cell = ros_map_cell(v, rule);
      out.set(cx, cy, cell);
    }
  }
}

RosMapInfo load_ros_map(const std::string& yaml_path, OccupancyGridBuffer& out) {
  RosMapInfo info = parse_ros_map_yaml(read_file(yaml_path), yaml_path);
  if (!info.image.empty() && info.image.front() == '/') {
    info.image_path = info.image;
  } else {
    const std::size_t slash = yaml_path.find_last_of('/');
    info.image_path = (slash == std::string::npos ? std::string() : yaml_path.substr(0, slash + 1)) + info.image;
  }
  const std::size_t dot = info.image_path.find_last_of('.');
  const std::string ext = dot == std::string::npos ? std::string() : info.image_path.substr(dot);
  if (ext != ".pgm" && ext != ".PGM")
    fail(yaml_path, "image '" + info.image + "' is not a .pgm (only PGM P5/P2 images are supported)");
  image_to_grid(read_pgm(info.image_path), info, out, info.image_path);
  return info;
}

void load_trinary_pgm_map(const std::string& pgm_path, OccupancyGridBuffer& out, float resolution, float origin_x,
                          float origin_y) {
  RosMapInfo info;
  info.image = pgm_path;
  info.image_path = pgm_path;
  info.resolution = resolution;
  info.origin_x = origin_x;
  info.origin_y = origin_y;
  if (!(resolution > 0.0f) || !std::isfinite(resolution)) fail(pgm_path, "resolution must be > 0");
  image_to_grid(read_pgm(pgm_path), info, out, pgm_path);
}

std::string shared_datasets_dir() {
  if (const char* env = std::getenv("EST_SHARED_DIR")) {
    const std::string d = std::string(env) + "/datasets";
    if (file_exists(d)) return d;
  }
  if (file_exists("../shared/datasets")) return "../shared/datasets";
  return {};
}

}  // namespace hal::maps

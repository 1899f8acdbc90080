// ROS map_server maps on the board (board_ros_map.hpp).
#include "board_ros_map.hpp"

#include <cstddef>

#include "decimal.hpp"
#include "hal/maps/ros_map_cell.hpp"
#include "semihosting_file.hpp"

namespace board {
namespace {

constexpr std::size_t kMaxPath = 256;
constexpr std::size_t kMaxKeys = 16;
constexpr std::size_t kMaxKey = 32;

FileReader g_reader;
std::uint8_t g_cell_of[65536];  // the pixel rule per pixel value 0..maxval

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f'; }

struct Text {
  const char* s;
  std::size_t n;

  Text trimmed() const {
    std::size_t a = 0, b = n;
    while (a < b && is_space(s[a])) ++a;
    while (b > a && is_space(s[b - 1])) --b;
    return {s + a, b - a};
  }
  Text unquoted() const {
    if (n >= 2 && ((s[0] == '"' && s[n - 1] == '"') || (s[0] == '\'' && s[n - 1] == '\''))) return {s + 1, n - 2};
    return *this;
  }
  bool is(const char* word) const {
    std::size_t i = 0;
    for (; i < n; ++i)
      if (word[i] == '\0' || word[i] != s[i]) return false;
    return word[i] == '\0';
  }
  std::size_t find(char c) const {
    for (std::size_t i = 0; i < n; ++i)
      if (s[i] == c) return i;
    return n;
  }
  bool number(double& v) const {
    const Text t = trimmed();
    return parse_decimal(t.s, t.n, v);
  }
};

struct Keys {
  char names[kMaxKeys][kMaxKey] = {};
  std::size_t count = 0;

  // False when `key` was seen before; `full` when there is no room to remember it.
  bool add(Text key, bool& full) {
    full = false;
    for (std::size_t k = 0; k < count; ++k)
      if (key.n < kMaxKey && key.is(names[k])) return false;
    if (count == kMaxKeys || key.n >= kMaxKey) {
      full = true;
      return true;
    }
    for (std::size_t i = 0; i < key.n; ++i) names[count][i] = key.s[i];
    names[count][key.n] = '\0';
    ++count;
    return true;
  }
};

struct YamlMap {
  char image_path[kMaxPath] = {};
  float resolution = 0.0f, origin_x = 0.0f, origin_y = 0.0f, origin_yaw = 0.0f;
  hal::maps::PixelRule rule;
};

MapError fail(MapLoadResult& r, MapError e, std::uint32_t line = 0) {
  r.error = e;
  r.yaml_line = line;
  return e;
}

// The image path against the YAML's folder, as the host loader resolves it.
bool resolve_image(const char* yaml_path, Text image, char (&out)[kMaxPath]) {
  std::size_t folder = 0;
  if (!(image.n > 0 && image.s[0] == '/'))
    for (std::size_t i = 0; yaml_path[i] != '\0' && i < kMaxPath; ++i)
      if (yaml_path[i] == '/') folder = i + 1;
  if (folder + image.n + 1 > kMaxPath) return false;
  for (std::size_t i = 0; i < folder; ++i) out[i] = yaml_path[i];
  for (std::size_t i = 0; i < image.n; ++i) out[folder + i] = image.s[i];
  out[folder + image.n] = '\0';
  return true;
}

MapError read_yaml(const char* yaml_path, YamlMap& m, MapLoadResult& r) {
  if (!g_reader.open(yaml_path)) return fail(r, MapError::cannot_open_yaml);
  Keys keys;
  bool have_image = false, have_res = false, have_origin = false, have_occ = false, have_free = false;
  const char* raw = nullptr;
  std::size_t raw_n = 0;
  std::uint32_t line_no = 0;
  while (g_reader.next_line(raw, raw_n)) {  // one pass per line of the file
    ++line_no;
    if (g_reader.long_lines() != 0u) return fail(r, MapError::yaml_syntax, line_no);
    Text line{raw, raw_n};
    line.n = line.find('#');
    if (line.trimmed().n == 0) continue;
    const std::size_t colon = line.find(':');
    if (colon == line.n) return fail(r, MapError::yaml_syntax, line_no);
    const Text key = Text{line.s, colon}.trimmed();
    const Text value = Text{line.s + colon + 1, line.n - colon - 1}.trimmed();
    bool full = false;
    if (!keys.add(key, full)) return fail(r, MapError::duplicate_key, line_no);
    double v = 0.0;
    if (key.is("image")) {
      const Text image = value.unquoted();
      if (image.n == 0) return fail(r, MapError::bad_value, line_no);
      const std::size_t dot = [&] {
        std::size_t d = image.n;
        for (std::size_t i = 0; i < image.n; ++i)
          if (image.s[i] == '.') d = i;
        return d;
      }();
      const Text ext{image.s + dot, image.n - dot};
      if (!ext.is(".pgm") && !ext.is(".PGM")) return fail(r, MapError::image_not_pgm, line_no);
      if (!resolve_image(yaml_path, image, m.image_path)) return fail(r, MapError::path_too_long, line_no);
      have_image = true;
    } else if (key.is("resolution")) {
      if (!value.number(v) || !(v > 0.0)) return fail(r, MapError::bad_value, line_no);
      m.resolution = static_cast<float>(v);
      have_res = true;
    } else if (key.is("origin")) {
      if (value.n < 2 || value.s[0] != '[' || value.s[value.n - 1] != ']') return fail(r, MapError::bad_value, line_no);
      const Text list{value.s + 1, value.n - 2};
      float xyz[3] = {};
      std::size_t start = 0, items = 0;
      while (start < list.n && items < 4) {  // at most four items are looked at
        std::size_t end = start;
        while (end < list.n && list.s[end] != ',') ++end;
        if (items < 3) {
          if (!Text{list.s + start, end - start}.number(v)) return fail(r, MapError::bad_value, line_no);
          xyz[items] = static_cast<float>(v);
        }
        ++items;
        start = end + 1;
      }
      if (items != 3) return fail(r, MapError::bad_value, line_no);
      m.origin_x = xyz[0];
      m.origin_y = xyz[1];
      m.origin_yaw = xyz[2];
      have_origin = true;
    } else if (key.is("negate")) {
      if (!value.number(v) || (v != 0.0 && v != 1.0)) return fail(r, MapError::bad_value, line_no);
      m.rule.negate = v == 1.0;
    } else if (key.is("occupied_thresh")) {
      if (!value.number(m.rule.occupied_thresh)) return fail(r, MapError::bad_value, line_no);
      have_occ = true;
    } else if (key.is("free_thresh")) {
      if (!value.number(m.rule.free_thresh)) return fail(r, MapError::bad_value, line_no);
      have_free = true;
    } else if (key.is("mode")) {
      const Text mode = value.unquoted();
      if (mode.is("trinary")) m.rule.mode = hal::maps::MapMode::trinary;
      else if (mode.is("scale")) m.rule.mode = hal::maps::MapMode::scale;
      else if (mode.is("raw")) m.rule.mode = hal::maps::MapMode::raw;
      else return fail(r, MapError::bad_value, line_no);
    } else if (full) {
      return fail(r, MapError::unsupported, line_no);  // an extra key the board cannot check for duplicates
    }
  }
  g_reader.close();
  if (!have_image || !have_res || !have_origin || !have_occ || !have_free) return fail(r, MapError::missing_key);
  if (m.origin_yaw != 0.0f) return fail(r, MapError::unsupported);
  const double occ = m.rule.occupied_thresh, fre = m.rule.free_thresh;
  if (!(occ >= 0.0 && occ <= 1.0) || !(fre >= 0.0 && fre <= 1.0) || !(fre < occ)) return fail(r, MapError::bad_value);
  return MapError::none;
}

// PGM header tokens, whitespace and '#' comments between them (as the host's reader).
class Header {
 public:
  explicit Header(FileReader& f) : f_(f) {}
  bool peek(char& c) {
    if (!have_ && !f_.get(c_)) return false;
    have_ = true;
    c = c_;
    return true;
  }
  void take() { have_ = false; }
  void skip() {
    char c = 0;
    while (peek(c)) {  // each pass consumes a byte
      if (c == '#') {
        while (peek(c) && c != '\n') take();
      } else if (is_space(c)) {
        take();
      } else {
        return;
      }
    }
  }
  bool integer(std::uint32_t& v) {
    skip();
    v = 0;
    int digits = 0;
    char c = 0;
    while (peek(c) && c >= '0' && c <= '9') {
      if (++digits > 9) return false;
      v = v * 10u + static_cast<std::uint32_t>(c - '0');
      take();
    }
    return digits > 0;
  }

 private:
  FileReader& f_;
  char c_ = 0;
  bool have_ = false;
};

MapError read_pgm(const YamlMap& m, est::OccupancyGridBuffer& out, MapLoadResult& r) {
  if (!g_reader.open(m.image_path)) return fail(r, MapError::cannot_open_image);
  Header h(g_reader);
  char p = 0, kind = 0;
  if (!h.peek(p) || p != 'P') return fail(r, MapError::bad_pgm_header);
  h.take();
  if (!h.peek(kind) || (kind != '5' && kind != '2')) return fail(r, MapError::bad_pgm_header);
  h.take();
  if (kind == '2') return fail(r, MapError::unsupported);
  std::uint32_t w = 0, ht = 0, maxval = 0;
  if (!h.integer(w) || !h.integer(ht) || !h.integer(maxval)) return fail(r, MapError::bad_pgm_header);
  if (w == 0 || ht == 0 || w > 16384 || ht > 16384 || maxval == 0 || maxval > 65535)
    return fail(r, MapError::bad_pgm_header);
  char sep = 0;
  if (!h.peek(sep) || !is_space(sep)) return fail(r, MapError::bad_pgm_header);  // exactly one byte, then the raster
  h.take();
  const std::int32_t width = static_cast<std::int32_t>(w), height = static_cast<std::int32_t>(ht);
  if (out.configure(width, height, m.resolution, m.origin_x, m.origin_y) != est::MapStatus::ok)
    return fail(r, MapError::too_large);
  hal::maps::PixelRule rule = m.rule;
  rule.maxval = maxval;
  for (std::uint32_t v = 0; v <= maxval; ++v) g_cell_of[v] = hal::maps::ros_map_cell(v, rule);
  const bool wide = maxval > 255u;
  for (std::int32_t row = 0; row < height; ++row) {
    const std::int32_t cy = hal::maps::ros_map_grid_row(row, height);
    for (std::int32_t cx = 0; cx < width; ++cx) {
      unsigned char b[2] = {0, 0};
      if (g_reader.read(b, wide ? 2u : 1u) != (wide ? 2u : 1u)) return fail(r, MapError::truncated_raster);
      const std::uint32_t v = wide ? (std::uint32_t{b[0]} << 8) | b[1] : b[0];
      if (v > maxval) return fail(r, MapError::pixel_above_maxval);
      out.set(cx, cy, g_cell_of[v]);
    }
  }
  g_reader.close();
  r.width = width;
  r.height = height;
  return MapError::none;
}

}  // namespace

const char* to_string(MapError e) {
  switch (e) {
    case MapError::none: return "none";
    case MapError::cannot_open_yaml: return "cannot_open_yaml";
    case MapError::yaml_syntax: return "yaml_syntax";
    case MapError::duplicate_key: return "duplicate_key";
    case MapError::missing_key: return "missing_key";
    case MapError::bad_value: return "bad_value";
    case MapError::unsupported: return "unsupported";
    case MapError::image_not_pgm: return "image_not_pgm";
    case MapError::path_too_long: return "path_too_long";
    case MapError::cannot_open_image: return "cannot_open_image";
    case MapError::bad_pgm_header: return "bad_pgm_header";
    case MapError::too_large: return "too_large";
    case MapError::truncated_raster: return "truncated_raster";
    case MapError::pixel_above_maxval: return "pixel_above_maxval";
  }
  return "unknown";
}

MapLoadResult load_ros_map(const char* yaml_path, est::OccupancyGridBuffer& out) {
  MapLoadResult r;
  YamlMap m;
  if (read_yaml(yaml_path, m, r) != MapError::none) {
    g_reader.close();
    return r;
  }
  r.resolution = m.resolution;
  r.origin_x = m.origin_x;
  r.origin_y = m.origin_y;
  if (read_pgm(m, out, r) != MapError::none) g_reader.close();
  return r;
}

}  // namespace board

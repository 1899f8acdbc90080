// sim_host import tricycle (data/tricycle.hpp).
#include "data/tricycle.hpp"

#include <est_lcm/encoder_ticks_t.hpp>
#include <est_lcm/ground_truth_t.hpp>
#include <est_lcm/steering_t.hpp>
#include <lcm/lcm-cpp.hpp>

#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "data/channels.hpp"
#include "data/formats.hpp"
#include "data/line_reader.hpp"
#include "hal/lcm/channels.hpp"
#include "hal/lcm/lcm_log_reader.hpp"
#include "node/lcm_log_io.hpp"

namespace sim::data {
namespace {

constexpr std::uint64_t kTractionModulus = 1ull << 32;

const hal::lcm::Channels& channels() {
  static const hal::lcm::Channels c;
  return c;
}

// "#parameter_values: 0.1 0.0106141 1.4 0" after "#parameters: [ Ksteer Ktraction axis_length steer_offset ]",
// "#joints_max_enc_values: 8192 5000", and the laser's "translation: [ x, y, z ]," and "rotation: [ x, y, z, w ]".
struct HeaderParser {
  TricycleHeader h;
  std::vector<std::string> names;
  int found = 0;  // parameters, encoders, translation, rotation

  static std::vector<double> numbers(std::string_view s) {
    std::string t(s);
    for (char& c : t)
      if (c == '[' || c == ']' || c == ',') c = ' ';
    std::vector<double> out;
    for (std::string_view f : split_fields(t)) {
      double v = 0.0;
      if (parse_double(f, v)) out.push_back(v);
    }
    return out;
  }

  void line(std::string_view l) {
    const auto after = [&](std::string_view key) -> std::string_view {
      const std::size_t p = l.find(key);
      return p == std::string_view::npos ? std::string_view() : l.substr(p + key.size());
    };
    if (std::string_view r = after("#parameters:"); !r.empty()) {
      std::string t(r);
      for (char& c : t)
        if (c == '[' || c == ']') c = ' ';
      names.clear();
      for (std::string_view f : split_fields(t)) names.emplace_back(f);
    } else if (std::string_view r2 = after("#parameter_values:"); !r2.empty()) {
      const std::vector<double> v = numbers(r2);
      if (v.size() != names.size()) return;
      for (std::size_t i = 0; i < v.size(); ++i) {
        if (names[i] == "Ksteer") h.guess.ksteer = v[i];
        if (names[i] == "Ktraction") h.guess.ktraction = v[i];
        if (names[i] == "axis_length") h.guess.axis_length = v[i];
        if (names[i] == "steer_offset") h.guess.steer_offset = v[i];
      }
      ++found;
    } else if (std::string_view r3 = after("#joints_max_enc_values:"); !r3.empty()) {
      const std::vector<double> v = numbers(r3);
      // Counts of an encoder's range: at least 2 (steering) and 1 (traction), at most 2^31 (int32 registers).
      constexpr double kMaxCounts = 2147483648.0;
      if (v.size() != 2 || !(v[0] >= 2.0 && v[0] <= kMaxCounts) || !(v[1] >= 1.0 && v[1] <= kMaxCounts)) return;
      h.steer_max = static_cast<std::int64_t>(v[0]);
      h.traction_max = static_cast<std::int64_t>(v[1]);
      ++found;
    } else if (std::string_view r4 = after("translation:"); !r4.empty()) {
      const std::vector<double> v = numbers(r4);
      if (v.size() != 3) return;
      h.guess.laser_x = v[0], h.guess.laser_y = v[1];
      ++found;
    } else if (std::string_view r5 = after("rotation:"); !r5.empty()) {
      const std::vector<double> v = numbers(r5);  // quaternion x, y, z, w: the yaw of a rotation about z
      if (v.size() != 4) return;
      h.guess.laser_theta = 2.0 * std::atan2(v[2], v[3]);
      ++found;
    }
  }
};

// "1668091584.821040869": seconds and nanosecond digits, exactly (a double would lose the nanoseconds).
bool parse_unix_ns(std::string_view f, std::int64_t& out) {
  const std::size_t dot = f.find('.');
  std::int64_t s = 0, frac = 0;
  // Seconds up to 9.2e9 (the year 2262): beyond, nanoseconds overflow an int64.
  if (!parse_int(f.substr(0, dot), s) || s < 0 || s >= std::numeric_limits<std::int64_t>::max() / 1000000000 - 1)
    return false;
  if (dot != std::string_view::npos) {
    std::string_view d = f.substr(dot + 1);
    if (d.empty() || d.size() > 9 || !parse_int(d, frac) || frac < 0 || d.front() == '-' || d.front() == '+')
      return false;
    for (std::size_t k = d.size(); k < 9; ++k) frac *= 10;
  }
  out = s * 1000000000 + frac;
  return true;
}

}  // namespace

double tricycle_steering_angle(std::uint32_t ticks, const TricycleParams& p, std::int64_t steer_max) {
  std::int64_t t = ticks;
  if (t > steer_max / 2) t -= steer_max;
  return p.ksteer * 2.0 * M_PI * static_cast<double>(t) / static_cast<double>(steer_max) + p.steer_offset;
}

TricycleImport import_tricycle(const std::string& file, const std::string& out_log, const TricycleImportOptions& o,
                               ImportReport& report) {
  TricycleImport result;
  LineReader in(file);
  HeaderParser header;
  std::string line;
  bool t0_set = false;
  std::int64_t t0_ns = 0, last_ns = std::numeric_limits<std::int64_t>::min();
  bool have_prev = false;
  std::uint32_t prev_traction = 0;
  node::LogWriter log(out_log);
  const double t_end = o.max_seconds > 0.0 ? o.max_seconds : std::numeric_limits<double>::infinity();
  while (in.next(line)) {
    if (blank_or_comment(line)) {
      if (!t0_set) header.line(line);
      continue;
    }
    if (!t0_set) {  // the header ends at the first record
      result.header = header.h;
      result.header.complete = header.found == 4;
      if (!result.header.complete)
        report.note(file + ": the header does not give every initial guess, encoder range and laser pose; the "
                    "dataset's published values stand in for those missing");
    }
    const auto f = split_fields(line);
    if (f.size() != 13) {
      report.bad_line(file, in.line_number(), "13 fields expected");
      continue;
    }
    if (f[0] != "time:" || f[2] != "ticks:" || f[5] != "model_pose:" || f[9] != "tracker_pose:") {
      report.bad_line(file, in.line_number(), "labels time: ticks: model_pose: tracker_pose: expected");
      continue;
    }
    std::int64_t t_unix_ns = 0, steer = 0, traction = 0;
    double pose[3];
    if (!parse_unix_ns(f[1], t_unix_ns)) {
      report.bad_line(file, in.line_number(), "time is not seconds.nanoseconds (0 .. 9.2e9 s)");
      continue;
    }
    if (!parse_int(f[3], steer) || !parse_int(f[4], traction)) {
      report.bad_line(file, in.line_number(), "encoder ticks are not integers");
      continue;
    }
    bool numbers = true;
    for (int k = 0; k < 3; ++k) numbers = numbers && parse_double(f[static_cast<std::size_t>(10 + k)], pose[k]);
    // The log stores floats: a pose beyond a float's range is not a pose.
    for (int k = 0; k < 3; ++k) numbers = numbers && std::fabs(pose[k]) <= 1e30;
    if (!numbers) {
      report.bad_line(file, in.line_number(), "a tracker pose field is not a finite number (of a float's range)");
      continue;
    }
    if (steer < 0 || steer >= result.header.steer_max) {
      report.bad_line(file, in.line_number(), "steering ticks outside the encoder's range");
      continue;
    }
    if (traction < 0 || static_cast<std::uint64_t>(traction) >= kTractionModulus) {
      report.bad_line(file, in.line_number(), "traction ticks outside uint32");
      continue;
    }
    if (t_unix_ns <= last_ns) {
      report.bad_line(file, in.line_number(), "time not after the previous record's");
      continue;
    }
    last_ns = t_unix_ns;
    if (!t0_set) {
      t0_set = true;
      t0_ns = t_unix_ns;
      result.t0_unix_s = static_cast<double>(t_unix_ns) * 1e-9;
    }
    const std::int64_t t_ns = t_unix_ns - t0_ns;
    if (static_cast<double>(t_ns) * 1e-9 > t_end) break;
    const auto tr = static_cast<std::uint32_t>(traction);
    if (have_prev) {
      const std::int64_t d = traction_increment(prev_traction, tr);
      if ((d > 0 && tr < prev_traction) || (d < 0 && tr > prev_traction)) {
        ++result.traction_wraps;
        report.note(file + ":" + std::to_string(in.line_number()) + ": the traction counter wrapped around 2^32 (" +
                    std::to_string(prev_traction) + " -> " + std::to_string(tr) + ", an increment of " +
                    std::to_string(d) + " ticks); increments are taken modulo 2^32");
      }
    }
    have_prev = true;
    prev_traction = tr;

    est_lcm::encoder_ticks_t wheel;
    wheel.num_wheels = 1;
    wheel.stamp_ns = t_ns;
    wheel.counter_bits = 32;
    wheel.count.push_back(static_cast<std::int32_t>(tr));
    log.write(channels().wheel_ticks, t_ns, wheel);
    est_lcm::encoder_ticks_t steer_raw;
    steer_raw.num_wheels = 1;
    steer_raw.stamp_ns = t_ns;
    steer_raw.counter_bits = 13;
    steer_raw.count.push_back(static_cast<std::int32_t>(steer));
    log.write(kSteeringTicksChannel, t_ns, steer_raw);
    est_lcm::steering_t angle;
    angle.stamp_ns = t_ns;
    angle.angle_rad = static_cast<float>(tricycle_steering_angle(static_cast<std::uint32_t>(steer),
                                                                 o.calibrated ? o.params : result.header.guess,
                                                                 result.header.steer_max));
    log.write(channels().steering, t_ns, angle);
    est_lcm::ground_truth_t g;
    g.stamp_ns = t_ns;
    g.x_m = static_cast<float>(pose[0]);
    g.y_m = static_cast<float>(pose[1]);
    g.theta_rad = static_cast<float>(pose[2]);
    g.v_mps = 0.0f;
    g.omega_rps = 0.0f;
    log.write(kGroundTruthChannel, t_ns, g);
    ++result.records;
    result.duration_s = static_cast<double>(t_ns) * 1e-9;
  }
  if (result.records == 0) throw std::runtime_error(file + ": no tricycle record");
  report.count("records (traction ticks, steering, tracked pose)", result.records);
  if (log.failures() != 0)
    throw std::runtime_error(out_log + ": " + std::to_string(log.failures()) + " events not written");
  result.events = log.events();
  return result;
}

std::vector<TricycleRecord> read_tricycle_log(const std::string& path) {
  std::vector<TricycleRecord> out;
  // The importer writes the four messages of a record with one stamp, the traction ticks first.
  TricycleRecord r;
  int have = 0;
  hal::lcm::read_lcm_log(path, "sim_host: warning", stderr, [&](const hal::lcm::LcmLogEvent& e) {
    const std::string& ch = e.channel;
    if (ch == channels().wheel_ticks || ch == kSteeringTicksChannel) {
      est_lcm::encoder_ticks_t m;
      if (m.decode(e.data.data(), 0, e.size()) < 0 || m.num_wheels < 1) throw std::runtime_error(path + ": bad ticks");
      if (ch == channels().wheel_ticks) {
        r = TricycleRecord{};
        r.t_ns = m.stamp_ns;
        r.traction_ticks = static_cast<std::uint32_t>(m.count[0]);
        have = 1;
      } else if (have == 1 && m.stamp_ns == r.t_ns) {
        r.steer_ticks = static_cast<std::uint32_t>(m.count[0]);
        have = 2;
      }
    } else if (ch == kGroundTruthChannel && have == 2) {
      est_lcm::ground_truth_t g;
      if (g.decode(e.data.data(), 0, e.size()) < 0) throw std::runtime_error(path + ": bad ground_truth_t");
      if (g.stamp_ns != r.t_ns) return;
      r.tracker = {g.stamp_ns, g.x_m, g.y_m, g.theta_rad};
      out.push_back(r);
      have = 0;
    }
  });
  return out;
}

}  // namespace sim::data

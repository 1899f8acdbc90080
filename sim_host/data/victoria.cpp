// sim_host import victoria (data/victoria.hpp).
#include "data/victoria.hpp"

#include <est_lcm/encoder_ticks_t.hpp>
#include <est_lcm/ground_truth_t.hpp>
#include <est_lcm/landmark_sighting_t.hpp>
#include <est_lcm/steering_t.hpp>
#include <lcm/lcm-cpp.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <stdexcept>

#include "data/channels.hpp"
#include "data/event_buffer.hpp"
#include "data/formats.hpp"
#include "data/line_reader.hpp"
#include "hal/lcm/channels.hpp"
#include "hal/lcm/lcm_log_reader.hpp"

namespace sim::data {
namespace {

namespace fs = std::filesystem;

constexpr double kMaxSteer = 1.2;  // rad: beyond any car's stop (the data stays within 0.6)
constexpr double kMaxTime = 1e9;   // s from the start: nanosecond stamps fit an int64 to 9.2e9 s
constexpr double kMaxSpeed = 100.0;           // m/s (the data stays within 6)
constexpr double kMaxGps = 1e7;               // m from the local origin (the fixes are within 300 m)
constexpr std::size_t kMaxTrees = 32767;      // detections at one scan time: landmark_sighting_t counts them in int16

const hal::lcm::Channels& channels() {
  static const hal::lcm::Channels c;
  return c;
}

using Rows = NumericRows;

// The numeric rows of one file with their line numbers, times never going back; malformed lines to the report.
Rows read_rows(const std::string& path, std::size_t fields, ImportReport& report) {
  return read_numeric_rows(path, fields, report, '%', true);
}

std::int64_t stamp(double t) { return static_cast<std::int64_t>(std::llround(t * 1e9)); }

std::string find_folder(const std::string& dir) {
  for (const fs::path& d : {fs::path(dir), fs::path(dir) / "acfr-text-rfsslam"})
    if (fs::exists(d / "inputs.dat") && fs::exists(d / "measurements.dat") && fs::exists(d / "gps.dat"))
      return d.string();
  throw std::runtime_error(dir + ": not a Victoria Park folder (inputs.dat, measurements.dat, gps.dat missing, "
                           "here and in acfr-text-rfsslam/)");
}

}  // namespace

double victoria_front_speed(double v_e, double steer, const VictoriaGeometry& g) {
  return v_e / ((1.0 - std::tan(steer) * g.encoder_offset / g.wheelbase) * std::cos(steer));
}

VictoriaImport import_victoria(const std::string& dir, const std::string& out_log, const VictoriaImportOptions& o,
                               ImportReport& report) {
  VictoriaImport result;
  result.folder = find_folder(dir);
  const VictoriaGeometry& g = o.geometry;
  if (!(o.metres_per_tick > 0.0)) throw std::invalid_argument("metres per tick must be positive");
  const Rows inputs = read_rows((fs::path(result.folder) / "inputs.dat").string(), 3, report);
  const Rows trees = read_rows((fs::path(result.folder) / "measurements.dat").string(), 4, report);
  const Rows gps = read_rows((fs::path(result.folder) / "gps.dat").string(), 3, report);
  const double t_end = o.max_seconds > 0.0 ? o.max_seconds : std::numeric_limits<double>::infinity();
  EventBuffer events;  // order at equal stamps: ticks 0, steering 1, GPS 2, trees 3

  // Speed and steering: the front axle's travel integrated over each row's interval (the row's speed held until the
  // next), as a counter; the ticks at a row's time come before its steering, so that the interval that ends there
  // is paired with the steering that held over it.
  double travel_m = 0.0;
  std::int64_t count = 0;
  std::uint64_t long_gaps = 0;
  for (std::size_t k = 0; k < inputs.values.size(); ++k) {
    const auto& v = inputs.values[k];
    if (v[0] > t_end) break;
    if (v[0] < 0.0 || v[0] > kMaxTime) {
      report.bad_line(inputs.path, inputs.lines[k], "time outside 0 .. 1e9 s");
      continue;
    }
    if (std::fabs(v[1]) > kMaxSpeed) {
      report.bad_line(inputs.path, inputs.lines[k], "speed beyond 100 m/s");
      continue;
    }
    if (std::fabs(v[2]) > kMaxSteer) {
      report.bad_line(inputs.path, inputs.lines[k], "steering beyond 1.2 rad");
      continue;
    }
    est_lcm::encoder_ticks_t ticks;
    ticks.num_wheels = 1;
    ticks.stamp_ns = stamp(v[0]);
    ticks.counter_bits = 32;
    ticks.count.push_back(static_cast<std::int32_t>(static_cast<std::uint32_t>(count)));
    events.add(ticks.stamp_ns, 0, channels().wheel_ticks, ticks);
    est_lcm::steering_t steer;
    steer.stamp_ns = ticks.stamp_ns;
    steer.angle_rad = static_cast<float>(v[2]);
    events.add(steer.stamp_ns, 1, channels().steering, steer);
    report.count("speed and steering samples");
    ++result.inputs;
    if (k + 1 < inputs.values.size()) {
      const double dt = inputs.values[k + 1][0] - v[0];
      if (dt > 0.5) ++long_gaps;
      travel_m += victoria_front_speed(v[1], v[2], g) * dt;
      count = static_cast<std::int64_t>(std::llround(travel_m / o.metres_per_tick));
    }
  }
  if (long_gaps > 0)
    report.note(std::to_string(long_gaps) + " gaps of more than 0.5 s between speed samples: the speed before each "
                "is held over it");
  report.note("speed: the rear left wheel's encoder as the front axle middle's speed, v_e / ((1 - tan(steer) H / L) "
              "cos(steer)), L = " + fixed(g.wheelbase, 2) + " m, H = " + fixed(g.encoder_offset, 2) + " m; trees: "
              "from the laser (a = " + fixed(g.laser_ahead, 2) + " m ahead of the front axle, b = " +
              fixed(g.laser_left, 2) + " m left) to the front axle's middle");

  // Trees: the rows of one scan time become one sighting.
  std::vector<float> range, bearing, diameter;
  std::int64_t scan_t = std::numeric_limits<std::int64_t>::min();
  const auto flush = [&] {
    if (range.empty()) return;
    est_lcm::landmark_sighting_t m;
    m.stamp_ns = scan_t;
    m.num_features = static_cast<std::int16_t>(range.size());
    m.range_m = range;
    m.bearing_rad = bearing;
    m.signature = diameter;
    m.id.assign(range.size(), -1);
    events.add(scan_t, 3, channels().landmarks, m);
    ++result.scans;
    range.clear(), bearing.clear(), diameter.clear();
  };
  for (std::size_t k = 0; k < trees.values.size(); ++k) {
    const auto& v = trees.values[k];
    if (v[0] > t_end) break;
    if (v[0] < 0.0 || v[0] > kMaxTime) {
      report.bad_line(trees.path, trees.lines[k], "time outside 0 .. 1e9 s");
      continue;
    }
    if (!(v[1] > 0.0) || v[1] > 100.0) {
      report.bad_line(trees.path, trees.lines[k], "range outside (0, 100] m");
      continue;
    }
    if (v[2] < -1e-6 || v[2] > M_PI + 1e-6) {
      report.bad_line(trees.path, trees.lines[k], "beam angle outside [0, pi]");
      continue;
    }
    if (!(v[3] >= 0.0) || v[3] > 100.0) {
      report.bad_line(trees.path, trees.lines[k], "diameter outside [0, 100] m");
      continue;
    }
    const std::int64_t t = stamp(v[0]);
    if (t != scan_t) flush();
    if (range.size() == kMaxTrees) {
      report.bad_line(trees.path, trees.lines[k], "more than 32767 detections at one time");
      continue;
    }
    scan_t = t;
    const double phi = v[2] - M_PI / 2.0;  // in the laser's frame, counter-clockwise from ahead
    const double x = g.laser_ahead + v[1] * std::cos(phi), y = g.laser_left + v[1] * std::sin(phi);
    range.push_back(static_cast<float>(std::hypot(x, y)));
    bearing.push_back(static_cast<float>(std::atan2(y, x)));
    diameter.push_back(static_cast<float>(v[3]));
    report.count("tree detections");
    ++result.detections;
  }
  flush();
  report.count("laser scans with trees", result.scans);

  for (std::size_t k = 0; k < gps.values.size(); ++k) {
    const auto& v = gps.values[k];
    if (v[0] > t_end) break;
    if (v[0] < 0.0 || v[0] > kMaxTime) {
      report.bad_line(gps.path, gps.lines[k], "time outside 0 .. 1e9 s");
      continue;
    }
    if (std::fabs(v[1]) > kMaxGps || std::fabs(v[2]) > kMaxGps) {
      report.bad_line(gps.path, gps.lines[k], "position beyond 1e7 m");
      continue;
    }
    est_lcm::ground_truth_t fix;
    fix.stamp_ns = stamp(v[0]);
    fix.x_m = static_cast<float>(v[1]);
    fix.y_m = static_cast<float>(v[2]);
    fix.theta_rad = std::numeric_limits<float>::quiet_NaN();
    fix.v_mps = 0.0f;
    fix.omega_rps = 0.0f;
    events.add(fix.stamp_ns, 2, kGpsChannel, fix);
    report.count("GPS fixes");
    ++result.gps;
  }

  if (result.inputs == 0)
    throw std::runtime_error(result.folder + ": no speed and steering sample imported from inputs.dat");
  result.duration_s = static_cast<double>(events.last_ns()) * 1e-9;
  result.events = events.write_sorted(out_log);
  return result;
}

VictoriaLog read_victoria_log(const std::string& path) {
  VictoriaLog out;
  hal::lcm::read_lcm_log(path, "sim_host: warning", stderr, [&](const hal::lcm::LcmLogEvent& e) {
    if (e.channel == channels().wheel_ticks) {
      est_lcm::encoder_ticks_t m;
      if (m.decode(e.data.data(), 0, e.size()) < 0 || m.num_wheels < 1) throw std::runtime_error(path + ": bad ticks");
      out.ticks.push_back({m.stamp_ns, static_cast<std::uint32_t>(m.count[0])});
    } else if (e.channel == channels().steering) {
      est_lcm::steering_t m;
      if (m.decode(e.data.data(), 0, e.size()) < 0) throw std::runtime_error(path + ": bad steering_t");
      out.steering.push_back({m.stamp_ns, m.angle_rad});
    } else if (e.channel == channels().landmarks) {
      est_lcm::landmark_sighting_t m;
      if (m.decode(e.data.data(), 0, e.size()) < 0) throw std::runtime_error(path + ": bad landmark_sighting_t");
      VictoriaScan s;
      s.t_ns = m.stamp_ns;
      for (std::size_t i = 0; i < static_cast<std::size_t>(m.num_features); ++i)
        s.trees.push_back({m.range_m[i], m.bearing_rad[i], m.signature[i]});
      out.scans.push_back(std::move(s));
    } else if (e.channel == kGpsChannel) {
      est_lcm::ground_truth_t g;
      if (g.decode(e.data.data(), 0, e.size()) < 0) throw std::runtime_error(path + ": bad ground_truth_t");
      out.gps.push_back({g.stamp_ns, g.x_m, g.y_m, 0.0});
    }
  });
  return out;
}

}  // namespace sim::data

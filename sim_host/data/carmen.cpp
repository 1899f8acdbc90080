// sim_host import carmen (data/carmen.hpp).
#include "data/carmen.hpp"

#include <est_lcm/ground_truth_t.hpp>
#include <est_lcm/odometry_t.hpp>
#include <est_lcm/range_scan_t.hpp>
#include <lcm/lcm-cpp.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <stdexcept>

#include "data/channels.hpp"
#include "data/formats.hpp"
#include "data/line_reader.hpp"
#include "hal/lcm/lcm_log_reader.hpp"
#include "hal/sensors/range_scan/lcm.hpp"
#include "node/lcm_log_io.hpp"

namespace sim::data {
namespace {

namespace fs = std::filesystem;


struct Pose {
  double x = 0.0, y = 0.0, theta = 0.0;
};
Pose compose(const Pose& a, const Pose& b) {
  const double c = std::cos(a.theta), s = std::sin(a.theta);
  return {a.x + c * b.x - s * b.y, a.y + s * b.x + c * b.y, wrap_angle(a.theta + b.theta)};
}
Pose between(const Pose& a, const Pose& b) {  // a^-1 (+) b
  const double c = std::cos(a.theta), s = std::sin(a.theta);
  const double dx = b.x - a.x, dy = b.y - a.y;
  return {c * dx + s * dy, -s * dx + c * dy, wrap_angle(b.theta - a.theta)};
}

std::int64_t to_ns(double t_s) { return static_cast<std::int64_t>(std::llround(t_s * 1e9)); }
constexpr double kMaxStamp = 9e9;    // s: nanosecond stamps fit an int64 to 9.2e9 s (the year 2262)
constexpr double kMaxBridge = 60.0;  // s: a longer pause in the odometry is left to the HAL's gap limit

// One ODOM line, or a scan, in line order, before the stamps are repaired.
struct Entry {
  bool scan = false;
  double t = 0.0;
  Pose odom;  // ODOM: the pose as printed
  bool reset = false;
  std::size_t scan_index = 0;
  std::uint64_t line = 0;
};

bool parse_all(const std::vector<std::string_view>& f, std::size_t from, std::size_t n, double* out) {
  for (std::size_t i = 0; i < n; ++i)
    if (!parse_double(f[from + i], out[i])) return false;
  return true;
}

// CARMEN's bearing convention for the old FLASER message: 180 degrees over n beams (n = 180, 360) or n - 1 (181, 361).
float flaser_increment(std::size_t n) {
  const double fov = M_PI;
  return static_cast<float>(n % 2 == 1 ? fov / static_cast<double>(n - 1) : fov / static_cast<double>(n));
}

std::string site_of(const std::string& path) {
  std::string name = fs::path(path).filename().string();
  for (const char* suffix : {".gz", ".log", ".clf", "-corrected"})
    if (name.size() > std::strlen(suffix) && name.compare(name.size() - std::strlen(suffix), std::strlen(suffix),
                                                          suffix) == 0)
      name.resize(name.size() - std::strlen(suffix));
  return name;
}

}  // namespace

CarmenData parse_carmen(const std::string& path, const CarmenImportOptions& o, ImportReport& report) {
  CarmenData data;
  data.path = path;
  LineReader in(path);
  std::vector<Entry> entries;
  std::map<std::string, std::uint64_t> other;
  double front_offset = 0.0;
  bool mount_from_robotlaser = false;
  double largest = 0.0;
  std::string line;
  while (in.next(line)) {
    if (blank_or_comment(line)) continue;
    const auto f = split_fields(line);
    const std::string type(f[0]);
    const std::uint64_t ln = in.line_number();
    if (type == "ODOM") {
      // ODOM x y theta tv rv accel timestamp host logger_timestamp
      double v[7];
      if (f.size() != 10) {
        report.bad_line(path, ln, "ODOM: 10 fields expected");
        continue;
      }
      if (!parse_all(f, 1, 7, v)) {
        report.bad_line(path, ln, "ODOM: a field is not a finite number");
        continue;
      }
      if (v[6] < 0.0 || v[6] > kMaxStamp) {
        report.bad_line(path, ln, "ODOM: timestamp outside 0 .. 9e9 s");
        continue;
      }
      Entry e;
      e.t = v[6];
      e.odom = {v[0], v[1], v[2]};
      // The line right after a scan holding the scan's corrected pose: its stamp is 0, or garbage (1e-42 in intel).
      if (!entries.empty() && entries.back().scan) {
        const TimedPose& c = data.scans[entries.back().scan_index].reference;
        e.reset = v[6] == 0.0 || (std::fabs(c.x - v[0]) < 1e-6 && std::fabs(c.y - v[1]) < 1e-6 &&
                                  std::fabs(wrap_angle(c.theta - v[2])) < 1e-6);
      }
      e.line = ln;
      entries.push_back(e);
      report.count("ODOM lines");
    } else if (type == "FLASER" || type == "ROBOTLASER1") {
      CarmenScan s;
      s.line = ln;
      std::size_t n = 0, pose_at = 0;
      std::int64_t count = 0;
      if (type == "FLASER") {
        // FLASER n r_1 .. r_n x y theta odom_x odom_y odom_theta timestamp host logger_timestamp
        if (f.size() < 2 || !parse_int(f[1], count) || count <= 0 || f.size() != static_cast<std::size_t>(count) + 11) {
          report.bad_line(path, ln, "FLASER: the field count does not match its beam count");
          continue;
        }
        if (count < 2) {  // one beam spans no angle: its increment (180 deg over n - 1) is undefined
          report.bad_line(path, ln, "FLASER: fewer than 2 beams");
          continue;
        }
        n = static_cast<std::size_t>(count);
        pose_at = 2 + n;
        s.geometry.angle_min_rad = static_cast<float>(-M_PI / 2.0);
        s.geometry.angle_increment_rad = flaser_increment(n);
      } else {
        // ROBOTLASER1 type start_angle fov resolution max_range accuracy remission_mode n r_1..r_n m rem_1..rem_m
        //   laser_x laser_y laser_theta robot_x robot_y robot_theta tv rv forward_safety side_safety turn_axis
        //   timestamp host logger_timestamp
        std::int64_t m = 0;
        double g[6];
        if (f.size() < 10 || !parse_int(f[8], count) || count <= 0 || f.size() < 10 + static_cast<std::size_t>(count) ||
            !parse_int(f[9 + static_cast<std::size_t>(count)], m) || m < 0 ||
            f.size() != static_cast<std::size_t>(count + m) + 24) {
          report.bad_line(path, ln, "ROBOTLASER1: the field count does not match its beam and remission counts");
          continue;
        }
        if (!parse_all(f, 2, 6, g)) {
          report.bad_line(path, ln, "ROBOTLASER1: a field is not a finite number");
          continue;
        }
        n = static_cast<std::size_t>(count);
        pose_at = 10 + n + static_cast<std::size_t>(m);
        s.geometry.angle_min_rad = static_cast<float>(g[0]);
        s.geometry.angle_increment_rad = static_cast<float>(g[2]);
        s.geometry.range_max_m = static_cast<float>(g[3]);
        // A finite double can still overflow the float of the scan's geometry.
        if (!std::isfinite(s.geometry.angle_min_rad) || !std::isfinite(s.geometry.angle_increment_rad) ||
            !std::isfinite(s.geometry.range_max_m)) {
          report.bad_line(path, ln, "ROBOTLASER1: an angle or the maximum range does not fit a float");
          continue;
        }
      }
      s.ranges.resize(n);
      bool ok = true;
      for (std::size_t i = 0; i < n && ok; ++i) {
        double r = 0.0;
        ok = parse_double(f[2 + i + (type == "FLASER" ? 0 : 7)], r);
        s.ranges[i] = static_cast<float>(r);
      }
      double p[6];
      const std::size_t t_at = type == "FLASER" ? pose_at + 6 : pose_at + 11;
      double t = 0.0;
      if (!ok || !parse_all(f, pose_at, 6, p) || !parse_double(f[t_at], t)) {
        report.bad_line(path, ln, type + ": a field is not a finite number");
        continue;
      }
      if (t < 0.0 || t > kMaxStamp) {
        report.bad_line(path, ln, type + ": timestamp outside 0 .. 9e9 s");
        continue;
      }
      // FLASER: laser pose = odometry pose = the corrected pose in these logs; ROBOTLASER1: the robot pose.
      const Pose robot = type == "FLASER" ? Pose{p[0], p[1], p[2]} : Pose{p[3], p[4], p[5]};
      if (type == "ROBOTLASER1" && !mount_from_robotlaser) {
        const Pose m = between(robot, {p[0], p[1], p[2]});
        data.mount = {static_cast<float>(m.x), static_cast<float>(m.y), static_cast<float>(m.theta)};
        mount_from_robotlaser = true;
      }
      s.t_ns = to_ns(t);
      s.reference = {s.t_ns, robot.x, robot.y, robot.theta};
      for (float r : s.ranges) largest = std::max(largest, static_cast<double>(r));
      Entry e;
      e.scan = true;
      e.t = t;
      e.scan_index = data.scans.size();
      e.line = ln;
      entries.push_back(e);
      data.scans.push_back(std::move(s));
      report.count("scans (" + type + ")");
    } else if (type == "PARAM") {
      if (f.size() >= 3 && f[1] == "robot_frontlaser_offset" && !parse_double(f[2], front_offset))
        report.bad_line(path, ln, "PARAM robot_frontlaser_offset: not a number");
      report.count("PARAM lines (robot parameters)");
    } else if (type == "NEFF") {
      report.count("NEFF lines (GMapping diagnostics, not used)");
    } else {
      report.count(type + " lines (not used)");
    }
  }
  if (data.scans.empty()) throw std::runtime_error(path + ": no FLASER or ROBOTLASER1 scan");
  if (!mount_from_robotlaser) data.mount = {static_cast<float>(front_offset), 0.0f, 0.0f};

  // Max-range readings: the log's largest reading is the laser's "no return" code.
  const double no_return = o.no_return_m > 0.0 ? o.no_return_m : largest;
  for (CarmenScan& s : data.scans) {
    if (!(s.geometry.range_max_m > 0.0f)) s.geometry.range_max_m = static_cast<float>(no_return);
    s.geometry.range_min_m = static_cast<float>(o.range_min_m);
  }

  // Stamps: the line order is the truth (GMapping wrote the lines as it processed them). The scans' stamps mostly
  // increase: the longest run of them that does keeps its stamps, the others are re-timed between their kept
  // neighbours. The ODOM stamps are often bunched (three lines within 2 ms turning 0.1 rad each), step back, or are
  // garbage (1e-42): between two scans, the ODOM lines keep their stamps when these increase, lie within the scans'
  // interval and give a plausible motion (at most kMaxSpeed and kMaxTurnRate); otherwise the lines of that interval
  // are spread evenly over it, in line order. The motion between two scans is the same either way, and so is what
  // MCL sees at the scans.
  constexpr double kMaxSpeed = 2.0, kMaxTurnRate = 4.0;  // m/s, rad/s: twice what these robots do
  const std::size_t ne = entries.size();
  std::uint64_t retimed_scans = 0, retimed_odom = 0, retimed_intervals = 0, intervals = 0;
  {
    std::vector<std::size_t> scans;
    for (std::size_t k = 0; k < ne; ++k)
      if (entries[k].scan) scans.push_back(k);
    std::vector<std::size_t> tails, parent(scans.size(), SIZE_MAX);  // patience sorting: the longest increasing run
    for (std::size_t i = 0; i < scans.size(); ++i) {
      const double t = entries[scans[i]].t;
      if (!(t > 0.0)) continue;
      const auto pos = std::lower_bound(tails.begin(), tails.end(), t,
                                        [&](std::size_t q, double v) { return entries[scans[q]].t < v; });
      if (pos != tails.begin()) parent[i] = *(pos - 1);
      if (pos == tails.end()) tails.push_back(i);
      else *pos = i;
    }
    std::vector<bool> kept(scans.size(), false);
    for (std::size_t i = tails.empty() ? SIZE_MAX : tails.back(); i != SIZE_MAX; i = parent[i]) kept[i] = true;
    for (std::size_t i = 0; i < scans.size(); ++i) {
      if (kept[i]) continue;
      std::size_t a = i, b = i;
      while (a > 0 && !kept[a]) --a;
      while (b < scans.size() && !kept[b]) ++b;
      const bool has_a = kept[a], has_b = b < scans.size();
      const double step = 3.0;  // s per scan where only one side is known
      const double n = static_cast<double>(b - (has_a ? a : i - 1));
      const double ta = has_a ? entries[scans[a]].t : (has_b ? entries[scans[b]].t - step * n : 0.0);
      const double tb = has_b ? entries[scans[b]].t : ta + step * n;
      entries[scans[i]].t = ta + (tb - ta) * static_cast<double>(i - (has_a ? a : i - 1)) / n;
      CarmenScan& sc = data.scans[entries[scans[i]].scan_index];
      sc.t_ns = to_ns(entries[scans[i]].t);
      sc.reference.t_ns = sc.t_ns;
      ++retimed_scans;
    }
  }
  {
    // Interval by interval: the ODOM lines after scan k-1 (from its reset pose on) up to scan k.
    std::size_t k = 0;
    double t_prev = -std::numeric_limits<double>::infinity();
    Pose pose_prev;
    bool have_pose = false;
    while (k < ne) {
      std::vector<std::size_t> lines;
      std::size_t j = k;
      for (; j < ne && !entries[j].scan; ++j)
        if (!entries[j].reset) lines.push_back(j);
      const bool closed = j < ne;  // ends at a scan
      const double t_scan = closed ? entries[j].t : std::numeric_limits<double>::infinity();
      bool ok = true;
      double t = t_prev;
      Pose p = pose_prev;
      bool hp = have_pose;
      for (std::size_t q : lines) {
        const Entry& e = entries[q];
        if (!(e.t > t) || e.t > t_scan || !(e.t > 0.0)) {
          ok = false;
          break;
        }
        if (hp && std::isfinite(t)) {
          const Pose inc = between(p, e.odom);
          const double dt = e.t - t;
          if (std::hypot(inc.x, inc.y) > kMaxSpeed * dt || std::fabs(inc.theta) > kMaxTurnRate * dt) {
            ok = false;
            break;
          }
        }
        t = e.t, p = e.odom, hp = true;
      }
      if (!lines.empty()) ++intervals;
      if (!ok && !lines.empty()) {
        const std::size_t m = lines.size();
        const double from = std::isfinite(t_prev) ? t_prev : t_scan - 0.1 * static_cast<double>(m);
        const double to = closed ? t_scan : from + 0.1 * static_cast<double>(m);
        for (std::size_t q = 0; q < m; ++q)
          entries[lines[q]].t = from + (to - from) * static_cast<double>(q + 1) / static_cast<double>(m);
        retimed_odom += m;
        ++retimed_intervals;
      }
      if (!closed) break;
      t_prev = t_scan;
      // The interval after the scan starts at its reset line's pose (the corrected pose), if there is one.
      have_pose = j + 1 < ne && entries[j + 1].reset;
      if (have_pose) pose_prev = entries[j + 1].odom;
      k = j + 1;
    }
  }
  if (retimed_odom + retimed_scans > 0)
    report.note(std::to_string(retimed_scans) + " scan stamps out of order re-timed between their neighbours; the "
                "ODOM lines of " + std::to_string(retimed_intervals) + " of " + std::to_string(intervals) +
                " intervals between scans (" + std::to_string(retimed_odom) + " lines: stamps bunched, stepping "
                "back or garbage such as 1e-42) spread evenly over their interval");
  if (retimed_scans * 20 > data.scans.size())
    report.note("more than 5 % of the scans needed new stamps: this log's times are not usable (SOURCE.md)");
  report.count("ODOM stamps re-timed", retimed_odom);
  report.count("scan stamps re-timed", retimed_scans);

  // The raw odometry: increments between consecutive ODOM lines, the jump into each stamp-0 line left out (it is
  // the SLAM correction); poses before the first scan have no reference and are not imported.
  Pose reference, raw;
  bool have_reference = false, started = false;
  std::uint64_t resets = 0, before_first = 0, bridged = 0, unbridged = 0;
  const double max_gap = o.max_odometry_gap_s;
  for (const Entry& e : entries) {
    if (e.scan) continue;
    if (e.reset) {
      reference = e.odom;
      have_reference = true;
      ++resets;
      continue;
    }
    if (!started) {
      if (e.t < static_cast<double>(data.scans.front().t_ns) * 1e-9) {
        ++before_first;
        continue;
      }
      started = true;
      raw = e.odom;
      reference = e.odom;
      have_reference = true;
      data.odometry.push_back({to_ns(e.t), raw.x, raw.y, raw.theta});
      continue;
    }
    const Pose inc = have_reference ? between(reference, e.odom) : Pose{};
    reference = e.odom;
    const Pose next = compose(raw, inc);
    const CarmenOdometry prev = data.odometry.back();  // a copy: the vector grows below
    const double gap = e.t - static_cast<double>(prev.t_ns) * 1e-9;
    if (max_gap > 0.0 && gap > kMaxBridge) {
      ++unbridged;
    } else if (max_gap > 0.0 && gap > max_gap) {
      const int pieces = static_cast<int>(std::ceil(gap / max_gap));
      for (int j = 1; j < pieces; ++j) {
        const double s = static_cast<double>(j) / pieces;
        const Pose part = compose(raw, {s * inc.x, s * inc.y, s * inc.theta});
        data.odometry.push_back({to_ns(static_cast<double>(prev.t_ns) * 1e-9 + s * gap), part.x, part.y, part.theta});
        ++bridged;
      }
    }
    raw = next;
    data.odometry.push_back({to_ns(e.t), raw.x, raw.y, raw.theta});
  }
  report.count("ODOM stamp-0 lines (corrected pose after a scan: not odometry)", resets);
  report.count("ODOM lines before the first scan (no reference: not imported)", before_first);
  report.count("odometry poses interpolated across gaps", bridged);
  if (unbridged > 0) report.count("odometry pauses over 60 s (not interpolated: the HAL drops the motion across)", unbridged);
  if (bridged > 0)
    report.note(std::to_string(bridged) + " odometry poses interpolated where the log's odometry pauses longer than " +
                fixed(max_gap, 2) + " s (the HAL's gap limit would drop the motion across the pause)");
  return data;
}

CarmenImport write_carmen_log(const CarmenData& data, const std::string& out_log, const CarmenImportOptions& o,
                              ImportReport& report) {
  CarmenImport r;
  r.site = site_of(data.path);
  r.mount = data.mount;
  const std::size_t first = std::min(o.first_scan, data.scans.size());
  std::size_t last = o.max_scans > 0 ? std::min(data.scans.size(), first + o.max_scans) : data.scans.size();
  if (first >= last) throw std::runtime_error(data.path + ": the slice holds no scan");
  const std::int64_t t0 = data.scans[first].t_ns;
  if (o.max_seconds > 0.0)
    while (last > first + 1 && data.scans[last - 1].t_ns - t0 > to_ns(o.max_seconds)) --last;
  const std::int64_t t1 = data.scans[last - 1].t_ns;
  const CarmenScan& s0 = data.scans[first];
  r.beams = s0.ranges.size();
  r.geometry = s0.geometry;
  r.t_first_s = static_cast<double>(t0) * 1e-9;
  r.t_last_s = static_cast<double>(t1) * 1e-9;

  node::LogWriter log(out_log);
  std::size_t k = static_cast<std::size_t>(
      std::lower_bound(data.odometry.begin(), data.odometry.end(), t0,
                       [](const CarmenOdometry& a, std::int64_t t) { return a.t_ns < t; }) -
      data.odometry.begin());
  // Odometry first at equal stamps (the loop applies motion before corrections), then the reference, then the scan.
  for (std::size_t i = first; i < last; ++i) {
    const CarmenScan& s = data.scans[i];
    for (; k < data.odometry.size() && data.odometry[k].t_ns <= s.t_ns; ++k) {
      const CarmenOdometry& q = data.odometry[k];
      est_lcm::odometry_t m{};
      m.stamp_ns = q.t_ns;
      m.x_m = static_cast<float>(q.x);
      m.y_m = static_cast<float>(q.y);
      m.theta_rad = static_cast<float>(q.theta);
      log.write("EST_ODOMETRY", m.stamp_ns, m);
      ++r.odometry;
    }
    est_lcm::ground_truth_t g{};
    g.stamp_ns = s.t_ns;
    g.x_m = static_cast<float>(s.reference.x);
    g.y_m = static_cast<float>(s.reference.y);
    g.theta_rad = static_cast<float>(s.reference.theta);
    log.write(kReferenceChannel, g.stamp_ns, g);
    const hal::RangeScanView view{s.t_ns, s.geometry, s.ranges.data(), s.ranges.size()};
    log.write(hal::lcm::Channels{}.range_scan, s.t_ns, hal::lcm::to_lcm(view));
    ++r.scans;
  }
  if (log.failures() != 0)
    throw std::runtime_error(out_log + ": " + std::to_string(log.failures()) + " events not written");
  r.events = log.events();
  if (last == data.scans.size())
    report.count("odometry poses after the last scan (no reference: not written)", data.odometry.size() - k);
  report.count("scans written", r.scans);
  report.count("odometry poses written", r.odometry);
  report.count("reference poses written", r.scans);
  return r;
}

CarmenImport import_carmen(const std::string& path, const std::string& out_log, const CarmenImportOptions& o,
                           ImportReport& report) {
  return write_carmen_log(parse_carmen(path, o, report), out_log, o, report);
}

CarmenLog read_carmen_log(const std::string& path) {
  CarmenLog out;
  std::map<std::int64_t, TimedPose> reference;
  hal::lcm::read_lcm_log(path, "sim_host: warning", stderr, [&](const hal::lcm::LcmLogEvent& e) {
    const std::string ch = e.channel;
    if (ch == kReferenceChannel) {
      est_lcm::ground_truth_t g;
      if (g.decode(e.data.data(), 0, e.size()) < 0) throw std::runtime_error(path + ": bad ground_truth_t");
      out.reference.push_back({g.stamp_ns, g.x_m, g.y_m, g.theta_rad});
      reference[g.stamp_ns] = out.reference.back();
    } else if (ch == "EST_ODOMETRY") {
      est_lcm::odometry_t m;
      if (m.decode(e.data.data(), 0, e.size()) < 0) throw std::runtime_error(path + ": bad odometry_t");
      out.odometry.push_back({m.stamp_ns, m.x_m, m.y_m, m.theta_rad});
    } else if (ch == "EST_RANGE_SCAN") {
      est_lcm::range_scan_t m;
      if (m.decode(e.data.data(), 0, e.size()) < 0) throw std::runtime_error(path + ": bad range_scan_t");
      CarmenScan s;
      s.t_ns = m.stamp_ns;
      s.geometry = {m.angle_min_rad, m.angle_increment_rad, m.range_min_m, m.range_max_m};
      s.ranges = m.ranges_m;
      const auto it = reference.find(m.stamp_ns);
      if (it == reference.end()) throw std::runtime_error(path + ": a scan without its reference pose");
      s.reference = it->second;
      out.scans.push_back(std::move(s));
    }
  });
  return out;
}

}  // namespace sim::data

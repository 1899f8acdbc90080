#include "data/eval_report.hpp"

#include <est_lcm/pose_estimate_t.hpp>
#include <lcm/lcm-cpp.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <stdexcept>

#include "hal/lcm/lcm_log_reader.hpp"

namespace sim::data {
double wrap_angle(double a) { return std::remainder(a, 2.0 * M_PI); }

bool interpolate(const Trajectory& ref, std::int64_t t, std::int64_t max_gap_ns, TimedPose& out) {
  if (ref.empty() || t < ref.front().t_ns || t > ref.back().t_ns) return false;
  const auto it = std::lower_bound(ref.begin(), ref.end(), t,
                                   [](const TimedPose& p, std::int64_t v) { return p.t_ns < v; });
  if (it->t_ns == t) {
    out = *it;
    return true;
  }
  const TimedPose& b = *it;
  const TimedPose& a = *(it - 1);
  if (b.t_ns - a.t_ns > max_gap_ns) return false;
  const double s = static_cast<double>(t - a.t_ns) / static_cast<double>(b.t_ns - a.t_ns);
  out.t_ns = t;
  out.x = a.x + s * (b.x - a.x);
  out.y = a.y + s * (b.y - a.y);
  out.theta = wrap_angle(a.theta + s * wrap_angle(b.theta - a.theta));
  return true;
}

TrajectoryError trajectory_error(const Trajectory& est, const Trajectory& ref, std::int64_t max_gap_ns,
                                 std::int64_t from_ns) {
  TrajectoryError e;
  double sxy = 0.0, sth = 0.0;
  for (const TimedPose& p : est) {
    if (p.t_ns < from_ns) continue;
    TimedPose r;
    if (!interpolate(ref, p.t_ns, max_gap_ns, r)) continue;
    const double d2 = (p.x - r.x) * (p.x - r.x) + (p.y - r.y) * (p.y - r.y);
    const double dth = wrap_angle(p.theta - r.theta);
    sxy += d2;
    sth += dth * dth;
    e.max_xy_m = std::max(e.max_xy_m, std::sqrt(d2));
    e.final_xy_m = std::sqrt(d2);
    ++e.n;
  }
  if (e.n > 0) {
    e.rmse_xy_m = std::sqrt(sxy / static_cast<double>(e.n));
    e.rmse_theta_rad = std::sqrt(sth / static_cast<double>(e.n));
  }
  return e;
}

std::vector<ErrorSample> error_series(const Trajectory& est, const Trajectory& ref, std::int64_t max_gap_ns,
                                      std::int64_t t0_ns) {
  std::vector<ErrorSample> out;
  for (const TimedPose& p : est) {
    TimedPose r;
    if (!interpolate(ref, p.t_ns, max_gap_ns, r)) continue;
    out.push_back({static_cast<double>(p.t_ns - t0_ns) * 1e-9, std::hypot(p.x - r.x, p.y - r.y),
                   std::fabs(wrap_angle(p.theta - r.theta))});
  }
  return out;
}

Trajectory read_pose_estimates(const std::string& path) {
  Trajectory out;
  hal::lcm::read_lcm_log(path, "sim_host: warning", stderr, [&](const hal::lcm::LcmLogEvent& e) {
    if (e.channel != "EST_POSE") return;
    est_lcm::pose_estimate_t p;
    if (p.decode(e.data.data(), 0, e.size()) < 0) throw std::runtime_error(path + ": bad pose_estimate_t");
    out.push_back({p.stamp_ns, p.x_m, p.y_m, p.theta_rad});
  });
  return out;
}

double wall_seconds() {
  using namespace std::chrono;
  return duration<double>(steady_clock::now().time_since_epoch()).count();
}

std::string fixed(double v, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

void print_table(std::FILE* f, const std::vector<std::string>& header,
                 const std::vector<std::vector<std::string>>& rows) {
  std::vector<std::size_t> w(header.size(), 0);
  for (std::size_t i = 0; i < header.size(); ++i) w[i] = header[i].size();
  for (const auto& r : rows)
    for (std::size_t i = 0; i < r.size() && i < w.size(); ++i) w[i] = std::max(w[i], r[i].size());
  const auto line = [&](const std::vector<std::string>& r) {
    for (std::size_t i = 0; i < w.size(); ++i) {
      const std::string& c = i < r.size() ? r[i] : std::string();
      if (i == 0) std::fprintf(f, "%-*s", static_cast<int>(w[i]), c.c_str());
      else std::fprintf(f, "  %*s", static_cast<int>(w[i]), c.c_str());
    }
    std::fprintf(f, "\n");
  };
  line(header);
  std::size_t total = 0;
  for (std::size_t x : w) total += x + 2;
  std::fprintf(f, "%s\n", std::string(total - 2, '-').c_str());
  for (const auto& r : rows) line(r);
}

void write_json(const std::string& path, const nlohmann::json& j) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error(path + ": cannot write");
  out << j.dump(2) << "\n";
  if (!out) throw std::runtime_error(path + ": write failed");
}

}  // namespace sim::data

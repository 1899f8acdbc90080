// The files of a simulation run: per-output CSV, the injected faults, the metrics JSON, and the gnuplot figures.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "sim/angles.hpp"
#include "sim/plot.hpp"
#include "sim/simulate.hpp"

namespace sim {
namespace {

namespace fs = std::filesystem;

double seconds(hal::TimeNs t, hal::TimeNs t0) { return static_cast<double>(t - t0) * 1e-9; }

std::string fmt(const char* f, double v) {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

std::ofstream open(const fs::path& p) {
  std::ofstream f(p, std::ios::binary);
  if (!f) throw std::runtime_error("cannot write " + p.string());
  return f;
}

void write_csv(const SimResult& r, const fs::path& path) {
  std::ofstream f = open(path);
  const hal::TimeNs t0 = r.stream.truth.front().t_ns;
  f << "t_s,truth_x_m,truth_y_m,truth_theta_rad,est_x_m,est_y_m,est_theta_rad,position_error_m,heading_error_rad,"
       "est_sigma_x_m,est_sigma_y_m,est_sigma_theta_rad,particles,status,rejected_inputs\n";
  char line[512];
  for (const OutputRow& w : r.rows) {
    std::snprintf(line, sizeof line, "%.3f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%u,%u,%u\n",
                  seconds(w.t_ns, t0), static_cast<double>(w.truth.x), static_cast<double>(w.truth.y),
                  static_cast<double>(w.truth.theta), static_cast<double>(w.estimate.x),
                  static_cast<double>(w.estimate.y), static_cast<double>(w.estimate.theta),
                  static_cast<double>(w.position_error_m), static_cast<double>(w.heading_error_rad),
                  static_cast<double>(w.sigma_x_m), static_cast<double>(w.sigma_y_m),
                  static_cast<double>(w.sigma_theta_rad), w.particles, w.status, w.rejected_inputs);
    f << line;
  }
  if (!f) throw std::runtime_error("error writing " + path.string());
}

void write_faults_csv(const SimResult& r, const fs::path& path) {
  std::ofstream f = open(path);
  const hal::TimeNs t0 = r.stream.truth.front().t_ns;
  f << "t_s,fault,expected_counter,amount\n";
  for (const InjectedFault& x : r.stream.faults)
    f << fmt("%.3f", seconds(x.t_ns, t0)) << "," << x.key << "," << x.expected << "," << x.amount << "\n";
}

// The map as an image for gnuplot (x y value; 0 free, 1 unknown, 2 occupied), at most ~500 columns.
void write_map_data(const SimWorld& w, const fs::path& path) {
  std::ofstream f = open(path);
  const est::OccupancyGrid& g = w.grid;
  const std::int32_t step = std::max<std::int32_t>(1, (std::max(g.width(), g.height()) + 499) / 500);
  for (std::int32_t cy = 0; cy < g.height(); cy += step) {
    for (std::int32_t cx = 0; cx < g.width(); cx += step) {
      // A block is as occupied as its most occupied cell, so thin walls survive the downsampling.
      int v = 0;
      for (std::int32_t dy = 0; dy < step && cy + dy < g.height(); ++dy)
        for (std::int32_t dx = 0; dx < step && cx + dx < g.width(); ++dx) {
          const est::CellClass c = g.classify(cx + dx, cy + dy);
          v = std::max(v, c == est::CellClass::occupied ? 2 : c == est::CellClass::unknown ? 1 : 0);
        }
      f << fmt("%.3f", static_cast<double>(g.origin_x()) + (cx + 0.5 * step) * static_cast<double>(g.resolution())) << " "
        << fmt("%.3f", static_cast<double>(g.origin_y()) + (cy + 0.5 * step) * static_cast<double>(g.resolution())) << " " << v << "\n";
    }
    f << "\n";
  }
}

// Truth and estimate at 20 Hz; the estimate's line is broken where it jumps (a new cluster won), so jumps are not
// drawn as motion.
void write_track_data(const SimResult& r, const fs::path& truth_path, const fs::path& est_path) {
  std::ofstream ft = open(truth_path), fe = open(est_path);
  const hal::TimeNs t0 = r.stream.truth.front().t_ns;
  for (std::size_t k = 0; k < r.stream.truth.size(); k += 5) {
    const TruthSample& s = r.stream.truth[k];
    if (r.stream.kidnap_ns >= 0 && s.t_ns >= r.stream.kidnap_ns && s.t_ns < r.stream.kidnap_ns + 5 * kSimStepNs)
      ft << "\n";  // the robot was carried: no line across
    ft << fmt("%.4f", seconds(s.t_ns, t0)) << " " << s.pose.x << " " << s.pose.y << "\n";
  }
  hal::TimeNs last_t = -1;
  est::Pose2 last{};
  for (const OutputRow& w : r.rows) {
    if (last_t >= 0 && w.t_ns - last_t < 50 * hal::kNsPerMs) continue;
    if (last_t >= 0 && std::hypot(w.estimate.x - last.x, w.estimate.y - last.y) > 0.4f) fe << "\n";
    fe << fmt("%.4f", seconds(w.t_ns, t0)) << " " << w.estimate.x << " " << w.estimate.y << "\n";
    last_t = w.t_ns;
    last = w.estimate;
  }
}

void write_snapshot_data(const ParticleSnapshot& s, const fs::path& path) {
  std::ofstream f = open(path);
  for (const est::Pose2& p : s.particles) f << p.x << " " << p.y << " " << p.theta << "\n";
}

std::string q(const fs::path& p) { return "'" + p.filename().string() + "'"; }

// Map framing shared by the map plots.
void map_frame(std::ostream& gp, const SimWorld& w) {
  const est::OccupancyGrid& g = w.grid;
  const double x0 = static_cast<double>(g.origin_x()), y0 = static_cast<double>(g.origin_y());
  const double x1 = x0 + g.width() * static_cast<double>(g.resolution());
  const double y1 = y0 + g.height() * static_cast<double>(g.resolution());
  gp << "set size ratio -1\n";
  gp << "set xrange [" << x0 << ":" << x1 << "]\nset yrange [" << y0 << ":" << y1 << "]\n";
  gp << "set palette defined (0 'white', 1 '#dcdcdc', 2 '#202020')\nset cbrange [0:2]\nunset colorbox\n";
  gp << "set xlabel 'x (m)'\nset ylabel 'y (m)'\n";
  gp << "set grid front lc rgb '#c8c8c8' lw 0.5\n";
}

std::string robot_title(const ScenarioConfig& sc) {
  return std::string(to_string(sc.robot)) + ", seed " + std::to_string(sc.seed);
}

void plot_trajectory(const SimResult& r, const ScenarioConfig& sc, const SimWorld& w, const fs::path& dir) {
  const fs::path gp_path = dir / "trajectory.gp", png = dir / "trajectory.png";
  std::ofstream gp = open(gp_path);
  gp << "# sim_host simulate: map, route, truth, estimate and particle clouds (run: cd to this folder; gnuplot "
        "trajectory.gp)\n";
  gp << "set terminal pngcairo size 1400,1250 enhanced font 'Sans,12'\nset output 'trajectory.png'\n";
  map_frame(gp, w);
  const hal::TimeNs t0 = r.stream.truth.front().t_ns;
  std::ostringstream title;
  const bool ekf = r.filter == est::loop::Filter::ekf;
  title << (ekf ? "EKF localization on landmarks in the " : "Monte Carlo localization in the ") << (w.name == "office" ? "synthetic office" : fs::path(w.name).filename().string()) << " ("
        << robot_title(sc) << ")\\nposition RMSE once localized " << fmt("%.3f", r.metrics.rmse_position_m)
        << " m, heading RMSE " << fmt("%.2f", r.metrics.rmse_heading_deg) << " deg";
  gp << "set title \"" << title.str() << "\" noenhanced\n";
  gp << "set key below center horizontal maxcols 3 box opaque width 1 spacing 1.2 noenhanced\n";
  // Route (none drawn for a robot on a control script)
  const bool route = sc.controls.empty() && w.route != nullptr;
  if (route) {
    std::ofstream f = open(dir / "route.dat");
    for (std::size_t i = 0; i <= w.route->size(); ++i) f << (*w.route)[i].x << " " << (*w.route)[i].y << "\n";
  }
  // Kidnapping arrow and burst marker.
  int arrow = 1;
  if (r.stream.kidnap_ns >= 0) {
    const est::Pose2 a = r.stream.truth_at(r.stream.kidnap_ns - kSimStepNs).pose;
    const est::Pose2 b = r.stream.truth_at(r.stream.kidnap_ns).pose;
    gp << "set arrow " << arrow++ << " from " << a.x << "," << a.y << " to " << b.x << "," << b.y
       << " lw 2.5 dt 2 lc rgb '#d62728' head filled size 0.4,20 front\n";
    gp << "set label 1 'kidnapped' at " << 0.5 * static_cast<double>(a.x + b.x) << "," << 0.5 * static_cast<double>(a.y + b.y)
       << " offset 0.5,0.8 tc rgb '#d62728' front font 'Sans,11'\n";
  }
  const est::Pose2 s0 = r.stream.truth.front().pose;
  gp << "set arrow " << arrow++ << " from " << s0.x << "," << s0.y << " rto " << 0.8 * std::cos(static_cast<double>(s0.theta)) << ","
     << 0.8 * std::sin(static_cast<double>(s0.theta)) << " lw 3 lc rgb '#2ca02c' head filled size 0.3,25 front\n";
  // Snapshots drawn: the cloud at 1 s (global localization) and shortly after the kidnapping.
  std::vector<std::pair<fs::path, std::string>> clouds;
  const char* colors[] = {"#9467bd", "#ffa54f"};
  for (std::size_t i = 0; i < r.snapshots.size(); ++i) {
    const ParticleSnapshot& s = r.snapshots[i];
    if (s.label != "first scan" && s.label != "kidnapped + 0.03 s") continue;
    const fs::path p = dir / ("particles_" + std::to_string(i) + ".dat");
    write_snapshot_data(s, p);
    clouds.push_back({p, "particles at " + fmt("%.2f", seconds(s.t_ns, t0)) + " s (" + s.label + ", " +
                             std::to_string(s.total) + ")"});
  }
  // EKF: the landmarks, and the estimate's 2-sigma position ellipse once a second.
  if (ekf) {
    std::ofstream f = open(dir / "landmarks.dat");
    for (std::int32_t j = 0; j < w.landmarks.size(); ++j)
      f << w.landmarks[j].x << " " << w.landmarks[j].y << " " << w.landmarks[j].signature << "\n";
    std::ofstream e = open(dir / "ellipses.dat");
    hal::TimeNs next = t0;
    for (const OutputRow& row : r.rows) {
      if (row.t_ns < next) continue;
      next = row.t_ns + hal::kNsPerS;
      // Axes from the eigenvalues of the 2 x 2 position covariance; 2 sigma: 86 % of a 2-D Gaussian.
      const double a = static_cast<double>(row.sigma_x_m) * static_cast<double>(row.sigma_x_m);
      const double c = static_cast<double>(row.sigma_y_m) * static_cast<double>(row.sigma_y_m);
      const double b = static_cast<double>(row.cov_xy_m2);
      const double mid = 0.5 * (a + c), rad = std::sqrt(0.25 * (a - c) * (a - c) + b * b);
      const double l1 = mid + rad, l2 = std::max(0.0, mid - rad);
      const double angle = 0.5 * std::atan2(2.0 * b, a - c);
      for (int k = 0; k <= 36; ++k) {
        const double u = 2.0 * kPi * k / 36.0;
        const double px = 2.0 * std::sqrt(l1) * std::cos(u), py = 2.0 * std::sqrt(l2) * std::sin(u);
        e << static_cast<double>(row.estimate.x) + px * std::cos(angle) - py * std::sin(angle) << " "
          << static_cast<double>(row.estimate.y) + px * std::sin(angle) + py * std::cos(angle) << "\n";
      }
      e << "\n";
    }
  }
  gp << "plot 'map.dat' using 1:2:3 with image notitle, \\\n";
  if (route)
    gp << "  'route.dat' using 1:2 with linespoints lw 1.5 dt 3 pt 6 ps 1.2 lc rgb '#7f7f7f' title 'route', \\\n";
  if (ekf) {
    gp << "  'landmarks.dat' using 1:2 with points pt 5 ps 1.6 lc rgb '#8c564b' title 'landmarks (posts)', \\\n";
    gp << "  'ellipses.dat' using 1:2 with lines lw 1 lc rgb '#9467bd' title 'estimate 2-sigma ellipse (1 Hz)', \\\n";
  }
  for (std::size_t i = 0; i < clouds.size(); ++i)
    gp << "  " << q(clouds[i].first) << " using 1:2 with points pt 7 ps 0.45 lc rgb '" << colors[i % 2]
       << "' title '" << clouds[i].second << "', \\\n";
  gp << "  'truth.dat' using 2:3 with lines lw 3 lc rgb '#1f77b4' title 'truth', \\\n";
  gp << "  'estimate.dat' using 2:3 with lines lw 1.5 lc rgb '#d62728' title '"
     << (ekf ? "estimate (EKF mean)" : "estimate (strongest cluster)") << "', \\\n";
  {
    std::ofstream f = open(dir / "start.dat");
    f << s0.x << " " << s0.y << "\n";
  }
  gp << "  'start.dat' using 1:2 with points pt 7 ps 2 lc rgb '#2ca02c' title 'start (truth)'\n";
  gp.close();
  run_gnuplot(gp_path, png);
}

void plot_errors(const SimResult& r, const ScenarioConfig& sc, const FilterOptions& fo, const fs::path& dir) {
  const fs::path gp_path = dir / "errors.gp", png = dir / "errors.png";
  std::ofstream gp = open(gp_path);
  const hal::TimeNs t0 = r.stream.truth.front().t_ns;
  const double end = seconds(r.stream.end_ns, t0);
  {
    std::ofstream f = open(dir / "errors.dat");
    for (const OutputRow& w : r.rows)
      f << fmt("%.3f", seconds(w.t_ns, t0)) << " " << w.position_error_m << " "
        << static_cast<double>(w.heading_error_rad) * kDegPerRad << " "
        << w.particles << " " << std::hypot(w.sigma_x_m, w.sigma_y_m) << " "
        << static_cast<double>(w.sigma_theta_rad) * kDegPerRad << "\n";
    std::ofstream g = open(dir / "fault_times.dat");
    for (const InjectedFault& x : r.stream.faults) {
      if (x.key.rfind("event.", 0) == 0) continue;
      const int row = x.key.rfind("wheel", 0) == 0      ? 0
                      : x.key.rfind("steering", 0) == 0 ? 1
                      : x.key.rfind("scan", 0) == 0     ? 2
                                                        : 3;
      g << fmt("%.3f", seconds(x.t_ns, t0)) << " " << row << " " << (x.expected == "-" ? 0 : 1) << "\n";
    }
  }
  gp << "# sim_host simulate: errors over time (gnuplot errors.gp in this folder)\n";
  gp << "set terminal pngcairo size 1500,1150 enhanced font 'Sans,12'\nset output 'errors.png'\n";
  gp << "set multiplot layout 4,1 margins 0.08,0.80,0.06,0.94 spacing 0,0.03 title \"Estimate vs truth ("
     << robot_title(sc) << ")\" font 'Sans,14'\n";
  gp << "set xrange [0:" << end << "]\nset grid lc rgb '#dddddd'\n";
  gp << "set key outside right top vertical noenhanced\n";
  // Event lines on every panel; the legend names only the kinds the run has.
  std::ostringstream events;
  int obj = 1;
  bool kidnap = false, burst = false, slip = false, localized = false, lost = false;
  for (const InjectedFault& x : r.stream.faults) {
    const double t = seconds(x.t_ns, t0);
    if (x.key == "event.kidnap") {
      kidnap = true;
      events << "set arrow " << obj++ << " from " << t << ", graph 0 to " << t
             << ", graph 1 nohead lw 2 dt 2 lc rgb '#d62728'\n";
    }
    if (x.key == "event.burst") {
      burst = true;
      events << "set object " << obj++ << " rect from " << t << ", graph 0 to " << t + sc.burst_ms * 1e-3
             << ", graph 1 fc rgb '#ffbb78' fs solid 0.6 noborder behind\n";
    }
    if (x.key == "event.slip") {
      slip = true;
      events << "set object " << obj++ << " rect from " << t << ", graph 0 to " << t + sc.slip_duration_s
             << ", graph 1 fc rgb '#c5e0b4' fs solid 0.6 noborder behind\n";
    }
  }
  for (const PhaseMetrics& p : r.metrics.phases) {
    if (p.localized) {
      localized = true;
      events << "set arrow " << obj++ << " from " << p.localized_at_s << ", graph 0 to " << p.localized_at_s
             << ", graph 1 nohead lw 1.5 lc rgb '#2ca02c'\n";
    }
    if (p.lost_at_s >= 0.0 && p.start_s > 0.0) {  // a kidnapping's loss (a global start is lost from 0)
      lost = true;
      events << "set arrow " << obj++ << " from " << p.lost_at_s << ", graph 0 to " << p.lost_at_s
             << ", graph 1 nohead lw 1.5 dt 3 lc rgb '#7f7f7f'\n";
    }
  }
  gp << events.str();
  gp << "set format x ''\n";
  gp << "set ylabel 'position error (m)'\nset logscale y\nset yrange [0.002:30]\n";
  gp << "plot 'errors.dat' using 1:2 with lines lw 1.5 lc rgb '#1f77b4' title 'position error', \\\n"
     << "  'errors.dat' using 1:5 with lines lw 1 dt 2 lc rgb '#9467bd' title 'estimated sigma xy', \\\n"
     << "  " << fo.converge_pos_m << " with lines lw 1 dt 3 lc rgb 'black' title 'localized bound "
     << fo.converge_pos_m << " m'";
  if (kidnap) gp << ", \\\n  NaN with lines lw 2 dt 2 lc rgb '#d62728' title 'kidnapping'";
  if (localized) gp << ", \\\n  NaN with lines lw 1.5 lc rgb '#2ca02c' title 'localized from'";
  if (lost) gp << ", \\\n  NaN with lines lw 1.5 dt 3 lc rgb '#7f7f7f' title 'lost at (kidnapping)'";
  if (burst) gp << ", \\\n  NaN with boxes fs solid 0.6 fc rgb '#ffbb78' title 'bus outage'";
  if (slip) gp << ", \\\n  NaN with boxes fs solid 0.6 fc rgb '#c5e0b4' title 'wheel slip'";
  gp << "\n";
  gp << "set ylabel 'heading error (deg)'\nset yrange [0.01:180]\n";
  gp << "plot 'errors.dat' using 1:3 with lines lw 1.5 lc rgb '#ff7f0e' title 'heading error', \\\n"
     << "  " << fo.converge_heading_deg << " with lines lw 1 dt 3 lc rgb 'black' title 'localized bound "
     << fo.converge_heading_deg << " deg'\n";
  if (r.filter == est::loop::Filter::ekf) {
    gp << "set ylabel 'heading sigma (deg)'\nset yrange [0.01:180]\n";
    gp << "plot 'errors.dat' using 1:6 with lines lw 1.5 lc rgb '#8c564b' title 'EKF heading sigma'\n";
  } else {
    gp << "set ylabel 'particles'\nset yrange [100:30000]\n";
    gp << "plot 'errors.dat' using 1:4 with steps lw 1.5 lc rgb '#8c564b' title '"
       << (fo.kld ? "particles (KLD)" : "particles (fixed)") << "'\n";
  }
  gp << "unset logscale y\nset format x '%g'\nset xlabel 'time (s)'\nset yrange [-0.7:3.7]\n";
  gp << "set ytics ('encoders' 0, 'steering' 1, 'scans' 2, 'landmarks' 3)\nset ylabel 'injected faults'\n";
  bool any_fault = false;  // gnuplot warns on an empty file: a run without faults plots none
  for (const InjectedFault& x : r.stream.faults) any_fault = any_fault || x.key.rfind("event.", 0) != 0;
  if (any_fault)
    gp << "plot 'fault_times.dat' using 1:($3 == 1 ? $2 : NaN) with points pt 9 ps 1.3 lc rgb '#d62728' title "
          "'must be rejected', \\\n"
       << "  'fault_times.dat' using 1:($3 == 0 ? $2 : NaN) with points pt 8 ps 1.3 lc rgb '#555555' title "
          "'dropped or reordered'\n";
  else
    gp << "set xrange [0:" << sc.duration_s << "]\nplot NaN title 'no faults injected'\n";
  gp << "unset multiplot\n";
  gp.close();
  run_gnuplot(gp_path, png);
}

void plot_particles(const SimResult& r, const ScenarioConfig& sc, const SimWorld& w, const fs::path& dir) {
  const fs::path gp_path = dir / "particles.gp", png = dir / "particles.png";
  std::ofstream gp = open(gp_path);
  const hal::TimeNs t0 = r.stream.truth.front().t_ns;
  const std::size_t n = std::min<std::size_t>(r.snapshots.size(), 8);
  gp << "# sim_host simulate: particle clouds at fixed times (gnuplot particles.gp in this folder)\n";
  gp << "set terminal pngcairo size 2000,1000 enhanced font 'Sans,11'\nset output 'particles.png'\n";
  gp << "set multiplot layout 2,4 title \"Particle clouds (" << robot_title(sc)
     << "): truth (blue arrow), estimate (red arrow)\" font 'Sans,14'\n";
  map_frame(gp, w);
  gp << "unset key\n";
  for (std::size_t i = 0; i < n; ++i) {
    const ParticleSnapshot& s = r.snapshots[i];
    const fs::path p = dir / ("snapshot_" + std::to_string(i) + ".dat");
    write_snapshot_data(s, p);
    gp << "unset arrow\n";
    gp << "set title \"t = " << fmt("%.2f", seconds(s.t_ns, t0)) << " s (" << s.label << "), " << s.total
       << " particles, error " << fmt("%.2f", std::hypot(s.estimate.x - s.truth.x, s.estimate.y - s.truth.y))
       << " m\" noenhanced\n";
    gp << "set arrow 1 from " << s.truth.x << "," << s.truth.y << " rto " << 0.9 * std::cos(static_cast<double>(s.truth.theta)) << ","
       << 0.9 * std::sin(static_cast<double>(s.truth.theta)) << " lw 2.5 lc rgb '#701f77b4' head filled size 0.3,25 front\n";
    gp << "set arrow 2 from " << s.estimate.x << "," << s.estimate.y << " rto " << 0.9 * std::cos(static_cast<double>(s.estimate.theta))
       << "," << 0.9 * std::sin(static_cast<double>(s.estimate.theta)) << " lw 2 lc rgb '#70d62728' head filled size 0.3,25 front\n";
    gp << "plot 'map.dat' using 1:2:3 with image, " << q(p) << " using 1:2 with points pt 7 ps 0.3 lc rgb '#ff7f0e'\n";
  }
  gp << "unset multiplot\n";
  gp.close();
  run_gnuplot(gp_path, png);
}

}  // namespace

std::string metrics_json(const SimResult& r, const ScenarioConfig& sc, const FilterOptions& fo, const SimWorld& w) {
  using nlohmann::json;
  using ordered = nlohmann::ordered_json;
  const hal::TimeNs t0 = r.stream.truth.front().t_ns;
  ordered j;
  j["scenario"] = {{"world", w.name},
                   {"robot", to_string(sc.robot)},
                   {"seed", sc.seed},
                   {"duration_s", sc.duration_s},
                   {"speed_mps", sc.speed_mps},
                   {"route_waypoints", r.stream.route_waypoints},
                   {"encoder_hz", sc.encoder_hz},
                   {"steering_hz", sc.robot == RobotKind::bicycle && sc.steering_sensor ? sc.steering_hz : 0},
                   {"twist_hz", has_twist(sc.robot) ? sc.twist_hz : 0},
                   {"odometry_hz", has_odometry(sc.robot) ? sc.odometry_hz : 0},
                   {"rangefinder", sc.handlebar ? "on the handlebar" : "fixed"},
                   {"scan_hz", sc.scan_hz},
                   {"beams", sc.beams},
                   {"fov_deg", sc.fov_deg},
                   {"range_max_m", sc.range_max_m},
                   {"landmarks", r.stream.landmark_count},
                   {"landmark_hz", r.stream.landmark_count > 0 ? sc.landmark_hz : 0},
                   {"landmark_ids", sc.landmark_ids_known ? "known" : "unknown"},
                   {"landmark_noise", {{"sigma_range_m", sc.landmark_sensor.noise.sigma_range},
                                       {"sigma_bearing_rad", sc.landmark_sensor.noise.sigma_bearing},
                                       {"sigma_signature", sc.landmark_sensor.noise.sigma_signature},
                                       {"max_range_m", sc.landmark_sensor.max_range}}},
                   {"kidnap_at_s", r.stream.kidnap_ns >= 0 ? seconds(r.stream.kidnap_ns, t0) : -1.0},
                   {"kidnap_distance_m", r.stream.kidnap_ns >= 0 ? r.stream.kidnap_distance_m : 0.0},
                   {"burst_at_s", sc.burst_at_s},
                   {"burst_ms", sc.burst_ms}};
  if (!sc.controls.empty()) j["scenario"]["control_script_commands"] = sc.controls.size();
  const ordered bound = {{"position_m", fo.converge_pos_m},
                         {"heading_deg", fo.converge_heading_deg},
                         {"hold_s", fo.hold_s}};
  const bool ekf = r.filter == est::loop::Filter::ekf;
  if (ekf)
    j["filter"] = {{"kind", "ekf"},
                   {"estimator", r.description},
                   {"description", "EKF localization on landmark features (Thrun table 7.2 with known "
                                   "correspondences, table 7.3 by maximum likelihood when the id is unknown)"},
                   {"start", "tracking"},
                   {"start_sigma_xy_m", fo.ekf_start_sigma_xy_m},
                   {"start_sigma_theta_rad", fo.ekf_start_sigma_theta_rad},
                   {"rot_sigma_per_prediction_rad", fo.ekf_rot_sigma_rad},
                   {"lost_sigma_m", fo.ekf_lost_sigma_m},
                   {"particles", 0},
                   {"localized_bound", bound}};
  else
    j["filter"] = {{"kind", "mcl"},
                   {"estimator", r.description},
                   {"range_model", node::to_string(fo.range_model)},
                   {"handle_positions", fo.range_model == node::RangeModel::steered ? fo.handle_positions : 0},
                   {"start", to_string(fo.start)},
                   {"particles", fo.particles},
                   {"kld", fo.kld},
                   {"kld_min", fo.kld_min},
                   {"beam_stride", fo.beam_stride},
                   {"alpha_slow", fo.alpha_slow},
                   {"alpha_fast", fo.alpha_fast},
                   {"max_injection", fo.max_injection},
                   {"localized_bound", bound}};
  const SimMetrics& m = r.metrics;
  ordered phases = ordered::array();
  for (const PhaseMetrics& p : m.phases) {
    ordered ph = {{"phase", p.name},
                  {"start_s", p.start_s},
                  {"end_s", p.end_s},
                  {"lost_at_s", p.lost_at_s >= 0.0 ? json(p.lost_at_s) : json(nullptr)},
                  {"localized", p.localized},
                  {"localized_at_s", p.localized ? json(p.localized_at_s) : json(nullptr)},
                  {"time_to_localize_s", p.time_to_localize_s}};
    if (!ekf) {
      const bool have = p.localized && p.particles_mean >= 0.0;
      ph["injected_share"] = have ? json(p.injected_share) : json(nullptr);
      ph["injected_particles"] = p.injected_particles;
      ph["drawn_particles"] = p.drawn_particles;
      ph["particles_mean"] = have ? json(p.particles_mean) : json(nullptr);
      ph["particles_max"] = have ? json(p.particles_max) : json(nullptr);
    }
    phases.push_back(ph);
  }
  j["accuracy"] = {{"rmse_position_m", m.rmse_position_m},
                   {"rmse_heading_deg", m.rmse_heading_deg},
                   {"max_position_error_m", m.max_position_error_m},
                   {"max_heading_error_deg", m.max_heading_error_deg},
                   {"localized_time_s", m.localized_time_s},
                   {"outside_bounds_while_localized_s", m.outside_bounds_s},
                   {"rmse_position_all_outputs_m", m.rmse_position_all_m},
                   {"note", "RMSE and maxima over the outputs from the time each phase is localized to its end; per "
                            "phase, time_to_localize_s counts from lost_at_s (a kidnapping: the first output off by "
                            "more than the bounds), injected_share (injected / drawn particles at the resamplings), "
                            "particles_mean and particles_max are over the phase's localized part"}};
  j["phases"] = phases;
  for (const PhaseMetrics& p : m.phases) {
    if (p.name == "global localization")
      j["time_to_converge_s"] = p.localized ? json(p.time_to_localize_s) : json(nullptr);
    if (p.name == "kidnap recovery") j["time_to_recover_s"] = p.localized ? json(p.time_to_localize_s) : json(nullptr);
  }
  if (ekf && r.stream.kidnap_ns >= 0)
    j["kidnap_note"] = "the EKF tracks one Gaussian from the start: it is not built to recover from a kidnapping "
                       "(use --filter mcl, augmented MCL, for that)";
  // Faults: what was injected, what each counter had to show, what it showed.
  const std::map<std::string, int> expected = r.stream.expected_counts();
  const std::map<std::string, int> observed = r.observed_counts();
  ordered cmp = ordered::object();
  bool match = true;
  std::map<std::string, int> keys = expected;
  for (const auto& [k, v] : observed) keys[k] += 0;
  for (const auto& [k, unused] : keys) {
    (void)unused;
    const int e = expected.count(k) ? expected.at(k) : 0;
    const int o = observed.count(k) ? observed.at(k) : 0;
    cmp[k] = {{"injected", e}, {"counted", o}};
    match = match && e == o;
  }
  std::map<std::string, int> injected;
  for (const InjectedFault& x : r.stream.faults) injected[x.key] += 1;
  j["faults"] = {{"injected_by_class", injected},
                 {"rejects_by_counter", cmp},
                 {"every_injected_fault_counted_with_its_reason", match},
                 {"list", "faults.csv"}};
  ordered hal_counts;
  for (const auto& [name, c] : r.sensor_faults) {
    ordered k = ordered::object();
    for (std::size_t i = 1; i < hal::kFaultCount; ++i) k[hal::to_string(static_cast<hal::Fault>(i))] = c.count[i];
    hal_counts[name] = k;
  }
  hal_counts["scan_beams"] = {{"hits", r.beams.hits},
                              {"max_range", r.beams.max_range},
                              {"not_a_number", r.beams.not_a_number},
                              {"below_min", r.beams.below_min}};
  hal_counts["landmark_features_accepted"] = r.landmark_features_accepted;
  j["hal"] = hal_counts;
  ordered stale = ordered::object();  // outputs published while an input kind the filter uses was stale
  for (const est::loop::InputKindInfo& k : est::loop::kInputKinds)
    if (r.loop.of(k.kind).accepted > 0 || r.loop.of(k.kind).stale > 0) stale[k.name] = r.loop.of(k.kind).stale;
  j["loop"] = {{"inputs", r.loop.inputs},
               {"too_old", r.loop.too_old},
               {"queue_full", r.loop.queue_full},
               {"rejected", r.loop.rejected},
               {"predictions", r.loop.predictions},
               {"corrections", r.loop.corrections},
               {"degenerate", r.loop.degenerate},
               {"stale_outputs", stale},
               {"unused", r.loop.unused},
               {"outputs", r.rows.size()},
               {"nonfinite_estimates", r.nonfinite_estimates}};
  if (ekf) {
    j["ekf"] = {{"features_fused", r.ekf.accepted},
                {"features_refused", {{"gated_out", r.ekf.gated_out},
                                      {"unknown_landmark", r.ekf.unknown_landmark},
                                      {"nonfinite", r.ekf.nonfinite},
                                      {"not_positive_definite", r.ekf.not_pd},
                                      {"bad_input", r.ekf.bad_input}}},
                {"predictions", r.ekf_predictions.accepted},
                {"predictions_refused", r.ekf_predictions.rejected_nonfinite + r.ekf_predictions.rejected_range},
                {"note", "refused features are the filter's decisions on inputs the HAL passed (a gate at chi2 "
                         "99.9 %); loop.rejected in rejects_by_counter leaves them out"}};
  } else {
    j["mcl"] = {{"predictions", r.mcl.predictions},
                {"corrections", r.mcl.corrections},
                {"resamplings", r.mcl.resamplings},
                {"drawn_particles", r.mcl.drawn_particles},
                {"injected_particles", r.mcl.injected_particles},
                {"failed_injections", r.mcl.failed_injections},
                {"degenerate_corrections", r.mcl.degenerate_corrections},
                {"map_penalized", r.mcl.map_penalized}};
  }
  j["timing"] = {{"note", "wall-clock figures of this host; not part of the deterministic outputs"},
                 {"wall_s", r.wall_s},
                 {"realtime_factor", r.wall_s > 0.0 ? sc.duration_s / r.wall_s : 0.0},
                 {"worst_step_ms", static_cast<double>(r.loop.worst_step_ns) * 1e-6},
                 {"steps_over_5ms_budget", r.loop.overruns}};
  return j.dump(2) + "\n";
}

std::vector<std::string> write_simulation_outputs(const SimResult& r, const ScenarioConfig& sc, const FilterOptions& fo,
                                                  const SimWorld& w, const std::string& dir_name, bool plots) {
  const fs::path dir(dir_name);
  fs::create_directories(dir);
  std::vector<std::string> out;
  write_csv(r, dir / "trajectory.csv");
  out.push_back((dir / "trajectory.csv").string());
  write_faults_csv(r, dir / "faults.csv");
  out.push_back((dir / "faults.csv").string());
  {
    std::ofstream f = open(dir / "metrics.json");
    f << metrics_json(r, sc, fo, w);
  }
  out.push_back((dir / "metrics.json").string());
  if (plots) {
    write_map_data(w, dir / "map.dat");
    write_track_data(r, dir / "truth.dat", dir / "estimate.dat");
    plot_trajectory(r, sc, w, dir);
    plot_errors(r, sc, fo, dir);
    out.push_back((dir / "trajectory.png").string());
    out.push_back((dir / "errors.png").string());
    if (!r.snapshots.empty()) {  // MCL's clouds; the EKF's ellipses are on trajectory.png
      plot_particles(r, sc, w, dir);
      out.push_back((dir / "particles.png").string());
    }
  }
  return out;
}

}  // namespace sim

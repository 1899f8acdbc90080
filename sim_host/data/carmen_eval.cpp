// sim_host eval carmen (data/carmen.hpp).
#include <CLI/CLI.hpp>
#include <est_lcm/pose_estimate_t.hpp>
#include <lcm/lcm-cpp.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <stdexcept>
#include <vector>

#include "data/carmen.hpp"
#include "data/formats.hpp"
#include "est/map/ray_casting.hpp"
#include "hal/maps/ros_map_loader.hpp"
#include "maps/learn_intrinsic_parameters.hpp"
#include "node/estimator_pipeline.hpp"
#include "node/node.hpp"
#include "sim/plot.hpp"

namespace sim::data {
namespace {

namespace fs = std::filesystem;

constexpr std::int64_t kScanGapNs = 60LL * 1000000000LL;  // reference poses are only at scans: no interpolation


// The estimates at the scans' stamps (the loop publishes the posterior at a correction's time).
Trajectory estimates_at_scans(const std::string& path, const Trajectory& reference) {
  std::map<std::int64_t, TimedPose> at;
  for (const TimedPose& r : reference) at[r.t_ns] = {};
  std::map<std::int64_t, bool> seen;
  for (const TimedPose& p : read_pose_estimates(path)) {
    const auto it = at.find(p.t_ns);
    if (it == at.end()) continue;
    it->second = p;
    seen[p.t_ns] = true;
  }
  Trajectory out;
  for (const auto& [t, pose] : at)
    if (seen.count(t) != 0) out.push_back(pose);
  return out;
}

// The raw odometry from the first corrected pose, at the scans' stamps.
Trajectory dead_reckoning(const CarmenLog& log) {
  Trajectory out;
  if (log.odometry.empty() || log.reference.empty()) return out;
  const TimedPose& o0 = log.odometry.front();
  const TimedPose& r0 = log.reference.front();
  std::size_t k = 0;
  for (const TimedPose& r : log.reference) {
    while (k + 1 < log.odometry.size() && log.odometry[k + 1].t_ns <= r.t_ns) ++k;
    const TimedPose& o = log.odometry[k];
    const double c0 = std::cos(o0.theta), s0 = std::sin(o0.theta);
    const double dx = c0 * (o.x - o0.x) + s0 * (o.y - o0.y), dy = -s0 * (o.x - o0.x) + c0 * (o.y - o0.y);
    const double c = std::cos(r0.theta), s = std::sin(r0.theta);
    out.push_back({r.t_ns, r0.x + c * dx - s * dy, r0.y + s * dx + c * dy, wrap_angle(r0.theta + o.theta - o0.theta)});
  }
  return out;
}

struct NodeRun {
  Trajectory estimates;
  std::uint32_t rejects = 0;
  std::uint32_t injected = 0;  // MCL's random particles (augmented MCL's recovery)
  double run_time_s = 0.0;
};

// MCL through estimator_node's pipeline, the imported log in lockstep.
NodeRun run_mcl(const std::string& log_path, const Trajectory& reference, const CarmenMap& map,
                const CarmenImport& import, const CarmenEvalOptions& o, bool global, std::uint64_t seed,
                const std::string& out_path) {
  node::NodeConfig c;
  c.replay_path = log_path;
  c.out_path = out_path;
  c.map = map.yaml;
  c.quiet = true;
  c.status_hz = 0.0;
  node::EstimatorSpec& s = c.spec;
  s.model = node::RobotModel::odometry;
  s.filter = est::loop::Filter::mcl;
  s.range_model = node::RangeModel::likelihood_field;
  s.motion.odometry = {o.odometry_noise[0], o.odometry_noise[1], o.odometry_noise[2], o.odometry_noise[3],
                       static_cast<float>(o.min_translation_m)};
  s.sensor_mount = import.mount;
  s.field = {1.0f - 0.05f - o.z_rand, 0.05f, o.z_rand, o.sigma_hit_m, import.geometry.range_max_m, 2.0f};
  s.beam.range_max = import.geometry.range_max_m;
  s.beam_stride = o.beam_stride;
  s.timing.predict_period_ns = static_cast<std::int64_t>(std::llround(1.0e9 / o.predict_hz));
  s.particles = global ? o.global_particles : o.particles;
  s.seed = seed;
  s.global = global;
  s.mcl.recovery = global || o.tracking_recovery;
  s.mcl.max_injection_fraction = o.max_injection_fraction;
  s.mcl.recovery_lost_deficit = o.recovery_lost_deficit;
  s.mcl.recovery_dead_band = o.recovery_dead_band;
  s.mcl.recovery_patience = o.recovery_patience;
  if (!global) {
    const TimedPose& x0 = reference.front();
    s.initial_pose = {static_cast<float>(x0.x), static_cast<float>(x0.y), static_cast<float>(x0.theta)};
    s.initial_sigma_xy_m = 0.1f;
    s.initial_sigma_theta_rad = 0.05f;
  }
  NodeRun r;
  const double start = wall_seconds();
  {
    node::Node n(c);
    if (n.run() != 0) throw std::runtime_error("estimator_node's replay of " + log_path + " failed");
    r.rejects = n.rejects_total();
    if (const est::MclCounters* m = n.pipeline().mcl_counters(); m != nullptr) r.injected = m->injected_particles;
    std::FILE* f = std::fopen((out_path + ".summary.txt").c_str(), "w");
    if (f != nullptr) {
      n.print_summary(f);
      std::fclose(f);
    }
  }
  r.run_time_s = wall_seconds() - start;
  r.estimates = estimates_at_scans(out_path, reference);
  return r;
}

bool close_to(const TimedPose& e, const TimedPose& r, const CarmenEvalOptions& o) {
  return std::hypot(e.x - r.x, e.y - r.y) <= o.global_success_m &&
         std::fabs(wrap_angle(e.theta - r.theta)) <= o.global_success_rad;
}

CarmenBeamModel learn_beam(const CarmenLog& log, const CarmenMap& map, const est::Pose2& mount,
                           const CarmenEvalOptions& o) {
  CarmenBeamModel b;
  const double start = wall_seconds();
  auto grid = std::make_unique<est::OccupancyGridStorage<node::kMapMaxSide, node::kMapMaxSide>>();
  hal::maps::load_ros_map(map.yaml, *grid);
  const est::GridRayCaster caster(grid->grid());
  std::vector<est::sim::RangeSample> data;
  float range_max = 0.0f;
  for (const CarmenScan& s : log.scans) {
    const est::Pose2 x{static_cast<float>(s.reference.x), static_cast<float>(s.reference.y),
                       static_cast<float>(s.reference.theta)};
    const est::SensorFrame f = est::sensor_frame(x, mount);
    range_max = s.geometry.range_max_m;
    for (std::size_t k = 0; k < s.ranges.size(); k += static_cast<std::size_t>(std::max(1, o.em_beam_stride))) {
      const float z = s.ranges[k];
      if (!std::isfinite(z) || z < s.geometry.range_min_m) continue;
      const float a = s.geometry.angle_min_rad + static_cast<float>(k) * s.geometry.angle_increment_rad;
      const float ux = std::cos(a), uy = std::sin(a);
      const float z_star = caster.cast(f.x, f.y, f.c * ux - f.s * uy, f.s * ux + f.c * uy, s.geometry.range_max_m);
      data.push_back({std::min(static_cast<double>(z), static_cast<double>(s.geometry.range_max_m)), z_star});
    }
  }
  if (data.empty()) return b;
  est::BeamModelParams init;  // the firmware's defaults, at the log's range
  init.range_max = range_max;
  const double n = static_cast<double>(data.size());
  b.log_likelihood_initial = est::sim::learn_intrinsic_parameters(data, init, 1).log_likelihood / n;
  const est::sim::LearnResult r = est::sim::learn_intrinsic_parameters(data, init, 300, 1e-6);
  b.log_likelihood_final = est::sim::learn_intrinsic_parameters(data, r.params, 1).log_likelihood / n;
  b.learned = true;
  b.z_hit = r.params.z_hit, b.z_short = r.params.z_short, b.z_max = r.params.z_max, b.z_rand = r.params.z_rand;
  b.sigma_hit = r.params.sigma_hit, b.lambda_short = r.params.lambda_short, b.range_max = r.params.range_max;
  b.iterations = r.iterations;
  b.converged = r.converged;
  b.readings = data.size();
  b.run_time_s = wall_seconds() - start;
  return b;
}

void write_trajectory(const fs::path& p, const Trajectory& est, const Trajectory& ref, std::int64_t t0) {
  std::ofstream f(p);
  f << "t x y theta err_xy err_theta\n";
  for (const TimedPose& e : est) {
    TimedPose r;
    const bool has = interpolate(ref, e.t_ns, kScanGapNs, r);
    f << static_cast<double>(e.t_ns - t0) * 1e-9 << " " << e.x << " " << e.y << " " << e.theta << " "
      << (has ? std::hypot(e.x - r.x, e.y - r.y) : 0.0) << " " << (has ? std::fabs(wrap_angle(e.theta - r.theta)) : 0.0)
      << "\n";
  }
}

void write_plots(const CarmenEval& ev, const CarmenLog& log, const std::vector<Trajectory>& methods,
                 const std::vector<Trajectory>& global, const std::string& dir) {
  const fs::path d(dir);
  {
    // The occupied cells of the map, read back from the PGM (top row first).
    hal::maps::PgmImage img = hal::maps::read_pgm(ev.map.pgm);
    std::ofstream w(d / "walls.csv");
    w << "x y\n";
    for (int r = 0; r < img.height; ++r)
      for (int c = 0; c < img.width; ++c)
        if (img.pixels[static_cast<std::size_t>(r * img.width + c)] == 0)
          w << ev.map.origin_x + (c + 0.5) * ev.map.resolution_m << " "
            << ev.map.origin_y + (img.height - 1 - r + 0.5) * ev.map.resolution_m << "\n";
  }
  const std::int64_t t0 = log.reference.front().t_ns;
  write_trajectory(d / "reference.csv", log.reference, log.reference, t0);
  for (std::size_t m = 0; m < methods.size(); ++m)
    write_trajectory(d / (ev.methods[m].name + ".csv"), methods[m], log.reference, t0);
  for (std::size_t g = 0; g < global.size(); ++g)
    write_trajectory(d / ("mcl-global-" + std::to_string(g) + ".csv"), global[g], log.reference, t0);
  const char* colors[] = {"#ff7f0e", "#1f77b4", "#2ca02c", "#d62728", "#9467bd"};
  {
    std::ofstream gp(d / "trajectories.gp");
    // The frame is the map's: dead reckoning, tens of metres off, would otherwise shrink the map to a corner.
    gp << "set terminal pngcairo size 1100,1000 font ',10'\nset output 'trajectories.png'\nset size ratio -1\n"
          "set title 'CARMEN " << ev.import.site << ": estimates against the corrected poses over the map built from "
          "them (framed on the map: dead reckoning leaves it)'\nset key outside bottom horizontal\nset xlabel 'x (m)'\n"
          "set ylabel 'y (m)'\nset xrange [" << ev.map.origin_x << ":" << ev.map.origin_x + ev.map.width * ev.map.resolution_m
       << "]\nset yrange [" << ev.map.origin_y << ":" << ev.map.origin_y + ev.map.height * ev.map.resolution_m << "]\n"
          "plot 'walls.csv' u 1:2 w dots lc rgb 'black' t 'map (occupied)', 'reference.csv' u 2:3 w l lw 2 lc rgb "
          "'gray60' t 'corrected (reference)'";
    for (std::size_t m = 0; m < methods.size(); ++m)
      gp << ", '" << ev.methods[m].name << ".csv' u 2:3 w l lc rgb '" << colors[m % 5] << "' t '"
         << ev.methods[m].name << "'";
    gp << "\n";
  }
  sim::run_gnuplot(d / "trajectories.gp", d / "trajectories.png");
  {
    std::ofstream gp(d / "errors.gp");
    gp << "set terminal pngcairo size 1100,700 font ',10'\nset output 'errors.png'\nset multiplot layout 2,1 title "
          "'CARMEN " << ev.import.site << ": position error against the corrected poses, at the scans'\n"
          "set xlabel 'log time (s)'\nset ylabel 'm'\nset key outside\nset logscale y\nset title 'tracking'\nplot ";
    for (std::size_t m = 0; m < methods.size(); ++m)
      gp << (m ? ", " : "") << "'" << ev.methods[m].name << ".csv' u 1:($5 > 1e-3 ? $5 : 1e-3) w l lc rgb '"
         << colors[m % 5] << "' t '" << ev.methods[m].name << "'";
    gp << "\nset title 'global localization, from each start'\n";
    if (global.empty()) gp << "plot 1e-3 t 'no global runs'\n";
    else gp << "plot ";
    for (std::size_t g = 0; g < global.size(); ++g)
      gp << (g ? ", " : "") << "'mcl-global-" << g << ".csv' u 1:($5 > 1e-3 ? $5 : 1e-3) w lp pt 7 ps 0.4 t 'start "
         << fixed(ev.global[g].start_s, 0) << " s'";
    gp << (global.empty() ? "" : "\n") << "unset multiplot\n";
  }
  sim::run_gnuplot(d / "errors.gp", d / "errors.png");
}

// The slice as MRPT's tools read it (scripts/carmen-vs-mrpt): a CARMEN log of ROBOTLASER1 lines, whose robot pose is
// the raw odometry at the scan (interpolated in the imported odometry, as the MCL runs see it; the corrected logs'
// FLASER lines carry the corrected pose in both of their poses, which carmen2rawlog would hand MRPT as odometry),
// whose laser pose is that pose composed with the mount, and a ground-truth file of the corrected poses, "t x y
// theta" per scan. MRPT lays a scan's beams symmetrically over its field of view, so the field of view is
// (n - 1) increments and the laser pose turns by the offset of the beams' centre from the mount's heading.
void write_mrpt_slice(const CarmenLog& part, const est::Pose2& mount, const fs::path& stem) {
  std::ofstream f(stem.string() + ".carmen.log");
  std::ofstream gt(stem.string() + ".gt.txt");
  f.precision(9);
  gt.precision(12);
  f << "# written by sim_host eval carmen for MRPT: ROBOTLASER1 with the raw odometry as the robot pose\n";
  if (part.odometry.empty()) return;
  for (const CarmenScan& s : part.scans) {
    TimedPose o;
    if (!interpolate(part.odometry, s.t_ns, 1000000000000LL, o))  // before the first odometry pose or after the last
      o = s.t_ns < part.odometry.front().t_ns ? part.odometry.front() : part.odometry.back();
    const std::size_t n = s.ranges.size();
    if (n < 2) continue;
    const double inc = static_cast<double>(s.geometry.angle_increment_rad);
    const double mx = static_cast<double>(mount.x), my = static_cast<double>(mount.y);
    const double fov = inc * static_cast<double>(n - 1);
    const double centre = static_cast<double>(s.geometry.angle_min_rad) + 0.5 * fov;
    const double c = std::cos(o.theta), sn = std::sin(o.theta);
    const double lx = o.x + c * mx - sn * my, ly = o.y + sn * mx + c * my;
    const double lth = wrap_angle(o.theta + static_cast<double>(mount.theta) + centre);
    const double t = static_cast<double>(s.t_ns) * 1e-9;
    f << "ROBOTLASER1 0 " << -0.5 * fov << " " << fov << " " << inc << " " << s.geometry.range_max_m << " 0.01 0 " << n;
    for (const float r : s.ranges)
      f << " " << (std::isfinite(r) ? std::min(r, s.geometry.range_max_m) : s.geometry.range_max_m);
    f << " 0 " << lx << " " << ly << " " << lth << " " << o.x << " " << o.y << " " << o.theta << " 0 0 0 0 0 " << t
      << " est " << t << "\n";
    gt << t << " " << s.reference.x << " " << s.reference.y << " " << s.reference.theta << "\n";
  }
}

}  // namespace

// The first scan from which the estimate is close at every scan of the next global_hold_s and at
// global_kept_fraction of the scans to the end of the run (CarmenEvalOptions).
CarmenGlobalRun judge_global_localization(const Trajectory& est, const Trajectory& ref, const CarmenEvalOptions& o) {
  CarmenGlobalRun g;
  g.start_s = static_cast<double>(ref.front().t_ns) * 1e-9;
  std::map<std::int64_t, TimedPose> by_t;
  for (const TimedPose& p : est) by_t[p.t_ns] = p;
  const std::size_t n = ref.size();
  std::vector<int> close(n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto it = by_t.find(ref[i].t_ns);
    close[i] = it != by_t.end() && close_to(it->second, ref[i], o) ? 1 : 0;
  }
  std::vector<std::size_t> close_from(n + 1, 0);  // close scans in [i, n)
  for (std::size_t i = n; i-- > 0;) close_from[i] = close_from[i + 1] + static_cast<std::size_t>(close[i]);
  const auto hold_ns = static_cast<std::int64_t>(o.global_hold_s * 1e9);
  std::size_t run_end = 0;  // one past the last close scan of the run of close scans holding scan j
  for (std::size_t j = 0; j < n; ++j) {
    if (!close[j]) continue;
    if (run_end <= j) {
      run_end = j;
      while (run_end < n && close[run_end]) ++run_end;
    }
    // Held for global_hold_s: the run of close scans lasts that long (a log that ends sooner confirms nothing).
    if (ref[run_end - 1].t_ns - ref[j].t_ns < hold_ns) continue;
    const double kept = static_cast<double>(close_from[j]) / static_cast<double>(n - j);
    if (kept < o.global_kept_fraction) continue;
    g.localized = true;
    g.time_to_localize_s = static_cast<double>(ref[j].t_ns - ref.front().t_ns) * 1e-9;
    g.kept_fraction = kept;
    g.after = trajectory_error(est, ref, kScanGapNs, ref[j].t_ns);
    break;
  }
  return g;
}


CarmenEval eval_carmen(const std::string& path, const CarmenEvalOptions& o) {
  fs::create_directories(o.out_dir);
  CarmenEval ev;
  ev.report = ImportReport(OnError::skip, o.quiet ? nullptr : stderr);
  const CarmenData data = parse_carmen(path, o.import, ev.report);
  ev.log_path = (fs::path(o.out_dir) / "carmen.lcmlog").string();
  ev.import = write_carmen_log(data, ev.log_path, o.import, ev.report);
  const CarmenLog log = read_carmen_log(ev.log_path);
  if (log.reference.size() < 2) throw std::runtime_error(path + ": the slice needs two scans at least");
  ev.duration_s = ev.import.t_last_s - ev.import.t_first_s;
  ev.map = build_carmen_map(log.scans, data.mount, (fs::path(o.out_dir) / "map").string(), o.map);

  const int global_runs = std::max(0, o.global_starts);
  Progress progress("eval carmen", (o.tracking ? 1.0 : 0.0) + global_runs + (o.learn_beam_model ? 1.0 : 0.0),
                    o.quiet);
  double done = 0.0;
  std::vector<Trajectory> method_estimates;
  {
    CarmenMethodResult m;
    m.name = "dead-reckoning";
    method_estimates.push_back(dead_reckoning(log));
    m.error = trajectory_error(method_estimates.back(), log.reference, kScanGapNs);
    ev.methods.push_back(m);
  }
  if (o.tracking) {
    const NodeRun r = run_mcl(ev.log_path, log.reference, ev.map, ev.import, o, false, o.seed,
                              (fs::path(o.out_dir) / "mcl-tracking.lcmlog").string());
    CarmenMethodResult m;
    m.name = "mcl-tracking";
    m.error = trajectory_error(r.estimates, log.reference, kScanGapNs);
    m.run_time_s = r.run_time_s;
    m.rejects = r.rejects;
    ev.methods.push_back(m);
    method_estimates.push_back(r.estimates);
    progress.update(done += 1.0);
  }

  // Global localization: starts spread over the slice, each with global_seconds of log time.
  std::vector<Trajectory> global_estimates;
  if (global_runs > 0) {
    const std::size_t first = o.import.first_scan, n = ev.import.scans;
    const std::int64_t window = static_cast<std::int64_t>(o.global_seconds * 1e9);
    std::size_t last_start = 0;  // the latest start (within the slice) with a full window after it
    for (std::size_t j = 0; j < n; ++j)
      if (log.scans[j].t_ns + window <= log.scans.back().t_ns) last_start = j;
    for (int g = 0; g < global_runs; ++g) {
      const std::size_t j = global_runs == 1 ? 0 : last_start * static_cast<std::size_t>(g) /
                                                      static_cast<std::size_t>(global_runs - 1);
      CarmenImportOptions io = o.import;
      io.first_scan = first + j;
      io.max_scans = n - j;
      io.max_seconds = o.global_seconds;
      ImportReport quiet(OnError::skip, nullptr);
      const std::string slice = (fs::path(o.out_dir) / ("global-" + std::to_string(g) + ".lcmlog")).string();
      write_carmen_log(data, slice, io, quiet);
      const CarmenLog part = read_carmen_log(slice);
      if (o.mrpt_export) write_mrpt_slice(part, ev.import.mount, fs::path(o.out_dir) / ("global-" + std::to_string(g)));
      const std::uint64_t seed = o.seed + 101u * static_cast<std::uint64_t>(g + 1);
      const NodeRun r = run_mcl(slice, part.reference, ev.map, ev.import, o, true, seed,
                                (fs::path(o.out_dir) / ("mcl-global-" + std::to_string(g) + ".lcmlog")).string());
      CarmenGlobalRun run = judge_global_localization(r.estimates, part.reference, o);
      run.start_scan = first + j;
      run.injected_particles = r.injected;
      run.run_time_s = r.run_time_s;
      ev.global.push_back(run);
      global_estimates.push_back(r.estimates);
      progress.update(done += 1.0);
    }
    int ok = 0;
    double t = 0.0;
    for (const CarmenGlobalRun& g : ev.global)
      if (g.localized) {
        ++ok, t += g.time_to_localize_s;
        ev.global_max_time_s = std::max(ev.global_max_time_s, g.time_to_localize_s);
      }
    ev.global_success_rate = static_cast<double>(ok) / static_cast<double>(ev.global.size());
    ev.global_mean_time_s = ok > 0 ? t / ok : 0.0;
    ev.global_particles = o.global_particles;
    ev.global_seconds = o.global_seconds;
  }
  if (o.learn_beam_model) {
    ev.beam = learn_beam(log, ev.map, data.mount, o);
    progress.update(done += 1.0);
  }
  progress.finish();
  if (o.plots) write_plots(ev, log, method_estimates, global_estimates, o.out_dir);
  return ev;
}

nlohmann::json to_json(const CarmenEval& ev) {
  nlohmann::json methods = nlohmann::json::array();
  for (const CarmenMethodResult& m : ev.methods)
    methods.push_back({{"name", m.name},
                       {"rmse_xy_m", m.error.rmse_xy_m},
                       {"rmse_theta_rad", m.error.rmse_theta_rad},
                       {"max_xy_m", m.error.max_xy_m},
                       {"final_xy_m", m.error.final_xy_m},
                       {"scans_compared", m.error.n},
                       {"run_time_s", m.run_time_s},
                       {"rejected_inputs", m.rejects}});
  nlohmann::json global = nlohmann::json::array();
  for (const CarmenGlobalRun& g : ev.global)
    global.push_back({{"start_s", g.start_s},
                      {"start_scan", g.start_scan},
                      {"injected_particles", g.injected_particles},
                      {"localized", g.localized},
                      {"time_to_localize_s", g.time_to_localize_s},
                      {"kept_fraction", g.kept_fraction},
                      {"rmse_xy_after_m", g.after.rmse_xy_m},
                      {"rmse_theta_after_rad", g.after.rmse_theta_rad},
                      {"run_time_s", g.run_time_s}});
  const CarmenBeamModel& b = ev.beam;
  return {{"site", ev.import.site},
          {"scans", ev.import.scans},
          {"odometry_poses", ev.import.odometry},
          {"beams", ev.import.beams},
          {"range_max_m", ev.import.geometry.range_max_m},
          {"mount", {ev.import.mount.x, ev.import.mount.y, ev.import.mount.theta}},
          {"t_first_s", ev.import.t_first_s},
          {"duration_s", ev.duration_s},
          {"import", ev.report.to_json()},
          {"map",
           {{"yaml", ev.map.yaml},
            {"width", ev.map.width},
            {"height", ev.map.height},
            {"resolution_m", ev.map.resolution_m},
            {"origin", {ev.map.origin_x, ev.map.origin_y}},
            {"occupied_cells", ev.map.occupied},
            {"free_cells", ev.map.free},
            {"endpoints_on_walls", ev.map.endpoints_on_walls},
            {"build_s", ev.map.build_s}}},
          {"methods", methods},
          {"global", {{"starts", ev.global.size()},
                      {"particles", ev.global_particles},
                      {"seconds_per_run", ev.global_seconds},
                      {"runs", global},
                      {"success_rate", ev.global_success_rate},
                      {"mean_time_to_localize_s", ev.global_mean_time_s},
                      {"max_time_to_localize_s", ev.global_max_time_s}}},
          {"beam_model",
           {{"learned", b.learned},
            {"z_hit", b.z_hit},
            {"z_short", b.z_short},
            {"z_max", b.z_max},
            {"z_rand", b.z_rand},
            {"sigma_hit_m", b.sigma_hit},
            {"lambda_short_per_m", b.lambda_short},
            {"range_max_m", b.range_max},
            {"log_likelihood_per_reading_initial", b.log_likelihood_initial},
            {"log_likelihood_per_reading_final", b.log_likelihood_final},
            {"iterations", b.iterations},
            {"converged", b.converged},
            {"readings", b.readings},
            {"run_time_s", b.run_time_s}}}};
}

void add_carmen_eval(CLI::App& eval) {
  CLI::App* cmd = eval.add_subcommand(
      "carmen", "CARMEN logs against their corrected poses: the occupancy grid from the corrected poses (table 9.1), "
                "MCL tracking and global localization on the raw odometry and the scans, the beam model by EM");
  auto in = std::make_shared<std::string>();
  auto json = std::make_shared<std::string>();
  auto o = std::make_shared<CarmenEvalOptions>();
  cmd->add_option("LOG", *in, "a CARMEN log (.log, .clf, .gz)")->required()->check(CLI::ExistingFile);
  cmd->add_option("--out", o->out_dir, "folder for the imported log, the map, the estimates, plots and results.json")
      ->capture_default_str();
  cmd->add_option("--json", *json, "also write the results to this JSON file");
  cmd->add_option("--first-scan", o->import.first_scan, "the slice starts at this scan")->capture_default_str();
  cmd->add_option("--max-scans", o->import.max_scans, "at most this many scans (0: all)")->capture_default_str();
  cmd->add_option("--seconds", o->import.max_seconds, "only the first seconds of log time (0: all)")
      ->capture_default_str();
  cmd->add_option("--resolution", o->map.resolution_m, "map cell size (m)")->capture_default_str();
  cmd->add_option("--map-range", o->map.max_range_m, "readings mapped up to this range (m)")->capture_default_str();
  cmd->add_option("--particles", o->particles, "MCL's particles when tracking")->capture_default_str();
  cmd->add_option("--seed", o->seed, "MCL's seed")->capture_default_str();
  cmd->add_option("--beam-stride", o->beam_stride, "MCL uses every n-th beam")->capture_default_str();
  cmd->add_option("--predict-hz", o->predict_hz, "MCL's prediction rate (log time)")->capture_default_str();
  cmd->add_option_function<std::vector<float>>(
         "--odometry-noise", [o](const std::vector<float>& v) { std::copy(v.begin(), v.end(), o->odometry_noise); },
         "a1..a4 of table 5.6 per prediction (variances)")
      ->delimiter(',')->expected(4);
  cmd->add_option("--min-translation", o->min_translation_m, "odometry model: below this per step, a turn (m)")
      ->capture_default_str();
  cmd->add_option("--sigma-hit", o->sigma_hit_m, "likelihood field's hit spread (m)")->capture_default_str();
  cmd->add_option("--z-rand", o->z_rand, "likelihood field's z_rand (z_max 0.05, z_hit the rest)")
      ->capture_default_str();
  cmd->add_option("--max-injection", o->max_injection_fraction, "augmented MCL: at most this share injected")
      ->capture_default_str();
  cmd->add_option("--lost-deficit", o->recovery_lost_deficit, "augmented MCL: a deficit this large injects at once")
      ->capture_default_str();
  cmd->add_option("--dead-band", o->recovery_dead_band, "augmented MCL: no injection within this deficit")
      ->capture_default_str();
  cmd->add_option("--patience", o->recovery_patience, "augmented MCL: corrections a milder deficit must last")
      ->capture_default_str();
  cmd->add_option("--global-starts", o->global_starts, "global runs, their starts spread evenly over the slice (0: none)")
      ->capture_default_str();
  cmd->add_option("--global-particles", o->global_particles, "MCL's particles for global localization")
      ->capture_default_str();
  cmd->add_option("--global-seconds", o->global_seconds, "log time each global run gets")->capture_default_str();
  cmd->add_option("--success-m", o->global_success_m, "global: localized within this distance ...")
      ->capture_default_str();
  cmd->add_option("--success-rad", o->global_success_rad, "... and this heading ...")->capture_default_str();
  cmd->add_option("--success-hold", o->global_hold_s, "... at every scan of this many seconds ...")
      ->capture_default_str();
  cmd->add_option("--success-kept", o->global_kept_fraction, "... and at this fraction of the scans to the run's end")
      ->capture_default_str();
  cmd->add_flag("--mrpt-export", o->mrpt_export,
                "also write each global run's slice for MRPT (global-N.carmen.log, global-N.gt.txt; "
                "scripts/carmen-vs-mrpt)");
  cmd->add_flag("--tracking-recovery", o->tracking_recovery, "tracking with augmented MCL's random particles");
  cmd->add_flag("--no-tracking", [o](std::int64_t) { o->tracking = false; }, "skip MCL tracking");
  cmd->add_flag("--no-em", [o](std::int64_t) { o->learn_beam_model = false; }, "skip the beam model's EM");
  cmd->add_flag("--no-plots", [o](std::int64_t) { o->plots = false; }, "skip the PNGs");
  cmd->add_flag("--quiet", o->quiet, "no progress, no import diagnostics");
  cmd->callback([=] {
    const CarmenEval ev = eval_carmen(*in, *o);
    const nlohmann::json j = to_json(ev);
    write_json((fs::path(o->out_dir) / "results.json").string(), j);
    if (!json->empty()) write_json(*json, j);
    ev.report.print_summary(stdout, "import carmen: " + *in);
    std::printf("\neval carmen: %s (%s, %zu scans, %.0f s of log time from %.1f s)\n", in->c_str(),
                ev.import.site.c_str(), ev.import.scans, ev.duration_s, ev.import.t_first_s);
    std::printf("  map: %d x %d cells of %.3f m (%llu occupied), %.1f %% of scan end points on walls, %.1f s\n",
                ev.map.width, ev.map.height, ev.map.resolution_m, static_cast<unsigned long long>(ev.map.occupied),
                100.0 * ev.map.endpoints_on_walls, ev.map.build_s);
    std::vector<std::vector<std::string>> rows;
    for (const CarmenMethodResult& m : ev.methods)
      rows.push_back({m.name, fixed(m.error.rmse_xy_m, 3), fixed(m.error.rmse_theta_rad, 3), fixed(m.error.max_xy_m, 2),
                      std::to_string(m.error.n), std::to_string(m.rejects), fixed(m.run_time_s, 1)});
    print_table(stdout, {"method", "RMSE xy (m)", "RMSE theta (rad)", "max xy (m)", "scans", "rejects", "run time (s)"},
                rows);
    if (!ev.global.empty()) {
      std::printf("\nglobal localization (%zu starts, %u particles; success: within %.2f m and %.2f rad for %.0f s, and "
                  "at %.0f %% of the scans to the end)\n",
                  ev.global.size(), o->global_particles, o->global_success_m, o->global_success_rad, o->global_hold_s,
                  100.0 * o->global_kept_fraction);
      std::vector<std::vector<std::string>> g;
      for (const CarmenGlobalRun& r : ev.global)
        g.push_back({fixed(r.start_s, 1), r.localized ? "yes" : "no",
                     r.localized ? fixed(r.time_to_localize_s, 1) : "-",
                     r.localized ? fixed(100.0 * r.kept_fraction, 0) + " %" : "-",
                     r.localized ? fixed(r.after.rmse_xy_m, 3) : "-", fixed(r.run_time_s, 1)});
      print_table(stdout, {"start (s)", "localized", "time to localize (s)", "kept after", "RMSE xy after (m)",
                           "run time (s)"}, g);
      const auto localized = std::count_if(ev.global.begin(), ev.global.end(),
                                           [](const CarmenGlobalRun& r) { return r.localized; });
      std::printf("  success rate %.0f %% (%td of %zu), mean time to localize %.1f s, max %.1f s\n",
                  100.0 * ev.global_success_rate, localized, ev.global.size(), ev.global_mean_time_s,
                  ev.global_max_time_s);
    }
    if (ev.beam.learned) {
      const CarmenBeamModel& b = ev.beam;
      std::printf("\nbeam model by EM (table 6.2), %llu readings at the corrected poses on the map, %d iterations%s:\n"
                  "  z_hit %.3f  z_short %.3f  z_max %.3f  z_rand %.3f  sigma_hit %.3f m  lambda_short %.3f /m  "
                  "(range_max %.2f m)\n  log-likelihood per reading %.3f -> %.3f, %.1f s\n",
                  static_cast<unsigned long long>(b.readings), b.iterations, b.converged ? ", converged" : "",
                  static_cast<double>(b.z_hit), static_cast<double>(b.z_short), static_cast<double>(b.z_max),
                  static_cast<double>(b.z_rand), static_cast<double>(b.sigma_hit), static_cast<double>(b.lambda_short),
                  static_cast<double>(b.range_max), b.log_likelihood_initial, b.log_likelihood_final, b.run_time_s);
    }
    std::printf("\n  results: %s/results.json; plots: %s/trajectories.png, errors.png; map: %s\n", o->out_dir.c_str(),
                o->out_dir.c_str(), ev.map.yaml.c_str());
  });
}

}  // namespace sim::data

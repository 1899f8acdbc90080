// sim_host eval victoria (data/victoria_eval.hpp).
#include "data/victoria_eval.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <stdexcept>

#include <est_lcm/slam_map_t.hpp>

#include "data/formats.hpp"
#include "est/motion/bicycle_model.hpp"
#include "hal/lcm/lcm_log_reader.hpp"
#include "node/estimator_pipeline.hpp"
#include "node/node.hpp"
#include "sim/plot.hpp"

namespace sim::data {
namespace {

namespace fs = std::filesystem;

constexpr double kStepS = 0.025;                    // the noise's reference step: the speed samples' period
constexpr std::int64_t kMaxEstimateGapNs = 200000000;
constexpr double kMetresPerTick = 0.001;            // the import's travel counter

// The laser (and GPS antenna) at (a, b) in the front axle's frame.
TimedPose laser_of(const est::Pose2& front, std::int64_t t_ns, const VictoriaGeometry& g) {
  const double c = std::cos(front.theta), s = std::sin(front.theta);
  const double x = front.x, y = front.y;
  return {t_ns, x + c * g.laser_ahead - s * g.laser_left, y + s * g.laser_ahead + c * g.laser_left, front.theta};
}

// The controls of the log in time order: the front axle's travel between tick samples with the steering that held
// over it. A filter predicts to any time with the last speed held, and the next tick sample's remaining travel puts
// it back on the measured distance (so a laser scan between samples is predicted to its own time, and no travel is
// lost or counted twice).
class ControlReplay {
 public:
  explicit ControlReplay(const VictoriaLog& log) : log_(log) {}

  // Calls predict(v, steer, dt) and, after each tick sample, sample(t_ns); then scan(scan) for each scan, all in
  // time order (at one stamp: ticks, steering, scan), until t_end_ns.
  template <typename Predict, typename Sample, typename Scan>
  void run(Predict&& predict, Sample&& sample, Scan&& scan) {
    if (log_.ticks.empty()) return;
    std::size_t ti = 1, si = 0, ci = 0;
    std::int64_t t_state = log_.ticks.front().t_ns;
    double steer = 0.0, v_held = 0.0, travelled = 0.0;
    while (si < log_.steering.size() && log_.steering[si].t_ns <= t_state) steer = log_.steering[si++].angle;
    while (ci < log_.scans.size() && log_.scans[ci].t_ns < t_state) ++ci;
    while (ti < log_.ticks.size() || ci < log_.scans.size()) {
      const bool tick_next = ti < log_.ticks.size() &&
                             (ci >= log_.scans.size() || log_.ticks[ti].t_ns <= log_.scans[ci].t_ns);
      if (tick_next) {
        const VictoriaTicks& a = log_.ticks[ti - 1];
        const VictoriaTicks& b = log_.ticks[ti];
        const double d = static_cast<double>(static_cast<std::int32_t>(b.count - a.count)) * kMetresPerTick;
        const double dt = static_cast<double>(b.t_ns - t_state) * 1e-9;
        if (dt > 0.0) predict((d - travelled) / dt, steer, dt);
        const double interval = static_cast<double>(b.t_ns - a.t_ns) * 1e-9;
        v_held = interval > 0.0 ? d / interval : 0.0;
        travelled = 0.0;
        t_state = b.t_ns;
        while (si < log_.steering.size() && log_.steering[si].t_ns <= t_state) steer = log_.steering[si++].angle;
        sample(t_state);
        ++ti;
      } else {
        const VictoriaScan& s = log_.scans[ci++];
        const double dt = static_cast<double>(s.t_ns - t_state) * 1e-9;
        if (dt > 0.0 && ti < log_.ticks.size()) {
          predict(v_held, steer, dt);
          travelled += v_held * dt;
          t_state = s.t_ns;
        }
        scan(s);
      }
    }
  }

 private:
  const VictoriaLog& log_;
};

est::BicycleParams bicycle_params(const VictoriaEvalOptions& o) {
  est::BicycleParams p;
  p.frame_length = static_cast<float>(o.geometry.wheelbase);
  p.steer_max = 0.8f;  // rad: the data's steering stays within 0.6
  return p;
}

// The bicycle's mean from `x0` over the whole log.
Trajectory dead_reckoning(const VictoriaLog& log, const est::Pose2& x0, const VictoriaEvalOptions& o) {
  Trajectory out;
  est::Pose2 x = x0;
  est::BicycleParams p = bicycle_params(o);
  ControlReplay(log).run(
      [&](double v, double steer, double dt) {
        p.dt = static_cast<float>(dt);
        x = est::predict_motion_bicycle(x, {static_cast<float>(v), static_cast<float>(steer)}, p);
      },
      [&](std::int64_t t) { out.push_back(laser_of(x, t, o.geometry)); }, [](const VictoriaScan&) {});
  return out;
}

// estimator_node on the imported log in lockstep (the path a user's replay takes), the traction counter and the
// steering as its inputs, from `x0`: dead reckoning (the EKF with no landmark input: the tree detections go to a
// channel it does not read) or EKF-SLAM on the tree detections (the landmark channel, diameter as signature).
node::NodeConfig node_config(const std::string& log_path, const std::string& out_name, const est::Pose2& x0,
                             const VictoriaEvalOptions& o, bool slam) {
  node::NodeConfig c;
  c.replay_path = log_path;
  c.out_path = (fs::path(o.out_dir) / out_name).string();
  c.quiet = true;
  c.status_hz = 0.0;  // the status (and EKF-SLAM's map) once, at the end
  c.lcm_wheel_counter_bits = 32;
  node::EstimatorSpec& s = c.spec;
  s.model = node::RobotModel::bicycle;
  s.motion.bicycle = bicycle_params(o);
  s.motion.bicycle_control.metres_per_tick = static_cast<float>(kMetresPerTick);
  s.limits.wheels.wheel_count = 1;
  s.limits.steering.max_angle_rad = s.motion.bicycle.steer_max;
  s.initial_pose = x0;
  if (!slam) {
    c.channels.landmarks = "EST_LANDMARKS_NOT_READ";
    s.filter = est::loop::Filter::ekf;
    return c;
  }
  const VictoriaNoise& n = o.noise;
  s.filter = est::loop::Filter::ekf_slam;
  // The noise per 25 ms step (the speed samples' period), scaled by the estimator to each prediction's step; the
  // heading's per prediction, at the speed samples' rate (40 Hz predictions, and one more at each scan).
  s.motion.bicycle.speed_var_per_speed = n.speed_var_per_speed;
  s.motion.bicycle.steer_sigma = n.steer_sigma;
  s.slam_noise_step_s = static_cast<float>(kStepS);
  s.timing.predict_period_ns = static_cast<std::int64_t>(kStepS * 1e9);
  s.ekf_rot_sigma = n.heading_sigma;
  s.landmark_noise = {n.sigma_range, n.sigma_bearing, 0.0f};
  s.limits.landmarks.max_range_m = 100.0f;  // the import's reach: the estimator counts what is beyond max_range_m
  s.slam_max_range_m = static_cast<float>(o.max_range_m);
  s.slam_gate_accept = o.gate_accept;
  s.slam_gate_new = o.gate_new;
  s.slam_confirm = o.confirm_sightings;
  s.slam_candidate_radius_m = o.candidate_radius_m;
  s.slam_candidate_frames = static_cast<std::uint32_t>(o.candidate_scans);
  s.initial_sigma_xy_m = 0.01f;
  s.initial_sigma_theta_rad = 0.01f;
  s.lost_sigma_m = 1000.0f;  // the map's frame is the start pose's: the robot's sd grows with the loop, not lost
  return c;
}

struct NodeRun {
  Trajectory laser;
  est_lcm::slam_map_t map{};  // EKF-SLAM: the last map the node wrote
  bool have_map = false;
};

NodeRun run_node(const node::NodeConfig& c, const VictoriaEvalOptions& o) {
  {  // the node's output log is complete once it is gone
    node::Node n(c);
    if (n.run() != 0) throw std::runtime_error("victoria: estimator_node's replay of " + c.replay_path + " failed");
    if (n.rejects_total() != 0)
      throw std::runtime_error("victoria: estimator_node's replay rejected " + std::to_string(n.rejects_total()) +
                               " inputs of " + c.replay_path);
  }
  NodeRun out;
  for (const TimedPose& f : read_pose_estimates(c.out_path))
    out.laser.push_back(laser_of({static_cast<float>(f.x), static_cast<float>(f.y), static_cast<float>(f.theta)},
                                 f.t_ns, o.geometry));
  hal::lcm::read_lcm_log(c.out_path, "sim_host: warning", stderr, [&](const hal::lcm::LcmLogEvent& e) {
    if (e.channel != c.channels.slam_map) return;
    if (out.map.decode(e.data.data(), 0, e.size()) < 0) throw std::runtime_error(c.out_path + ": bad slam_map_t");
    out.have_map = true;
  });
  return out;
}

// The start pose (data/victoria_eval.hpp): the laser at the GPS fixes' mean before the first motion, the heading from
// the first heading_from_m metres of dead reckoning against GPS.
TimedPose start_pose(const VictoriaLog& log, const VictoriaEvalOptions& o) {
  if (log.ticks.empty() || log.gps.empty()) throw std::runtime_error("victoria: no speed samples or no GPS fix");
  std::int64_t t_move = log.ticks.back().t_ns;
  for (std::size_t k = 1; k < log.ticks.size(); ++k)
    if (log.ticks[k].count != log.ticks[0].count) {
      t_move = log.ticks[k - 1].t_ns;
      break;
    }
  double gx = 0.0, gy = 0.0;
  int n = 0;
  for (const TimedPose& f : log.gps)
    if (f.t_ns <= t_move) gx += f.x, gy += f.y, ++n;
  if (n == 0) gx = log.gps.front().x, gy = log.gps.front().y, n = 1;
  gx /= n, gy /= n;
  const VictoriaGeometry& g = o.geometry;
  // Dead reckoning with heading 0 from the laser at the origin, until heading_from_m of travel.
  const est::Pose2 zero{static_cast<float>(-g.laser_ahead), static_cast<float>(-g.laser_left), 0.0f};
  const Trajectory dr = dead_reckoning(log, zero, o);
  double heading = 0.0;
  for (std::size_t k = 1; k < dr.size(); ++k) {
    if (std::hypot(dr[k].x, dr[k].y) < o.heading_from_m) continue;
    const auto it = std::min_element(log.gps.begin(), log.gps.end(), [&](const TimedPose& a, const TimedPose& b) {
      return std::llabs(a.t_ns - dr[k].t_ns) < std::llabs(b.t_ns - dr[k].t_ns);
    });
    TimedPose at;
    if (!interpolate(dr, it->t_ns, kMaxEstimateGapNs, at)) at = dr[k];
    heading = std::atan2(it->y - gy, it->x - gx) - std::atan2(at.y, at.x);
    break;
  }
  heading = wrap_angle(heading);
  const double c = std::cos(heading), s = std::sin(heading);
  return {log.ticks.front().t_ns, gx - c * g.laser_ahead + s * g.laser_left, gy - s * g.laser_ahead - c * g.laser_left,
          heading};
}

struct SlamRun {
  VictoriaRun run;
  Trajectory laser;
  std::vector<Eigen::Vector2f> landmarks;
};

// EKF-SLAM with unknown correspondence (est/loop/ekf_slam_estimator.hpp) through estimator_node's replay.
SlamRun ekf_slam(const std::string& log_path, const est::Pose2& x0, const VictoriaEvalOptions& o) {
  SlamRun out;
  out.run.name = "ekf-slam";
  const double start = wall_seconds();
  const NodeRun r = run_node(node_config(log_path, "ekf-slam-node.lcmlog", x0, o, true), o);
  out.run.run_time_s = wall_seconds() - start;
  if (!r.have_map) throw std::runtime_error("victoria: estimator_node wrote no EKF-SLAM map");
  out.laser = r.laser;
  const est_lcm::slam_map_t& m = r.map;
  for (int k = 0; k < m.num_landmarks; ++k)
    out.landmarks.emplace_back(m.x_m[static_cast<std::size_t>(k)], m.y_m[static_cast<std::size_t>(k)]);
  VictoriaRun& v = out.run;
  v.landmarks = m.num_landmarks;
  const auto u = [](std::int64_t x) { return static_cast<std::uint64_t>(x); };
  v.associated = u(m.associated);
  v.created = u(m.created);
  v.discarded = u(m.discarded);
  v.update_refused = u(m.update_refused);
  v.out_of_range = u(m.beyond_range);
  v.tentative = u(m.held_tentative);
  v.forgotten = u(m.tentative_forgotten);
  v.refused = u(m.map_full) + u(m.insert_refused);
  v.tentative_full = u(m.tentative_full);
  v.bad_input = u(m.bad_input);
  return out;
}

void write_plots(const VictoriaEval& ev, const VictoriaLog& log, const Trajectory& dr, const SlamRun& slam,
                 const std::string& dir) {
  const fs::path d(dir);
  const auto write_traj = [&](const std::string& name, const Trajectory& t) {
    std::ofstream f(d / name);
    f << "t x y\n";
    for (std::size_t k = 0; k < t.size(); k += 4)
      f << static_cast<double>(t[k].t_ns) * 1e-9 << " " << t[k].x << " " << t[k].y << "\n";
  };
  write_traj("dead-reckoning.csv", dr);
  write_traj("ekf-slam.csv", slam.laser);
  {
    std::ofstream f(d / "gps.csv");
    f << "t x y\n";
    for (const TimedPose& p : log.gps) f << static_cast<double>(p.t_ns) * 1e-9 << " " << p.x << " " << p.y << "\n";
    std::ofstream l(d / "landmarks.csv");
    l << "x y\n";
    for (const Eigen::Vector2f& m : slam.landmarks) l << m.x() << " " << m.y() << "\n";
  }
  const auto write_err = [&](const std::string& name, const Trajectory& t) {
    std::ofstream f(d / name);
    f << "t err_xy\n";
    for (const ErrorSample& e : error_series(log.gps, t, kMaxEstimateGapNs, 0)) f << e.t_s << " " << e.xy_m << "\n";
  };
  write_err("dead-reckoning-errors.csv", dr);
  write_err("ekf-slam-errors.csv", slam.laser);
  {
    std::ofstream gp(d / "map.gp");
    gp << "set terminal pngcairo size 1200,1000 font ',9'\nset output 'map.png'\nset title 'Victoria Park: EKF-SLAM "
          "(laser / antenna position, " << ev.runs.back().landmarks << " landmarks) against GPS'\nset size ratio -1\n"
          "set xlabel 'x (m)'\nset ylabel 'y (m)'\nset key outside bottom\n"
          "plot 'gps.csv' u 2:3 w p pt 7 ps 0.3 lc rgb 'gray60' t 'GPS', 'dead-reckoning.csv' u 2:3 w l lc rgb "
          "'#ff7f0e' t 'dead reckoning', 'ekf-slam.csv' u 2:3 w l lc rgb '#1f77b4' lw 1.5 t 'EKF-SLAM', "
          "'landmarks.csv' u 1:2 w p pt 6 ps 0.8 lc rgb '#2ca02c' t 'landmarks (trees)'\n";
  }
  sim::run_gnuplot(d / "map.gp", d / "map.png");
  {
    std::ofstream gp(d / "errors.gp");
    gp << "set terminal pngcairo size 1100,450 font ',9'\nset output 'errors.png'\nset title 'Victoria Park: "
          "position error against each GPS fix'\nset xlabel 't (s)'\nset ylabel 'm'\nset logscale y\n"
          "set key top left\nplot 'dead-reckoning-errors.csv' u 1:($2+1e-3) w l lc rgb '#ff7f0e' t 'dead reckoning', "
          "'ekf-slam-errors.csv' u 1:($2+1e-3) w l lc rgb '#1f77b4' t 'EKF-SLAM'\n";
  }
  sim::run_gnuplot(d / "errors.gp", d / "errors.png");
}

// The errors at every GPS fix, with their median and 95th percentile.
void gps_error(const Trajectory& gps, const Trajectory& estimate, VictoriaRun& run) {
  run.gps = trajectory_error(gps, estimate, kMaxEstimateGapNs);
  std::vector<double> e;
  for (const ErrorSample& s : error_series(gps, estimate, kMaxEstimateGapNs, 0)) e.push_back(s.xy_m);
  if (e.empty()) return;
  std::sort(e.begin(), e.end());
  run.gps_median_m = e[e.size() / 2];
  run.gps_p95_m = e[std::min(e.size() - 1, static_cast<std::size_t>(0.95 * static_cast<double>(e.size())))];
}

}  // namespace

VictoriaEval eval_victoria(const std::string& dir, const VictoriaEvalOptions& o) {
  fs::create_directories(o.out_dir);
  VictoriaEval ev;
  ev.capacity = node::kSlamLandmarks;
  ev.log_path = (fs::path(o.out_dir) / "victoria.lcmlog").string();
  ImportReport report(OnError::skip, o.quiet ? nullptr : stderr);
  VictoriaImportOptions io;
  io.geometry = o.geometry;
  io.max_seconds = o.max_seconds;
  io.metres_per_tick = kMetresPerTick;
  ev.import = import_victoria(dir, ev.log_path, io, report);
  const VictoriaLog log = read_victoria_log(ev.log_path);
  ev.start = start_pose(log, o);
  const est::Pose2 x0{static_cast<float>(ev.start.x), static_cast<float>(ev.start.y),
                      static_cast<float>(ev.start.theta)};

  Progress progress("eval victoria", 2.0, o.quiet);
  VictoriaRun dr_run;
  dr_run.name = "dead-reckoning";
  double t0 = wall_seconds();
  const Trajectory dr = run_node(node_config(ev.log_path, "dead-reckoning-node.lcmlog", x0, o, false), o).laser;
  dr_run.run_time_s = wall_seconds() - t0;
  ev.node_vs_direct_rmse_m = trajectory_error(dr, dead_reckoning(log, x0, o), kMaxEstimateGapNs).rmse_xy_m;
  gps_error(log.gps, dr, dr_run);
  ev.runs.push_back(dr_run);
  progress.update(1.0);

  SlamRun slam = ekf_slam(ev.log_path, x0, o);
  progress.update(2.0);
  progress.finish();
  gps_error(log.gps, slam.laser, slam.run);
  ev.runs.push_back(slam.run);
  if (o.plots) write_plots(ev, log, dr, slam, o.out_dir);
  return ev;
}

nlohmann::json to_json(const VictoriaEval& ev) {
  nlohmann::json runs = nlohmann::json::array();
  for (const VictoriaRun& r : ev.runs)
    runs.push_back({{"name", r.name},
                    {"gps_rmse_m", r.gps.rmse_xy_m},
                    {"gps_median_m", r.gps_median_m},
                    {"gps_p95_m", r.gps_p95_m},
                    {"gps_max_m", r.gps.max_xy_m},
                    {"gps_final_m", r.gps.final_xy_m},
                    {"gps_fixes", r.gps.n},
                    {"run_time_s", r.run_time_s},
                    {"landmarks", r.landmarks},
                    {"associated", r.associated},
                    {"created", r.created},
                    {"discarded", r.discarded},
                    {"update_refused", r.update_refused},
                    {"tentative_full", r.tentative_full},
                    {"bad_input", r.bad_input},
                    {"beyond_range", r.out_of_range},
                    {"tentative", r.tentative},
                    {"tentative_forgotten", r.forgotten},
                    {"refused", r.refused}});
  return {{"duration_s", ev.import.duration_s},
          {"scans", ev.import.scans},
          {"detections", ev.import.detections},
          {"gps_fixes", ev.import.gps},
          {"landmark_capacity", ev.capacity},
          {"start_pose", {{"x_m", ev.start.x}, {"y_m", ev.start.y}, {"theta_rad", ev.start.theta}}},
          {"reference_point", "front axle middle (the bicycle's front wheel); compared at the laser / GPS antenna"},
          {"dead_reckoning_node_vs_direct_rmse_m", ev.node_vs_direct_rmse_m},
          {"runs", runs}};
}

void add_victoria_eval(CLI::App& eval) {
  CLI::App* cmd = eval.add_subcommand(
      "victoria", "Victoria Park: EKF-SLAM of the car (the bicycle at its front axle) on the tree detections with "
                  "unknown correspondence (gated maximum likelihood), against GPS; dead reckoning for comparison");
  auto dir = std::make_shared<std::string>();
  auto opts = std::make_shared<VictoriaEvalOptions>();
  auto json = std::make_shared<bool>(false);
  VictoriaNoise& n = opts->noise;
  cmd->add_option("DIR", *dir, "the dataset's folder (victoria-park/ or its acfr-text-rfsslam/)")
      ->required()->check(CLI::ExistingDirectory);
  cmd->add_option("--out", opts->out_dir, "folder for the imported log, plots and results.json")->capture_default_str();
  cmd->add_option("--seconds", opts->max_seconds, "only the first seconds (0: all)")->capture_default_str();
  cmd->add_option("--max-range", opts->max_range_m, "detections beyond are not used (m)")->capture_default_str();
  cmd->add_option("--gate-accept", opts->gate_accept, "associate under this Mahalanobis distance^2")
      ->capture_default_str();
  cmd->add_option("--gate-new", opts->gate_new, "a new landmark above this Mahalanobis distance^2")
      ->capture_default_str();
  cmd->add_option("--confirm", opts->confirm_sightings, "sightings (in different scans) before a new landmark "
                                                      "enters the map")->capture_default_str();
  cmd->add_option("--sigma-range", n.sigma_range, "laser range noise (m)")->capture_default_str();
  cmd->add_option("--sigma-bearing", n.sigma_bearing, "laser bearing noise (rad)")->capture_default_str();
  cmd->add_option("--speed-var-per-speed", n.speed_var_per_speed, "Var(v) = k |v| per 25 ms (m/s)")
      ->capture_default_str();
  cmd->add_option("--steer-sigma", n.steer_sigma, "steering noise per 25 ms (rad)")->capture_default_str();
  cmd->add_option("--heading-sigma", n.heading_sigma, "heading noise per 25 ms (rad)")->capture_default_str();
  cmd->add_flag("--json", *json, "print the results as JSON on stdout instead of the table");
  cmd->add_flag("--no-plots", [opts](std::int64_t) { opts->plots = false; }, "skip the PNGs");
  cmd->add_flag("--quiet", opts->quiet, "no progress, no import diagnostics");
  cmd->callback([=] {
    const VictoriaEval ev = eval_victoria(*dir, *opts);
    const nlohmann::json j = to_json(ev);
    write_json((fs::path(opts->out_dir) / "results.json").string(), j);
    if (*json) {
      std::printf("%s\n", j.dump(2).c_str());
      return;
    }
    const VictoriaGeometry& g = opts->geometry;
    std::printf("eval victoria: %s (%.0f s, %llu scans, %llu tree detections, %llu GPS fixes)\n", dir->c_str(),
                ev.import.duration_s, static_cast<unsigned long long>(ev.import.scans),
                static_cast<unsigned long long>(ev.import.detections), static_cast<unsigned long long>(ev.import.gps));
    std::printf("  model: the bicycle referenced at the front axle's middle (where the firmware's model puts its pose "
                "and the steering angle applies), L = %.2f m; the rear left encoder's speed v_e taken there as "
                "v_e / ((1 - tan(steer) H / L) cos(steer)), H = %.2f m; the trees from the laser at a = %.2f m ahead "
                "of the front axle, b = %.2f m left\n", g.wheelbase, g.encoder_offset, g.laser_ahead, g.laser_left);
    std::printf("  start pose (the only alignment, from GPS): front axle at (%.2f, %.2f), heading %.3f rad; the "
                "laser / antenna position compared with every GPS fix, jumps and all\n",
                ev.start.x, ev.start.y, ev.start.theta);
    std::vector<std::vector<std::string>> rows;
    for (const VictoriaRun& r : ev.runs)
      rows.push_back({r.name, fixed(r.gps.rmse_xy_m, 2) + " m", fixed(r.gps_median_m, 2) + " m",
                      fixed(r.gps_p95_m, 1) + " m", fixed(r.gps.max_xy_m, 1) + " m", std::to_string(r.gps.n),
                      std::to_string(r.landmarks), fixed(r.run_time_s, 1) + " s"});
    print_table(stdout, {"method", "GPS RMSE", "median", "95 %", "max", "fixes", "landmarks", "run time"}, rows);
    const VictoriaRun& s = ev.runs.back();
    const auto u = [](std::uint64_t v) { return static_cast<unsigned long long>(v); };
    std::printf("  association (gates %.2f / %.2f): %llu associated, %llu new landmarks, %llu discarded between the "
                "gates, %llu beyond %.0f m, %llu held as tentative (%llu tentative landmarks never confirmed), %llu "
                "updates refused by the filter, %llu refused (capacity %d), %llu tentative table full, %llu bad\n",
                double{opts->gate_accept}, double{opts->gate_new}, u(s.associated), u(s.created), u(s.discarded),
                u(s.out_of_range), opts->max_range_m, u(s.tentative), u(s.forgotten), u(s.update_refused),
                u(s.refused), ev.capacity, u(s.tentative_full), u(s.bad_input));
    std::printf("  EKF-SLAM: estimator_node --filter ekf-slam, the log replayed in lockstep (its estimates: %s/"
                "ekf-slam-node.lcmlog)\n", opts->out_dir.c_str());
    std::printf("  dead reckoning: estimator_node's replay of the log, %.3f m RMSE from the bicycle's mean integrated "
                "directly\n", ev.node_vs_direct_rmse_m);
    std::printf("  results: %s/results.json; plots: %s/map.png, errors.png; log: %s\n", opts->out_dir.c_str(),
                opts->out_dir.c_str(), ev.log_path.c_str());
  });
}

}  // namespace sim::data

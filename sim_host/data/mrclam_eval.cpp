// sim_host eval mrclam (data/mrclam_eval.hpp).
#include "data/mrclam_eval.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <stdexcept>

#include "data/channels.hpp"
#include "data/formats.hpp"
#include "est/motion/velocity_model.hpp"
#include "est/slam/cooperative_ekf_slam.hpp"
#include "node/node.hpp"
#include "sim/plot.hpp"

namespace sim::data {
namespace {

namespace fs = std::filesystem;

constexpr std::int64_t kMaxTruthGapNs = 200000000;  // a Vicon dropout longer than 0.2 s is no reference
constexpr std::int64_t kTeamStepNs = 20000000;       // the team filter's step: 50 Hz, the sampled layout's grid

est::VelocityParams motion_noise(const MrclamNoise& n) {
  est::VelocityParams p;
  p.a1 = n.a[0], p.a2 = n.a[1], p.a3 = n.a[2], p.a4 = n.a[3], p.a5 = n.a[4], p.a6 = n.a[5];
  return p;
}
est::LandmarkNoise camera_noise(const MrclamNoise& n) { return {n.sigma_range, n.sigma_bearing, 0.0f}; }
// The noise of a sighting at range r for the filters that know what they see.
est::LandmarkNoise camera_noise_at(const MrclamNoise& n, double r) {
  return {n.range_sigma_0 + n.range_sigma_per_m * static_cast<float>(r), n.sigma_bearing, 0.0f};
}

TimedPose first_truth(const MrclamRobotLog& r) {
  if (r.truth.empty()) throw std::runtime_error("robot " + std::to_string(r.subject) + ": no ground truth");
  return r.truth.front();
}

// The velocity model's mean (the arc of table 5.3 without noise), integrated over each held (v, w).
Trajectory dead_reckoning(const MrclamRobotLog& r) {
  Trajectory out;
  TimedPose x = first_truth(r);
  out.push_back(x);
  for (std::size_t k = 0; k + 1 < r.twists.size(); ++k) {
    const double dt = static_cast<double>(r.twists[k + 1].t_ns - r.twists[k].t_ns) * 1e-9;
    const double v = r.twists[k].v, w = r.twists[k].w;
    if (r.twists[k + 1].t_ns <= x.t_ns) continue;
    if (std::fabs(w) < 1e-9) {
      x.x += v * dt * std::cos(x.theta);
      x.y += v * dt * std::sin(x.theta);
    } else {
      x.x += -v / w * std::sin(x.theta) + v / w * std::sin(x.theta + w * dt);
      x.y += v / w * std::cos(x.theta) - v / w * std::cos(x.theta + w * dt);
      x.theta = wrap_angle(x.theta + w * dt);
    }
    x.t_ns = r.twists[k + 1].t_ns;
    out.push_back(x);
  }
  return out;
}

// One robot through estimator_node's pipeline: the imported log in lockstep, the robot's channels as its inputs.
Trajectory run_node(const MrclamEval& ev, const MrclamRobotLog& r, const std::string& method,
                    const MrclamEvalOptions& o, const std::string& out_dir) {
  node::NodeConfig c;
  c.replay_path = ev.log_path;
  c.out_path = (fs::path(out_dir) / (method + "-robot" + std::to_string(r.subject) + ".lcmlog")).string();
  c.channels.twist = robot_channel("EST_TWIST", r.subject);
  c.channels.landmarks = robot_channel("EST_LANDMARKS", r.subject);
  c.landmarks = ev.import.landmarks_csv;
  c.map = ev.import.arena_yaml;
  c.quiet = true;
  c.status_hz = 0.0;
  node::EstimatorSpec& s = c.spec;
  s.model = node::RobotModel::velocity;
  s.motion.velocity = motion_noise(o.noise);
  s.landmark_noise = camera_noise(o.noise);
  s.ekf_rot_sigma = o.noise.ekf_rot_sigma >= 0.0f ? o.noise.ekf_rot_sigma : o.noise.rot_sigma;
  s.ekf_motion_noise = o.noise.ekf_motion;
  s.ekf_reopen_after = o.noise.reopen_after;
  s.ekf_reopen_sigma_xy = o.noise.reopen_sigma_xy;
  s.ekf_reopen_sigma_theta = o.noise.reopen_sigma_theta;
  s.ambiguity_nats = o.noise.ambiguity_nats;
  s.joint_association = o.noise.joint_association;
  s.lone_pairing_sigma_m = o.noise.lone_pairing_sigma_m;
  const TimedPose x0 = first_truth(r);
  s.initial_pose = {static_cast<float>(x0.x), static_cast<float>(x0.y), static_cast<float>(x0.theta)};
  s.initial_sigma_xy_m = 0.05f;
  s.initial_sigma_theta_rad = 0.05f;
  s.limits.landmarks.max_range_m = 20.0f;
  if (method == "mcl-landmarks") {
    s.filter = est::loop::Filter::mcl;
    s.mcl_landmarks = true;
    s.particles = o.particles;
    s.mcl.recovery = false;  // tracking from the true start: random particles in the open arena only compete
    s.motion.velocity.a4 = o.noise.mcl_a4;
    s.seed = o.seed + static_cast<std::uint64_t>(r.subject);
  } else {
    s.filter = est::loop::Filter::ekf;
    s.landmark_ids = method != "ekf-unknown-correspondence";
    if (s.landmark_ids || s.joint_association) {  // the camera's noise; table 7.3 keeps the constant (MrclamNoise)
      s.landmark_noise.sigma_range = o.noise.range_sigma_0;
      s.landmark_sigma_range_per_m = o.noise.range_sigma_per_m;
    }
  }
  {  // the node closes its output log when it goes: read it after, not while its last events are still buffered
    node::Node n(c);
    if (n.run() != 0) throw std::runtime_error(method + ": estimator_node's replay failed for robot " +
                                               std::to_string(r.subject));
  }
  return read_pose_estimates(c.out_path);
}

// The team: one EKF over every robot's pose (and the landmarks), stepped every 20 ms: each robot's (v, w) held over
// the step predicts its block, then the step's sightings (landmarks, robots) correct it, robot by robot in subject
// order, each in its time order. With `known_landmarks` the surveyed positions enter as priors (cooperative
// localization), else each landmark enters the state at its first sighting (cooperative EKF-SLAM).
using TeamSlam = est::CooperativeEkfSlam<est::VelocityMotionModel, kMrclamRobots, 20>;

struct TeamRun {
  std::vector<Trajectory> estimates;
  std::string detail;
};

TeamRun run_team(const MrclamEval& ev, const std::vector<MrclamRobotLog>& robots, bool known_landmarks,
                 const MrclamNoise& noise) {
  const int R = static_cast<int>(robots.size());
  TeamSlam::Params params;
  params.additive_process_noise(2, 2) = 2.0f * noise.rot_sigma * noise.rot_sigma;  // 20 ms = two 10 ms steps
  auto slam = std::make_unique<TeamSlam>(params);
  std::vector<est::Pose2> means(static_cast<std::size_t>(R));
  std::vector<TeamSlam::RobotCovariance> covs(static_cast<std::size_t>(R));
  for (int a = 0; a < R; ++a) {
    const TimedPose x0 = first_truth(robots[static_cast<std::size_t>(a)]);
    means[static_cast<std::size_t>(a)] = {static_cast<float>(x0.x), static_cast<float>(x0.y),
                                          static_cast<float>(x0.theta)};
    covs[static_cast<std::size_t>(a)] = TeamSlam::RobotCovariance::Identity() * 0.0025f;
  }
  if (!slam->init(R, means.data(), covs.data())) throw std::runtime_error("team filter: init refused");
  if (known_landmarks)
    for (std::size_t k = 0; k < ev.import.landmarks.size(); ++k)
      slam->add_landmark(static_cast<std::int32_t>(k),
                         Eigen::Vector2f(static_cast<float>(ev.import.landmarks[k].x),
                                         static_cast<float>(ev.import.landmarks[k].y)),
                         Eigen::Matrix2f::Identity() * 1.0e-6f);
  int index_of_subject[kMrclamRobots + 1];
  std::fill(std::begin(index_of_subject), std::end(index_of_subject), -1);
  for (int a = 0; a < R; ++a) index_of_subject[robots[static_cast<std::size_t>(a)].subject] = a;

  std::int64_t t_end = 0;
  for (const MrclamRobotLog& r : robots) {
    if (!r.twists.empty()) t_end = std::max(t_end, r.twists.back().t_ns);
    if (!r.landmarks.empty()) t_end = std::max(t_end, r.landmarks.back().t_ns);
  }
  std::vector<std::size_t> twist_i(static_cast<std::size_t>(R), 0), lm_i(static_cast<std::size_t>(R), 0),
      rb_i(static_cast<std::size_t>(R), 0);
  TeamRun run;
  run.estimates.resize(static_cast<std::size_t>(R));
  est::VelocityParams mp = motion_noise(noise);
  mp.dt = static_cast<float>(kTeamStepNs) * 1e-9f;
  std::uint32_t rejected = 0, fused = 0;
  for (std::int64_t t = kTeamStepNs; t <= t_end + kTeamStepNs; t += kTeamStepNs) {
    for (int a = 0; a < R; ++a) {
      const MrclamRobotLog& r = robots[static_cast<std::size_t>(a)];
      std::size_t& i = twist_i[static_cast<std::size_t>(a)];
      while (i + 1 < r.twists.size() && r.twists[i + 1].t_ns <= t - kTeamStepNs) ++i;
      if (r.twists.empty() || r.twists[i].t_ns > t - kTeamStepNs) continue;
      const est::VelocityControl u{static_cast<float>(r.twists[i].v), static_cast<float>(r.twists[i].w)};
      if (u.v == 0.0f && u.w == 0.0f) continue;  // standing still: no diffusion, as the loop's estimators
      slam->predict_robot(a, u, mp);
    }
    for (int a = 0; a < R; ++a) {
      const MrclamRobotLog& r = robots[static_cast<std::size_t>(a)];
      for (std::size_t& i = lm_i[static_cast<std::size_t>(a)]; i < r.landmarks.size() && r.landmarks[i].t_ns <= t;
           ++i) {
        const MrclamSighting& z = r.landmarks[i];
        const est::CorrectionResult c = slam->correct_landmark_range_bearing(
            a, z.id, static_cast<float>(z.range), static_cast<float>(z.bearing), camera_noise_at(noise, z.range));
        (est::accepted(c.status) ? fused : rejected)++;
      }
      for (std::size_t& i = rb_i[static_cast<std::size_t>(a)]; i < r.robots.size() && r.robots[i].t_ns <= t; ++i) {
        const MrclamSighting& z = r.robots[i];
        const int b = z.id >= 1 && z.id <= kMrclamRobots ? index_of_subject[z.id] : -1;
        if (b < 0 || b == a) continue;
        const est::CorrectionResult c = slam->correct_robot_range_bearing(
            a, b, static_cast<float>(z.range), static_cast<float>(z.bearing), camera_noise_at(noise, z.range));
        (est::accepted(c.status) ? fused : rejected)++;
      }
    }
    for (int a = 0; a < R; ++a) {
      const est::Pose2 x = slam->robot(a);
      run.estimates[static_cast<std::size_t>(a)].push_back({t, x.x, x.y, x.theta});
    }
  }
  char buf[256];
  if (known_landmarks) {
    std::snprintf(buf, sizeof buf, "%u measurements fused, %u gated out", fused, rejected);
  } else {
    double se = 0.0;
    int n = 0;
    for (int k = 0; k < slam->landmarks(); ++k) {
      const auto id = static_cast<std::size_t>(slam->landmark_id(k));
      if (id >= ev.import.landmarks.size()) continue;
      const Eigen::Vector2f m = slam->landmark(k);
      const MrclamLandmark& l = ev.import.landmarks[id];
      se += std::pow(double{m.x()} - l.x, 2) + std::pow(double{m.y()} - l.y, 2);
      ++n;
    }
    std::snprintf(buf, sizeof buf, "%d landmarks mapped, RMSE %.3f m against the survey; %u fused, %u gated out", n,
                  n > 0 ? std::sqrt(se / n) : 0.0, fused, rejected);
  }
  run.detail = buf;
  return run;
}

void write_plots(const MrclamEval& ev, const std::vector<MrclamRobotLog>& robots,
                 const std::vector<std::vector<Trajectory>>& estimates, const std::string& dir) {
  const fs::path d(dir);
  {
    std::ofstream lm(d / "landmarks.csv");
    lm << "x y\n";
    for (const MrclamLandmark& l : ev.import.landmarks) lm << l.x << " " << l.y << "\n";
  }
  const char* colors[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e"};
  const std::int64_t t0 = 0;
  for (std::size_t m = 0; m < ev.methods.size(); ++m) {
    for (std::size_t a = 0; a < robots.size(); ++a) {
      std::ofstream tr(d / (ev.methods[m].name + "-robot" + std::to_string(robots[a].subject) + ".csv"));
      tr << "t x y theta err_xy err_theta\n";
      const auto errs = error_series(estimates[m][a], robots[a].truth, kMaxTruthGapNs, t0);
      std::size_t e = 0;
      for (std::size_t k = 0; k < estimates[m][a].size(); k += 10) {
        const TimedPose& p = estimates[m][a][k];
        while (e + 1 < errs.size() && errs[e].t_s < static_cast<double>(p.t_ns) * 1e-9) ++e;
        tr << static_cast<double>(p.t_ns) * 1e-9 << " " << p.x << " " << p.y << " " << p.theta << " "
           << (errs.empty() ? 0.0 : errs[e].xy_m) << " " << (errs.empty() ? 0.0 : errs[e].theta_rad) << "\n";
      }
    }
  }
  for (std::size_t a = 0; a < robots.size(); ++a) {
    std::ofstream gt(d / ("truth-robot" + std::to_string(robots[a].subject) + ".csv"));
    gt << "t x y theta\n";
    for (std::size_t k = 0; k < robots[a].truth.size(); k += 10)
      gt << static_cast<double>(robots[a].truth[k].t_ns) * 1e-9 << " " << robots[a].truth[k].x << " "
         << robots[a].truth[k].y << "\n";
  }
  const int n = static_cast<int>(ev.methods.size());
  {
    // One panel per robot (row) and method (column): a robot's estimate over its own true path, its RMSE in the
    // title. (All five robots in one panel per method hid every path under the others.)
    const int rows = static_cast<int>(robots.size());
    std::ofstream gp(d / "trajectories.gp");
    gp << "set terminal pngcairo size " << 300 * n << "," << 420 * rows << " font ',8'\nset output "
       << "'trajectories.png'\nset multiplot layout " << rows << "," << n
       << " title \"MRCLAM: each robot's estimate (colour) against Vicon (grey), landmarks (black); columns: "
          "methods, rows: robots\"\nset size ratio -1\nset key off\n";
    for (std::size_t a = 0; a < robots.size(); ++a) {
      const std::string id = std::to_string(robots[a].subject);
      for (const MrclamMethodResult& m : ev.methods) {
        const auto r = std::find_if(m.robots.begin(), m.robots.end(),
                                    [&](const MrclamRobotResult& x) { return x.id == robots[a].subject; });
        gp << "set title \"" << m.name << "\\nrobot " << id;
        if (r != m.robots.end() && r->error.n > 0) gp << ": " << fixed(r->error.rmse_xy_m, 3) << " m RMSE";
        gp << "\"\nplot 'truth-robot" << id << ".csv' u 2:3 w l lc rgb 'gray70' lw 2, '" << m.name << "-robot" << id
           << ".csv' u 2:3 w l lc rgb '" << colors[a % 5] << "' lw 1, 'landmarks.csv' u 1:2 w p pt 7 ps 0.6 lc rgb "
           << "'black'\n";
      }
    }
    gp << "unset multiplot\n";
  }
  sim::run_gnuplot(d / "trajectories.gp", d / "trajectories.png");
  {
    std::ofstream gp(d / "errors.gp");
    gp << "set terminal pngcairo size 1100," << 260 * n << " font ',9'\nset output 'errors.png'\nset multiplot "
       << "layout " << n << ",1 title 'MRCLAM: position error against Vicon'\nset ylabel 'm'\nset key outside\n";
    for (const MrclamMethodResult& m : ev.methods) {
      gp << "set title '" << m.name << "'\nplot ";
      for (std::size_t a = 0; a < robots.size(); ++a) {
        const std::string id = std::to_string(robots[a].subject);
        gp << (a ? ", " : "") << "'" << m.name << "-robot" << id << ".csv' u 1:5 w l lc rgb '" << colors[a % 5]
           << "' t 'robot " << id << "'";
      }
      gp << "\n";
    }
    gp << "unset multiplot\n";
  }
  sim::run_gnuplot(d / "errors.gp", d / "errors.png");
}

}  // namespace

const std::vector<std::string>& mrclam_methods() {
  static const std::vector<std::string> m{"dead-reckoning",          "ekf-known-landmarks",
                                          "ekf-unknown-correspondence", "mcl-landmarks",
                                          "cooperative-localization", "cooperative-ekf-slam"};
  return m;
}

MrclamEval eval_mrclam(const std::string& dir, const MrclamEvalOptions& o) {
  const std::vector<std::string> methods = o.methods.empty() ? mrclam_methods() : o.methods;
  for (const std::string& m : methods)
    if (std::find(mrclam_methods().begin(), mrclam_methods().end(), m) == mrclam_methods().end())
      throw std::invalid_argument("unknown method '" + m + "'");
  fs::create_directories(o.out_dir);
  MrclamEval ev;
  ev.options = o;
  ev.log_path = (fs::path(o.out_dir) / "mrclam.lcmlog").string();
  ImportReport report(OnError::skip, o.quiet ? nullptr : stderr);
  MrclamImportOptions io;
  io.max_seconds = o.max_seconds;
  ev.calibration_dir = o.calibration_dir;
  if (ev.calibration_dir == "auto") {
    const fs::path here = fs::path(dir).lexically_normal();
    const std::string name = (here.has_filename() ? here : here.parent_path()).filename().string();
    const std::string other = name == "MRCLAM_Dataset1" ? "MRCLAM_Dataset2" : "MRCLAM_Dataset1";
    const fs::path sibling = (here.has_filename() ? here : here.parent_path()).parent_path() / other;
    ev.calibration_dir = (name == "MRCLAM_Dataset1" || name == "MRCLAM_Dataset2") && fs::exists(sibling)
                             ? sibling.string()
                             : std::string();
  }
  if (!ev.calibration_dir.empty()) {
    if (fs::equivalent(ev.calibration_dir, dir))
      throw std::invalid_argument("the odometry calibration must come from another dataset than the one evaluated");
    ev.scales = fit_mrclam_odometry_scales(ev.calibration_dir);
    std::copy(std::begin(ev.scales.v), std::end(ev.scales.v), io.scale_v);
    std::copy(std::begin(ev.scales.w), std::end(ev.scales.w), io.scale_w);
    std::copy(std::begin(ev.scales.lag_s), std::end(ev.scales.lag_s), io.lag_s);
  }
  ev.import = import_mrclam(dir, ev.log_path, io, report);
  if (!ev.import.has_ground_truth)
    throw std::runtime_error(dir + ": no ground truth to evaluate against (use the sampled-50hz layout)");
  const std::vector<MrclamRobotLog> robots = read_mrclam_log(ev.log_path, io.robots);

  std::vector<std::vector<Trajectory>> estimates;
  Progress progress("eval mrclam", static_cast<double>(methods.size() * robots.size()), o.quiet);
  double done = 0.0;
  for (const std::string& name : methods) {
    MrclamMethodResult m;
    m.name = name;
    const double start = wall_seconds();
    std::vector<Trajectory> est(robots.size());
    if (name == "cooperative-localization" || name == "cooperative-ekf-slam") {
      TeamRun t = run_team(ev, robots, name == "cooperative-localization", o.noise);
      est = std::move(t.estimates);
      m.detail = t.detail;
      progress.update(done += static_cast<double>(robots.size()));
    } else {
      for (std::size_t a = 0; a < robots.size(); ++a) {
        est[a] = name == "dead-reckoning" ? dead_reckoning(robots[a]) : run_node(ev, robots[a], name, o, o.out_dir);
        progress.update(done += 1.0);
      }
    }
    m.run_time_s = wall_seconds() - start;
    for (std::size_t a = 0; a < robots.size(); ++a)
      m.robots.push_back({robots[a].subject, trajectory_error(est[a], robots[a].truth, kMaxTruthGapNs)});
    ev.methods.push_back(std::move(m));
    estimates.push_back(std::move(est));
  }
  progress.finish();
  if (o.plots) write_plots(ev, robots, estimates, o.out_dir);
  return ev;
}

nlohmann::json to_json(const MrclamEval& ev) {
  nlohmann::json methods = nlohmann::json::array();
  for (const MrclamMethodResult& m : ev.methods) {
    nlohmann::json robots = nlohmann::json::array();
    for (const MrclamRobotResult& r : m.robots)
      robots.push_back({{"id", r.id},
                        {"rmse_xy_m", r.error.rmse_xy_m},
                        {"rmse_theta_rad", r.error.rmse_theta_rad},
                        {"max_xy_m", r.error.max_xy_m},
                        {"estimates", r.error.n}});
    methods.push_back({{"name", m.name}, {"robots", robots}, {"run_time_s", m.run_time_s}, {"detail", m.detail}});
  }
  nlohmann::json scales = nlohmann::json::array();
  for (int r = 1; r <= kMrclamRobots; ++r) scales.push_back({{"id", r}, {"v", ev.scales.v[r]}, {"w", ev.scales.w[r]}, {"lag_s", ev.scales.lag_s[r]}});
  const MrclamNoise& n = ev.options.noise;
  const nlohmann::json settings = {
      {"motion_noise_a", std::vector<float>(std::begin(n.a), std::end(n.a))},
      {"mcl_a4", n.mcl_a4},
      {"rot_sigma_rad", n.rot_sigma},
      {"sigma_range_m", n.sigma_range},
      {"sigma_bearing_rad", n.sigma_bearing},
      {"range_sigma_0_m", n.range_sigma_0},
      {"range_sigma_per_m", n.range_sigma_per_m},
      {"association", n.joint_association ? "jcbb" : "ml"},
      {"ambiguity_nats", n.ambiguity_nats},
      {"lone_pairing_sigma_m", n.lone_pairing_sigma_m},
      {"ekf_rot_sigma_rad", n.ekf_rot_sigma},
      {"ekf_heading_noise_per_rad", n.ekf_motion.heading_per_rad},
      {"ekf_heading_noise_per_m", n.ekf_motion.heading_per_m},
      {"ekf_along_noise_per_m", n.ekf_motion.along_per_m},
      {"ekf_cross_noise_per_m", n.ekf_motion.cross_per_m},
      {"reopen_after", n.reopen_after},
      {"reopen_sigma_xy_m", n.reopen_sigma_xy},
      {"reopen_sigma_theta_rad", n.reopen_sigma_theta},
      {"particles", ev.options.particles},
      {"seed", ev.options.seed},
      {"max_seconds", ev.options.max_seconds}};
  return {{"dataset", ev.import.dataset},
          {"settings", settings},
          {"odometry_calibration", {{"fitted_on", ev.calibration_dir}, {"scales", scales}}},
          {"layout", ev.import.sampled ? "sampled-50hz" : "raw"},
          {"duration_s", ev.import.duration_s},
          {"methods", methods}};
}

void add_mrclam_eval(CLI::App& eval) {
  CLI::App* cmd = eval.add_subcommand(
      "mrclam", "UTIAS MRCLAM against Vicon, per robot: dead reckoning, EKF localization (known and unknown "
                "correspondence), MCL on the landmarks, cooperative localization, cooperative EKF-SLAM");
  auto dir = std::make_shared<std::string>();
  auto opts = std::make_shared<MrclamEvalOptions>();
  auto json = std::make_shared<bool>(false);
  cmd->add_option("DIR", *dir, "a dataset folder with ground truth (sampled-50hz/MRCLAM_DatasetN)")
      ->required()->check(CLI::ExistingDirectory);
  cmd->add_option("--out", opts->out_dir, "folder for the imported log, the estimates, plots and results.json")
      ->capture_default_str();
  cmd->add_option("--seconds", opts->max_seconds, "only the first seconds (0: all)")->capture_default_str();
  cmd->add_option("--methods", opts->methods, "methods to run (default: all)")->delimiter(',');
  cmd->add_option("--particles", opts->particles, "MCL's particles")->capture_default_str();
  cmd->add_option("--seed", opts->seed, "MCL's seed")->capture_default_str();
  cmd->add_option("--calibrate-on", opts->calibration_dir,
                  "fit the odometry scales on this sampled-50hz folder ('auto': the other of Datasets 1 and 2; "
                  "'': none, the commanded (v, w) as they are)")->capture_default_str();
  cmd->add_option("--sigma-range", opts->noise.sigma_range,
                  "camera range noise (m), constant: MCL and --association ml")->capture_default_str();
  cmd->add_option("--range-sigma-0", opts->noise.range_sigma_0,
                  "the EKFs' (but --association ml's) and the team's range noise at range 0 (m)")->capture_default_str();
  cmd->add_option("--range-sigma-per-m", opts->noise.range_sigma_per_m,
                  "the EKFs' (but --association ml's) and the team's range noise growth per metre of range")
      ->capture_default_str();
  cmd->add_option("--sigma-bearing", opts->noise.sigma_bearing, "camera bearing noise (rad)")->capture_default_str();
  cmd->add_option("--ambiguity-nats", opts->noise.ambiguity_nats,
                  "unknown correspondence: refuse a sighting (ml) or a frame's disputed pairings (jcbb) whose runner-up "
                  "landmark or assignment is this close (log likelihood)")
      ->capture_default_str();
  cmd->add_option("--lone-pairing-sigma", opts->noise.lone_pairing_sigma_m,
                  "unknown correspondence, jcbb: a frame pairing one sighting, another landmark in its gate, is not "
                  "fused while the position's deviation is above this (m; 0: always fused)")
      ->capture_default_str()->check(CLI::NonNegativeNumber);
  cmd->add_option_function<std::string>(
         "--association",
         [opts](const std::string& v) {
           if (v != "jcbb" && v != "ml") throw CLI::ValidationError("--association", "jcbb or ml");
           opts->noise.joint_association = v == "jcbb";
         },
         "unknown correspondence: jcbb: each camera frame's sightings jointly (joint compatibility branch and bound); "
         "ml: one at a time by maximum likelihood (table 7.3)")
      ->default_str("jcbb");
  cmd->add_option("--rot-sigma", opts->noise.rot_sigma, "heading noise per 10 ms prediction (rad)")
      ->capture_default_str();
  auto a = std::make_shared<std::vector<float>>(std::begin(opts->noise.a), std::end(opts->noise.a));
  cmd->add_option("--motion-noise", *a, "the velocity model's a1..a6")->delimiter(',')->expected(6)
      ->default_str("0.5,0.05,0.3,0.5,0.01,0.01");
  cmd->add_option("--mcl-rotation-noise", opts->noise.mcl_a4,
                  "MCL's a4 (variance of w per w^2) in place of --motion-noise's: the book's noise, drawn at each "
                  "prediction, spreads a turn's heading with the root of the step")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--ekf-rot-sigma", opts->noise.ekf_rot_sigma,
                  "the single-robot EKFs' heading noise per 10 ms prediction (rad; < 0: --rot-sigma)")
      ->capture_default_str();
  cmd->add_option("--ekf-heading-noise-per-rad", opts->noise.ekf_motion.heading_per_rad,
                  "the single-robot EKFs' heading variance per radian turned (rad^2 / rad)")->capture_default_str();
  cmd->add_option("--ekf-heading-noise-per-m", opts->noise.ekf_motion.heading_per_m,
                  "the single-robot EKFs' heading variance per metre driven (rad^2 / m)")->capture_default_str();
  cmd->add_option("--ekf-along-noise-per-m", opts->noise.ekf_motion.along_per_m,
                  "the single-robot EKFs' along-track variance per metre driven (m^2 / m)")->capture_default_str();
  cmd->add_option("--ekf-cross-noise-per-m", opts->noise.ekf_motion.cross_per_m,
                  "the single-robot EKFs' cross-track variance per metre driven (m^2 / m)")->capture_default_str();
  cmd->add_option("--reopen-after", opts->noise.reopen_after,
                  "the single-robot EKFs: consecutive gate refusals (known landmarks) or frames without a pairing (unknown correspondence) that re-open the gate (0: never)")->capture_default_str();
  cmd->add_option("--reopen-sigma-xy", opts->noise.reopen_sigma_xy, "position deviation added when it re-opens (m)")
      ->capture_default_str();
  cmd->add_option("--reopen-sigma-theta", opts->noise.reopen_sigma_theta, "heading deviation added (rad)")
      ->capture_default_str();
  cmd->add_flag("--json", *json, "print the results as JSON on stdout instead of the table");
  cmd->add_flag("--no-plots", [opts](std::int64_t) { opts->plots = false; }, "skip the PNGs");
  cmd->add_flag("--quiet", opts->quiet, "no progress, no import diagnostics");
  cmd->callback([=] {
    std::copy(a->begin(), a->end(), opts->noise.a);
    const MrclamEval ev = eval_mrclam(*dir, *opts);
    const nlohmann::json j = to_json(ev);
    write_json((fs::path(opts->out_dir) / "results.json").string(), j);
    if (*json) {
      std::printf("%s\n", j.dump(2).c_str());
      return;
    }
    std::printf("eval mrclam: %s (dataset %d, %.0f s), position / heading RMSE against Vicon\n", dir->c_str(),
                ev.import.dataset, ev.import.duration_s);
    std::vector<std::string> header{"method"};
    for (const MrclamRobotResult& r : ev.methods.front().robots) header.push_back("robot " + std::to_string(r.id));
    header.push_back("mean");
    header.push_back("run time");
    std::vector<std::vector<std::string>> rows;
    for (const MrclamMethodResult& m : ev.methods) {
      std::vector<std::string> row{m.name};
      double sum = 0.0;
      for (const MrclamRobotResult& r : m.robots) {
        row.push_back(fixed(r.error.rmse_xy_m, 3) + " m / " + fixed(r.error.rmse_theta_rad, 3));
        sum += r.error.rmse_xy_m;
      }
      row.push_back(fixed(sum / static_cast<double>(m.robots.size()), 3) + " m");
      row.push_back(fixed(m.run_time_s, 1) + " s");
      rows.push_back(std::move(row));
    }
    print_table(stdout, header, rows);
    if (!ev.calibration_dir.empty()) {
      std::printf("  odometry calibration fitted on %s (v, w scale and lag by robot):", ev.calibration_dir.c_str());
      for (int r = 1; r <= kMrclamRobots; ++r)
        std::printf(" %d: %.3f, %.3f, %.2f s", r, ev.scales.v[r], ev.scales.w[r], ev.scales.lag_s[r]);
      std::printf("\n");
    }
    for (const MrclamMethodResult& m : ev.methods)
      if (!m.detail.empty()) std::printf("  %s: %s\n", m.name.c_str(), m.detail.c_str());
    std::printf("  results: %s/results.json; plots: %s/trajectories.png, errors.png; log: %s\n",
                opts->out_dir.c_str(), opts->out_dir.c_str(), ev.log_path.c_str());
  });
}

}  // namespace sim::data

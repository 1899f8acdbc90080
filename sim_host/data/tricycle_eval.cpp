// sim_host eval tricycle (data/tricycle_eval.hpp).
#include "data/tricycle_eval.hpp"

#include <CLI/CLI.hpp>
#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <stdexcept>

#include "data/formats.hpp"
#include "est/motion/bicycle_model.hpp"
#include "node/node.hpp"
#include "sim/plot.hpp"

namespace sim::data {
namespace {

namespace fs = std::filesystem;

constexpr int kParams = 7;  // ksteer, ktraction, axis_length, steer_offset, laser_x, laser_y, laser_theta
constexpr std::int64_t kMaxTrackerGapNs = 200000000;
constexpr float kSteerStop = 1.55f;  // rad: the fit's angles reach 75 deg; the model's stop must not clamp them

using Vec = Eigen::Matrix<double, kParams, 1>;


Vec to_vector(const TricycleParams& p) {
  Vec v;
  v << p.ksteer, p.ktraction, p.axis_length, p.steer_offset, p.laser_x, p.laser_y, p.laser_theta;
  return v;
}
TricycleParams from_vector(const Vec& v) {
  return {v(0), v(1), v(2), v(3), v(4), v(5), v(6)};
}

struct P2 {
  double x = 0.0, y = 0.0, t = 0.0;
};
P2 compose(const P2& a, const P2& b) {
  const double c = std::cos(a.t), s = std::sin(a.t);
  return {a.x + c * b.x - s * b.y, a.y + s * b.x + c * b.y, wrap_angle(a.t + b.t)};
}
P2 inverse(const P2& a) {
  const double c = std::cos(a.t), s = std::sin(a.t);
  return {-c * a.x - s * a.y, s * a.x - c * a.y, wrap_angle(-a.t)};
}
P2 pose_of(const TimedPose& p) { return {p.x, p.y, p.theta}; }
P2 sensor_of(const TricycleParams& p) { return {p.laser_x, p.laser_y, p.laser_theta}; }

double travel(const std::vector<TricycleRecord>& r, std::size_t k, const TricycleParams& p, const TricycleHeader& h) {
  return p.ktraction * static_cast<double>(traction_increment(r[k - 1].traction_ticks, r[k].traction_ticks)) /
         static_cast<double>(h.traction_max);
}

// The base's motion over records [i, j) in double: the bicycle's chord form (est/motion/bicycle_model.hpp) at the
// front wheel, the steering held from the step's start; base_link is l behind the front wheel.
P2 base_motion(const std::vector<TricycleRecord>& r, std::size_t i, std::size_t j, const TricycleParams& p,
               const TricycleHeader& h) {
  const double l = p.axis_length;
  P2 f{l, 0.0, 0.0};
  for (std::size_t k = i + 1; k <= j; ++k) {
    const double s = travel(r, k, p, h);
    const double a = tricycle_steering_angle(r[k - 1].steer_ticks, p, h.steer_max);
    const double half = 0.5 * s * std::sin(a) / l;
    const double sinc = std::fabs(half) < 1e-9 ? 1.0 : std::sin(half) / half;
    f.x += s * sinc * std::cos(f.t + a + half);
    f.y += s * sinc * std::sin(f.t + a + half);
    f.t += 2.0 * half;
  }
  return {f.x - l * std::cos(f.t), f.y - l * std::sin(f.t), wrap_angle(f.t)};
}

// The windows of `window` records in [from, to), every window / 5 records (overlapping: more residuals, same data).
std::vector<std::size_t> window_starts(std::size_t from, std::size_t to, int window, int stride) {
  std::vector<std::size_t> out;
  for (std::size_t i = from; i + static_cast<std::size_t>(window) < to; i += static_cast<std::size_t>(stride))
    out.push_back(i);
  return out;
}

// The sensor's relative motion predicted against the tracker's, per window: (dx, dy, dtheta).
Eigen::VectorXd residuals(const std::vector<TricycleRecord>& r, const std::vector<std::size_t>& starts, int window,
                          const TricycleParams& p, const TricycleHeader& h) {
  Eigen::VectorXd e(3 * static_cast<Eigen::Index>(starts.size()));
  const P2 L = sensor_of(p), Linv = inverse(L);
  for (std::size_t w = 0; w < starts.size(); ++w) {
    const std::size_t i = starts[w], j = i + static_cast<std::size_t>(window);
    const P2 predicted = compose(compose(Linv, base_motion(r, i, j, p, h)), L);
    const P2 tracked = compose(inverse(pose_of(r[i].tracker)), pose_of(r[j].tracker));
    const auto k = static_cast<Eigen::Index>(3 * w);
    e(k) = predicted.x - tracked.x;
    e(k + 1) = predicted.y - tracked.y;
    e(k + 2) = wrap_angle(predicted.t - tracked.t);
  }
  return e;
}

struct Fit {
  TricycleParams params;
  double cost_before = 0.0, cost_after = 0.0;
  int iterations = 0;
};

// Levenberg-Marquardt on the window residuals, central-difference Jacobian.
Fit levenberg_marquardt(const std::vector<TricycleRecord>& r, const std::vector<std::size_t>& starts, int window,
                        const TricycleParams& guess, const TricycleHeader& h, int max_iterations) {
  Vec x = to_vector(guess);
  Eigen::VectorXd e = residuals(r, starts, window, from_vector(x), h);
  Fit fit;
  fit.cost_before = e.squaredNorm();
  double cost = fit.cost_before, lambda = 1e-3;
  for (int it = 0; it < max_iterations; ++it) {
    Eigen::MatrixXd J(e.size(), kParams);
    for (int c = 0; c < kParams; ++c) {
      const double step = 1e-6 * std::max(std::fabs(x(c)), 1e-2);
      Vec a = x, b = x;
      a(c) += step;
      b(c) -= step;
      J.col(c) = (residuals(r, starts, window, from_vector(a), h) - residuals(r, starts, window, from_vector(b), h)) /
                 (2.0 * step);
    }
    const Eigen::Matrix<double, kParams, kParams> A = J.transpose() * J;
    const Vec g = J.transpose() * e;
    bool improved = false;
    for (int tries = 0; tries < 12 && !improved; ++tries) {
      Eigen::Matrix<double, kParams, kParams> damped = A;
      damped.diagonal() += lambda * A.diagonal().cwiseMax(1e-12);
      const Vec dx = damped.ldlt().solve(-g);
      const Vec xn = x + dx;
      if (!(xn(2) > 0.1)) {  // a frame length must stay positive
        lambda *= 10.0;
        continue;
      }
      const Eigen::VectorXd en = residuals(r, starts, window, from_vector(xn), h);
      if (en.allFinite() && en.squaredNorm() < cost) {
        const double gain = cost - en.squaredNorm();
        x = xn, e = en, cost = en.squaredNorm();
        lambda = std::max(lambda * 0.3, 1e-9);
        improved = true;
        fit.iterations = it + 1;
        if (gain < 1e-12 * std::max(cost, 1e-12)) it = max_iterations;
      } else {
        lambda *= 10.0;
      }
    }
    if (!improved) break;
  }
  x(6) = wrap_angle(x(6));
  fit.params = from_vector(x);
  fit.cost_after = cost;
  return fit;
}

void write_plots(const TricycleEval& ev, const std::vector<TricycleRecord>& r, std::size_t split,
                 const std::string& dir) {
  const fs::path d(dir);
  struct Part {
    const char* name;
    std::size_t from, to;  // records [from, to)
  };
  const Part parts[] = {{"fit", 0, split}, {"held-out", split, r.size()}};
  Trajectory tracker;
  for (const TricycleRecord& k : r) tracker.push_back(k.tracker);
  for (const Part& part : parts) {
    // Each part's own stretch of the tracked path, for its panel (the whole path hid which part was which).
    std::ofstream f(d / ("tracker-" + std::string(part.name) + ".csv"));
    f << "t x y theta\n";
    for (std::size_t k = part.from; k < part.to && k < r.size(); ++k)
      f << static_cast<double>(r[k].t_ns) * 1e-9 << " " << r[k].tracker.x << " " << r[k].tracker.y << " "
        << r[k].tracker.theta << "\n";
  }
  const std::pair<const char*, const TricycleParams*> sets[] = {{"before", &ev.before}, {"after", &ev.after}};
  for (const auto& [name, p] : sets) {
    for (const Part& part : parts) {
      const Trajectory odo = tricycle_odometry(r, *p, ev.import.header, part.from, part.to);
      const auto errs = error_series(odo, tracker, kMaxTrackerGapNs, 0);
      std::ofstream f(d / (std::string(name) + "-" + part.name + ".csv"));
      f << "t x y theta err_xy err_theta\n";
      for (std::size_t k = 0; k < odo.size() && k < errs.size(); ++k)
        f << static_cast<double>(odo[k].t_ns) * 1e-9 << " " << odo[k].x << " " << odo[k].y << " " << odo[k].theta
          << " " << errs[k].xy_m << " " << errs[k].theta_rad << "\n";
    }
  }
  {
    std::ofstream gp(d / "trajectories.gp");
    gp << "set terminal pngcairo size 1400,600 font ',9'\nset output 'trajectories.png'\nset multiplot layout 1,2 "
          "title 'tricycle: sensor odometry (each part from its first tracked pose) against the tracker'\n"
          "set size ratio -1\nset key outside bottom\nset xlabel 'x (m)'\nset ylabel 'y (m)'\n";
    for (const Part& part : parts) {
      gp << "set title '" << part.name << " part'\nplot 'tracker-" << part.name << ".csv' u 2:3 w l lc rgb 'gray60' "
         << "lw 2 t 'tracker', 'before-" << part.name << ".csv' u 2:3 w l lc rgb '#d62728' t 'header guesses', 'after-"
         << part.name << ".csv' u 2:3 w l lc rgb '#1f77b4' t 'calibrated'\n";
    }
    gp << "unset multiplot\n";
  }
  sim::run_gnuplot(d / "trajectories.gp", d / "trajectories.png");
  {
    std::ofstream gp(d / "errors.gp");
    gp << "set terminal pngcairo size 1100,500 font ',9'\nset output 'errors.png'\nset title 'tricycle: position "
          "error of the dead-reckoned sensor against the tracker (fit part, then held-out part from its start)'\n"
          "set xlabel 't (s)'\nset ylabel 'm'\nset logscale y\nset key top left\nset arrow from "
       << ev.split_t_s << ", graph 0 to " << ev.split_t_s << ", graph 1 nohead dt 2\n"
       << "plot 'before-fit.csv' u 1:($5+1e-4) w l lc rgb '#d62728' t 'header guesses', 'before-held-out.csv' u "
          "1:($5+1e-4) w l lc rgb '#d62728' notitle, 'after-fit.csv' u 1:($5+1e-4) w l lc rgb '#1f77b4' t "
          "'calibrated', 'after-held-out.csv' u 1:($5+1e-4) w l lc rgb '#1f77b4' notitle\n";
  }
  sim::run_gnuplot(d / "errors.gp", d / "errors.png");
}

nlohmann::json params_json(const TricycleParams& p, const TricycleHeader& h) {
  return {{"ksteer", p.ksteer},
          {"ktraction", p.ktraction},
          {"axis_length_m", p.axis_length},
          {"steer_offset_rad", p.steer_offset},
          {"laser_x_m", p.laser_x},
          {"laser_y_m", p.laser_y},
          {"laser_theta_rad", p.laser_theta},
          {"rad_per_steer_tick", p.ksteer * 2.0 * M_PI / static_cast<double>(h.steer_max)},
          {"m_per_traction_tick", p.ktraction / static_cast<double>(h.traction_max)}};
}

nlohmann::json error_json(const OdometryError& e) {
  return {{"rmse_xy_m", e.trajectory.rmse_xy_m},
          {"rmse_theta_rad", e.trajectory.rmse_theta_rad},
          {"max_xy_m", e.trajectory.max_xy_m},
          {"final_xy_m", e.trajectory.final_xy_m},
          {"window_rmse_xy_m", e.window_rmse_xy_m},
          {"window_rmse_theta_rad", e.window_rmse_theta_rad},
          {"windows", e.windows}};
}

}  // namespace

Trajectory tricycle_odometry(const std::vector<TricycleRecord>& r, const TricycleParams& p, const TricycleHeader& h,
                             std::size_t from, std::size_t to) {
  Trajectory out;
  if (from >= to || to > r.size()) return out;
  const P2 L = sensor_of(p);
  const P2 base = compose(pose_of(r[from].tracker), inverse(L));
  const float l = static_cast<float>(p.axis_length);
  est::Pose2 front{static_cast<float>(base.x + p.axis_length * std::cos(base.t)),
                   static_cast<float>(base.y + p.axis_length * std::sin(base.t)), static_cast<float>(base.t)};
  const auto sensor = [&](std::int64_t t_ns) {
    const P2 b{front.x - l * std::cos(front.theta), front.y - l * std::sin(front.theta), front.theta};
    const P2 s = compose(b, L);
    return TimedPose{t_ns, s.x, s.y, s.t};
  };
  out.push_back(sensor(r[from].t_ns));
  est::BicycleParams bp;
  bp.frame_length = l;
  bp.steer_max = kSteerStop;
  for (std::size_t k = from + 1; k < to; ++k) {
    bp.dt = static_cast<float>(static_cast<double>(r[k].t_ns - r[k - 1].t_ns) * 1e-9);
    const est::BicycleControl u{static_cast<float>(travel(r, k, p, h) / static_cast<double>(bp.dt)),
                                static_cast<float>(tricycle_steering_angle(r[k - 1].steer_ticks, p, h.steer_max))};
    front = est::predict_motion_bicycle(front, u, bp);
    out.push_back(sensor(r[k].t_ns));
  }
  return out;
}

TimedPose tricycle_front_wheel(const TimedPose& sensor, const TricycleParams& p) {
  const P2 base = compose(pose_of(sensor), inverse(sensor_of(p)));
  return {sensor.t_ns, base.x + p.axis_length * std::cos(base.t), base.y + p.axis_length * std::sin(base.t), base.t};
}

Trajectory tricycle_node_odometry(const std::string& log, const std::vector<TricycleRecord>& r,
                                  const TricycleParams& p, const TricycleHeader& h, const std::string& out_log) {
  if (r.empty()) return {};
  const P2 L = sensor_of(p);
  const TimedPose front = tricycle_front_wheel(r.front().tracker, p);
  node::NodeConfig c;
  c.replay_path = log;
  c.out_path = out_log;
  c.quiet = true;
  c.status_hz = 0.0;
  c.lcm_wheel_counter_bits = 32;  // the traction counter as read, wrapping at 2^32
  node::EstimatorSpec& s = c.spec;
  s.model = node::RobotModel::bicycle;
  s.filter = est::loop::Filter::ekf;
  s.motion.bicycle.frame_length = static_cast<float>(p.axis_length);
  s.motion.bicycle.steer_max = kSteerStop;
  s.motion.bicycle_control.metres_per_tick = static_cast<float>(p.ktraction / static_cast<double>(h.traction_max));
  s.limits.wheels.wheel_count = 1;
  s.limits.wheels.max_ticks_per_s = 1000000;
  s.limits.steering.max_angle_rad = kSteerStop;
  s.initial_pose = {static_cast<float>(front.x), static_cast<float>(front.y), static_cast<float>(front.theta)};
  node::Node n(c);
  if (n.run() != 0) throw std::runtime_error("tricycle: estimator_node's replay of " + log + " failed");
  if (n.rejects_total() != 0)
    throw std::runtime_error("tricycle: estimator_node's replay rejected " + std::to_string(n.rejects_total()) +
                             " inputs of " + log);
  Trajectory out;
  for (const TimedPose& f : read_pose_estimates(out_log)) {
    const P2 b{f.x - p.axis_length * std::cos(f.theta), f.y - p.axis_length * std::sin(f.theta), f.theta};
    const P2 sp = compose(b, L);
    out.push_back({f.t_ns, sp.x, sp.y, sp.t});
  }
  return out;
}

OdometryError tricycle_odometry_error(const std::vector<TricycleRecord>& r, const TricycleParams& p,
                                      const TricycleHeader& h, std::size_t from, std::size_t to, int window) {
  OdometryError e;
  Trajectory tracker;
  for (std::size_t k = from; k < to; ++k) tracker.push_back(r[k].tracker);
  e.trajectory = trajectory_error(tricycle_odometry(r, p, h, from, to), tracker, kMaxTrackerGapNs);
  const std::vector<std::size_t> starts = window_starts(from, to, window, window);
  const Eigen::VectorXd res = residuals(r, starts, window, p, h);
  double sxy = 0.0, sth = 0.0;
  for (std::size_t w = 0; w < starts.size(); ++w) {
    const auto k = static_cast<Eigen::Index>(3 * w);
    sxy += res(k) * res(k) + res(k + 1) * res(k + 1);
    sth += res(k + 2) * res(k + 2);
  }
  e.windows = starts.size();
  if (e.windows > 0) {
    e.window_rmse_xy_m = std::sqrt(sxy / static_cast<double>(e.windows));
    e.window_rmse_theta_rad = std::sqrt(sth / static_cast<double>(e.windows));
  }
  return e;
}

TricycleEval eval_tricycle(const std::string& file, const TricycleEvalOptions& o) {
  if (!(o.fit_fraction > 0.0 && o.fit_fraction < 1.0)) throw std::invalid_argument("the fit fraction is in (0, 1)");
  if (o.window < 2) throw std::invalid_argument("a window holds at least 2 records");
  const double start = wall_seconds();
  fs::create_directories(o.out_dir);
  TricycleEval ev;
  ev.log_path = (fs::path(o.out_dir) / "tricycle.lcmlog").string();
  ImportReport report(OnError::skip, o.quiet ? nullptr : stderr);
  TricycleImportOptions io;
  io.max_seconds = o.max_seconds;
  ev.import = import_tricycle(file, ev.log_path, io, report);
  const std::vector<TricycleRecord> r = read_tricycle_log(ev.log_path);
  const auto split = static_cast<std::size_t>(o.fit_fraction * static_cast<double>(r.size()));
  if (split < static_cast<std::size_t>(2 * o.window) || r.size() - split < static_cast<std::size_t>(2 * o.window))
    throw std::runtime_error(file + ": too few records for a fit part and a held-out part");
  ev.fit_records = split;
  ev.held_out_records = r.size() - split;
  ev.split_t_s = static_cast<double>(r[split].t_ns) * 1e-9;
  ev.before = ev.import.header.guess;

  Progress progress("eval tricycle", 1.0, o.quiet);
  const std::vector<std::size_t> starts = window_starts(0, split, o.window, std::max(1, o.window / 5));
  const Fit fit = levenberg_marquardt(r, starts, o.window, ev.before, ev.import.header, o.max_iterations);
  progress.update(0.9);
  ev.after = fit.params;
  ev.cost_before = fit.cost_before;
  ev.cost_after = fit.cost_after;
  ev.iterations = fit.iterations;
  const TricycleHeader& h = ev.import.header;
  ev.fit_before = tricycle_odometry_error(r, ev.before, h, 0, split, o.window);
  ev.fit_after = tricycle_odometry_error(r, ev.after, h, 0, split, o.window);
  ev.held_before = tricycle_odometry_error(r, ev.before, h, split, r.size(), o.window);
  ev.held_after = tricycle_odometry_error(r, ev.after, h, split, r.size(), o.window);
  {
    // The user's path: the log imported with the calibrated steering, replayed through estimator_node's pipeline.
    TricycleImportOptions cal = io;
    cal.calibrated = true;
    cal.params = ev.after;
    ImportReport quiet(OnError::skip, nullptr);
    const std::string cal_log = (fs::path(o.out_dir) / "tricycle-calibrated.lcmlog").string();
    import_tricycle(file, cal_log, cal, quiet);
    ev.node_log_path = (fs::path(o.out_dir) / "tricycle-node-estimates.lcmlog").string();
    const Trajectory node_odo = tricycle_node_odometry(cal_log, r, ev.after, h, ev.node_log_path);
    Trajectory tracker;
    for (const TricycleRecord& k : r) tracker.push_back(k.tracker);
    ev.node_after = trajectory_error(node_odo, tracker, kMaxTrackerGapNs);
    ev.node_vs_direct_rmse_m =
        trajectory_error(node_odo, tricycle_odometry(r, ev.after, h, 0, r.size()), kMaxTrackerGapNs).rmse_xy_m;
  }
  progress.finish();
  ev.run_time_s = wall_seconds() - start;
  if (o.plots) write_plots(ev, r, split, o.out_dir);
  return ev;
}

nlohmann::json to_json(const TricycleEval& ev) {
  const TricycleHeader& h = ev.import.header;
  return {{"records", ev.import.records},
          {"duration_s", ev.import.duration_s},
          {"fit_records", ev.fit_records},
          {"held_out_records", ev.held_out_records},
          {"held_out_from_s", ev.split_t_s},
          {"before", params_json(ev.before, h)},
          {"after", params_json(ev.after, h)},
          {"fit", {{"iterations", ev.iterations}, {"cost_before", ev.cost_before}, {"cost_after", ev.cost_after}}},
          {"odometry_error",
           {{"fit_part", {{"before", error_json(ev.fit_before)}, {"after", error_json(ev.fit_after)}}},
            {"held_out", {{"before", error_json(ev.held_before)}, {"after", error_json(ev.held_after)}}}}},
          {"estimator_node_replay",
           {{"rmse_xy_m", ev.node_after.rmse_xy_m},
            {"rmse_theta_rad", ev.node_after.rmse_theta_rad},
            {"final_xy_m", ev.node_after.final_xy_m},
            {"rmse_against_direct_m", ev.node_vs_direct_rmse_m}}},
          {"run_time_s", ev.run_time_s}};
}

void add_tricycle_eval(CLI::App& eval) {
  CLI::App* cmd = eval.add_subcommand(
      "tricycle", "Calibrate the front-steered model on the tricycle set (steering offset and scale, traction ticks "
                  "to metres, axle length, sensor pose) by least squares against the tracked sensor pose; the "
                  "odometry error before and after on a held-out part");
  auto file = std::make_shared<std::string>();
  auto opts = std::make_shared<TricycleEvalOptions>();
  auto json = std::make_shared<bool>(false);
  cmd->add_option("FILE", *file, "the dataset's dataset.txt")->required()->check(CLI::ExistingFile);
  cmd->add_option("--out", opts->out_dir, "folder for the imported log, plots and results.json")->capture_default_str();
  cmd->add_option("--fit-fraction", opts->fit_fraction, "the first part of the records that fits; the rest is held "
                                                        "out")->capture_default_str();
  cmd->add_option("--window", opts->window, "records per relative-motion residual")->capture_default_str();
  cmd->add_option("--seconds", opts->max_seconds, "only the first seconds (0: all)")->capture_default_str();
  cmd->add_flag("--json", *json, "print the results as JSON on stdout instead of the table");
  cmd->add_flag("--no-plots", [opts](std::int64_t) { opts->plots = false; }, "skip the PNGs");
  cmd->add_flag("--quiet", opts->quiet, "no progress, no import diagnostics");
  cmd->callback([=] {
    const TricycleEval ev = eval_tricycle(*file, *opts);
    const nlohmann::json j = to_json(ev);
    write_json((fs::path(opts->out_dir) / "results.json").string(), j);
    if (*json) {
      std::printf("%s\n", j.dump(2).c_str());
      return;
    }
    std::printf("eval tricycle: %s (%llu records, %.1f s); fit on the first %zu records, held out from t = %.1f s "
                "(%zu records)\n", file->c_str(), static_cast<unsigned long long>(ev.import.records),
                ev.import.duration_s, ev.fit_records, ev.split_t_s, ev.held_out_records);
    std::printf("  model: the bicycle at the front wheel (traction and steering there), base_link l behind it, the "
                "sensor at (x, y, theta) in base_link\n");
    const auto prow = [](const char* name, const TricycleParams& p) {
      return std::vector<std::string>{name, fixed(p.ksteer, 5), fixed(p.ktraction, 6), fixed(p.axis_length, 4),
                                      fixed(p.steer_offset, 4), fixed(p.laser_x, 3), fixed(p.laser_y, 3),
                                      fixed(p.laser_theta, 4)};
    };
    print_table(stdout, {"parameters", "Ksteer", "Ktraction", "axis_length m", "steer_offset rad", "laser x m",
                         "laser y m", "laser theta rad"},
                {prow("header guesses", ev.before), prow("calibrated", ev.after)});
    const auto erow = [](const char* name, const OdometryError& e) {
      return std::vector<std::string>{name, fixed(e.trajectory.rmse_xy_m, 3), fixed(e.trajectory.rmse_theta_rad, 3),
                                      fixed(e.trajectory.final_xy_m, 3), fixed(e.window_rmse_xy_m, 4),
                                      fixed(e.window_rmse_theta_rad, 4)};
    };
    std::printf("\n");
    print_table(stdout, {"odometry error", "RMSE m", "RMSE rad", "final m", "per window m", "per window rad"},
                {erow("fit part, header guesses", ev.fit_before), erow("fit part, calibrated", ev.fit_after),
                 erow("held out, header guesses", ev.held_before), erow("held out, calibrated", ev.held_after)});
    std::printf("  Levenberg-Marquardt: %d iterations, cost %.4g -> %.4g; run time %.2f s\n", ev.iterations,
                ev.cost_before, ev.cost_after, ev.run_time_s);
    std::printf("  the whole log, calibrated, through estimator_node's replay (%s): RMSE %.3f m / %.3f rad against the "
                "tracker, %.4f m from the direct integration\n", ev.node_log_path.c_str(), ev.node_after.rmse_xy_m,
                ev.node_after.rmse_theta_rad, ev.node_vs_direct_rmse_m);
    std::printf("  results: %s/results.json; plots: %s/trajectories.png, errors.png; log: %s\n",
                opts->out_dir.c_str(), opts->out_dir.c_str(), ev.log_path.c_str());
  });
}

}  // namespace sim::data

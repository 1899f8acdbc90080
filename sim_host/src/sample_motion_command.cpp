// The sample-motion subcommand: one sub-subcommand per motion model, plus the two textbook exercises.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "est/motion/bicycle_model.hpp"
#include "est/motion/diff_drive_model.hpp"
#include "est/motion/odometry_model.hpp"
#include "est/motion/omni_model.hpp"
#include "est/motion/velocity_model.hpp"
#include "sim/commands.hpp"
#include "sim/sample_motion.hpp"

namespace sim {
namespace {

constexpr double kDegToRad = 3.14159265358979323846 / 180.0;

// Options every model's command shares.
struct CommonOptions {
  std::string out;
  std::string name;
  int n = 5000;
  std::uint64_t seed = kDefaultMotionSeed;
  std::vector<double> start{0.0, 0.0, 0.0};
};

void add_common(CLI::App* cmd, CommonOptions& o, const std::string& default_name) {
  o.name = default_name;
  cmd->add_option("--out", o.out, "output directory (created if missing)")->required();
  cmd->add_option("--n", o.n, "number of samples")->check(CLI::Range(1, 10000000))->capture_default_str();
  cmd->add_option("--seed", o.seed, "seed of the random generator")->capture_default_str();
  cmd->add_option("--start", o.start, "start pose x_m,y_m,theta_rad")->expected(3)->delimiter(',')
      ->capture_default_str();
  cmd->add_option("--name", o.name, "file stem of the CSV and PNG")->capture_default_str();
}

est::Pose2 start_pose(const CommonOptions& o) {
  for (double v : o.start)
    if (!std::isfinite(v)) throw CLI::ValidationError("--start", "must be three finite numbers");
  return {static_cast<float>(o.start[0]), static_cast<float>(o.start[1]), static_cast<float>(o.start[2])};
}

void finish(MotionCloud cloud, const CommonOptions& o, const std::string& title) {
  cloud.name = o.name;
  cloud.title = title;
  write_cloud(cloud, o.out);
  std::cout << "sample-motion: " << cloud.samples.size() << " samples -> " << o.out << "/" << o.name << ".csv, .png\n";
  if (!cloud.note.empty()) std::cout << "sample-motion: note: " << cloud.note << "\n";
}

void print_exercise(const std::vector<MotionCloud>& clouds, const std::string& dir, const char* what) {
  for (const MotionCloud& c : clouds) {
    std::cout << what << " " << c.name << ": " << c.samples.size() << " samples -> " << dir << "/" << c.name
              << ".csv, " << c.name << ".png  (" << c.title << ")\n";
    if (!c.note.empty()) std::cout << what << " " << c.name << ": " << c.note << "\n";
  }
}

std::string num(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

}  // namespace

void add_sample_motion_command(CLI::App& app) {
  CLI::App* sm = app.add_subcommand(
      "sample-motion",
      "Posterior samples x_t ~ p(x_t | u_t, x_{t-1}) of a motion model from one start pose: CSV (x_m,y_m,theta_rad) "
      "and PNG of the cloud. Models: velocity, odometry, bicycle, diff-drive, omni; exercises: bicycle-exercise, "
      "velocity-exercise.");
  sm->require_subcommand(1);

  // velocity (Thrun table 5.3)
  {
    auto* cmd = sm->add_subcommand("velocity", "velocity model (Thrun table 5.3): --v, --w, --dt, --alpha a1..a6");
    auto o = std::make_shared<CommonOptions>();
    auto v = std::make_shared<double>(1.0), w = std::make_shared<double>(0.5), dt = std::make_shared<double>(1.0);
    auto alpha = std::make_shared<std::vector<double>>(std::vector<double>{0.01, 0.0, 0.01, 0.0, 0.001, 0.0});
    cmd->add_option("--v", *v, "translational speed, m/s")->capture_default_str();
    cmd->add_option("--w", *w, "turn rate, rad/s")->capture_default_str();
    cmd->add_option("--dt", *dt, "step, s")->capture_default_str();
    cmd->add_option("--alpha", *alpha,
                    "a1..a6: var(v) = a1 v^2 + a2 w^2, var(w) = a3 v^2 + a4 w^2, var(gamma) = a5 v^2 + a6 w^2")
        ->expected(6)->delimiter(',')->capture_default_str();
    add_common(cmd, *o, "velocity");
    cmd->callback([=] {
      est::VelocityParams p;
      p.dt = static_cast<float>(*dt);
      float* a[] = {&p.a1, &p.a2, &p.a3, &p.a4, &p.a5, &p.a6};
      for (std::size_t i = 0; i < 6; ++i) *a[i] = static_cast<float>((*alpha)[i]);
      const est::VelocityControl u{static_cast<float>(*v), static_cast<float>(*w)};
      finish(sample_cloud<est::VelocityMotionModel>(u, p, start_pose(*o), o->n, o->seed), *o,
             "Velocity model: v = " + num(*v) + " m/s, w = " + num(*w) + " rad/s, dt = " + num(*dt) + " s");
    });
  }

  // odometry (Thrun table 5.6)
  {
    auto* cmd = sm->add_subcommand("odometry",
                                   "odometry model (Thrun table 5.6): --odom-prev, --odom (x,y,theta), --alpha a1..a4");
    auto o = std::make_shared<CommonOptions>();
    auto prev = std::make_shared<std::vector<double>>(std::vector<double>{0.0, 0.0, 0.0});
    auto cur = std::make_shared<std::vector<double>>(std::vector<double>{1.0, 0.3, 0.5});
    auto alpha = std::make_shared<std::vector<double>>(std::vector<double>{0.01, 0.01, 0.01, 0.01});
    cmd->add_option("--odom-prev", *prev, "odometry pose x_bar_{t-1}: x_m,y_m,theta_rad")->expected(3)
        ->delimiter(',')->capture_default_str();
    cmd->add_option("--odom", *cur, "odometry pose x_bar_t: x_m,y_m,theta_rad")->expected(3)->delimiter(',')
        ->capture_default_str();
    cmd->add_option("--alpha", *alpha, "a1..a4 of table 5.6 (variances)")->expected(4)->delimiter(',')
        ->capture_default_str();
    add_common(cmd, *o, "odometry");
    cmd->callback([=] {
      est::OdometryParams p;
      p.a1 = static_cast<float>((*alpha)[0]);
      p.a2 = static_cast<float>((*alpha)[1]);
      p.a3 = static_cast<float>((*alpha)[2]);
      p.a4 = static_cast<float>((*alpha)[3]);
      const auto pose = [](const std::vector<double>& q) {
        return est::Pose2{static_cast<float>(q[0]), static_cast<float>(q[1]), static_cast<float>(q[2])};
      };
      const est::OdometryControl u{pose(*prev), pose(*cur)};
      finish(sample_cloud<est::OdometryMotionModel>(u, p, start_pose(*o), o->n, o->seed), *o, "Odometry model");
    });
  }

  // bicycle (front wheel)
  {
    auto* cmd = sm->add_subcommand(
        "bicycle", "bicycle, pose at the front wheel: --v, --steer-deg, --dt, --length, --steer-max-deg, noise");
    auto o = std::make_shared<CommonOptions>();
    auto v = std::make_shared<double>(0.2), steer = std::make_shared<double>(25.0), dt = std::make_shared<double>(1.0);
    auto len = std::make_shared<double>(1.0), steer_max = std::make_shared<double>(80.0);
    auto steer_sd = std::make_shared<double>(5.0), k = std::make_shared<double>(0.5);
    auto rot_sd = std::make_shared<double>(0.5);
    cmd->add_option("--v", *v, "front wheel speed, m/s")->capture_default_str();
    cmd->add_option("--steer-deg", *steer, "steering angle, deg (left positive)")->capture_default_str();
    cmd->add_option("--dt", *dt, "step, s")->capture_default_str();
    cmd->add_option("--length", *len, "frame length l (rear to front wheel), m")->capture_default_str();
    cmd->add_option("--steer-max-deg", *steer_max, "steering stop a_max, deg")->capture_default_str();
    cmd->add_option("--steer-sigma-deg", *steer_sd, "steering noise sd, deg")->capture_default_str();
    cmd->add_option("--speed-var-per-speed", *k, "k in var(v) = k |v|, m/s (0.5 = 50 cm^2/s^2 per cm/s)")
        ->capture_default_str();
    cmd->add_option("--final-rot-sigma-deg", *rot_sd, "final rotation sd, deg")->capture_default_str();
    add_common(cmd, *o, "bicycle");
    cmd->callback([=] {
      est::BicycleParams p;
      p.frame_length = static_cast<float>(*len);
      p.dt = static_cast<float>(*dt);
      p.steer_max = static_cast<float>(*steer_max * kDegToRad);
      p.steer_sigma = static_cast<float>(*steer_sd * kDegToRad);
      p.speed_var_per_speed = static_cast<float>(*k);
      p.final_rot_sigma = static_cast<float>(*rot_sd * kDegToRad);
      const est::BicycleControl u{static_cast<float>(*v), static_cast<float>(*steer * kDegToRad)};
      MotionCloud c = sample_cloud<est::BicycleMotionModel>(u, p, start_pose(*o), o->n, o->seed);
      c.frame_length_m = *len;
      finish(std::move(c), *o,
             "Bicycle: a = " + num(*steer) + " deg, v = " + num(*v) + " m/s, l = " + num(*len) + " m, dt = " +
                 num(*dt) + " s");
    });
  }

  // differential drive
  {
    auto* cmd = sm->add_subcommand(
        "diff-drive", "differential drive: --left-ticks/--right-ticks (or --left-rad-s/--right-rad-s with --dt)");
    auto o = std::make_shared<CommonOptions>();
    auto lt = std::make_shared<std::int32_t>(2900), rt = std::make_shared<std::int32_t>(3500);
    auto lw = std::make_shared<double>(0.0), rw = std::make_shared<double>(0.0), dt = std::make_shared<double>(1.0);
    auto radius = std::make_shared<double>(0.05), track = std::make_shared<double>(0.3);
    auto tpr = std::make_shared<std::uint32_t>(1024u);
    auto k = std::make_shared<double>(0.05), floor_m = std::make_shared<double>(0.005);
    auto rot_sd = std::make_shared<double>(0.5);
    auto lt_opt = cmd->add_option("--left-ticks", *lt, "left encoder tick delta")->capture_default_str();
    auto rt_opt = cmd->add_option("--right-ticks", *rt, "right encoder tick delta")->capture_default_str();
    auto lw_opt = cmd->add_option("--left-rad-s", *lw, "left wheel speed, rad/s (instead of ticks)");
    auto rw_opt = cmd->add_option("--right-rad-s", *rw, "right wheel speed, rad/s (instead of ticks)");
    lw_opt->excludes(lt_opt)->excludes(rt_opt)->needs(rw_opt);
    rw_opt->excludes(lt_opt)->excludes(rt_opt)->needs(lw_opt);
    cmd->add_option("--dt", *dt, "step, s (with wheel speeds)")->capture_default_str();
    cmd->add_option("--wheel-radius", *radius, "m")->capture_default_str();
    cmd->add_option("--track-width", *track, "m")->capture_default_str();
    cmd->add_option("--ticks-per-rev", *tpr, "encoder ticks per wheel revolution")->capture_default_str();
    cmd->add_option("--travel-sigma-per-m", *k, "wheel travel sd per metre travelled")->capture_default_str();
    cmd->add_option("--travel-sigma-floor", *floor_m, "wheel travel sd floor, m")->capture_default_str();
    cmd->add_option("--final-rot-sigma-deg", *rot_sd, "final rotation sd, deg")->capture_default_str();
    add_common(cmd, *o, "diff_drive");
    cmd->callback([=] {
      est::DiffDriveParams p;
      p.wheel_radius = static_cast<float>(*radius);
      p.track_width = static_cast<float>(*track);
      p.ticks_per_rev = *tpr;
      p.travel_sigma_per_m = static_cast<float>(*k);
      p.travel_sigma_floor = static_cast<float>(*floor_m);
      p.final_rot_sigma = static_cast<float>(*rot_sd * kDegToRad);
      const bool speeds = lw_opt->count() > 0;
      MotionCloud c;
      std::string title;
      if (speeds) {
        // Wheel speeds: the model's free functions take wheel travel directly.
        const est::WheelTravel d = est::wheel_travel_from_speeds(static_cast<float>(*lw), static_cast<float>(*rw),
                                                                 static_cast<float>(*dt), p);
        const est::MotionStatus s = est::check_motion_diff_drive(d, p);
        if (!est::usable(s))
          throw std::invalid_argument(std::string("the model rejects this control (") + motion_status_name(s) + ")");
        est::Rng rng(o->seed);
        c.start = start_pose(*o);
        c.noise_free = est::predict_motion_diff_drive(c.start, d, p);
        for (int i = 0; i < o->n; ++i) c.samples.push_back(est::sample_motion_model_diff_drive(d, c.start, p, rng));
        title = "Differential drive: wheels " + num(*lw) + ", " + num(*rw) + " rad/s for " + num(*dt) + " s";
      } else {
        c = sample_cloud<est::DiffDriveMotionModel>({*lt, *rt}, p, start_pose(*o), o->n, o->seed);
        title = "Differential drive: " + std::to_string(*lt) + " / " + std::to_string(*rt) + " ticks";
      }
      finish(std::move(c), *o, title);
    });
  }

  // omnidirectional
  {
    auto* cmd = sm->add_subcommand("omni", "omnidirectional: --v1 (forward), --v2 (left), --w, --dt, --alpha a1..a9");
    auto o = std::make_shared<CommonOptions>();
    auto v1 = std::make_shared<double>(1.0), v2 = std::make_shared<double>(0.5), w = std::make_shared<double>(0.5);
    auto dt = std::make_shared<double>(1.0);
    auto alpha = std::make_shared<std::vector<double>>(
        std::vector<double>{0.1, 0.02, 0.02, 0.02, 0.1, 0.02, 0.02, 0.02, 0.1});
    cmd->add_option("--v1", *v1, "forward speed, m/s")->capture_default_str();
    cmd->add_option("--v2", *v2, "leftward speed, m/s")->capture_default_str();
    cmd->add_option("--w", *w, "yaw rate, rad/s")->capture_default_str();
    cmd->add_option("--dt", *dt, "step, s")->capture_default_str();
    cmd->add_option("--alpha", *alpha,
                    "a1..a9: sd(v1) = a1|v1| + a2|v2| + a3|w|, sd(v2) = a4.. a6, sd(w) = a7.. a9")
        ->expected(9)->delimiter(',')->capture_default_str();
    add_common(cmd, *o, "omni");
    cmd->callback([=] {
      est::OmniParams p;
      p.dt = static_cast<float>(*dt);
      for (std::size_t i = 0; i < 9; ++i) p.alpha[i] = static_cast<float>((*alpha)[i]);
      const est::OmniControl u{static_cast<float>(*v1), static_cast<float>(*v2), static_cast<float>(*w)};
      finish(sample_cloud<est::OmniMotionModel>(u, p, start_pose(*o), o->n, o->seed), *o,
             "Omnidirectional: v1 = " + num(*v1) + " m/s, v2 = " + num(*v2) + " m/s, w = " + num(*w) + " rad/s");
    });
  }

  // The exercises.
  {
    auto* cmd = sm->add_subcommand(
        "bicycle-exercise",
        "Thrun ch. 5 bicycle exercise: l = 100 cm, dt = 1 s, |a| <= 80 deg, sigma_a^2 = 25 deg^2, "
        "sigma_v^2 = 50 cm^2/s^2 per cm/s; cases (a, v) = (25 deg, 20 cm/s), (-25, 20), (25, 90), (80, 10), (85, 90); "
        "writes case1..5.csv/png");
    auto out = std::make_shared<std::string>();
    auto n = std::make_shared<int>(5000);
    auto seed = std::make_shared<std::uint64_t>(kDefaultMotionSeed);
    cmd->add_option("--out", *out, "output directory (created if missing)")->required();
    cmd->add_option("--n", *n, "samples per case")->check(CLI::Range(1, 10000000))->capture_default_str();
    cmd->add_option("--seed", *seed, "seed of the random generator")->capture_default_str();
    cmd->callback([=] {
      const auto clouds = bicycle_exercise(*seed, *n);
      for (const MotionCloud& c : clouds) write_cloud(c, *out);
      print_exercise(clouds, *out, "bicycle-exercise");
    });
  }
  {
    auto* cmd = sm->add_subcommand(
        "velocity-exercise",
        "Thrun fig. 5.3 with v = 1 m/s, w = 0.5 rad/s, dt = 1 s: small speed and large turn-rate error, the reverse, "
        "and a very large turn-rate error; writes case1..3.csv/png");
    auto out = std::make_shared<std::string>();
    auto n = std::make_shared<int>(5000);
    auto seed = std::make_shared<std::uint64_t>(kDefaultMotionSeed);
    cmd->add_option("--out", *out, "output directory (created if missing)")->required();
    cmd->add_option("--n", *n, "samples per case")->check(CLI::Range(1, 10000000))->capture_default_str();
    cmd->add_option("--seed", *seed, "seed of the random generator")->capture_default_str();
    cmd->callback([=] {
      const auto clouds = velocity_exercise(*seed, *n);
      for (const MotionCloud& c : clouds) write_cloud(c, *out);
      print_exercise(clouds, *out, "velocity-exercise");
    });
  }
}

}  // namespace sim

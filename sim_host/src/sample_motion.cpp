#include "sim/sample_motion.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "est/motion/bicycle_model.hpp"
#include "est/motion/diff_drive_model.hpp"
#include "est/motion/odometry_model.hpp"
#include "est/motion/omni_model.hpp"
#include "est/motion/velocity_model.hpp"
#include "sim/plot.hpp"

namespace sim {
namespace {

constexpr double kDegToRad = 3.14159265358979323846 / 180.0;

float deg(double d) { return static_cast<float>(d * kDegToRad); }

std::string fmt_num(double v, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

// What each model accepts, for the error message (the models' headers have the full policy).
template <typename Model>
struct ModelInfo;
template <>
struct ModelInfo<est::VelocityMotionModel> {
  static constexpr const char* name = "velocity";
  static constexpr const char* ranges = "finite values, dt in [1e-6, 100] s, a_i >= 0, |v| <= 100 m/s, |w| <= 100 rad/s";
};
template <>
struct ModelInfo<est::OdometryMotionModel> {
  static constexpr const char* name = "odometry";
  static constexpr const char* ranges = "finite poses with |x|, |y| <= 1e7 m, a_i >= 0";
};
template <>
struct ModelInfo<est::BicycleMotionModel> {
  static constexpr const char* name = "bicycle";
  static constexpr const char* ranges =
      "finite values, dt in [1e-6, 100] s, length in (0, 1000] m, steer max in (0, 90) deg, |steer| <= 90 deg "
      "(beyond the stop it is clamped), noise >= 0, |v| <= 100 m/s";
};
template <>
struct ModelInfo<est::DiffDriveMotionModel> {
  static constexpr const char* name = "diff-drive";
  static constexpr const char* ranges =
      "wheel radius and track width in (0, 1000] m, ticks per rev > 0, |ticks| <= 2^24, noise >= 0";
};
template <>
struct ModelInfo<est::OmniMotionModel> {
  static constexpr const char* name = "omni";
  static constexpr const char* ranges =
      "finite values, dt in [1e-6, 100] s, alpha >= 0, |v1|, |v2| <= 100 m/s, |w| <= 100 rad/s";
};

}  // namespace

const char* motion_status_name(est::MotionStatus s) {
  switch (s) {
    case est::MotionStatus::ok: return "ok";
    case est::MotionStatus::clamped: return "clamped";
    case est::MotionStatus::rejected_nonfinite: return "rejected_nonfinite";
    case est::MotionStatus::rejected_range: return "rejected_range";
  }
  return "unknown";
}

template <typename Model>
MotionCloud sample_cloud(const typename Model::Control& u, const typename Model::Params& p, const est::Pose2& start,
                         int n, std::uint64_t seed) {
  if (n <= 0) throw std::invalid_argument("the number of samples must be positive");
  const est::MotionStatus status = Model::check(u, p);
  if (!est::usable(status))
    throw std::invalid_argument(std::string("the ") + ModelInfo<Model>::name +
                                " model rejects this control or these parameters (" + motion_status_name(status) +
                                "): " + ModelInfo<Model>::ranges);
  MotionCloud c;
  if (status == est::MotionStatus::clamped) c.note = "a control beyond its limit was clamped to the limit";
  c.start = start;
  c.noise_free = Model::predict(start, u, p);
  est::Rng rng(seed);
  c.samples.reserve(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) c.samples.push_back(Model::sample(start, u, p, rng));
  return c;
}

template MotionCloud sample_cloud<est::VelocityMotionModel>(const est::VelocityControl&, const est::VelocityParams&,
                                                            const est::Pose2&, int, std::uint64_t);
template MotionCloud sample_cloud<est::OdometryMotionModel>(const est::OdometryControl&, const est::OdometryParams&,
                                                            const est::Pose2&, int, std::uint64_t);
template MotionCloud sample_cloud<est::BicycleMotionModel>(const est::BicycleControl&, const est::BicycleParams&,
                                                           const est::Pose2&, int, std::uint64_t);
template MotionCloud sample_cloud<est::DiffDriveMotionModel>(const est::DiffDriveControl&,
                                                             const est::DiffDriveParams&, const est::Pose2&, int,
                                                             std::uint64_t);
template MotionCloud sample_cloud<est::OmniMotionModel>(const est::OmniControl&, const est::OmniParams&,
                                                        const est::Pose2&, int, std::uint64_t);

void write_pose_csv(const std::string& path, const std::vector<est::Pose2>& poses) {
  std::ofstream f(path);
  if (!f) throw std::runtime_error("cannot write " + path);
  f << "x_m,y_m,theta_rad\n";
  char line[96];
  for (const est::Pose2& x : poses) {
    // %.9g round-trips a float exactly.
    std::snprintf(line, sizeof line, "%.9g,%.9g,%.9g\n", static_cast<double>(x.x), static_cast<double>(x.y),
                  static_cast<double>(x.theta));
    f << line;
  }
  if (!f) throw std::runtime_error("error writing " + path);
}

void write_cloud(const MotionCloud& cloud, const std::string& dir) {
  namespace fs = std::filesystem;
  fs::create_directories(dir);
  const std::string csv = (fs::path(dir) / (cloud.name + ".csv")).string();
  const std::string png = (fs::path(dir) / (cloud.name + ".png")).string();
  write_pose_csv(csv, cloud.samples);
  ScatterPlot plot;
  plot.title = cloud.title;
  plot.x_label = "x [cm]";
  plot.y_label = "y [cm]";
  plot.csv_path = csv;
  plot.scale = 100.0;
  plot.points_label = std::to_string(cloud.samples.size()) + " samples";
  // Arrows a tenth of the plot's extent long show the headings.
  double span = 0.0;
  for (const est::Pose2& x : cloud.samples)
    span = std::max({span, std::fabs(static_cast<double>(x.x - cloud.start.x)),
                     std::fabs(static_cast<double>(x.y - cloud.start.y))});
  span = std::max(span * 100.0, 10.0);
  PlotMarker start;
  start.x = 100.0 * static_cast<double>(cloud.start.x);
  start.y = 100.0 * static_cast<double>(cloud.start.y);
  start.label = "start";
  start.point_type = 9;
  start.color = "black";
  start.heading = static_cast<double>(cloud.start.theta);
  start.arrow_length = 0.12 * span;
  PlotMarker free_pose;
  free_pose.x = 100.0 * static_cast<double>(cloud.noise_free.x);
  free_pose.y = 100.0 * static_cast<double>(cloud.noise_free.y);
  free_pose.label = "noise-free pose";
  free_pose.point_type = 5;
  free_pose.color = "red";
  free_pose.heading = static_cast<double>(cloud.noise_free.theta);
  free_pose.arrow_length = 0.12 * span;
  plot.markers = {start, free_pose};
  plot.markers.insert(plot.markers.end(), cloud.extra_markers.begin(), cloud.extra_markers.end());
  if (cloud.frame_length_m > 0.0) {
    PlotSegment frame;
    const double th = static_cast<double>(cloud.start.theta);
    frame.x1 = start.x;
    frame.y1 = start.y;
    frame.x0 = start.x - 100.0 * cloud.frame_length_m * std::cos(th);
    frame.y0 = start.y - 100.0 * cloud.frame_length_m * std::sin(th);
    frame.label = "frame at start (rear wheel to front wheel)";
    plot.segments.push_back(frame);
  }
  render_scatter_png(plot, png);
}

std::vector<MotionCloud> bicycle_exercise(std::uint64_t seed, int n) {
  est::BicycleParams p;
  p.frame_length = 1.0f;                 // 100 cm
  p.dt = 1.0f;
  p.steer_max = deg(80.0);
  p.steer_sigma = deg(5.0);              // sigma_a^2 = 25 deg^2
  p.speed_var_per_speed = 0.5f;          // 50 cm^2/s^2 per cm/s = 0.5 m^2/s^2 per m/s
  p.final_rot_sigma = deg(0.5);          // not in the exercise: gives the pose a density, leaves (x, y) alone
  struct Case {
    double a_deg;
    double v_cm_s;
  };
  const Case cases[] = {{25.0, 20.0}, {-25.0, 20.0}, {25.0, 90.0}, {80.0, 10.0}, {85.0, 90.0}};
  std::vector<MotionCloud> out;
  int k = 0;
  for (const Case& c : cases) {
    ++k;
    const est::BicycleControl u{static_cast<float>(c.v_cm_s / 100.0), deg(c.a_deg)};
    // Each case its own stream, so that changing one case's sample count leaves the others' samples alone.
    MotionCloud cloud = sample_cloud<est::BicycleMotionModel>(u, p, {}, n, seed + static_cast<std::uint64_t>(k));
    cloud.name = "case" + std::to_string(k);
    cloud.frame_length_m = 1.0;
    // The noise-free ICR: on the rear axle line (x = -l) at l / tan(a); shown when it is near the cloud.
    const double a = static_cast<double>(est::bicycle_detail::clamp_steer(u.steer, p.steer_max));
    double reach = 0.0;
    for (const est::Pose2& q : cloud.samples)
      reach = std::max(reach, std::hypot(static_cast<double>(q.x), static_cast<double>(q.y)));
    const double icr_y = 1.0 / std::tan(a);
    if (std::hypot(1.0, icr_y) < 1.2 * reach) {
      PlotMarker icr;
      icr.x = -100.0;
      icr.y = 100.0 * icr_y;
      icr.label = "ICR (noise-free)";
      icr.point_type = 3;
      icr.color = "dark-green";
      cloud.extra_markers.push_back(icr);
    }
    cloud.title = "Bicycle case " + std::to_string(k) + ": a = " + fmt_num(c.a_deg, 0) + " deg, v = " +
                  fmt_num(c.v_cm_s, 0) + " cm/s (l = 100 cm, dt = 1 s, |a| <= 80 deg)";
    const est::MotionStatus s = est::BicycleMotionModel::check(u, p);
    if (s == est::MotionStatus::clamped) {
      cloud.title += ": clamped to 80 deg";
      cloud.note = "steering " + fmt_num(c.a_deg, 0) + " deg is beyond the 80 deg stop: clamped to 80 deg "
                   "(check() returns MotionStatus::clamped); noisy steering is folded back inside the stop";
    }
    out.push_back(std::move(cloud));
  }
  return out;
}

std::vector<MotionCloud> velocity_exercise(std::uint64_t seed, int n) {
  // The helper's parametrization: var(v_hat - v) = a1 v^2 + a2 w^2, var(w_hat - w) = a3 v^2 + a4 w^2,
  // var(gamma_hat) = a5 v^2 + a6 w^2. With v = 1 m/s the a1, a3, a5 terms are the variances themselves.
  struct Case {
    const char* what;
    float sigma_v;  // m/s
    float sigma_w;  // rad/s
  };
  const Case cases[] = {{"small speed error, large turn-rate error", 0.05f, 0.3f},
                        {"large speed error, small turn-rate error", 0.3f, 0.05f},
                        {"very large turn-rate error", 0.05f, 0.8f}};
  const est::VelocityControl u{1.0f, 0.5f};
  std::vector<MotionCloud> out;
  int k = 0;
  for (const Case& c : cases) {
    ++k;
    est::VelocityParams p;
    p.dt = 1.0f;
    p.a1 = c.sigma_v * c.sigma_v;
    p.a3 = c.sigma_w * c.sigma_w;
    p.a5 = 0.02f * 0.02f;  // small final rotation, rad/s
    MotionCloud cloud = sample_cloud<est::VelocityMotionModel>(u, p, {}, n, seed + static_cast<std::uint64_t>(k));
    cloud.name = "case" + std::to_string(k);
    cloud.title = "Velocity model case " + std::to_string(k) + ": " + c.what + " (v = 1 m/s, w = 0.5 rad/s, dt = 1 s; "
                  "sd_v = " + fmt_num(static_cast<double>(c.sigma_v), 2) + " m/s, sd_w = " +
                  fmt_num(static_cast<double>(c.sigma_w), 2) + " rad/s)";
    out.push_back(std::move(cloud));
  }
  return out;
}

}  // namespace sim

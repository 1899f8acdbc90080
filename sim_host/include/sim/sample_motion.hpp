#pragma once
// sample-motion: draw posterior samples x_t ~ p(x_t | u_t, x_{t-1}) of the firmware's motion models from one start
// pose, and write them as CSV (one pose per row, SI units) and as a PNG of the cloud. Host only (may throw).
#include <cstdint>
#include <string>
#include <vector>

#include "est/geometry/pose2.hpp"
#include "est/motion/motion_model.hpp"
#include "est/random/xoshiro128.hpp"
#include "sim/plot.hpp"

namespace sim {

// The seed every sample-motion run uses unless --seed is given.
inline constexpr std::uint64_t kDefaultMotionSeed = 20240917u;

// One sample cloud and what its plot shows.
struct MotionCloud {
  std::string name;   // file stem: <dir>/<name>.csv and .png
  std::string title;  // plot title
  std::string note;   // said on the terminal (e.g. how a steering command beyond the stop was handled)
  std::vector<est::Pose2> samples;
  est::Pose2 start;
  est::Pose2 noise_free;
  double frame_length_m = 0.0;  // > 0: the bicycle's frame (rear wheel to front wheel) is drawn at the start
  std::vector<PlotMarker> extra_markers;  // drawn too, in cm (e.g. the bicycle's ICR)
};

// Draws n samples of Model from start with the generator seeded by seed; the noise-free pose from predict().
// Throws std::invalid_argument when check() rejects the control or the parameters (with the status), and sets note
// when it clamps.
template <typename Model>
MotionCloud sample_cloud(const typename Model::Control& u, const typename Model::Params& p, const est::Pose2& start,
                         int n, std::uint64_t seed);

// Writes <dir>/<name>.csv (header x_m,y_m,theta_rad) and <dir>/<name>.png (axes in cm, equal scale, the start and
// the noise-free pose marked). Creates dir.
void write_cloud(const MotionCloud& cloud, const std::string& dir);
void write_pose_csv(const std::string& path, const std::vector<est::Pose2>& poses);

// Probabilistic Robotics, ch. 5 exercise on the bicycle model: l = 100 cm, dt = 1 s, |a| <= 80 deg,
// sigma_a^2 = 25 deg^2, sigma_v^2 = 50 cm^2/s^2 per cm/s of |v|, start at the origin heading 0, n samples for each
// of the five cases (a, v) = (25 deg, 20 cm/s), (-25, 20), (25, 90), (80, 10), (85, 90). Names case1..case5.
std::vector<MotionCloud> bicycle_exercise(std::uint64_t seed, int n);

// Thrun fig. 5.3 with the three noise settings the issue names: small speed error and large turn-rate error, the
// reverse, and a very large turn-rate error; v = 1 m/s, w = 0.5 rad/s, dt = 1 s. Names case1..case3.
std::vector<MotionCloud> velocity_exercise(std::uint64_t seed, int n);

const char* motion_status_name(est::MotionStatus s);

}  // namespace sim

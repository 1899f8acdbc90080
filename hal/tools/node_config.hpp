#pragma once
// estimator_node's configuration: every option of the command line, with its default, in one struct (host only).
#include <CLI/CLI.hpp>
#include <cstdint>
#include <string>

#include "est/geometry/pose2.hpp"
#include "est/loop/configured_loop.hpp"
#include "est/sensor/landmark_model.hpp"
#include "est/motion/bicycle_model.hpp"
#include "est/motion/diff_drive_model.hpp"
#include "est/sensor/likelihood_field_range_finder_model.hpp"
#include "hal/lcm/lcm_backend.hpp"
#include "hal/validated_inputs.hpp"

namespace hal::node {

// Compiled capacities (the loop and the filter are statically sized, as on the board).
inline constexpr std::uint32_t kMaxParticles = 20000;
inline constexpr std::int32_t kMaxBeams = 1081;
inline constexpr std::uint32_t kQueueCapacity = 256;
inline constexpr std::uint32_t kScanSlots = 4;
inline constexpr std::int32_t kMapMaxSide = 2048;  // cells per side of a map file
inline constexpr std::int32_t kMaxLandmarks = 1024;  // landmarks in a landmark map file

enum class RobotModel { diff_drive, bicycle };

struct NodeConfig {
  // Inputs and outputs.
  std::string can_interface;  // --can
  std::string lcm_url;        // --lcm: inputs (and outputs unless --lcm-out)
  bool lcm_input = false;
  std::string lcm_out_url;    // --lcm-out: outputs; default --lcm's URL, else LCM's default (udpm)
  bool can_out = false;
  std::string replay_path;    // --replay
  std::string out_path;       // --out
  std::string record_path;    // --record-inputs
  hal::lcm::Channels channels;
  double status_hz = 1.0;
  double duration_s = 0.0;  // live: stop after this long (0: until SIGINT/SIGTERM)
  bool quiet = false;

  // Robot.
  RobotModel model = RobotModel::diff_drive;
  // Noise for 100 Hz predictions: per-step floors must cover what ticks do not see (slip, quantization) or the
  // cloud collapses to millimetres and lags the truth (measured with sim_host simulate).
  est::DiffDriveParams diff_drive{0.05f, 0.3f, 4096u, 0.05f, 0.003f, 0.01f};
  est::BicycleParams bicycle{0.6f, 1.0471976f, 0.04f, 0.1f, 0.01f, 0.01f};
  float metres_per_tick = 0.001f;  // bicycle: front-wheel travel per tick of wheel 0
  est::Pose2 sensor_mount{};

  // Map and initial belief.
  std::string map = "office";
  float clearance_m = 0.2f;
  bool global = false;
  est::Pose2 initial_pose{};
  bool initial_pose_given = false;
  float initial_sigma_xy_m = 0.2f;
  float initial_sigma_theta_rad = 0.1f;

  // Filter.
  est::loop::Filter filter = est::loop::Filter::mcl;
  // EKF localization on landmark sightings.
  std::string landmarks = "office";  // 'office' or a CSV file of x,y,signature
  est::LandmarkNoise landmark_noise{0.05f, 0.02f, 0.0f};
  float ekf_rot_sigma = 0.002f;  // heading noise added per prediction (rad): what the odometry model leaves out
  float lost_sigma_m = 5.0f;
  // MCL.
  std::uint32_t particles = 1000;
  std::uint64_t seed = 1;
  std::int32_t beam_stride = 4;
  float cluster_cell_m = 1.0f;
  est::LikelihoodFieldParams field{0.85f, 0.05f, 0.10f, 0.2f, 12.0f, 2.0f};
  float alpha_slow = 0.02f;
  float alpha_fast = 0.3f;
  bool recovery = true;

  // Loop rates and limits.
  est::loop::LoopTiming timing{};
  hal::InputLimits limits{};
  unsigned lcm_wheel_counter_bits = 32;
};

// Registers every option on `app` (defaults shown in --help), and checks them after parsing (throws CLI::ValidationError).
void add_options(CLI::App& app, NodeConfig& c);
void finish_options(const CLI::App& app, NodeConfig& c);

}  // namespace hal::node

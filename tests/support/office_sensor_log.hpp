#pragma once
// A small recorded sensor stream for the node's tests, until `sim_host record` is there to write one: a differential
// drive robot following the office route (sim_host/world), its encoders at 100 Hz (32-bit counters) and a 360-beam
// rangefinder at 10 Hz (ray cast in the office map, with the sim's range noise), landmark sightings of the office's
// posts at 5 Hz (within 6 m and in line of sight, known correspondence), plus the ground truth, written as an
// LCM log (est_lcm types on the hal::lcm default channels) with lcm::LogFile. Event times are the stamps. Seeded.
// Optionally the base's own view of its motion too, at 100 Hz with the encoders: the twist measured from the
// encoders over each 10 ms (twist_t) and the odometry pose integrated from them (odometry_t), so that the velocity,
// omni, holonomic and odometry models have their inputs.
#include <cstdint>
#include <string>
#include <vector>

#include "est/geometry/pose2.hpp"
#include "est/motion/diff_drive_model.hpp"
#include "hal/time.hpp"

namespace est::test {

struct OfficeStreamSpec {
  double duration_s = 6.0;
  hal::TimeNs t0_ns = hal::kNsPerS;  // stamp of the first sample
  std::uint64_t seed = 7;
  float speed_mps = 0.6f;
  float range_max_m = 12.0f;
  int scan_every = 10;  // encoder periods (10 ms) per scan
  int landmark_every = 20;  // encoder periods per landmark sighting (0: none)
  bool twist = false;       // twist_t on EST_TWIST with every encoder sample
  bool odometry = false;    // odometry_t on EST_ODOMETRY with every encoder sample
};

struct OfficeStream {
  est::Pose2 start;                  // the true pose at t0 (give it to the node as --initial-pose)
  std::vector<hal::TimeNs> truth_t;  // every 10 ms
  std::vector<est::Pose2> truth;
  std::size_t encoder_messages = 0, scan_messages = 0, landmark_messages = 0, landmark_features = 0;
  std::size_t twist_messages = 0, odometry_messages = 0;
};

// The robot's true noise (the node is told larger: see the tests' options).
est::DiffDriveParams office_robot_truth();

OfficeStream write_office_stream(const std::string& path, const OfficeStreamSpec& spec = {});

}  // namespace est::test

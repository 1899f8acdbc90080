#pragma once
// What the filter loop consumes: timestamped samples in firmware types, one payload per input kind
// (est/loop/input_kinds.hpp lists the kinds and what the loop does with each). Backends (hal/) validate raw samples
// and convert them to these; the loop never sees a bus, a file or a clock other than the one it is given.
#include <cstdint>

#include "est/geometry/pose2.hpp"
#include "est/sensor/range_scan.hpp"

namespace est::loop {

using TimeNs = std::int64_t;  // monotonic nanoseconds, the same clock for every input

inline constexpr std::int32_t kMaxWheels = 4;

// Encoder tick increments of each wheel since the previous sample of the same encoders (wrap-around already
// resolved), over (previous stamp, t_ns]. Which wheel is which is the robot's (its control assembler says).
struct WheelTicksInput {
  TimeNs t_ns = 0;
  std::int32_t ticks[kMaxWheels] = {};
  std::uint8_t wheel_count = 0;
};

// The steering angle at t_ns (left positive); held until the next sample.
struct SteeringInput {
  TimeNs t_ns = 0;
  float angle_rad = 0.0f;
};

// A commanded or measured body twist, held from t_ns until the next sample: forward and leftward speed and yaw
// rate. (v, w) for the velocity model is (v1, w) with v2 = 0; (u_x, u_y) of the holonomic robot is (v1, v2).
struct TwistInput {
  TimeNs t_ns = 0;
  float v1_mps = 0.0f;
  float v2_mps = 0.0f;
  float w_rps = 0.0f;
};

// An odometry pose increment over (previous stamp, t_ns]: the pose of the odometry frame at t_ns in the odometry
// frame of the previous sample (x_bar_{t-1} (-) x_bar_t of Thrun table 5.6, what a base that publishes its
// odometry pose gives after differencing).
struct OdometryInput {
  TimeNs t_ns = 0;
  Pose2 increment;
};

// A scan as the models need it; `ranges` must stay valid only during the call that passes it in.
struct ScanInput {
  TimeNs t_ns = 0;
  ScanLayout layout;
  const float* ranges = nullptr;
};

// One feature of a landmark sensor (Thrun eq. 6.40: range, bearing in the robot frame, signature). `id` is the
// landmark's index in the map when the sensor knows the correspondence (table 7.2), -1 when the filter must find it
// by maximum likelihood (table 7.3). A sighting of several features is several inputs with the same stamp.
struct LandmarkInput {
  TimeNs t_ns = 0;
  float range_m = 0.0f;
  float bearing_rad = 0.0f;
  float signature = 0.0f;
  std::int32_t id = -1;
};

}  // namespace est::loop

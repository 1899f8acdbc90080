#pragma once
// What the filter loop consumes: timestamped samples in firmware types. Backends (hal/) validate raw samples and
// convert them to these; the loop never sees a bus, a file or a clock other than the one it is given.
#include <cstdint>

#include "est/sensor/range_scan.hpp"

namespace est::loop {

using TimeNs = std::int64_t;  // monotonic nanoseconds, the same clock for every input

// Encoder tick increments since the previous sample of the same encoders (wrap-around already resolved).
struct WheelTicksInput {
  TimeNs t_ns = 0;
  std::int32_t left_ticks = 0;
  std::int32_t right_ticks = 0;
};

struct SteeringInput {
  TimeNs t_ns = 0;
  float angle_rad = 0.0f;
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

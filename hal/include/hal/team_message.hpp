#pragma once
// The team filter's shared message: one robot's controls over a step and its range-bearing measurements of
// landmarks and other robots (cooperative EKF-SLAM). Bounded: at most kMaxTeamMeasurements per message.
#include <cstddef>
#include <cstdint>

#include "hal/fault.hpp"
#include "hal/time.hpp"

namespace hal {

inline constexpr std::size_t kMaxTeamMeasurements = 32;

enum class TeamTarget : std::uint8_t { landmark = 0, robot = 1 };

struct TeamMeasurement {
  TeamTarget type = TeamTarget::landmark;
  float range_m = 0.0f;
  float bearing_rad = 0.0f;  // in the sender's frame, counter-clockwise
  std::int32_t target_id = 0;
};

struct TeamMessage {
  TimeNs stamp_ns = 0;
  std::int32_t robot_id = 0;
  float v_mps = 0.0f;
  float omega_rps = 0.0f;
  float dt_s = 0.0f;
  std::size_t count = 0;
  TeamMeasurement measurements[kMaxTeamMeasurements] = {};
};

// Content checks (finite, range >= 0, |bearing| <= pi, 0 <= dt <= 1 s, count within capacity).
inline Fault check_team_message(const TeamMessage& m) {
  auto finite = [](float x) { return __builtin_isfinite(x); };
  if (!finite(m.v_mps) || !finite(m.omega_rps) || !finite(m.dt_s)) return Fault::not_finite;
  if (m.count > kMaxTeamMeasurements || m.dt_s < 0.0f || m.dt_s > 1.0f) return Fault::out_of_range;
  for (std::size_t i = 0; i < m.count; ++i) {
    const TeamMeasurement& z = m.measurements[i];
    if (!finite(z.range_m) || !finite(z.bearing_rad)) return Fault::not_finite;
    if (z.range_m < 0.0f || z.bearing_rad > 3.1415927f || z.bearing_rad < -3.1415927f) return Fault::out_of_range;
  }
  return Fault::none;
}

class TeamPort {
 public:
  virtual void on_team_message(const TeamMessage& message) = 0;

 protected:
  ~TeamPort() = default;
};

}  // namespace hal

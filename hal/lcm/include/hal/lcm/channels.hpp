#pragma once
// The LCM channels of the estimator and how its receiver is configured (host only). Channel names are
// configuration.
#include <cstddef>
#include <string>

namespace hal::lcm {

struct Channels {
  std::string wheel_ticks = "EST_WHEEL_TICKS";
  std::string steering = "EST_STEERING";
  std::string twist = "EST_TWIST";
  std::string odometry = "EST_ODOMETRY";
  std::string range_scan = "EST_RANGE_SCAN";
  std::string landmarks = "EST_LANDMARKS";
  std::string team = "EST_TEAM";  // one channel for the whole team: every robot's message, the sender inside it
  std::string pose = "EST_POSE";
  std::string particles = "EST_PARTICLES";
  std::string status = "EST_STATUS";
  std::string slam_map = "EST_SLAM_MAP";  // slam_map_t: EKF-SLAM's landmarks and association counters
  std::string ground_truth = "EST_GROUND_TRUTH";
};

struct InputConfig {
  Channels channels;
  unsigned wheel_counter_bits = 32;  // encoder_ticks_t.counter_bits must match (the HAL validator unwraps with it)
  std::size_t max_ranges = 4096;     // larger scans are rejected before decoding
};

// How each raw sample travels on LCM, specialized in its sensor's folder (hal/sensors/<sensor>/lcm.hpp):
//   using Message;                                   the est_lcm type
//   static std::string Channels::* const channel;    its channel
//   struct Storage;                                  what the sample's view points into while it is delivered
//   static std::int64_t max_count(const InputConfig&);
//   static LcmReject to_hal(const Message&, const InputConfig&, Storage&, Sample& out);
//   static Message to_lcm(const Sample&, ...);
template <typename Sample>
struct LcmCodec;

}  // namespace hal::lcm

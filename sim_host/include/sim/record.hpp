#pragma once
// `record`: a scenario's sensor stream and ground truth as an LCM log file (lcm::LogFile), in arrival order, on the
// LCM backend's default channels (hal/lcm/lcm_backend.hpp): EST_WHEEL_TICKS (est_lcm::encoder_ticks_t, 32-bit
// counters), EST_STEERING, EST_RANGE_SCAN, EST_LANDMARKS (est_lcm::landmark_sighting_t) and EST_GROUND_TRUTH (every
// 10 ms step). Event times are the arrival times
// in microseconds of the robot's clock, so a replay that paces by event time sees the same late, stale and
// out-of-order deliveries the in-process simulation sees. Host only (may throw).
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "hal/estimate.hpp"

#include "sim/sensor_stream.hpp"

namespace sim {

struct RecordSummary {
  std::map<std::string, std::uint64_t> messages;  // by channel
  std::uint64_t events = 0;
};

// With `estimates` (a run's outputs, sim/simulate.hpp), they go in too, on EST_POSE at their stamps: the log of a
// whole run, which estimator_node --replay reads as it reads a recording (it takes its inputs only).
RecordSummary record_lcm_log(const SensorStream& stream, const std::string& path,
                             const std::vector<hal::Estimate>* estimates = nullptr);

struct FilterOptions;  // sim/simulate.hpp

// The sidecar <log>.json: the scenario, the message counts per channel, the injected faults and the reject counts
// a HAL must show after replaying the log (the same keys as metrics.json), and estimator_node options that match:
// the run's filter when `filter` is given (the log of a run), else MCL tracking from the start (and the EKF's, with
// landmarks).
std::string record_sidecar_json(const SensorStream& stream, const ScenarioConfig& scenario, const SimWorld& world,
                                const RecordSummary& summary, const std::string& log_path,
                                const FilterOptions* filter = nullptr);

}  // namespace sim

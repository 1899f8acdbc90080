#pragma once
// LCM messages <-> HAL types, with the checks a decoder from the network needs (host only). Every est_lcm type
// that has arrays declares its count first, so the count is bounded before lcm-gen's decoder allocates for it.
#include <cstddef>
#include <cstdint>
#include <est_lcm/encoder_ticks_t.hpp>
#include <est_lcm/ground_truth_t.hpp>
#include <est_lcm/landmark_sighting_t.hpp>
#include <est_lcm/particle_cloud_t.hpp>
#include <est_lcm/pose_estimate_t.hpp>
#include <est_lcm/range_scan_t.hpp>
#include <est_lcm/status_t.hpp>
#include <est_lcm/steering_t.hpp>
#include <est_lcm/team_message_t.hpp>

#include "hal/estimate.hpp"
#include "hal/fault.hpp"
#include "hal/landmarks.hpp"
#include "hal/range_scan.hpp"
#include "hal/steering.hpp"
#include "hal/team_message.hpp"
#include "hal/wheel_ticks.hpp"

namespace hal::lcm {

enum class LcmReject : std::uint8_t {
  none = 0,
  malformed,   // lcm-gen's decoder failed (wrong fingerprint, truncated, trailing garbage)
  bad_count,   // an array count negative or above what the receiver holds
  bad_shape,   // fields inconsistent with the receiver's configuration (e.g. counter width)
  bad_value,   // content rejected by the HAL checks (counted by hal::Fault too)
  kCount
};
const char* to_string(LcmReject r);
using LcmRejectCounters = ReasonCounters<LcmReject>;

// Decodes msg from one LCM payload. max_count bounds the leading array count (ignored for types without arrays).
template <typename Message>
LcmReject decode_guarded(const void* data, std::size_t size, Message& msg, std::int64_t max_count);

LcmReject to_hal(const est_lcm::encoder_ticks_t& m, unsigned expected_counter_bits, WheelTicks& out);
SteeringSample to_hal(const est_lcm::steering_t& m);
// The view points into m.ranges_m: valid while m lives.
LcmReject to_hal(const est_lcm::range_scan_t& m, RangeScanView& out);
LcmReject to_hal(const est_lcm::team_message_t& m, TeamMessage& out, Fault& content);
// Copies up to kMaxLandmarkFeatures features (more: bad_count).
LcmReject to_hal(const est_lcm::landmark_sighting_t& m, LandmarkSighting<kMaxLandmarkFeatures>& out);

est_lcm::encoder_ticks_t to_lcm(const WheelTicks& s, unsigned counter_bits);
est_lcm::steering_t to_lcm(const SteeringSample& s);
est_lcm::range_scan_t to_lcm(const RangeScanView& s);
est_lcm::team_message_t to_lcm(const TeamMessage& m);
est_lcm::landmark_sighting_t to_lcm(const LandmarkSightingView& s);
est_lcm::pose_estimate_t to_lcm(const Estimate& e);
Estimate to_hal(const est_lcm::pose_estimate_t& m);

}  // namespace hal::lcm

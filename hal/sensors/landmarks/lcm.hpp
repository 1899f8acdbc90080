#pragma once
// Landmark sightings on LCM: est_lcm::landmark_sighting_t (no CAN frame: hal/can/estimator_dbc.hpp says why).
#include <cstdint>
#include <est_lcm/landmark_sighting_t.hpp>

#include "hal/lcm/channels.hpp"
#include "hal/lcm/lcm_guard.hpp"
#include "hal/sensors/landmarks/landmarks.hpp"

namespace hal::lcm {

template <> struct LeadingCount<est_lcm::landmark_sighting_t> { static constexpr int bytes = 2; };

// Copies up to kMaxLandmarkFeatures features (more: bad_count).
LcmReject to_hal(const est_lcm::landmark_sighting_t& m, LandmarkSighting<kMaxLandmarkFeatures>& out);
est_lcm::landmark_sighting_t to_lcm(const LandmarkSightingView& s);

template <>
struct LcmCodec<LandmarkSightingView> {
  using Message = est_lcm::landmark_sighting_t;
  static constexpr std::string Channels::*channel = &Channels::landmarks;
  using Storage = LandmarkSighting<kMaxLandmarkFeatures>;
  static std::int64_t max_count(const InputConfig&) { return static_cast<std::int64_t>(kMaxLandmarkFeatures); }
  static LcmReject to_hal(const Message& m, const InputConfig&, Storage& storage, LandmarkSightingView& out) {
    const LcmReject r = lcm::to_hal(m, storage);
    out = storage.view();
    return r;
  }
};

}  // namespace hal::lcm

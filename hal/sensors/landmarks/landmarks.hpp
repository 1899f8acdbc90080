#pragma once
// A landmark sensor's sighting: the features seen at one time, each a range, a bearing in the robot frame
// (counter-clockwise), a signature (Thrun eq. 6.40), and the landmark's index in the map when the sensor knows the
// correspondence (a coded marker), -1 when the filter must find it.
#include <cstddef>
#include <cstdint>

#include "est/loop/inputs.hpp"
#include "hal/time.hpp"

namespace hal {

struct LandmarkFeature {
  float range_m = 0.0f;
  float bearing_rad = 0.0f;
  float signature = 0.0f;
  std::int32_t id = -1;
};

inline constexpr std::size_t kMaxLandmarkFeatures = 64;  // per sighting

struct LandmarkSightingView {
  TimeNs stamp_ns = 0;
  const LandmarkFeature* features = nullptr;
  std::size_t count = 0;
};

template <std::size_t N>
struct LandmarkSighting {
  static_assert(N > 0, "a sighting holds at least one feature");
  static constexpr std::size_t kCapacity = N;

  TimeNs stamp_ns = 0;
  std::size_t count = 0;
  LandmarkFeature features[N] = {};

  LandmarkSightingView view() const { return {stamp_ns, features, count}; }
};

// One loop input per feature, all with the sighting's stamp (the loop fuses them in a fixed order).
template <typename Push>
void to_loop_inputs(const LandmarkSightingView& s, Push&& push) {
  for (std::size_t i = 0; i < s.count; ++i) {
    const LandmarkFeature& f = s.features[i];
    push(est::loop::LandmarkInput{s.stamp_ns, f.range_m, f.bearing_rad, f.signature, f.id});
  }
}

}  // namespace hal

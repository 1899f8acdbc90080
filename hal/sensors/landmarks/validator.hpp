#pragma once
// Checks landmark sightings: the sighting's shape and timing, then every feature (finite, range within the
// sensor's reach, bearing within (-pi, pi], id -1 or a map index). A bad feature is dropped and counted and the others
// pass on; a sighting with a bad shape or timing, or without a good feature left, is rejected whole.
#include <cstddef>
#include <cstdint>

#include "hal/fault.hpp"
#include "hal/sensors/landmarks/landmarks.hpp"
#include "hal/sample_timing.hpp"
#include "hal/sample_validator.hpp"

namespace hal {

struct LandmarkLimits {
  float max_range_m = 50.0f;              // the sensor's reach
  std::int32_t max_id = 65535;            // largest map index a sensor may name
  std::size_t max_features = kMaxLandmarkFeatures;
  TimingLimits timing;
};

class LandmarkValidator : public SampleValidator<LandmarkLimits> {
 public:
  using Limits = LandmarkLimits;
  static constexpr const char* kName = "landmarks";

  explicit LandmarkValidator(const LandmarkLimits& limits = {}) : SampleValidator(limits) {}

  // The good features go to `out` (same stamp; it views the validator's own buffer, valid until the next check);
  // Fault::none when at least one passed.
  Fault check(const LandmarkSightingView& sighting, TimeNs now_ns, LandmarkSightingView& out);

  std::uint32_t features_accepted() const { return features_accepted_; }

 private:
  Fault check_feature(const LandmarkFeature& f) const;

  std::uint32_t features_accepted_ = 0;
  LandmarkSighting<kMaxLandmarkFeatures> passed_;
};

}  // namespace hal

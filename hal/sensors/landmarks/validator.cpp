// The landmark sighting validator (hal/sensors/landmarks/validator.hpp).
#include "hal/sensors/landmarks/validator.hpp"

namespace hal {

Fault LandmarkValidator::check_feature(const LandmarkFeature& f) const {
  if (!__builtin_isfinite(f.range_m) || !__builtin_isfinite(f.bearing_rad) || !__builtin_isfinite(f.signature))
    return Fault::not_finite;
  if (!(f.range_m > 0.0f) || f.range_m > limits_.max_range_m) return Fault::out_of_range;
  if (f.bearing_rad > 3.14159274f || f.bearing_rad < -3.14159274f) return Fault::out_of_range;
  if (f.id < -1 || f.id > limits_.max_id) return Fault::out_of_range;
  return Fault::none;
}

Fault LandmarkValidator::check(const LandmarkSightingView& sighting, TimeNs now_ns, LandmarkSightingView& out) {
  passed_.count = 0;
  passed_.stamp_ns = sighting.stamp_ns;
  if (sighting.count == 0 || sighting.count > limits_.max_features || sighting.count > kMaxLandmarkFeatures ||
      sighting.features == nullptr)
    return reject(Fault::out_of_range);
  const Fault t = timing_.check(sighting.stamp_ns, now_ns);
  if (t != Fault::none) return reject(t);
  for (std::size_t i = 0; i < sighting.count; ++i) {
    const Fault f = check_feature(sighting.features[i]);
    if (f == Fault::none)
      passed_.features[passed_.count++] = sighting.features[i];
    else
      faults_.add(f);
  }
  if (passed_.count == 0) return Fault::out_of_range;  // every feature already counted
  features_accepted_ += static_cast<std::uint32_t>(passed_.count);
  timing_.accept(sighting.stamp_ns);
  out = passed_.view();
  return Fault::none;
}

}  // namespace hal

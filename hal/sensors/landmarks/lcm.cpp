// Landmark sightings on LCM (hal/sensors/landmarks/lcm.hpp).
#include "hal/sensors/landmarks/lcm.hpp"

namespace hal::lcm {

LcmReject to_hal(const est_lcm::landmark_sighting_t& m, LandmarkSighting<kMaxLandmarkFeatures>& out) {
  const auto n = static_cast<std::size_t>(m.num_features < 0 ? 0 : m.num_features);
  if (m.num_features < 0 || n > kMaxLandmarkFeatures || m.range_m.size() != n || m.bearing_rad.size() != n ||
      m.signature.size() != n || m.id.size() != n)
    return LcmReject::bad_count;
  out.stamp_ns = m.stamp_ns;
  out.count = n;
  for (std::size_t i = 0; i < n; ++i) out.features[i] = {m.range_m[i], m.bearing_rad[i], m.signature[i], m.id[i]};
  return LcmReject::none;
}

est_lcm::landmark_sighting_t to_lcm(const LandmarkSightingView& s) {
  est_lcm::landmark_sighting_t m{};
  m.stamp_ns = s.stamp_ns;
  const std::size_t n = s.count < kMaxLandmarkFeatures ? s.count : kMaxLandmarkFeatures;
  for (std::size_t i = 0; i < n; ++i) {
    m.range_m.push_back(s.features[i].range_m);
    m.bearing_rad.push_back(s.features[i].bearing_rad);
    m.signature.push_back(s.features[i].signature);
    m.id.push_back(s.features[i].id);
  }
  m.num_features = static_cast<std::int16_t>(n);
  return m;
}

}  // namespace hal::lcm

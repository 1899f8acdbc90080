#pragma once
// MCL's correction with one landmark feature (Thrun table 8.2 line 5 with the feature model of table 6.4): each
// particle's weight times q(f | x, m) of the feature's known correspondence, or, when it has none, of the landmark
// that is most likely from that particle (the maximum likelihood correspondence of section 7.5, per particle). The
// recovery statistic's scale is one factor with the model's mode as its peak.
#include <cstdint>

#include "est/filter/augmented_mcl.hpp"
#include "est/map/landmark_map.hpp"
#include "est/math/fmath.hpp"
#include "est/math/normal.hpp"
#include "est/sensor/landmark_model.hpp"

namespace est::loop {

// The largest log q of table 6.4: the density at a perfect measurement.
inline float landmark_log_peak(const LandmarkNoise& n) {
  float sigma_product = n.sigma_range * n.sigma_bearing;
  float factors = 2.0f;
  if (n.sigma_signature > 0.0f) {
    sigma_product *= n.sigma_signature;
    factors = 3.0f;
  }
  return -fmath::log(sigma_product) - factors * kLogSqrtTwoPi;
}

// id >= 0: the map index the sensor named; id < 0: per particle, the best of the map's landmarks (M of them: a
// bounded scan of N x M densities).
template <std::uint32_t N>
CorrectionReport correct_with_landmark(AugmentedMcl<N>& mcl, const LandmarkMeasurement& f, std::int32_t id,
                                       const LandmarkMap& map, const LandmarkNoise& noise) {
  const MeasurementScale scale{1, landmark_log_peak(noise)};
  if (id >= 0)
    return mcl.correct([&](const Pose2& x) { return landmark_model_known_correspondence(f, id, x, map, noise); },
                       scale);
  return mcl.correct(
      [&](const Pose2& x) {
        float best = kLandmarkLogDensityFloor;
        for (std::int32_t j = 0; j < map.size(); ++j) {
          const float q = landmark_model_known_correspondence(f, j, x, map, noise);
          best = q > best ? q : best;
        }
        return best;
      },
      scale);
}

}  // namespace est::loop

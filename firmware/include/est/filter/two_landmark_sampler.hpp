#pragma once
// Recovery particles from the landmarks in view: the closed-form pose from two identified landmarks
// (pose_from_two_landmarks, est/sensor/landmark_model.hpp), with the two measurements perturbed by the sensor noise
// so that the injected particles spread like p(x | f_i, f_j, m) instead of piling on one point. This is the sensor
// resetting of augmented MCL (Thrun 8.3.5, and Lenser and Veloso 2000): far more useful than uniform particles when
// landmarks are seen, since every injected particle is already near a pose that explains two of them.
// Holds the sightings of the current step (up to MaxSightings, static); a draw picks a random pair. Bounded: at most
// max_tries pairs per draw; fewer than two sightings, or no consistent pair, reports failure.
#include <cstdint>

#include "est/geometry/pose2.hpp"
#include "est/map/landmark_map.hpp"
#include "est/random/samplers.hpp"
#include "est/random/xoshiro128.hpp"
#include "est/sensor/landmark_model.hpp"

namespace est {

template <std::int32_t MaxSightings>
class TwoLandmarkSampler {
  static_assert(MaxSightings >= 2, "a pose needs two landmarks");

 public:
  TwoLandmarkSampler(const LandmarkMap& map, const LandmarkNoise& noise, std::uint32_t max_tries = 8u)
      : map_(map), noise_(noise), max_tries_(max_tries) {}

  void clear() { count_ = 0; }
  // Keeps a sighting with correspondence c; false (not kept) when full or invalid.
  bool add(const LandmarkMeasurement& f, std::int32_t c) {
    if (count_ >= MaxSightings || check_landmark_measurement(f, c, map_, noise_) != LandmarkStatus::ok) return false;
    f_[static_cast<std::uint32_t>(count_)] = f;
    c_[static_cast<std::uint32_t>(count_)] = c;
    ++count_;
    return true;
  }
  std::int32_t count() const { return count_; }

  // A measured separation further than this many of its sigmas from the mapped one means a wrong pairing. Its
  // variance: two ranges (sigma_r each) and two bearings (r sigma_b each), doubled by the perturbation.
  static constexpr float kMismatchSigmas = 4.0f;

  bool operator()(Rng& rng, Pose2& p) const {
    if (count_ < 2) return false;
    for (std::uint32_t t = 0; t < max_tries_; ++t) {
      const std::int32_t i = static_cast<std::int32_t>(rng.below(static_cast<std::uint32_t>(count_)));
      std::int32_t j = static_cast<std::int32_t>(rng.below(static_cast<std::uint32_t>(count_ - 1)));
      if (j >= i) ++j;
      const std::uint32_t ui = static_cast<std::uint32_t>(i), uj = static_cast<std::uint32_t>(j);
      LandmarkMeasurement a = f_[ui], b = f_[uj];
      const float sr = noise_.sigma_range, sa = a.range * noise_.sigma_bearing, sb = b.range * noise_.sigma_bearing;
      const float max_mismatch = kMismatchSigmas * fmath::sqrt(2.0f * (2.0f * sr * sr + sa * sa + sb * sb));
      a.range += sample_normal(rng, noise_.sigma_range);
      a.bearing += sample_normal(rng, noise_.sigma_bearing);
      b.range += sample_normal(rng, noise_.sigma_range);
      b.bearing += sample_normal(rng, noise_.sigma_bearing);
      const TwoLandmarkPose q = pose_from_two_landmarks(map_[c_[ui]], a, map_[c_[uj]], b, 0.05f, max_mismatch);
      if (q.status == TwoLandmarkStatus::ok) {
        p = q.pose;
        return true;
      }
    }
    return false;
  }

 private:
  LandmarkMap map_;
  LandmarkNoise noise_;
  std::uint32_t max_tries_;
  LandmarkMeasurement f_[static_cast<std::uint32_t>(MaxSightings)] = {};
  std::int32_t c_[static_cast<std::uint32_t>(MaxSightings)] = {};
  std::int32_t count_ = 0;
};

}  // namespace est

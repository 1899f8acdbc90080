// MCL's correction with landmark features (est/loop/landmark_correction.hpp): from a Gaussian 0.45 m and 0.15 rad
// off, features of a known map drawn from the true pose pull the set onto it, with the sensor's correspondences and
// without them (MCL without motion cannot move particles: the start is dense enough to hold the truth).
#include <catch2/catch.hpp>

#include <cmath>
#include <memory>

#include "est/filter/augmented_mcl.hpp"
#include "est/loop/landmark_correction.hpp"
#include "est/random/xoshiro128.hpp"

namespace {

const est::Landmark kLandmarks[4] = {{0.0f, 0.0f, 1.0f}, {8.0f, 0.0f, 2.0f}, {8.0f, 6.0f, 3.0f}, {0.0f, 6.0f, 4.0f}};
const est::LandmarkMap kMap(kLandmarks, 4);
constexpr est::LandmarkNoise kNoise{0.1f, 0.05f, 0.0f};

const auto uniform_box = [](est::Rng& rng, est::Pose2& p) {
  p = {rng.uniform(0.0f, 8.0f), rng.uniform(0.0f, 6.0f), rng.uniform(-3.14159f, 3.14159f)};
  return true;
};

// Corrections with every landmark's feature from `truth`, each followed by resampling; the weighted mean after.
est::Pose2 localize(bool known_ids, std::uint64_t seed) {
  est::MclConfig cfg;
  cfg.recovery = false;  // the correction alone: no random particles from the box
  auto owned = std::make_unique<est::AugmentedMcl<2000>>(cfg, seed);  // too large for the stack
  est::AugmentedMcl<2000>& mcl = *owned;
  mcl.initialize_gaussian({4.2f, 2.8f, 0.25f}, 0.5f, 0.2f, 2000);
  est::Rng world(seed + 100u);
  const est::Pose2 truth{4.5f, 2.5f, 0.1f};
  for (int round = 0; round < 5; ++round) {
    for (std::int32_t j = 0; j < kMap.size(); ++j) {
      est::LandmarkMeasurement f = est::sample_landmark_measurement(truth, kLandmarks[j], kNoise, world);
      est::loop::correct_with_landmark(mcl, f, known_ids ? j : -1, kMap, kNoise);
      mcl.resample(uniform_box);
    }
  }
  return mcl.estimate().mean;
}

}  // namespace

TEST_CASE("landmark features pull MCL onto the true pose, with known correspondences and without", "[mcl_landmarks]") {
  for (const bool known : {true, false}) {
    for (std::uint64_t seed = 1; seed <= 3; ++seed) {
      const est::Pose2 m = localize(known, seed);
      INFO("known ids " << known << ", seed " << seed << ": mean " << m.x << ", " << m.y << ", " << m.theta);
      CHECK(std::hypot(m.x - 4.5f, m.y - 2.5f) < 0.1f);
      CHECK(std::fabs(m.theta - 0.1f) < 0.05f);
    }
  }
}

TEST_CASE("the recovery statistic's scale for a landmark feature is one factor at the model's mode",
          "[mcl_landmarks]") {
  const float peak = est::loop::landmark_log_peak(kNoise);
  const est::Pose2 x{2.0f, 1.0f, 0.0f};
  const est::LandmarkMeasurement exact = est::expected_landmark_measurement(x, kLandmarks[1]);
  CHECK(est::landmark_model_known_correspondence(exact, 1, x, kMap, kNoise) == Approx(peak).epsilon(1e-5));
  est::LandmarkMeasurement off = exact;
  off.range += 0.3f;
  CHECK(est::landmark_model_known_correspondence(off, 1, x, kMap, kNoise) < peak - 4.0f);
}

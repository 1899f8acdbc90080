#pragma once
// MCL's correction for a rangefinder on a steered part, the handlebar of the bicycle (Probabilistic Robotics ch. 6
// exercise): the sensor pose depends on the steering angle alpha, which the filter knows only as one of M handle
// positions alpha_m with probabilities p(alpha_m | x), and the measurement model marginalizes it,
//   p(z | x, m) = sum_m p(alpha_m | x) prod_k p(z_k | x, alpha_m, m)
// (est/sensor/steered_range_finder.hpp, in log space), with the likelihood field per beam.
//
// The positions: M centres of M equal sectors across the steering stops, alpha_m = -a_max + (m + 1/2) 2 a_max / M.
// The exercise speaks of six positions and lists five (-pi/3, -pi/6, 0, pi/6, pi/3, spaced pi/6 and ending at the
// stops of a +-pi/3 handlebar): a list of five cannot be six positions, and an even count cannot include 0 while
// staying symmetric. Sector centres cover the whole range of a continuous handlebar evenly, each hypothesis standing
// for the angles nearest it (the quantization is at most half a sector, a_max / M: 10 deg for M = 6 and stops at
// +-60 deg), and they include 0 when M is odd. M = 6 by default, as the exercise says; up to
// kMaxSteeringHypotheses.
//
// p(alpha_m | x): with a steering reading s of standard deviation sigma_s (the sensor's noise and any bias it may
// have: the filter is told what it should not trust), the mass of N(s, sigma_s^2) over sector m, floored at
// `floor` (a reading is never allowed to rule a position out entirely); without a steering sensor (or before its
// first sample), uniform.
#include <cstdint>

#include "est/filter/augmented_mcl.hpp"
#include "est/geometry/pose2.hpp"
#include "est/loop/likelihood_field_scan.hpp"
#include "est/math/fmath.hpp"
#include "est/math/normal.hpp"
#include "est/sensor/likelihood_field_range_finder_model.hpp"
#include "est/sensor/range_scan.hpp"
#include "est/sensor/steered_range_finder.hpp"

namespace est::loop {

struct SteeredScanConfig {
  SteeredMount mount;                 // pivot and the sensor's pose on the handlebar
  float steer_max = 1.0471976f;       // rad, the stops (the bicycle's steer_max)
  std::int32_t positions = 6;         // M
  float reading_sigma = 0.05f;        // rad, sigma_s of the steering reading as the filter should take it
  float floor = 1.0e-3f;              // least p(alpha_m | x) with a reading
  bool use_reading = true;            // false: uniform even when a steering sensor reports
};

class SteeredScan {
 public:
  // The field outlives this. Positions beyond kMaxSteeringHypotheses are cut there.
  SteeredScan(const LikelihoodField& field, const SteeredScanConfig& config) : field_(&field), config_(config) {
    m_ = config.positions < 1 ? 1 : (config.positions > kMaxSteeringHypotheses ? kMaxSteeringHypotheses : config.positions);
    const float width = 2.0f * config.steer_max / static_cast<float>(m_);
    for (std::int32_t i = 0; i < m_; ++i) alphas_[i] = -config.steer_max + (static_cast<float>(i) + 0.5f) * width;
  }

  // p(alpha_m | x) for a steering reading (or none).
  void handle_probabilities(const ScanContext& c, float* probs) const {
    if (!c.steering_known || !config_.use_reading || !(config_.reading_sigma > 0.0f)) {
      for (std::int32_t i = 0; i < m_; ++i) probs[i] = 1.0f / static_cast<float>(m_);
      return;
    }
    const float width = 2.0f * config_.steer_max / static_cast<float>(m_);
    const float inv = 1.0f / config_.reading_sigma;
    float sum = 0.0f;
    for (std::int32_t i = 0; i < m_; ++i) {
      // The outer sectors reach the stops and beyond: a reading past a stop belongs to the last position.
      const float lo = i == 0 ? -1.0e30f : alphas_[i] - 0.5f * width;
      const float hi = i == m_ - 1 ? 1.0e30f : alphas_[i] + 0.5f * width;
      const float a = lo < -1.0e29f ? -10.0f : (lo - c.steering_rad) * inv;
      const float b = hi > 1.0e29f ? 10.0f : (hi - c.steering_rad) * inv;
      float p = normal_cdf(b) - normal_cdf(a);
      if (!(p > config_.floor)) p = config_.floor;
      probs[i] = p;
      sum += p;
    }
    for (std::int32_t i = 0; i < m_; ++i) probs[i] /= sum;
  }

  template <std::uint32_t N>
  CorrectionReport correct(AugmentedMcl<N>& mcl, const ScanBeams& beams, const ScanContext& c) {
    float probs[kMaxSteeringHypotheses];
    handle_probabilities(c, probs);
    const LikelihoodField& field = *field_;
    const SteeredMount& mount = config_.mount;
    const float* alphas = alphas_;
    const std::int32_t m = m_;
    return mcl.correct([&](const Pose2& x) {
      return steered_likelihood_field_range_finder_model(beams, x, mount, alphas, probs, m, field);
    });
  }

  std::int32_t positions() const { return m_; }
  const float* alphas() const { return alphas_; }
  const SteeredScanConfig& config() const { return config_; }

 private:
  const LikelihoodField* field_;
  SteeredScanConfig config_;
  std::int32_t m_ = 1;
  float alphas_[kMaxSteeringHypotheses] = {};
};

}  // namespace est::loop

#pragma once
// MCL's correction for a rangefinder on a steered part, the handlebar of the bicycle (Probabilistic Robotics ch. 6
// exercise): the sensor pose depends on the steering angle alpha, which the filter knows only as one of M handle
// positions alpha_m with probabilities p(alpha_m | x), and the measurement model marginalizes it,
//   p(z | x, m) = sum_m p(alpha_m | x) prod_k p(z_k | x, alpha_m, m),
// with the likelihood field per beam (table 6.3), in log space.
//
// The positions: M evenly spaced from stop to stop, alpha_m = -a_max + m 2 a_max / (M - 1). The exercise speaks of
// six positions and lists five, -pi/3, -pi/6, 0, pi/6, pi/3: those five are this rule for M = 5 on a handlebar whose
// stops are at +-pi/3 (a handlebar's positions run from one stop to the other, both included, evenly). M = 6 by
// default, as the exercise says; then 0 is not a position (a six-notch handlebar steers straight by alternating
// +-a_max/5), and M = 5 or any odd M has it. A continuous handlebar is approximated to half a spacing, a_max / (M - 1):
// give it a larger M (25 positions put every angle within 2.5 deg of one at +-60 deg stops).
//
// p(alpha_m | x): with a steering reading s of standard deviation sigma_s (the sensor's noise and any bias it may
// have: the filter is told what it should not trust), the mass of N(s, sigma_s^2) over the angles nearest alpha_m
// (the outer positions take everything beyond them), floored at `floor` (a reading never rules a position out
// entirely); without a steering sensor (or before its first sample), uniform.
//
// Why the scans estimate the steering too: a scan from the handlebar fixes the sensor's pose, that is the frame's
// heading plus the steering angle, theta + alpha, not theta alone; the frame's heading is pinned only by the
// bicycle's kinematics (the front wheel runs along theta + alpha, the frame turns at v sin(alpha) / l), so the
// prediction must use the steering the correction believes, or the two pull theta apart by the steering's error.
// After each correction the posterior over the handle positions, P_m ~ p(alpha_m | x) sum_i w_i p(z | x_i, alpha_m)
// (the marginal of the joint belief over pose and handle position), gives a steering estimate (the P-weighted mean
// of the most probable position and its neighbours) that MclEstimator hands to the next predictions in place of the
// reading (steering_estimate()): with a biased reading the scans correct it, without a sensor they supply it.
//
// positions = 0 is the baseline the marginalization is measured against: one hypothesis at the steering reading,
// taken as exact (at 0 without a reading), and no steering estimate.
#include <cstdint>

#include "est/filter/augmented_mcl.hpp"
#include "est/geometry/pose2.hpp"
#include "est/loop/likelihood_field_scan.hpp"
#include "est/math/fmath.hpp"
#include "est/math/normal.hpp"
#include "est/motion/motion_density.hpp"
#include "est/sensor/likelihood_field_grid.hpp"
#include "est/sensor/likelihood_field_range_finder_model.hpp"
#include "est/sensor/range_scan.hpp"
#include "est/sensor/steered_range_finder.hpp"

namespace est::loop {

struct SteeredScanConfig {
  SteeredMount mount;                 // pivot and the sensor's pose on the handlebar
  float steer_max = 1.0471976f;       // rad, the stops (the bicycle's steer_max)
  std::int32_t positions = 6;         // M; 0: the steering reading taken as exact
  float reading_sigma = 0.05f;        // rad, sigma_s of the steering reading as the filter should take it
  float floor = 1.0e-3f;              // least p(alpha_m | x) with a reading
  bool use_reading = true;            // false: uniform even when a steering sensor reports
};

// NMax: the particle capacity of the filter it corrects (a buffer of one log-likelihood per particle).
template <std::uint32_t NMax>
class SteeredScan {
 public:
  // The field (and the grid, if given: tabulated from that field) outlive this. Positions beyond
  // kMaxSteeringHypotheses are cut there.
  SteeredScan(const LikelihoodField& field, const SteeredScanConfig& config,
              const LikelihoodFieldGrid* grid = nullptr)
      : field_(&field), grid_(grid), config_(config) {
    exact_ = config.positions < 1;
    m_ = exact_ ? 1 : (config.positions > kMaxSteeringHypotheses ? kMaxSteeringHypotheses : config.positions);
    for (std::int32_t i = 0; i < m_; ++i)
      alphas_[i] = m_ == 1 ? 0.0f
                           : -config.steer_max + static_cast<float>(i) * (2.0f * config.steer_max) /
                                                     static_cast<float>(m_ - 1);
  }
  SteeredScan(const SteeredScan& o)
      : field_(o.field_), grid_(o.grid_), config_(o.config_), m_(o.m_), exact_(o.exact_) {
    for (std::int32_t i = 0; i < kMaxSteeringHypotheses; ++i) alphas_[i] = o.alphas_[i];
  }
  SteeredScan& operator=(const SteeredScan&) = delete;

  // p(alpha_m | x) for a steering reading (or none).
  void handle_probabilities(const ScanContext& c, float* probs) const {
    if (!c.steering_known || !config_.use_reading || !(config_.reading_sigma > 0.0f) || m_ == 1) {
      for (std::int32_t i = 0; i < m_; ++i) probs[i] = 1.0f / static_cast<float>(m_);
      return;
    }
    const float inv = 1.0f / config_.reading_sigma;
    float sum = 0.0f;
    for (std::int32_t i = 0; i < m_; ++i) {
      // The angles nearest alpha_i; the outer positions reach the stops and beyond.
      const float a = i == 0 ? -10.0f : (0.5f * (alphas_[i - 1] + alphas_[i]) - c.steering_rad) * inv;
      const float b = i == m_ - 1 ? 10.0f : (0.5f * (alphas_[i] + alphas_[i + 1]) - c.steering_rad) * inv;
      float p = normal_cdf(b < 10.0f ? b : 10.0f) - normal_cdf(a > -10.0f ? a : -10.0f);
      if (!(p > config_.floor)) p = config_.floor;
      probs[i] = p;
      sum += p;
    }
    for (std::int32_t i = 0; i < m_; ++i) probs[i] /= sum;
  }

  template <std::uint32_t N>
  CorrectionReport correct(AugmentedMcl<N>& mcl, const ScanBeams& beams, const ScanContext& c) {
    static_assert(N <= NMax, "the steered range model's buffer holds fewer particles than the filter");
    float probs[kMaxSteeringHypotheses];
    float alphas[kMaxSteeringHypotheses];
    handle_probabilities(c, probs);
    for (std::int32_t i = 0; i < m_; ++i) alphas[i] = alphas_[i];
    if (exact_) {
      alphas[0] = c.steering_known ? c.steering_rad : 0.0f;
      probs[0] = 1.0f;
    }
    float evidence[kMaxSteeringHypotheses] = {};  // log sum_i w_i p(z | x_i, alpha_m)
    const CorrectionReport r = mcl.correct_batch([&](ConstParticleSetView v, float* out) {
      for (std::uint32_t i = 0; i < v.count; ++i) out[i] = kLogZero;
      for (std::int32_t m = 0; m < m_; ++m) {
        evidence[m] = kLogZero;
        if (!(probs[m] > 0.0f)) continue;
        const Pose2 mount = steered_sensor_mount(config_.mount, alphas[m]);
        scan_log_likelihoods(beams, v, mount, buffer_);
        const float log_p = fmath::log(probs[m]);
        for (std::uint32_t i = 0; i < v.count; ++i) {
          out[i] = motion_density::log_add(out[i], log_p + buffer_[i]);
          evidence[m] = motion_density::log_add(evidence[m], v.log_w[i] + buffer_[i]);
        }
      }
    }, likelihood_field_scale(beams, *field_));  // a mixture of products: at most its largest component's bound
    if (!exact_) update_estimate(probs, evidence);
    return r;
  }

  // The steering the last correction believes (see the header comment); false before one, or as the exact baseline.
  bool steering_estimate(float& alpha) const {
    if (!have_estimate_) return false;
    alpha = estimate_;
    return true;
  }

  std::int32_t positions() const { return m_; }
  const float* alphas() const { return alphas_; }
  const SteeredScanConfig& config() const { return config_; }
  const Pose2 mount() const { return steered_sensor_mount(config_.mount, 0.0f); }

 private:
  void scan_log_likelihoods(const ScanBeams& beams, ConstParticleSetView v, const Pose2& mount, float* out) const {
    if (grid_ != nullptr && grid_->valid()) {
      likelihood_field_range_finder_model_batch(beams, v.x, v.y, v.theta, v.count, mount, *grid_, out);
      return;
    }
    for (std::uint32_t i = 0; i < v.count; ++i)
      out[i] = likelihood_field_range_finder_model(beams, v.pose(i), mount, *field_);
  }

  void update_estimate(const float* probs, const float* evidence) {
    float post[kMaxSteeringHypotheses] = {};
    std::int32_t best = 0;
    for (std::int32_t m = 0; m < m_; ++m) {
      post[m] = probs[m] > 0.0f ? fmath::log(probs[m]) + evidence[m] : kLogZero;
      if (post[m] > post[best]) best = m;
    }
    if (!(post[best] > kLogZero)) return;  // nothing explained the scan: keep the previous estimate
    const std::int32_t lo = best > 0 ? best - 1 : 0, hi = best + 1 < m_ ? best + 1 : m_ - 1;
    float sum = 0.0f, mean = 0.0f;
    for (std::int32_t m = lo; m <= hi; ++m) {
      const float w = post[m] - post[best] < -87.0f ? 0.0f : fmath::exp(post[m] - post[best]);
      sum += w;
      mean += w * alphas_[m];
    }
    estimate_ = mean / sum;
    have_estimate_ = true;
  }

  const LikelihoodField* field_;
  const LikelihoodFieldGrid* grid_;
  SteeredScanConfig config_;
  std::int32_t m_ = 1;
  bool exact_ = false;
  float alphas_[kMaxSteeringHypotheses] = {};
  float estimate_ = 0.0f;
  bool have_estimate_ = false;
  float buffer_[NMax];
};

}  // namespace est::loop

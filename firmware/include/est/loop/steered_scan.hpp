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
// entirely); without a steering sensor (or before its first sample), uniform. The floor is 0.05, not a rounding
// guard: the scans cannot tell (theta, m) from (theta + alpha_m - alpha_m', m') (below), so at such a scan the
// reading alone decides, and a reading that names the wrong position (held while the sensor's samples at a stop are
// refused, lagging a change, biased) must not outvote what the kinematics have gathered. Chosen on seeds 1-10 of
// bicycle-rangefinder-global with the steering sensor present (1e-3: heading RMSE 6-10 deg from the wrong
// position winning for 0.3-0.9 s at the stops; 0.05: the same as without a sensor).
//
// Why the scans estimate the steering too: a scan from the handlebar fixes the sensor's pose, that is the frame's
// heading plus the steering angle, theta + alpha, not theta alone; the frame's heading is pinned only by the
// bicycle's kinematics (the front wheel runs along theta + alpha, the frame turns at v sin(alpha) / l), so the
// prediction must use the steering the correction believes, or the two pull theta apart by the steering's error.
//
// The handle position is part of each particle's state (its mode, est/filter/particle_set.hpp): the filter runs
// over the joint (x, y, theta, m). Each correction is the optimal proposal for the discrete part,
//   w_i *= sum_m T(m_i, m) p(alpha_m | s) p(z | x_i, alpha_m),   m_i ~ T(m_i, m) p(alpha_m | s) p(z | x_i, alpha_m),
// with T the handle's moves between scans (stay; a neighbouring position with switch_probability; any position with
// jump_probability; uniform for a particle without a mode: initialized or injected), and each particle is
// predicted with its own position's steering (MclEstimator). Why per particle and not one steering for the set (the
// design before: the handle posterior of the whole set, handed to every prediction): from a global start, or after a
// kidnapping, (theta, m) and (theta + alpha_m - alpha_m', m') fit a scan alike, and one shared steering is right for
// one of them only, so every particle turned with the kinematics of the hypothesis the set believed and the right
// one could never win: the frame's heading stayed one or two positions (20-45 deg) off for whole runs. With its own
// steering each hypothesis turns as its handle says, so the path's curvature against the handle separates them once
// the bicycle moves (a wrong one drifts off its scans by ~v dt |sin a - sin a'| / l a step), and the KLD bins count
// the mode (kld_sampling.hpp), so the hypotheses keep their samples until then.
// Injection along the ambiguity (split()): the scans cannot tell those hypotheses apart, so one scan from a uniform
// cloud gives its weight to one particle and one hypothesis, chosen by chance; after every resampling split_share of
// the particles are moved to another position m' with the pose that keeps their sensor's pose (the frame turned by
// alpha_m - alpha_m', and moved where the pivot is off the reference point). They fit the last scan exactly as
// before; the next scans keep those whose handle the kinematics bear out. Once the right hypothesis holds, the split
// ones drift off by the next scan and lose their weight (the estimate is taken before resampling, so they never
// enter it). Not a random particle: counted apart (splits()), never as the recovery's injection. The estimate
// between scans is the strongest cluster's heaviest mode (est/filter/particle_estimate.hpp, by_mode): the split
// particles share the place of the ones they came from, and their headings (24 deg and more off) must not enter the
// mean (they had put 1.5-2.2 deg of heading RMSE on tracking). split_share 0.05, switch 0.3, jump 0.02: chosen on
// seeds 1-10.
//
// positions = 0 is the baseline the marginalization is measured against: one hypothesis at the steering reading,
// taken as exact (at 0 without a reading), and no modes.
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
  float floor = 0.05f;                // least p(alpha_m | x) with a reading: how often it names a wrong position
  bool use_reading = true;            // false: uniform even when a steering sensor reports
  float switch_probability = 0.3f;    // T: the handle moved to a neighbouring position since the last scan
  float jump_probability = 0.02f;     // T: to any position (spread over all of them)
  float split_share = 0.05f;          // of a resampled set, taken to another position with the same sensor pose
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
    moded_ = !exact_ && m_ > 1;
    if (moded_) build_transitions();
    for (std::int32_t i = 0; i < m_; ++i) {
      mounts_[i] = steered_sensor_mount(config.mount, alphas_[i]);
      unmounts_[i] = inverse(mounts_[i]);
    }
  }
  SteeredScan(const SteeredScan& o)
      : field_(o.field_), grid_(o.grid_), config_(o.config_), m_(o.m_), exact_(o.exact_), moded_(o.moded_) {
    for (std::int32_t i = 0; i < kMaxSteeringHypotheses; ++i) {
      alphas_[i] = o.alphas_[i];
      mounts_[i] = o.mounts_[i];
      unmounts_[i] = o.unmounts_[i];
    }
    for (std::int32_t h = 0; h <= kMaxSteeringHypotheses; ++h)
      for (std::int32_t i = 0; i < kMaxSteeringHypotheses; ++i) log_t_[h][i] = o.log_t_[h][i];
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
    handle_probabilities(c, probs);
    const MeasurementScale scale = likelihood_field_scale(beams, *field_);  // a mixture: its largest component's
    if (!moded_) {
      const float alpha = exact_ ? (c.steering_known ? c.steering_rad : 0.0f) : alphas_[0];
      const Pose2 mount = steered_sensor_mount(config_.mount, alpha);
      return mcl.correct_batch([&](ConstParticleSetView v, float* out) { scan_log_likelihoods(beams, v, mount, out); },
                               scale);
    }
    float log_p[kMaxSteeringHypotheses];
    for (std::int32_t m = 0; m < m_; ++m) log_p[m] = probs[m] > 0.0f ? fmath::log(probs[m]) : kLogZero;
    Rng& rng = mcl.rng();
    const CorrectionReport r = mcl.correct_batch([&](ConstParticleSetView v, float* out) {
      for (std::uint32_t i = 0; i < v.count; ++i) out[i] = kLogZero;
      for (std::int32_t m = 0; m < m_; ++m) {
        if (!(log_p[m] > kLogZero)) continue;
        scan_log_likelihoods(beams, v, mounts_[m], buffer_);
        const std::uint8_t pm = static_cast<std::uint8_t>(m);
        for (std::uint32_t i = 0; i < v.count; ++i) {
          const std::int32_t h = v.mode[i] < m_ ? v.mode[i] : kMaxSteeringHypotheses;
          const float a = log_t_[h][m] + log_p[m] + buffer_[i];
          if (!(a > kLogZero)) continue;
          // m_i drawn as the terms arrive: the new one takes the choice with its share of the sum so far.
          const float sum = motion_density::log_add(out[i], a);
          if (!(out[i] > kLogZero) || rng.uniform() < fmath::exp(a - sum)) next_[i] = pm;
          out[i] = sum;
        }
      }
    }, scale);
    const ConstParticleSetView v = mcl.particles();
    std::uint8_t* modes = mcl.particle_modes();
    for (std::uint32_t i = 0; i < v.count; ++i)
      if (v.log_w[i] > kLogZero) modes[i] = next_[i];  // a particle no term explained keeps its mode
    return r;
  }

  // Injection along the ambiguity (header), after a resampling: split_share of the particles, drawn at random, each to
  // another position with the same sensor pose. Returns how many moved.
  template <std::uint32_t N>
  std::uint32_t split(AugmentedMcl<N>& mcl) {
    if (!moded_ || !(config_.split_share > 0.0f)) return 0u;
    Rng& rng = mcl.rng();
    ParticleSetView v = mcl.particles_mutable();
    if (v.count == 0u) return 0u;
    std::uint32_t n = static_cast<std::uint32_t>(config_.split_share * static_cast<float>(v.count) + rng.uniform());
    if (n > v.count) n = v.count;
    std::uint32_t moved = 0;
    for (std::uint32_t k = 0; k < n; ++k) {
      const std::uint32_t i = rng.below(v.count);
      const std::uint8_t h = v.mode[i];
      if (h >= m_) continue;  // no position yet: every one is open to it anyway
      std::uint32_t to = rng.below(static_cast<std::uint32_t>(m_ - 1));
      if (to >= h) ++to;
      v.set_pose(i, compose(compose(v.pose(i), mounts_[h]), unmounts_[to]));
      v.mode[i] = static_cast<std::uint8_t>(to);
      ++moved;
    }
    splits_ += moved;
    return moved;
  }
  std::uint32_t splits() const { return splits_; }

  // The handle positions the particles carry as modes, each a steering for the predictions (MclEstimator); 0 when
  // the model carries none (the exact baseline, or one position).
  std::int32_t modes() const { return moded_ ? m_ : 0; }

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

  // log T(h, m): row h the handle position at the last scan; row kMaxSteeringHypotheses none yet (uniform).
  void build_transitions() {
    const float stay = 1.0f - config_.switch_probability - config_.jump_probability;
    for (std::int32_t h = 0; h < m_; ++h) {
      float t[kMaxSteeringHypotheses];
      const std::int32_t neighbours = (h > 0 ? 1 : 0) + (h + 1 < m_ ? 1 : 0);
      float sum = 0.0f;
      for (std::int32_t m = 0; m < m_; ++m) {
        t[m] = config_.jump_probability / static_cast<float>(m_);
        if (m == h) t[m] += stay > 0.0f ? stay : 0.0f;
        if (m == h - 1 || m == h + 1) t[m] += config_.switch_probability / static_cast<float>(neighbours);
        sum += t[m];
      }
      for (std::int32_t m = 0; m < m_; ++m) log_t_[h][m] = t[m] > 0.0f ? fmath::log(t[m] / sum) : kLogZero;
    }
    for (std::int32_t m = 0; m < m_; ++m) log_t_[kMaxSteeringHypotheses][m] = -fmath::log(static_cast<float>(m_));
  }

  const LikelihoodField* field_;
  const LikelihoodFieldGrid* grid_;
  SteeredScanConfig config_;
  std::int32_t m_ = 1;
  bool exact_ = false;
  bool moded_ = false;
  float alphas_[kMaxSteeringHypotheses] = {};
  float log_t_[kMaxSteeringHypotheses + 1][kMaxSteeringHypotheses] = {};
  Pose2 mounts_[kMaxSteeringHypotheses];    // the sensor on the frame at each position
  Pose2 unmounts_[kMaxSteeringHypotheses];  // their inverses
  std::uint32_t splits_ = 0;
  float buffer_[NMax];
  std::uint8_t next_[NMax];  // the modes drawn by the correction in progress
};

}  // namespace est::loop

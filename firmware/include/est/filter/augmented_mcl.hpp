#pragma once
// Monte Carlo localization with recovery: augmented_mcl, Thrun table 8.3 (w_slow/w_fast), with log-space weights,
// resampling only when the effective sample size falls below a threshold (Thrun 4.3.4), optional KLD-adaptive
// particle counts (table 8.4, applied at resampling), and map-conditioned prediction
// p(x_t | u_t, x_t-1, m) ~ p(x_t | m) p(x_t | u_t, x_t-1) (Thrun eq. 5.47): particles predicted into occupied or
// unknown space are down-weighted.
//
// The filter is generic: any motion model of est/motion (static sample/check), any measurement model given as a
// callable `float log_likelihood(const Pose2&)`, any map given as a callable `bool is_free(float x, float y)`, and
// any source of recovery particles given as a callable `bool draw(Rng&, Pose2&)` (uniform over free space, or the
// two-landmark closed-form pose). No heap: N_max is the template parameter; every loop is bounded by it.
// Whole-set forms for speed: predict_batch (est/motion/motion_batch.hpp: same distribution, vectorizable) and
// correct_batch (a batched log-likelihood such as likelihood_field_range_finder_model_batch: same bits).
#include <cstdint>

#include "est/filter/kld_sampling.hpp"
#include "est/filter/log_weights.hpp"
#include "est/filter/low_variance_sampler.hpp"
#include "est/filter/particle_estimate.hpp"
#include "est/filter/particle_set.hpp"
#include "est/motion/motion_model.hpp"
#include "est/random/samplers.hpp"
#include "est/random/xoshiro128.hpp"

namespace est {

struct MclConfig {
  float resample_ess_fraction = 0.5f;  // resample when ESS < fraction * N
  bool recovery = true;                // augmented MCL: inject random particles when w_fast falls below w_slow
  float alpha_slow = 0.001f;           // 0 <= alpha_slow << alpha_fast (table 8.3)
  float alpha_fast = 0.1f;
  float max_injection_fraction = 0.5f; // at most this share of a resampled set is injected
  float occupied_log_weight = -4.6f;   // log p(x | m) for a particle in occupied/unknown space (log 0.01)
  bool kld = false;                    // adapt the particle count by KLD-sampling at each resampling
  KldConfig kld_config{};
};

struct MclCounters {
  std::uint32_t predictions = 0;
  std::uint32_t rejected_controls = 0;    // motion inputs the model's check() refused
  std::uint32_t corrections = 0;
  std::uint32_t degenerate_corrections = 0;  // every weight was zero or NaN: weights reset, recovery forced
  std::uint32_t nonfinite_weights = 0;    // single NaN/inf log-likelihoods treated as zero weight
  std::uint32_t resamplings = 0;
  std::uint32_t injected_particles = 0;
  std::uint32_t failed_injections = 0;    // the injector could not draw a pose (e.g. no free cell found in its tries)
  std::uint32_t map_penalized = 0;        // particles predicted into occupied or unknown space
};

struct CorrectionReport {
  float log_mean_likelihood;  // log of the average likelihood over particles (w_avg of table 8.3, in log space)
  float ess;
  bool degenerate;
};

template <std::uint32_t NMax>
class AugmentedMcl {
 public:
  static constexpr std::uint32_t kCapacity = NMax;

  AugmentedMcl(const MclConfig& config, std::uint64_t seed) : config_(config), rng_(seed) {}

  // Particles from N(mean, diag(sigma^2)), equal weights.
  void initialize_gaussian(const Pose2& mean, float sigma_xy, float sigma_theta, std::uint32_t n) {
    set_.set_count(n);
    ParticleSetView v = set_.view();
    const float lw = -fmath::log(static_cast<float>(v.count));
    for (std::uint32_t i = 0; i < v.count; ++i) {
      v.x[i] = mean.x + sample_normal(rng_, sigma_xy);
      v.y[i] = mean.y + sample_normal(rng_, sigma_xy);
      v.theta[i] = fmath::normalize_angle(mean.theta + sample_normal(rng_, sigma_theta));
      v.log_w[i] = lw;
    }
    reset_averages();
  }

  // Global localization: particles drawn by `draw(Rng&, Pose2&)`, e.g. uniform over free space. Returns how many
  // were drawn; a failed draw is counted and the slot gets a copy of the previous particle.
  template <typename Injector>
  std::uint32_t initialize_global(const Injector& draw, std::uint32_t n) {
    set_.set_count(n);
    ParticleSetView v = set_.view();
    const float lw = -fmath::log(static_cast<float>(v.count));
    std::uint32_t drawn = 0;
    for (std::uint32_t i = 0; i < v.count; ++i) {
      Pose2 p;
      if (draw(rng_, p)) {
        ++drawn;
      } else {
        ++counters_.failed_injections;
        p = i > 0 ? v.pose(i - 1) : Pose2{};
      }
      v.set_pose(i, p);
      v.log_w[i] = lw;
    }
    reset_averages();
    return drawn;
  }

  // Prediction: every particle sampled from p(x_t | u_t, x_t-1). A control the model refuses leaves the set as it is.
  template <typename Model>
  MotionStatus predict(const typename Model::Control& u, const typename Model::Params& p) {
    const MotionStatus s = Model::check(u, p);
    if (!usable(s)) {
      ++counters_.rejected_controls;
      return s;
    }
    ParticleSetView v = set_.view();
    for (std::uint32_t i = 0; i < v.count; ++i) v.set_pose(i, Model::sample(v.pose(i), u, p, rng_));
    ++counters_.predictions;
    return s;
  }

  // The same prediction for the whole set at once by sample_motion_batch (est/motion/motion_batch.hpp, which the
  // caller includes): noise drawn in bulk, inline trigonometry; the same distribution as predict(), not the same
  // bits. The scratch set holds the noise (it is idle between resamplings).
  template <typename Model>
  MotionStatus predict_batch(const typename Model::Control& u, const typename Model::Params& p) {
    const MotionStatus s = Model::check(u, p);
    if (!usable(s)) {
      ++counters_.rejected_controls;
      return s;
    }
    ParticleSetView v = set_.view();
    ParticleSetView scratch = set_.scratch();
    sample_motion_batch(Model{}, u, p, v.x, v.y, v.theta, v.count, rng_, {scratch.x, scratch.y, scratch.theta});
    ++counters_.predictions;
    return s;
  }

  // Prediction conditioned on the map (Thrun eq. 5.47): as predict(), then log p(x | m) added to each weight.
  template <typename Model, typename IsFree>
  MotionStatus predict_in_map(const typename Model::Control& u, const typename Model::Params& p,
                              const IsFree& is_free) {
    const MotionStatus s = predict<Model>(u, p);
    if (usable(s)) penalize_occupied(is_free);
    return s;
  }
  template <typename Model, typename IsFree>
  MotionStatus predict_in_map_batch(const typename Model::Control& u, const typename Model::Params& p,
                                    const IsFree& is_free) {
    const MotionStatus s = predict_batch<Model>(u, p);
    if (usable(s)) penalize_occupied(is_free);
    return s;
  }

  // Correction: w_i *= p(z | x_i, m), normalized in log space; w_slow and w_fast follow the average likelihood.
  template <typename LogLikelihood>
  CorrectionReport correct(const LogLikelihood& log_likelihood) {
    ParticleSetView v = set_.view();
    // log w_avg = log( sum_i w_i p(z|x_i) ) for normalized prior weights: the predictive likelihood of z.
    for (std::uint32_t i = 0; i < v.count; ++i) v.log_w[i] += log_likelihood(v.pose(i));
    return finish_correction(v);
  }

  // The same correction with the log-likelihoods of the whole set computed at once by
  // `batch(ConstParticleSetView, float* out)` (e.g. likelihood_field_range_finder_model_batch, which vectorizes
  // across particles): bit-identical to correct() when batch gives the per-particle values. `out` is the scratch
  // buffer's weight array, idle between resamplings.
  template <typename BatchLogLikelihood>
  CorrectionReport correct_batch(const BatchLogLikelihood& batch) {
    ParticleSetView v = set_.view();
    float* ll = set_.scratch().log_w;
    batch(ConstParticleSetView(v), ll);
    for (std::uint32_t i = 0; i < v.count; ++i) v.log_w[i] += ll[i];
    return finish_correction(v);
  }

  // Resampling when ESS < fraction * N (always when `force`), with augmented-MCL injection drawn by `draw`.
  // Returns true if the set was resampled.
  template <typename Injector>
  bool resample(const Injector& draw, bool force = false) {
    ParticleSetView v = set_.view();
    const float ess = effective_sample_size(v.log_w, v.count);
    const float p_inject = injection_probability();
    if (!force && !force_recovery_ && p_inject <= 0.0f &&
        ess >= config_.resample_ess_fraction * static_cast<float>(v.count))
      return false;

    std::uint32_t m = v.count;
    if (config_.kld) m = kld_particle_count(ConstParticleSetView(v), config_.kld_config, NMax, bins_);
    // Stochastic rounding keeps the expected number of injected particles at p * m with a deterministic stream.
    const float expected = p_inject * static_cast<float>(m);
    std::uint32_t n_inject = static_cast<std::uint32_t>(expected + rng_.uniform());
    if (n_inject > m) n_inject = m;

    ParticleSetView out = set_.scratch();
    const std::uint32_t drawn = low_variance_sampler(ConstParticleSetView(v), out, m - n_inject, rng_);
    for (std::uint32_t k = drawn; k < m; ++k) {
      Pose2 p;
      if (draw(rng_, p)) {
        ++counters_.injected_particles;
      } else {
        ++counters_.failed_injections;
        p = out.pose(drawn > 0u ? k % drawn : 0u);
        if (drawn == 0u) p = v.pose(k % v.count);
      }
      out.set_pose(k, p);
    }
    const float lw = -fmath::log(static_cast<float>(m));
    for (std::uint32_t k = 0; k < m; ++k) out.log_w[k] = lw;
    set_.swap_with_scratch(m);
    ++counters_.resamplings;
    // As table 8.3: the averages are NOT reset after an injection. Restarting them at the (low) likelihood of a
    // kidnapped robot would make w_fast = w_slow there and stop the injection after one burst of a few percent.
    force_recovery_ = false;
    return true;
  }

  // max(0, 1 - w_fast / w_slow) (table 8.3, line 13), capped; 1 share of the cap after a degenerate correction.
  float injection_probability() const {
    if (!config_.recovery) return 0.0f;
    if (force_recovery_) return config_.max_injection_fraction;
    if (!averages_valid_) return 0.0f;
    const float ratio = fmath::exp(log_w_fast_ - log_w_slow_);
    const float p = 1.0f - ratio;
    if (!(p > 0.0f)) return 0.0f;
    return p < config_.max_injection_fraction ? p : config_.max_injection_fraction;
  }

  PoseEstimate estimate() const { return weighted_mean(set_.view()); }
  ClusterEstimate cluster_estimate(float cell = 1.0f) const { return strongest_cluster(set_.view(), cell); }

  ConstParticleSetView particles() const { return set_.view(); }
  ParticleSetView particles_mutable() { return set_.view(); }
  const MclCounters& counters() const { return counters_; }
  const MclConfig& config() const { return config_; }
  Rng& rng() { return rng_; }

 private:
  template <typename IsFree>
  void penalize_occupied(const IsFree& is_free) {
    ParticleSetView v = set_.view();
    std::uint32_t penalized = 0;
    for (std::uint32_t i = 0; i < v.count; ++i) {
      if (!is_free(v.x[i], v.y[i])) {
        v.log_w[i] += config_.occupied_log_weight;
        ++penalized;
      }
    }
    if (penalized > 0u) {
      counters_.map_penalized += penalized;
      normalize_log_weights(v.log_w, v.count);
    }
  }

  CorrectionReport finish_correction(ParticleSetView v) {
    const LogNormalization n = normalize_log_weights(v.log_w, v.count);
    ++counters_.corrections;
    counters_.nonfinite_weights += n.nonfinite;
    CorrectionReport r{n.log_sum, effective_sample_size(v.log_w, v.count), n.degenerate};
    if (n.degenerate) {
      ++counters_.degenerate_corrections;
      force_recovery_ = true;  // nothing explains z: the next resampling injects as many particles as allowed
    } else {
      update_averages(n.log_sum);
    }
    return r;
  }

  void reset_averages() {
    averages_valid_ = false;
    force_recovery_ = false;
  }

  // w <- w + alpha (w_avg - w) in log space: log w + log(1 + alpha (exp(log w_avg - log w) - 1)).
  static float smooth_log(float log_w, float log_avg, float alpha) {
    const float d = log_avg - log_w;
    if (d > 20.0f) return log_w + d + fmath::log(alpha + (1.0f - alpha) * fmath::exp(-d));
    return log_w + fmath::log(1.0f + alpha * (fmath::exp(d) - 1.0f));
  }

  void update_averages(float log_avg) {
    if (!averages_valid_) {
      log_w_slow_ = log_avg;
      log_w_fast_ = log_avg;
      averages_valid_ = true;
      return;
    }
    log_w_slow_ = smooth_log(log_w_slow_, log_avg, config_.alpha_slow);
    log_w_fast_ = smooth_log(log_w_fast_, log_avg, config_.alpha_fast);
  }

  MclConfig config_;
  Rng rng_;
  ParticleSet<NMax> set_;
  BinCounter<4096> bins_;
  MclCounters counters_;
  float log_w_slow_ = 0.0f;
  float log_w_fast_ = 0.0f;
  bool averages_valid_ = false;
  bool force_recovery_ = false;
};

}  // namespace est

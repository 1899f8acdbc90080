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
//
// The importance weights are the book's: w_i *= p(z | x_i, m), the product over the beams (tables 6.1 / 6.3), kept
// in log space.
//
// RECOVERY STATISTIC (what w_slow and w_fast average, table 8.3 lines 10-12). The book averages the predictive
// likelihood of the whole scan, w_avg = sum_i w_i p(z | x_i). Its log is a sum over the K beams, so it moves by
// several nats from one scan to the next while the filter is exactly right (range noise, the share of max readings
// and of beams on clutter, K itself); w_slow, a linear average, sits near the best recent scans, so with 60 beams
// w_fast / w_slow was ~e^-5 on an ordinary scan and the injection ran at its cap while tracking (1.8 million random
// particles in the office demo). When the caller states the measurement's scale (MeasurementScale: K factors and the
// origin log_peak, what one factor of a correct pose scores) the averages take instead the per-beam fit of the
// predictive likelihood
//     f_t = min(0, log(w_avg) / K - log_peak)     (0: every beam as well as a correct pose's),
// exp(f_t) being the geometric mean over the beams of p(z_k | x) / e^log_peak. Why this statistic:
//  - per beam, its scan-to-scan spread falls like 1/sqrt(K) instead of growing like sqrt(K): in the office demo it
//    is -0.11 +- 0.08 while tracking; kidnapped, the old cloud misses most beams and f drops to -2..-3.4; on a
//    look-alike pose (the 180-degree corridor) it stays at -0.4..-1, where a share-of-beams test sees almost
//    nothing (83-97 % of the beams still end within 0.4-0.6 m of a wall) because here one bad beam costs ~5 nats;
//  - it has an absolute origin, so the averages start at a perfect fit (f = 0) at every initialization instead of
//    at the first scan: from the uniform cloud's first scan (the worst of a run) any later hypothesis looked like an
//    improvement, and a filter settled on the corridor look-alike never injected again (the 12.1 s failure);
//  - the filter computes it from what it has (w_avg): the model owes only K and its origin, computed once
//    (LikelihoodField::log_term_max(), the field's mode; a marginalized model's largest component; the beam model's
//    typical hit, BeamRangeFinderModel::log_typical(), half a nat under its peak: its sigma_hit is the sensor's, so
//    a correct pose scores the Gaussian's mean log density, not its mode. Measured from the beam model's peak a
//    filter tracking exactly scored -0.4 to -0.6 a beam, and from the start's perfect fit w_slow took 10-20 s to
//    come down: 14-21 % of the particles drawn while localized were random): no per-beam work, one division per
//    scan. A scan that fits better than the origin counts as the origin.
// INJECTION (line 13, gated). p_8.3 = max(0, 1 - e^band w_fast / w_slow), capped. With a scale it applies only
// when the deficit d_t = log w_slow - f_t of the scan calls for it:
//  - fine, d_t <= band: never (w_fast may still lag a scan that already fits);
//  - lost, d_t >= lost_deficit (most beams miss, e.g. kidnapped): at once;
//  - in between: once `patience` corrections in a row have been in doubt (p_8.3 > 0, the scan not fine). A mild
//    deficit is what a filter shows both on a look-alike and right after it found the robot (the found pose sits
//    0.2-0.4 m off); random poses help nothing in the second case, and with KLD counting their bins each such
//    resampling draws N_max;
//  - never while holding after a find, which holds as long as each scan fits better than the one before (a false
//    find plateaus and is let go). A find: the random particles of the last injection took over half the weight,
//    or the weighted mean left the resampled part's mean by more than find_jump (a pose found earlier took over),
//    or the scan beats w_fast by find_gain with an ESS below find_ess.
// ROUGHENING. While in doubt (p_8.3 > 0, the scan not fine) the resampled particles are spread by N(0, sigma_xy^2)
// and N(0, sigma_theta^2), about half the likelihood field's sigma_hit: after a find the set is copies of one pose
// a few decimetres off, and the motion noise alone closes a sideways offset at ~2-5 cm/s for a car-like robot
// (seconds of a poor fit: seconds of injection, or of waiting); spread by the sensor's resolution the set finds the
// peak in 1-3 scans. While the fit is fine (all of tracking) resampling is the book's.
// Without a scale (factors < 0) the statistic is the book's log w_avg, its averages start at the first correction,
// line 13 applies as printed (no band, no gate) and nothing is roughened.
// Alternatives weighed (each run on the office demo, seeds 1-20, both robots): the share of beams the map explains
// within a tolerance at the estimate (blind to the corridor look-alike: 12.5 s to localize); a coarse per-beam fit
// at the estimate (a look-alike and a 0.3 m offset fit alike); the log-likelihood normalized by its expectation
// (the beam model's expectation depends on z* per beam: per-particle work); a fast average that follows the fit at
// once, or long patience without roughening (the found cloud fits as badly as a look-alike for 1-4 s: either
// injection while localized or 4-14 s to escape a look-alike).
//
// KLD-sampling (table 8.4) draws the new set one sample at a time, i.i.d. from the weighted set or, with the
// injection probability, from the recovery source (as table 8.3 adds them), and counts the bins of every sample
// drawn, random ones included (as AMCL does), until n >= n_chi(k) and n >= n_min (KldStoppingRule). That count M is
// table 8.4's; the resampled part (M minus the random ones) is then drawn again by the low-variance sampler (table
// 4.4), so its variance stays low: the bins decide how many, the comb which. Bounded by N_max draws, each a binary
// search of the weights' cumulative sum. With more than ~10 % random draws most open a new bin, n_chi(k) ~ 10 k grows
// faster than the draws and the count goes to N_max: a lost filter searches with the whole capacity.
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
  // With a MeasurementScale (see the header): the per-beam recovery statistic and its gate, in nats per beam.
  float recovery_dead_band = 0.15f;    // line 13 is positive once w_fast < w_slow e^-band
  float recovery_lost_deficit = 1.0f;  // a scan this far below w_slow is lost: inject at once
  std::uint32_t recovery_patience = 10u;  // corrections a milder deficit must last before it injects
  float recovery_find_gain = 0.1f;     // a find: the scan beats w_fast by this with an ESS below find_ess ...
  float recovery_find_ess = 10.0f;     // ... (or the last injection's particles took half the weight)
  float recovery_find_jump = 1.0f;     // m: ... (or the weighted mean left the resampled part's mean by this)
  float roughening_sigma_xy = 0.1f;    // m: resampled particles are spread by this while the fit is in doubt
  float roughening_sigma_theta = 0.02f;  // rad
  // log p(x | m) of table 5.7 for a particle predicted into occupied or unknown space: log 0.01 where the book has
  // p(x | m) = 0. Kept, because a map is never exact (a wall drawn a cell too thick, a door the map shows closed,
  // unknown cells the robot may stand in): with 0 such a particle dies however well the scan fits it, and a robot
  // whose true pose the map calls occupied loses every particle near it (each weight 0: a degenerate correction
  // forcing recovery every step). At 0.01 the scan still decides: 4.6 nats are less than one poor beam costs.
  float occupied_log_weight = -4.6f;
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
  std::uint32_t drawn_particles = 0;      // samples of the new sets at the resamplings, injected ones included
  std::uint32_t injected_particles = 0;
  std::uint32_t failed_injections = 0;    // the injector could not draw a pose (e.g. no free cell found in its tries)
  std::uint32_t map_penalized = 0;        // particles predicted into occupied or unknown space
};

// What the recovery statistic needs from a measurement model: how many factors p(z_k | x) its likelihood multiplies
// (the beams that entered the product: max readings skipped) and what one factor's log density is at a correct pose
// (the origin of the fit: LikelihoodField::log_term_max(), its mode; BeamRangeFinderModel::log_typical(), a hit's
// mean). factors < 0: unknown, the book's statistic; 0: nothing was measured (every beam a max reading), the
// averages are left as they are.
struct MeasurementScale {
  std::int32_t factors = -1;
  float log_peak = 0.0f;
};

struct CorrectionReport {
  float log_mean_likelihood;  // log of the average likelihood over particles (w_avg of table 8.3, in log space)
  float ess;
  bool degenerate;
  float fit;                  // the recovery statistic of this correction: f_t, or log w_avg without a scale
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
      v.mode[i] = kUnknownMode;
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
      v.set_new(i, p);
      v.log_w[i] = lw;
    }
    reset_averages();
    random_begin_ = 0;  // every particle is a random one
    random_end_ = v.count;
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

  // Prediction when the control depends on the particle's mode (the steering of its handle position): particle i is
  // sampled with u[mode_i] and p[mode_i] for a mode below `modes`, with u[modes] and p[modes] for kUnknownMode (or
  // any other). u and p hold modes + 1 entries. Controls the model refuses leave their particles as they are; the
  // status is the worst of the used controls'. Then log p(x | m) as predict_in_map().
  template <typename Model, typename IsFree>
  MotionStatus predict_in_map_by_mode(const typename Model::Control* u, const typename Model::Params* p,
                                      std::uint32_t modes, const IsFree& is_free) {
    constexpr std::uint32_t kMaxModes = 32u;
    if (modes >= kMaxModes) return MotionStatus::rejected_range;
    bool ok[kMaxModes + 1u];
    MotionStatus worst = MotionStatus::ok;
    bool any = false;
    for (std::uint32_t m = 0; m <= modes; ++m) {
      const MotionStatus s = Model::check(u[m], p[m]);
      ok[m] = usable(s);
      if (ok[m]) {
        any = true;
        if (s != MotionStatus::ok) worst = s;
      } else if (m == modes) {
        worst = s;
      }
    }
    if (!any) {
      ++counters_.rejected_controls;
      return worst;
    }
    ParticleSetView v = set_.view();
    for (std::uint32_t i = 0; i < v.count; ++i) {
      const std::uint32_t m = v.mode[i] < modes ? v.mode[i] : modes;
      if (ok[m]) v.set_pose(i, Model::sample(v.pose(i), u[m], p[m], rng_));
    }
    ++counters_.predictions;
    penalize_occupied(is_free);
    return usable(worst) ? worst : MotionStatus::ok;
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

  // Correction: w_i *= p(z | x_i, m), normalized in log space; w_slow and w_fast follow the recovery statistic, the
  // per-beam fit when `scale` states the measurement's size, else the book's average likelihood (see the header).
  template <typename LogLikelihood>
  CorrectionReport correct(const LogLikelihood& log_likelihood, const MeasurementScale& scale = {}) {
    ParticleSetView v = set_.view();
    // log w_avg = log( sum_i w_i p(z|x_i) ) for normalized prior weights: the predictive likelihood of z.
    for (std::uint32_t i = 0; i < v.count; ++i) v.log_w[i] += log_likelihood(v.pose(i));
    return finish_correction(v, scale);
  }

  // The same correction with the log-likelihoods of the whole set computed at once by
  // `batch(ConstParticleSetView, float* out)` (e.g. likelihood_field_range_finder_model_batch, which vectorizes
  // across particles): bit-identical to correct() when batch gives the per-particle values. `out` is the scratch
  // buffer's weight array, idle between resamplings.
  template <typename BatchLogLikelihood>
  CorrectionReport correct_batch(const BatchLogLikelihood& batch, const MeasurementScale& scale = {}) {
    ParticleSetView v = set_.view();
    float* ll = set_.scratch().log_w;
    batch(ConstParticleSetView(v), ll);
    for (std::uint32_t i = 0; i < v.count; ++i) v.log_w[i] += ll[i];
    return finish_correction(v, scale);
  }

  // Resampling when ESS < fraction * N (always when `force`, or when the recovery injects): M particles, a KLD count
  // (table 8.4) or the current count, of which the random share is drawn by `draw` and the rest by the low-variance
  // sampler. Returns true if the set was resampled.
  template <typename Injector>
  bool resample(const Injector& draw, bool force = false) {
    ParticleSetView v = set_.view();
    if (v.count == 0u) return false;
    // The ESS only when it decides (not when forced), and the last correction's when the weights have not changed
    // since (the same bits, one exp pass fewer).
    const float p_inject = injection_probability();
    if (!force && !force_recovery_ && p_inject <= 0.0f &&
        (ess_valid_ ? last_ess_ : effective_sample_size(v.log_w, v.count)) >=
            config_.resample_ess_fraction * static_cast<float>(v.count))
      return false;

    // Random poses go to the scratch set's tail first (the front is the low-variance sampler's).
    ParticleSetView out = set_.scratch();
    std::uint32_t m = v.count;
    std::uint32_t n_inject = 0;
    if (config_.kld) {
      m = kld_sample(ConstParticleSetView(v), out, draw, p_inject, n_inject);
    } else {
      // Stochastic rounding keeps the expected number of injected particles at p * m with a deterministic stream.
      std::uint32_t want = static_cast<std::uint32_t>(p_inject * static_cast<float>(m) + rng_.uniform());
      if (want > m) want = m;
      for (std::uint32_t k = 0; k < want; ++k) {
        Pose2 p;
        if (draw(rng_, p))
          out.set_new(NMax - 1u - n_inject++, p);
        else
          ++counters_.failed_injections;  // the slot is resampled instead
      }
    }
    const std::uint32_t n_resampled = m - n_inject;
    low_variance_sampler(ConstParticleSetView(v), out, n_resampled, rng_);
    if (doubting()) roughen(out, n_resampled);
    // The random poses, [NMax - n_inject, NMax), join the resampled ones at [n_resampled, m): only the part that is
    // not there already moves (their order does not matter).
    const std::uint32_t tail = NMax - n_inject;
    std::uint32_t dst = n_resampled;
    for (std::uint32_t src = m > tail ? m : tail; src < NMax; ++src, ++dst) out.copy(dst, src);
    const float lw = -fmath::log(static_cast<float>(m));
    for (std::uint32_t k = 0; k < m; ++k) out.log_w[k] = lw;
    set_.swap_with_scratch(m);
    ess_valid_ = false;
    ++counters_.resamplings;
    counters_.drawn_particles += m;
    counters_.injected_particles += n_inject;
    random_begin_ = n_resampled;  // the next correction tells whether they found something
    random_end_ = m;
    // As table 8.3: the averages are NOT reset after an injection. Restarting them at the (low) likelihood of a
    // kidnapped robot would make w_fast = w_slow there and stop the injection after one burst of a few percent.
    force_recovery_ = false;
    return true;
  }

  // Table 8.3, line 13: max(0, 1 - e^band w_fast / w_slow), capped, gated by the deficit with a scale (header); the
  // cap after a degenerate correction.
  float injection_probability() const {
    if (!config_.recovery) return 0.0f;
    if (force_recovery_) return config_.max_injection_fraction;
    if (!averages_valid_) return 0.0f;
    if (!per_beam_) return line13_probability();
    if (holding_ || !doubting()) return 0.0f;
    if (last_deficit_ < config_.recovery_lost_deficit && mild_run_ < config_.recovery_patience) return 0.0f;
    return line13_probability();
  }

  PoseEstimate estimate() const { return weighted_mean(set_.view()); }
  // Its table is the filter's (static storage with the set), sized for NMax: the same clusters as 2048 slots.
  ClusterEstimate cluster_estimate(float cell = 1.0f, bool by_mode = false) const {
    return strongest_cluster(set_.view(), cluster_table_, cell, 0.9f, by_mode);
  }

  ConstParticleSetView particles() const { return set_.view(); }
  ParticleSetView particles_mutable() {
    ess_valid_ = false;  // the caller may change the weights
    return set_.view();
  }
  // The particles' modes, for a measurement model that estimates them (the weights stay as they are).
  std::uint8_t* particle_modes() { return set_.view().mode; }
  const MclCounters& counters() const { return counters_; }
  const MclConfig& config() const { return config_; }
  Rng& rng() { return rng_; }
  // The averages of the recovery statistic (log w_slow, log w_fast), the last statistic and its deficit
  // log w_slow - f_t; meaningful once a correction was made.
  float log_w_slow() const { return log_w_slow_; }
  float log_w_fast() const { return log_w_fast_; }
  float last_fit() const { return last_fit_; }
  float last_deficit() const { return last_deficit_; }
  bool last_found() const { return last_found_; }

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
      ess_valid_ = false;
      counters_.map_penalized += penalized;
      normalize_log_weights(v.log_w, v.count);
    }
  }

  // Roughening (header): while in doubt the resampled part is spread by about half the likelihood field's sigma_hit,
  // so a cloud a few decimetres off (one random pose took all the weight) finds the peak within a few scans.
  void roughen(ParticleSetView out, std::uint32_t n) {
    if (!(config_.roughening_sigma_xy > 0.0f) && !(config_.roughening_sigma_theta > 0.0f)) return;
    for (std::uint32_t k = 0; k < n; ++k) {
      out.x[k] += sample_normal(rng_, config_.roughening_sigma_xy);
      out.y[k] += sample_normal(rng_, config_.roughening_sigma_xy);
      out.theta[k] = fmath::normalize_angle(out.theta[k] + sample_normal(rng_, config_.roughening_sigma_theta));
    }
  }

  // Table 8.4 with table 8.3's injection: samples drawn one at a time, each from `draw` with probability p_inject
  // (into out's tail) or else i.i.d. from the weighted set, the bins of all counted, until the stopping rule holds.
  // Returns the count M; n_inject of them are random. The weighted draws only count bins: the low-variance sampler
  // draws the resampled part afterwards. The cumulative weights live in out.log_w, idle until then.
  template <typename Injector>
  std::uint32_t kld_sample(ConstParticleSetView v, ParticleSetView out, const Injector& draw, float p_inject,
                           std::uint32_t& n_inject) {
    float* cdf = out.log_w;
    float c = 0.0f;
    for (std::uint32_t i = 0; i < v.count; ++i) {
      c += imath::exp(v.log_w[i]);
      cdf[i] = c;
    }
    kld_.start(config_.kld_config, NMax);
    n_inject = 0;
    std::uint32_t n = 0;
    for (; !kld_.done(n); ++n) {  // bounded: done(NMax)
      Pose2 p;
      if (p_inject > 0.0f && rng_.uniform() < p_inject) {
        if (draw(rng_, p)) {
          out.set_new(NMax - 1u - n_inject++, p);
          kld_.add(p.x, p.y, p.theta, kUnknownMode);
          continue;
        }
        ++counters_.failed_injections;  // a weighted draw instead
      }
      if (kld_.saturated()) continue;  // the count is N_max now: bins no longer matter
      // The first i with cdf[i] > u, branch-free (the steps do not depend on the data): ceil(log2 N) steps.
      const float u = rng_.uniform() * c;
      std::uint32_t lo = 0, len = v.count;
      while (len > 1u) {
        const std::uint32_t half = len / 2u;
        lo += cdf[lo + half - 1u] > u ? 0u : half;
        len -= half;
      }
      if (!(cdf[lo] > u) && lo + 1u < v.count) ++lo;  // rounding: the last particle absorbs what is left
      kld_.add(v.x[lo], v.y[lo], v.theta[lo], v.mode[lo]);
    }
    return n;
  }

  CorrectionReport finish_correction(ParticleSetView v, const MeasurementScale& scale) {
    const LogNormalization n = normalize_log_weights(v.log_w, v.count);
    ++counters_.corrections;
    counters_.nonfinite_weights += n.nonfinite;
    CorrectionReport r{n.log_sum, effective_sample_size(v.log_w, v.count), n.degenerate, n.log_sum};
    last_ess_ = r.ess;
    ess_valid_ = true;
    if (n.degenerate) {
      ++counters_.degenerate_corrections;
      force_recovery_ = true;  // nothing explains z: the next resampling injects as many particles as allowed
      return r;
    }
    if (scale.factors == 0) return r;  // nothing measured: no evidence either way
    if (scale.factors < 0) {
      per_beam_ = false;
      update_averages(n.log_sum, false);
      return r;
    }
    float f = n.log_sum / static_cast<float>(scale.factors) - scale.log_peak;
    if (f > 0.0f) f = 0.0f;  // as well as a correct pose: no better (the origin of the averages)
    r.fit = f;
    per_beam_ = true;
    const float fast_before = log_w_fast_;
    const float previous_fit = last_fit_;
    const bool had_averages = averages_valid_;
    update_averages(f, true);
    // The gate of line 13 (header). A find: the random particles of the last injection took most of the weight, or
    // the scan fits much better than the recent ones (a hypothesis found a scan or two ago took over).
    float w_random = 0.0f;
    for (std::uint32_t i = random_begin_; i < random_end_ && i < v.count; ++i) w_random += imath::exp(v.log_w[i]);
    bool jumped = false;
    if (random_end_ > random_begin_ && random_begin_ > 0u && random_end_ <= v.count) {
      // The belief before this scan (the resampled part, equal weights) against the posterior: a jump of the mean.
      float bx = 0.0f, by = 0.0f, px = 0.0f, py = 0.0f;
      for (std::uint32_t i = 0; i < random_begin_; ++i) {
        bx += v.x[i];
        by += v.y[i];
      }
      for (std::uint32_t i = 0; i < v.count; ++i) {
        const float w = imath::exp(v.log_w[i]);
        px += w * v.x[i];
        py += w * v.y[i];
      }
      const float inv = 1.0f / static_cast<float>(random_begin_);
      const float dx = px - bx * inv, dy = py - by * inv;
      jumped = dx * dx + dy * dy > config_.recovery_find_jump * config_.recovery_find_jump;
    }
    random_begin_ = random_end_ = 0;
    last_found_ = w_random > 0.5f || jumped || (had_averages && r.ess < config_.recovery_find_ess &&
                                                  f > fast_before + config_.recovery_find_gain);
    // A find holds the injection, and so does every scan after it that fits better than the one before.
    holding_ = last_found_ || (holding_ && f > previous_fit);
    last_deficit_ = log_w_slow_ - f;
    // The run of doubting corrections (line 13 positive, the scan not fine) restarts at a fine scan and while holding.
    if (holding_ || !doubting())
      mild_run_ = 0;
    else if (mild_run_ < config_.recovery_patience)
      ++mild_run_;
    return r;
  }

  // With a scale: line 13 is positive and the last scan fits worse than w_slow by more than the band.
  bool doubting() const {
    return per_beam_ && last_deficit_ > config_.recovery_dead_band && line13_probability() > 0.0f;
  }

  // max(0, 1 - e^band w_fast / w_slow), capped (the band with a scale only: without, table 8.3 as printed).
  float line13_probability() const {
    const float band = per_beam_ ? config_.recovery_dead_band : 0.0f;
    const float ratio = fmath::exp(log_w_fast_ - log_w_slow_ + band);
    const float p = 1.0f - ratio;
    if (!(p > 0.0f)) return 0.0f;
    return p < config_.max_injection_fraction ? p : config_.max_injection_fraction;
  }

  void reset_averages() {
    ess_valid_ = false;
    averages_valid_ = false;
    force_recovery_ = false;
    mild_run_ = 0;
    holding_ = false;
    last_found_ = false;
    last_deficit_ = 0.0f;
    last_fit_ = 0.0f;
    random_begin_ = random_end_ = 0;
  }

  // w <- w + alpha (w_avg - w) in log space: log w + log(1 + alpha (exp(log w_avg - log w) - 1)).
  static float smooth_log(float log_w, float log_avg, float alpha) {
    const float d = log_avg - log_w;
    if (d > 20.0f) return log_w + d + fmath::log(alpha + (1.0f - alpha) * fmath::exp(-d));
    return log_w + fmath::log(1.0f + alpha * (fmath::exp(d) - 1.0f));
  }

  // Lines 10-11. `anchored`: the statistic is a fit <= 0 whose averages start at the perfect fit 0 (header);
  // otherwise they start at the first value.
  void update_averages(float stat, bool anchored) {
    last_fit_ = stat;
    if (!averages_valid_) {
      averages_valid_ = true;
      log_w_slow_ = anchored ? 0.0f : stat;
      log_w_fast_ = anchored ? 0.0f : stat;
      if (!anchored) return;
    }
    log_w_slow_ = smooth_log(log_w_slow_, stat, config_.alpha_slow);
    log_w_fast_ = smooth_log(log_w_fast_, stat, config_.alpha_fast);
  }

  MclConfig config_;
  Rng rng_;
  ParticleSet<NMax> set_;
  mutable ClusterTable<cluster_slots(NMax)> cluster_table_;  // scratch of cluster_estimate()
  KldStoppingRule<4096> kld_;
  MclCounters counters_;
  float log_w_slow_ = 0.0f;
  float log_w_fast_ = 0.0f;
  float last_fit_ = 0.0f;
  float last_deficit_ = 0.0f;
  std::uint32_t mild_run_ = 0;
  std::uint32_t random_begin_ = 0, random_end_ = 0;  // the particles of the last injection
  bool last_found_ = false;
  bool holding_ = false;
  bool averages_valid_ = false;
  bool per_beam_ = false;
  bool force_recovery_ = false;
  float last_ess_ = 0.0f;  // the ESS of the weights as the last correction left them, while ess_valid_
  bool ess_valid_ = false;
};

}  // namespace est

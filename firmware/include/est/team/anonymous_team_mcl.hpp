#pragma once
// Monte Carlo localization of N differential-drive robots whose sensors see each other anonymously (the three-robot
// exercise): one particle set per robot (Thrun table 8.2, global localization from a uniform cloud over a rectangle,
// prediction by sample_motion_model_diff_drive, correction by landmark_model_known_correspondence, table 6.4), and a
// discrete Bayes filter (est/assoc/permutation_belief.hpp) over the N! assignments of the markers' tags to robots.
// Hypothesis h says that tag t is carried by robot robot_of(h, t).
//
// LIKELIHOOD OF A SIGHTING under an assignment. Robot i sees tag t at z = (r, phi), phi in i's frame. Under h the
// tag is robot j = robot_of(h, t), and
//   p(z | i, j) = (1 - eps) N(z; h(mu_i, mu_j), S) + eps / (reach 2 pi),
//   S = H_i Sigma_i H_i^T + H_j Sigma_j,xy H_j^T + diag(sigma_r^2, sigma_phi^2),
// with (mu, Sigma) the robots' current particle estimates and H_i, H_j the Jacobians of range and bearing
// (est/filter/landmark_measurement.hpp): each particle cloud summarized by a Gaussian and pushed through the
// linearized measurement, the sensor noise added. Why this and not a particle-by-particle marginal: the marginal costs
// Particles^2 per sighting and hypothesis; the Gaussian costs one 2x2 solve, and it has the property that matters:
// a lost robot (its cloud spread over the field, Sigma the whole cloud's covariance, not a cluster's) gives a broad
// S, hence nearly the same likelihood under every hypothesis, so lost robots barely move the belief. The clutter term
// eps (a false detection, uniform over the sensor's reach) bounds what one sighting can do, so a cloud that is
// confidently wrong or a reflection cannot drive a hypothesis to the floor at once. A robot never sees its own
// marker: j = i gets the clutter term alone, which is what lets the tag a robot never sees name it. An observer whose
// heading spread exceeds `bearing_heading_limit_rad` (a lost robot: its mean heading is arbitrary, and a Gaussian
// about it would favour one hypothesis by chance) has its sightings scored on the range alone.
// Every sighting of one step goes into one belief update: log p(z_1..z_K | h) = sum_k log p(z_k | i_k, robot_of(h,
// t_k)), the sightings independent given the robots' states; rows of tags not seen are zero (no evidence).
//
// CORRECTION BY A SIGHTING (Fox, Burgard, Kruppa and Thrun 2000). After the belief update, if the most probable
// assignment holds at least `ambiguity_threshold` of the probability (else the step is counted ambiguous and no
// robot is corrected), each sighting pairs observer i with j = robot_of(best, t). Of the two, the robot with the
// larger position spread is corrected, with the other as the reference, and only when the reference is localized:
// two lost robots do not make each other confident, and one sighting is used once (correcting both from the same z
// would count it twice). The target's particles x get w *= p(z | x, mu_ref), the same mixture as above with S built
// from the reference's covariance alone (the target is the particle).
//
// LOCALIZED: the strongest cluster (est/filter/particle_estimate.hpp) holds at least `cluster_dominance` of the
// weight, and its position spread sqrt(var_x + var_y) and heading spread are below the stated limits. The estimate
// is that cluster's mean and covariance when localized, else the whole cloud's (broad: what the sightings need).
// While a robot sees two landmarks, `reset_fraction` of its particles (`tracking_reset_fraction` once localized) are
// replaced before each landmark correction by poses from the two-landmark sampler (sensor resetting, Thrun 8.3.5;
// Lenser and Veloso 2000): a uniform cloud of a few thousand particles over a field of hundreds of square metres
// rarely holds a pose within the landmark model's reach, and a cloud that locked on a few decimetres off (the first
// resampling keeps few distinct poses) moves back only at the pace of the motion noise without fresh poses.
//
// Bounded: every loop runs over N robots, Particles particles, the map's landmarks, MaxSightings sightings or N!
// hypotheses. Non-finite or malformed inputs are refused and counted; the estimate is never NaN.
#include <cstdint>

#include "est/assoc/permutation_belief.hpp"
#include "est/eigen.hpp"
#include "est/filter/landmark_measurement.hpp"
#include "est/filter/log_weights.hpp"
#include "est/filter/low_variance_sampler.hpp"
#include "est/filter/particle_estimate.hpp"
#include "est/filter/particle_set.hpp"
#include "est/filter/two_landmark_sampler.hpp"
#include "est/map/landmark_map.hpp"
#include "est/math/fmath.hpp"
#include "est/math/normal.hpp"
#include "est/motion/diff_drive_model.hpp"
#include "est/random/xoshiro128.hpp"
#include "est/sensor/landmark_model.hpp"
#include "est/team/team_message.hpp"

namespace est::team {

struct AnonymousTeamMclConfig {
  DiffDriveParams motion{};                 // the filter's motion model (its noise covers the wheels' slip)
  LandmarkNoise landmark_noise{0.1f, 0.05f, 0.1f};
  float signature_gate = 0.45f;             // a landmark's signature must be this close to the map's
  float sighting_sigma_range = 0.1f;        // m, the robot sensor's range noise
  float sighting_sigma_bearing = 0.05f;     // rad
  float sighting_reach_m = 6.0f;            // the sensor's reach: the clutter density is 1 / (reach 2 pi)
  float sighting_clutter = 0.01f;           // eps: the share of sightings that are false detections
  float min_x = 0.0f, min_y = 0.0f;         // m, the rectangle of global localization
  float max_x = 20.0f, max_y = 15.0f;
  float resample_ess_fraction = 0.5f;       // resample when ESS < fraction * Particles
  float reset_fraction = 0.1f;              // sensor resetting while not localized
  float tracking_reset_fraction = 0.02f;    // ... and while localized (a cloud locked a little off recovers)
  float cluster_cell = 1.0f;                // m, the strongest cluster's grid
  float cluster_dominance = 0.9f;
  float localized_spread_m = 0.5f;          // sqrt(var_x + var_y) of the strongest cluster
  float localized_heading_rad = 0.3f;       // its heading standard deviation
  float ambiguity_threshold = 0.9f;         // a step whose best assignment holds less is ambiguous
  float bearing_heading_limit_rad = 0.8f;   // an observer's heading spread beyond this: its bearings not scored
};

// One anonymous sighting: observer `observer` sees the marker `tag` (0..N-1; which robot carries it is unknown) at
// z.range_m, z.bearing_rad in its own frame. z.target is TargetKind::robot, z.has_bearing true, z.id kAnonymous.
struct RobotSighting {
  std::int32_t observer = 0;
  std::int32_t tag = 0;
  TeamMeasurement z{TargetKind::robot, true, 0.0f, 0.0f, kAnonymous};
};

struct TeamRobotEstimate {
  Pose2 mean;
  Eigen::Matrix3f covariance = Eigen::Matrix3f::Identity();
  bool localized = false;
  float cluster_weight = 0.0f;  // the strongest cluster's share of the weight
};

struct AnonymousTeamMclCounters {
  std::uint32_t predictions = 0;
  std::uint32_t rejected_controls = 0;       // ticks the motion model refused, or an unknown robot
  std::uint32_t landmark_sightings = 0;      // used in a correction
  std::uint32_t rejected_landmarks = 0;      // non-finite, negative range, or over the per-call capacity
  std::uint32_t unknown_landmarks = 0;       // no signature of the map within the gate
  std::uint32_t sighting_steps = 0;          // belief updates
  std::uint32_t sightings = 0;               // robot sightings used
  std::uint32_t rejected_sightings = 0;      // non-finite, malformed, not anonymous, or over the capacity
  std::uint32_t duplicate_sightings = 0;     // the same (observer, tag) twice in one step
  std::uint32_t ambiguous_steps = 0;         // the best assignment below ambiguity_threshold
  std::uint32_t corrections_applied = 0;     // sightings that weighted a robot's particles
  std::uint32_t corrections_unlocalized = 0; // refused: the reference robot was not localized (Fox et al.'s rule)
  std::uint32_t self_sightings = 0;          // the best assignment says the observer saw its own marker: not used
  std::uint32_t injected_particles = 0;      // sensor resetting
  std::uint32_t resamplings = 0;
  std::uint32_t degenerate_corrections = 0;  // every weight zero or NaN: weights reset to uniform
};

template <int N, std::uint32_t Particles, std::int32_t MaxSightings = 16, std::int32_t MaxLandmarks = 16,
          std::uint32_t ClusterSlots = 1024>
class AnonymousTeamMcl {
  static_assert(N >= 2 && N <= 5, "2 to 5 robots (N! hypotheses)");
  static_assert(Particles >= 2u, "at least two particles per robot");
  static_assert(MaxSightings >= 1 && MaxLandmarks >= 2, "capacities");

 public:
  using Belief = PermutationBelief<N>;
  static constexpr int kRobots = N;
  static constexpr int kHypotheses = Belief::kHypotheses;

  AnonymousTeamMcl(const AnonymousTeamMclConfig& config, const LandmarkMap& map, std::uint64_t seed)
      : config_(config), map_(map) {
    for (int r = 0; r < N; ++r) rng_[r] = Rng::stream(seed, static_cast<std::uint32_t>(r));
    initialize_global();
  }

  // Global localization: every robot's particles uniform over the rectangle, the belief uniform.
  void initialize_global() {
    const float lw = -fmath::log(static_cast<float>(Particles));
    for (int r = 0; r < N; ++r) {
      set_[r].set_count(Particles);
      ParticleSetView v = set_[r].view();
      for (std::uint32_t k = 0; k < Particles; ++k) {
        v.x[k] = rng_[r].uniform(config_.min_x, config_.max_x);
        v.y[k] = rng_[r].uniform(config_.min_y, config_.max_y);
        v.theta[k] = rng_[r].uniform(-kPi, kPi);
        v.log_w[k] = lw;
      }
      refresh_estimate(r);
    }
    belief_.reset();
  }

  // Table 8.2 line 4 for one robot: x ~ p(x | u, x_prev) by the model's sampler. Standing still diffuses nothing.
  bool predict(int robot, const DiffDriveControl& u) {
    if (robot < 0 || robot >= N || !usable(DiffDriveMotionModel::check(u, config_.motion))) {
      ++counters_.rejected_controls;
      return false;
    }
    if (u.left_ticks == 0 && u.right_ticks == 0) return true;
    ParticleSetView v = set_[robot].view();
    for (std::uint32_t k = 0; k < v.count; ++k)
      v.set_pose(k, DiffDriveMotionModel::sample(v.pose(k), u, config_.motion, rng_[robot]));
    ++counters_.predictions;
    refresh_estimate(robot);
    return true;
  }

  // Table 8.2 lines 5-6 with table 6.4 for every landmark of one step of one robot; correspondences from the
  // signatures. Returns the sightings used.
  std::int32_t correct_landmarks(int robot, const LandmarkMeasurement* f, std::int32_t count) {
    if (robot < 0 || robot >= N || count < 0) {
      counters_.rejected_landmarks += count > 0 ? static_cast<std::uint32_t>(count) : 0u;
      return 0;
    }
    LandmarkMeasurement used[static_cast<std::uint32_t>(MaxLandmarks)];
    std::int32_t c[static_cast<std::uint32_t>(MaxLandmarks)];
    std::int32_t n = 0;
    for (std::int32_t k = 0; k < count; ++k) {
      const std::int32_t j = correspondence(f[k]);
      if (j == kRejected || n >= MaxLandmarks) {
        ++counters_.rejected_landmarks;
      } else if (j < 0) {
        ++counters_.unknown_landmarks;
      } else {
        used[n] = f[k];
        c[n] = j;
        ++n;
      }
    }
    if (n == 0) return 0;
    const bool localized = estimate_[robot].localized;
    if (n >= 2) sensor_reset(robot, used, c, n, localized ? config_.tracking_reset_fraction : config_.reset_fraction);
    ParticleSetView v = set_[robot].view();
    for (std::uint32_t i = 0; i < v.count; ++i) {
      const Pose2 x = v.pose(i);
      float l = 0.0f;
      for (std::int32_t k = 0; k < n; ++k)
        l += landmark_model_known_correspondence(used[k], c[k], x, map_, config_.landmark_noise);
      v.log_w[i] += l;
    }
    counters_.landmark_sightings += static_cast<std::uint32_t>(n);
    finish_correction(robot);
    return n;
  }

  // One step's robot sightings of the whole team: one belief update, then the corrections (header). Returns the
  // sightings used.
  std::int32_t correct_sightings(const RobotSighting* s, std::int32_t count) {
    if (count < 0) return 0;
    RobotSighting used[static_cast<std::uint32_t>(MaxSightings)];
    std::int32_t n = 0;
    for (std::int32_t k = 0; k < count; ++k) {
      if (!well_formed(s[k]) || n >= MaxSightings) {
        ++counters_.rejected_sightings;
        continue;
      }
      bool dup = false;
      for (std::int32_t m = 0; m < n; ++m) dup = dup || (used[m].observer == s[k].observer && used[m].tag == s[k].tag);
      if (dup) {
        ++counters_.duplicate_sightings;
        continue;
      }
      used[n++] = s[k];
    }
    if (n == 0) return 0;
    // The estimates of this step, before any sighting corrects them.
    TeamRobotEstimate e[static_cast<unsigned>(N)];
    for (int r = 0; r < N; ++r) e[r] = estimate_[r];
    typename Belief::LogLikelihoods ll;
    for (int t = 0; t < N; ++t)
      for (int j = 0; j < N; ++j) ll[t][j] = 0.0f;
    for (std::int32_t k = 0; k < n; ++k) {
      const RobotSighting& z = used[k];
      for (int j = 0; j < N; ++j)
        ll[z.tag][j] += j == z.observer ? log_clutter() : log_sighting(z.z, e[z.observer], e[j]);
    }
    if (!belief_.update(ll)) {  // cannot happen with finite estimates; counted as refused if it does
      counters_.rejected_sightings += static_cast<std::uint32_t>(n);
      return 0;
    }
    ++counters_.sighting_steps;
    counters_.sightings += static_cast<std::uint32_t>(n);
    const int best = belief_.most_probable();
    if (belief_.probability(best) < config_.ambiguity_threshold) {
      ++counters_.ambiguous_steps;
      return n;
    }
    bool touched[static_cast<unsigned>(N)] = {};
    for (std::int32_t k = 0; k < n; ++k) {
      const int i = used[k].observer;
      const int j = belief_.robot_of(best, used[k].tag);
      if (j == i) {
        ++counters_.self_sightings;
        continue;
      }
      // The less certain robot of the pair is corrected, the other is the reference.
      const bool seen_is_target = spread2(e[j]) >= spread2(e[i]);
      const int target = seen_is_target ? j : i;
      const int ref = seen_is_target ? i : j;
      if (!e[ref].localized) {
        ++counters_.corrections_unlocalized;
        continue;
      }
      correct_by_sighting(target, used[k].z, e[ref], seen_is_target);
      touched[target] = true;
      ++counters_.corrections_applied;
    }
    for (int r = 0; r < N; ++r)
      if (touched[r]) finish_correction(r);
    return n;
  }

  const TeamRobotEstimate& estimate(int robot) const { return estimate_[robot]; }
  ConstParticleSetView particles(int robot) const { return set_[robot].view(); }
  const Belief& belief() const { return belief_; }
  float probability(int h) const { return belief_.probability(h); }
  // The hypothesis that says tag t is robot robot_of_tag[t], or -1 when robot_of_tag is not a permutation.
  int hypothesis_of(const std::int32_t (&robot_of_tag)[static_cast<unsigned>(N)]) const {
    for (int h = 0; h < kHypotheses; ++h) {
      bool same = true;
      for (int t = 0; t < N; ++t) same = same && belief_.robot_of(h, t) == robot_of_tag[t];
      if (same) return h;
    }
    return -1;
  }
  float probability_of(const std::int32_t (&robot_of_tag)[static_cast<unsigned>(N)]) const {
    const int h = hypothesis_of(robot_of_tag);
    return h < 0 ? 0.0f : belief_.probability(h);
  }
  float identity_probability() const { return belief_.probability(0); }  // h = 0 is the identity
  const AnonymousTeamMclCounters& counters() const { return counters_; }
  const AnonymousTeamMclConfig& config() const { return config_; }

 private:
  static constexpr std::int32_t kRejected = -2;  // correspondence(): a malformed measurement

  // The map's landmark with the nearest signature within the gate, -1 when none, kRejected when malformed.
  std::int32_t correspondence(const LandmarkMeasurement& f) const {
    if (!fmath::isfinite(f.range) || !fmath::isfinite(f.bearing) || !fmath::isfinite(f.signature) ||
        !(f.range >= 0.0f))
      return kRejected;
    std::int32_t best = -1;
    float best_d = config_.signature_gate;
    for (std::int32_t j = 0; j < map_.size(); ++j) {
      const float d = fmath::abs(map_[j].signature - f.signature);
      if (d <= best_d) {
        best_d = d;
        best = j;
      }
    }
    return best;
  }

  static bool well_formed(const RobotSighting& s) {
    const TeamMeasurement& z = s.z;
    if (s.observer < 0 || s.observer >= N || s.tag < 0 || s.tag >= N) return false;
    if (z.target != TargetKind::robot || !z.has_bearing || z.id != kAnonymous) return false;
    if (!fmath::isfinite(z.range_m) || !fmath::isfinite(z.bearing_rad) || !(z.range_m >= kMinMeasurementRange))
      return false;
    return z.bearing_rad <= kPi && z.bearing_rad >= -kPi;
  }

  static float spread2(const TeamRobotEstimate& e) { return e.covariance(0, 0) + e.covariance(1, 1); }

  float log_clutter() const {
    const float reach = config_.sighting_reach_m > 0.1f ? config_.sighting_reach_m : 0.1f;
    return fmath::log(config_.sighting_clutter) - fmath::log(reach * kTwoPi);
  }

  // log p(z | observer at mu_o, seen at mu_s) of the header: the mixture of the Gaussian of the innovation and the
  // clutter, S from both robots' covariances.
  float log_sighting(const TeamMeasurement& z, const TeamRobotEstimate& o, const TeamRobotEstimate& s) const {
    const Eigen::Vector3f xo(o.mean.x, o.mean.y, o.mean.theta);
    const Eigen::Vector2f ps(s.mean.x, s.mean.y);
    const RangeBearingMeasurement<3> h = range_bearing_measurement<3>(xo, ps);
    if (!h.ok) return log_clutter();
    Eigen::Matrix2f S = Eigen::Matrix2f::Zero();
    S += h.H_robot * o.covariance * h.H_robot.transpose();
    S += h.H_landmark * s.covariance.template topLeftCorner<2, 2>() * h.H_landmark.transpose();
    const float heading_limit = config_.bearing_heading_limit_rad * config_.bearing_heading_limit_rad;
    return log_mixture(z, h.z, S, o.covariance(2, 2) <= heading_limit);
  }

  // log((1 - eps) N(z - z_hat; 0, S + Q) + eps / (reach 2 pi)); without the bearing, its factor uniform 1 / (2 pi).
  float log_mixture(const TeamMeasurement& z, const Eigen::Vector2f& z_hat, const Eigen::Matrix2f& S_in,
                    bool use_bearing = true) const {
    const float sr = config_.sighting_sigma_range, sb = config_.sighting_sigma_bearing;
    const float a = S_in(0, 0) + sr * sr, b = 0.5f * (S_in(0, 1) + S_in(1, 0)), d = S_in(1, 1) + sb * sb;
    const float log_c = log_clutter();
    const float vr = z.range_m - z_hat(0);
    const float vb = fmath::normalize_angle(z.bearing_rad - z_hat(1));
    float log_g = fmath::log(1.0f - config_.sighting_clutter);
    if (use_bearing) {
      const float det = a * d - b * b;
      if (!(det > 0.0f) || !fmath::isfinite(det)) return log_c;
      const float quad = (d * vr * vr - 2.0f * b * vr * vb + a * vb * vb) / det;
      log_g += -0.5f * quad - 0.5f * fmath::log(det) - 2.0f * kLogSqrtTwoPi;
    } else {
      if (!(a > 0.0f) || !fmath::isfinite(a)) return log_c;
      log_g += -0.5f * vr * vr / a - 0.5f * fmath::log(a) - kLogSqrtTwoPi - fmath::log(kTwoPi);
    }
    const float hi = log_g > log_c ? log_g : log_c;
    const float lo = log_g > log_c ? log_c : log_g;
    const float out = hi + fmath::log(1.0f + fmath::exp(lo - hi));
    return fmath::isfinite(out) ? out : log_c;
  }

  // The target's particles weighted by the sighting, the reference at its estimate (header). seen_is_target: the
  // target is the robot seen (its particle is the seen position), else the observer (its particle is the pose).
  void correct_by_sighting(int target, const TeamMeasurement& z, const TeamRobotEstimate& ref, bool seen_is_target) {
    const TeamRobotEstimate& tgt = estimate_[target];
    const TeamRobotEstimate& o = seen_is_target ? ref : tgt;
    const TeamRobotEstimate& s = seen_is_target ? tgt : ref;
    // S from the reference's covariance alone, linearized once at the two estimates.
    const Eigen::Vector3f xo(o.mean.x, o.mean.y, o.mean.theta);
    const RangeBearingMeasurement<3> h0 = range_bearing_measurement<3>(xo, Eigen::Vector2f(s.mean.x, s.mean.y));
    Eigen::Matrix2f S = Eigen::Matrix2f::Zero();
    if (h0.ok) {
      if (seen_is_target)
        S = h0.H_robot * ref.covariance * h0.H_robot.transpose();
      else
        S = h0.H_landmark * ref.covariance.template topLeftCorner<2, 2>() * h0.H_landmark.transpose();
    }
    ParticleSetView v = set_[target].view();
    for (std::uint32_t i = 0; i < v.count; ++i) {
      const Pose2 p = v.pose(i);
      const Eigen::Vector3f xi = seen_is_target ? xo : Eigen::Vector3f(p.x, p.y, p.theta);
      const Eigen::Vector2f pi = seen_is_target ? Eigen::Vector2f(p.x, p.y) : Eigen::Vector2f(s.mean.x, s.mean.y);
      const RangeBearingMeasurement<3> h = range_bearing_measurement<3>(xi, pi);
      v.log_w[i] += h.ok ? log_mixture(z, h.z, S) : log_clutter();
    }
  }

  // Sensor resetting (header): reset_fraction of the particles, evenly spaced from a random start, replaced by poses
  // that explain two of the landmarks in view. They take the average weight.
  void sensor_reset(int robot, const LandmarkMeasurement* f, const std::int32_t* c, std::int32_t n, float fraction) {
    TwoLandmarkSampler<MaxLandmarks> draw(map_, config_.landmark_noise);
    for (std::int32_t k = 0; k < n; ++k) draw.add(f[k], c[k]);
    ParticleSetView v = set_[robot].view();
    const std::uint32_t m = static_cast<std::uint32_t>(fraction * static_cast<float>(v.count));
    if (m == 0u) return;
    const std::uint32_t stride = v.count / m;
    const std::uint32_t start = rng_[robot].below(stride);
    const float lw = -fmath::log(static_cast<float>(v.count));
    for (std::uint32_t k = 0; k < m; ++k) {
      Pose2 p;
      if (!draw(rng_[robot], p)) continue;
      const std::uint32_t i = start + k * stride;
      v.set_pose(i, p);
      v.log_w[i] = lw;
      ++counters_.injected_particles;
    }
    normalize_log_weights(v.log_w, v.count);
  }

  // Normalize, resample by the low-variance sampler (table 4.4) when the ESS is low, refresh the estimate.
  void finish_correction(int robot) {
    ParticleSetView v = set_[robot].view();
    const LogNormalization nrm = normalize_log_weights(v.log_w, v.count);
    if (nrm.degenerate) ++counters_.degenerate_corrections;
    refresh_estimate(robot);  // the corrected set's, before resampling duplicates it
    if (effective_sample_size(v.log_w, v.count) < config_.resample_ess_fraction * static_cast<float>(v.count)) {
      ParticleSet<Particles>& set = set_[robot];
      set.swap_with_scratch(low_variance_sampler(ConstParticleSetView(v), set.scratch(), v.count, rng_[robot]));
      ++counters_.resamplings;
    }
  }

  void refresh_estimate(int robot) {
    const ClusterEstimate c =
        strongest_cluster<ClusterSlots>(set_[robot].view(), config_.cluster_cell, config_.cluster_dominance);
    TeamRobotEstimate& e = estimate_[robot];
    const PoseEstimate& s = c.strongest;
    const float lim_xy = config_.localized_spread_m * config_.localized_spread_m;
    const float lim_th = config_.localized_heading_rad * config_.localized_heading_rad;
    e.cluster_weight = s.weight;
    e.localized = !c.multimodal && s.covariance(0, 0) + s.covariance(1, 1) <= lim_xy && s.covariance(2, 2) <= lim_th;
    const PoseEstimate& use = e.localized ? s : c.overall;
    if (use.mean.is_finite() && use.covariance.allFinite() && use.weight > 0.0f) {
      e.mean = use.mean;
      e.covariance = use.covariance;
    } else {  // no weight: keep the last estimate, not localized
      e.localized = false;
    }
  }

  AnonymousTeamMclConfig config_;
  LandmarkMap map_;
  Rng rng_[static_cast<unsigned>(N)];
  ParticleSet<Particles> set_[static_cast<unsigned>(N)];
  TeamRobotEstimate estimate_[static_cast<unsigned>(N)];
  Belief belief_;
  AnonymousTeamMclCounters counters_;
};

}  // namespace est::team

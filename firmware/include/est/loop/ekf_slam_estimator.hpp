#pragma once
// The loop's EKF-SLAM estimator (Probabilistic Robotics table 10.1 with unknown correspondence): one robot and up to
// MaxLandmarks landmarks in one Gaussian (est/slam/cooperative_ekf_slam.hpp with a team of one), any pose motion
// model predicting through its control assembler (est/loop/control_assemblers.hpp), landmark features (range,
// bearing in the robot frame, signature) correcting it; the features of one sensor frame share a stamp.
//
// Association, per feature, by gated maximum likelihood (the correspondence test of table 10.2, lines 9-16, done by
// maximum likelihood): the Mahalanobis distance d^2 of the innovation under S_k = H_k P H_k^T + Q for every landmark
// k not yet used in this frame (within search_radius_m of where the feature puts it); then
//   d^2 < gate_accept              fused with the nearest landmark (associated);
//   d^2 > gate_new or no landmark  a new landmark, once confirmed (below);
//   in between                     discarded: too far to be that landmark, too near to be another.
// A new landmark is tentative until confirm_sightings features of different frames fall within candidate_radius_m
// of one another (the mean of them), so that clutter and one-off returns do not take the map's fixed capacity;
// a tentative landmark unseen for candidate_scans frames is forgotten. Up to MaxTentative are held at once.
//
// Every feature ends in exactly one counter of SlamAssociationCounters (their sum is the features corrected with).
// Outcomes the loop counts: a feature refused (not finite, the filter refused the update or the insertion, the map
// or the tentative table full) is `rejected` and the belief kept; one beyond max_range_m, held as tentative or
// discarded between the gates is a decision, not a fault (`applied`). A robot position standard deviation beyond
// lost_sigma_m is reported `degenerate`.
//
// Motion noise: the model's per-step noise (e.g. the bicycle's speed_var_per_speed, steer_sigma) is for steps of
// noise_step_s when that is positive, and is scaled to each prediction's dt as a white noise (variances in
// proportion to noise_step_s / dt; only the bicycle's parameters are per step, the other models' are left as they
// are); rot_sigma is added to the heading at every prediction. No heap: the storage is the filter's (3 + 2 M)^2
// covariance and the tentative table; every loop is bounded by M or MaxTentative.
#include <cstdint>

#include "est/filter/correction_status.hpp"
#include "est/filter/landmark_measurement.hpp"
#include "est/filter/particle_estimate.hpp"
#include "est/loop/control_assemblers.hpp"
#include "est/loop/filter_loop.hpp"
#include "est/math/fmath.hpp"
#include "est/motion/bicycle_model.hpp"
#include "est/sensor/landmark_model.hpp"
#include "est/slam/cooperative_ekf_slam.hpp"

namespace est::loop {

template <typename Model>
struct EkfSlamEstimatorConfig {
  typename Model::Params motion{};
  typename ControlAssembler<Model>::Config control{};
  LandmarkNoise noise{0.5f, 0.05f, 0.0f};  // of the landmark sensor (the signature is kept, not used to associate)
  float rot_sigma = 0.002f;                // rad per prediction, added to the heading: what the model leaves out
  float noise_step_s = 0.0f;               // > 0: the model's per-step noise is for steps this long (above)
  float max_range_m = 30.0f;               // features farther away are not used (counted beyond_range)
  float gate_accept = 9.21f;               // chi^2 with 2 dof at 0.99: associate under it
  float gate_new = 30.0f;                  // a new landmark above it
  float search_radius_m = 10.0f;           // landmarks farther from where the feature puts it are not candidates
  std::int32_t confirm_sightings = 2;      // sightings in different frames before a new landmark enters (1: at once)
  float candidate_radius_m = 1.0f;         // a tentative landmark's sightings agree within this
  std::uint32_t candidate_scans = 10;      // a tentative landmark unseen for this many frames is forgotten
  float lost_sigma_m = 50.0f;              // robot position sd (the larger axis) above which the belief is degenerate
  CovarianceGuard guard{};
};

// Where each feature went (EkfSlamEstimator::counters()).
struct SlamAssociationCounters {
  std::uint32_t frames = 0;               // sensor frames (distinct stamps) with features
  std::uint32_t associated = 0;           // fused with an existing landmark
  std::uint32_t created = 0;              // entered the map as a new landmark
  std::uint32_t discarded = 0;            // between the gates
  std::uint32_t beyond_range = 0;         // beyond max_range_m
  std::uint32_t tentative = 0;            // held for a tentative landmark
  std::uint32_t update_refused = 0;       // associated, but the filter refused the update (its gate, not PD)
  std::uint32_t insert_refused = 0;       // confirmed, but the filter refused the insertion (geometry, not finite)
  std::uint32_t map_full = 0;             // confirmed, but the map holds MaxLandmarks already
  std::uint32_t tentative_full = 0;       // new, but the tentative table holds MaxTentative already
  std::uint32_t bad_input = 0;            // range or bearing not finite, range not positive, or not initialized
  std::uint32_t tentative_forgotten = 0;  // tentative landmarks never confirmed (not features: not in features())

  std::uint32_t features() const {
    return associated + created + discarded + beyond_range + tentative + update_refused + insert_refused + map_full +
           tentative_full + bad_input;
  }
};

// The bicycle's noise is per step; scaled to a step of `ratio` times the reference (variances in proportion to
// 1 / ratio: a white noise of the speed and the steering). Other models: as configured.
inline void scale_step_noise(BicycleParams& p, float step_over_dt) {
  p.speed_var_per_speed *= step_over_dt;
  const float s = fmath::sqrt(step_over_dt);
  p.steer_sigma *= s;
  p.final_rot_sigma *= s;
}
template <typename Params>
void scale_step_noise(Params&, float) {}

template <typename Model, int MaxLandmarks, int MaxTentative = 32>
class EkfSlamEstimator {
  static_assert(Model::kStateDim == 3, "the loop's EKF-SLAM estimates a pose (x, y, theta) and the landmarks");
  static_assert(MaxLandmarks >= 1 && MaxTentative >= 1, "capacities");

 public:
  using Slam = CooperativeEkfSlam<Model, 1, MaxLandmarks>;
  using Assembler = ControlAssembler<Model>;
  static constexpr int kMaxLandmarks = MaxLandmarks;
  static constexpr int kMaxTentative = MaxTentative;

  explicit EkfSlamEstimator(const EkfSlamEstimatorConfig<Model>& config) : config_(config) {
    typename Slam::Params p;
    p.gate.chi2_2dof = 1.01f * config.gate_accept;  // the association gated already; the same test, rounding aside
    p.guard = config.guard;
    p.additive_process_noise(2, 2) = config.rot_sigma * config.rot_sigma;
    slam_.configure(p);
  }

  InputKinds inputs() const { return Assembler::inputs(config_.control) | InputKind::landmark; }

  // A Gaussian start with an empty map; false (and still uninitialized) for a pose or deviations not finite and
  // positive.
  bool initialize_at(const Pose2& pose, float sigma_xy, float sigma_theta) {
    initialized_ = false;
    if (!(sigma_xy > 0.0f) || !(sigma_theta > 0.0f) || !fmath::isfinite(sigma_xy) || !fmath::isfinite(sigma_theta))
      return false;
    typename Slam::RobotCovariance cov = Slam::RobotCovariance::Zero();
    cov(0, 0) = sigma_xy * sigma_xy;
    cov(1, 1) = sigma_xy * sigma_xy;
    cov(2, 2) = sigma_theta * sigma_theta;
    initialized_ = slam_.init(1, &pose, &cov);
    n_tentative_ = 0;
    frame_started_ = false;
    frame_t_ = 0;
    counters_ = SlamAssociationCounters{};
    return initialized_;
  }

  // Table 10.1 lines 2-5 over the motion since the last prediction.
  StepOutcome predict(const MotionInput& m) {
    if (!initialized_) return StepOutcome::rejected;
    typename Model::Params p = config_.motion;
    typename Model::Control u{};
    const ControlStatus c = Assembler::make(m, config_.control, p, u);
    if (c == ControlStatus::still) return StepOutcome::applied;  // standing still: no diffusion
    if (c == ControlStatus::rejected) return StepOutcome::rejected;
    if (config_.noise_step_s > 0.0f && m.dt_s > 0.0f) scale_step_noise(p, config_.noise_step_s / m.dt_s);
    if (!usable(slam_.predict_robot(0, u, p))) return StepOutcome::rejected;
    return lost() ? StepOutcome::degenerate : StepOutcome::applied;
  }

  // One feature: associated, a new landmark, held, discarded or refused (the header says which is which).
  StepOutcome correct(const LandmarkInput& z) {
    if (!initialized_ || !fmath::isfinite(z.range_m) || !fmath::isfinite(z.bearing_rad) || !(z.range_m > 0.0f)) {
      ++counters_.bad_input;
      return StepOutcome::rejected;
    }
    if (!frame_started_ || z.t_ns != frame_t_) start_frame(z.t_ns);
    if (z.range_m > config_.max_range_m) {
      ++counters_.beyond_range;
      return StepOutcome::applied;
    }
    const Candidate c = most_likely_landmark(z);
    if (c.slot >= 0 && c.d2 < config_.gate_accept) {
      used_[c.slot] = true;
      const CorrectionResult r =
          slam_.correct_landmark_range_bearing(0, slam_.landmark_id(c.slot), z.range_m, z.bearing_rad, config_.noise);
      if (!accepted(r.status)) {
        ++counters_.update_refused;
        return StepOutcome::rejected;
      }
      ++counters_.associated;
      add_signature(c.slot, z.signature);
      return lost() ? StepOutcome::degenerate : StepOutcome::applied;
    }
    if (c.slot >= 0 && c.d2 <= config_.gate_new) {
      ++counters_.discarded;
      return StepOutcome::applied;
    }
    switch (confirm(z)) {
      case Confirmation::held: return StepOutcome::applied;
      case Confirmation::table_full: return StepOutcome::rejected;
      case Confirmation::confirmed: break;
    }
    if (slam_.landmarks() >= MaxLandmarks) {
      ++counters_.map_full;
      return StepOutcome::rejected;
    }
    const std::int32_t slot = slam_.landmarks();
    const CorrectionResult r = slam_.correct_landmark_range_bearing(0, slot, z.range_m, z.bearing_rad, config_.noise);
    if (!accepted(r.status) || slam_.landmarks() != slot + 1) {
      ++counters_.insert_refused;
      return StepOutcome::rejected;
    }
    ++counters_.created;
    used_[slot] = true;
    signature_[slot] = 0.0f;
    sightings_[slot] = 0;
    add_signature(slot, z.signature);
    return lost() ? StepOutcome::degenerate : StepOutcome::applied;
  }

  PoseEstimate estimate() const {
    PoseEstimate e;
    e.mean = slam_.robot(0);
    e.covariance = slam_.robot_covariance(0);
    e.weight = 1.0f;
    e.particles = 0;
    return e;
  }

  bool initialized() const { return initialized_; }
  const Slam& filter() const { return slam_; }
  const SlamAssociationCounters& counters() const { return counters_; }
  int landmarks() const { return slam_.landmarks(); }
  Eigen::Vector2f landmark(int k) const { return slam_.landmark(k); }
  float landmark_signature(int k) const { return signature_[k]; }  // the mean of its sightings' signatures
  int tentative_landmarks() const { return n_tentative_; }

 private:
  struct Candidate {
    int slot = -1;
    float d2 = 0.0f;
  };
  struct Tentative {
    float x, y;
    std::int32_t seen;
    std::uint32_t last_frame;
  };
  enum class Confirmation : std::uint8_t { confirmed, held, table_full };

  // A new frame: landmarks may be used again, and the tentative landmarks unseen for too long are forgotten
  // (order kept, so that the search's ties fall the same way).
  void start_frame(TimeNs t) {
    frame_started_ = true;
    frame_t_ = t;
    ++counters_.frames;
    for (int k = 0; k < MaxLandmarks; ++k) used_[k] = false;
    int kept = 0;
    for (int i = 0; i < n_tentative_; ++i) {
      if (counters_.frames - tentative_[i].last_frame > config_.candidate_scans) {
        ++counters_.tentative_forgotten;
        continue;
      }
      tentative_[kept++] = tentative_[i];
    }
    n_tentative_ = kept;
  }

  // The landmark of smallest Mahalanobis distance among those not used in this frame.
  Candidate most_likely_landmark(const LandmarkInput& z) const {
    Candidate best;
    const typename Slam::Vector& mu = slam_.mean();
    const typename Slam::Covariance& P = slam_.covariance();
    const Eigen::Vector3f x = mu.template segment<3>(0);
    const Eigen::Matrix3f Paa = P.template block<3, 3>(0, 0);
    float s = 0.0f, c = 0.0f;
    fmath::sincos(x(2) + z.bearing_rad, s, c);
    const Eigen::Vector2f seen(x(0) + z.range_m * c, x(1) + z.range_m * s);
    const float radius2 = config_.search_radius_m * config_.search_radius_m;
    const float q_range = config_.noise.sigma_range * config_.noise.sigma_range;
    const float q_bearing = config_.noise.sigma_bearing * config_.noise.sigma_bearing;
    for (int k = 0; k < slam_.landmarks(); ++k) {
      if (used_[k]) continue;
      const int lo = slam_.landmark_offset(k);
      const Eigen::Vector2f m = mu.template segment<2>(lo);
      if ((m - seen).squaredNorm() > radius2) continue;
      const auto h = range_bearing_measurement<3>(x, m);
      if (!h.ok) continue;
      const Eigen::Matrix<float, 3, 2> Pal = P.template block<3, 2>(0, lo);
      const Eigen::Matrix2f Pll = P.template block<2, 2>(lo, lo);
      Eigen::Matrix2f S = h.H_robot * Paa * h.H_robot.transpose() + h.H_robot * Pal * h.H_landmark.transpose() +
                          h.H_landmark * Pal.transpose() * h.H_robot.transpose() +
                          h.H_landmark * Pll * h.H_landmark.transpose();
      S(0, 0) += q_range;
      S(1, 1) += q_bearing;
      const float nu0 = z.range_m - h.z(0);
      const float nu1 = fmath::normalize_angle(z.bearing_rad - h.z(1));
      const float det = S(0, 0) * S(1, 1) - S(0, 1) * S(1, 0);
      if (!(det > 0.0f)) continue;
      const float d2 = (S(1, 1) * nu0 * nu0 - 2.0f * S(0, 1) * nu0 * nu1 + S(0, 0) * nu1 * nu1) / det;
      if (!fmath::isfinite(d2)) continue;
      if (best.slot < 0 || d2 < best.d2) best = {k, d2};
    }
    return best;
  }

  // A feature that fits no landmark: a new tentative landmark, another sighting of one (from another frame), or,
  // at the confirm_sightings-th sighting, confirmed (and taken off the table).
  Confirmation confirm(const LandmarkInput& z) {
    if (config_.confirm_sightings <= 1) return Confirmation::confirmed;
    const Pose2 x = slam_.robot(0);
    float s = 0.0f, c = 0.0f;
    fmath::sincos(x.theta + z.bearing_rad, s, c);
    const float px = x.x + z.range_m * c, py = x.y + z.range_m * s;
    int best = -1;
    float best_d = config_.candidate_radius_m;
    for (int i = 0; i < n_tentative_; ++i) {
      const float dx = tentative_[i].x - px, dy = tentative_[i].y - py;
      const float d = fmath::sqrt(dx * dx + dy * dy);
      if (tentative_[i].last_frame != counters_.frames && d < best_d) best = i, best_d = d;
    }
    if (best < 0) {
      if (n_tentative_ >= MaxTentative) {
        ++counters_.tentative_full;
        return Confirmation::table_full;
      }
      tentative_[n_tentative_++] = {px, py, 1, counters_.frames};
      ++counters_.tentative;
      return Confirmation::held;
    }
    Tentative& t = tentative_[best];
    const float n = static_cast<float>(t.seen);
    t.x = (t.x * n + px) / (n + 1.0f);
    t.y = (t.y * n + py) / (n + 1.0f);
    t.last_frame = counters_.frames;
    if (++t.seen < config_.confirm_sightings) {
      ++counters_.tentative;
      return Confirmation::held;
    }
    for (int i = best + 1; i < n_tentative_; ++i) tentative_[i - 1] = tentative_[i];
    --n_tentative_;
    return Confirmation::confirmed;
  }

  void add_signature(int slot, float signature) {
    if (!fmath::isfinite(signature)) return;
    const float n = static_cast<float>(sightings_[slot]);
    signature_[slot] = (signature_[slot] * n + signature) / (n + 1.0f);
    ++sightings_[slot];
  }

  bool lost() const {
    const typename Slam::RobotCovariance P = slam_.robot_covariance(0);
    const float limit = config_.lost_sigma_m * config_.lost_sigma_m;
    return P(0, 0) > limit || P(1, 1) > limit;
  }

  EkfSlamEstimatorConfig<Model> config_;
  Slam slam_;
  bool initialized_ = false;
  bool frame_started_ = false;
  TimeNs frame_t_ = 0;
  bool used_[static_cast<unsigned>(MaxLandmarks)] = {};
  float signature_[static_cast<unsigned>(MaxLandmarks)] = {};
  std::uint32_t sightings_[static_cast<unsigned>(MaxLandmarks)] = {};
  Tentative tentative_[static_cast<unsigned>(MaxTentative)] = {};
  int n_tentative_ = 0;
  SlamAssociationCounters counters_{};
};

}  // namespace est::loop

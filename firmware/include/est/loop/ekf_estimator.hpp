#pragma once
// The loop's EKF localization estimator (Probabilistic Robotics table 7.2, and table 7.3 for features without a
// correspondence): any motion model's mean and Jacobians predict (through its control assembler,
// est/loop/control_assemblers.hpp), landmark features of a known map
// correct, one feature at a time. Storage is the 3 x 3 belief; the landmark map is owned by the caller and outlives
// the estimator. Features are in the robot frame (a landmark sensor mounted elsewhere is transformed by its driver).
//
// Outcomes the loop counts: a prediction the model refuses, a feature the filter refuses (gate, unknown landmark,
// non-finite, not positive definite; each also counted by reason in filter().counters()) are `rejected`, and the
// belief is kept; a belief whose position standard deviation grew beyond `lost_sigma_m` is reported `degenerate`
// (dead reckoning without landmarks for too long: the Gaussian no longer localizes the robot).
//
// Joint association is a capacity of the type: EkfEstimator<Model, JointSightings> with JointSightings > 0 holds a
// frame of that many features and the search of est/assoc/jcbb.hpp; with 0 (the default) neither is compiled in, and
// a board image that does not associate jointly pays no flash, RAM or stack for it (the EKF reference image on the
// M4F: flash 42 880 -> 34 624 B, RAM 9 332 -> 6 260 B, a step's stack bound 1 532 -> 1 148 B). With
// `joint_association` set (which a type without the capacity refuses: initialize_at() returns false), features
// without a correspondence are not associated one at a time (table 7.3) but per sensor frame, the features sharing a
// stamp, by joint compatibility: they are gathered by correct() and fused, each with the landmark its frame's
// assignment gave it, by end_of_frame() (the loop calls it after the last input of a stamp), or by the next
// predict() or a feature of another stamp. A frame of more than JointSightings features is associated in parts of
// that many (counted as split).
//
// Re-opening the gate (`reopen_after` > 0): a feature of known correspondence that the gate refuses says the belief
// is wrong or overconfident, and after a long gap several such refusals in a row say the robot is elsewhere than
// the Gaussian allows; the refused features would never be fused again. After `reopen_after` consecutive gate
// refusals of known-correspondence features, the belief is taken as relocalizing: its covariance is widened by
// reopen_sigma_xy / reopen_sigma_theta (added variance) and the last feature is tried again (counted, reopenings()).
// With joint association the same holds for frames: `reopen_after` frames in a row in which no feature is jointly
// compatible with any landmark widen the belief, and the last frame is associated again.
#include <cstdint>
#include <type_traits>

#include "est/assoc/jcbb.hpp"
#include "est/filter/ekf_localization.hpp"
#include "est/filter/particle_estimate.hpp"
#include "est/loop/filter_loop.hpp"
#include "est/loop/control_assemblers.hpp"
#include "est/map/landmark_map.hpp"
#include "est/sensor/landmark_model.hpp"

namespace est::loop {

template <typename Model>
struct EkfEstimatorConfig {
  typename EkfLocalization<Model>::Params ekf{};
  typename Model::Params motion{};
  typename ControlAssembler<Model>::Config control{};
  LandmarkNoise noise{};      // of the landmark sensor (sigma_signature <= 0: signatures not used)
  // A range noise that grows with the range, as a camera's does: a feature at range r is fused with
  // sigma_range + sigma_range_per_m * r (0: the constant noise.sigma_range).
  float sigma_range_per_m = 0.0f;
  float lost_sigma_m = 5.0f;  // position standard deviation (the larger axis) above which the belief is degenerate
  bool sensor_ids = true;     // false: the sensor's ids are ignored, every feature is associated by table 7.3
  std::uint32_t reopen_after = 0;   // consecutive gate refusals of known features that re-open the gate (0: never)
  float reopen_sigma_xy = 0.5f;     // m, added to the position's deviation (in variance) when the gate re-opens
  float reopen_sigma_theta = 0.3f;  // rad, added to the heading's
  bool joint_association = false;  // features without an id: associated per frame by JCBB instead of table 7.3
                                   // (needs an EkfEstimator with JointSightings > 0)
  JcbbParams jcbb{};
  // Joint association: a frame whose assignment pairs a single feature is not fused while the position's deviation
  // (sqrt(var x + var y)) is above this and another landmark is also in that feature's gate (a runner-up): one
  // range and bearing cannot tell the landmarks apart then, and a wrong one, fused at that width, moves the pose by
  // metres. Frames of two or more pairings are fused (their joint compatibility tells). 0: never refused.
  float lone_pairing_sigma_m = 0.0f;
};

// Joint association's counts (EkfEstimator::joint_counters()).
struct JointAssociationCounters {
  std::uint32_t frames = 0;
  std::uint32_t features = 0;
  std::uint32_t paired = 0;              // given a landmark by the frame's assignment
  std::uint32_t unpaired = 0;            // in no jointly compatible assignment of the most pairings, ambiguous, or lone
  std::uint32_t ambiguous_frames = 0;    // the runner-up assignment within ambiguity_nats: shared pairings only
  std::uint32_t lone_refused = 0;        // one pairing, a runner-up, the pose uncertain (lone_pairing_sigma_m)
  std::uint32_t node_cap_hits = 0;       // frames whose search stopped at JcbbParams::max_nodes
  std::uint32_t split_frames = 0;        // frames of more than kFrameSightings features
  std::uint32_t candidates_dropped = 0;  // individually compatible landmarks beyond kCandidates
};

namespace detail {
// Joint association's storage: the frame gathered, the search, its counts; nothing without the capacity.
template <int Sightings, int Candidates>
struct JointAssociationState {
  JointCompatibility<Sightings, Candidates> jcbb;
  LandmarkInput frame[static_cast<unsigned>(Sightings)];
  int n = 0;
  JointAssociationCounters counters{};
};
template <int Candidates>
struct JointAssociationState<0, Candidates> {
  static constexpr int n = 0;
  static constexpr JointAssociationCounters counters{};
};
}  // namespace detail

// The host programs' capacity (estimator_node, sim_host, the evaluations): frames of up to 8 features.
inline constexpr int kHostJointSightings = 8;

template <typename Model, int JointSightings = 0>
class EkfEstimator {
  static_assert(Model::kStateDim == 3, "the loop's EKF estimates a pose (x, y, theta)");
  static_assert(JointSightings >= 0, "a capacity");

 public:
  using Filter = EkfLocalization<Model>;
  using Assembler = ControlAssembler<Model>;
  static constexpr int kFrameSightings = JointSightings;  // features associated jointly (more in one frame: in parts)
  static constexpr int kCandidates = 4;      // landmarks kept per feature for the joint search, nearest first
  static constexpr bool kJointAssociation = JointSightings > 0;

  EkfEstimator(const EkfEstimatorConfig<Model>& config, const LandmarkMap& map)
      : config_(config), ekf_(config.ekf), map_(map) {}

  InputKinds inputs() const { return Assembler::inputs(config_.control) | InputKind::landmark; }

  // A Gaussian start; false (and still uninitialized) when the pose or the deviations are not finite and positive.
  // Also false when the configuration asks for joint association and the type has no capacity for it.
  bool initialize_at(const Pose2& pose, float sigma_xy, float sigma_theta) {
    if (config_.joint_association && !kJointAssociation) return false;
    if (!(sigma_xy > 0.0f) || !(sigma_theta > 0.0f) || !fmath::isfinite(sigma_xy) || !fmath::isfinite(sigma_theta))
      return false;
    typename Filter::Covariance cov = Filter::Covariance::Zero();
    cov(0, 0) = sigma_xy * sigma_xy;
    cov(1, 1) = sigma_xy * sigma_xy;
    cov(2, 2) = sigma_theta * sigma_theta;
    initialized_ = ekf_.init(pose, cov);
    return initialized_;
  }

  // Table 7.2 lines 2-7 over the motion since the last prediction.
  StepOutcome predict(const MotionInput& m) {
    if (!initialized_) return StepOutcome::rejected;
    if (frame_pending()) end_of_frame();  // the loop has fused it already (end_of_frame); a caller without one
    typename Model::Params p = config_.motion;
    typename Model::Control u{};
    const ControlStatus c = Assembler::make(m, config_.control, p, u);
    if (c == ControlStatus::still) return StepOutcome::applied;  // standing still: no diffusion
    if (c == ControlStatus::rejected) return StepOutcome::rejected;
    if (!usable(ekf_.predict(u, p))) return StepOutcome::rejected;
    return lost() ? StepOutcome::degenerate : StepOutcome::applied;
  }

  // Table 7.2 lines 8-20 with the feature's correspondence, or table 7.3 when it has none (id < 0).
  StepOutcome correct(const LandmarkInput& z) {
    if (!initialized_) return StepOutcome::rejected;
    const LandmarkMeasurement f{z.range_m, z.bearing_rad, z.signature};
    const bool known = z.id >= 0 && config_.sensor_ids;
    if constexpr (kJointAssociation)
      if (!known && config_.joint_association) return gather(z);
    const LandmarkNoise noise = noise_at(z.range_m);
    CorrectionResult r = known ? ekf_.correct_range_bearing(f, map_, z.id, noise)
                               : ekf_.correct_range_bearing_unknown(f, map_, noise).correction;
    if (known) {
      if (r.status == CorrectionStatus::rejected_gate && config_.reopen_after > 0 &&
          ++gate_refusals_ >= config_.reopen_after && reopen())
        r = ekf_.correct_range_bearing(f, map_, z.id, noise);
      if (accepted(r.status)) gate_refusals_ = 0;
    }
    if (!accepted(r.status)) return StepOutcome::rejected;
    return lost() ? StepOutcome::degenerate : StepOutcome::applied;
  }

  // Fuses the frame gathered (fuse_frame()); the loop calls it after the last input of a stamp. Without the capacity
  // there is never a frame.
  StepOutcome end_of_frame() {
    if constexpr (kJointAssociation) return fuse_frame();
    else return StepOutcome::applied;
  }

  PoseEstimate estimate() const {
    PoseEstimate e;
    e.mean = ekf_.mean();
    e.covariance = ekf_.covariance();
    e.weight = 1.0f;
    e.particles = 0;
    return e;
  }

  bool initialized() const { return initialized_; }
  const Filter& filter() const { return ekf_; }
  const JointAssociationCounters& joint_counters() const { return joint_.counters; }
  bool frame_pending() const { return joint_.n > 0; }
  std::uint32_t reopenings() const { return reopenings_; }

 private:
  // Fuses the gathered frame: JCBB's assignment, then each paired feature with its landmark (table 7.2 lines
  // 8-20, one at a time). Rejected when no feature of the frame was fused.
  StepOutcome fuse_frame() {
    auto& st = joint_;
    if (st.n <= 0) return StepOutcome::applied;
    JcbbSighting s[static_cast<unsigned>(kFrameSightings)];
    for (int i = 0; i < st.n; ++i) {
      const LandmarkNoise n = noise_at(st.frame[i].range_m);
      s[i] = {st.frame[i].range_m, st.frame[i].bearing_rad, n.sigma_range, n.sigma_bearing};
    }
    const int n = st.n;
    st.n = 0;
    // At most two searches (one call site, so the search is compiled once): the second after the gate re-opened.
    typename std::remove_reference_t<decltype(st.jcbb)>::Result a;
    for (int attempt = 0; attempt < 2; ++attempt) {
      a = st.jcbb.associate(ekf_.mean_vector(), ekf_.covariance(), s, n, map_, config_.jcbb);
      if (attempt > 0 || config_.reopen_after == 0 || !a.ok) break;
      bool any = false;
      for (int i = 0; i < n; ++i) any = any || a.landmark_of[i] >= 0;
      if (any) {
        gate_refusals_ = 0;
        break;
      }
      if (++gate_refusals_ < config_.reopen_after || !reopen()) break;
    }
    JointAssociationCounters& c = st.counters;
    ++c.frames;
    c.features += static_cast<std::uint32_t>(n);
    c.candidates_dropped += a.candidates_dropped;
    if (a.node_cap_hit) ++c.node_cap_hits;
    // The ambiguity test of table 7.3's (EkfLocalization::Params::ambiguity_nats), for the frame: when the
    // runner-up assignment's log likelihood is within that margin, only the pairings both make are fused.
    const bool ambiguous = a.has_runner_up && 0.5f * (a.runner_up_nis - a.joint_nis) < config_.ekf.ambiguity_nats;
    if (ambiguous) ++c.ambiguous_frames;
    if (a.ok && a.paired == 1 && a.has_runner_up && lone_pairing_uncertain()) {
      ++c.lone_refused;
      c.unpaired += static_cast<std::uint32_t>(n);
      return StepOutcome::rejected;
    }
    std::int32_t fused = 0;
    for (int i = 0; i < n; ++i) {
      std::int32_t j = a.ok ? a.landmark_of[i] : -1;
      if (ambiguous && j != a.runner_up_of[i]) j = -1;
      if (j < 0) {
        ++c.unpaired;
        continue;
      }
      ++c.paired;
      const LandmarkInput& z = st.frame[i];
      const LandmarkMeasurement f{z.range_m, z.bearing_rad, z.signature};
      if (accepted(ekf_.correct_range_bearing(f, map_, j, noise_at(z.range_m)).status)) ++fused;
    }
    if (fused == 0) return StepOutcome::rejected;
    return lost() ? StepOutcome::degenerate : StepOutcome::applied;
  }

  LandmarkNoise noise_at(float range_m) const {
    LandmarkNoise noise = config_.noise;
    if (config_.sigma_range_per_m > 0.0f && range_m > 0.0f) noise.sigma_range += config_.sigma_range_per_m * range_m;
    return noise;
  }

  // Joint association: a feature joins the frame of its stamp; a feature of another stamp, or one beyond the
  // frame's capacity, first fuses the frame gathered so far. The outcome of a gathered feature is its frame's.
  StepOutcome gather(const LandmarkInput& z) {
    auto& st = joint_;
    StepOutcome o = StepOutcome::applied;
    if (st.n > 0 && z.t_ns != st.frame[0].t_ns) o = fuse_frame();
    if (st.n >= kFrameSightings) {
      ++st.counters.split_frames;
      o = fuse_frame();
    }
    st.frame[st.n++] = z;
    return o;
  }

  // The gate re-opened: the covariance widened (the mean kept); false if the filter refused it.
  bool reopen() {
    typename Filter::Covariance P = ekf_.covariance();
    P(0, 0) += config_.reopen_sigma_xy * config_.reopen_sigma_xy;
    P(1, 1) += config_.reopen_sigma_xy * config_.reopen_sigma_xy;
    P(2, 2) += config_.reopen_sigma_theta * config_.reopen_sigma_theta;
    if (!ekf_.init(ekf_.mean(), P)) return false;
    gate_refusals_ = 0;
    ++reopenings_;
    return true;
  }

  bool lone_pairing_uncertain() const {
    const float limit = config_.lone_pairing_sigma_m * config_.lone_pairing_sigma_m;
    return limit > 0.0f && ekf_.covariance()(0, 0) + ekf_.covariance()(1, 1) > limit;
  }

  bool lost() const {
    const float limit = config_.lost_sigma_m * config_.lost_sigma_m;
    return ekf_.covariance()(0, 0) > limit || ekf_.covariance()(1, 1) > limit;
  }

  EkfEstimatorConfig<Model> config_;
  Filter ekf_;
  LandmarkMap map_;
  bool initialized_ = false;
  detail::JointAssociationState<JointSightings, kCandidates> joint_{};
  std::uint32_t gate_refusals_ = 0;  // consecutive gate refusals of known features (or frames with no pairing)
  std::uint32_t reopenings_ = 0;
};

}  // namespace est::loop

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
#include <cstdint>

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
};

template <typename Model>
class EkfEstimator {
  static_assert(Model::kStateDim == 3, "the loop's EKF estimates a pose (x, y, theta)");

 public:
  using Filter = EkfLocalization<Model>;
  using Assembler = ControlAssembler<Model>;

  EkfEstimator(const EkfEstimatorConfig<Model>& config, const LandmarkMap& map)
      : config_(config), ekf_(config.ekf), map_(map) {}

  InputKinds inputs() const { return Assembler::inputs(config_.control) | InputKind::landmark; }

  // A Gaussian start; false (and still uninitialized) when the pose or the deviations are not finite and positive.
  bool initialize_at(const Pose2& pose, float sigma_xy, float sigma_theta) {
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
    LandmarkNoise noise = config_.noise;
    if (config_.sigma_range_per_m > 0.0f && z.range_m > 0.0f)
      noise.sigma_range += config_.sigma_range_per_m * z.range_m;
    const CorrectionResult r = known ? ekf_.correct_range_bearing(f, map_, z.id, noise)
                                     : ekf_.correct_range_bearing_unknown(f, map_, noise).correction;
    if (!accepted(r.status)) return StepOutcome::rejected;
    return lost() ? StepOutcome::degenerate : StepOutcome::applied;
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

 private:
  bool lost() const {
    const float limit = config_.lost_sigma_m * config_.lost_sigma_m;
    return ekf_.covariance()(0, 0) > limit || ekf_.covariance()(1, 1) > limit;
  }

  EkfEstimatorConfig<Model> config_;
  Filter ekf_;
  LandmarkMap map_;
  bool initialized_ = false;
};

}  // namespace est::loop

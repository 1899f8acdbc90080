#pragma once
// The loop's Monte Carlo localization estimator: augmented MCL with a wheel-odometry motion model, map-conditioned
// prediction, the likelihood-field range finder model (Thrun table 6.3) and recovery from free space. All storage is
// static: N_max particles and K_max beams are template parameters; the map, its distance transform and the
// likelihood field are owned by the caller and outlive the estimator.
// Prediction uses the whole-set sampler (est/motion/motion_batch.hpp: the model's distribution, vectorizable). The
// correction uses the per-cell likelihood-field grid when one is given (4 bytes a cell, the fast path on a host),
// otherwise the 4 KiB distance-bucket table (the small-memory path for a board); both give the same bits.
#include <cstdint>

#include "est/filter/augmented_mcl.hpp"
#include "est/filter/free_space_sampler.hpp"
#include "est/loop/filter_loop.hpp"
#include "est/loop/odometry_control.hpp"
#include "est/motion/motion_batch.hpp"
#include "est/sensor/likelihood_field_grid.hpp"
#include "est/sensor/likelihood_field_range_finder_model.hpp"
#include "est/sensor/range_scan.hpp"

namespace est::loop {

template <typename Model>
struct MclEstimatorConfig {
  MclConfig mcl{};
  typename Model::Params motion{};
  typename OdometryControl<Model>::Config odometry{};
  Pose2 sensor_mount{};         // rangefinder pose in the robot frame
  std::int32_t beam_stride = 1; // use every s-th beam
  float cluster_cell = 1.0f;    // m, the grid of the strongest-cluster estimate
};

template <typename Model, std::uint32_t NMax, std::int32_t KMax>
class MclEstimator {
 public:
  static constexpr bool kUsesSteering = OdometryControl<Model>::kUsesSteering;
  static constexpr bool kUsesScans = true;
  static constexpr bool kUsesLandmarks = false;

  // `field_grid`, if not null, must be tabulated from `field` over the same map.
  MclEstimator(const MclEstimatorConfig<Model>& config, std::uint64_t seed, const LikelihoodField& field,
               const FreeSpaceSampler& free_space, const LikelihoodFieldGrid* field_grid = nullptr)
      : config_(config), mcl_(config.mcl, seed), field_(field), free_space_(free_space), field_grid_(field_grid) {}

  void initialize_at(const Pose2& pose, float sigma_xy, float sigma_theta, std::uint32_t n) {
    mcl_.initialize_gaussian(pose, sigma_xy, sigma_theta, n);
    initialized_ = true;
    estimate_valid_ = false;
  }
  void initialize_global(std::uint32_t n) {
    mcl_.initialize_global(free_space_, n);
    initialized_ = true;
    estimate_valid_ = false;
  }

  StepOutcome predict(const MotionInput& m) {
    if (!initialized_) return StepOutcome::rejected;
    if (m.left_ticks == 0 && m.right_ticks == 0) return StepOutcome::applied;  // standing still: no diffusion
    typename Model::Params p = config_.motion;
    typename Model::Control u{};
    if (!OdometryControl<Model>::make(m, config_.odometry, p, u)) return StepOutcome::rejected;
    const auto is_free = [this](float x, float y) { return free_space_.admissible_at(x, y); };
    const MotionStatus s = mcl_.template predict_in_map_batch<Model>(u, p, is_free);
    estimate_valid_ = false;
    return usable(s) ? StepOutcome::applied : StepOutcome::rejected;
  }

  StepOutcome correct(const ScanInput& s) {
    if (!initialized_) return StepOutcome::rejected;
    if (scan_.prepare(s.layout, s.ranges, config_.beam_stride) != ScanStatus::ok) return StepOutcome::rejected;
    const ScanBeams beams = scan_.beams();
    const Pose2 mount = config_.sensor_mount;
    const LikelihoodField& field = field_;
    const CorrectionReport r =
        field_grid_ != nullptr && field_grid_->valid()
            ? mcl_.correct_batch([&](ConstParticleSetView v, float* out) {
                likelihood_field_range_finder_model_batch(beams, v.x, v.y, v.theta, v.count, mount, *field_grid_, out);
              })
            : mcl_.correct([&](const Pose2& x) { return likelihood_field_range_finder_model(beams, x, mount, field); });
    // The estimate of this step is the corrected set's, taken before resampling injects random particles.
    estimate_ = mcl_.cluster_estimate(config_.cluster_cell).strongest;
    estimate_valid_ = true;
    mcl_.resample(free_space_);
    return r.degenerate ? StepOutcome::degenerate : StepOutcome::applied;
  }

  // The strongest cluster: the mean of a multi-modal cloud would sit between the modes.
  PoseEstimate estimate() const {
    return estimate_valid_ ? estimate_ : mcl_.cluster_estimate(config_.cluster_cell).strongest;
  }

  const AugmentedMcl<NMax>& filter() const { return mcl_; }
  const ScanCounters& last_scan_counters() const { return scan_.counters(); }

 private:
  MclEstimatorConfig<Model> config_;
  AugmentedMcl<NMax> mcl_;
  const LikelihoodField& field_;
  const FreeSpaceSampler& free_space_;
  const LikelihoodFieldGrid* field_grid_;
  PreparedScan<KMax> scan_;
  PoseEstimate estimate_;
  bool estimate_valid_ = false;
  bool initialized_ = false;
};

}  // namespace est::loop

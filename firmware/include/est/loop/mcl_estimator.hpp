#pragma once
// The loop's Monte Carlo localization estimator: augmented MCL (est/filter/augmented_mcl.hpp) with any motion model
// of est/motion through its control assembler (est/loop/control_assemblers.hpp), map-conditioned prediction, a range
// model for the scans (est/loop/likelihood_field_scan.hpp, beam_scan.hpp, steered_scan.hpp) and recovery from free
// space. All storage is static: N_max particles and K_max beams are template parameters; the range model's map
// structures and the free space are owned by the caller and outlive the estimator.
// Prediction uses the whole-set sampler (est/motion/motion_batch.hpp: the model's distribution, vectorizable, for the
// models that have one; the others sample particle by particle). A range model whose particles carry modes (the
// handlebar's positions, est/loop/steered_scan.hpp) has each particle predicted with its own position's steering in
// place of the steering reading (a particle without a mode yet: the reading). Given a
// landmark map (MclEstimatorConfig::landmarks), landmark features correct the set too
// (est/loop/landmark_correction.hpp).
#include <cstdint>
#include <type_traits>
#include <utility>

#include "est/filter/augmented_mcl.hpp"
#include "est/filter/free_space_sampler.hpp"
#include "est/loop/control_assemblers.hpp"
#include "est/loop/filter_loop.hpp"
#include "est/loop/landmark_correction.hpp"
#include "est/loop/likelihood_field_scan.hpp"
#include "est/motion/motion_batch.hpp"
#include "est/sensor/range_scan.hpp"
#include "est/sensor/steered_range_finder.hpp"

namespace est::loop {

// Whether a range model's particles carry modes, each a steering for the predictions (est/loop/steered_scan.hpp).
template <typename ScanModel, typename = void>
struct CarriesSteeringModes : std::false_type {};
template <typename ScanModel>
struct CarriesSteeringModes<ScanModel, std::void_t<decltype(std::declval<const ScanModel&>().modes()),
                                                   decltype(std::declval<const ScanModel&>().alphas())>>
    : std::true_type {};

template <typename Model>
struct MclEstimatorConfig {
  MclConfig mcl{};
  typename Model::Params motion{};
  typename ControlAssembler<Model>::Config control{};
  std::int32_t beam_stride = 1; // use every s-th beam
  float cluster_cell = 1.0f;    // m, the grid of the strongest-cluster estimate
  // Landmark features correct the set as well as scans when a map is given (it outlives the estimator); without the
  // sensor's ids each particle takes its most likely landmark.
  LandmarkMap landmarks{};
  LandmarkNoise landmark_noise{};
  bool sensor_ids = true;
};

template <typename Model, std::uint32_t NMax, std::int32_t KMax, typename ScanModel = LikelihoodFieldScan>
class MclEstimator {
 public:
  using Assembler = ControlAssembler<Model>;

  MclEstimator(const MclEstimatorConfig<Model>& config, std::uint64_t seed, const ScanModel& scan_model,
               const FreeSpaceSampler& free_space)
      : config_(config), mcl_(config.mcl, seed), scan_model_(scan_model), free_space_(free_space) {}

  InputKinds inputs() const {
    const InputKinds k = Assembler::inputs(config_.control) | InputKind::scan;
    return config_.landmarks.size() > 0 ? k | InputKind::landmark : k;
  }

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

  StepOutcome predict(const MotionInput& in) {
    if (!initialized_) return StepOutcome::rejected;
    context_ = {in.steering_rad, in.steering_known};  // the reading, for the next correction
    typename Model::Params p = config_.motion;
    typename Model::Control u{};
    const ControlStatus c = Assembler::make(in, config_.control, p, u);
    if (c == ControlStatus::still) return StepOutcome::applied;  // standing still: no diffusion
    if (c == ControlStatus::rejected) return StepOutcome::rejected;
    const auto is_free = [this](float x, float y) { return free_space_.admissible_at(x, y); };
    if constexpr (CarriesSteeringModes<ScanModel>::value) {
      if (scan_model_.modes() > 0) return predict_by_mode(in, u, p, is_free);
    }
    const MotionStatus s = mcl_.template predict_in_map_batch<Model>(u, p, is_free);
    estimate_valid_ = false;
    return usable(s) ? StepOutcome::applied : StepOutcome::rejected;
  }

  StepOutcome correct(const ScanInput& s) {
    if (!initialized_) return StepOutcome::rejected;
    if (scan_.prepare(s.layout, s.ranges, config_.beam_stride) != ScanStatus::ok) return StepOutcome::rejected;
    const CorrectionReport r = scan_model_.correct(mcl_, scan_.beams(), context_);
    // The estimate of this step is the corrected set's, taken before resampling injects random particles.
    estimate_ = mcl_.cluster_estimate(config_.cluster_cell, by_mode()).strongest;
    estimate_valid_ = true;
    const bool resampled = mcl_.resample(free_space_);
    if constexpr (CarriesSteeringModes<ScanModel>::value) {
      if (resampled) scan_model_.split(mcl_);
    }
    return r.degenerate ? StepOutcome::degenerate : StepOutcome::applied;
  }

  StepOutcome correct(const LandmarkInput& z) {
    const LandmarkMap& map = config_.landmarks;
    if (!initialized_ || map.size() == 0) return StepOutcome::rejected;
    const std::int32_t id = config_.sensor_ids ? z.id : -1;
    if (id >= map.size()) return StepOutcome::rejected;
    const LandmarkMeasurement f{z.range_m, z.bearing_rad, z.signature};
    const CorrectionReport r = correct_with_landmark(mcl_, f, id, map, config_.landmark_noise);
    estimate_ = mcl_.cluster_estimate(config_.cluster_cell, by_mode()).strongest;
    estimate_valid_ = true;
    mcl_.resample(free_space_);
    return r.degenerate ? StepOutcome::degenerate : StepOutcome::applied;
  }

  // The strongest cluster: the mean of a multi-modal cloud would sit between the modes.
  PoseEstimate estimate() const {
    return estimate_valid_ ? estimate_ : mcl_.cluster_estimate(config_.cluster_cell, by_mode()).strongest;
  }

  const AugmentedMcl<NMax>& filter() const { return mcl_; }
  const ScanModel& scan_model() const { return scan_model_; }
  const ScanCounters& last_scan_counters() const { return scan_.counters(); }

 private:
  // Particles with modes: the estimate is the strongest cluster's heaviest mode (est/filter/particle_estimate.hpp).
  bool by_mode() const {
    if constexpr (CarriesSteeringModes<ScanModel>::value) return scan_model_.modes() > 0;
    return false;
  }

  // Each particle with its handle position's steering (u_m, p_m), one without a mode with the reading's (u, p).
  template <typename IsFree>
  StepOutcome predict_by_mode(const MotionInput& in, const typename Model::Control& u, const typename Model::Params& p,
                              const IsFree& is_free) {
    constexpr std::int32_t kMax = kMaxSteeringHypotheses;
    typename Model::Control us[kMax + 1];
    typename Model::Params ps[kMax + 1];
    const std::int32_t modes = scan_model_.modes() < kMax ? scan_model_.modes() : kMax;
    for (std::int32_t m = 0; m < modes; ++m) {
      MotionInput at = in;
      at.steering_rad = scan_model_.alphas()[m];
      at.steering_known = true;
      ps[m] = config_.motion;
      if (Assembler::make(at, config_.control, ps[m], us[m]) != ControlStatus::ok) return StepOutcome::rejected;
    }
    us[modes] = u;
    ps[modes] = p;
    const MotionStatus s =
        mcl_.template predict_in_map_by_mode<Model>(us, ps, static_cast<std::uint32_t>(modes), is_free);
    estimate_valid_ = false;
    return usable(s) ? StepOutcome::applied : StepOutcome::rejected;
  }

  MclEstimatorConfig<Model> config_;
  AugmentedMcl<NMax> mcl_;
  ScanModel scan_model_;
  const FreeSpaceSampler& free_space_;
  PreparedScan<KMax> scan_;
  ScanContext context_;
  PoseEstimate estimate_;
  bool estimate_valid_ = false;
  bool initialized_ = false;
};

}  // namespace est::loop

#pragma once
// The firmware's configuration in one static struct: the robot model, the filter (MCL, EKF or EKF-SLAM), MCL's range model,
// the capacities, and the loop's rates and staleness limits. ConfiguredLoop<Config> turns it into the estimator and
// loop types:
//
//   struct RigConfig {
//     using Model = est::BicycleMotionModel;                    // any model of est/motion (est/loop/controls/)
//     static constexpr est::loop::Filter kFilter = est::loop::Filter::mcl;
//     using ScanModel = est::loop::LikelihoodFieldScan;         // MCL only, optional (this is the default); or
//                                                               // BeamScan<Caster>, SteeredScan<...>
//     static constexpr std::uint32_t kMaxParticles = 2048;      // MCL only
//     static constexpr std::int32_t kMaxLandmarks = 32;         // EKF-SLAM only, optional (32): the map's capacity
//     static constexpr std::int32_t kMaxTentative = 32;         // EKF-SLAM only, optional (32): landmarks on trial
//     static constexpr std::int32_t kMaxBeams = 360;            // scan capacity (an EKF rig: 1, it drops scans)
//     static constexpr int kJointSightings = 8;                 // EKF only, optional (default 0: no joint
//                                                               // association compiled in, est/loop/ekf_estimator.hpp)
//     static constexpr std::uint32_t kQueueCapacity = 64;       // inputs pending within the reorder window
//     static constexpr std::uint32_t kScanSlots = 2;
//     static constexpr est::loop::LoopTiming kTiming{};         // 100 Hz predict, 20 ms window, staleness limits
//   };
//   using Rig = est::loop::ConfiguredLoop<RigConfig>;
//   Rig::Estimator estimator(estimator_config, seed, scan_model, free_space);   // or (config, landmark map): EKF
//                                                                               // or (config): EKF-SLAM
//   Rig::Loop loop(estimator, RigConfig::kTiming);
//
// Corrections run at the rate their inputs arrive (a scan or a landmark sighting each); predictions at
// kTiming.predict_period_ns of input time. The estimator's own parameters (noise, map) stay run-time values: they
// come from calibration, and the EKF's are Eigen matrices.
#include <cstdint>
#include <type_traits>

#include "est/loop/ekf_estimator.hpp"
#include "est/loop/ekf_slam_estimator.hpp"
#include "est/loop/filter_loop.hpp"
#include "est/loop/likelihood_field_scan.hpp"
#include "est/loop/mcl_estimator.hpp"
#include "est/loop/model_kinds.hpp"

namespace est::loop {


namespace detail {
template <typename Config, typename = void>
struct ScanModelOf {
  using type = LikelihoodFieldScan;
};
template <typename Config>
struct ScanModelOf<Config, std::void_t<typename Config::ScanModel>> {
  using type = typename Config::ScanModel;
};

template <typename Config, typename = void>
struct JointSightingsOf {
  static constexpr int value = 0;
};
template <typename Config>
struct JointSightingsOf<Config, std::void_t<decltype(Config::kJointSightings)>> {
  static constexpr int value = Config::kJointSightings;
};

template <typename Config, typename = void>
struct MaxLandmarksOf {
  static constexpr int value = 32;
};
template <typename Config>
struct MaxLandmarksOf<Config, std::void_t<decltype(Config::kMaxLandmarks)>> {
  static constexpr int value = Config::kMaxLandmarks;
};
template <typename Config, typename = void>
struct MaxTentativeOf {
  static constexpr int value = 32;
};
template <typename Config>
struct MaxTentativeOf<Config, std::void_t<decltype(Config::kMaxTentative)>> {
  static constexpr int value = Config::kMaxTentative;
};

template <typename Config, Filter F>
struct EstimatorOf;
template <typename Config>
struct EstimatorOf<Config, Filter::mcl> {
  using type = MclEstimator<typename Config::Model, Config::kMaxParticles, Config::kMaxBeams,
                            typename ScanModelOf<Config>::type>;
  using config = MclEstimatorConfig<typename Config::Model>;
};
template <typename Config>
struct EstimatorOf<Config, Filter::ekf> {  // kMaxParticles and ScanModel are not needed
  using type = EkfEstimator<typename Config::Model, JointSightingsOf<Config>::value>;
  using config = EkfEstimatorConfig<typename Config::Model>;
};
template <typename Config>
struct EstimatorOf<Config, Filter::ekf_slam> {
  using type = EkfSlamEstimator<typename Config::Model, MaxLandmarksOf<Config>::value, MaxTentativeOf<Config>::value>;
  using config = EkfSlamEstimatorConfig<typename Config::Model>;
};
}  // namespace detail

template <typename Config>
struct ConfiguredLoop {
  using Model = typename Config::Model;
  static constexpr Filter kFilter = Config::kFilter;
  static_assert(Config::kQueueCapacity >= 2u && Config::kMaxBeams > 0 && Config::kScanSlots >= 1u,
                "capacities must be positive");
  static_assert(Config::kTiming.predict_period_ns > 0 && Config::kTiming.reorder_window_ns >= 0,
                "the predict period must be positive and the reorder window not negative");

  using Estimator = typename detail::EstimatorOf<Config, kFilter>::type;
  using EstimatorConfig = typename detail::EstimatorOf<Config, kFilter>::config;
  using Loop = FilterLoopStorage<Estimator, Config::kQueueCapacity, Config::kMaxBeams, Config::kScanSlots>;
  static constexpr LoopTiming kTiming = Config::kTiming;
};

// A config struct from template arguments, for host programs that choose the model, the filter and the range model
// at run time among a few instantiations (estimator_node, sim_host) and pass their run-time timing to the loop.
template <typename RobotModel, Filter F, std::uint32_t MaxParticles, std::int32_t MaxBeams, std::uint32_t QueueCapacity,
          std::uint32_t ScanSlots, typename Range = LikelihoodFieldScan, int JointSightings = 0,
          std::int32_t MaxLandmarks = 32, std::int32_t MaxTentative = 32>
struct LoopConfig {
  using Model = RobotModel;
  using ScanModel = Range;
  static constexpr Filter kFilter = F;
  static constexpr std::uint32_t kMaxParticles = MaxParticles;
  static constexpr std::int32_t kMaxBeams = MaxBeams;
  static constexpr std::uint32_t kQueueCapacity = QueueCapacity;
  static constexpr std::uint32_t kScanSlots = ScanSlots;
  static constexpr int kJointSightings = JointSightings;
  static constexpr std::int32_t kMaxLandmarks = MaxLandmarks;
  static constexpr std::int32_t kMaxTentative = MaxTentative;
  static constexpr LoopTiming kTiming{};
};

}  // namespace est::loop

// The EKF-SLAM loop estimator (est/loop/ekf_slam_estimator.hpp) instantiated in full under the board's compiler and
// rules, at a board's capacities, through the configured loop as a board would state it: every member compiles for
// the Cortex-M4F (the header check only includes the header; no board image runs it yet). Compiled, not linked.
#include <cstdint>

#include "est/loop/configured_loop.hpp"
#include "est/motion/bicycle_model.hpp"

namespace {

struct SlamRigConfig {
  using Model = est::BicycleMotionModel;
  static constexpr est::loop::Filter kFilter = est::loop::Filter::ekf_slam;
  static constexpr std::int32_t kMaxLandmarks = 32;  // the covariance: 67 x 67 floats, 18 KB
  static constexpr std::int32_t kMaxTentative = 16;
  static constexpr std::uint32_t kMaxParticles = 1;
  static constexpr std::int32_t kMaxBeams = 1;
  static constexpr std::uint32_t kQueueCapacity = 32;
  static constexpr std::uint32_t kScanSlots = 1;
  static constexpr est::loop::LoopTiming kTiming{};
};
using Rig = est::loop::ConfiguredLoop<SlamRigConfig>;
static_assert(Rig::Estimator::kMaxLandmarks == 32 && Rig::Estimator::kMaxTentative == 16, "the rig's capacities");

}  // namespace

template class est::loop::EkfSlamEstimator<est::BicycleMotionModel, 32, 16>;
template class est::loop::FilterLoop<Rig::Estimator>;

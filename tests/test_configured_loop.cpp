// One static config struct selects the model, the filter, the capacities and the loop's rates
// (est/loop/configured_loop.hpp).
#include <catch2/catch.hpp>

#include <type_traits>

#include "est/loop/configured_loop.hpp"
#include "est/loop/steered_scan.hpp"
#include "est/motion/bicycle_model.hpp"
#include "est/motion/diff_drive_model.hpp"

namespace {

constexpr est::loop::TimeNs kMs = 1000000;

// Staleness limits in the table's order: wheel ticks, steering, twist, odometry, scan, landmark.
constexpr est::loop::StalenessLimits limits(est::loop::TimeNs landmark) {
  return est::loop::StalenessLimits{{100 * kMs, 100 * kMs, 100 * kMs, 100 * kMs, 500 * kMs, landmark}};
}

struct MclRig {
  using Model = est::BicycleMotionModel;
  static constexpr est::loop::Filter kFilter = est::loop::Filter::mcl;
  static constexpr std::uint32_t kMaxParticles = 512;
  static constexpr std::int32_t kMaxBeams = 60;
  static constexpr std::uint32_t kQueueCapacity = 32;
  static constexpr std::uint32_t kScanSlots = 2;
  static constexpr est::loop::LoopTiming kTiming{20 * kMs, 30 * kMs, limits(1000 * kMs), 5 * kMs, 100};
};

struct SteeredRig : MclRig {  // MCL's range model chosen by the config
  using ScanModel = est::loop::SteeredScan<512>;
};

struct EkfRig {  // no kMaxParticles: an EKF has none
  using Model = est::DiffDriveMotionModel;
  static constexpr est::loop::Filter kFilter = est::loop::Filter::ekf;
  static constexpr std::int32_t kMaxBeams = 1;
  static constexpr std::uint32_t kQueueCapacity = 64;
  static constexpr std::uint32_t kScanSlots = 1;
  static constexpr est::loop::LoopTiming kTiming{10 * kMs, 20 * kMs, limits(400 * kMs), 5 * kMs, 100};
};

struct JointEkfRig : EkfRig {  // joint association compiled in (est/loop/ekf_estimator.hpp)
  static constexpr int kJointSightings = 8;
};

using Mcl = est::loop::ConfiguredLoop<MclRig>;
using Steered = est::loop::ConfiguredLoop<SteeredRig>;
using Ekf = est::loop::ConfiguredLoop<EkfRig>;

static_assert(std::is_same_v<Mcl::Estimator,
                             est::loop::MclEstimator<est::BicycleMotionModel, 512, 60, est::loop::LikelihoodFieldScan>>);
static_assert(std::is_same_v<Steered::Estimator,
                             est::loop::MclEstimator<est::BicycleMotionModel, 512, 60, est::loop::SteeredScan<512>>>);
static_assert(std::is_same_v<Mcl::Loop, est::loop::FilterLoopStorage<Mcl::Estimator, 32, 60, 2>>);
static_assert(std::is_base_of_v<est::loop::FilterLoop<Mcl::Estimator>, Mcl::Loop>);
static_assert(std::is_same_v<Ekf::Estimator, est::loop::EkfEstimator<est::DiffDriveMotionModel>>);
static_assert(!Ekf::Estimator::kJointAssociation);  // without kJointSightings: no joint association in the type
static_assert(std::is_same_v<est::loop::ConfiguredLoop<JointEkfRig>::Estimator,
                             est::loop::EkfEstimator<est::DiffDriveMotionModel, 8>>);
static_assert(std::is_same_v<
              est::loop::ConfiguredLoop<est::loop::LoopConfig<est::DiffDriveMotionModel, est::loop::Filter::ekf, 0u, 1,
                                                              32u, 1u, est::loop::LikelihoodFieldScan, 8>>::Estimator,
              est::loop::EkfEstimator<est::DiffDriveMotionModel, 8>>);
static_assert(std::is_same_v<Ekf::EstimatorConfig, est::loop::EkfEstimatorConfig<est::DiffDriveMotionModel>>);
static_assert(std::is_same_v<Mcl::EstimatorConfig, est::loop::MclEstimatorConfig<est::BicycleMotionModel>>);
static_assert(Mcl::kTiming.staleness[est::loop::InputKind::landmark] == 1000 * kMs);
static_assert(Ekf::kTiming.staleness[est::loop::InputKind::landmark] == 400 * kMs);
// MCL corrects with scans, and with landmark features when its configuration has a landmark map.
static_assert(est::loop::CorrectsWith<Mcl::Estimator, est::loop::ScanInput>::value &&
              est::loop::CorrectsWith<Mcl::Estimator, est::loop::LandmarkInput>::value);
static_assert(!est::loop::CorrectsWith<Ekf::Estimator, est::loop::ScanInput>::value &&
              est::loop::CorrectsWith<Ekf::Estimator, est::loop::LandmarkInput>::value);

struct Outputs {
  std::vector<est::loop::TimeNs> times;
  std::vector<std::uint32_t> status;
  void operator()(const est::loop::LoopOutput& o) {
    times.push_back(o.t_ns);
    status.push_back(o.status);
  }
};
struct StepClock {
  est::loop::TimeNs t = 0;
  est::loop::TimeNs operator()() { return t += 1000; }
};

}  // namespace

TEST_CASE("the config struct's rates and staleness limits are the ones the loop runs with", "[configured_loop]") {
  const est::Landmark lm[1] = {{5.0f, 0.0f, 1.0f}};
  Ekf::EstimatorConfig c;
  c.motion.ticks_per_rev = 1024u;
  Ekf::Estimator estimator(c, est::LandmarkMap(lm, 1));
  REQUIRE(estimator.initialize_at({0.0f, 0.0f, 0.0f}, 0.1f, 0.05f));
  Ekf::Loop loop(estimator, Ekf::kTiming);
  CHECK(estimator.inputs() == (est::loop::InputKind::wheel_ticks | est::loop::InputKind::landmark));
  Outputs out;
  StepClock clock;
  float range[1] = {1.0f};
  for (int i = 0; i <= 100; ++i) {
    est::loop::WheelTicksInput w;
    w.t_ns = i * 5 * kMs;
    w.ticks[0] = w.ticks[1] = 2;
    w.wheel_count = 2;
    loop.push(w);  // 200 Hz encoders
    if (i == 10) loop.push(est::loop::LandmarkInput{i * 5 * kMs, 4.9f, 0.0f, 0.0f, 0});
    loop.push(est::loop::ScanInput{i * 5 * kMs + kMs, est::ScanLayout{0.0f, 0.1f, 1, 0.1f, 10.0f}, range});
    loop.run(clock, out);
  }
  loop.flush(clock, out);
  // 100 Hz predictions from EkfRig::kTiming: outputs at 10 ms steps over 0.5 s.
  REQUIRE(out.times.size() == 50u);
  for (std::size_t i = 0; i < out.times.size(); ++i) CHECK(out.times[i] == static_cast<est::loop::TimeNs>(i + 1) * 10 * kMs);
  CHECK(loop.counters().unused == 101u);  // scans: the EKF rig does not use them
  CHECK(loop.counters().corrections == 1u);
  // The 400 ms landmark limit: the sighting at 50 ms keeps the status clear up to 450 ms.
  CHECK((out.status[43] & est::loop::status::kLandmarkTimeout) == 0u);  // 440 ms
  CHECK((out.status[45] & est::loop::status::kLandmarkTimeout) != 0u);  // 460 ms
  CHECK((out.status[0] & est::loop::status::kLandmarkTimeout) != 0u);   // 10 ms, before any sighting
}

TEST_CASE("the MCL rig uses its model's motion inputs and scans; without a steering sensor the steering is unused",
          "[configured_loop]") {
  const est::LikelihoodField field;
  const est::FreeSpaceSampler free_space;
  Mcl::EstimatorConfig c;
  Mcl::Estimator with_steering(c, 1u, est::loop::LikelihoodFieldScan(field), free_space);
  CHECK(with_steering.inputs() ==
        (est::loop::InputKind::wheel_ticks | est::loop::InputKind::steering | est::loop::InputKind::scan));
  c.control.steering_fitted = false;
  Mcl::Estimator without(c, 1u, est::loop::LikelihoodFieldScan(field), free_space);
  CHECK(without.inputs() == (est::loop::InputKind::wheel_ticks | est::loop::InputKind::scan));
  Mcl::Loop loop(without, Mcl::kTiming);
  CHECK_FALSE(loop.push(est::loop::SteeringInput{0, 0.1f}));
  CHECK(loop.counters().unused == 1u);
  CHECK(loop.max_beams() == 60);
}

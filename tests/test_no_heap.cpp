#include <catch2/catch.hpp>
#include <Eigen/Core>
#include <cmath>
#include <memory>
#include <vector>

#include "est/filter/augmented_mcl.hpp"
#include "est/loop/ekf_estimator.hpp"
#include "est/loop/filter_loop.hpp"
#include "est/filter/free_space_sampler.hpp"
#include "est/filter/two_landmark_sampler.hpp"
#include "est/map/ray_casting.hpp"
#include "est/motion/bicycle_model.hpp"
#include "est/sensor/beam_range_finder_model.hpp"
#include "est/sensor/likelihood_field_grid.hpp"
#include "hal/can/can_input.hpp"
#include "hal/can/sample_frames.hpp"
#include "hal/pipeline.hpp"
#include "hal/sensors/range_scan/can_frames.hpp"
#include "heap_guard.hpp"
#include "selftest.hpp"

// Positive controls: the guard must see the heap uses it is meant to catch, or its zeros prove nothing.
TEST_CASE("heap guard counts std::vector, new and a dynamic Eigen matrix", "[heap]") {
  {
    est::test::HeapGuard guard;
    std::vector<int> v(3);
    CHECK(guard.allocations() == 1u);
  }
  {
    est::test::HeapGuard guard;
    auto p = std::make_unique<int>(7);
    CHECK(guard.allocations() == 1u);
  }
  {
    est::test::HeapGuard guard;
    Eigen::MatrixXf m(4, 4);
    m.setZero();
    CHECK(guard.allocations() == 1u);
  }
}

TEST_CASE("the whole self-test workload runs without touching the heap", "[heap]") {
  est::selftest::Result results[est::selftest::kMaxSections];
  est::test::HeapGuard guard;
  const int n = est::selftest::run_all(results);
  const auto count = guard.allocations();
  CHECK(n >= 2);
  CHECK(count == 0u);
}

TEST_CASE("each traced workload of the determinism suite runs without touching the heap", "[heap]") {
  // A first run outside the guard is the start-up (function statics are built); the second is watched.
  int n = 0;
  const est::selftest::Section* s = est::selftest::sections(n);
  int traced = 0;
  for (int i = 0; i < n; ++i) {
    if (s[i].trace == nullptr) continue;
    ++traced;
    (void)s[i].run();
    est::test::HeapGuard guard;
    const std::uint64_t digest = s[i].run();
    const auto count = guard.allocations();
    INFO(s[i].name << ": " << count << " allocations");
    CHECK(count == 0u);
    CHECK(digest == s[i].expected);
  }
  CHECK(traced >= 12);
}

namespace {
est::OccupancyGridStorage<80, 60> g_mcl_grid;
est::DistanceTransformStorage<80, 60> g_mcl_edt;
est::LikelihoodFieldGridStorage<80, 60> g_mcl_field_grid;
est::LikelihoodField g_mcl_field;
est::PreparedScan<60> g_mcl_scan;
est::LandmarkMapStorage<4> g_mcl_landmarks;
est::AugmentedMcl<2048> g_mcl(est::MclConfig{}, 1u);
}  // namespace

TEST_CASE("MCL steps (predict, both range models, landmarks, KLD resampling with injection) never touch the heap",
          "[heap]") {
  // Set-up (maps, transforms, tables) may run before the guard; the steps run under it.
  g_mcl_grid.configure(80, 60, 0.1f, 0.0f, 0.0f, est::kFreeCell);
  g_mcl_grid.fill_rect(0, 0, 79, 0, est::kOccupiedCell);
  g_mcl_grid.fill_rect(0, 59, 79, 59, est::kOccupiedCell);
  g_mcl_grid.fill_rect(0, 0, 0, 59, est::kOccupiedCell);
  g_mcl_grid.fill_rect(79, 0, 79, 59, est::kOccupiedCell);
  g_mcl_grid.fill_rect(30, 10, 35, 40, est::kOccupiedCell);
  const est::OccupancyGrid grid = g_mcl_grid.grid();
  REQUIRE(g_mcl_edt.build(grid) == est::MapStatus::ok);
  est::LikelihoodFieldParams lp;
  lp.range_max = 8.0f;
  REQUIRE(g_mcl_field.configure(lp, grid, g_mcl_edt.view()) == est::SensorModelStatus::ok);
  REQUIRE(g_mcl_field_grid.build(g_mcl_field, grid) == est::MapStatus::ok);
  est::BeamRangeFinderModel beam;
  est::BeamModelParams bp;
  bp.range_max = 8.0f;
  REQUIRE(beam.configure(bp) == est::SensorModelStatus::ok);
  g_mcl_landmarks.clear();
  g_mcl_landmarks.add({1.0f, 1.0f, 1.0f});
  g_mcl_landmarks.add({6.0f, 5.0f, 2.0f});
  const est::DistanceTransformRayCaster caster(grid, g_mcl_edt.view());
  const est::FreeSpaceSampler free_space(grid, g_mcl_edt.view(), 0.2f);
  const est::LandmarkNoise noise{0.05f, 0.02f, 0.0f};
  est::TwoLandmarkSampler<8> from_landmarks(g_mcl_landmarks.view(), noise);
  est::MclConfig cfg;
  cfg.kld = true;
  g_mcl = est::AugmentedMcl<2048>(cfg, 3u);
  const est::ScanLayout layout{-est::kPi, est::kTwoPi / 60.0f, 60, 0.05f, 8.0f};
  float ranges[60];
  for (int k = 0; k < 60; ++k) ranges[k] = 1.0f + 0.05f * static_cast<float>(k);
  const auto is_free = [&grid](float x, float y) {
    std::int32_t cx = 0, cy = 0;
    return grid.world_to_cell(x, y, cx, cy) && grid.classify(cx, cy) == est::CellClass::free;
  };
  est::BicycleParams bike;
  bike.steer_sigma = 0.05f;
  bike.speed_var_per_speed = 0.01f;
  bike.final_rot_sigma = 0.01f;
  const est::Pose2 truth{5.0f, 3.0f, 0.5f};

  est::test::HeapGuard guard;
  g_mcl.initialize_global(free_space, 2048);
  float checksum = 0.0f;
  for (int t = 0; t < 6; ++t) {
    g_mcl.predict_in_map<est::BicycleMotionModel>({0.5f, 0.1f}, bike, is_free);
    g_mcl_scan.prepare(layout, ranges);
    const est::ScanBeams z = g_mcl_scan.beams();
    const est::LikelihoodFieldGrid field = g_mcl_field_grid.view();
    g_mcl.correct_batch([&](est::ConstParticleSetView p, float* out) {
      est::likelihood_field_range_finder_model_batch(z, p.x, p.y, p.theta, p.count, {}, field, out);
    });
    g_mcl.correct([&](const est::Pose2& x) { return est::beam_range_finder_model(z, x, {}, caster, beam); });
    from_landmarks.clear();
    for (std::int32_t j = 0; j < 2; ++j)
      from_landmarks.add(est::expected_landmark_measurement(truth, g_mcl_landmarks.view()[j]), j);
    g_mcl.correct([&](const est::Pose2& x) {
      return est::landmark_model_known_correspondence(
          est::expected_landmark_measurement(truth, g_mcl_landmarks.view()[0]), 0, x, g_mcl_landmarks.view(), noise);
    });
    g_mcl.resample([&](est::Rng& rng, est::Pose2& p) { return from_landmarks(rng, p) || free_space(rng, p); }, true);
    checksum += g_mcl.cluster_estimate().strongest.mean.x;
  }
  const auto count = guard.allocations();
  CHECK(count == 0u);
  CHECK(std::isfinite(checksum));
  CHECK(g_mcl.counters().resamplings == 6u);
}

namespace {
struct NoClock final : hal::Clock {
  hal::TimeNs now = 0;
  hal::TimeNs now_ns() override { return now; }
};
struct NoSink final : hal::EstimateSink {
  std::uint32_t n = 0;
  float x = 0.0f;
  void publish(const hal::Estimate& e) override {
    ++n;
    x += e.pose.x;
  }
};
using NoHeapEkf = est::loop::EkfEstimator<est::DiffDriveMotionModel>;
const est::Landmark g_posts[2] = {{3.0f, 0.0f, 1.0f}, {0.0f, 3.0f, 2.0f}};
NoHeapEkf g_ekf(est::loop::EkfEstimatorConfig<est::DiffDriveMotionModel>{}, est::LandmarkMap(g_posts, 2));
est::loop::FilterLoopStorage<NoHeapEkf, 64, 8, 1> g_loop(g_ekf, est::loop::LoopTiming{});
NoClock g_clock;
NoSink g_sink;
hal::Pipeline<NoHeapEkf> g_pipeline(g_loop, hal::InputLimits{}, g_clock, g_clock, g_sink);
hal::can::ScanReassembler<8> g_scans;
hal::can::CanInput g_can(g_scans, g_pipeline.input());
hal::can::SampleFrames g_frames;
}  // namespace

TEST_CASE("the CAN receive path, the HAL pipeline and the loop handle every sensor's samples without the heap",
          "[heap]") {
  REQUIRE(g_ekf.initialize_at({1.0f, 1.0f, 0.0f}, 0.1f, 0.05f));
  hal::can::CanFrame frames[4];
  const float ranges[4] = {1.0f, 2.0f, 3.0f, 4.0f};
  const hal::LandmarkFeature features[2] = {{2.2f, -0.46f, 1.0f, 0}, {2.2f, 2.0f, 2.0f, -1}};
  est::test::HeapGuard guard;
  for (int k = 0; k < 100; ++k) {
    const hal::TimeNs t = k * 10 * hal::kNsPerMs;
    g_clock.now = t;
    hal::WheelTicks w;
    w.stamp_ns = t;
    w.wheel_count = 2;
    w.count[0] = static_cast<std::uint32_t>(3 * k);
    w.count[1] = static_cast<std::uint32_t>(4 * k);
    // Encoders, steering, twist and odometry over the bus; scans and sightings straight into the gate.
    std::size_t n = g_frames.encode(w, frames, 4);
    for (std::size_t i = 0; i < n; ++i) g_can.on_frame(frames[i], t);
    n = g_frames.encode(hal::SteeringSample{t, 0.01f}, frames, 4);
    for (std::size_t i = 0; i < n; ++i) g_can.on_frame(frames[i], t);
    n = g_frames.encode(hal::TwistSample{t, 0.2f, 0.0f, 0.1f}, frames, 4);
    for (std::size_t i = 0; i < n; ++i) g_can.on_frame(frames[i], t);
    hal::OdometrySample o;
    o.stamp_ns = t;
    o.pose = {0.002f * static_cast<float>(k), 0.0f, 0.0f};
    n = g_frames.encode(o, frames, 4);
    for (std::size_t i = 0; i < n; ++i) g_can.on_frame(frames[i], t);
    if (k % 10 == 5) g_pipeline.input().on(hal::RangeScanView{t, {0.0f, 0.1f, 0.1f, 10.0f, 0.1f}, ranges, 4});
    if (k % 20 == 10) g_pipeline.input().on(hal::LandmarkSightingView{t, features, 2});
    g_pipeline.refresh(0, g_can.rejects().total());
  }
  g_pipeline.flush();
  const auto count = guard.allocations();
  CHECK(count == 0u);
  CHECK(g_sink.n > 90u);
  CHECK(std::isfinite(g_sink.x));
  CHECK(g_loop.counters().of(est::loop::InputKind::wheel_ticks).accepted == 100u);
  CHECK(g_loop.counters().of(est::loop::InputKind::landmark).accepted == 10u);
  CHECK(g_loop.counters().unused > 0u);  // steering, twist, odometry, scans: not this EKF's
}

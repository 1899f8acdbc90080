// The loop's EKF-SLAM estimator (est/loop/ekf_slam_estimator.hpp): gated maximum-likelihood association with its two
// gates, tentative landmarks confirmed or forgotten, the capacities refused and counted, every feature in exactly
// one counter, and a drive among unknown landmarks behind the FilterLoop, the same bits twice.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include "est/loop/ekf_slam_estimator.hpp"
#include "est/loop/filter_loop.hpp"
#include "est/motion/diff_drive_model.hpp"
#include "est/random/samplers.hpp"

namespace {

using est::loop::StepOutcome;
using est::loop::TimeNs;
using Model = est::DiffDriveMotionModel;
constexpr TimeNs kMs = 1000000;

est::loop::EkfSlamEstimatorConfig<Model> config() {
  est::loop::EkfSlamEstimatorConfig<Model> c;
  c.motion.wheel_radius = 0.05f;
  c.motion.track_width = 0.3f;
  c.motion.ticks_per_rev = 1024u;
  c.motion.travel_sigma_per_m = 0.05f;
  c.motion.travel_sigma_floor = 0.0005f;
  c.motion.final_rot_sigma = 0.002f;
  c.noise = {0.5f, 0.05f, 0.0f};
  return c;
}

est::loop::LandmarkInput feature(TimeNs t, float range, float bearing, float signature = 0.3f) {
  est::loop::LandmarkInput z;
  z.t_ns = t;
  z.range_m = range;
  z.bearing_rad = bearing;
  z.signature = signature;
  return z;
}

template <typename Estimator>
void start(Estimator& e) {
  REQUIRE(e.initialize_at({0.0f, 0.0f, 0.0f}, 0.01f, 0.01f));
}

// One landmark mapped 10 m ahead: seen in frames 1 and 2 (tentative, then confirmed).
template <typename Estimator>
void map_one(Estimator& e) {
  start(e);
  CHECK(e.correct(feature(1, 10.0f, 0.0f)) == StepOutcome::applied);
  CHECK(e.landmarks() == 0);
  CHECK(e.counters().tentative == 1u);
  CHECK(e.correct(feature(2, 10.0f, 0.0f)) == StepOutcome::applied);
  REQUIRE(e.landmarks() == 1);
  CHECK(e.counters().created == 1u);
}

}  // namespace

TEST_CASE("a feature with no landmark is tentative, confirmed by a second frame, then associated", "[ekf_slam]") {
  est::loop::EkfSlamEstimator<Model, 8, 4> e(config());
  map_one(e);
  CHECK(e.landmark(0).x() == Approx(10.0f).margin(1e-4));
  CHECK(e.landmark(0).y() == Approx(0.0f).margin(1e-4));
  CHECK(e.tentative_landmarks() == 0);
  // The same frame may not use a landmark twice: a second feature there in frame 2 would have been a new one.
  CHECK(e.correct(feature(3, 10.3f, 0.01f, 0.5f)) == StepOutcome::applied);
  CHECK(e.counters().associated == 1u);
  CHECK(e.landmarks() == 1);
  CHECK(e.landmark_signature(0) == Approx(0.4f));  // the mean of 0.3 and 0.5
  CHECK(e.counters().frames == 3u);
}

TEST_CASE("the two gates: associated under gate_accept, discarded between, a new candidate above gate_new",
          "[ekf_slam]") {
  // The mapped landmark's range variance is the sensor's 0.25 m^2 (inserted from one feature), the feature's another
  // 0.25: S_rr = 0.5 (the robot's 1e-4 aside), so a range innovation d gives d^2 / 0.5.
  const struct {
    float innovation_m;
    const char* counter;
  } cases[] = {{1.0f, "associated"}, {2.74f, "discarded"}, {5.0f, "tentative"}};  // d^2 2, 15, 50
  for (const auto& c : cases) {
    INFO(c.counter);
    est::loop::EkfSlamEstimator<Model, 8, 4> e(config());
    map_one(e);
    const est::loop::SlamAssociationCounters before = e.counters();
    CHECK(e.correct(feature(3, 10.0f + c.innovation_m, 0.0f)) == StepOutcome::applied);
    const est::loop::SlamAssociationCounters& after = e.counters();
    CHECK(after.associated - before.associated == (std::strcmp(c.counter, "associated") == 0 ? 1u : 0u));
    CHECK(after.discarded - before.discarded == (std::strcmp(c.counter, "discarded") == 0 ? 1u : 0u));
    CHECK(after.tentative - before.tentative == (std::strcmp(c.counter, "tentative") == 0 ? 1u : 0u));
    CHECK(e.landmarks() == 1);
  }
}

TEST_CASE("a tentative landmark unseen for candidate_scans frames is forgotten and counted", "[ekf_slam]") {
  auto c = config();
  c.candidate_scans = 2;
  est::loop::EkfSlamEstimator<Model, 8, 4> e(c);
  start(e);
  e.correct(feature(1, 10.0f, 0.0f));
  CHECK(e.tentative_landmarks() == 1);
  for (TimeNs t = 2; t <= 3; ++t) CHECK(e.correct(feature(t, 40.0f, 0.0f)) == StepOutcome::applied);  // beyond range
  CHECK(e.counters().beyond_range == 2u);
  CHECK(e.tentative_landmarks() == 1);  // frame 3: unseen for 2 frames, kept
  e.correct(feature(4, 10.0f, 0.0f));   // frame 4: forgotten first, so this one starts afresh
  CHECK(e.counters().tentative_forgotten == 1u);
  CHECK(e.landmarks() == 0);
  CHECK(e.tentative_landmarks() == 1);
  CHECK(e.counters().tentative == 2u);
}

TEST_CASE("sightings of one frame never confirm each other", "[ekf_slam]") {
  est::loop::EkfSlamEstimator<Model, 8, 4> e(config());
  start(e);
  e.correct(feature(1, 10.0f, 0.0f));
  e.correct(feature(1, 10.2f, 0.0f));  // the same frame: a second tentative landmark, not a confirmation
  CHECK(e.landmarks() == 0);
  CHECK(e.tentative_landmarks() == 2);
}

TEST_CASE("the map's and the tentative table's capacities refuse and count, and every feature lands in one counter",
          "[ekf_slam]") {
  SECTION("map full") {
    auto c = config();
    c.confirm_sightings = 1;  // at once
    est::loop::EkfSlamEstimator<Model, 2, 4> e(c);
    start(e);
    CHECK(e.correct(feature(1, 10.0f, 0.0f)) == StepOutcome::applied);
    CHECK(e.correct(feature(1, 10.0f, 1.5f)) == StepOutcome::applied);
    CHECK(e.correct(feature(1, 10.0f, -1.5f)) == StepOutcome::rejected);
    CHECK(e.landmarks() == 2);
    CHECK(e.counters().created == 2u);
    CHECK(e.counters().map_full == 1u);
    CHECK(e.counters().features() == 3u);
  }
  SECTION("tentative table full") {
    est::loop::EkfSlamEstimator<Model, 8, 2> e(config());
    start(e);
    CHECK(e.correct(feature(1, 10.0f, 0.0f)) == StepOutcome::applied);
    CHECK(e.correct(feature(1, 10.0f, 1.5f)) == StepOutcome::applied);
    CHECK(e.correct(feature(1, 10.0f, -1.5f)) == StepOutcome::rejected);
    CHECK(e.counters().tentative == 2u);
    CHECK(e.counters().tentative_full == 1u);
    CHECK(e.counters().features() == 3u);
  }
  SECTION("not finite, or before initialization: refused, the belief kept finite") {
    est::loop::EkfSlamEstimator<Model, 8, 4> e(config());
    CHECK(e.correct(feature(1, 10.0f, 0.0f)) == StepOutcome::rejected);  // not initialized
    CHECK(e.counters().bad_input == 1u);
    start(e);  // counts afresh
    CHECK(e.correct(feature(2, std::numeric_limits<float>::quiet_NaN(), 0.0f)) == StepOutcome::rejected);
    CHECK(e.correct(feature(2, 10.0f, std::numeric_limits<float>::infinity())) == StepOutcome::rejected);
    CHECK(e.correct(feature(2, -1.0f, 0.0f)) == StepOutcome::rejected);
    CHECK(e.counters().bad_input == 3u);
    CHECK(e.counters().features() == 3u);
    const est::PoseEstimate p = e.estimate();
    CHECK(std::isfinite(p.mean.x));
    CHECK(p.covariance.allFinite());
  }
}

namespace {

struct StepClock {
  TimeNs t = 0;
  TimeNs operator()() { return t += 1000; }
};

struct Outputs {
  std::vector<est::loop::LoopOutput> all;
  void operator()(const est::loop::LoopOutput& o) { all.push_back(o); }
};

constexpr float kTrees[10][2] = {{0.0f, 0.0f}, {6.0f, 0.0f}, {6.0f, 6.0f}, {0.0f, 6.0f}, {3.0f, -1.5f},
                                 {7.5f, 3.0f}, {3.0f, 7.5f}, {-1.5f, 3.0f}, {3.0f, 3.0f}, {9.0f, 9.0f}};

using Estimator = est::loop::EkfSlamEstimator<Model, 16, 8>;
using Loop = est::loop::FilterLoopStorage<Estimator, 64, 1, 1>;

struct DriveResult {
  Outputs out;
  est::Pose2 truth;
  std::vector<Eigen::Vector2f> map;
  est::loop::SlamAssociationCounters counters;
  std::uint32_t features = 0;
};

// 60 s of a circle among the trees: ticks at 100 Hz, the truth sampled by the model, every tree within 6 m seen at
// 5 Hz with range / bearing noise and no identity; the filter starts at the true pose.
void drive(std::uint64_t seed, DriveResult& r) {
  const auto c = config();
  Estimator e(c);
  Loop loop(e, est::loop::LoopTiming{});
  est::Rng rng(seed);
  est::Pose2 truth{3.0f, 1.0f, 0.0f};
  REQUIRE(e.initialize_at(truth, 0.01f, 0.01f));
  StepClock clock;
  const float m_per_tick = est::diff_drive_m_per_tick(c.motion);
  est::loop::WheelTicksInput t0;
  t0.wheel_count = 2;
  loop.push(t0);
  for (int k = 1; k <= 6000; ++k) {
    const float v = 0.6f, w = 0.3f, dt = 0.01f;
    est::loop::WheelTicksInput in;
    in.t_ns = k * 10 * kMs;
    in.wheel_count = 2;
    in.ticks[0] = static_cast<std::int32_t>(std::lround((v - 0.5f * w * c.motion.track_width) * dt / m_per_tick));
    in.ticks[1] = static_cast<std::int32_t>(std::lround((v + 0.5f * w * c.motion.track_width) * dt / m_per_tick));
    truth = Model::sample(truth, {in.ticks[0], in.ticks[1]}, c.motion, rng);
    loop.push(in);
    if (k % 20 == 0) {
      for (const auto& tree : kTrees) {
        const float dx = tree[0] - truth.x, dy = tree[1] - truth.y;
        if (std::hypot(dx, dy) > 6.0f) continue;
        est::loop::LandmarkInput z;
        z.t_ns = k * 10 * kMs;
        z.range_m = std::hypot(dx, dy) + est::sample_normal(rng, 0.05f);
        z.bearing_rad = est::fmath::normalize_angle(std::atan2(dy, dx) - truth.theta + est::sample_normal(rng, 0.01f));
        z.signature = 0.3f;
        loop.push(z);
        ++r.features;
      }
    }
    loop.run(clock, r.out);
  }
  loop.flush(clock, r.out);
  r.truth = truth;
  for (int k = 0; k < e.landmarks(); ++k) r.map.push_back(e.landmark(k));
  r.counters = e.counters();
}

}  // namespace

TEST_CASE("a drive among unknown trees: each mapped once, the pose tracked, the same bits twice", "[ekf_slam]") {
  DriveResult a, b;
  drive(7, a);
  drive(7, b);
  REQUIRE(a.out.all.size() == b.out.all.size());
  for (std::size_t i = 0; i < a.out.all.size(); ++i) {
    const est::PoseEstimate &p = a.out.all[i].estimate, &q = b.out.all[i].estimate;
    REQUIRE(std::memcmp(&p.mean, &q.mean, sizeof p.mean) == 0);
    REQUIRE(std::memcmp(p.covariance.data(), q.covariance.data(), 9 * sizeof(float)) == 0);
  }
  // The circle (radius 2 m about (3, 3)) passes within 6 m of every tree but (9, 9) (about 6.2 m at best).
  CHECK(a.map.size() == 9u);
  for (const Eigen::Vector2f& m : a.map) {
    float nearest = 1e9f;
    for (const auto& tree : kTrees) nearest = std::fmin(nearest, std::hypot(m.x() - tree[0], m.y() - tree[1]));
    CHECK(nearest < 0.3f);
  }
  const est::Pose2& x = a.out.all.back().estimate.mean;
  CHECK(std::hypot(x.x - a.truth.x, x.y - a.truth.y) < 0.3f);
  CHECK(a.counters.features() == a.features);
  CHECK(a.counters.associated > a.features * 9u / 10u);
  CHECK(a.counters.map_full + a.counters.tentative_full + a.counters.update_refused + a.counters.bad_input == 0u);
}

// The three-robot particle filter that resolves which robot it sees (est/team/anonymous_team_mcl.hpp): the belief
// over the 3! tag assignments goes to the true one whatever the mapping, every robot localizes from a uniform start,
// a pair the sensor cannot tell apart keeps the steps ambiguous, lost robots do not correct each other, malformed
// sightings are refused and counted, and a seed gives the same bits.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <vector>

#include "est/team/anonymous_team_mcl.hpp"

namespace {

using est::DiffDriveControl;
using est::Landmark;
using est::LandmarkMeasurement;
using est::Pose2;
using est::Rng;
using est::team::AnonymousTeamMcl;
using est::team::AnonymousTeamMclConfig;
using est::team::RobotSighting;

constexpr int kN = 3;
#if defined(__SANITIZE_ADDRESS__)
constexpr std::uint32_t kParticles = 500;  // the sanitizers are slower (even at -O1); the bounds stay the same
#else
constexpr std::uint32_t kParticles = 1000;
#endif
constexpr int kLocalizeSteps = 400, kRepeatSteps = 120;
using Filter = AnonymousTeamMcl<kN, kParticles>;

constexpr float kDt = 0.1f;     // s, one step
constexpr float kReach = 6.0f;  // m, landmarks and robots

// A 20 m x 15 m field with twelve landmarks (signatures 1..12), irregular so that no two places look alike.
const Landmark kLandmarks[] = {{2.0f, 2.5f, 1.0f},   {7.5f, 1.5f, 2.0f},   {13.0f, 2.0f, 3.0f}, {18.0f, 3.0f, 4.0f},
                               {3.0f, 7.0f, 5.0f},   {9.0f, 6.0f, 6.0f},   {12.5f, 9.0f, 7.0f}, {17.5f, 8.0f, 8.0f},
                               {1.5f, 12.5f, 9.0f},  {6.5f, 13.0f, 10.0f}, {11.0f, 13.5f, 11.0f},
                               {16.0f, 12.0f, 12.0f}};

est::LandmarkMap landmark_map() { return est::LandmarkMap(kLandmarks, 12); }

AnonymousTeamMclConfig filter_config() {
  AnonymousTeamMclConfig c;
  c.motion.travel_sigma_per_m = 0.05f;
  c.motion.travel_sigma_floor = 0.002f;
  c.motion.final_rot_sigma = 0.01f;
  c.landmark_noise = {0.1f, 0.05f, 0.1f};
  c.sighting_sigma_range = 0.1f;
  c.sighting_sigma_bearing = 0.05f;
  c.sighting_reach_m = kReach;
  return c;
}

// Three robots on circles (v, w held), the sensor of table 6.4 on landmarks and on each other (anonymous tags).
struct World {
  Pose2 truth[kN];
  float v[kN];
  float w[kN];
  std::int32_t robot_of_tag[kN];
  std::int32_t tag_of_robot[kN];
  bool robots_see[kN] = {true, true, true};
  est::LandmarkMap map = landmark_map();
  est::DiffDriveParams motion;  // the world's slip, below the filter's
  est::LandmarkNoise noise{0.05f, 0.02f, 0.1f};
  Rng rng;

  World(int true_hypothesis, std::uint64_t seed) : rng(seed) {
    // Robot 0 around (6, 7.5), robot 1 around (14, 7.5) the other way, robot 2 around both.
    truth[0] = {6.0f, 4.0f, 0.0f};
    truth[1] = {14.0f, 11.0f, 0.0f};
    truth[2] = {10.0f, 2.0f, 0.0f};
    v[0] = v[1] = v[2] = 0.5f;
    w[0] = 0.5f / 3.5f;
    w[1] = -0.5f / 3.5f;
    w[2] = 0.5f / 5.5f;
    motion.travel_sigma_per_m = 0.02f;
    motion.travel_sigma_floor = 0.001f;
    motion.final_rot_sigma = 0.003f;
    const est::PermutationBelief<kN> table;
    for (int t = 0; t < kN; ++t) {
      robot_of_tag[t] = table.robot_of(true_hypothesis, t);
      tag_of_robot[robot_of_tag[t]] = t;
    }
  }

  // One step: the robots move, the encoders report ticks.
  void move(DiffDriveControl (&u)[kN]) {
    const float m_per_tick = est::diff_drive_m_per_tick(motion);
    for (int r = 0; r < kN; ++r) {
      const float half = 0.5f * w[r] * motion.track_width;
      u[r].left_ticks = static_cast<std::int32_t>(std::lround((v[r] - half) * kDt / m_per_tick));
      u[r].right_ticks = static_cast<std::int32_t>(std::lround((v[r] + half) * kDt / m_per_tick));
      if (v[r] == 0.0f && w[r] == 0.0f) continue;
      truth[r] = est::sample_motion_model_diff_drive(est::wheel_travel_from_ticks(u[r], motion), truth[r], motion, rng);
    }
  }

  std::vector<LandmarkMeasurement> landmarks(int r) {
    std::vector<LandmarkMeasurement> out;
    for (std::int32_t j = 0; j < map.size(); ++j)
      if (est::expected_landmark_measurement(truth[r], map[j]).range <= kReach)
        out.push_back(est::sample_landmark_measurement(truth[r], map[j], noise, rng));
    return out;
  }

  std::vector<RobotSighting> sightings() {
    std::vector<RobotSighting> out;
    for (int i = 0; i < kN; ++i) {
      if (!robots_see[i]) continue;
      for (int j = 0; j < kN; ++j) {
        if (j == i) continue;
        const LandmarkMeasurement e = est::expected_landmark_measurement(truth[i], {truth[j].x, truth[j].y, 0.0f});
        if (e.range > kReach) continue;
        RobotSighting s;
        s.observer = i;
        s.tag = tag_of_robot[j];
        s.z.range_m = e.range + est::sample_normal(rng, noise.sigma_range);
        s.z.bearing_rad = est::fmath::normalize_angle(e.bearing + est::sample_normal(rng, noise.sigma_bearing));
        out.push_back(s);
      }
    }
    return out;
  }

  // One whole step of the filter.
  void step(Filter& f) {
    DiffDriveControl u[kN];
    move(u);
    for (int r = 0; r < kN; ++r) REQUIRE(f.predict(r, u[r]));
    for (int r = 0; r < kN; ++r) {
      const std::vector<LandmarkMeasurement> z = landmarks(r);
      f.correct_landmarks(r, z.data(), static_cast<std::int32_t>(z.size()));
    }
    const std::vector<RobotSighting> s = sightings();
    f.correct_sightings(s.data(), static_cast<std::int32_t>(s.size()));
  }

  float error(const Filter& f, int r) const {
    const Pose2& m = f.estimate(r).mean;
    return std::hypot(m.x - truth[r].x, m.y - truth[r].y);
  }
};

std::unique_ptr<Filter> make_filter(std::uint64_t seed, const est::LandmarkMap& map = landmark_map()) {
  return std::make_unique<Filter>(filter_config(), map, seed);
}

}  // namespace

TEST_CASE("the belief goes to the true tag assignment within 30 s, for each of the six mappings") {
  constexpr int kSteps = 300;  // 30 s
  for (int h = 0; h < Filter::kHypotheses; ++h) {
    CAPTURE(h);
    World world(h, 100u + static_cast<std::uint64_t>(h));
    auto f = make_filter(7u + static_cast<std::uint64_t>(h));
    for (int k = 0; k < kSteps; ++k) world.step(*f);
    CHECK(f->hypothesis_of(world.robot_of_tag) == h);
    CHECK(f->probability_of(world.robot_of_tag) > 0.95f);
    CHECK(f->belief().most_probable() == h);
    CHECK(f->counters().corrections_applied > 0u);
    CHECK(f->counters().sighting_steps > 0u);
  }
}

TEST_CASE("every robot localizes globally from a uniform start: within 0.3 m after 15 s, and stays there") {
  World world(3, 21u);
  auto f = make_filter(5u);
  for (int r = 0; r < kN; ++r) CHECK_FALSE(f->estimate(r).localized);
  float worst_after = 0.0f;
  for (int k = 1; k <= kLocalizeSteps; ++k) {
    world.step(*f);
    if (k >= 150)
      for (int r = 0; r < kN; ++r) {
        CHECK(f->estimate(r).localized);
        worst_after = std::max(worst_after, world.error(*f, r));
      }
  }
  CHECK(worst_after < 0.3f);
}

TEST_CASE("a lost robot midway between two localized robots placed symmetrically: every step ambiguous") {
  // A field mirror-symmetric about x = 10 (signatures tell the sides apart). Robot 0 stands at the centre with no
  // landmark in reach, robots 1 and 2 stand 4 m to either side (8 m apart: out of each other's reach) among
  // landmarks. Robot 0 sees two tags at the same range, and it cannot know its heading: either pairing fits.
  static const Landmark kMirror[] = {{2.0f, 7.5f, 1.0f},  {2.5f, 4.0f, 2.0f},  {2.5f, 11.0f, 3.0f},
                                     {18.0f, 7.5f, 4.0f}, {17.5f, 4.0f, 5.0f}, {17.5f, 11.0f, 6.0f}};
  const est::LandmarkMap mirror(kMirror, 6);
  World world(4, 33u);
  world.map = mirror;
  world.truth[0] = {10.0f, 7.5f, 0.7f};
  world.truth[1] = {6.0f, 7.5f, 0.0f};
  world.truth[2] = {14.0f, 7.5f, 3.0f};
  for (int r = 0; r < kN; ++r) world.v[r] = world.w[r] = 0.0f;
  auto f = make_filter(9u, mirror);
  for (int k = 0; k < 200; ++k) world.step(*f);
  CHECK_FALSE(f->estimate(0).localized);
  CHECK(f->estimate(1).localized);
  CHECK(f->estimate(2).localized);
  const auto& c = f->counters();
  CHECK(c.sighting_steps == 200u);
  CHECK(c.ambiguous_steps == c.sighting_steps);
  CHECK(c.corrections_applied == 0u);
  // Robots 1 and 2 both see robot 0's tag, so it names robot 0; between the other two the belief stays split.
  std::int32_t swapped[kN];
  for (int t = 0; t < kN; ++t) swapped[t] = world.robot_of_tag[t] == 0 ? 0 : 3 - world.robot_of_tag[t];
  const float p_true = f->probability_of(world.robot_of_tag), p_swapped = f->probability_of(swapped);
  CHECK(p_true + p_swapped > 0.95f);
  CHECK(p_true < 0.9f);
  CHECK(p_swapped < 0.9f);
}

TEST_CASE("two lost robots do not make each other confident (no landmarks: corrections refused)") {
  World world(2, 44u);
  const est::LandmarkMap empty(kLandmarks, 0);
  world.map = empty;
  auto f = make_filter(11u, empty);
  for (int k = 0; k < 200; ++k) world.step(*f);
  const auto& c = f->counters();
  CHECK(c.sightings > 0u);
  CHECK(c.corrections_applied == 0u);
  CHECK(c.corrections_unlocalized > 0u);
  for (int r = 0; r < kN; ++r) CHECK_FALSE(f->estimate(r).localized);
}

TEST_CASE("non-finite and malformed sightings are refused, counted, and change nothing") {
  auto f = make_filter(3u);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  RobotSighting bad[6];
  bad[0].z.range_m = nan;
  bad[1].z.range_m = 2.0f;
  bad[1].z.bearing_rad = inf;
  bad[2].z.range_m = 2.0f;
  bad[2].tag = 3;  // no such tag
  bad[3].z.range_m = 2.0f;
  bad[3].observer = -1;
  bad[4].z.range_m = 2.0f;
  bad[4].z.id = 1;  // not anonymous
  bad[5].z.range_m = -1.0f;
  float before[Filter::kHypotheses];
  for (int h = 0; h < Filter::kHypotheses; ++h) before[h] = f->probability(h);
  CHECK(f->correct_sightings(bad, 6) == 0);
  CHECK(f->counters().rejected_sightings == 6u);
  CHECK(f->counters().sighting_steps == 0u);
  for (int h = 0; h < Filter::kHypotheses; ++h) CHECK(f->probability(h) == before[h]);
  const LandmarkMeasurement lm[2] = {{nan, 0.0f, 1.0f}, {3.0f, 0.1f, 40.0f}};
  CHECK(f->correct_landmarks(0, lm, 2) == 0);
  CHECK(f->counters().rejected_landmarks == 1u);
  CHECK(f->counters().unknown_landmarks == 1u);
  CHECK_FALSE(f->predict(0, DiffDriveControl{DiffDriveControl::kMaxTicks + 1, 0}));
  CHECK(f->counters().rejected_controls == 1u);
  for (int r = 0; r < kN; ++r) CHECK(f->estimate(r).mean.is_finite());
}

TEST_CASE("the same seed gives bit-identical estimates and beliefs, another seed other ones") {
  auto run = [](std::uint64_t seed, std::vector<float>& out) {
    World world(5, 55u);
    auto f = make_filter(seed);
    for (int k = 0; k < kRepeatSteps; ++k) world.step(*f);
    for (int r = 0; r < kN; ++r) {
      const est::team::TeamRobotEstimate& e = f->estimate(r);
      out.insert(out.end(), {e.mean.x, e.mean.y, e.mean.theta, e.covariance(0, 0), e.covariance(1, 1)});
    }
    for (int h = 0; h < Filter::kHypotheses; ++h) out.push_back(f->belief().log_probability(h));
  };
  std::vector<float> a, b, c;
  run(17u, a);
  run(17u, b);
  run(18u, c);
  REQUIRE(a.size() == b.size());
  CHECK(std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0);
  CHECK(std::memcmp(a.data(), c.data(), a.size() * sizeof(float)) != 0);
}

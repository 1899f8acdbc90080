#include <catch2/catch.hpp>

#include <cmath>
#include <algorithm>
#include <cstring>
#include <memory>
#include <vector>

#include <Eigen/Dense>

#include "est/team/coop_ekf_estimator.hpp"
#include "est/team/team_window.hpp"
#include "statistics.hpp"
#include "team_exercise.hpp"

namespace {

using est::team::TeamMessage;
using Estimator = est::team::CoopEkfEstimator<4, 12>;
using Window = est::team::TeamWindow<4, 8>;

struct Node {  // what one robot's node holds: the window and the team's estimator
  Window window;
  std::unique_ptr<Estimator> est = std::make_unique<Estimator>();
  void push(const TeamMessage& m) {
    window.push(m, [this](std::uint32_t seq, const TeamMessage* const* msgs) { est->step(seq, msgs); });
  }
};

est::team::CoopEkfConfig config_for(const est::test::TeamExercise& x) {
  est::team::CoopEkfConfig c;
  c.robots = x.robots;
  c.step_s = x.step_s;
  c.noise.sigma_range = x.sigma_range;
  c.noise.sigma_bearing = x.sigma_bearing;
  c.motion_sigma_mps = x.motion_sigma_mps;
  return c;
}

void start(Node& n, const est::test::TeamExercise& x, bool landmark_priors) {
  const Estimator::RobotCovariance c0 = Estimator::RobotCovariance::Identity() * (x.sigma_robot0 * x.sigma_robot0);
  std::vector<Estimator::RobotCovariance> covs(static_cast<std::size_t>(x.robots), c0);
  REQUIRE(n.window.start(x.robots, 1));
  REQUIRE(n.est->init(config_for(x), x.robot0.data(), covs.data()));
  if (landmark_priors)
    for (int l = 0; l < x.landmarks; ++l)
      REQUIRE(n.est->add_landmark(100 + l, x.landmark0[static_cast<std::size_t>(l)],
                                  Eigen::Matrix2f::Identity() * (x.sigma_landmark0 * x.sigma_landmark0)) ==
              est::CorrectionStatus::accepted);
}

// NEES of the whole state (robots, then landmarks in the filter's order) against the truth.
double nees(const Estimator& e, const est::test::TeamExercise& x) {
  const auto& s = e.slam();
  const int n = s.dim();
  Eigen::VectorXd err(n);
  for (int a = 0; a < s.robots(); ++a)
    for (int i = 0; i < 2; ++i) err(2 * a + i) = double(s.mean()(2 * a + i)) - double(x.x[std::size_t(a)](i));
  for (int k = 0; k < s.landmarks(); ++k)
    for (int i = 0; i < 2; ++i)
      err(s.landmark_offset(k) + i) = double(s.landmark(k)(i)) - double(x.m[std::size_t(s.landmark_id(k) - 100)](i));
  const Eigen::MatrixXd P = s.covariance().topLeftCorner(n, n).cast<double>();
  return err.dot(P.ldlt().solve(err));
}

double robot_error(const Estimator& e, const est::test::TeamExercise& x, int a) {
  return double((e.slam().robot(a) - x.x[std::size_t(a)]).norm());
}

struct RunResult {
  double mean_nees = 0.0;           // over steps
  double final_nees = 0.0;
  double rmse_shared[2] = {0, 0};   // robot 0's node, robots 0 and 1
  double rmse_own[2] = {0, 0};      // each robot's node with only its own messages
};

// The exercise: two point robots, one landmark with an initial estimate, range only, all four rows of z_k.
RunResult run_exercise(std::uint64_t seed, int steps = 150) {
  est::test::TeamExercise x(2, 1, false, seed);
  Node shared, own[2];
  start(shared, x, true);
  for (Node& n : own) start(n, x, true);
  RunResult r;
  for (std::uint32_t k = 1; k <= static_cast<std::uint32_t>(steps); ++k) {
    const std::vector<TeamMessage> msgs = x.step(k);
    for (const TeamMessage& m : msgs) shared.push(m);
    for (int a = 0; a < 2; ++a) own[a].push(msgs[std::size_t(a)]);  // nothing from the teammate
    const double e = nees(*shared.est, x);
    r.mean_nees += e / steps;
    r.final_nees = e;
    for (int a = 0; a < 2; ++a) {
      r.rmse_shared[a] += std::pow(robot_error(*shared.est, x, a), 2) / steps;
      r.rmse_own[a] += std::pow(robot_error(*own[a].est, x, a), 2) / steps;
    }
  }
  for (int a = 0; a < 2; ++a) r.rmse_shared[a] = std::sqrt(r.rmse_shared[a]), r.rmse_own[a] = std::sqrt(r.rmse_own[a]);
  CHECK(shared.window.counters().steps_complete == static_cast<std::uint32_t>(steps));
  return r;
}

}  // namespace

TEST_CASE("coop EKF: the team exercise through the window is consistent (NEES in its 95 % band over 40 runs)") {
  constexpr int kRuns = 40;
  double final_sum = 0.0, mean_sum = 0.0;
  for (int s = 1; s <= kRuns; ++s) {
    const RunResult r = run_exercise(static_cast<std::uint64_t>(s));
    final_sum += r.final_nees;
    mean_sum += r.mean_nees;
  }
  // runs * average of the final NEES ~ chi2(6 runs): the two-sided 95 % band of the average.
  const double lo = est::test::chi_square_critical(6.0 * kRuns, 0.975) / kRuns;
  const double hi = est::test::chi_square_critical(6.0 * kRuns, 0.025) / kRuns;
  INFO("average final NEES " << final_sum / kRuns << " band [" << lo << ", " << hi << "], over all steps "
                             << mean_sum / kRuns);
  CHECK(final_sum / kRuns > lo);
  CHECK(final_sum / kRuns < hi);
  CHECK(mean_sum / kRuns == Approx(6.0).epsilon(0.15));  // linearization leaves the time average within 15 %
}

TEST_CASE("coop EKF: sharing z and u locates both robots better than each robot's own measurements alone") {
  double shared = 0.0, own = 0.0;
  for (int s = 1; s <= 20; ++s) {
    const RunResult r = run_exercise(static_cast<std::uint64_t>(100 + s));
    shared += (r.rmse_shared[0] + r.rmse_shared[1]) / 40.0;
    own += (r.rmse_own[0] + r.rmse_own[1]) / 40.0;
  }
  INFO("position RMSE shared " << shared << " m, own only " << own << " m");
  CHECK(shared < 0.7 * own);
}

TEST_CASE("coop EKF: nodes that receive the same messages in any order hold the same estimate, bit for bit") {
  est::test::TeamExercise x(4, 12, true, 7);
  Node lockstep, shuffled;
  start(lockstep, x, false);
  start(shuffled, x, false);
  std::vector<TeamMessage> late;  // each step's messages delivered in reverse, robot 2's three steps late
  for (std::uint32_t k = 1; k <= 120; ++k) {
    const std::vector<TeamMessage> msgs = x.step(k);
    for (const TeamMessage& m : msgs) lockstep.push(m);
    for (int a = 3; a >= 0; --a) {
      if (a == 2) late.push_back(msgs[2]);
      else shuffled.push(msgs[std::size_t(a)]);
    }
    if (late.size() == 4) {
      for (const TeamMessage& m : late) shuffled.push(m);
      late.clear();
    }
  }
  for (const TeamMessage& m : late) shuffled.push(m);
  lockstep.window.flush([&](std::uint32_t s, const TeamMessage* const* m) { lockstep.est->step(s, m); });
  shuffled.window.flush([&](std::uint32_t s, const TeamMessage* const* m) { shuffled.est->step(s, m); });
  REQUIRE(shuffled.window.counters().steps_complete == 120);
  const auto& a = lockstep.est->slam();
  const auto& b = shuffled.est->slam();
  REQUIRE(a.dim() == b.dim());
  CHECK(a.landmarks() == 12);
  CHECK(std::memcmp(a.mean().data(), b.mean().data(), sizeof(float) * std::size_t(a.dim())) == 0);
  CHECK(std::memcmp(a.covariance().data(), b.covariance().data(), sizeof(Estimator::Slam::Covariance)) == 0);
}

TEST_CASE("coop EKF: four robots and twelve landmarks, range and bearing, map the landmarks from scratch") {
  est::test::TeamExercise x(4, 12, true, 11);
  Node n;
  start(n, x, false);
  double worst_landmark = 0.0;
  for (std::uint32_t k = 1; k <= 200; ++k)
    for (const TeamMessage& m : x.step(k)) n.push(m);
  const auto& s = n.est->slam();
  REQUIRE(s.landmarks() == 12);
  for (int k = 0; k < 12; ++k) {
    // Relative to robot 0: the team's frame is held by the prior only (0.2 m), the map relative to the team is
    // what the measurements fix.
    const Eigen::Vector2f est_rel = s.landmark(k) - s.robot(0);
    const Eigen::Vector2f true_rel = x.m[std::size_t(s.landmark_id(k) - 100)] - x.x[0];
    worst_landmark = std::max(worst_landmark, double((est_rel - true_rel).norm()));
  }
  INFO("worst landmark error relative to robot 0: " << worst_landmark << " m");
  CHECK(worst_landmark < 0.1);
  CHECK(nees(*n.est, x) < est::test::chi_square_critical(32.0, 0.001));
  CHECK(s.counters().accepted > 200u * 4u * 14u * 9u / 10u);
}

TEST_CASE("coop EKF: a robot whose messages stop is predicted only and flagged, then rejoins") {
  est::test::TeamExercise x(2, 1, false, 3);
  Node n;
  start(n, x, true);
  double var_before = 0.0, var_gap = 0.0;
  bool flagged_during_gap = true, clear_after = true;
  for (std::uint32_t k = 1; k <= 200; ++k) {
    std::vector<TeamMessage> msgs = x.step(k);
    const bool silent = k > 60 && k <= 90;  // robot 1 silent for 3 s
    n.push(msgs[0]);
    if (!silent) n.push(msgs[1]);
    const std::uint32_t closed = n.window.next_step() - 1;  // the step the estimate is at
    const bool gap = closed > 60 && closed <= 90;
    // The variance of robot 1's position relative to robot 0's (the absolute one is the team's prior, shared).
    const auto& P = n.est->slam().covariance();
    const double rel =
        double(P.block<2, 2>(2, 2).trace() + P.block<2, 2>(0, 0).trace() - 2.0f * P.block<2, 2>(0, 2).trace());
    if (closed == 60) var_before = rel;
    if (gap) var_gap = std::max(var_gap, rel);
    if (gap) flagged_during_gap = flagged_during_gap && (n.est->status() & est::loop::status::kTeamRobotMissing) != 0u;
    if (closed > 92) clear_after = clear_after && (n.est->status() & est::loop::status::kTeamRobotMissing) == 0u;
  }
  CHECK(flagged_during_gap);
  CHECK(clear_after);
  CHECK(n.est->counters().predicted_only[1] == 30);
  CHECK(n.est->counters().rejoined[1] == 1);
  CHECK(n.window.counters().missing[1] == 30);
  CHECK(var_gap > 4.0 * var_before);  // unknown control: the position spreads
  CHECK(robot_error(*n.est, x, 1) < 0.3);  // back with the team
  CHECK(n.est->slam().covariance_plausible());
}

TEST_CASE("coop EKF: a control of the wrong kind and anonymous sightings are counted, not used") {
  est::test::TeamExercise x(2, 1, false, 5);
  Node n;
  start(n, x, true);
  std::vector<TeamMessage> msgs = x.step(1);
  msgs[1].control.kind = est::team::ControlKind::velocity;
  msgs[0].measurements[0].id = est::team::kAnonymous;
  for (const TeamMessage& m : msgs) n.push(m);
  CHECK(n.est->counters().wrong_control == 1);
  CHECK(n.est->counters().predicted_only[1] == 1);
  CHECK(n.est->counters().anonymous_skipped == 1);
  CHECK((n.est->status() & est::loop::status::kInputRejected) != 0u);
  est::team::CoopEkfConfig bad = config_for(x);
  bad.robots = 5;
  Estimator::RobotCovariance covs[5];
  CHECK_FALSE(n.est->init(bad, x.robot0.data(), covs));
  CHECK((n.est->status() & est::loop::status::kNotInitialized) != 0u);
}

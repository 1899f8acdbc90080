#pragma once
// The team's workload for reference-coop-slam (board support): the team's estimator
// (est/team/coop_ekf_estimator.hpp) with R point robots (the exercise's start, each driving its own straight line)
// and M landmarks (the exercise's one above the robots with a prior, or a grid of 4 columns that enters the state
// from the first step's range and bearing, untimed), and each step's messages: every robot measures every other
// robot, then `seen` of the landmarks (as many as a message holds by default), from the truth with small fixed offsets, so every
// measurement passes the gate and is fused. The estimator and the messages live in static storage.
//
// bench-ekf's TeamBench builds the same messages in its own file: built from this header, its figures moved by 5 to
// 9 % (GCC's inlining within a translation unit depends on the unit's size and linkage), and those figures are
// compared over the project's history, so it keeps its copy.
#include <cstdint>

#include "est/math/fmath.hpp"
#include "est/team/coop_ekf_estimator.hpp"
#include "est/team/team_message.hpp"

namespace board {
namespace {  // internal linkage, as an image's own code

template <int R, int M, bool Bearings>
struct TeamWorkload {
  using Estimator = est::team::CoopEkfEstimator<R, M>;
  using TeamMessage = est::team::TeamMessage;
  static constexpr unsigned kR = static_cast<unsigned>(R), kM = static_cast<unsigned>(M);
  static constexpr float kStep = 0.1f;
  // Landmarks a message has room for beside the other robots (a message holds kMaxTeamMeasurements).
  static constexpr int kMaxSeen = M < est::team::kMaxTeamMeasurements - (R - 1) ? M
                                                                                 : est::team::kMaxTeamMeasurements - (R - 1);
  static constexpr int kMeasurements = R * (R - 1 + kMaxSeen);  // a step's, with kMaxSeen landmarks each

  struct State {
    Estimator estimator;
    TeamMessage msgs[kR];
    const TeamMessage* inbox[kR];
    Eigen::Vector2f x[kR], m[kM];
    std::uint32_t k = 0;
  };
  static State& state() {
    static State s;
    return s;
  }

  static Eigen::Vector2f landmark0(int l) {
    return M == 1 ? Eigen::Vector2f(2.0f, 3.0f)
                  : Eigen::Vector2f(-2.0f + 3.0f * static_cast<float>(l % 4), -2.0f + 3.5f * static_cast<float>(l / 4));
  }

  // Moves the truth over the next step and writes every robot's message: none of the measurements with
  // predict_only, else the other robots and `seen` landmarks (a different subset each step when seen < M; at most
  // kMaxSeen).
  static void messages(bool predict_only, int seen = kMaxSeen) {
    seen = seen < kMaxSeen ? seen : kMaxSeen;
    State& s = state();
    const std::uint32_t k = ++s.k;
    for (int a = 0; a < R; ++a) {
      const float heading = static_cast<float>(a);
      const Eigen::Vector2f u(0.3f * est::fmath::cos(heading), 0.3f * est::fmath::sin(heading));
      s.x[a] += u * kStep;
      TeamMessage& msg = s.msgs[a];
      msg.robot = a;
      msg.seq = k;
      msg.control = est::team::TeamControl{};
      msg.control.kind = est::team::ControlKind::holonomic;
      msg.control.dt_s = kStep;
      msg.control.v1 = u(0);
      msg.control.v2 = u(1);
      msg.count = 0;
    }
    for (int a = 0; predict_only == false && a < R; ++a) {
      TeamMessage& msg = s.msgs[a];
      for (int t = 0; t < R - 1 + seen; ++t) {
        const bool robot = t < R - 1;
        const int l = static_cast<int>((static_cast<std::uint32_t>(t - (R - 1)) + 3u * k) % kM);
        const int id = robot ? (t < a ? t : t + 1) : (seen == M ? t - (R - 1) : l);
        const Eigen::Vector2f d = (robot ? s.x[id] : s.m[id]) - s.x[a];
        est::team::TeamMeasurement& z = msg.measurements[msg.count];
        z.target = robot ? est::team::TargetKind::robot : est::team::TargetKind::landmark;
        z.id = robot ? id : 100 + id;
        z.range_m = est::fmath::sqrt(d(0) * d(0) + d(1) * d(1)) + 0.01f * static_cast<float>(msg.count % 3 - 1);
        z.has_bearing = Bearings;
        z.bearing_rad = Bearings ? est::fmath::normalize_angle(est::fmath::atan2(d(1), d(0)) + 0.005f) : 0.0f;
        ++msg.count;
      }
    }
  }

  // The estimator at the start, then the first step with every measurement (every landmark in the state); false
  // when the estimator refused its configuration.
  static bool start() {
    State& s = state();
    est::team::CoopEkfConfig c;
    c.robots = R;
    c.step_s = kStep;
    Eigen::Vector2f means[kR];
    typename Estimator::RobotCovariance covs[kR];
    for (int a = 0; a < R; ++a) {
      means[a] = Eigen::Vector2f(4.0f * static_cast<float>(a % 2), 3.0f * static_cast<float>(a / 2));
      covs[a] = Estimator::RobotCovariance::Identity() * 0.04f;
      s.x[a] = means[a];
      s.inbox[a] = &s.msgs[a];
    }
    for (int l = 0; l < M; ++l) s.m[l] = landmark0(l);
    if (!s.estimator.init(c, means, covs)) return false;
    if (!Bearings)
      for (int l = 0; l < M; ++l) s.estimator.add_landmark(100 + l, landmark0(l), Eigen::Matrix2f::Identity() * 0.09f);
    messages(false);
    step();
    return true;
  }

  // The estimator's step on the messages last written.
  static void step() { state().estimator.step(state().k, state().inbox); }
};

}  // namespace
}  // namespace board

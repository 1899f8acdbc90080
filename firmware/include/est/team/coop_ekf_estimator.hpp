#pragma once
// The team's cooperative EKF-SLAM in the loop (Probabilistic Robotics' team exercise, est/slam/cooperative_ekf_slam.hpp
// for the math): R holonomic point robots (x_k+1 = x_k + B u_k + w_k with u = (u_x, u_y) held over the step, so
// B = dt I) and M point landmarks in one Gaussian. Every robot's node runs this estimator on the shared messages as
// the team window (est/team/team_window.hpp) closes their steps; step() is a pure function of the messages a step
// had and their fixed order (robots 0..R-1, each message's measurements in order), so nodes that close the same
// steps hold the same estimate bit for bit.
//
// One step: (1) every robot is predicted, with its own control when its message is in, and when it is not (the
// message was lost, or the robot stopped sending) with u = 0 and the noise of a robot moving at up to
// unknown_speed_mps in any direction: its position spreads until its messages come back, and it rejoins with its
// next message (counted); (2) every message's measurements are fused one at a time (the factored update of
// est/filter/sparse_joseph_update.hpp): range, or range and bearing (world frame: point robots have no heading),
// to a robot with its id, or to a landmark with its id. A landmark not yet in the state enters from its first range
// and bearing (table 10.1 lines 9-10), or from ranges of spread positions when range only; landmarks given a prior
// (the exercise's initial estimate) start there.
// Anonymous sightings carry no correspondence this filter could use: they are counted and skipped (the three-robot
// filter, est/team/anonymous_team_mcl.hpp, resolves them). Controls of another kind than holonomic are refused and
// counted, and the robot is predicted as if its control were missing.
//
// Capacities: R_max robots and M_max landmarks; storage is dominated by the (2 R_max + 2 M_max)^2 covariance.
#include <cstdint>

#include "est/eigen.hpp"
#include "est/loop/status.hpp"
#include "est/motion/holonomic_model.hpp"
#include "est/slam/cooperative_ekf_slam.hpp"
#include "est/team/team_message.hpp"

namespace est::team {

struct CoopEkfConfig {
  std::int32_t robots = 2;
  float step_s = 0.1f;                      // the team's step: how long a robot without a control moves
  LandmarkNoise noise{0.05f, 0.02f, 0.0f};  // of the range (and bearing) sensors
  float motion_sigma_mps = 0.05f;     // w_k: per axis, as a velocity error (Q = (sigma dt)^2 I per step)
  float unknown_speed_mps = 0.5f;     // a robot without a control: how fast it may be moving, per axis
  InnovationGate gate{};
  CovarianceGuard guard{};
  RangeOnlyInitParams range_only_init{};
};

struct CoopEkfCounters {
  std::uint32_t steps = 0;
  std::uint32_t predicted_only[kMaxTeamRobots] = {};  // steps without robot a's control
  std::uint32_t rejoined[kMaxTeamRobots] = {};        // messages after a gap
  std::uint32_t wrong_control = 0;                    // a control of another kind than holonomic
  std::uint32_t anonymous_skipped = 0;
  std::uint32_t measurements = 0;                     // offered to the filter (its counters say what became of them)
};

template <int R_max, int M_max>
class CoopEkfEstimator {
 public:
  using Slam = CooperativeEkfSlam<HolonomicMotionModel, R_max, M_max>;
  using RobotCovariance = typename Slam::RobotCovariance;

  // The team from its initial estimate: each robot's position and covariance (the prior that holds the team's
  // unobservable translation), and optionally landmarks with a prior. False for a bad configuration.
  bool init(const CoopEkfConfig& c, const Eigen::Vector2f* means, const RobotCovariance* covs) {
    config_ = c;
    counters_ = CoopEkfCounters{};
    status_ = 0u;
    for (bool& g : gap_) g = false;
    if (c.robots < 1 || c.robots > R_max || !(c.step_s > 0.0f) || !(c.motion_sigma_mps >= 0.0f) ||
        !(c.unknown_speed_mps >= 0.0f) || !(c.noise.sigma_range > 0.0f) || !(c.noise.sigma_bearing > 0.0f)) {
      ok_ = false;
      return false;
    }
    typename Slam::Params p;
    p.gate = c.gate;
    p.guard = c.guard;
    p.range_only_init = c.range_only_init;
    slam_.configure(p);
    ok_ = slam_.init(c.robots, means, covs);
    return ok_;
  }
  CorrectionStatus add_landmark(std::int32_t id, const Eigen::Vector2f& mean, const Eigen::Matrix2f& cov) {
    return slam_.add_landmark(id, mean, cov);
  }

  // The window's close function: step `seq` with msgs[a] robot a's message or nullptr.
  void step(std::uint32_t /*seq*/, const TeamMessage* const* msgs) {
    if (!ok_) return;
    status_ = 0u;
    ++counters_.steps;
    const std::int32_t R = config_.robots;
    for (std::int32_t a = 0; a < R; ++a) predict(a, msgs[a]);
    for (std::int32_t a = 0; a < R; ++a)
      if (msgs[a] != nullptr) correct(a, *msgs[a]);
    if (!slam_.covariance_plausible()) status_ |= est::loop::status::kFilterDegenerate;
  }

  bool initialized() const { return ok_; }
  const Slam& slam() const { return slam_; }
  const CoopEkfCounters& counters() const { return counters_; }
  const CoopEkfConfig& config() const { return config_; }
  // est::loop::status bits of the last step: kTeamRobotMissing while a robot is predicted only, kInputRejected
  // when a measurement or control was refused.
  std::uint32_t status() const { return status_ | (ok_ ? 0u : est::loop::status::kNotInitialized); }
  bool robot_missing(std::int32_t a) const { return gap_[a]; }

 private:
  void predict(std::int32_t a, const TeamMessage* m) {
    const bool usable = m != nullptr && m->control.kind == ControlKind::holonomic;
    if (m != nullptr && m->control.kind != ControlKind::holonomic) {
      ++counters_.wrong_control;
      status_ |= est::loop::status::kInputRejected;
    }
    // The step length: the control's own; a robot without one moves over the team's step.
    const float dt = usable ? m->control.dt_s : config_.step_s;
    HolonomicParams p;
    const float s = config_.motion_sigma_mps * dt;
    p.Q = Eigen::Matrix2f::Identity() * (s * s);
    Eigen::Vector2f u = Eigen::Vector2f::Zero();
    if (usable) {
      u = Eigen::Vector2f(m->control.v1 * dt, m->control.v2 * dt);  // B = dt I: the displacement
      if (gap_[a]) ++counters_.rejoined[a];
      gap_[a] = false;
    } else {
      const float q = config_.unknown_speed_mps * dt;
      p.Q += Eigen::Matrix2f::Identity() * (q * q);
      ++counters_.predicted_only[a];
      gap_[a] = true;
      status_ |= est::loop::status::kTeamRobotMissing;
    }
    if (!usable_motion(slam_.predict_robot(a, u, p))) status_ |= est::loop::status::kInputRejected;
  }

  static bool usable_motion(MotionStatus s) { return est::usable(s); }

  void correct(std::int32_t a, const TeamMessage& m) {
    for (std::int32_t i = 0; i < m.count; ++i) {
      const TeamMeasurement& z = m.measurements[i];
      if (z.id == kAnonymous) {
        ++counters_.anonymous_skipped;
        continue;
      }
      ++counters_.measurements;
      CorrectionResult r;
      if (z.target == TargetKind::robot)
        r = z.has_bearing ? slam_.correct_robot_range_bearing(a, z.id, z.range_m, z.bearing_rad, config_.noise)
                          : slam_.correct_robot_range(a, z.id, z.range_m, config_.noise.sigma_range);
      else
        r = z.has_bearing ? slam_.correct_landmark_range_bearing(a, z.id, z.range_m, z.bearing_rad, config_.noise)
                          : slam_.correct_landmark_range(a, z.id, z.range_m, config_.noise.sigma_range);
      if (r.status != CorrectionStatus::accepted && r.status != CorrectionStatus::pending_initialization)
        status_ |= est::loop::status::kInputRejected;
    }
  }

  CoopEkfConfig config_{};
  Slam slam_{};
  CoopEkfCounters counters_{};
  bool gap_[static_cast<unsigned>(R_max)] = {};
  std::uint32_t status_ = 0u;
  bool ok_ = false;
};

}  // namespace est::team

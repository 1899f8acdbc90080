// Self-test section coop_ekf: the team's cooperative EKF-SLAM (est/team/coop_ekf_estimator.hpp) behind its reorder
// window (est/team/team_window.hpp), fed the team exercise's messages (est/team/team_message.hpp) the way a node
// receives them: one robot's messages a few steps late, one robot silent for a while, a duplicate and a message
// that comes after its step closed.
//
// The board's team capacities, in static storage (StaticInstance), never on the stack (mps2.ld keeps at least
// _min_stack = 64 KiB for it); sizeof on cortex-m4f and cortex-m7 (bench-ekf prints them), the same on the host:
//   CoopEkfEstimator<4, 12>   n = 32, the 32 x 32 covariance             5 668 bytes
//   TeamWindow<4, 8>          8 steps x 4 messages of 576 bytes         18 584 bytes
//   CoopEkfEstimator<2, 1>    n = 6                                      1 544 bytes
//   TeamWindow<2, 8>          8 steps x 2 messages                       9 368 bytes
// One step of CoopEkfEstimator<4, 12> with 60 range-and-bearing measurements is ~0.70 M instructions on the board
// (bench-ekf), so the section's 60 such steps are ~42 M instructions, a quarter of a second under qemu.

#include <cstdint>

#include "est/eigen.hpp"
#include "est/math/fmath.hpp"
#include "est/random/samplers.hpp"
#include "est/random/xoshiro128.hpp"
#include "est/team/coop_ekf_estimator.hpp"
#include "est/team/team_message.hpp"
#include "est/team/team_window.hpp"
#include "est/util/digest.hpp"
#include "loop_digest.hpp"
#include "selftest.hpp"

namespace est::selftest {
namespace {

using team::TeamMessage;

// The firmware's twin of tests/support/team_exercise.hpp (fixed sizes, est::fmath): R holonomic point robots
// driving circles and M point landmarks, every robot measuring its range (and world-frame bearing) to every other
// robot, then to every landmark, at every step; the truth drawn from the filter's prior.
template <int R, int M>
class TeamExercise {
  static constexpr unsigned kR = static_cast<unsigned>(R), kM = static_cast<unsigned>(M > 0 ? M : 1);

 public:
  static constexpr float kStep = 0.1f;
  static constexpr float kSigmaRange = 0.05f, kSigmaBearing = 0.02f, kMotionSigma = 0.05f;
  static constexpr float kSigmaRobot0 = 0.2f, kSigmaLandmark0 = 0.3f;

  void start(bool bearings, std::uint64_t seed) {
    bearings_ = bearings;
    rng_ = Rng(seed);
    for (int a = 0; a < R; ++a)
      robot0_[a] = Eigen::Vector2f(4.0f * static_cast<float>(a % 2), 3.0f * static_cast<float>(a / 2));
    for (int l = 0; l < M; ++l)  // the exercise's one landmark above the robots, or a grid of 4 columns
      landmark0_[l] = M == 1 ? Eigen::Vector2f(2.0f, 3.0f)
                             : Eigen::Vector2f(-2.0f + 3.0f * static_cast<float>(l % 4),
                                               -2.0f + 3.5f * static_cast<float>(l / 4));
    for (int a = 0; a < R; ++a) x_[a] = robot0_[a] + draw(kSigmaRobot0);
    for (int l = 0; l < M; ++l) m_[l] = landmark0_[l] + draw(kSigmaLandmark0);
  }

  // Moves the truth over step k and writes every robot's message for it.
  void step(std::uint32_t k, TeamMessage (&out)[kR]) {
    for (int a = 0; a < R; ++a) {
      const Eigen::Vector2f u = velocity(a, k);
      x_[a] += u * kStep + draw(kMotionSigma * kStep);
      TeamMessage& msg = out[a];
      msg.robot = a;
      msg.seq = k;
      msg.stamp_ns = static_cast<team::TimeNs>(k) * 100000000;
      msg.control = team::TeamControl{};
      msg.control.kind = team::ControlKind::holonomic;
      msg.control.dt_s = kStep;
      msg.control.v1 = u(0);
      msg.control.v2 = u(1);
      msg.count = 0;
    }
    for (int a = 0; a < R; ++a) {
      for (int b = 0; b < R; ++b)
        if (b != a) add(out[a], team::TargetKind::robot, b, x_[b]);
      for (int l = 0; l < M; ++l) add(out[a], team::TargetKind::landmark, 100 + l, m_[l]);
    }
  }

  const Eigen::Vector2f& robot0(int a) const { return robot0_[a]; }
  const Eigen::Vector2f& landmark0(int l) const { return landmark0_[l]; }
  const Eigen::Vector2f& truth(int a) const { return x_[a]; }

 private:
  Eigen::Vector2f draw(float s) {
    // Two statements: the order of evaluation of a call's arguments is unspecified and differs between targets.
    const float dx = sample_normal(rng_, s);
    const float dy = sample_normal(rng_, s);
    return Eigen::Vector2f(dx, dy);
  }
  // Robot a's commanded velocity at step k: circles of radius ~1.5 m, each robot its own phase and sense.
  static Eigen::Vector2f velocity(int a, std::uint32_t k) {
    const float w = (a % 2 == 0 ? 0.6f : -0.5f) * kStep;
    const float ph = w * static_cast<float>(k) + static_cast<float>(a);
    return Eigen::Vector2f(0.9f * fmath::cos(ph), 0.9f * fmath::sin(ph));
  }
  void add(TeamMessage& msg, team::TargetKind t, std::int32_t id, const Eigen::Vector2f& p) {
    const Eigen::Vector2f d = p - x_[msg.robot];
    team::TeamMeasurement& z = msg.measurements[msg.count++];
    z.target = t;
    z.id = id;
    z.range_m = fmath::abs(fmath::sqrt(d(0) * d(0) + d(1) * d(1)) + sample_normal(rng_, kSigmaRange));
    z.has_bearing = bearings_;
    z.bearing_rad =
        bearings_ ? fmath::normalize_angle(fmath::atan2(d(1), d(0)) + sample_normal(rng_, kSigmaBearing)) : 0.0f;
  }

  bool bearings_ = false;
  Rng rng_{0u};
  Eigen::Vector2f robot0_[kR], landmark0_[kM], x_[kR], m_[kM];
};

// One robot's node: the window, the team's estimator and (for the section) the exercise and its message buffers.
template <int R, int M, int Delay>
struct TeamNode {
  static constexpr int kWindow = 8;
  static constexpr unsigned kR = static_cast<unsigned>(R);
  team::TeamWindow<R, kWindow> window;
  team::CoopEkfEstimator<R, M> estimator;
  TeamExercise<R, M> exercise;
  TeamMessage msgs[kR];
  TeamMessage held[static_cast<unsigned>(Delay)];  // the late robot's messages of the last Delay steps

  void push(const TeamMessage& m) {
    window.push(m, [this](std::uint32_t seq, const TeamMessage* const* step) { estimator.step(seq, step); });
  }
  void flush() {
    window.flush([this](std::uint32_t seq, const TeamMessage* const* step) { estimator.step(seq, step); });
  }

  bool start(bool bearings, std::uint64_t seed, bool landmark_priors) {
    exercise.start(bearings, seed);
    team::CoopEkfConfig c;
    c.robots = R;
    c.step_s = TeamExercise<R, M>::kStep;
    c.noise.sigma_range = TeamExercise<R, M>::kSigmaRange;
    c.noise.sigma_bearing = TeamExercise<R, M>::kSigmaBearing;
    c.motion_sigma_mps = TeamExercise<R, M>::kMotionSigma;
    const float s0 = TeamExercise<R, M>::kSigmaRobot0, l0 = TeamExercise<R, M>::kSigmaLandmark0;
    Eigen::Vector2f means[kR];
    typename team::CoopEkfEstimator<R, M>::RobotCovariance covs[kR];
    for (int a = 0; a < R; ++a) {
      means[a] = exercise.robot0(a);
      covs[a] = Eigen::Matrix2f::Identity() * (s0 * s0);
    }
    bool ok = window.start(R, 1) && estimator.init(c, means, covs);
    for (int l = 0; ok && landmark_priors && l < M; ++l)
      ok = estimator.add_landmark(100 + l, exercise.landmark0(l), Eigen::Matrix2f::Identity() * (l0 * l0)) ==
           CorrectionStatus::accepted;
    return ok;
  }

  // The final estimate (mean and covariance of the active state, landmark ids in the filter's order), what the
  // window, the estimator and its filter counted, and the truth.
  void add_end(Digest& d, bool started) const {
    const auto& s = estimator.slam();
    const int n = s.dim();
    d.add_u32(started ? 1u : 0u);
    d.add_u32(static_cast<std::uint32_t>(n));
    d.add_matrix(s.mean().head(n));
    d.add_matrix(s.covariance().topLeftCorner(n, n));
    for (int k = 0; k < s.landmarks(); ++k) d.add_u32(static_cast<std::uint32_t>(s.landmark_id(k)));
    const team::TeamWindowCounters& w = window.counters();
    d.add_u32(w.accepted);
    for (std::uint32_t r : w.rejected) d.add_u32(r);
    d.add_u32(w.steps_closed);
    d.add_u32(w.steps_complete);
    for (int a = 0; a < R; ++a) d.add_u32(w.missing[a]);
    const team::CoopEkfCounters& e = estimator.counters();
    d.add_u32(e.steps);
    for (int a = 0; a < R; ++a) d.add_u32(e.predicted_only[a]);
    for (int a = 0; a < R; ++a) d.add_u32(e.rejoined[a]);
    d.add_u32(e.wrong_control);
    d.add_u32(e.anonymous_skipped);
    d.add_u32(e.measurements);
    const CorrectionCounters& c = s.counters();
    d.add_u32(c.accepted);
    d.add_u32(c.gated_out);
    d.add_u32(c.nonfinite);
    d.add_u32(c.not_pd);
    d.add_u32(c.pending);
    d.add_u32(estimator.status());
    for (int a = 0; a < R; ++a) {
      d.add(exercise.truth(a)(0));
      d.add(exercise.truth(a)(1));
    }
  }
};

// The exercise itself: 2 point robots and 1 landmark with a prior, range only (all four rows of z_k: d_AB, d_Al,
// d_BA, d_Bl), 100 steps; robot 0's messages arrive 2 steps late, robot 1 is silent over steps 41-50.
void two_robots_range_only(Digest& d) {
  using Node = TeamNode<2, 1, 2>;
  StaticInstance<Node> node;
  const bool started = node->start(false, 21u, true);
  for (std::uint32_t k = 1; k <= 100; ++k) {
    node->exercise.step(k, node->msgs);
    if (k > 2) node->push(node->held[k % 2]);
    node->held[k % 2] = node->msgs[0];
    if (k <= 40 || k > 50) node->push(node->msgs[1]);
  }
  node->push(node->held[1]);  // steps 99 and 100
  node->push(node->held[0]);
  node->flush();
  node->add_end(d, started);
}

// Four robots and twelve landmarks mapped from scratch, range and bearing, 60 steps: each step's messages arrive
// in reverse order, robot 2's three steps late; robot 3 is silent over steps 31-36 and its step-31 message arrives
// at step 50 (late: refused); robot 0's step-20 message arrives twice (duplicate: refused).
void four_robots_range_bearing(Digest& d) {
  using Node = TeamNode<4, 12, 3>;
  StaticInstance<Node> node;
  const bool started = node->start(true, 7u, false);
  static TeamMessage straggler;
  for (std::uint32_t k = 1; k <= 60; ++k) {
    node->exercise.step(k, node->msgs);
    if (k == 31) straggler = node->msgs[3];
    for (int a = 3; a >= 0; --a) {
      if (a == 3 && k > 30 && k <= 36) continue;
      if (a == 2) {
        if (k > 3) node->push(node->held[k % 3]);
        node->held[k % 3] = node->msgs[2];
        continue;
      }
      node->push(node->msgs[a]);
      if (a == 0 && k == 20) node->push(node->msgs[0]);
    }
    if (k == 50) node->push(straggler);
  }
  for (std::uint32_t k = 58; k <= 60; ++k) node->push(node->held[k % 3]);
  node->flush();
  node->add_end(d, started);
}

}  // namespace

std::uint64_t section_coop_ekf() {
  Digest d;
  two_robots_range_only(d);
  four_robots_range_bearing(d);
  return d.value();
}

}  // namespace est::selftest

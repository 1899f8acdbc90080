// bench-ekf for the qemu mps2 boards: instructions per cooperative EKF-SLAM range/bearing update (pose robots,
// velocity model) for R = 2 robots and M = 16 and 32 landmarks, and per step of the team's estimator
// (est/team/coop_ekf_estimator.hpp: predict every robot, fuse every measurement of every robot's message) for the
// exercise, R = 2 point robots and M = 1 landmark, range only (4 measurements a step), and R = 4, M = 12, range and
// bearing (each robot 3 robots + 12 landmarks: 60 measurements a step), timed with SysTick.
//
// Run under `-icount shift=10` (the ctest does): every instruction then takes 2^10 ns of virtual time and SysTick
// counts at 25 MHz, so instructions = ticks * 40 / 1024, exactly and repeatably (PLATFORM-NOTES, "Counting target
// instructions"). Without -icount the figure is wall-clock noise. SysTick runs without its interrupt (the vector
// table sends SysTick to the fault handler); each update is timed alone, well inside the 24-bit counter's range.
// A team step of R = 4, M = 12 (~1.5 M instructions) is not: at 25 MHz the counter wraps every 655 360
// instructions, so team steps are timed on SysTick's reference clock (CLKSOURCE = 0: qemu's mps2 REFCLK, 1 MHz),
// instructions = ticks * 1000 / 1024, within one instruction, up to 16 M. The image checks that clock against the
// processor clock on one update first and fails (exit 1, "FAIL") when they disagree.
//
// The board's team capacities and their static RAM (printed as "static RAM", sizeof on the board):
// CoopEkfEstimator<4, 12> and TeamWindow<4, 8> (8 steps x 4 messages), the self-test's coop_ekf section's sizes.
#include <cstdint>

#include "est/math/fmath.hpp"
#include "est/motion/velocity_model.hpp"
#include "est/slam/cooperative_ekf_slam.hpp"
#include "est/team/coop_ekf_estimator.hpp"
#include "est/team/team_message.hpp"
#include "est/team/team_window.hpp"
#include "budget_report.hpp"
#include "semihosting.hpp"

namespace {

constexpr std::uintptr_t kSystCsr = 0xE000E010u;
constexpr std::uintptr_t kSystRvr = 0xE000E014u;
constexpr std::uintptr_t kSystCvr = 0xE000E018u;

volatile std::uint32_t& reg(std::uintptr_t a) { return *reinterpret_cast<volatile std::uint32_t*>(a); }

enum class Clock : std::uint32_t { processor = 0x5u, reference = 0x1u };  // SYST_CSR: ENABLE (| CLKSOURCE)

void systick_start(Clock clock = Clock::processor) {
  reg(kSystCsr) = 0u;
  reg(kSystRvr) = 0x00FFFFFFu;
  reg(kSystCvr) = 0u;  // any write clears the counter and COUNTFLAG
  reg(kSystCsr) = static_cast<std::uint32_t>(clock);  // no TICKINT
}
std::uint32_t systick_now() { return reg(kSystCvr) & 0x00FFFFFFu; }
std::uint64_t instructions(std::uint64_t ticks, Clock clock) {
  return clock == Clock::processor ? ticks * 40u / 1024u : (ticks * 1000u + 512u) / 1024u;
}

template <int R, int M>
struct Bench {
  using Slam = est::CooperativeEkfSlam<est::VelocityMotionModel, R, M>;
  static Slam& filter() {
    static Slam f;
    return f;
  }
  // Mean instructions per update over `updates` updates (and the minimum), every landmark in the state.
  static std::uint64_t run(int updates) {
    Slam& f = filter();
    est::Pose2 x[static_cast<unsigned>(R)];
    typename Slam::RobotCovariance P[static_cast<unsigned>(R)];
    for (int a = 0; a < R; ++a) {
      x[a] = {static_cast<float>(a), 0.5f * static_cast<float>(a), 0.1f * static_cast<float>(a)};
      P[a] = Slam::RobotCovariance::Identity() * 0.01f;
    }
    f.init(R, x, P);
    const est::LandmarkNoise noise{0.05f, 0.02f, 0.0f};
    for (int k = 0; k < M; ++k)
      f.correct_landmark_range_bearing(k % R, k, 5.0f + 0.1f * static_cast<float>(k),
                                       0.1f * static_cast<float>(k) - 3.0f, noise);
    std::uint64_t total_ticks = 0;
    std::uint32_t min_ticks = 0xFFFFFFFFu;
    int accepted = 0;
    for (int i = 0; i < updates; ++i) {
      const int k = i % M;
      Eigen::Vector2f z = Eigen::Vector2f::Zero();
      Eigen::Matrix2f S = Eigen::Matrix2f::Zero();
      f.predicted_range_bearing(k % R, k, noise, &z, &S);
      z(0) += 0.01f;  // a small innovation, so the update does its full work
      systick_start();
      const std::uint32_t t0 = systick_now();
      const est::CorrectionResult r = f.correct_landmark_range_bearing(k % R, k, z(0), z(1), noise);
      const std::uint32_t t1 = systick_now();
      const std::uint32_t ticks = (t0 - t1) & 0x00FFFFFFu;
      total_ticks += ticks;
      min_ticks = ticks < min_ticks ? ticks : min_ticks;
      accepted += est::accepted(r.status) ? 1 : 0;
    }
    board::write("bench-ekf " EST_BOARD_NAME " R=");
    board::write_dec(static_cast<std::uint64_t>(R));
    board::write(" M=");
    board::write_dec(static_cast<std::uint64_t>(M));
    board::write(" n=");
    board::write_dec(static_cast<std::uint64_t>(f.dim()));
    board::write(" updates=");
    board::write_dec(static_cast<std::uint64_t>(accepted));
    board::write(" instructions per update: mean ");
    const std::uint64_t mean = total_ticks * 40u / 1024u / static_cast<std::uint64_t>(updates);
    board::write_dec(mean);
    board::write(" min ");
    board::write_dec(static_cast<std::uint64_t>(min_ticks) * 40u / 1024u);
    board::write("\n");
    return mean;
  }
};

// One update of Bench<2, 16> timed on both of SysTick's clocks: the reference clock must give the processor
// clock's count within 2 instructions (1 for the reference clock's tick, 1 for the rounding of each).
bool reference_clock_agrees() {
  using Slam = Bench<2, 16>::Slam;
  Slam& f = Bench<2, 16>::filter();
  const est::LandmarkNoise noise{0.05f, 0.02f, 0.0f};
  std::uint64_t count[2] = {0, 0};
  const Clock clocks[2] = {Clock::processor, Clock::reference};
  for (int c = 0; c < 2; ++c) {
    Eigen::Vector2f z = Eigen::Vector2f::Zero();
    Eigen::Matrix2f S = Eigen::Matrix2f::Zero();
    f.predicted_range_bearing(0, 0, noise, &z, &S);
    z(0) += 0.01f;
    systick_start(clocks[c]);
    const std::uint32_t t0 = systick_now();
    f.correct_landmark_range_bearing(0, 0, z(0), z(1), noise);
    const std::uint32_t t1 = systick_now();
    count[c] = instructions((t0 - t1) & 0x00FFFFFFu, clocks[c]);
  }
  const std::uint64_t diff = count[0] > count[1] ? count[0] - count[1] : count[1] - count[0];
  board::write("bench-ekf " EST_BOARD_NAME " reference clock check: processor clock ");
  board::write_dec(count[0]);
  board::write(" reference clock ");
  board::write_dec(count[1]);
  board::write(" instructions per update");
  board::write(diff <= 2u ? " ok\n" : " FAIL\n");
  return diff <= 2u;
}

// The team's estimator, R point robots (the exercise's start, each driving its own straight line) and M landmarks
// (the exercise's one above the robots with a prior, or a grid of 4 columns that enters the state from the first
// step's range and bearing, untimed). Every robot measures every other robot, then every landmark, from the truth
// with small fixed offsets, so every measurement passes the gate and is fused.
template <int R, int M, bool Bearings>
struct TeamBench {
  using Estimator = est::team::CoopEkfEstimator<R, M>;
  using TeamMessage = est::team::TeamMessage;
  static constexpr unsigned kR = static_cast<unsigned>(R), kM = static_cast<unsigned>(M);
  static constexpr float kStep = 0.1f;
  static constexpr int kMeasurements = R * (R - 1 + M);

  struct State {
    Estimator estimator;
    TeamMessage msgs[kR];
    Eigen::Vector2f x[kR], m[kM];
  };
  static State& state() {  // the estimator and R messages: static storage, not the stack
    static State s;
    return s;
  }

  static Eigen::Vector2f landmark0(int l) {
    return M == 1 ? Eigen::Vector2f(2.0f, 3.0f)
                  : Eigen::Vector2f(-2.0f + 3.0f * static_cast<float>(l % 4), -2.0f + 3.5f * static_cast<float>(l / 4));
  }

  // Moves the truth over step k and writes every robot's message; predict_only: no measurements.
  static void messages(std::uint32_t k, bool predict_only) {
    State& s = state();
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
      for (int t = 0; t < R - 1 + M; ++t) {
        const bool robot = t < R - 1;
        const int id = robot ? (t < a ? t : t + 1) : t - (R - 1);
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

  // Instructions of one step (mean and minimum over `steps` steps), then of one step without measurements.
  static inline std::uint64_t mean_step = 0;  // of the last run
  static bool run(int steps) {
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
    }
    for (int l = 0; l < M; ++l) s.m[l] = landmark0(l);
    if (!s.estimator.init(c, means, covs)) return false;
    if (!Bearings)
      for (int l = 0; l < M; ++l) s.estimator.add_landmark(100 + l, landmark0(l), Eigen::Matrix2f::Identity() * 0.09f);
    const TeamMessage* msgs[kR];
    for (int a = 0; a < R; ++a) msgs[a] = &s.msgs[a];
    std::uint32_t k = 1;
    messages(k, false);
    s.estimator.step(k, msgs);  // every landmark in the state
    const std::uint32_t accepted0 = s.estimator.slam().counters().accepted;
    std::uint64_t total = 0, least = ~std::uint64_t{0};
    for (int i = 0; i < steps; ++i) {
      messages(++k, false);
      systick_start(Clock::reference);
      const std::uint32_t t0 = systick_now();
      s.estimator.step(k, msgs);
      const std::uint32_t t1 = systick_now();
      const std::uint64_t n = instructions((t0 - t1) & 0x00FFFFFFu, Clock::reference);
      total += n;
      least = n < least ? n : least;
    }
    const std::uint32_t accepted = s.estimator.slam().counters().accepted - accepted0;
    messages(++k, true);
    systick_start(Clock::reference);
    const std::uint32_t t0 = systick_now();
    s.estimator.step(k, msgs);
    const std::uint32_t t1 = systick_now();
    const std::uint64_t predict = instructions((t0 - t1) & 0x00FFFFFFu, Clock::reference);
    const std::uint64_t mean = total / static_cast<std::uint64_t>(steps);
    mean_step = mean;
    board::write("bench-ekf " EST_BOARD_NAME " team R=");
    board::write_dec(static_cast<std::uint64_t>(R));
    board::write(" M=");
    board::write_dec(static_cast<std::uint64_t>(M));
    board::write(Bearings ? " range+bearing n=" : " range n=");
    board::write_dec(static_cast<std::uint64_t>(s.estimator.slam().dim()));
    board::write(" measurements=");
    board::write_dec(static_cast<std::uint64_t>(kMeasurements));
    board::write(" steps=");
    board::write_dec(static_cast<std::uint64_t>(steps));
    board::write(" fused=");
    board::write_dec(accepted);
    board::write(" instructions per step: mean ");
    board::write_dec(mean);
    board::write(" min ");
    board::write_dec(least);
    board::write(" per measurement ");
    board::write_dec(mean / static_cast<std::uint64_t>(kMeasurements));
    board::write(" predict only ");
    board::write_dec(predict);
    board::write("\n");
    return accepted == static_cast<std::uint32_t>(steps * kMeasurements);
  }
};

void write_size(const char* what, std::uint64_t bytes) {
  board::write("bench-ekf " EST_BOARD_NAME " static RAM ");
  board::write(what);
  board::write(" ");
  board::write_dec(bytes);
  board::write(" bytes\n");
}

}  // namespace

int main() {
  Bench<2, 16>::run(64);
  const std::uint64_t update = Bench<2, 32>::run(64);
  bool ok = reference_clock_agrees();
  ok = TeamBench<2, 1, false>::run(16) && ok;
  ok = TeamBench<4, 12, true>::run(16) && ok;
  write_size("CoopEkfEstimator<4, 12>", sizeof(est::team::CoopEkfEstimator<4, 12>));
  write_size("TeamWindow<4, 8>", sizeof(est::team::TeamWindow<4, 8>));
  write_size("CoopEkfEstimator<2, 1>", sizeof(est::team::CoopEkfEstimator<2, 1>));
  write_size("TeamWindow<2, 8>", sizeof(est::team::TeamWindow<2, 8>));
  write_size("TeamMessage", sizeof(est::team::TeamMessage));
  board::report_budget("bench.ekf.update_r2_m32", update, "instructions");
  board::report_budget("bench.ekf.team_step_r4_m12", TeamBench<4, 12, true>::mean_step, "instructions");
  if (!ok) board::write("bench-ekf " EST_BOARD_NAME " FAIL\n");
  return ok ? 0 : 1;
}

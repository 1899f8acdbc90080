// bench-ekf for the qemu mps2 boards: instructions per cooperative EKF-SLAM range/bearing update (pose robots,
// velocity model) for R = 2 robots and M = 16 and 32 landmarks, timed with SysTick.
//
// Run under `-icount shift=10` (the ctest does): every instruction then takes 2^10 ns of virtual time and SysTick
// counts at 25 MHz, so instructions = ticks * 40 / 1024, exactly and repeatably (PLATFORM-NOTES, "Counting target
// instructions"). Without -icount the figure is wall-clock noise. SysTick runs without its interrupt (the vector
// table sends SysTick to the fault handler); each update is timed alone, well inside the 24-bit counter's range.
#include <cstdint>

#include "est/motion/velocity_model.hpp"
#include "est/slam/cooperative_ekf_slam.hpp"
#include "semihosting.hpp"

namespace {

constexpr std::uintptr_t kSystCsr = 0xE000E010u;
constexpr std::uintptr_t kSystRvr = 0xE000E014u;
constexpr std::uintptr_t kSystCvr = 0xE000E018u;

volatile std::uint32_t& reg(std::uintptr_t a) { return *reinterpret_cast<volatile std::uint32_t*>(a); }

void systick_start() {
  reg(kSystRvr) = 0x00FFFFFFu;
  reg(kSystCvr) = 0u;    // any write clears the counter and COUNTFLAG
  reg(kSystCsr) = 0x5u;  // ENABLE | CLKSOURCE (processor clock), no TICKINT
}
std::uint32_t systick_now() { return reg(kSystCvr) & 0x00FFFFFFu; }

template <int R, int M>
struct Bench {
  using Slam = est::CooperativeEkfSlam<est::VelocityMotionModel, R, M>;
  static Slam& filter() {
    static Slam f;
    return f;
  }
  // Mean instructions per update over `updates` updates (and the minimum), every landmark in the state.
  static void run(int updates) {
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
    board::write_dec(total_ticks * 40u / 1024u / static_cast<std::uint64_t>(updates));
    board::write(" min ");
    board::write_dec(static_cast<std::uint64_t>(min_ticks) * 40u / 1024u);
    board::write("\n");
  }
};

}  // namespace

int main() {
  Bench<2, 16>::run(64);
  Bench<2, 32>::run(64);
  return 0;
}

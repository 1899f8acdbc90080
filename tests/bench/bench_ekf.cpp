// Cost of cooperative EKF-SLAM steps against the team size R and the number of landmarks M (pose robots, velocity
// model): one robot's prediction (O(n D^2)), the whole team's prediction, and one range/bearing update (O(n^2)),
// with n = 3 R + 2 M active states. Run: build/host/bin/bench_ekf
#include <benchmark/benchmark.h>

#include <memory>

#include "est/motion/velocity_model.hpp"
#include "est/slam/cooperative_ekf_slam.hpp"

namespace {

template <int R, int M>
std::unique_ptr<est::CooperativeEkfSlam<est::VelocityMotionModel, R, M>> make_filter() {
  using Slam = est::CooperativeEkfSlam<est::VelocityMotionModel, R, M>;
  auto f = std::make_unique<Slam>();
  est::Pose2 x[static_cast<unsigned>(R)];
  typename Slam::RobotCovariance P[static_cast<unsigned>(R)];
  for (int a = 0; a < R; ++a) {
    x[a] = {static_cast<float>(a), 0.5f * static_cast<float>(a), 0.1f * static_cast<float>(a)};
    P[a] = Slam::RobotCovariance::Identity() * 0.01f;
  }
  f->init(R, x, P);
  const est::LandmarkNoise noise{0.05f, 0.02f, 0.0f};
  for (int k = 0; k < M; ++k)  // landmarks on a ring around the team, each seen first by robot k % R
    f->correct_landmark_range_bearing(k % R, k, 5.0f + 0.1f * static_cast<float>(k),
                                      0.1f * static_cast<float>(k) - 3.0f, noise);
  return f;
}

template <int R, int M>
void BM_predict_team(benchmark::State& state) {
  auto f = make_filter<R, M>();
  est::VelocityParams mp;
  mp.a1 = mp.a4 = 0.01f;
  mp.dt = 0.1f;
  est::VelocityControl u[static_cast<unsigned>(R)];
  for (int a = 0; a < R; ++a) u[a] = {0.5f, 0.1f};
  for (auto _ : state) benchmark::DoNotOptimize(f->predict(u, mp));
  state.counters["n"] = f->dim();
}

template <int R, int M>
void BM_update_range_bearing(benchmark::State& state) {
  auto f = make_filter<R, M>();
  const est::LandmarkNoise noise{0.05f, 0.02f, 0.0f};
  int k = 0;
  for (auto _ : state) {
    Eigen::Vector2f z = Eigen::Vector2f::Zero();
    Eigen::Matrix2f S = Eigen::Matrix2f::Zero();
    f->predicted_range_bearing(k % R, k, noise, &z, &S);
    benchmark::DoNotOptimize(f->correct_landmark_range_bearing(k % R, k, z(0), z(1), noise));
    k = (k + 1) % M;
  }
  state.counters["n"] = f->dim();
}

template <int R, int M>
void BM_update_robot_range(benchmark::State& state) {
  auto f = make_filter<R, M>();
  for (auto _ : state) {
    const Eigen::Vector2f d = f->mean().template segment<2>(f->robot_offset(R - 1)) - f->mean().template segment<2>(0);
    benchmark::DoNotOptimize(f->correct_robot_range(0, R - 1, d.norm(), 0.05f));
  }
  state.counters["n"] = f->dim();
}

#define EST_BENCH_RM(R, M)                        \
  BENCHMARK_TEMPLATE(BM_predict_team, R, M);      \
  BENCHMARK_TEMPLATE(BM_update_range_bearing, R, M);
#define EST_BENCH_R(R) EST_BENCH_RM(R, 4) EST_BENCH_RM(R, 16) EST_BENCH_RM(R, 32) EST_BENCH_RM(R, 64)
EST_BENCH_R(1)
EST_BENCH_R(2)
EST_BENCH_R(4)
BENCHMARK_TEMPLATE(BM_update_robot_range, 2, 16);
BENCHMARK_TEMPLATE(BM_update_robot_range, 4, 64);

}  // namespace

BENCHMARK_MAIN();

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "est/motion/motion_batch.hpp"
#include "est/random/samplers.hpp"

// The batched samplers against the models' own samplers: same start pose, many draws each, and the two-sample
// Kolmogorov-Smirnov test on each coordinate of the result at significance 0.001 (c(0.001) = 1.949).
namespace {

double ks_two_sample(std::vector<double> a, std::vector<double> b) {
  std::sort(a.begin(), a.end());
  std::sort(b.begin(), b.end());
  std::size_t i = 0, j = 0;
  double d = 0.0;
  while (i < a.size() && j < b.size()) {
    const double v = std::min(a[i], b[j]);
    while (i < a.size() && a[i] <= v) ++i;
    while (j < b.size() && b[j] <= v) ++j;
    d = std::max(d, std::fabs(static_cast<double>(i) / static_cast<double>(a.size()) -
                              static_cast<double>(j) / static_cast<double>(b.size())));
  }
  return d;
}
double ks_two_sample_critical(std::size_t n, std::size_t m) {
  return 1.949 * std::sqrt(static_cast<double>(n + m) / (static_cast<double>(n) * static_cast<double>(m)));
}

template <class Model>
void compare(const typename Model::Control& u, const typename Model::Params& p, const est::Pose2& start) {
  const std::uint32_t n = 20000;
  std::vector<float> x(n, start.x), y(n, start.y), th(n, start.theta), a(n), b(n), c(n);
  est::Rng rng_batch(11u), rng_scalar(12u);
  est::sample_motion_batch(Model{}, u, p, x.data(), y.data(), th.data(), n, rng_batch, {a.data(), b.data(), c.data()});
  std::vector<double> bx, by, bt, sx, sy, st;
  for (std::uint32_t i = 0; i < n; ++i) {
    bx.push_back(x[i]);
    by.push_back(y[i]);
    bt.push_back(th[i]);
    const est::Pose2 q = Model::sample(start, u, p, rng_scalar);
    sx.push_back(q.x);
    sy.push_back(q.y);
    st.push_back(q.theta);
  }
  const double crit = ks_two_sample_critical(n, n);
  CHECK(ks_two_sample(bx, sx) < crit);
  CHECK(ks_two_sample(by, sy) < crit);
  CHECK(ks_two_sample(bt, st) < crit);
}

}  // namespace

TEST_CASE("batched bicycle sampling has the distribution of sample_motion_model_bicycle", "[motion_batch]") {
  est::BicycleParams p;
  p.frame_length = 0.6f;
  p.steer_max = 0.6f;
  p.steer_sigma = 0.1f;
  p.speed_var_per_speed = 0.05f;
  p.final_rot_sigma = 0.02f;
  p.dt = 0.5f;
  compare<est::BicycleMotionModel>({1.2f, 0.3f}, p, {1.0f, -2.0f, 3.0f});     // heading near pi: wraps
  compare<est::BicycleMotionModel>({-0.8f, -0.55f}, p, {0.0f, 0.0f, -1.0f});  // backwards, near the stop: folds
  p.dt = 4.0f;
  compare<est::BicycleMotionModel>({2.0f, 0.5f}, p, {0.0f, 0.0f, 0.2f});  // a long step: |h| > 0.1, sinc by sin
}

TEST_CASE("batched differential-drive sampling has the distribution of sample_motion_model_diff_drive",
          "[motion_batch]") {
  est::DiffDriveParams p;
  p.travel_sigma_per_m = 0.1f;
  p.travel_sigma_floor = 0.002f;
  p.final_rot_sigma = 0.02f;
  compare<est::DiffDriveMotionModel>({2000, 2600}, p, {2.0f, 1.0f, -3.1f});
  compare<est::DiffDriveMotionModel>({-5000, 5000}, p, {0.0f, 0.0f, 0.5f});  // spinning in place
}

TEST_CASE("batched sampling refuses what the model refuses and keeps NaN particles from spreading", "[motion_batch]") {
  est::DiffDriveParams p;
  p.travel_sigma_per_m = 0.1f;
  float x[3] = {0.0f, 1.0f, std::numeric_limits<float>::quiet_NaN()}, y[3] = {0.0f, 0.0f, 0.0f},
        th[3] = {0.0f, 1.0f, 0.0f}, a[3], b[3], c[3];
  est::Rng rng(1u);
  const est::Rng before = rng;
  est::sample_motion_batch(est::DiffDriveMotionModel{}, {est::DiffDriveControl::kMaxTicks + 1, 0}, p, x, y, th, 3, rng,
                           {a, b, c});
  CHECK(rng == before);  // rejected: nothing drawn, nothing moved
  CHECK(x[1] == 1.0f);
  est::sample_motion_batch(est::DiffDriveMotionModel{}, {100, 120}, p, x, y, th, 3, rng, {a, b, c});
  CHECK(std::isfinite(x[0]));
  CHECK(std::isfinite(x[1]));
  CHECK(std::isfinite(th[1]));
  CHECK(std::isnan(x[2]));
}

TEST_CASE("a model without a batched form falls back to its own sampler, bit for bit", "[motion_batch]") {
  est::BicycleParams p;
  p.steer_sigma = 0.05f;
  struct Wrapped : est::BicycleMotionModel {};  // a distinct type: only the generic overload matches
  float x[4] = {0, 1, 2, 3}, y[4] = {0, 0, 1, 1}, th[4] = {0.1f, 0.2f, 0.3f, 0.4f}, a[4], b[4], c[4];
  est::Rng r1(3u), r2(3u);
  est::sample_motion_batch(Wrapped{}, {1.0f, 0.1f}, p, x, y, th, 4, r1, {a, b, c});
  for (int i = 0; i < 4; ++i) {
    const est::Pose2 q = est::BicycleMotionModel::sample(
        {static_cast<float>(i), i < 2 ? 0.0f : 1.0f, 0.1f * static_cast<float>(i + 1)}, {1.0f, 0.1f}, p, r2);
    CHECK(x[i] == q.x);
    CHECK(th[i] == q.theta);
  }
}

namespace {

std::uint32_t bits(float v) {
  std::uint32_t b = 0;
  std::memcpy(&b, &v, sizeof b);
  return b;
}

// The first pass over n particles as the host runs it (lanes::kLanes at a time, first_pass) and one particle at a
// time (the board's loop): every output's bits and the count left to the second pass must agree.
template <class Step>
void check_lanes_match_scalar(const Step& step) {
  const std::uint32_t n = 4003;  // not a multiple of the lanes: the remainder takes the scalar form
  std::vector<float> x(n), y(n), th(n), a(n), b(n), c(n);
  est::Rng rng(21u);
  for (std::uint32_t i = 0; i < n; ++i) {
    x[i] = rng.uniform(-20.0f, 20.0f);
    y[i] = rng.uniform(-20.0f, 20.0f);
    th[i] = rng.uniform(-3.5f, 3.5f);  // some beyond pi: left to the second pass
    a[i] = 4.0f * est::sample_normal(rng, 1.0f);  // wide noise: some steering and arcs beyond the fast case
    b[i] = 4.0f * est::sample_normal(rng, 1.0f);
    c[i] = 40.0f * est::sample_normal(rng, 1.0f);
  }
  x[5] = std::numeric_limits<float>::quiet_NaN();
  th[6] = std::numeric_limits<float>::infinity();
  th[7] = -0.0f;
  th[8] = est::kPi;
  th[9] = -est::kPi;
  std::vector<float> sx = x, sy = y, st = th, sa = a;
  const std::uint32_t pending = est::motion_batch_detail::first_pass(step, x.data(), y.data(), th.data(), a.data(),
                                                                     b.data(), c.data(), n);
  std::uint32_t scalar_pending = 0;
  for (std::uint32_t i = 0; i < n; ++i) scalar_pending += step(sx[i], sy[i], st[i], sa[i], b[i], c[i]);
  std::uint32_t differ = 0;
  for (std::uint32_t i = 0; i < n; ++i)
    differ += (bits(x[i]) != bits(sx[i]) || bits(y[i]) != bits(sy[i]) || bits(th[i]) != bits(st[i]) ||
               bits(a[i]) != bits(sa[i]))
                  ? 1u
                  : 0u;
  CHECK(differ == 0u);
  CHECK(pending == scalar_pending);
  CHECK(pending > 100u);     // both cases are taken
  CHECK(pending < n - 100u);
}

}  // namespace

TEST_CASE("the first pass gives the same bits four particles at a time as one at a time", "[motion_batch]") {
  const est::motion_batch_detail::BicycleFast bike{0.1f, 0.04f, 0.8f, 0.3f, 0.01f, 0.1f, 0.5f * 0.1f / 0.6f,
                                                   0.7853981f};
  check_lanes_match_scalar([&bike](auto& xi, auto& yi, auto& ti, auto& ai, auto bi, auto ci) {
    return est::motion_batch_detail::bicycle_fast(bike, xi, yi, ti, ai, bi, ci);
  });
  const est::motion_batch_detail::DiffDriveFast dd{0.05f, 0.06f, 0.01f, 0.01f, 0.01f, 0.5f / 0.3f};
  check_lanes_match_scalar([&dd](auto& xi, auto& yi, auto& ti, auto& ai, auto bi, auto ci) {
    return est::motion_batch_detail::diff_drive_fast(dd, xi, yi, ti, ai, bi, ci);
  });
}

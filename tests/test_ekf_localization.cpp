#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include <Eigen/Dense>

#include "est/filter/ekf_localization.hpp"
#include "est/motion/velocity_model.hpp"
#include "est/random/samplers.hpp"
#include "statistics.hpp"

namespace {

using Ekf = est::EkfLocalization<est::VelocityMotionModel>;
using est::CorrectionStatus;

struct World {
  est::Landmark lm[8] = {{0.0f, 0.0f, 1.0f}, {6.0f, 0.0f, 2.0f}, {6.0f, 6.0f, 3.0f}, {0.0f, 6.0f, 4.0f},
                         {3.0f, -1.5f, 5.0f}, {7.5f, 3.0f, 6.0f}, {3.0f, 7.5f, 7.0f}, {-1.5f, 3.0f, 8.0f}};
  est::LandmarkMap map{lm, 8};
  est::LandmarkNoise noise{0.1f, 0.03f, 0.0f};
  est::VelocityParams motion;
  est::Pose2 start{3.0f, 1.0f, 0.0f};
  float max_range = 5.0f;
  World() {
    motion.a1 = 0.02f;
    motion.a2 = 0.001f;
    motion.a3 = 0.001f;
    motion.a4 = 0.02f;
    motion.dt = 0.1f;
  }
  est::VelocityControl control(int k) const { return {0.6f, 0.3f + 0.1f * std::sin(0.02f * static_cast<float>(k))}; }
  est::LandmarkMeasurement measure(const est::Pose2& x, int j, est::Rng& rng) const {
    const float dx = lm[j].x - x.x, dy = lm[j].y - x.y;
    return {std::sqrt(dx * dx + dy * dy) + est::sample_normal(rng, noise.sigma_range),
            est::fmath::normalize_angle(std::atan2(dy, dx) - x.theta + est::sample_normal(rng, noise.sigma_bearing)),
            lm[j].signature};
  }
  bool visible(const est::Pose2& x, int j) const { return std::hypot(lm[j].x - x.x, lm[j].y - x.y) < max_range; }
};

double nees3(const Ekf& f, const est::Pose2& x) {
  const Eigen::Vector3d e(static_cast<double>(f.mean().x - x.x), static_cast<double>(f.mean().y - x.y),
                          std::remainder(static_cast<double>(f.mean().theta - x.theta), 2.0 * M_PI));
  return e.dot(f.covariance().cast<double>().inverse() * e);
}

bool spd(const Ekf::Covariance& P) {
  if (!(P == P.transpose())) return false;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(P.cast<double>());
  return es.eigenvalues().minCoeff() > 0.0;
}

}  // namespace

TEST_CASE("EKF localization with known correspondences tracks a circle with consistent NEES (40 runs)",
          "[ekf_localization]") {
  constexpr int kRuns = 40, kSteps = 200;
  const World w;
  std::vector<double> anees(kSteps, 0.0);
  double sq_err = 0.0;
  for (int run = 0; run < kRuns; ++run) {
    est::Rng rng(100u + static_cast<std::uint64_t>(run));
    Ekf::Covariance P0 = Ekf::Covariance::Zero();
    P0.diagonal() << 0.3f * 0.3f, 0.3f * 0.3f, 0.1f * 0.1f;
    est::Pose2 x{w.start.x + est::sample_normal(rng, 0.3f), w.start.y + est::sample_normal(rng, 0.3f),
                 w.start.theta + est::sample_normal(rng, 0.1f)};
    Ekf f;
    REQUIRE(f.init(w.start, P0));
    for (int k = 0; k < kSteps; ++k) {
      const est::VelocityControl u = w.control(k);
      x = est::VelocityMotionModel::sample(x, u, w.motion, rng);
      REQUIRE(f.predict(u, w.motion) == est::MotionStatus::ok);
      for (int j = 0; j < w.map.size(); ++j)
        if (w.visible(x, j)) f.correct_range_bearing(w.measure(x, j, rng), w.map, j, w.noise);
      anees[static_cast<std::size_t>(k)] += nees3(f, x) / kRuns;
      REQUIRE(spd(f.covariance()));
    }
    sq_err += (std::pow(static_cast<double>(f.mean().x - x.x), 2) + std::pow(static_cast<double>(f.mean().y - x.y), 2)) / kRuns;
  }
  const double lo = est::test::chi_square_critical(3.0 * kRuns, 0.975) / kRuns;
  const double hi = est::test::chi_square_critical(3.0 * kRuns, 0.025) / kRuns;
  int inside = 0;
  double mean = 0.0;
  for (double a : anees) {
    inside += (a >= lo && a <= hi) ? 1 : 0;
    mean += a / kSteps;
  }
  const double frac = static_cast<double>(inside) / kSteps;
  WARN("EKF localization: ANEES band [" << lo << ", " << hi << "], time-mean " << mean << ", final " << anees.back()
                                        << ", steps inside " << frac << ", RMS final position error "
                                        << std::sqrt(sq_err) << " m");
  CHECK(frac >= 0.90);
  CHECK(anees.back() >= lo);
  CHECK(anees.back() <= hi);
  CHECK(std::sqrt(sq_err) < 0.08);  // sigma_range 0.1 m, several landmarks in view
}

TEST_CASE("unknown correspondences: maximum likelihood picks the right landmark", "[ekf_localization]") {
  const World w;
  est::Rng rng(7u);
  Ekf::Covariance P0 = Ekf::Covariance::Zero();
  P0.diagonal() << 0.05f * 0.05f, 0.05f * 0.05f, 0.02f * 0.02f;
  est::Pose2 x = w.start;
  Ekf f;
  REQUIRE(f.init(w.start, P0));
  int right = 0, total = 0;
  for (int k = 0; k < 200; ++k) {
    const est::VelocityControl u = w.control(k);
    x = est::VelocityMotionModel::sample(x, u, w.motion, rng);
    f.predict(u, w.motion);
    for (int j = 0; j < w.map.size(); ++j) {
      if (!w.visible(x, j)) continue;
      const est::AssociationResult r = f.correct_range_bearing_unknown(w.measure(x, j, rng), w.map, w.noise);
      ++total;
      right += r.landmark == j ? 1 : 0;
    }
  }
  WARN("ML correspondence right " << right << " of " << total);
  CHECK(right >= total * 99 / 100);
  CHECK(f.counters().accepted + f.counters().gated_out == static_cast<std::uint32_t>(total));
  // Signatures: with sigma_signature > 0 a measurement carrying landmark 3's signature picks landmark 3 even from
  // far away where geometry alone cannot tell.
  est::LandmarkNoise with_sig = w.noise;
  with_sig.sigma_signature = 0.1f;
  est::LandmarkMeasurement z = w.measure(f.mean(), 2, rng);
  const est::AssociationResult r = f.correct_range_bearing_unknown(z, w.map, with_sig);
  CHECK(r.landmark == 2);
}

TEST_CASE("unknown correspondences: a sighting two landmarks explain almost equally is refused as ambiguous",
          "[ekf_localization]") {
  // Two posts 0.6 m apart, both 3 m ahead; a wide belief (0.5 m) cannot tell which one a range and bearing between
  // them came from: their log likelihoods differ by well under 2 nats.
  est::Landmark lm[2] = {{3.0f, 0.3f, 1.0f}, {3.0f, -0.3f, 2.0f}};
  const est::LandmarkMap map{lm, 2};
  const est::LandmarkNoise noise{0.1f, 0.03f, 0.0f};
  Ekf::Covariance P0 = Ekf::Covariance::Zero();
  P0.diagonal() << 0.25f, 0.25f, 0.01f;
  const est::LandmarkMeasurement between{3.0f, 0.02f, 0.0f};  // slightly closer to the left post
  const est::LandmarkMeasurement on_left{3.015f, std::atan2(0.3f, 3.0f), 0.0f};

  Ekf plain;  // table 7.3 as printed: the maximum, whatever the margin
  REQUIRE(plain.init(est::Pose2{0.0f, 0.0f, 0.0f}, P0));
  const est::AssociationResult taken = plain.correct_range_bearing_unknown(between, map, noise);
  CHECK(taken.landmark == 0);
  CHECK(est::accepted(taken.correction.status));

  Ekf::Params p;
  p.ambiguity_nats = 2.0f;
  Ekf careful(p);
  REQUIRE(careful.init(est::Pose2{0.0f, 0.0f, 0.0f}, P0));
  const est::AssociationResult refused = careful.correct_range_bearing_unknown(between, map, noise);
  CHECK(refused.landmark == -1);
  CHECK(refused.correction.status == CorrectionStatus::rejected_ambiguous);
  CHECK(careful.counters().ambiguous == 1u);
  CHECK(careful.counters().rejected() == 1u);
  CHECK(careful.mean().x == 0.0f);  // nothing fused
  // With the belief tight (0.05 m) the same geometry is no longer ambiguous: a sighting on the left post is fused.
  Ekf::Covariance P1 = Ekf::Covariance::Zero();
  P1.diagonal() << 0.0025f, 0.0025f, 0.0004f;
  REQUIRE(careful.init(est::Pose2{0.0f, 0.0f, 0.0f}, P1));
  const est::AssociationResult fused = careful.correct_range_bearing_unknown(on_left, map, noise);
  CHECK(fused.landmark == 0);
  CHECK(est::accepted(fused.correction.status));
}

TEST_CASE("5-sigma outliers are gated and counted; bad input is refused by reason; the estimate is never NaN",
          "[ekf_localization]") {
  const World w;
  est::Rng rng(8u);
  Ekf f;
  Ekf::Covariance P0 = Ekf::Covariance::Identity() * 0.01f;
  REQUIRE(f.init(w.start, P0));
  est::Pose2 x = w.start;
  int faults = 0;
  for (int k = 0; k < 100; ++k) {
    const est::VelocityControl u = w.control(k);
    x = est::VelocityMotionModel::sample(x, u, w.motion, rng);
    f.predict(u, w.motion);
    for (int j = 0; j < w.map.size(); ++j) {
      if (!w.visible(x, j)) continue;
      est::LandmarkMeasurement z = w.measure(x, j, rng);
      if (k % 5 == 0) {  // 5 innovation sigmas in range, from the filter's own S
        const Eigen::Vector3f mu = f.mean_vector();
        const auto h = est::range_bearing_measurement<3>(mu, Eigen::Vector2f(w.lm[j].x, w.lm[j].y));
        const Eigen::Matrix2f S = h.H_robot * f.covariance() * h.H_robot.transpose() +
                                  Eigen::Vector2f(0.01f, 0.0009f).asDiagonal().toDenseMatrix();
        z.range = h.z(0) + 5.0f * std::sqrt(S(0, 0));
        z.bearing = h.z(1);
        const Ekf::Covariance before = f.covariance();
        const est::CorrectionResult r = f.correct_range_bearing(z, w.map, j, w.noise);
        CHECK(r.status == CorrectionStatus::rejected_gate);
        CHECK(r.nis >= 25.0f * 0.999f);
        CHECK(f.covariance() == before);
        ++faults;
      } else {
        f.correct_range_bearing(z, w.map, j, w.noise);
      }
    }
  }
  CHECK(f.counters().gated_out >= static_cast<std::uint32_t>(faults));
  CHECK(f.counters().gated_out <= static_cast<std::uint32_t>(faults) + 2u);
  const std::uint32_t before = f.counters().total();
  CHECK(f.correct_range_bearing({std::nanf(""), 0.0f, 0.0f}, w.map, 0, w.noise).status ==
        CorrectionStatus::rejected_nonfinite);
  CHECK(f.correct_range_bearing({1.0f, 0.0f, 0.0f}, w.map, 99, w.noise).status ==
        CorrectionStatus::rejected_unknown_landmark);
  CHECK(f.correct_range_bearing({1.0f, 0.0f, 0.0f}, w.map, 0, est::LandmarkNoise{-1.0f, 0.1f, 0.0f}).status ==
        CorrectionStatus::rejected_bad_input);
  CHECK(f.correct_range(std::numeric_limits<float>::infinity(), w.map, 0, 0.1f).status ==
        CorrectionStatus::rejected_nonfinite);
  CHECK(f.counters().total() == before + 4u);
  CHECK(f.counters().nonfinite == 2u);
  CHECK(f.counters().unknown_landmark == 1u);
  CHECK(f.counters().bad_input == 1u);
  est::VelocityControl bad{std::nanf(""), 0.0f};
  CHECK(f.predict(bad, w.motion) == est::MotionStatus::rejected_nonfinite);
  CHECK(f.prediction_counters().rejected_nonfinite == 1u);
  CHECK(f.mean().is_finite());
  CHECK(spd(f.covariance()));
  CHECK_FALSE(f.init(w.start, -P0));  // a non-PD prior is refused
}

TEST_CASE("range-only beacons localize a robot (known correspondences)", "[ekf_localization]") {
  const World w;
  est::Rng rng(9u);
  Ekf f;
  Ekf::Covariance P0 = Ekf::Covariance::Zero();
  P0.diagonal() << 0.2f * 0.2f, 0.2f * 0.2f, 0.05f * 0.05f;
  est::Pose2 x{w.start.x + 0.1f, w.start.y - 0.1f, 0.02f};
  REQUIRE(f.init(w.start, P0));
  double nees_sum = 0.0;
  for (int k = 0; k < 150; ++k) {
    const est::VelocityControl u = w.control(k);
    x = est::VelocityMotionModel::sample(x, u, w.motion, rng);
    f.predict(u, w.motion);
    for (int j = 0; j < 4; ++j)
      f.correct_range(std::hypot(w.lm[j].x - x.x, w.lm[j].y - x.y) + est::sample_normal(rng, 0.05f), w.map, j, 0.05f);
    if (k >= 50) nees_sum += nees3(f, x);
  }
  CHECK(std::hypot(f.mean().x - x.x, f.mean().y - x.y) < 0.15f);
  CHECK(nees_sum / 100.0 < est::test::chi_square_critical(300, 0.001) / 100.0 * 1.5);  // one run: loose
  CHECK(spd(f.covariance()));
}

TEST_CASE("motion-proportional noise grows with the path driven and turned, not with the time, in the robot frame",
          "[ekf_localization]") {
  World w;
  w.motion = est::VelocityParams{};  // no velocity noise: only the proportional terms
  w.motion.dt = 0.01f;
  Ekf::Params p;
  p.motion_noise.along_per_m = 0.01f;
  p.motion_noise.cross_per_m = 0.001f;
  p.motion_noise.heading_per_m = 0.002f;
  p.motion_noise.heading_per_rad = 0.004f;
  const Ekf::Covariance p0 = Ekf::Covariance::Identity() * 1e-6f;
  // 1 m straight along the y axis in 100 or 1000 steps: the same variance (a random walk over the path), along
  // the heading in y, across it in x; the heading gains heading_per_m only.
  for (int steps : {100, 1000}) {
    Ekf f(p);
    REQUIRE(f.init({0.0f, 0.0f, 1.5707964f}, p0));
    w.motion.dt = 1.0f / static_cast<float>(steps);
    for (int k = 0; k < steps; ++k) REQUIRE(f.predict({1.0f, 0.0f}, w.motion) == est::MotionStatus::ok);
    INFO(steps << " steps");
    CHECK(f.mean().y == Approx(1.0f).margin(1e-4));
    CHECK(f.covariance()(1, 1) == Approx(1e-6 + 0.01).epsilon(0.01));   // along
    CHECK(f.covariance()(2, 2) == Approx(1e-6 + 0.002).epsilon(0.01));  // heading per metre
    // across: the cross term plus the heading's uncertainty levered over the path (G), at least the cross term
    CHECK(static_cast<double>(f.covariance()(0, 0)) > 1e-6 + 0.001);
    CHECK(static_cast<double>(f.covariance()(0, 0)) < 1e-6 + 0.001 + 0.002 * 1.0 / 3.0 + 1e-4);  // + var(theta) grown linearly, s^2 / 3
  }
  // Turning on the spot by 1 rad: heading_per_rad, no position noise; standing still for as long: nothing.
  Ekf turn(p), still(p);
  REQUIRE(turn.init({0.0f, 0.0f, 0.0f}, p0));
  REQUIRE(still.init({0.0f, 0.0f, 0.0f}, p0));
  w.motion.dt = 0.01f;
  for (int k = 0; k < 100; ++k) {
    REQUIRE(turn.predict({0.0f, 1.0f}, w.motion) == est::MotionStatus::ok);
    REQUIRE(still.predict({0.0f, 0.0f}, w.motion) == est::MotionStatus::ok);
  }
  CHECK(turn.covariance()(2, 2) == Approx(1e-6 + 0.004).epsilon(0.01));
  CHECK(turn.covariance()(0, 0) == Approx(1e-6).epsilon(0.01));
  CHECK(still.covariance() == p0);
}

#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <memory>
#include <vector>

#include <Eigen/Dense>

#include "est/motion/holonomic_model.hpp"
#include "est/motion/velocity_model.hpp"
#include "est/random/samplers.hpp"
#include "est/slam/cooperative_ekf_slam.hpp"
#include "statistics.hpp"

namespace {

using est::CorrectionStatus;

// NEES e^T P^-1 e over the first n entries, in double (angles in e already wrapped).
template <typename Mu, typename Cov>
double nees(const Mu& mu, const Cov& P, const Eigen::VectorXd& truth, int n, const std::vector<bool>& angle) {
  Eigen::VectorXd e(n);
  Eigen::MatrixXd S(n, n);
  for (int i = 0; i < n; ++i) {
    e(i) = static_cast<double>(mu(i)) - truth(i);
    if (angle[static_cast<std::size_t>(i)]) e(i) = std::remainder(e(i), 2.0 * M_PI);
    for (int j = 0; j < n; ++j) S(i, j) = static_cast<double>(P(i, j));
  }
  return e.dot(S.ldlt().solve(e));
}

template <typename Cov>
bool symmetric_positive_definite(const Cov& P, int n) {
  Eigen::MatrixXd S(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      if (P(i, j) != P(j, i)) return false;
      S(i, j) = static_cast<double>(P(i, j));
    }
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(S);
  return es.eigenvalues().minCoeff() > 0.0;
}

// The 95 % two-sided band of the average NEES (or NIS) over `runs` runs of a `dof`-dimensional quantity:
// runs * average ~ chi2(runs * dof).
struct Band {
  double lo, hi;
};
Band average_chi2_band(int runs, int dof) {
  const double k = static_cast<double>(runs) * dof;
  return {est::test::chi_square_critical(k, 0.975) / runs, est::test::chi_square_critical(k, 0.025) / runs};
}

// ---- The team exercise: 2 omnidirectional point robots, 1 landmark, range-only, shared z and u. ----------------
using PointSlam = est::CooperativeEkfSlam<est::HolonomicMotionModel, 2, 1>;

struct ExerciseSetup {
  static constexpr int kSteps = 150;
  static constexpr float kSigmaRange = 0.05f;  // m
  static constexpr float kSigmaMotion = 0.02f;  // m per step and axis (w_k)
  static constexpr float kSigmaRobot0 = 0.2f;   // m, the prior that holds the unobservable translation
  static constexpr float kSigmaLandmark0 = 0.3f;
  Eigen::Vector2f robot0[2] = {Eigen::Vector2f(0.0f, 0.0f), Eigen::Vector2f(4.0f, 0.0f)};
  Eigen::Vector2f landmark0 = Eigen::Vector2f(2.0f, 3.0f);
  est::HolonomicParams motion;
  ExerciseSetup() { motion.Q = Eigen::Matrix2f::Identity() * (kSigmaMotion * kSigmaMotion); }
  // The robots' commanded displacements at step k: two different circles of radius ~1.5 m.
  Eigen::Vector2f control(int robot, int k) const {
    const float w = robot == 0 ? 0.06f : -0.05f;
    const float a = w * static_cast<float>(k) + (robot == 0 ? 0.0f : 1.0f);
    return Eigen::Vector2f(0.09f * std::cos(a), 0.09f * std::sin(a));
  }
};

struct ExerciseRun {
  std::vector<double> nees;  // per step
  Eigen::VectorXd final_error;
  double final_distance_error = 0.0;  // estimated minus true robot-robot distance
  est::CorrectionCounters counters;
  bool always_pd = true;
};

// One seeded run: the truth starts at a draw from the prior, so that the prior's uncertainty is the real one.
ExerciseRun run_exercise(std::uint64_t seed, int instances = 1, bool* identical = nullptr) {
  const ExerciseSetup s;
  est::Rng rng(seed);
  Eigen::Vector2f x[2], m;
  for (int a = 0; a < 2; ++a)
    x[a] = s.robot0[a] + Eigen::Vector2f(est::sample_normal(rng, s.kSigmaRobot0), est::sample_normal(rng, s.kSigmaRobot0));
  m = s.landmark0 +
      Eigen::Vector2f(est::sample_normal(rng, s.kSigmaLandmark0), est::sample_normal(rng, s.kSigmaLandmark0));

  std::vector<std::unique_ptr<PointSlam>> f;
  for (std::size_t i = 0; i < static_cast<std::size_t>(instances); ++i) {
    f.push_back(std::make_unique<PointSlam>());
    const PointSlam::RobotCovariance P0 = PointSlam::RobotCovariance::Identity() * (s.kSigmaRobot0 * s.kSigmaRobot0);
    const PointSlam::RobotCovariance covs[2] = {P0, P0};
    REQUIRE(f[i]->init(2, s.robot0, covs));
    REQUIRE(f[i]->add_landmark(7, s.landmark0, Eigen::Matrix2f::Identity() * (s.kSigmaLandmark0 * s.kSigmaLandmark0)) ==
            CorrectionStatus::accepted);
  }
  ExerciseRun out;
  const std::vector<bool> no_angles(6, false);
  for (int k = 0; k < s.kSteps; ++k) {
    Eigen::Vector2f u[2];
    for (int a = 0; a < 2; ++a) {
      u[a] = s.control(a, k);
      x[a] = est::HolonomicMotionModel::sample(x[a], u[a], s.motion, rng);
    }
    const float r01 = (x[1] - x[0]).norm() + est::sample_normal(rng, s.kSigmaRange);
    const float r0m = (m - x[0]).norm() + est::sample_normal(rng, s.kSigmaRange);
    const float r1m = (m - x[1]).norm() + est::sample_normal(rng, s.kSigmaRange);
    for (auto& fi : f) {  // every robot's filter gets the same shared u and z, in the same order
      REQUIRE(fi->predict(u, s.motion) == 2);
      fi->correct_robot_range(0, 1, r01, s.kSigmaRange);
      fi->correct_landmark_range(0, 7, r0m, s.kSigmaRange);
      fi->correct_landmark_range(1, 7, r1m, s.kSigmaRange);
    }
    Eigen::VectorXd truth(6);
    truth << x[0](0), x[0](1), x[1](0), x[1](1), m(0), m(1);
    out.nees.push_back(nees(f[0]->mean(), f[0]->covariance(), truth, 6, no_angles));
    if (k == s.kSteps - 1) {
      out.final_error = Eigen::VectorXd(6);
      for (int i = 0; i < 6; ++i) out.final_error(i) = static_cast<double>(f[0]->mean()(i)) - truth(i);
      out.final_distance_error = static_cast<double>((f[0]->mean().segment<2>(2) - f[0]->mean().segment<2>(0)).norm()) -
                                 static_cast<double>((x[1] - x[0]).norm());
    }
    out.always_pd = out.always_pd && f[0]->covariance_plausible();
  }
  out.always_pd = out.always_pd && symmetric_positive_definite(f[0]->covariance(), 6);
  out.counters = f[0]->counters();
  if (identical != nullptr) {
    *identical = true;
    for (std::size_t i = 1; i < f.size(); ++i)
      *identical = *identical &&
                   std::memcmp(f[0]->mean().data(), f[i]->mean().data(), sizeof(float) * 6) == 0 &&
                   std::memcmp(f[0]->covariance().data(), f[i]->covariance().data(), sizeof(PointSlam::Covariance)) == 0;
  }
  return out;
}

}  // namespace

TEST_CASE("team exercise: 2 point robots, 1 landmark, range-only, 50 runs: NEES in the 95% band, errors bounded",
          "[ekf_slam][exercise]") {
  constexpr int kRuns = 50;
  const Band band = average_chi2_band(kRuns, 6);  // 50 * ANEES ~ chi2(300)
  std::vector<double> anees(ExerciseSetup::kSteps, 0.0);
  double rms_robot = 0.0, rms_relative = 0.0, rms_landmark_relative = 0.0, rms_distance = 0.0;
  std::uint32_t gated = 0, accepted_count = 0;
  for (int run = 0; run < kRuns; ++run) {
    const ExerciseRun r = run_exercise(1000u + static_cast<std::uint64_t>(run));
    REQUIRE(r.always_pd);
    for (int k = 0; k < ExerciseSetup::kSteps; ++k) anees[static_cast<std::size_t>(k)] += r.nees[static_cast<std::size_t>(k)] / kRuns;
    const Eigen::VectorXd& e = r.final_error;
    rms_robot += (e(0) * e(0) + e(1) * e(1) + e(2) * e(2) + e(3) * e(3)) / (2.0 * kRuns);
    rms_relative += ((e(2) - e(0)) * (e(2) - e(0)) + (e(3) - e(1)) * (e(3) - e(1))) / kRuns;
    rms_landmark_relative += ((e(4) - e(0)) * (e(4) - e(0)) + (e(5) - e(1)) * (e(5) - e(1))) / kRuns;
    rms_distance += r.final_distance_error * r.final_distance_error / kRuns;
    gated += r.counters.gated_out;
    accepted_count += r.counters.accepted;
  }
  rms_robot = std::sqrt(rms_robot);
  rms_relative = std::sqrt(rms_relative);
  rms_landmark_relative = std::sqrt(rms_landmark_relative);
  rms_distance = std::sqrt(rms_distance);
  int inside = 0;
  double mean_anees = 0.0;
  for (double a : anees) {
    inside += (a >= band.lo && a <= band.hi) ? 1 : 0;
    mean_anees += a / ExerciseSetup::kSteps;
  }
  const double frac = static_cast<double>(inside) / ExerciseSetup::kSteps;
  INFO("band [" << band.lo << ", " << band.hi << "], final ANEES " << anees.back() << ", time-mean ANEES "
                << mean_anees << ", steps inside " << frac << "; RMS final error: robot " << rms_robot
                << " m, robot-robot " << rms_relative << " m, landmark-robot " << rms_landmark_relative
                << " m, distance " << rms_distance << " m; gated " << gated << " of " << accepted_count + gated);
  WARN("exercise: band [" << band.lo << ", " << band.hi << "], final ANEES " << anees.back() << ", time-mean ANEES "
                          << mean_anees << ", steps inside " << frac << "; RMS final error robot " << rms_robot
                          << " m, robot-robot " << rms_relative << " m, landmark-robot " << rms_landmark_relative
                          << " m, distance " << rms_distance << " m; gated " << gated << " of " << accepted_count + gated);
  CHECK(anees.back() >= band.lo);
  CHECK(anees.back() <= band.hi);
  CHECK(frac >= 0.90);  // 95 % expected; consecutive steps are correlated, so allow a few excursions
  // The translation of the whole team is unobservable: absolute errors stay at the prior's scale (0.2 m per axis).
  // The ranges fix the triangle's shape to centimetres; its orientation is observed only through the robots' known
  // world-frame displacements, so the robot-robot vector is known to ~0.15 m, the inter-robot distance below the range noise.
  CHECK(rms_robot < 0.30);
  CHECK(rms_relative < 0.20);
  CHECK(rms_landmark_relative < 0.10);
  CHECK(rms_distance < 0.04);  // sigma_range = 0.05 m
  CHECK(gated < accepted_count / 500u);  // the 99.9 % gate refuses ~0.1 % of good ranges
}

TEST_CASE("per-robot filters fed the same shared z and u are bit-identical, and a seed reproduces its run",
          "[ekf_slam][determinism]") {
  bool identical = false;
  const ExerciseRun a = run_exercise(77u, 3, &identical);
  CHECK(identical);
  const ExerciseRun b = run_exercise(77u);
  REQUIRE(a.nees.size() == b.nees.size());
  CHECK(std::memcmp(a.nees.data(), b.nees.data(), sizeof(double) * a.nees.size()) == 0);
  CHECK(a.final_error == b.final_error);
}

namespace {

// ---- A larger team: 4 pose robots (velocity model), 12 landmarks met on the way, range/bearing and robot ranges. --
using PoseSlam = est::CooperativeEkfSlam<est::VelocityMotionModel, 4, 12>;

struct TeamSetup {
  static constexpr int kRobots = 4;
  static constexpr int kLandmarks = 12;
  static constexpr int kSteps = 120;
  static constexpr float kMaxRange = 7.0f;
  est::LandmarkNoise noise{0.05f, 0.02f, 0.0f};
  float sigma_robot_range = 0.05f;
  est::VelocityParams motion;
  est::Pose2 start[kRobots] = {{1.0f, 1.0f, 0.0f}, {7.0f, 1.0f, 1.5708f}, {7.0f, 7.0f, 3.1416f}, {1.0f, 7.0f, -1.5708f}};
  Eigen::Vector2f landmarks[kLandmarks];
  TeamSetup() {
    motion.a1 = 0.01f;
    motion.a2 = 0.0005f;
    motion.a3 = 0.0005f;
    motion.a4 = 0.01f;
    motion.dt = 0.1f;
    for (int j = 0; j < kLandmarks; ++j)
      landmarks[j] = Eigen::Vector2f(0.5f + 2.3f * static_cast<float>(j % 4), 0.5f + 3.3f * static_cast<float>(j / 4));
  }
  est::VelocityControl control(int robot, int k) const {
    return {0.5f + 0.05f * static_cast<float>(robot), (robot % 2 == 0 ? 0.25f : -0.2f) + 0.002f * static_cast<float>(k)};
  }
};

struct TeamRun {
  std::vector<double> nees;  // per step, NaN where not all landmarks are in the state yet
  std::vector<int> dims;
  double nis_sum = 0.0;      // over every range/bearing innovation formed (accepted or gated)
  std::uint32_t nis_count = 0;
  est::CorrectionCounters counters;
  bool pd = true;
  int landmarks = 0;
};

// fault_every > 0: every fault_every-th range/bearing measurement is replaced by one 5 innovation sigmas off in range.
TeamRun run_team(std::uint64_t seed, int fault_every = 0, std::uint32_t* faults = nullptr,
                 std::uint32_t* faults_gated = nullptr) {
  const TeamSetup s;
  est::Rng rng(seed);
  est::Pose2 x[TeamSetup::kRobots];
  PoseSlam::RobotCovariance P0 = PoseSlam::RobotCovariance::Zero();
  P0.diagonal() << 0.05f * 0.05f, 0.05f * 0.05f, 0.01f * 0.01f;
  PoseSlam::RobotCovariance covs[TeamSetup::kRobots];
  for (int a = 0; a < TeamSetup::kRobots; ++a) {
    covs[a] = P0;
    x[a] = {s.start[a].x + est::sample_normal(rng, 0.05f), s.start[a].y + est::sample_normal(rng, 0.05f),
            s.start[a].theta + est::sample_normal(rng, 0.01f)};
  }
  auto f = std::make_unique<PoseSlam>();
  REQUIRE(f->init(TeamSetup::kRobots, s.start, covs));
  TeamRun out;
  int measurement = 0;
  for (int k = 0; k < TeamSetup::kSteps; ++k) {
    est::VelocityControl u[TeamSetup::kRobots];
    for (int a = 0; a < TeamSetup::kRobots; ++a) {
      u[a] = s.control(a, k);
      x[a] = est::VelocityMotionModel::sample(x[a], u[a], s.motion, rng);
    }
    REQUIRE(f->predict(u, s.motion) == TeamSetup::kRobots);
    for (int a = 0; a < TeamSetup::kRobots; ++a) {
      for (int j = 0; j < TeamSetup::kLandmarks; ++j) {
        const float dx = s.landmarks[j](0) - x[a].x, dy = s.landmarks[j](1) - x[a].y;
        const float r = std::sqrt(dx * dx + dy * dy);
        if (r > TeamSetup::kMaxRange) continue;
        float zr = r + est::sample_normal(rng, s.noise.sigma_range);
        const float zb = est::fmath::normalize_angle(std::atan2(dy, dx) - x[a].theta +
                                                     est::sample_normal(rng, s.noise.sigma_bearing));
        Eigen::Vector2f zhat;
        Eigen::Matrix2f S;
        const bool known = f->predicted_range_bearing(a, j, s.noise, &zhat, &S);
        const bool fault = known && fault_every > 0 && (++measurement % fault_every) == 0;
        if (fault) zr = zhat(0) + 5.0f * std::sqrt(S(0, 0));
        const est::CorrectionResult res = f->correct_landmark_range_bearing(a, j, zr, zb, s.noise);
        if (fault) {
          ++*faults;
          *faults_gated += res.status == CorrectionStatus::rejected_gate ? 1u : 0u;
        } else if (res.nis >= 0.0f) {
          out.nis_sum += static_cast<double>(res.nis);
          ++out.nis_count;
        }
      }
      const int b = (a + 1) % TeamSetup::kRobots;
      const float rab = std::hypot(x[b].x - x[a].x, x[b].y - x[a].y) + est::sample_normal(rng, s.sigma_robot_range);
      f->correct_robot_range(a, b, rab, s.sigma_robot_range);
    }
    const int n = f->dim();
    out.dims.push_back(n);
    out.pd = out.pd && f->covariance_plausible();
    if (f->landmarks() == TeamSetup::kLandmarks) {
      Eigen::VectorXd truth(n);
      std::vector<bool> angle(static_cast<std::size_t>(n), false);
      for (int a = 0; a < TeamSetup::kRobots; ++a) {
        truth.segment<3>(3 * a) << x[a].x, x[a].y, x[a].theta;
        angle[static_cast<std::size_t>(3 * a + 2)] = true;
      }
      for (int kk = 0; kk < TeamSetup::kLandmarks; ++kk) {
        const int id = f->landmark_id(kk);
        truth.segment<2>(f->landmark_offset(kk)) << s.landmarks[id](0), s.landmarks[id](1);
      }
      out.nees.push_back(nees(f->mean(), f->covariance(), truth, n, angle));
    } else {
      out.nees.push_back(std::nan(""));
    }
  }
  out.pd = out.pd && symmetric_positive_definite(f->covariance(), f->dim());
  out.counters = f->counters();
  out.landmarks = f->landmarks();
  return out;
}

}  // namespace

TEST_CASE("team of 4 pose robots, 12 landmarks, range/bearing: NEES and NIS within their 95% bands",
          "[ekf_slam][team]") {
#ifdef NDEBUG
  constexpr int kRuns = 20;
#else
  constexpr int kRuns = 4;  // the sanitizer build runs ~500x slower; the band below follows the run count
#endif
  constexpr int kDim = 3 * TeamSetup::kRobots + 2 * TeamSetup::kLandmarks;  // 36
  const Band band = average_chi2_band(kRuns, kDim);
  std::vector<double> anees(TeamSetup::kSteps, 0.0);
  std::vector<int> counted(TeamSetup::kSteps, 0);
  double nis_sum = 0.0;
  std::uint32_t nis_count = 0, gated = 0, accepted_count = 0;
  for (int run = 0; run < kRuns; ++run) {
    const TeamRun r = run_team(5000u + static_cast<std::uint64_t>(run));
    REQUIRE(r.pd);
    REQUIRE(r.landmarks == TeamSetup::kLandmarks);
    for (std::size_t k = 0; k < r.nees.size(); ++k)
      if (!std::isnan(r.nees[k])) {
        anees[k] += r.nees[k] / kRuns;
        ++counted[k];
      }
    nis_sum += r.nis_sum;
    nis_count += r.nis_count;
    gated += r.counters.gated_out;
    accepted_count += r.counters.accepted;
  }
  int steps = 0, inside = 0;
  double mean_anees = 0.0;
  for (std::size_t k = 0; k < anees.size(); ++k) {
    if (counted[k] != kRuns) continue;
    ++steps;
    inside += (anees[k] >= band.lo && anees[k] <= band.hi) ? 1 : 0;
    mean_anees += anees[k];
  }
  REQUIRE(steps >= TeamSetup::kSteps / 2);
  mean_anees /= steps;
  // NIS: the sum over all innovations ~ chi2(2 count) when the filter is consistent.
  const double nis_mean = nis_sum / nis_count;
  const Band nis_band = average_chi2_band(static_cast<int>(nis_count), 2);
  const double frac = static_cast<double>(inside) / steps;
  WARN("team: ANEES band [" << band.lo << ", " << band.hi << "] (" << kDim << " dof, " << kRuns << " runs), final "
                            << anees.back() << ", time-mean " << mean_anees << ", steps inside " << frac << " of "
                            << steps << "; mean NIS " << nis_mean << " over " << nis_count << " in [" << nis_band.lo
                            << ", " << nis_band.hi << "]; gated " << gated << " of " << gated + accepted_count);
  CHECK(anees.back() >= band.lo);
  CHECK(anees.back() <= band.hi);
  CHECK(frac >= 0.90);
  CHECK(nis_mean >= nis_band.lo);
  CHECK(nis_mean <= nis_band.hi);
}

TEST_CASE("gating refuses injected 5-sigma range faults, counts them, and the filter stays consistent",
          "[ekf_slam][gating]") {
  std::uint32_t faults = 0, gated_faults = 0;
  const TeamRun r = run_team(9001u, 25, &faults, &gated_faults);
  REQUIRE(faults > 50u);
  CHECK(gated_faults == faults);
  CHECK(r.counters.gated_out >= faults);
  CHECK(r.counters.gated_out <= faults + r.counters.accepted / 200u);  // + ~0.1 % of good measurements
  CHECK(r.pd);
  const Band band = average_chi2_band(1, 36);
  const double final_nees = r.nees.back();
  CHECK(final_nees < est::test::chi_square_critical(36, 0.001));
  (void)band;
}

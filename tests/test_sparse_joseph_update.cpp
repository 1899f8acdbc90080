#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>

#include <Eigen/Dense>

#include "est/filter/sparse_joseph_update.hpp"
#include "est/random/xoshiro128.hpp"

namespace {

constexpr int N = 12;
using Vec = Eigen::Matrix<float, N, 1>;
using Mat = Eigen::Matrix<float, N, N>;

// Both forms of the covariance step (est/filter/sparse_joseph_update.hpp): every case runs each.
enum class Form { joseph, factored };
constexpr Form kForms[] = {Form::joseph, Form::factored};
const char* name(Form f) { return f == Form::joseph ? "joseph" : "factored"; }

template <int Mdim>
est::CorrectionResult update(Form f, Vec& mu, Mat& P, int n, const est::SparseJacobian<Mdim>& H,
                             const Eigen::Matrix<float, Mdim, 1>& nu, const Eigen::Matrix<float, Mdim, Mdim>& Q,
                             float gate, const est::CovarianceGuard& g = est::CovarianceGuard{}) {
  return f == Form::joseph ? est::sparse_joseph_update<N, Mdim>(mu, P, n, H, nu, Q, gate, g)
                           : est::sparse_factored_update<N, Mdim>(mu, P, n, H, nu, Q, gate, g);
}

Mat random_spd(est::Rng& rng, int n) {
  Eigen::MatrixXf A(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) A(i, j) = rng.uniform(-1.0f, 1.0f);
  Mat P = Mat::Identity();
  P.topLeftCorner(n, n) = A * A.transpose() * 0.1f + Eigen::MatrixXf::Identity(n, n) * 0.05f;
  return P;
}

}  // namespace

TEST_CASE("both sparse updates equal the dense Joseph form (double) and are exactly symmetric",
          "[sparse_joseph_update]") {
  for (const Form form : kForms) {
  INFO(name(form));
  est::Rng rng(41u);
  const int n = 10;
  for (int t = 0; t < 100; ++t) {
    Mat P = random_spd(rng, n);
    Vec mu = Vec::Zero();
    est::SparseJacobian<2> H;
    Eigen::Matrix<float, 2, 3> b0;
    Eigen::Matrix<float, 2, 2> b1, b2;
    for (int i = 0; i < 6; ++i) b0(i % 2, i / 2) = rng.uniform(-1.0f, 1.0f);
    for (int i = 0; i < 4; ++i) b1(i % 2, i / 2) = rng.uniform(-1.0f, 1.0f);
    for (int i = 0; i < 4; ++i) b2(i % 2, i / 2) = rng.uniform(-1.0f, 1.0f);
    H.add<3>(0, b0);
    H.add<2>(4, b1);
    H.add<2>(8, b2);
    Eigen::MatrixXd Hd = Eigen::MatrixXd::Zero(2, n);
    Hd.block(0, 0, 2, 3) = b0.cast<double>();
    Hd.block(0, 4, 2, 2) = b1.cast<double>();
    Hd.block(0, 8, 2, 2) = b2.cast<double>();
    const Eigen::Vector2f nu(rng.uniform(-0.1f, 0.1f), rng.uniform(-0.1f, 0.1f));
    const Eigen::Matrix2f Q = Eigen::Vector2f(0.02f, 0.01f).asDiagonal();
    const Eigen::MatrixXd Pd = P.topLeftCorner(n, n).cast<double>();
    const Eigen::MatrixXd S = Hd * Pd * Hd.transpose() + Q.cast<double>();
    const Eigen::MatrixXd K = Pd * Hd.transpose() * S.inverse();
    const Eigen::MatrixXd IKH = Eigen::MatrixXd::Identity(n, n) - K * Hd;
    const Eigen::MatrixXd Pj = IKH * Pd * IKH.transpose() + K * Q.cast<double>() * K.transpose();
    const Eigen::VectorXd muj = K * nu.cast<double>();
    const est::CorrectionResult r = update<2>(form, mu, P, n, H, nu, Q, 0.0f);
    REQUIRE(r.status == est::CorrectionStatus::accepted);
    CHECK(static_cast<double>(r.nis) == Approx(nu.cast<double>().dot(S.inverse() * nu.cast<double>())).epsilon(1e-4));
    CHECK((P.topLeftCorner(n, n).cast<double>() - Pj).cwiseAbs().maxCoeff() < 1e-5 * Pj.cwiseAbs().maxCoeff() + 1e-7);
    CHECK((mu.head(n).cast<double>() - muj).cwiseAbs().maxCoeff() < 1e-5);
    CHECK(P == P.transpose());
    CHECK(P(n, n) == 1.0f);  // inactive entries untouched
  }
  }
}

TEST_CASE("refusals leave mean and covariance bit-identical", "[sparse_joseph_update]") {
  for (const Form form : kForms) {
  INFO(name(form));
  est::Rng rng(42u);
  Mat P = random_spd(rng, 6);
  Vec mu = Vec::Constant(0.5f);
  const Mat P0 = P;
  const Vec mu0 = mu;
  est::SparseJacobian<1> H;
  H.add<2>(2, Eigen::Matrix<float, 1, 2>(0.6f, 0.8f));
  Eigen::Matrix<float, 1, 1> nu, Q;
  Q(0, 0) = 0.01f;
  const float s = std::sqrt((H.block[0].leftCols<2>() * P.block<2, 2>(2, 2) * H.block[0].leftCols<2>().transpose())(0, 0) + 0.01f);
  nu(0) = 5.0f * s;  // NIS 25 > 10.83
  auto r = update<1>(form, mu, P, 6, H, nu, Q, 10.828f);
  CHECK(r.status == est::CorrectionStatus::rejected_gate);
  CHECK(r.nis == Approx(25.0f).epsilon(1e-4));
  nu(0) = std::nanf("");
  CHECK(update<1>(form, mu, P, 6, H, nu, Q, 10.828f).status ==
        est::CorrectionStatus::rejected_nonfinite);
  nu(0) = 0.0f;
  Q(0, 0) = -1.0f;  // S not positive
  CHECK(update<1>(form, mu, P, 6, H, nu, Q, 10.828f).status ==
        est::CorrectionStatus::rejected_not_pd);
  Q(0, 0) = 0.01f;
  est::SparseJacobian<1> outside;
  outside.add<2>(5, Eigen::Matrix<float, 1, 2>(1.0f, 0.0f));  // reaches entry 6 of a 6-state
  CHECK(update<1>(form, mu, P, 6, outside, nu, Q, 10.828f).status ==
        est::CorrectionStatus::rejected_bad_input);
  CHECK(P == P0);
  CHECK(mu == mu0);
  }
}

TEST_CASE("the covariance floor keeps a perfectly measured variance positive", "[sparse_joseph_update]") {
  for (const Form form : kForms) {
  INFO(name(form));
  Mat P = Mat::Identity();
  Vec mu = Vec::Zero();
  est::SparseJacobian<1> H;
  H.add<1>(0, Eigen::Matrix<float, 1, 1>(1.0f));
  Eigen::Matrix<float, 1, 1> nu, Q;
  nu(0) = 0.1f;
  Q(0, 0) = 1e-12f;
  est::CovarianceGuard g;
  REQUIRE(update<1>(form, mu, P, 3, H, nu, Q, 0.0f, g).status == est::CorrectionStatus::accepted);
  CHECK(P(0, 0) >= g.variance_floor);
  CHECK(mu(0) == Approx(0.1f));
  }
}

TEST_CASE("the factored form refuses a measurement that would make a variance negative, and leaves the state as is",
          "[sparse_joseph_update]") {
  // A covariance that is not positive semidefinite (correlation 1.5): a measurement of x0 then drives P11 to
  // 1 - 1.5^2 < 0, beyond rounding: refused before anything is written.
  Mat P = Mat::Identity();
  P(0, 1) = P(1, 0) = 1.5f;
  Vec mu = Vec::Zero();
  const Mat P0 = P;
  est::SparseJacobian<1> H;
  H.add<1>(0, Eigen::Matrix<float, 1, 1>(1.0f));
  Eigen::Matrix<float, 1, 1> nu, Q;
  nu(0) = 0.1f;
  Q(0, 0) = 1e-6f;
  CHECK(est::sparse_factored_update<N, 1>(mu, P, 3, H, nu, Q, 0.0f, est::CovarianceGuard{}).status ==
        est::CorrectionStatus::rejected_not_pd);
  CHECK(P == P0);
  CHECK(mu == Vec::Zero());
}

TEST_CASE("the factored form agrees with the Joseph form within float rounding over a chain of updates",
          "[sparse_joseph_update]") {
  // 200 range-bearing-like updates of a 12-state through both forms from the same start: the two stay within
  // 2e-5 of each other relative to the largest entry, and both stay positive definite.
  est::Rng rng(43u);
  Mat Pj = random_spd(rng, N);
  Mat Pf = Pj;
  Vec mj = Vec::Zero(), mf = Vec::Zero();
  for (int t = 0; t < 200; ++t) {
    est::SparseJacobian<2> H;
    Eigen::Matrix<float, 2, 3> b0;
    Eigen::Matrix<float, 2, 2> b1;
    for (int i = 0; i < 6; ++i) b0(i % 2, i / 2) = rng.uniform(-1.0f, 1.0f);
    for (int i = 0; i < 4; ++i) b1(i % 2, i / 2) = rng.uniform(-1.0f, 1.0f);
    const int robot = 3 * static_cast<int>(rng.uniform(0.0f, 1.99f));
    const int landmark = 6 + 2 * static_cast<int>(rng.uniform(0.0f, 2.99f));
    H.add<3>(robot, b0);
    H.add<2>(landmark, b1);
    const Eigen::Vector2f nu(rng.uniform(-0.05f, 0.05f), rng.uniform(-0.05f, 0.05f));
    const Eigen::Matrix2f Q = Eigen::Vector2f(0.01f, 0.004f).asDiagonal();
    REQUIRE(update<2>(Form::joseph, mj, Pj, N, H, nu, Q, 0.0f).status == est::CorrectionStatus::accepted);
    REQUIRE(update<2>(Form::factored, mf, Pf, N, H, nu, Q, 0.0f).status == est::CorrectionStatus::accepted);
  }
  const float dP = (Pf - Pj).cwiseAbs().maxCoeff() / Pj.cwiseAbs().maxCoeff();
  const float dmu = (mf - mj).cwiseAbs().maxCoeff();
  std::printf("factored vs Joseph after 200 updates: covariance %.3g relative to its largest entry, mean %.3g\n",
              static_cast<double>(dP), static_cast<double>(dmu));
  CHECK(dP < 2e-5f);
  CHECK(dmu < 2e-5f);
  CHECK(Pf == Pf.transpose());
  CHECK(Pf.llt().info() == Eigen::Success);
  CHECK(Pj.llt().info() == Eigen::Success);
}

#pragma once
// Cooperative EKF-SLAM (Probabilistic Robotics ch. 10.2, table 10.1, generalized to a team): one Gaussian over the
// joint state of R <= R_max robots and M <= M_max landmarks. The robots share their controls u and measurements z
// every step and each runs this same filter, so each holds the same estimate: the filter is a pure function of the
// shared data and its order (fixed summation order everywhere), and per-robot instances fed the same data agree bit
// for bit.
//
// State layout: robot a at [D a, D a + D), landmark k at [D R + 2 k, D R + 2 k + 2); only the first n = D R + 2 M
// entries are active. D = Model::kStateDim: 2 for holonomic point robots (x_{k+1} = x_k + B u_k + w_k, the team
// exercise), 3 for any pose motion model of est/motion (velocity, odometry, differential drive ...).
//
// Prediction: each robot's block through its model's G, V, M (table 10.1 lines 3-5, with F_x replaced by the robot's
// rows): P_aa = G P_aa G^T + V M V^T, P_a* = G P_a*; O(n D^2) per robot, and only the noise is added when G = I.
// Measurements (each fused on its own, P+ = P - K S K^T formed as a Gram matrix W W^T on the upper triangle,
// est/filter/sparse_joseph_update.hpp's factored form, O(n^2 m) with m products per entry):
//   robot-robot range           |p_b - p_a|           H touches robots a and b
//   robot-landmark range        |m_k - p_a|           H touches robot a and landmark k (range-only, the exercise)
//   robot-landmark range/bearing (eq. 7.12)           H touches robot a and landmark k
//   robot-robot range/bearing (eq. 7.12, b as the landmark) H touches robots a and b
// H is never formed as a dense m x n matrix: only its one to three nonzero blocks.
//
// New landmarks: a range/bearing landmark enters the state at once through the inverse measurement with covariance
// G_r P_aa G_r^T + G_z Q G_z^T and correlation G_r P_a* (table 10.1 lines 9-10, done consistently). A range-only
// landmark is buffered (est/slam/range_only_initializer.hpp) until ranges from spread robot positions fix it.
//
// Observability and priors: ranges and bearings are relative, so they cannot tell where the whole team is. With
// point robots and ranges, translating all robots and landmarks together changes no measurement (2 unobservable
// directions; the controls, given in the world frame, make rotation observable once the robots move); with pose
// robots, controls in the robot frame and relative measurements, the team's global translation and rotation (3
// directions) are unobservable. The filter does not fix these directions by pinning a robot; they are held by the
// prior of init() (and add_landmark()): the initial covariance is the uncertainty of the team's frame, it never
// shrinks below what the prior gives along those directions, and the truth must be drawn from that prior for NEES
// to be consistent. With an improper (infinite) prior the EKF would lose positive definiteness.
#include <cstdint>

#include "est/eigen.hpp"
#include "est/filter/correction_status.hpp"
#include "est/filter/ekf_localization.hpp"  // PredictionCounters
#include "est/sensor/landmark_model.hpp"
#include "est/filter/landmark_measurement.hpp"
#include "est/filter/sparse_joseph_update.hpp"
#include "est/filter/state_vector.hpp"
#include "est/math/fmath.hpp"
#include "est/motion/motion_model.hpp"
#include "est/slam/range_only_initializer.hpp"

namespace est {

template <typename Model, int R_max, int M_max, int PendingLandmarks = 4, int ObservationsPerLandmark = 8>
class CooperativeEkfSlam {
 public:
  using State = typename Model::State;
  using Control = typename Model::Control;
  using MotionParams = typename Model::Params;
  using Traits = StateVector<State>;
  static constexpr int D = Model::kStateDim;
  static_assert(Traits::kDim == D, "the model's kStateDim must match its State");
  static_assert(R_max >= 1 && M_max >= 0, "capacities");
  static constexpr int N = D * R_max + 2 * M_max;
  using Vector = Eigen::Matrix<float, N, 1>;
  using Covariance = Eigen::Matrix<float, N, N>;
  using RobotVector = Eigen::Matrix<float, D, 1>;
  using RobotCovariance = Eigen::Matrix<float, D, D>;
  using Initializer = RangeOnlyInitializer<PendingLandmarks, ObservationsPerLandmark>;

  struct Params {
    InnovationGate gate;
    CovarianceGuard guard;
    RobotCovariance additive_process_noise = RobotCovariance::Zero();  // per robot per step, added to V M V^T
    RangeOnlyInitParams range_only_init;
  };

  CooperativeEkfSlam() = default;
  explicit CooperativeEkfSlam(const Params& p) : params_(p), init_(p.range_only_init) {}
  // New parameters in place (no temporary of the filter's size on the stack); call init() next.
  void configure(const Params& p) {
    params_ = p;
    init_ = Initializer(p.range_only_init);
  }

  // The team: `robots` robots with independent Gaussian priors (the priors that hold the unobservable directions).
  // Refused (false, filter emptied) for a bad count or a non-finite / non-positive-definite prior.
  // init() starts afresh: landmarks, pending initializations and counters are cleared.
  bool init(int robots, const State* means, const RobotCovariance* covs) {
    R_ = 0;
    M_ = 0;
    init_.clear();
    counters_ = CorrectionCounters{};
    prediction_counters_ = PredictionCounters{};
    last_nis_ = -1.0f;
    if (robots < 1 || robots > R_max) return false;
    mu_.setZero();
    P_.setZero();
    for (int a = 0; a < robots; ++a) {
      const RobotVector m = Traits::to_vector(means[a]);
      if (!m.allFinite() || !is_positive_definite<D>(covs[a])) return false;
      mu_.template segment<D>(D * a) = Traits::to_vector(Traits::from_vector(m));
      P_.template block<D, D>(D * a, D * a) = 0.5f * (covs[a] + covs[a].transpose());
    }
    for (int i = 0; i < N; ++i) angle_[i] = false;
    if constexpr (Traits::kHasHeading)
      for (int a = 0; a < robots; ++a) angle_[D * a + 2] = true;
    R_ = robots;
    return true;
  }

  // A landmark known a priori (mean, covariance, uncorrelated with the rest), e.g. the exercise's landmark.
  CorrectionStatus add_landmark(std::int32_t id, const Eigen::Vector2f& mean, const Eigen::Matrix2f& cov) {
    if (R_ == 0 || landmark_index(id) >= 0) return CorrectionStatus::rejected_bad_input;
    if (!mean.allFinite() || !is_positive_definite<2>(cov)) return CorrectionStatus::rejected_nonfinite;
    if (M_ >= M_max) return CorrectionStatus::rejected_capacity;
    const int o = dim();
    mu_.template segment<2>(o) = mean;
    for (int c = 0; c < o; ++c) P_(o, c) = P_(o + 1, c) = P_(c, o) = P_(c, o + 1) = 0.0f;
    P_.template block<2, 2>(o, o) = 0.5f * (cov + cov.transpose());
    ids_[M_++] = id;
    init_.forget(id);
    return CorrectionStatus::accepted;
  }

  // Robot a moves with control u (table 10.1 lines 3-5 on robot a's block). Refused controls leave the state as is.
  MotionStatus predict_robot(int a, const Control& u, const MotionParams& mp) {
    if (a < 0 || a >= R_) {
      ++prediction_counters_.rejected_range;
      return MotionStatus::rejected_range;
    }
    const MotionStatus st = Model::check(u, mp);
    if (!usable(st)) {
      (st == MotionStatus::rejected_nonfinite ? prediction_counters_.rejected_nonfinite
                                              : prediction_counters_.rejected_range)++;
      return st;
    }
    const int o = D * a;
    const RobotVector x_prev = mu_.template segment<D>(o);
    const State prev = Traits::from_vector(x_prev);
    const auto J = Model::jacobians(prev, u, mp);
    const RobotVector next = Traits::to_vector(Model::predict(prev, u, mp));
    RobotCovariance Q = J.V * J.M * J.V.transpose() + params_.additive_process_noise;
    if (!next.allFinite() || !J.G.allFinite() || !Q.allFinite()) {
      ++prediction_counters_.rejected_nonfinite;
      return MotionStatus::rejected_nonfinite;
    }
    const int n = dim();
    if (!J.G.isIdentity(0.0f)) {
      // Rows of robot a: P_a* = G P_a*; then the columns mirror them (P stays symmetric bit for bit).
      for (int c = 0; c < n; ++c) {
        if (c >= o && c < o + D) continue;
        float v[static_cast<unsigned>(D)];
        for (int i = 0; i < D; ++i) v[i] = P_(o + i, c);
        for (int i = 0; i < D; ++i) {
          float s = 0.0f;
          for (int k = 0; k < D; ++k) s += J.G(i, k) * v[k];
          P_(o + i, c) = s;
          P_(c, o + i) = s;
        }
      }
      const RobotCovariance Paa = P_.template block<D, D>(o, o);
      P_.template block<D, D>(o, o) = J.G * Paa * J.G.transpose();
    }
    RobotCovariance Paa = P_.template block<D, D>(o, o) + Q;
    for (int i = 0; i < D; ++i) {
      for (int k = i + 1; k < D; ++k) Paa(i, k) = Paa(k, i) = 0.5f * (Paa(i, k) + Paa(k, i));
      if (Paa(i, i) < params_.guard.variance_floor) Paa(i, i) = params_.guard.variance_floor;
    }
    P_.template block<D, D>(o, o) = Paa;
    mu_.template segment<D>(o) = next;
    ++prediction_counters_.accepted;
    return st;
  }

  // The shared controls of the whole team, robot 0 first; returns how many robots were predicted.
  int predict(const Control* u, const MotionParams& mp) {
    int ok = 0;
    for (int a = 0; a < R_; ++a) ok += usable(predict_robot(a, u[a], mp)) ? 1 : 0;
    return ok;
  }

  // Range measured from robot a to robot b.
  CorrectionResult correct_robot_range(int a, int b, float range, float sigma_range) {
    if (a < 0 || b < 0 || a >= R_ || b >= R_ || a == b || !(sigma_range > 0.0f))
      return count({CorrectionStatus::rejected_bad_input, -1.0f});
    if (!fmath::isfinite(range) || !fmath::isfinite(sigma_range))
      return count({CorrectionStatus::rejected_nonfinite, -1.0f});
    const RangeMeasurement h = range_measurement(position(D * a), position(D * b));
    if (!h.ok) return count({CorrectionStatus::rejected_bad_input, -1.0f});
    SparseJacobian<1> H;
    H.template add<2>(D * a, h.d_a);
    H.template add<2>(D * b, h.d_b);
    return fuse1(H, range - h.range, sigma_range);
  }

  // Range and bearing of robot b from robot a (eq. 7.12 with robot b's position as the landmark): the bearing in a's
  // frame for pose robots, in the world frame for point robots.
  CorrectionResult correct_robot_range_bearing(int a, int b, float range, float bearing, const LandmarkNoise& noise) {
    if (a < 0 || b < 0 || a >= R_ || b >= R_ || a == b || !(noise.sigma_range > 0.0f) || !(noise.sigma_bearing > 0.0f))
      return count({CorrectionStatus::rejected_bad_input, -1.0f});
    if (!fmath::isfinite(range) || !fmath::isfinite(bearing) || !fmath::isfinite(noise.sigma_range) ||
        !fmath::isfinite(noise.sigma_bearing))
      return count({CorrectionStatus::rejected_nonfinite, -1.0f});
    return count(fuse_range_bearing(a, D * b, range, bearing, noise));
  }

  // Range measured from robot a to landmark id; an id not yet in the state is buffered for its initialization
  // (pending_initialization), and enters the state when the ranges fix it.
  CorrectionResult correct_landmark_range(int a, std::int32_t id, float range, float sigma_range) {
    if (a < 0 || a >= R_ || !(sigma_range > 0.0f)) return count({CorrectionStatus::rejected_bad_input, -1.0f});
    if (!fmath::isfinite(range) || !fmath::isfinite(sigma_range))
      return count({CorrectionStatus::rejected_nonfinite, -1.0f});
    const int k = landmark_index(id);
    if (k < 0) return count(buffer_range(a, id, range, sigma_range));
    const int lo = landmark_offset(k);
    const RangeMeasurement h = range_measurement(position(D * a), position(lo));
    if (!h.ok) return count({CorrectionStatus::rejected_bad_input, -1.0f});
    SparseJacobian<1> H;
    H.template add<2>(D * a, h.d_a);
    H.template add<2>(lo, h.d_b);
    return fuse1(H, range - h.range, sigma_range);
  }

  // Range and bearing from robot a to landmark id (eq. 7.12); an unknown id is added to the state from this
  // measurement (table 10.1 lines 9-10), which is then not fused a second time.
  CorrectionResult correct_landmark_range_bearing(int a, std::int32_t id, float range, float bearing,
                                                  const LandmarkNoise& noise) {
    if (a < 0 || a >= R_ || !(noise.sigma_range > 0.0f) || !(noise.sigma_bearing > 0.0f))
      return count({CorrectionStatus::rejected_bad_input, -1.0f});
    if (!fmath::isfinite(range) || !fmath::isfinite(bearing) || !fmath::isfinite(noise.sigma_range) ||
        !fmath::isfinite(noise.sigma_bearing))
      return count({CorrectionStatus::rejected_nonfinite, -1.0f});
    Eigen::Matrix2f Q = Eigen::Matrix2f::Zero();
    Q(0, 0) = noise.sigma_range * noise.sigma_range;
    Q(1, 1) = noise.sigma_bearing * noise.sigma_bearing;
    const int k = landmark_index(id);
    if (k < 0) return count(insert_range_bearing(a, id, Eigen::Vector2f(range, bearing), Q));
    return count(fuse_range_bearing(a, landmark_offset(k), range, bearing, noise));
  }

  // Predicted range/bearing of landmark id from robot a, its innovation covariance S = H P H^T + Q, for gating and
  // data association outside the filter. False if a or id is unknown or the geometry is degenerate.
  bool predicted_range_bearing(int a, std::int32_t id, const LandmarkNoise& noise, Eigen::Vector2f* z_hat,
                               Eigen::Matrix2f* S) const {
    const int k = landmark_index(id);
    if (a < 0 || a >= R_ || k < 0) return false;
    const int lo = landmark_offset(k);
    const auto h = range_bearing_measurement<D>(RobotVector(mu_.template segment<D>(D * a)), position(lo));
    if (!h.ok) return false;
    const Eigen::Matrix<float, D, D> Paa = P_.template block<D, D>(D * a, D * a);
    const Eigen::Matrix<float, D, 2> Pal = P_.template block<D, 2>(D * a, lo);
    const Eigen::Matrix2f Pll = P_.template block<2, 2>(lo, lo);
    Eigen::Matrix2f s = h.H_robot * Paa * h.H_robot.transpose() + h.H_robot * Pal * h.H_landmark.transpose() +
                        h.H_landmark * Pal.transpose() * h.H_robot.transpose() +
                        h.H_landmark * Pll * h.H_landmark.transpose();
    s(0, 0) += noise.sigma_range * noise.sigma_range;
    s(1, 1) += noise.sigma_bearing * noise.sigma_bearing;
    *z_hat = h.z;
    *S = s;
    return true;
  }

  // Sizes and the estimate.
  int robots() const { return R_; }
  int landmarks() const { return M_; }
  int dim() const { return D * R_ + 2 * M_; }
  const Vector& mean() const { return mu_; }              // first dim() entries active
  const Covariance& covariance() const { return P_; }     // top-left dim() x dim() block active
  State robot(int a) const { return Traits::from_vector(mu_.template segment<D>(D * a)); }
  RobotCovariance robot_covariance(int a) const { return P_.template block<D, D>(D * a, D * a); }
  int robot_offset(int a) const { return D * a; }
  int landmark_offset(int k) const { return D * R_ + 2 * k; }
  Eigen::Vector2f landmark(int k) const { return mu_.template segment<2>(landmark_offset(k)); }
  std::int32_t landmark_id(int k) const { return ids_[k]; }
  // Slot of landmark id in the state, or -1 (a bounded scan of M entries).
  int landmark_index(std::int32_t id) const {
    for (int k = 0; k < M_; ++k)
      if (ids_[k] == id) return k;
    return -1;
  }
  const CorrectionCounters& counters() const { return counters_; }
  const PredictionCounters& prediction_counters() const { return prediction_counters_; }
  float last_nis() const { return last_nis_; }  // NIS of the last measurement that formed an innovation, or -1
  const Initializer& initializer() const { return init_; }
  const Params& params() const { return params_; }

  // Cheap O(n^2) necessary conditions for a valid covariance: exactly symmetric, finite, every variance at least the
  // floor, every correlation within [-1, 1] (up to float rounding). A full Cholesky check is O(n^3): tests do it.
  bool covariance_plausible() const {
    const int n = dim();
    for (int j = 0; j < n; ++j) {
      if (!fmath::isfinite(mu_(j)) || !(P_(j, j) >= params_.guard.variance_floor)) return false;
      for (int i = 0; i < j; ++i) {
        if (P_(i, j) != P_(j, i) || !fmath::isfinite(P_(i, j))) return false;
        if (P_(i, j) * P_(i, j) > 1.0001f * P_(i, i) * P_(j, j)) return false;
      }
    }
    return true;
  }

 private:
  Eigen::Vector2f position(int offset) const { return Eigen::Vector2f(mu_(offset), mu_(offset + 1)); }

  CorrectionResult fuse1(const SparseJacobian<1>& H, float innovation, float sigma) {
    Eigen::Matrix<float, 1, 1> nu, Q;
    nu(0) = innovation;
    Q(0, 0) = sigma * sigma;
    const CorrectionResult r =
        sparse_factored_update<N, 1>(mu_, P_, dim(), H, nu, Q, params_.gate.chi2_1dof, params_.guard, angle_);
    last_nis_ = r.nis;
    return count(r);
  }

  // Range and bearing from robot a to the point at `target` (a landmark, or another robot's position entries).
  CorrectionResult fuse_range_bearing(int a, int target, float range, float bearing, const LandmarkNoise& noise) {
    Eigen::Matrix2f Q = Eigen::Matrix2f::Zero();
    Q(0, 0) = noise.sigma_range * noise.sigma_range;
    Q(1, 1) = noise.sigma_bearing * noise.sigma_bearing;
    const RobotVector x = mu_.template segment<D>(D * a);
    const auto h = range_bearing_measurement<D>(x, position(target));
    if (!h.ok) return {CorrectionStatus::rejected_bad_input, -1.0f};
    SparseJacobian<2> H;
    H.template add<D>(D * a, h.H_robot);
    H.template add<2>(target, h.H_landmark);
    const Eigen::Vector2f nu(range - h.z(0), fmath::normalize_angle(bearing - h.z(1)));
    const CorrectionResult r =
        sparse_factored_update<N, 2>(mu_, P_, dim(), H, nu, Q, params_.gate.chi2_2dof, params_.guard, angle_);
    last_nis_ = r.nis;
    return r;
  }

  CorrectionResult buffer_range(int a, std::int32_t id, float range, float sigma) {
    if (M_ >= M_max) return {CorrectionStatus::rejected_capacity, -1.0f};
    RangeOnlyLandmark l;
    const Eigen::Matrix2f Ppos = P_.template block<2, 2>(D * a, D * a);
    const RangeOnlyInitStatus st = init_.add(id, position(D * a), Ppos, range, sigma * sigma, &l);
    switch (st) {
      case RangeOnlyInitStatus::ready:
        return {add_landmark(id, l.mean, l.covariance), -1.0f};
      case RangeOnlyInitStatus::rejected_input: return {CorrectionStatus::rejected_bad_input, -1.0f};
      case RangeOnlyInitStatus::rejected_capacity: return {CorrectionStatus::rejected_capacity, -1.0f};
      case RangeOnlyInitStatus::inconsistent: return {CorrectionStatus::rejected_gate, -1.0f};
      case RangeOnlyInitStatus::pending: break;
    }
    return {CorrectionStatus::pending_initialization, -1.0f};
  }

  // Table 10.1 lines 9-10 with the covariance carried through the inverse measurement.
  CorrectionResult insert_range_bearing(int a, std::int32_t id, const Eigen::Vector2f& z, const Eigen::Matrix2f& Q) {
    if (M_ >= M_max) return {CorrectionStatus::rejected_capacity, -1.0f};
    if (!(z(0) >= kMinMeasurementRange)) return {CorrectionStatus::rejected_bad_input, -1.0f};
    const int ra = D * a;
    const auto g = landmark_from_range_bearing<D>(RobotVector(mu_.template segment<D>(ra)), z);
    if (!g.m.allFinite()) return {CorrectionStatus::rejected_nonfinite, -1.0f};
    const int n = dim();
    const int o = n;
    // Cross terms G_r P_a* for every active column, then the landmark's own block.
    for (int c = 0; c < n; ++c) {
      for (int i = 0; i < 2; ++i) {
        float s = 0.0f;
        for (int k = 0; k < D; ++k) s += g.G_robot(i, k) * P_(ra + k, c);
        P_(o + i, c) = s;
        P_(c, o + i) = s;
      }
    }
    const RobotCovariance Paa = P_.template block<D, D>(ra, ra);
    Eigen::Matrix2f Pll = g.G_robot * Paa * g.G_robot.transpose() + g.G_z * Q * g.G_z.transpose();
    Pll(0, 1) = Pll(1, 0) = 0.5f * (Pll(0, 1) + Pll(1, 0));
    for (int i = 0; i < 2; ++i)
      if (Pll(i, i) < params_.guard.variance_floor) Pll(i, i) = params_.guard.variance_floor;
    P_.template block<2, 2>(o, o) = Pll;
    mu_.template segment<2>(o) = g.m;
    ids_[M_++] = id;
    return {CorrectionStatus::accepted, -1.0f};
  }

  CorrectionResult count(const CorrectionResult& r) {
    counters_.count(r.status);
    return r;
  }

  Params params_{};
  Initializer init_{};
  int R_ = 0;
  int M_ = 0;
  Vector mu_ = Vector::Zero();
  Covariance P_ = Covariance::Zero();
  bool angle_[static_cast<unsigned>(N)] = {};
  std::int32_t ids_[static_cast<unsigned>(M_max > 0 ? M_max : 1)] = {};
  CorrectionCounters counters_{};
  PredictionCounters prediction_counters_{};
  float last_nis_ = -1.0f;
};

}  // namespace est

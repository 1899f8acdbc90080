#pragma once
// EKF localization (Probabilistic Robotics ch. 7.4-7.5): a Gaussian over the robot state, predicted through any
// motion model of est/motion (its G, V, M; table 7.2 lines 2-7) and corrected with landmarks of a known map:
//   correct_range_bearing            table 7.2 lines 8-20, known correspondence (the landmark's index in the map)
//   correct_range_bearing_unknown    table 7.3, the correspondence by maximum likelihood among the landmarks whose
//                                    Mahalanobis distance passes the gate (and whose signature agrees); with
//                                    Params::ambiguity_nats > 0, refused when a second landmark's likelihood is
//                                    within that many nats of the best: table 7.3 takes the maximum even when it is
//                                    a coin toss, and one wrong association pulls the estimate towards the wrong
//                                    landmark, where the next ones then agree with it (the filter is lost)
//   correct_range                    a range-only beacon (one row of the same model)
// Every measurement is fused one at a time (the book's loop over features), with the Joseph-form update of
// est/filter/sparse_joseph_update.hpp; the updated covariance is checked by Cholesky before it is committed, so a
// measurement that would make it non-positive-definite is refused and the estimate kept. Every refusal is counted by
// reason (counters()); the estimate is never NaN: non-finite input never reaches it.
//
// Measurements and noise are the sensor model's (est/sensor/landmark_model.hpp: range, bearing in the robot frame,
// signature). A point robot (D = 2) has no heading: its bearings are taken in the world frame.
// Signatures: in table 7.2 the signature row of H is zero, so with a known correspondence it cannot move the state
// and is not fused; with unknown correspondence it enters the likelihood (and the gate) as a third, independent
// dimension with standard deviation sigma_signature; sigma_signature <= 0 means signatures are not measured.
#include <cstdint>

#include "est/eigen.hpp"
#include "est/filter/correction_status.hpp"
#include "est/filter/covariance_check.hpp"
#include "est/filter/landmark_measurement.hpp"
#include "est/filter/sparse_joseph_update.hpp"
#include "est/filter/state_vector.hpp"
#include "est/map/landmark_map.hpp"
#include "est/math/fmath.hpp"
#include "est/motion/motion_model.hpp"
#include "est/sensor/landmark_model.hpp"

namespace est {

// Counts of predictions refused by the motion model's check() (the estimate is then left unchanged).
struct PredictionCounters {
  std::uint32_t accepted = 0;
  std::uint32_t rejected_nonfinite = 0;
  std::uint32_t rejected_range = 0;
};

// Process noise that grows with the motion of a prediction rather than with its duration: variances per metre driven
// and per radian turned (the predicted mean's change), added in the robot's frame along the step's chord (the
// heading halfway through an arc). A random walk over the path, not over time (the book's M_t, var = a v^2 dt^2 per step, shrinks with the
// step and vanishes at high rates; a constant noise per step diffuses the heading while the robot drives straight
// or stands still): a robot that does not turn does not lose heading by turning. Zero by default; each >= 0.
struct MotionProportionalNoise {
  float along_per_m = 0.0f;      // m^2 along the heading per m driven
  float cross_per_m = 0.0f;      // m^2 across the heading per m driven
  float heading_per_m = 0.0f;    // rad^2 per m driven
  float heading_per_rad = 0.0f;  // rad^2 per rad turned
};

// Which landmark a measurement was fused with (-1 if none) and how.
struct AssociationResult {
  CorrectionResult correction;
  std::int32_t landmark = -1;
};

template <typename Model>
class EkfLocalization {
 public:
  using State = typename Model::State;
  using Control = typename Model::Control;
  using MotionParams = typename Model::Params;
  using Traits = StateVector<State>;
  static constexpr int D = Model::kStateDim;
  static_assert(Traits::kDim == D, "the model's kStateDim must match its State");
  using Vector = Eigen::Matrix<float, D, 1>;
  using Covariance = Eigen::Matrix<float, D, D>;

  struct Params {
    InnovationGate gate;
    CovarianceGuard guard;
    // Added to V M V^T every prediction: unmodelled motion (slip, the velocity model's final turn gamma). Zero by
    // default; must be symmetric positive semi-definite.
    Covariance additive_process_noise = Covariance::Zero();
    // Added every prediction in proportion to the predicted motion (a model with a heading only).
    MotionProportionalNoise motion_noise{};
    // Unknown correspondence: the least margin (log likelihood, nats) of the best gated landmark over the second
    // for a measurement to be fused; 0 fuses the maximum whatever the margin (table 7.3 as printed).
    float ambiguity_nats = 0.0f;
  };

  EkfLocalization() = default;
  explicit EkfLocalization(const Params& p) : params_(p) {}

  // Start from mean and covariance; refused (false, nothing changed) if not finite or not positive definite.
  bool init(const State& mean, const Covariance& cov) {
    const Vector m = Traits::to_vector(mean);
    for (int i = 0; i < D; ++i)
      if (!fmath::isfinite(m(i))) return false;
    if (!is_positive_definite<D>(cov)) return false;
    mu_ = Traits::to_vector(Traits::from_vector(m));
    P_ = 0.5f * (cov + cov.transpose());
    return true;
  }

  // Table 7.2 lines 2-7: mu = g(u, mu), Sigma = G Sigma G^T + V M V^T (+ the additive noise).
  MotionStatus predict(const Control& u, const MotionParams& mp) {
    const MotionStatus st = Model::check(u, mp);
    if (!usable(st)) {
      (st == MotionStatus::rejected_nonfinite ? prediction_counters_.rejected_nonfinite
                                              : prediction_counters_.rejected_range)++;
      return st;
    }
    const State prev = Traits::from_vector(mu_);
    const auto J = Model::jacobians(prev, u, mp);
    const Vector next = Traits::to_vector(Model::predict(prev, u, mp));
    Covariance P = J.G * P_ * J.G.transpose() + J.V * J.M * J.V.transpose() + params_.additive_process_noise;
    if constexpr (Traits::kHasHeading) add_motion_noise(mu_, next, P);
    P = (0.5f * (P + P.transpose())).eval();
    for (int i = 0; i < D; ++i) {
      if (!fmath::isfinite(next(i))) {
        ++prediction_counters_.rejected_nonfinite;
        return MotionStatus::rejected_nonfinite;
      }
      if (P(i, i) < params_.guard.variance_floor) P(i, i) = params_.guard.variance_floor;
    }
    if (!is_positive_definite<D>(P)) {
      ++prediction_counters_.rejected_nonfinite;
      return MotionStatus::rejected_nonfinite;
    }
    mu_ = next;
    P_ = P;
    ++prediction_counters_.accepted;
    return st;
  }

  // Table 7.2 lines 8-20 for one feature whose correspondence j (index in the map) is known.
  CorrectionResult correct_range_bearing(const LandmarkMeasurement& z, const LandmarkMap& map, std::int32_t j,
                                         const LandmarkNoise& noise) {
    return count(correct_rb(z, map, j, noise));
  }

  // Table 7.3 for one feature: the correspondence maximizing the measurement likelihood among the landmarks that
  // pass the gate; rejected_gate if none does (then nothing is fused), rejected_unknown_landmark if the map is empty.
  AssociationResult correct_range_bearing_unknown(const LandmarkMeasurement& z, const LandmarkMap& map,
                                                  const LandmarkNoise& noise) {
    AssociationResult out;
    out.landmark = associate(z, map, noise, &out.correction.nis);
    if (out.landmark < 0) {
      out.correction.status = out.landmark == kNoLandmark  ? CorrectionStatus::rejected_unknown_landmark
                              : out.landmark == kAmbiguous ? CorrectionStatus::rejected_ambiguous
                                                           : CorrectionStatus::rejected_gate;
      count(out.correction);
      out.landmark = -1;
      return out;
    }
    out.correction = count(correct_rb(z, map, out.landmark, noise));
    if (!accepted(out.correction.status)) out.landmark = -1;
    return out;
  }

  // A range-only beacon at map index j, range standard deviation sigma_range.
  CorrectionResult correct_range(float range, const LandmarkMap& map, std::int32_t j, float sigma_range) {
    if (!map.contains(j)) return count({CorrectionStatus::rejected_unknown_landmark, -1.0f});
    if (!fmath::isfinite(range) || !fmath::isfinite(sigma_range)) return count({CorrectionStatus::rejected_nonfinite, -1.0f});
    if (!(sigma_range > 0.0f)) return count({CorrectionStatus::rejected_bad_input, -1.0f});
    const Eigen::Vector2f m(map[j].x, map[j].y);
    const RangeMeasurement h = range_measurement(Eigen::Vector2f(mu_(0), mu_(1)), m);
    if (!h.ok) return count({CorrectionStatus::rejected_bad_input, -1.0f});
    SparseJacobian<1> H;
    Eigen::Matrix<float, 1, D> row = Eigen::Matrix<float, 1, D>::Zero();
    row.template leftCols<2>() = h.d_a;
    H.add<D>(0, row);
    Eigen::Matrix<float, 1, 1> nu, Q;
    nu(0) = range - h.range;
    Q(0, 0) = sigma_range * sigma_range;
    return count(commit(H, nu, Q));
  }

  State mean() const { return Traits::from_vector(mu_); }
  const Vector& mean_vector() const { return mu_; }
  const Covariance& covariance() const { return P_; }
  const CorrectionCounters& counters() const { return counters_; }
  const PredictionCounters& prediction_counters() const { return prediction_counters_; }
  const Params& params() const { return params_; }

 private:
  static constexpr std::int32_t kNoLandmark = -2;
  static constexpr std::int32_t kAmbiguous = -3;

  // MotionProportionalNoise over the step from `from` to `to`, rotated into the world frame along the chord.
  void add_motion_noise(const Vector& from, const Vector& to, Covariance& P) const {
    const MotionProportionalNoise& q = params_.motion_noise;
    if (!(q.along_per_m > 0.0f || q.cross_per_m > 0.0f || q.heading_per_m > 0.0f || q.heading_per_rad > 0.0f))
      return;  // none configured: the prediction's cost and bits as without it
    const float dx = to(0) - from(0), dy = to(1) - from(1);
    const float dist = fmath::sqrt(dx * dx + dy * dy);
    const float dtheta = fmath::normalize_angle(to(2) - from(2));
    const float turned = fmath::abs(dtheta);
    const float a = q.along_per_m * dist, c = q.cross_per_m * dist;
    if ((a > 0.0f || c > 0.0f) && dist > 0.0f) {
      // The chord's direction: the heading halfway through an arc (theta + w dt / 2), without a sine or cosine.
      const float cs = dx / dist, sn = dy / dist;
      P(0, 0) += a * cs * cs + c * sn * sn;
      P(1, 1) += a * sn * sn + c * cs * cs;
      const float xy = (a - c) * cs * sn;
      P(0, 1) += xy;
      P(1, 0) += xy;
    }
    P(2, 2) += q.heading_per_m * dist + q.heading_per_rad * turned;
  }

  static Eigen::Matrix2f q_of(const LandmarkNoise& n) {
    Eigen::Matrix2f Q = Eigen::Matrix2f::Zero();
    Q(0, 0) = n.sigma_range * n.sigma_range;
    Q(1, 1) = n.sigma_bearing * n.sigma_bearing;
    return Q;
  }
  static bool noise_ok(const LandmarkNoise& n) {
    return fmath::isfinite(n.sigma_range) && fmath::isfinite(n.sigma_bearing) && fmath::isfinite(n.sigma_signature) &&
           n.sigma_range > 0.0f && n.sigma_bearing > 0.0f;
  }

  CorrectionResult correct_rb(const LandmarkMeasurement& z, const LandmarkMap& map, std::int32_t j,
                              const LandmarkNoise& noise) {
    if (!map.contains(j)) return {CorrectionStatus::rejected_unknown_landmark, -1.0f};
    if (!fmath::isfinite(z.range) || !fmath::isfinite(z.bearing)) return {CorrectionStatus::rejected_nonfinite, -1.0f};
    if (!noise_ok(noise)) return {CorrectionStatus::rejected_bad_input, -1.0f};
    const auto h = range_bearing_measurement<D>(mu_, Eigen::Vector2f(map[j].x, map[j].y));
    if (!h.ok) return {CorrectionStatus::rejected_bad_input, -1.0f};
    SparseJacobian<2> H;
    H.add<D>(0, h.H_robot);
    Eigen::Vector2f nu(z.range - h.z(0), fmath::normalize_angle(z.bearing - h.z(1)));
    return commit(H, nu, q_of(noise));
  }

  // Fuses into a copy, and commits only a positive-definite result.
  template <int Mdim>
  CorrectionResult commit(const SparseJacobian<Mdim>& H, const Eigen::Matrix<float, Mdim, 1>& nu,
                          const Eigen::Matrix<float, Mdim, Mdim>& Q) {
    Vector mu = mu_;
    Covariance P = P_;
    const CorrectionResult r = sparse_joseph_update<D, Mdim>(mu, P, D, H, nu, Q, params_.gate.for_dim(Mdim),
                                                             params_.guard, kAngleMask);
    if (!accepted(r.status)) return r;
    if (!is_positive_definite<D>(P)) return {CorrectionStatus::rejected_not_pd, r.nis};
    mu_ = mu;
    P_ = P;
    return r;
  }

  // Maximum likelihood over the map (table 7.3 lines 9-18) with gating; returns the index, -1 if none passes the
  // gate, kNoLandmark if the map is empty, kAmbiguous if the runner-up is within ambiguity_nats of the winner.
  // *best_nis gets the NIS of the winner (or the smallest seen).
  std::int32_t associate(const LandmarkMeasurement& z, const LandmarkMap& map, const LandmarkNoise& noise,
                         float* best_nis) const {
    if (map.size() <= 0) return kNoLandmark;
    if (!fmath::isfinite(z.range) || !fmath::isfinite(z.bearing) || !fmath::isfinite(z.signature) || !noise_ok(noise))
      return -1;
    const Eigen::Matrix2f Q = q_of(noise);
    const bool use_signature = noise.sigma_signature > 0.0f;
    const float gate = use_signature ? params_.gate.chi2_3dof : params_.gate.chi2_2dof;
    std::int32_t best = -1;
    float best_score = 0.0f, second_score = 0.0f;
    bool has_second = false;
    float smallest = -1.0f;
    for (std::int32_t k = 0; k < map.size(); ++k) {  // bounded by the map's size
      const Landmark& l = map[k];
      const auto h = range_bearing_measurement<D>(mu_, Eigen::Vector2f(l.x, l.y));
      if (!h.ok) continue;
      const Eigen::Matrix2f S = h.H_robot * P_ * h.H_robot.transpose() + Q;
      const float det = S(0, 0) * S(1, 1) - S(0, 1) * S(1, 0);
      if (!(det > 0.0f) || !(S(0, 0) > 0.0f)) continue;
      const Eigen::Vector2f nu(z.range - h.z(0), fmath::normalize_angle(z.bearing - h.z(1)));
      float d2 = (nu(0) * S(1, 1) * nu(0) - 2.0f * nu(0) * S(0, 1) * nu(1) + nu(1) * S(0, 0) * nu(1)) / det;
      float log_det = fmath::log(det);
      if (use_signature) {
        const float ds = (z.signature - l.signature) / noise.sigma_signature;
        d2 += ds * ds;
        log_det += 2.0f * fmath::log(noise.sigma_signature);
      }
      if (!fmath::isfinite(d2)) continue;
      if (smallest < 0.0f || d2 < smallest) smallest = d2;
      if (gate > 0.0f && d2 > gate) continue;
      const float score = -0.5f * d2 - 0.5f * log_det;  // log N(z; z_hat_k, S_k) up to a constant
      if (best < 0 || score > best_score) {
        if (best >= 0) second_score = best_score, has_second = true;
        best = k;
        best_score = score;
        *best_nis = d2;
      } else if (!has_second || score > second_score) {
        second_score = score;
        has_second = true;
      }
    }
    if (best < 0) *best_nis = smallest;
    if (best >= 0 && has_second && best_score - second_score < params_.ambiguity_nats) return kAmbiguous;
    return best;
  }

  CorrectionResult count(const CorrectionResult& r) {
    counters_.count(r.status);
    return r;
  }

  static constexpr bool kAngleMask[static_cast<unsigned>(D > 2 ? D : 3)] = {false, false, Traits::kHasHeading};

  Params params_{};
  Vector mu_ = Vector::Zero();
  Covariance P_ = Covariance::Identity();
  CorrectionCounters counters_{};
  PredictionCounters prediction_counters_{};
};

}  // namespace est

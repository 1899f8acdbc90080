#pragma once
// What became of a measurement offered to a Gaussian filter, and the counters that keep every refusal visible.
#include <cstdint>

namespace est {

enum class CorrectionStatus : std::uint8_t {
  accepted = 0,
  rejected_gate,              // the innovation's Mahalanobis distance exceeded the gate (an outlier)
  rejected_nonfinite,         // NaN or infinite measurement, noise, prediction or Jacobian
  rejected_not_pd,            // the innovation covariance, or the updated covariance, would not be positive definite
  rejected_unknown_landmark,  // the correspondence names no landmark of the map / state
  rejected_bad_input,         // a robot index out of range, a robot measuring itself, negative noise, zero range
  rejected_capacity,          // the state or the initializer is full
  pending_initialization,     // range-only landmark not yet in the state: kept for its initialization, not fused
  rejected_ambiguous,         // unknown correspondence: another landmark explains the measurement almost as well
};

constexpr bool accepted(CorrectionStatus s) { return s == CorrectionStatus::accepted; }

// One counter per outcome; the sum equals the number of measurements offered.
struct CorrectionCounters {
  std::uint32_t accepted = 0;
  std::uint32_t gated_out = 0;
  std::uint32_t nonfinite = 0;
  std::uint32_t not_pd = 0;
  std::uint32_t unknown_landmark = 0;
  std::uint32_t bad_input = 0;
  std::uint32_t capacity = 0;
  std::uint32_t pending = 0;
  std::uint32_t ambiguous = 0;

  void count(CorrectionStatus s) {
    switch (s) {
      case CorrectionStatus::accepted: ++accepted; break;
      case CorrectionStatus::rejected_gate: ++gated_out; break;
      case CorrectionStatus::rejected_nonfinite: ++nonfinite; break;
      case CorrectionStatus::rejected_not_pd: ++not_pd; break;
      case CorrectionStatus::rejected_unknown_landmark: ++unknown_landmark; break;
      case CorrectionStatus::rejected_bad_input: ++bad_input; break;
      case CorrectionStatus::rejected_capacity: ++capacity; break;
      case CorrectionStatus::pending_initialization: ++pending; break;
      case CorrectionStatus::rejected_ambiguous: ++ambiguous; break;
    }
  }
  std::uint32_t rejected() const {
    return gated_out + nonfinite + not_pd + unknown_landmark + bad_input + capacity + ambiguous;
  }
  std::uint32_t total() const { return accepted + rejected() + pending; }
};

// Chi-square gates on the normalized innovation squared, per measurement dimension. The defaults pass 99.9 % of
// correct measurements (chi2 quantiles 10.83, 13.82, 16.27 for 1, 2, 3 dof), so a 5-sigma fault (NIS >= 25) is
// refused. A gate <= 0 disables gating.
struct InnovationGate {
  float chi2_1dof = 10.828f;
  float chi2_2dof = 13.816f;
  float chi2_3dof = 16.266f;
  float for_dim(int m) const { return m == 1 ? chi2_1dof : (m == 2 ? chi2_2dof : chi2_3dof); }
};

// Result of one correction: the status and, when the innovation was formed, its NIS (nu^T S^-1 nu), else -1.
struct CorrectionResult {
  CorrectionStatus status = CorrectionStatus::rejected_bad_input;
  float nis = -1.0f;
};

}  // namespace est

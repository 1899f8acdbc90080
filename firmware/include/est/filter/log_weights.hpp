#pragma once
// Importance weights kept in log space: normalization by log-sum-exp and the effective sample size
// (Thrun ch. 4.3.4; Doucet et al. 2000). Never NaN: weights that are all -inf or NaN are reported as degenerate.
#include <cstdint>

#include "est/math/fmath.hpp"
#include "est/math/inline_exp.hpp"
#include "est/math/normal.hpp"

namespace est {


struct LogNormalization {
  float log_sum;      // log of the sum of the unnormalized weights (the log marginal likelihood of the step + const)
  bool degenerate;    // every weight was -inf or NaN: weights were reset to uniform
  std::uint32_t nonfinite;  // weights that were NaN or +inf and were treated as log 0
};

// Subtracts log-sum-exp from every log weight so that sum(exp(log_w)) = 1.
inline LogNormalization normalize_log_weights(float* log_w, std::uint32_t n) {
  LogNormalization r{kLogZero, false, 0u};
  if (n == 0u) return r;
  float max_lw = kLogZero;
  for (std::uint32_t i = 0; i < n; ++i) {
    const float lw = log_w[i];
    if (!(lw <= 3.0e38f)) {  // NaN or +inf: a sensor model fault, never a certainty
      log_w[i] = kLogZero;
      ++r.nonfinite;
    } else if (lw < kLogZero) {
      log_w[i] = kLogZero;
    }
    if (log_w[i] > max_lw) max_lw = log_w[i];
  }
  if (max_lw <= kLogZero) {
    const float uniform = -fmath::log(static_cast<float>(n));
    for (std::uint32_t i = 0; i < n; ++i) log_w[i] = uniform;
    r.degenerate = true;
    return r;
  }
  float sum = 0.0f;
  for (std::uint32_t i = 0; i < n; ++i) sum += imath::exp(log_w[i] - max_lw);  // fmath::exp's bits, inline
  // (lw - max) is exact for nearby weights (Sterbenz), so normalized weights keep float's relative precision even
  // when every log weight is around -1000; subtracting the rounded log_sum instead would not.
  const float log_sum_rel = fmath::log(sum);
  for (std::uint32_t i = 0; i < n; ++i) log_w[i] = (log_w[i] - max_lw) - log_sum_rel;
  r.log_sum = max_lw + log_sum_rel;
  return r;
}

// Effective sample size 1 / sum(w_i^2) of normalized log weights, in [1, n].
inline float effective_sample_size(const float* log_w, std::uint32_t n) {
  float s = 0.0f;
  for (std::uint32_t i = 0; i < n; ++i) {
    const float w = imath::exp(log_w[i]);  // fmath::exp's bits, inline
    s += w * w;
  }
  return s > 0.0f ? 1.0f / s : 1.0f;
}

}  // namespace est

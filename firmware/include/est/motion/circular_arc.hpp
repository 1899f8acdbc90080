#pragma once
// Planar motion along a circular arc (constant speed and turn rate over the step), in chord form: after arc length s
// with heading change delta = 2h, the point has moved s * sinc(h) along the start direction turned by h. This is
// Thrun eq. 5.9 without the 1/omega, so the straight limit (h -> 0) needs no special case. Shared by the bicycle,
// differential-drive and omnidirectional models, which differ only in what sets s, h and the start direction.
#include <cstdint>

#include "est/math/fmath.hpp"

namespace est::arc {

// Below this |h| the quotients sin(h)/h and (cos h - sinc h)/h lose digits in float; the series are used instead
// (their truncation error at |h| = 0.1 is below 1e-9 relative).
inline constexpr float kSeriesBelow = 0.1f;

// sin(h) / h, equal to 1 at h = 0.
inline float sinc(float h) {
  if (fmath::abs(h) < kSeriesBelow) {
    const float h2 = h * h;
    return 1.0f - h2 * (1.0f / 6.0f) + h2 * h2 * (1.0f / 120.0f);
  }
  return fmath::sin(h) / h;
}

// d sinc / dh = (cos h - sinc h) / h, equal to 0 at h = 0.
inline float sinc_derivative(float h) {
  if (fmath::abs(h) < kSeriesBelow) {
    const float h2 = h * h;
    return h * (-1.0f / 3.0f + h2 * (1.0f / 30.0f) - h2 * h2 * (1.0f / 840.0f));
  }
  float s = 0.0f;
  float c = 0.0f;
  fmath::sincos(h, s, c);
  return (c - s / h) / h;
}

// One preimage of a chord: arc length s (signed: negative is backwards) and half heading change h.
struct ArcPreimage {
  float s;
  float h;
  bool ok;  // false when this branch does not exist (sinc(h) = 0 in float)
};

// Every arc that starts at the origin along +x and ends at (cx, cy) has h = h0 + m pi for an integer m (each step
// of m is one more full turn of the heading, since delta = 2h) and s = rho_m / sinc(h_m), where the signed chord
// length rho_m = +-|c| alternates with m. Branch m = 0 is the one with |delta| <= pi.
inline ArcPreimage arc_preimage(float cx, float cy, std::int32_t m) {
  const float len = fmath::sqrt(cx * cx + cy * cy);
  float h = fmath::atan2(cy, cx);
  float rho = len;
  // Fold the chord direction into (-pi/2, pi/2]: a chord pointing backwards is a backwards arc.
  if (h > kHalfPi) {
    h -= kPi;
    rho = -rho;
  } else if (h <= -kHalfPi) {
    h += kPi;
    rho = -rho;
  }
  h += static_cast<float>(m) * kPi;
  if ((m & 1) != 0) rho = -rho;
  const float sc = sinc(h);
  if (sc == 0.0f) return {0.0f, h, false};
  return {rho / sc, h, true};
}

}  // namespace est::arc

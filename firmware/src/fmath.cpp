// PROVISIONAL: libm-backed placeholders so the API exists; replaced by the firmware's own implementations.
#include "est/math/fmath.hpp"

namespace est::fmath {

float sin(float x) { return __builtin_sinf(x); }
float cos(float x) { return __builtin_cosf(x); }
void sincos(float x, float& s, float& c) {
  s = sin(x);
  c = cos(x);
}
float atan2(float y, float x) { return __builtin_atan2f(y, x); }
float exp(float x) { return __builtin_expf(x); }
float log(float x) { return __builtin_logf(x); }
float normalize_angle(float a) {
  float r = __builtin_remainderf(a, kTwoPi);
  if (r <= -kPi) r += kTwoPi;
  return r;
}

}  // namespace est::fmath

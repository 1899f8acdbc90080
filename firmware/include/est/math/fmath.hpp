#pragma once
// The firmware's own float math: the same bits on glibc and newlib, because no libm transcendental is called.
// Pure float and 32/64-bit integer arithmetic (no double, no long double), so with -ffp-contract=off every target
// that has IEEE 754 binary32 with round-to-nearest gives identical results.
// Accuracy (ULP against a long double reference) is stated per function and tested in tests/test_fmath.cpp.
//
// Conventions for every function here:
// - ULP: |result - exact| / ulp(exact), ulp(y) = 2^(floor(log2 |y|) - 23), and 2^-149 below 2^-126.
// - NaN in, NaN out; every NaN result is the default quiet NaN 0x7fc00000 (the same bits on every target),
//   whatever the input NaN.
// - Subnormal inputs and results are handled (gradual underflow, nothing is flushed to zero); the boards run with
//   the FPU's flush-to-zero off (the reset default), the host without -ffast-math.
#include <cstdint>

namespace est {

inline constexpr float kPi = 3.14159265358979323846f;
inline constexpr float kTwoPi = 6.28318530717958647692f;
inline constexpr float kHalfPi = 1.57079632679489661923f;

namespace fmath {

// Measured maxima below: "every float" = an exhaustive run over the floats named against glibc's long double
// functions (offline); "sampled" = the sweeps of tests/test_fmath.cpp (millions of points, every
// binade).
//
// sin, cos: <= 1 ULP for every finite x (max 0.85 ULP over every float in [0.5, 1), every 7th in [1, 200) and every
// 97th above; 0.83 sampled by the test). The argument is reduced by pi/2 exactly: Cody-Waite with a three-part pi/2
// for |x| < 200, integer Payne-Hanek with 2/pi to 288 bits above, so even sin(1e38f) is right. sin(+-0) = +-0,
// sin(+-inf) = cos(+-inf) = NaN.
float sin(float x);
float cos(float x);
// Exactly the bits of sin(x) and cos(x), for the cost of one reduction.
void sincos(float x, float& s, float& c);
// atan: <= 1 ULP for every x (max 0.85 ULP sampled); atan(+-inf) = +-float(pi/2), atan(+-0) = +-0.
float atan(float x);
// atan2: <= 2 ULP for every pair of finite or infinite arguments (max 1.45 ULP sampled over all quadrants and
// exponent differences), result in [-pi, pi]. Signs and special values as IEEE 754 / C99 Annex F:
// atan2(+-0, +0) = +-0, atan2(+-0, -0) = +-pi, atan2(+-y, -inf) = +-pi, atan2(+-inf, +-inf) = +-pi/4 or +-3pi/4,
// atan2(+-inf, x) = +-pi/2; a NaN argument gives NaN.
float atan2(float y, float x);
// exp: <= 1 ULP for every x (max 0.9954 ULP, every float of both signs). x >= 88.72284 (0x42b17218, where the
// exact result rounds beyond FLT_MAX) gives +inf; results below 2^-126 are subnormal, rounded once (gradual
// underflow: the error is <= 1 ULP of the subnormal spacing 2^-149); x <= -103.97208 (0xc2cff1b5) gives +0.
// exp(-inf) = +0, exp(+inf) = +inf.
float exp(float x);
// log: <= 1 ULP for every positive float, subnormals included (max 0.88 ULP, every float in [0.5, 1) and sampled
// over all binades); log(+-0) = -inf, log(x < 0) = NaN (also log(-inf)), log(+inf) = +inf, log(1) = +0.
float log(float x);
// Correctly rounded on every target (IEEE 754 requires it of the hardware instruction and of libm). Negative and NaN
// arguments give the canonical NaN here: the x86 instruction and newlib's sqrtf return different NaN bits.
inline float sqrt(float x) { return x >= 0.0f ? __builtin_sqrtf(x) : __builtin_nanf(""); }

// Angle wrapped to (-pi, pi], pi being the float kPi: the identity on (-kPi, kPi], kPi -> kPi and -kPi -> kPi.
// Outside, the exact remainder modulo the real 2 pi (the same reduction as sin and cos, right for every finite a),
// within 1 ULP (max 0.75 ULP sampled) and never outside (-kPi, kPi]. Non-finite input (NaN, +-inf: no angle) gives
// NaN; callers check finiteness, as the filters do.
float normalize_angle(float a);

inline bool isfinite(float x) { return __builtin_isfinite(x); }
inline float abs(float x) { return __builtin_fabsf(x); }

}  // namespace fmath
}  // namespace est

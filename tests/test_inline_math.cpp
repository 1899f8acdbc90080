#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>

#include "est/math/fmath.hpp"
#include "est/math/inline_math.hpp"

namespace {

// Error in units of the result's ULP, or in units of 2^-27 absolute near zero (whichever is more lenient), against
// the long double value.
double ulp_error(float got, long double exact) {
  const long double a = std::fabs(exact);
  const long double ulp = a < 1e-30L ? 1e-45L : std::ldexp(1.0L, std::ilogb(a) - 23);
  const long double abs_unit = std::ldexp(1.0L, -27);
  return static_cast<double>(std::fabs(static_cast<long double>(got) - exact) / std::max(ulp, abs_unit));
}

}  // namespace

TEST_CASE("sincos_moderate is within 2 ULP (or 2^-26 absolute) on |x| <= 64", "[inline_math]") {
  double worst = 0.0;
  const int n = 400000;
  for (int i = 0; i <= n; ++i) {
    const float x = -64.0f + 128.0f * static_cast<float>(i) / static_cast<float>(n);
    float s = 0.0f, c = 0.0f;
    est::imath::sincos_moderate(x, s, c);
    worst = std::max(worst, ulp_error(s, std::sin(static_cast<long double>(x))));
    worst = std::max(worst, ulp_error(c, std::cos(static_cast<long double>(x))));
  }
  INFO("worst error " << worst << " (ULP or 2^-27)");
  CHECK(worst <= 2.0);
}

TEST_CASE("sincos_turns gives sin and cos of 2 pi u within 2 ULP (or 2^-26) for every 24-bit u", "[inline_math]") {
  double worst = 0.0;
  for (std::uint32_t k = 0; k < (1u << 24); k += 7u) {
    const float u = static_cast<float>(k) * 0x1.0p-24f;
    float s = 0.0f, c = 0.0f;
    est::imath::sincos_turns(u, s, c);
    const long double a = 2.0L * 3.14159265358979323846264338327950288L * static_cast<long double>(u);
    worst = std::max(worst, ulp_error(s, std::sin(a)));
    worst = std::max(worst, ulp_error(c, std::cos(a)));
  }
  INFO("worst error " << worst);
  CHECK(worst <= 2.0);
}

TEST_CASE("wrap_angle_near agrees with fmath::normalize_angle within 2 ULP of pi from -3 pi to 3 pi", "[inline_math]") {
  double worst = 0.0;
  int outside = 0;
  for (int i = -300000; i <= 300000; ++i) {
    const float a = 3.0f * est::kPi * static_cast<float>(i) / 300000.0f;
    const float w = est::imath::wrap_angle_near(a);
    outside += (w > -est::kPi - 4e-7f && w <= est::kPi + 4e-7f) ? 0 : 1;
    const float r = est::fmath::normalize_angle(a);
    const double d = std::fabs(std::remainder(static_cast<double>(w) - static_cast<double>(r), 2.0 * M_PI));
    worst = std::max(worst, d);
  }
  CHECK(outside == 0);
  INFO("worst difference " << worst << " rad");
  CHECK(worst <= 4.8e-7);  // two ULP of pi
}

TEST_CASE("log_normal_positive is within 1 ULP on every 24-bit uniform and across the normal range", "[inline_math]") {
  double worst = 0.0;
  for (std::uint32_t k = 1; k <= (1u << 24); k += 5u) {  // uniform_open_zero's values
    const float u = static_cast<float>(k) * 0x1.0p-24f;
    worst = std::max(worst, ulp_error(est::imath::log_normal_positive(u), std::log(static_cast<long double>(u))));
  }
  for (float x = 1.2e-38f; x < 3.0e38f; x *= 1.0009765f)
    worst = std::max(worst, ulp_error(est::imath::log_normal_positive(x), std::log(static_cast<long double>(x))));
  INFO("worst error " << worst << " ULP");
  CHECK(worst <= 1.0);
}

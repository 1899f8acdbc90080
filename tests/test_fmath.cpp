// est::fmath against a long double reference (glibc's sinl, atan2l, expl, logl: exact argument reduction, errors far
// below a float ULP). Each case states the bound of fmath.hpp, sweeps floats by bit pattern (every binade equally, or
// every float of a range) and prints the largest error it measured.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <tuple>

#include "est/math/fmath.hpp"
#include "est/random/xoshiro128.hpp"

namespace {

namespace fm = est::fmath;

// The bounds stated in fmath.hpp, in ULP.
constexpr double kSinCosUlp = 1.0;
constexpr double kAtanUlp = 1.0;
constexpr double kAtan2Ulp = 2.0;
constexpr double kExpUlp = 1.0;
constexpr double kLogUlp = 1.0;
constexpr double kNormalizeUlp = 1.0;

// Sanitizer builds (no NDEBUG) run 5-10x slower: they sweep every 4th point of the same ranges.
#ifdef NDEBUG
constexpr std::uint32_t kThin = 1u;
#else
constexpr std::uint32_t kThin = 4u;
#endif

constexpr std::uint32_t kCanonicalNaN = 0x7fc00000u;
constexpr long double kPiL = 3.141592653589793238462643383279502884L;
constexpr double kPiD = 3.141592653589793238462643383279502884;

float from_bits(std::uint32_t b) {
  float x = 0.0f;
  std::memcpy(&x, &b, sizeof x);
  return x;
}

std::uint32_t bits(float x) {
  std::uint32_t b = 0;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

// ulp(y) = 2^(floor(log2 |y|) - 23), and 2^-149 in the subnormal range.
long double ulp_of(long double y) {
  const long double a = std::fabs(y);
  if (a < 0x1p-126L) return 0x1p-149L;
  int e = 0;
  std::frexp(a, &e);  // a = f 2^e, f in [0.5, 1)
  return std::ldexp(1.0L, e - 24);
}

// Error of a float result in ULP of the exact value; a result the reference says is beyond FLT_MAX must be what
// rounding gives (FLT_MAX or inf), anything else counts as a huge error.
double ulp_error(float got, long double exact) {
  if (std::isnan(exact)) return std::isnan(got) ? 0.0 : 1e30;
  if (std::fabs(exact) > static_cast<long double>(FLT_MAX)) return got == static_cast<float>(exact) ? 0.0 : 1e30;
  if (!std::isfinite(got)) return 1e30;
  return static_cast<double>(std::fabs(static_cast<long double>(got) - exact) / ulp_of(exact));
}

struct MaxError {
  double ulp = 0.0;
  float at = 0.0f;
  float at2 = 0.0f;
  std::size_t points = 0;
  void add(double e, float x, float x2 = 0.0f) {
    ++points;
    if (e > ulp) {
      ulp = e;
      at = x;
      at2 = x2;
    }
  }
  void merge(const MaxError& o) {
    points += o.points;
    if (o.ulp > ulp) {
      ulp = o.ulp;
      at = o.at;
      at2 = o.at2;
    }
  }
};

// Every stride-th float whose bit pattern lies in [first, last] (patterns of one sign are ordered by value).
template <typename F, typename Ref>
MaxError sweep(F f, Ref ref, std::uint32_t first, std::uint32_t last, std::uint32_t stride) {
  MaxError m;
  for (std::uint64_t b = first; b <= last; b += stride) {
    const float x = from_bits(static_cast<std::uint32_t>(b));
    m.add(ulp_error(f(x), ref(static_cast<long double>(x))), x);
  }
  return m;
}

void report(const char* what, const MaxError& m) {
  std::printf("fmath: %-44s max %.4f ULP at %a (%g) over %zu points\n", what, m.ulp, static_cast<double>(m.at),
              static_cast<double>(m.at), m.points);
  std::fflush(stdout);
}

float fsin(float x) { return fm::sin(x); }
float fcos(float x) { return fm::cos(x); }
long double lsin(long double x) { return std::sin(x); }
long double lcos(long double x) { return std::cos(x); }

constexpr std::uint32_t kPio4Bits = 0x3f490fdbu;  // float(pi/4)
constexpr std::uint32_t kInfBits = 0x7f800000u;
constexpr std::uint32_t kMaxBits = 0x7f7fffffu;  // FLT_MAX

}  // namespace

TEST_CASE("sin and cos are within 1 ULP for every finite argument", "[fmath]") {
  MaxError all;
  for (auto [f, ref, name] : {std::tuple{&fsin, &lsin, "sin"}, std::tuple{&fcos, &lcos, "cos"}}) {
    MaxError m;
    // |x| <= pi/4, no reduction: every binade from the subnormals up, evenly by bit pattern.
    m.merge(sweep(f, ref, 0x00000001u, kPio4Bits, 4093u * kThin));
    // The Cody-Waite range [pi/4, 200) and a dense stretch of it.
    m.merge(sweep(f, ref, kPio4Bits, bits(200.0f), 127u * kThin));
    m.merge(sweep(f, ref, bits(3.0f), bits(3.3f), 3u * kThin));
    // The Payne-Hanek range [200, FLT_MAX].
    m.merge(sweep(f, ref, bits(200.0f), kMaxBits, 1931u * kThin));
    // Negative arguments.
    m.merge(sweep(f, ref, 0x80000000u | bits(0.5f), 0x80000000u | bits(1.0e6f), 419u * kThin));
    // Around every multiple of pi/2 up to 2^12 (where the reduced argument cancels most): the 1024 floats nearest.
    for (int j = 1; j < 2608; ++j) {
      const auto c = bits(static_cast<float>(static_cast<long double>(j) * 1.5707963267948966192313216916397514L));
      m.merge(sweep(f, ref, c - 512u, c + 512u, j < 128 ? kThin : 16u * kThin));
    }
    report(name, m);
    CHECK(m.ulp <= kSinCosUlp);
    all.merge(m);
  }
  CHECK(all.points > 1000000u / kThin);
}

TEST_CASE("sin and cos of huge arguments are right (exact reduction, not a 0 or a garbage value)", "[fmath]") {
  // sin(FLT_MAX) and friends against the reference; a naive reduction gets these completely wrong.
  const float cases[] = {FLT_MAX, 1.0e38f, 0x1.2d97c8p+127f, 16777216.0f, 1.0e10f, 0x1.921fb6p+100f, 0x1p+90f};
  for (float x : cases) {
    INFO("x = " << x);
    CHECK(ulp_error(fm::sin(x), std::sin(static_cast<long double>(x))) <= kSinCosUlp);
    CHECK(ulp_error(fm::cos(x), std::cos(static_cast<long double>(x))) <= kSinCosUlp);
  }
  // Hand check: float(pi) is pi + 8.742278e-8 (to 7 digits), so sin(float(pi)) = -8.742278e-8 and cos = -1.
  CHECK(fm::sin(est::kPi) == Approx(-8.742278e-8f).epsilon(1e-6));
  CHECK(fm::cos(est::kPi) == -1.0f);
}

TEST_CASE("sin and cos special values: signed zeros, subnormals, infinities, NaN", "[fmath]") {
  CHECK(bits(fm::sin(0.0f)) == bits(0.0f));
  CHECK(bits(fm::sin(-0.0f)) == bits(-0.0f));
  CHECK(fm::cos(0.0f) == 1.0f);
  CHECK(fm::cos(-0.0f) == 1.0f);
  const float tiny = from_bits(1u);  // 2^-149
  CHECK(fm::sin(tiny) == tiny);
  CHECK(fm::sin(-tiny) == -tiny);
  CHECK(fm::sin(0x1p-126f) == 0x1p-126f);
  CHECK(fm::cos(tiny) == 1.0f);
  for (float x : {INFINITY, -INFINITY, NAN, -NAN}) {
    CHECK(bits(fm::sin(x)) == kCanonicalNaN);
    CHECK(bits(fm::cos(x)) == kCanonicalNaN);
    float s = 0.0f, c = 0.0f;
    fm::sincos(x, s, c);
    CHECK(bits(s) == kCanonicalNaN);
    CHECK(bits(c) == kCanonicalNaN);
  }
}

TEST_CASE("sin is odd and cos even bit for bit, and sincos gives exactly sin and cos", "[fmath]") {
  est::Rng rng(7u);
  for (int i = 0; i < 200000 / static_cast<int>(kThin); ++i) {
    // Random bit patterns: every exponent equally often.
    const float x = from_bits(rng() & 0x7fffffffu);
    if (!std::isfinite(x)) continue;
    REQUIRE(bits(fm::sin(-x)) == bits(-fm::sin(x)));
    REQUIRE(bits(fm::cos(-x)) == bits(fm::cos(x)));
    float s = 0.0f, c = 0.0f;
    fm::sincos(x, s, c);
    REQUIRE(bits(s) == bits(fm::sin(x)));
    REQUIRE(bits(c) == bits(fm::cos(x)));
    fm::sincos(-x, s, c);
    REQUIRE(bits(s) == bits(fm::sin(-x)));
    REQUIRE(bits(c) == bits(fm::cos(-x)));
  }
}

TEST_CASE("sin^2 + cos^2 = 1 to within 3 float ULP of 1", "[fmath]") {
  // Each factor is within 1 ULP, so s^2 + c^2 - 1 (in double, exact enough) is within about 2 (2^-24).
  double worst = 0.0;
  for (std::uint64_t b = 0x3a000000u; b <= kMaxBits; b += 7919u * kThin) {
    const float x = from_bits(static_cast<std::uint32_t>(b));
    float s = 0.0f, c = 0.0f;
    fm::sincos(x, s, c);
    const double sd = s, cd = c;
    worst = std::max(worst, std::fabs(sd * sd + cd * cd - 1.0));
  }
  std::printf("fmath: sin^2 + cos^2 - 1 worst %.3g (= %.2f x 2^-24)\n", worst, worst / 0x1p-24);
  CHECK(worst <= 3.0 * 0x1p-24);
}

TEST_CASE("atan is within 1 ULP for every argument", "[fmath]") {
  const auto f = [](float x) { return fm::atan(x); };
  const auto ref = [](long double x) { return std::atan(x); };
  MaxError m = sweep(f, ref, 0x00000001u, kMaxBits, 2819u * kThin);
  m.merge(sweep(f, ref, 0x80000001u, 0x80000000u | kMaxBits, 1409u * kThin));
  // Every breakpoint region of the reduction, densely: [1/4, 4).
  m.merge(sweep(f, ref, bits(0.25f), bits(4.0f), 23u * kThin));
  report("atan", m);
  CHECK(m.ulp <= kAtanUlp);
  CHECK(bits(fm::atan(0.0f)) == bits(0.0f));
  CHECK(bits(fm::atan(-0.0f)) == bits(-0.0f));
  CHECK(fm::atan(INFINITY) == est::kHalfPi);
  CHECK(fm::atan(-INFINITY) == -est::kHalfPi);
  CHECK(fm::atan(1.0f) == 0x1.921fb6p-1f);  // float(pi/4), correctly rounded
  CHECK(bits(fm::atan(NAN)) == kCanonicalNaN);
}

TEST_CASE("atan2 is within 2 ULP over all four quadrants and all magnitudes", "[fmath]") {
  est::Rng rng(2026u);
  MaxError m;
  const int n = 1000000 / static_cast<int>(kThin);
  for (int i = 0; i < n; ++i) {
    // Exponents of y and x within 40 binades of each other (beyond that the result is 0, pi/2 or pi to the
    // last bit and is checked below), signs random.
    const std::uint32_t ex = 1u + rng.below(253u);
    const std::uint32_t d = rng.below(81u);
    const std::uint32_t ey = std::min(254u, std::max(1u, ex + d > 40u ? ex + d - 40u : 1u));
    const float x = from_bits((rng() & 0x80000000u) | (ex << 23) | (rng() & 0x7fffffu));
    const float y = from_bits((rng() & 0x80000000u) | (ey << 23) | (rng() & 0x7fffffu));
    m.add(ulp_error(fm::atan2(y, x), std::atan2(static_cast<long double>(y), static_cast<long double>(x))), y, x);
  }
  // Extreme ratios, subnormals and the axes' neighbourhoods.
  const float edge[] = {0x1p-149f, 0x1p-130f, 0x1p-126f, 1e-30f, 1e-6f, 0.5f, 1.0f, 3.0f, 1e6f, 1e30f, FLT_MAX};
  for (float a : edge)
    for (float b : edge)
      for (float sy : {1.0f, -1.0f})
        for (float sx : {1.0f, -1.0f}) {
          const float y = sy * a, x = sx * b;
          m.add(ulp_error(fm::atan2(y, x), std::atan2(static_cast<long double>(y), static_cast<long double>(x))),
                y, x);
        }
  std::printf("fmath: %-44s max %.4f ULP at atan2(%a, %a) over %zu points\n", "atan2", m.ulp,
              static_cast<double>(m.at), static_cast<double>(m.at2), m.points);
  CHECK(m.ulp <= kAtan2Ulp);
}

TEST_CASE("atan2 follows IEEE 754 for zeros, infinities and NaN", "[fmath]") {
  const float pi = est::kPi, h = est::kHalfPi, q = 0x1.921fb6p-1f, q3 = 0x1.2d97c8p+1f;
  struct Case {
    float y, x, expected;
  };
  const Case cases[] = {
      {0.0f, 0.0f, 0.0f},        {-0.0f, 0.0f, -0.0f},     {0.0f, -0.0f, pi},        {-0.0f, -0.0f, -pi},
      {0.0f, 5.0f, 0.0f},        {-0.0f, 5.0f, -0.0f},     {0.0f, -5.0f, pi},        {-0.0f, -5.0f, -pi},
      {5.0f, 0.0f, h},           {5.0f, -0.0f, h},         {-5.0f, 0.0f, -h},        {-5.0f, -0.0f, -h},
      {5.0f, INFINITY, 0.0f},    {-5.0f, INFINITY, -0.0f}, {5.0f, -INFINITY, pi},    {-5.0f, -INFINITY, -pi},
      {INFINITY, 5.0f, h},       {-INFINITY, -5.0f, -h},   {INFINITY, INFINITY, q},  {-INFINITY, INFINITY, -q},
      {INFINITY, -INFINITY, q3}, {-INFINITY, -INFINITY, -q3},
      {1.0f, 1.0f, q},           {-1.0f, -1.0f, -q3},      {1.0f, -1.0f, q3},        {-1.0f, 1.0f, -q},
  };
  for (const Case& c : cases) {
    INFO("atan2(" << c.y << ", " << c.x << ")");
    CHECK(bits(fm::atan2(c.y, c.x)) == bits(c.expected));
  }
  CHECK(bits(fm::atan2(NAN, 1.0f)) == kCanonicalNaN);
  CHECK(bits(fm::atan2(1.0f, NAN)) == kCanonicalNaN);
  CHECK(bits(fm::atan2(NAN, NAN)) == kCanonicalNaN);
  // Extreme ratios: exactly the nearest float of the limit.
  CHECK(fm::atan2(FLT_MAX, 0x1p-149f) == h);
  CHECK(fm::atan2(0x1p-149f, -FLT_MAX) == pi);
  CHECK(fm::atan2(-0x1p-149f, -FLT_MAX) == -pi);
  CHECK(fm::atan2(0x1p-149f, FLT_MAX) == 0.0f);
}

TEST_CASE("atan2(sin t, cos t) recovers t in every quadrant", "[fmath]") {
  // Both steps are within 1-2 ULP, and atan2's condition number is 1 in angle: |error| <= 4 ULP of pi.
  double worst = 0.0;
  for (int i = -20000; i <= 20000; ++i) {
    const float t = static_cast<float>(i) * (est::kPi / 20000.0f);
    if (!(t > -est::kPi && t <= est::kPi)) continue;
    float s = 0.0f, c = 0.0f;
    fm::sincos(t, s, c);
    worst = std::max(worst, std::fabs(static_cast<double>(fm::atan2(s, c)) - static_cast<double>(t)));
  }
  std::printf("fmath: atan2(sin t, cos t) - t worst %.3g rad\n", worst);
  CHECK(worst <= 4.0 * 0x1p-22);
}

TEST_CASE("exp is within 1 ULP where the result is normal, with exact overflow and gradual underflow", "[fmath]") {
  const auto f = [](float x) { return fm::exp(x); };
  const auto ref = [](long double x) { return std::exp(x); };
  MaxError m = sweep(f, ref, 0x00000001u, bits(88.8f), 619u * kThin);
  m.merge(sweep(f, ref, 0x80000001u, bits(-104.0f), 619u * kThin));
  // |x| in [2^-16, 1], densely (below 2^-14 exp(x) rounds to 1 + x).
  m.merge(sweep(f, ref, 0x80000000u | bits(0x1p-16f), bits(-1.0f), 127u * kThin));
  m.merge(sweep(f, ref, bits(0x1p-16f), bits(1.0f), 127u * kThin));
  m.merge(sweep(f, ref, bits(80.0f), bits(88.8f), 5u * kThin));
  report("exp (normal results)", m);
  CHECK(m.ulp <= kExpUlp);
  // Subnormal results: measured in the subnormal ULP 2^-149 (ulp_of gives it below 2^-126).
  MaxError sub = sweep(f, ref, bits(-87.34f), bits(-104.0f), 3u * kThin);
  report("exp (subnormal results, in ULP of 2^-149)", sub);
  CHECK(sub.ulp <= kExpUlp);

  // The worst case of an exhaustive run over all floats (0.9954 ULP), checked here by name.
  CHECK(ulp_error(fm::exp(0x1.2083c6p+2f), std::exp(static_cast<long double>(0x1.2083c6p+2f))) <= kExpUlp);
  CHECK(fm::exp(0.0f) == 1.0f);
  CHECK(fm::exp(-0.0f) == 1.0f);
  CHECK(fm::exp(1.0f) == 0x1.5bf0a8p+1f);  // e, correctly rounded
  CHECK(fm::exp(INFINITY) == INFINITY);
  CHECK(bits(fm::exp(-INFINITY)) == bits(0.0f));
  CHECK(bits(fm::exp(NAN)) == kCanonicalNaN);
  // Overflow: 88.72284 (0x42b17218) is the least float with exp > FLT_MAX + ulp/2; the float below stays finite.
  CHECK(fm::exp(from_bits(0x42b17218u)) == INFINITY);
  CHECK(fm::exp(from_bits(0x42b17217u)) < INFINITY);
  CHECK(ulp_error(fm::exp(from_bits(0x42b17217u)), std::exp(static_cast<long double>(from_bits(0x42b17217u)))) <=
        kExpUlp);
  CHECK(fm::exp(1000.0f) == INFINITY);
  // Underflow: -103.97208 is the greatest float whose exp rounds to 0; the next one up gives 2^-149.
  CHECK(bits(fm::exp(-0x1.9fe36ap+6f)) == bits(0.0f));
  CHECK(fm::exp(-0x1.9fe368p+6f) == 0x1p-149f);
  CHECK(bits(fm::exp(-1000.0f)) == bits(0.0f));
}

TEST_CASE("log is within 1 ULP over every float from 0.5 to 1 and over every binade", "[fmath]") {
  const auto f = [](float x) { return fm::log(x); };
  const auto ref = [](long double x) { return std::log(x); };
  MaxError every = sweep(f, ref, bits(0.5f), bits(1.0f) - 1u, kThin);
  report(kThin == 1u ? "log, every float in [0.5, 1)" : "log, every 4th float in [0.5, 1)", every);
  CHECK(every.ulp <= kLogUlp);
  MaxError m = sweep(f, ref, 0x00000001u, kMaxBits, 1021u * kThin);  // subnormals included
  m.merge(sweep(f, ref, bits(1.0f), bits(2.0f), 29u * kThin));
  report("log, all positive floats", m);
  CHECK(m.ulp <= kLogUlp);

  CHECK(bits(fm::log(1.0f)) == bits(0.0f));
  CHECK(fm::log(0.0f) == -INFINITY);
  CHECK(fm::log(-0.0f) == -INFINITY);
  CHECK(fm::log(INFINITY) == INFINITY);
  for (float x : {-1.0f, -0x1p-149f, -INFINITY, NAN, -NAN}) CHECK(bits(fm::log(x)) == kCanonicalNaN);
  CHECK(fm::log(2.0f) == 0x1.62e43p-1f);        // ln 2, correctly rounded
  CHECK(fm::log(0x1p-149f) == -0x1.9d1da0p+6f);  // -149 ln 2 = -103.2789, correctly rounded
}

TEST_CASE("exp(log(x)) returns x to within the conditioning of the pair", "[fmath]") {
  // log(x) carries an absolute error up to 1 ULP of log(x) ~ |log x| 2^-23, which exp turns into that relative
  // error; plus 1 ULP of exp: |exp(log x) / x - 1| <= (|log x| + 2) 2^-23.
  double worst_ratio = 0.0;
  for (std::uint64_t b = bits(0x1p-60f); b <= bits(0x1p60f); b += 4099u * kThin) {
    const float x = from_bits(static_cast<std::uint32_t>(b));
    const double lx = std::log(static_cast<double>(x));
    const double rel = std::fabs(static_cast<double>(fm::exp(fm::log(x))) / static_cast<double>(x) - 1.0);
    worst_ratio = std::max(worst_ratio, rel / ((std::fabs(lx) + 2.0) * 0x1p-23));
  }
  std::printf("fmath: exp(log x) relative error, worst fraction of its bound %.3f\n", worst_ratio);
  CHECK(worst_ratio <= 1.0);
}

TEST_CASE("normalize_angle is the identity between -pi and pi and maps both ends to pi", "[fmath]") {
  CHECK(fm::normalize_angle(est::kPi) == est::kPi);
  CHECK(fm::normalize_angle(-est::kPi) == est::kPi);
  CHECK(bits(fm::normalize_angle(0.0f)) == bits(0.0f));
  CHECK(bits(fm::normalize_angle(-0.0f)) == bits(-0.0f));
  for (std::uint64_t b = 0; b < bits(est::kPi); b += 997u * kThin) {
    const float a = from_bits(static_cast<std::uint32_t>(b));
    REQUIRE(fm::normalize_angle(a) == a);
    REQUIRE(fm::normalize_angle(-a) == -a);
  }
  // Just outside: the next float above pi wraps to just above -pi; so does 3 pi.
  const float above = std::nextafter(est::kPi, 4.0f);
  CHECK(fm::normalize_angle(above) == Approx(static_cast<double>(above) - 2.0 * kPiD).margin(1e-6));
  CHECK(fm::normalize_angle(above) > -est::kPi);
  // float(3 pi) - 4 pi = -3.14159263 lies within half an ULP of -pi: it rounds to -float(pi), returned as pi.
  CHECK(fm::normalize_angle(3.0f * est::kPi) == est::kPi);
  CHECK(fm::normalize_angle(-1.5f * est::kPi) == Approx(0.5 * kPiD).margin(1e-6));
  CHECK(fm::normalize_angle(2.0f * est::kPi) == Approx(2.0 * static_cast<double>(est::kPi) - 2.0 * kPiD).margin(1e-9));
}

TEST_CASE("normalize_angle is within 1 ULP of the exact remainder mod 2 pi for every finite angle, never beyond pi",
          "[fmath]") {
  // Reference: the angle of (cos a, sin a) from glibc's long double functions, exact for every a.
  const auto check = [](float a, MaxError& m) {
    const float got = fm::normalize_angle(a);
    const long double la = a;
    const long double exact = std::atan2(std::sin(la), std::cos(la));
    REQUIRE(got > -est::kPi);
    REQUIRE(got <= est::kPi);
    // Compare as angles: an exact value within half an ULP of -pi legitimately comes back as pi.
    long double d = static_cast<long double>(got) - exact;
    if (d > 3.0L) d -= 2.0L * kPiL;
    m.add(static_cast<double>(std::fabs(d) / ulp_of(exact)), a);
  };
  MaxError m;
  for (std::uint64_t b = bits(est::kPi); b <= kMaxBits; b += 3163u * kThin) {
    check(from_bits(static_cast<std::uint32_t>(b)), m);
    check(-from_bits(static_cast<std::uint32_t>(b)), m);
  }
  for (std::uint64_t b = bits(3.0f); b <= bits(40.0f); b += 61u * kThin)
    check(from_bits(static_cast<std::uint32_t>(b)), m);
  // Around multiples of pi (results near 0 and near +-pi).
  for (int j = 2; j < 200; ++j) {
    const auto c = bits(static_cast<float>(static_cast<long double>(j) * kPiL));
    for (std::uint32_t b = c - 64u; b <= c + 64u; ++b) check(from_bits(b), m);
  }
  report("normalize_angle", m);
  CHECK(m.ulp <= kNormalizeUlp);
}

TEST_CASE("normalize_angle of a non-finite angle is NaN", "[fmath]") {
  for (float a : {INFINITY, -INFINITY, NAN, -NAN}) CHECK(bits(fm::normalize_angle(a)) == kCanonicalNaN);
  CHECK(fm::isfinite(fm::normalize_angle(FLT_MAX)));
  CHECK(fm::isfinite(fm::normalize_angle(-FLT_MAX)));
}

TEST_CASE("sqrt is correctly rounded and gives the canonical NaN below zero", "[fmath]") {
  for (float x : {0.0f, 2.0f, 0x1p-149f, 1e30f, FLT_MAX, INFINITY}) CHECK(fm::sqrt(x) == std::sqrt(x));
  CHECK(bits(fm::sqrt(-0.0f)) == bits(-0.0f));
  for (float x : {-1.0f, -0x1p-149f, -INFINITY, NAN, -NAN}) CHECK(bits(fm::sqrt(x)) == kCanonicalNaN);
}

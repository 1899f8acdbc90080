#include <catch2/catch.hpp>
#include <cstdint>
#include <cstring>
#include <vector>

#include "est/math/fmath.hpp"
#include "est/math/inline_exp.hpp"
#include "est/math/inline_math.hpp"
#include "est/math/lanes.hpp"
#include "est/math/normal.hpp"

namespace {

using est::lanes::F;
using est::lanes::I;
using est::lanes::kLanes;

std::uint32_t bits(float x) {
  std::uint32_t b = 0;
  std::memcpy(&b, &x, sizeof b);
  return b;
}
float from_bits(std::uint32_t b) {
  float x = 0.0f;
  std::memcpy(&x, &b, sizeof x);
  return x;
}

// Inputs for the comparisons: every `step`-th float of both signs from +0 up to `top` (bits), and the floats around
// each multiple of pi/4 up to `top` (the quadrant and kernel boundaries), and a few special values.
std::vector<float> inputs(std::uint32_t top, std::uint32_t step) {
  std::vector<float> xs;
  for (std::uint32_t b = 0; b < top; b += step) {
    xs.push_back(from_bits(b));
    xs.push_back(-from_bits(b));
  }
  const float limit = from_bits(top);
  for (int k = 0; static_cast<float>(k) * 0.785398163f < limit; ++k) {
    const std::uint32_t c = bits(static_cast<float>(k) * 0.785398163f);
    for (std::uint32_t d = 0; d < 64; ++d) {
      for (const std::uint32_t b : {c + d, c - d}) {
        if (b >= top) continue;
        xs.push_back(from_bits(b));
        xs.push_back(-from_bits(b));
      }
    }
  }
  for (const std::uint32_t b : {0x3f490fdau, 0x3f490fdbu, 0x3e99999au, 0x3e999999u, 0x3f480000u, 0x3f480001u, 1u})
    if (b < top) xs.push_back(from_bits(b)), xs.push_back(-from_bits(b));
  while (xs.size() % kLanes != 0u) xs.push_back(0.5f);
  return xs;
}

}  // namespace

TEST_CASE("lanes::sincos gives fmath::sincos's bits on |x| < 200 and flags every other lane", "[lanes]") {
  const std::vector<float> xs = inputs(0x43480000u, 61u);  // 200.0f: ~36 million floats
  std::uint64_t mismatches = 0, checked = 0;
  float first_bad = 0.0f;
  for (std::size_t i = 0; i < xs.size(); i += kLanes) {
    F s, c;
    const I ok = est::lanes::sincos(est::lanes::load(&xs[i]), s, c);
    for (std::uint32_t j = 0; j < kLanes; ++j) {
      float rs = 0.0f, rc = 0.0f;
      est::fmath::sincos(xs[i + j], rs, rc);
      ++checked;
      if (ok[j] == 0 || bits(s[j]) != bits(rs) || bits(c[j]) != bits(rc)) {
        if (mismatches++ == 0u) first_bad = xs[i + j];
      }
    }
  }
  INFO("checked " << checked << ", first mismatch at " << first_bad);
  CHECK(checked > 30000000u);
  CHECK(mismatches == 0u);

  // Outside the Cody-Waite range, and not finite: flagged; the largest float below 200 is inside.
  const float outside[] = {200.0f, -200.0f, 1e30f, -3.0e38f, __builtin_inff(), -__builtin_inff(),
                           __builtin_nanf(""), 199.99998f};
  static_assert(sizeof outside / sizeof outside[0] % kLanes == 0, "whole vectors");
  for (std::size_t i = 0; i < sizeof outside / sizeof outside[0]; i += kLanes) {
    F s, c;
    const I ok = est::lanes::sincos(est::lanes::load(&outside[i]), s, c);
    for (std::uint32_t j = 0; j < kLanes; ++j) CHECK((ok[j] != 0) == (outside[i + j] == 199.99998f));
  }
}

TEST_CASE("lanes::sincos_moderate, sin_kernel and wrap_angle_near give imath's bits", "[lanes]") {
  std::vector<float> xs;
  for (int i = -2000000; i < 2000000; ++i) xs.push_back(64.0f * static_cast<float>(i) / 2000000.0f);
  for (std::uint32_t b = 0; b < 0x42800000u; b += 4099u) xs.push_back(from_bits(b)), xs.push_back(-from_bits(b));
  while (xs.size() % kLanes != 0u) xs.push_back(1.0f);
  std::uint64_t bad_sincos = 0, bad_kernel = 0, bad_wrap = 0;
  for (std::size_t i = 0; i < xs.size(); i += kLanes) {
    const F x = est::lanes::load(&xs[i]);
    F s, c;
    est::lanes::sincos_moderate(x, s, c);
    const F k = est::lanes::sin_kernel(x * 0.01f);
    const F w = est::lanes::wrap_angle_near(x * 0.147f);  // |x| < 9.42: the (-3 pi, 3 pi] wrap's domain
    for (std::uint32_t j = 0; j < kLanes; ++j) {
      float rs = 0.0f, rc = 0.0f;
      est::imath::sincos_moderate(xs[i + j], rs, rc);
      bad_sincos += (bits(s[j]) != bits(rs) || bits(c[j]) != bits(rc)) ? 1u : 0u;
      bad_kernel += bits(k[j]) != bits(est::imath::sin_kernel(xs[i + j] * 0.01f)) ? 1u : 0u;
      bad_wrap += bits(w[j]) != bits(est::imath::wrap_angle_near(xs[i + j] * 0.147f)) ? 1u : 0u;
    }
  }
  INFO(xs.size() << " inputs");
  CHECK(bad_sincos == 0u);
  CHECK(bad_kernel == 0u);
  CHECK(bad_wrap == 0u);
  // The wrap's three cases are all taken: values beyond pi and below -pi are among the inputs.
  CHECK(est::lanes::wrap_angle_near(est::lanes::splat(4.0f))[0] == est::imath::wrap_angle_near(4.0f));
  CHECK(est::lanes::wrap_angle_near(est::lanes::splat(-4.0f))[0] == est::imath::wrap_angle_near(-4.0f));
}

TEST_CASE("lanes::count and select follow the masks", "[lanes]") {
  float a[kLanes], b[kLanes];
  for (std::uint32_t j = 0; j < kLanes; ++j) a[j] = static_cast<float>(j), b[j] = -1.0f;
  const F x = est::lanes::load(a);
  const I m = x >= 3.0f;
  CHECK(est::lanes::count(m) == kLanes - 3u);
  CHECK(est::lanes::any(m));
  CHECK_FALSE(est::lanes::any(x > 100.0f));
  const F s = est::lanes::select(m, x, est::lanes::load(b));
  for (std::uint32_t j = 0; j < kLanes; ++j) CHECK(s[j] == (j >= 3u ? static_cast<float>(j) : -1.0f));
}

TEST_CASE("lanes::exp gives imath::exp's bits on (-85, 0] and flags every other lane", "[lanes]") {
  std::vector<float> xs;
  for (std::uint32_t b = 0; b < 0x42aa0000u; b += 37u) xs.push_back(-from_bits(b));  // -0 .. -85
  for (const float v : {1e-30f, 0.5f, -85.0f, -85.00001f, -100.0f, __builtin_inff(), -__builtin_inff(),
                        __builtin_nanf("")})
    xs.push_back(v);
  while (xs.size() % kLanes != 0u) xs.push_back(-1.0f);
  std::uint64_t bad = 0, flagged = 0;
  for (std::size_t i = 0; i < xs.size(); i += kLanes) {
    F e;
    const I ok = est::lanes::exp(est::lanes::load(&xs[i]), e);
    for (std::uint32_t j = 0; j < kLanes; ++j) {
      const float x = xs[i + j];
      const bool inside = x > -85.0f && x <= 0.0f;
      flagged += ok[j] == 0 ? 1u : 0u;
      bad += (ok[j] != 0) != inside || (inside && bits(e[j]) != bits(est::imath::exp(x))) ? 1u : 0u;
    }
  }
  INFO(xs.size() << " inputs");
  CHECK(bad == 0u);
  CHECK(flagged == 8u);  // 1e-30, 0.5, -85 (outside: the range is open there), -85.00001, -100, +-inf, NaN
}

TEST_CASE("lanes::normal_cdf gives est::normal_cdf's bits on every float", "[lanes]") {
  // Every 97th float of both signs up to 20 (beyond the tails' cut at 9 sqrt 2), the floats around the cut, and the
  // special values.
  std::vector<float> xs = inputs(0x41a00000u, 97u);
  const float cut = 9.0f * 1.41421356f;
  for (std::uint32_t d = 0; d < 64; ++d)
    for (const float v : {from_bits(bits(cut) + d), from_bits(bits(cut) - d)}) xs.push_back(v), xs.push_back(-v);
  for (const float v : {__builtin_inff(), -__builtin_inff(), __builtin_nanf(""), 1e30f, -1e30f}) xs.push_back(v);
  while (xs.size() % kLanes != 0u) xs.push_back(0.5f);
  std::uint64_t bad = 0;
  for (std::size_t i = 0; i < xs.size(); i += kLanes) {
    const F c = est::lanes::normal_cdf(est::lanes::load(&xs[i]));
    for (std::uint32_t j = 0; j < kLanes; ++j) bad += bits(c[j]) != bits(est::normal_cdf(xs[i + j])) ? 1u : 0u;
  }
  INFO(xs.size() << " inputs");
  CHECK(bad == 0u);
  CHECK(xs.size() > 1000000u);
}

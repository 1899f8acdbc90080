#include <catch2/catch.hpp>

#include <cstdint>
#include <cstring>
#include <vector>

#include "est/sensor/beam_readings.hpp"

namespace {

std::uint32_t bits(float x) {
  std::uint32_t b = 0;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

// density(reading(z), z*) against density(z, z*) over a dense grid of (z, z*): every 2 cm, plus the points where
// the model's branches switch (0, z = z*, 5.5 and 12 sigma from z* and from both ends, range_max, beyond it).
std::uint32_t count_mismatches(const est::BeamRangeFinderModel& m, std::uint32_t& tried) {
  const float zm = m.params().range_max, s = m.params().sigma_hit;
  std::vector<float> zs;
  for (int i = -3; i <= static_cast<int>(zm * 50.0f) + 25; ++i) zs.push_back(0.02f * static_cast<float>(i));
  for (float v : {0.0f, 1e-7f, 1e-4f, 5.5f * s, 12.0f * s, zm - 5.5f * s, zm - 12.0f * s, zm - 1e-4f, zm, zm + 1e-4f,
                  2.0f * zm, 1e30f})
    zs.push_back(v);
  std::uint32_t bad = 0;
  tried = 0;
  for (float z_exp : zs) {
    std::vector<float> z_here = zs;
    for (float d : {0.0f, 1e-6f, -1e-6f, 5.5f * s, -5.5f * s, 11.99f * s, -11.99f * s, 12.0f * s, -12.0f * s})
      z_here.push_back(z_exp + d);
    for (float z : z_here) {
      const est::BeamRangeFinderModel::Reading r = m.reading(z);
      ++tried;
      if (bits(m.density(r, z_exp)) != bits(m.density(z, z_exp))) ++bad;
    }
  }
  return bad;
}

// densities() (kLanes beams at a time on the host) against density() one beam at a time, over the same grid: every
// reading against a run of expected ranges, so each group of lanes mixes z* near and far from the ends.
std::uint32_t count_batch_mismatches(const est::BeamRangeFinderModel& m, std::uint32_t& tried) {
  const float zm = m.params().range_max, s = m.params().sigma_hit;
  std::vector<float> zs;
  for (int i = -3; i <= static_cast<int>(zm * 50.0f) + 25; ++i) zs.push_back(0.02f * static_cast<float>(i));
  for (float v : {0.0f, 1e-7f, 1e-4f, 5.5f * s, 12.0f * s, zm - 5.5f * s, zm - 12.0f * s, zm - 1e-4f, zm, zm + 1e-4f,
                  2.0f * zm, 1e30f, __builtin_nanf("")})
    zs.push_back(v);
  std::vector<est::BeamRangeFinderModel::Reading> r(zs.size());
  std::vector<float> z_exp(zs.size()), out(zs.size());
  std::uint32_t bad = 0;
  tried = 0;
  for (std::size_t shift = 0; shift < zs.size(); shift += 7) {
    for (std::size_t i = 0; i < zs.size(); ++i) {
      r[i] = m.reading(zs[i]);
      const float e = zs[(i + shift) % zs.size()];
      z_exp[i] = e == e ? e : 0.0f;  // z* is a caster's range: finite
    }
    m.densities(r.data(), z_exp.data(), out.data(), static_cast<std::int32_t>(zs.size()));
    for (std::size_t i = 0; i < zs.size(); ++i) {
      ++tried;
      if (bits(out[i]) != bits(m.density(r[i], z_exp[i]))) ++bad;
    }
  }
  return bad;
}

}  // namespace

// count(model, tried) == 0 for four configurations: the default, a wide Gaussian (the truncation mass away from 1
// everywhere), no short part, and a sharp short part (lambda z* >= 85 leaves the lanes' exp: those groups one beam
// at a time). The first must try at least `at_least` pairs.
template <class Count>
void for_each_configuration(Count count, std::uint32_t at_least) {
  est::BeamRangeFinderModel m;
  est::BeamModelParams p;
  p.range_max = 20.0f;
  REQUIRE(m.configure(p) == est::SensorModelStatus::ok);
  std::uint32_t tried = 0;
  CHECK(count(m, tried) == 0u);
  CHECK(tried > at_least);
  p.range_max = 8.0f;
  p.sigma_hit = 2.0f;
  REQUIRE(m.configure(p) == est::SensorModelStatus::ok);
  CHECK(count(m, tried) == 0u);
  p.sigma_hit = 0.05f;
  p.z_short = 0.0f;
  p.z_hit = 0.9f;
  REQUIRE(m.configure(p) == est::SensorModelStatus::ok);
  CHECK(count(m, tried) == 0u);
  p = {};
  p.lambda_short = 40.0f;
  REQUIRE(m.configure(p) == est::SensorModelStatus::ok);
  CHECK(count(m, tried) == 0u);
}

TEST_CASE("beam density from a prepared reading is bit-identical to the model's density", "[beam_readings]") {
  for_each_configuration(count_mismatches, 1000000u);
}

TEST_CASE("beam densities of many beams at once are bit-identical to the density of each", "[beam_readings]") {
  for_each_configuration(count_batch_mismatches, 100000u);
}

TEST_CASE("a non-finite reading has density 0, as the model gives", "[beam_readings]") {
  est::BeamRangeFinderModel m;
  REQUIRE(m.configure({}) == est::SensorModelStatus::ok);
  for (float z : {__builtin_nanf(""), __builtin_inff(), -__builtin_inff()})
    for (float z_exp : {0.0f, 3.0f, 30.0f}) {
      INFO("z = " << z << " z* = " << z_exp);
      CHECK(m.density(m.reading(z), z_exp) == 0.0f);
      CHECK(m.density(z, z_exp) == 0.0f);
    }
}

TEST_CASE("beam readings are prepared once per scan for one model configuration", "[beam_readings]") {
  static est::PreparedScan<8> scan;
  const est::ScanLayout layout{-1.0f, 0.25f, 8, 0.05f, 10.0f};
  const float ranges[8] = {1.0f, 2.0f, 12.0f, __builtin_inff(), 0.5f, 9.99f, 10.0f, 3.0f};
  REQUIRE(scan.prepare(layout, ranges) == est::ScanStatus::ok);
  const est::ScanBeams b = scan.beams();
  REQUIRE(b.count == 8);
  est::BeamRangeFinderModel m;
  est::BeamModelParams p;
  p.range_max = 10.0f;

  est::BeamReadingsStorage<8> readings;
  CHECK_FALSE(readings.prepare(b, m));  // not configured
  CHECK_FALSE(readings.view().matches(8, m));
  REQUIRE(m.configure(p) == est::SensorModelStatus::ok);
  REQUIRE(readings.prepare(b, m));
  const est::BeamReadings v = readings.view();
  REQUIRE(v.matches(8, m));
  CHECK_FALSE(v.matches(7, m));
  for (int k = 0; k < 8; ++k) {
    INFO("beam " << k);
    const float z = b.is_max[k] ? 10.0f : b.range[k];
    CHECK(bits(m.density(v.reading[k], 4.0f)) == bits(m.density(z, 4.0f)));
  }
  // Max readings (12, inf, 10) carry the atom's constant, the others z_rand / range_max.
  CHECK(v.reading[2].base == Approx(p.z_max / p.max_bin_width));
  CHECK(v.reading[3].z == 10.0f);
  CHECK(v.reading[0].base == Approx(p.z_rand / 10.0f));

  // Reconfigured model: the prepared readings no longer match.
  p.sigma_hit = 0.3f;
  REQUIRE(m.configure(p) == est::SensorModelStatus::ok);
  CHECK_FALSE(v.matches(8, m));
  // Too many beams for the capacity: refused, empty view.
  est::BeamReadingsStorage<4> small;
  CHECK_FALSE(small.prepare(b, m));
  CHECK(small.view().reading == nullptr);
  CHECK_FALSE(small.view().matches(8, m));
}

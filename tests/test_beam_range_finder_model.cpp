#include <catch2/catch.hpp>

#include <cmath>

#include "est/map/ray_casting.hpp"
#include "est/sensor/beam_range_finder_model.hpp"
#include "world/office_map.hpp"

namespace {

est::OccupancyGridStorage<400, 300> g_grid;
est::DistanceTransformStorage<400, 300> g_edt;
est::PreparedScan<360> g_scan;

// Double-precision reference of table 6.1 with the atom convention of the header.
double reference_density(double z, double z_exp, const est::BeamModelParams& p) {
  const double zm = p.range_max;
  const bool is_max = z >= zm;
  if (is_max) z = zm;
  const double s = p.sigma_hit, z_hit = p.z_hit, z_short = p.z_short, z_max = p.z_max, z_rand = p.z_rand;
  const double lambda = p.lambda_short, bin = p.max_bin_width;
  const auto Phi = [](double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); };
  const double mass = Phi((zm - z_exp) / s) - Phi(-z_exp / s);
  double d = z_hit * std::exp(-0.5 * (z - z_exp) * (z - z_exp) / (s * s)) / (s * std::sqrt(2.0 * M_PI)) / mass;
  if (z <= z_exp) d += z_short * lambda * std::exp(-lambda * z) / (1.0 - std::exp(-lambda * z_exp));
  d += is_max ? z_max / bin : z_rand / zm;
  return d;
}

// Integral over [0, z_max) by the midpoint rule with n cells, plus the max atom's mass.
double total_mass(const est::BeamRangeFinderModel& m, float z_exp, int n) {
  const double zm = m.params().range_max;
  const double h = zm / n;
  double sum = 0.0;
  for (int i = 0; i < n; ++i) sum += double(m.density(static_cast<float>((i + 0.5) * h), z_exp)) * h;
  return sum + double(m.params().z_max);
}

}  // namespace

TEST_CASE("beam model: continuous parts plus the max atom integrate to one over z", "[beam_model]") {
  est::BeamRangeFinderModel m;
  est::BeamModelParams p;
  p.range_max = 10.0f;
  p.sigma_hit = 0.1f;
  p.lambda_short = 0.8f;
  REQUIRE(m.configure(p) == est::SensorModelStatus::ok);
  // Tolerance 1e-4: midpoint rule with 1 mm cells around a 0.1 m Gaussian and the p_short jump at z*.
  for (float z_exp : {0.05f, 0.3f, 1.0f, 5.0f, 9.95f, 10.0f}) {
    INFO("z* = " << z_exp);
    CHECK(total_mass(m, z_exp, 200000) == Approx(1.0).margin(1e-4));
  }
  // Truncation near both ends matters: a wide Gaussian next to 0.
  p.sigma_hit = 2.0f;
  REQUIRE(m.configure(p) == est::SensorModelStatus::ok);
  CHECK(total_mass(m, 0.5f, 100000) == Approx(1.0).margin(1e-4));
  CHECK(total_mass(m, 9.5f, 100000) == Approx(1.0).margin(1e-4));
}

TEST_CASE("beam model density matches a double-precision reference of table 6.1", "[beam_model]") {
  est::BeamRangeFinderModel m;
  est::BeamModelParams p;
  p.range_max = 8.0f;
  p.sigma_hit = 0.15f;
  p.lambda_short = 1.2f;
  p.z_hit = 0.7f;
  p.z_short = 0.15f;
  p.z_max = 0.05f;
  p.z_rand = 0.1f;
  REQUIRE(m.configure(p) == est::SensorModelStatus::ok);
  for (float z_exp : {0.2f, 1.0f, 3.3f, 7.9f, 8.0f})
    for (float z : {0.0f, 0.1f, 0.19f, 0.25f, 0.9f, 1.05f, 3.0f, 3.3f, 3.5f, 7.95f, 8.0f, 9.0f}) {
      INFO("z* = " << z_exp << " z = " << z);
      const double ref = reference_density(double(z), double(z_exp), p);
      CHECK(double(m.density(z, z_exp)) == Approx(ref).epsilon(2e-5));
      CHECK(double(m.log_density(z, z_exp)) == Approx(std::log(ref)).margin(2e-5));
    }
  // Hand values, z* = 2, sigma 0.15. z = 2.1: hit 0.7 N(0.1; 0.15) = 0.7 * 2.12965337 = 1.49075736 (the
  // truncation mass is 1 to 1e-12 here), no short part beyond z*, rand 0.1 / 8 = 0.0125: total 1.50325736.
  // z = 1.9: the same hit and rand, plus short 0.15 * 1.2 e^{-2.28} / (1 - e^{-2.4}) = 0.02024801: 1.52350537.
  CHECK(m.density(2.1f, 2.0f) == Approx(1.50325736f).epsilon(1e-5));
  CHECK(m.density(1.9f, 2.0f) == Approx(1.52350537f).epsilon(1e-5));
  // A max reading: hit 0.7 N(6; 0.15) ~ 0, rand excluded, atom 0.05 / 0.05 m = 1 per metre.
  CHECK(m.density(8.0f, 2.0f) == Approx(1.0f).epsilon(1e-6));
  CHECK(m.density(50.0f, 2.0f) == m.density(8.0f, 2.0f));
}

TEST_CASE("beam model: log_peak is the density of a reading where a correct pose puts it", "[beam_model]") {
  // Without p_short (which it leaves out): a reading at its expected range mid-range, and a max reading on a ray with
  // no hit.
  est::BeamModelParams p;
  p.z_hit = 0.85f;
  p.z_short = 0.0f;
  p.z_max = 0.05f;
  p.z_rand = 0.10f;
  est::BeamRangeFinderModel m;
  REQUIRE(m.configure(p) == est::SensorModelStatus::ok);
  CHECK(m.log_peak(false) == Approx(m.log_density(6.0f, 6.0f)).margin(1e-6));
  CHECK(m.log_peak(true) == Approx(m.log_density(p.range_max, p.range_max)).margin(1e-6));
  // Away from z* the density is lower.
  CHECK(m.log_density(6.3f, 6.0f) < m.log_peak(false));
  CHECK(m.log_density(6.0f, p.range_max) < m.log_peak(false));
}

TEST_CASE("beam model: log_typical is a hit's mean log density, half a nat under the peak for a Gaussian",
          "[beam_model]") {
  // The origin of augmented MCL's per-beam recovery statistic (est/loop/beam_scan.hpp beam_scale). A Gaussian's mean
  // log density is its peak's minus 1/2 (its entropy): with the other components near 0 the mixture's is that.
  est::BeamModelParams g;
  g.z_hit = 1.0f - 2e-6f;
  g.z_short = 1e-6f;
  g.z_max = 0.0f;
  g.z_rand = 1e-6f;
  g.sigma_hit = 0.1f;
  est::BeamRangeFinderModel m;
  REQUIRE(m.configure(g) == est::SensorModelStatus::ok);
  CHECK(m.log_peak(false) - m.log_typical(false) == Approx(0.5).margin(0.005));
  CHECK(m.log_typical(true) == m.log_peak(true));  // a max reading on a ray with no hit is exact
  // The default mixture: E[log p(z | z*)] over z ~ N(z*, sigma^2) at z* = range_max / 2, against a fine sum here.
  est::BeamModelParams p;
  REQUIRE(m.configure(p) == est::SensorModelStatus::ok);
  const double z_exp = 0.5 * static_cast<double>(p.range_max), sigma = static_cast<double>(p.sigma_hit);
  double sum = 0.0, sum_w = 0.0;
  for (int i = -4000; i <= 4000; ++i) {
    const double u = i * 0.002, w = std::exp(-0.5 * u * u);
    sum += w * static_cast<double>(m.log_density(static_cast<float>(z_exp + u * sigma), static_cast<float>(z_exp)));
    sum_w += w;
  }
  CHECK(static_cast<double>(m.log_typical(false)) == Approx(sum / sum_w).margin(2e-3));
  CHECK(m.log_typical(false) < m.log_peak(false) - 0.3f);  // the short and random parts lift it above peak - 1/2
}

TEST_CASE("beam model parameters are validated", "[beam_model]") {
  est::BeamRangeFinderModel m;
  est::BeamModelParams p;
  p.z_hit = 0.9f;  // sums to 1.1
  CHECK(m.configure(p) == est::SensorModelStatus::bad_weights);
  CHECK_FALSE(m.ready());
  p = {};
  p.z_rand = -0.05f;
  p.z_hit = 0.9f;
  CHECK(m.configure(p) == est::SensorModelStatus::bad_weights);
  p = {};
  p.sigma_hit = 0.0f;
  CHECK(m.configure(p) == est::SensorModelStatus::bad_sigma);
  p = {};
  p.lambda_short = __builtin_nanf("");
  CHECK(m.configure(p) == est::SensorModelStatus::nonfinite);
  p = {};
  p.range_max = -1.0f;
  CHECK(m.configure(p) == est::SensorModelStatus::bad_range);
  p = {};
  p.max_bin_width = 0.0f;
  CHECK(m.configure(p) == est::SensorModelStatus::bad_bin);
}

TEST_CASE("beam model never returns NaN or -inf", "[beam_model]") {
  est::BeamRangeFinderModel m;
  est::BeamModelParams p;
  p.z_hit = 1.0f;
  p.z_short = p.z_max = p.z_rand = 0.0f;  // no floor from the mixture: the stated floor must hold
  p.sigma_hit = 0.01f;
  REQUIRE(m.configure(p) == est::SensorModelStatus::ok);
  const float nan = __builtin_nanf(""), inf = __builtin_inff();
  for (float z : {0.0f, 5.0f, 29.0f, 30.0f, 1e30f, -1.0f, nan, inf, -inf})
    for (float z_exp : {0.0f, 1.0f, 30.0f, -3.0f, 1e30f, nan, inf}) {
      const float l = m.log_density(z, z_exp);
      INFO("z = " << z << " z* = " << z_exp);
      CHECK(std::isfinite(l));
      CHECK(l >= est::kBeamLogDensityFloor);
    }
  CHECK(m.log_density(20.0f, 1.0f) == est::kBeamLogDensityFloor);
}

TEST_CASE("scan log-likelihood is the sum of per-beam log densities at the ray-cast ranges", "[beam_model]") {
  est::sim::make_office_map(g_grid);
  REQUIRE(g_edt.build(g_grid.grid()) == est::MapStatus::ok);
  const est::GridRayCaster exact(g_grid.grid());
  const est::DistanceTransformRayCaster fast(g_grid.grid(), g_edt.view());
  est::BeamRangeFinderModel m;
  est::BeamModelParams p;
  p.range_max = 12.0f;
  REQUIRE(m.configure(p) == est::SensorModelStatus::ok);

  // Simulate a 180 x 1 deg scan at the true pose from a mount 0.2 m ahead, flipped backwards.
  const est::Pose2 truth{4.0f, 7.2f, 0.3f};
  const est::Pose2 mount{0.2f, 0.0f, est::kPi};
  const est::ScanLayout layout{-est::kHalfPi, est::kPi / 180.0f, 180, 0.0f, 12.0f};
  float ranges[180];
  const est::SensorFrame f = est::sensor_frame(truth, mount);
  for (int k = 0; k < 180; ++k) {
    const double a = std::atan2(double(f.s), double(f.c)) + double(layout.angle_min) + k * double(layout.angle_increment);
    ranges[k] = exact.cast(f.x, f.y, static_cast<float>(std::cos(a)), static_cast<float>(std::sin(a)), 12.0f);
  }
  ranges[7] = __builtin_nanf("");
  ranges[8] = -1.0f;
  REQUIRE(g_scan.prepare(layout, ranges, 2) == est::ScanStatus::ok);
  const est::ScanBeams b = g_scan.beams();
  CHECK(b.count == 89);  // 90 kept on the stride, beam 8 rejected (beam 7 is off the stride)

  double by_hand = 0.0;
  for (int k = 0; k < b.count; ++k) {
    const float dx = f.c * b.ux[k] - f.s * b.uy[k], dy = f.s * b.ux[k] + f.c * b.uy[k];
    by_hand += double(m.log_density(b.is_max[k] ? 12.0f : b.range[k], exact.cast(f.x, f.y, dx, dy, 12.0f)));
  }
  const float l_exact = est::beam_range_finder_model(b, truth, mount, exact, m);
  const float l_fast = est::beam_range_finder_model(b, truth, mount, fast, m);
  CHECK(double(l_exact) == Approx(by_hand).epsilon(1e-5));
  CHECK(l_fast == l_exact);
  // The true pose explains the scan better than a displaced one.
  CHECK(l_exact > est::beam_range_finder_model(b, {4.3f, 7.2f, 0.3f}, mount, fast, m) + 20.0f);
  CHECK(l_exact > est::beam_range_finder_model(b, {4.0f, 7.2f, 0.4f}, mount, fast, m) + 20.0f);
  // Non-finite poses give the stated floor on every beam, never NaN.
  const float l_nan = est::beam_range_finder_model(b, {__builtin_nanf(""), 0.0f, 0.0f}, mount, fast, m);
  CHECK(l_nan == Approx(89.0f * est::kBeamLogDensityFloor));
  // A pose off the map: z* = 0 on every beam, finite.
  CHECK(std::isfinite(est::beam_range_finder_model(b, {-50.0f, 0.0f, 0.0f}, mount, fast, m)));
}

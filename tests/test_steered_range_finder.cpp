#include <catch2/catch.hpp>

#include <cmath>

#include "est/map/ray_casting.hpp"
#include "est/sensor/steered_range_finder.hpp"
#include "world/office_map.hpp"

namespace {
est::OccupancyGridStorage<400, 300> g_grid;
est::DistanceTransformStorage<400, 300> g_edt;
est::PreparedScan<90> g_scan;
}  // namespace

TEST_CASE("the steered mount rotates the sensor about the steering axis", "[steered_range_finder]") {
  est::SteeredMount m;
  m.pivot_x = 1.0f;
  m.sensor_on_part = {0.2f, 0.0f, 0.0f};
  const est::Pose2 a = est::steered_sensor_mount(m, 0.0f);
  CHECK(a.x == Approx(1.2f));
  CHECK(a.y == Approx(0.0f).margin(1e-7));
  const est::Pose2 b = est::steered_sensor_mount(m, est::kHalfPi);
  CHECK(b.x == Approx(1.0f).margin(1e-6));
  CHECK(b.y == Approx(0.2f).margin(1e-6));
  CHECK(b.theta == Approx(est::kHalfPi));
}

TEST_CASE("the marginalized steered model equals the explicit sum over steering positions", "[steered_range_finder]") {
  est::sim::make_office_map(g_grid);
  REQUIRE(g_edt.build(g_grid.grid()) == est::MapStatus::ok);
  const est::DistanceTransformRayCaster caster(g_grid.grid(), g_edt.view());
  est::BeamRangeFinderModel beam;
  est::BeamModelParams bp;
  bp.range_max = 10.0f;
  REQUIRE(beam.configure(bp) == est::SensorModelStatus::ok);
  est::LikelihoodField field;
  est::LikelihoodFieldParams lp;
  lp.range_max = 10.0f;
  REQUIRE(field.configure(lp, g_grid.grid(), g_edt.view()) == est::SensorModelStatus::ok);

  // Bicycle: handlebar axis 0.9 m ahead of the rear axle, the scanner 0.1 m ahead of it on the bar.
  est::SteeredMount mount;
  mount.pivot_x = 0.9f;
  mount.sensor_on_part = {0.1f, 0.0f, 0.0f};
  const float alphas[3] = {-0.3f, 0.0f, 0.3f};
  const float probs[3] = {0.2f, 0.5f, 0.3f};
  const est::Pose2 x{5.0f, 7.0f, 0.1f};

  // The scan as seen with the bar at +0.3 rad.
  const est::Pose2 true_mount = est::steered_sensor_mount(mount, 0.3f);
  const est::SensorFrame f = est::sensor_frame(x, true_mount);
  const est::ScanLayout layout{-est::kHalfPi, est::kPi / 89.0f, 90, 0.0f, 10.0f};
  float ranges[90];
  for (int k = 0; k < 90; ++k) {
    const double a = std::atan2(double(f.s), double(f.c)) + double(layout.angle_min) + k * double(layout.angle_increment);
    ranges[k] = caster.cast(f.x, f.y, static_cast<float>(std::cos(a)), static_cast<float>(std::sin(a)), 10.0f);
  }
  REQUIRE(g_scan.prepare(layout, ranges) == est::ScanStatus::ok);
  const est::ScanBeams b = g_scan.beams();

  double ll[3];
  for (int m = 0; m < 3; ++m)
    ll[m] = double(est::beam_range_finder_model(b, x, est::steered_sensor_mount(mount, alphas[m]), caster, beam));
  const double mx = std::max(ll[0], std::max(ll[1], ll[2]));
  double s = 0.0;
  for (int m = 0; m < 3; ++m) s += double(probs[m]) * std::exp(ll[m] - mx);
  const double explicit_sum = mx + std::log(s);
  const float marginal = est::steered_beam_range_finder_model(b, x, mount, alphas, probs, 3, caster, beam);
  // Relative 1e-6 of a log-likelihood of magnitude ~100: float rounding of the three sums.
  CHECK(double(marginal) == Approx(explicit_sum).epsilon(1e-6));
  // The steering is identifiable from the scan: the hypotheses differ by many nats (exp of such sums over- or
  // underflows float, hence log space).
  CHECK(ll[2] - ll[0] > 30.0);
  CHECK(ll[2] - ll[1] > 10.0);
  // The right steering dominates: the marginal is close to log p(+0.3) + ll(+0.3).
  CHECK(double(marginal) == Approx(std::log(0.3) + ll[2]).margin(1e-3));

  double lf[3];
  for (int m = 0; m < 3; ++m)
    lf[m] = double(est::likelihood_field_range_finder_model(b, x, est::steered_sensor_mount(mount, alphas[m]), field));
  const double mf = std::max(lf[0], std::max(lf[1], lf[2]));
  double sf = 0.0;
  for (int m = 0; m < 3; ++m) sf += double(probs[m]) * std::exp(lf[m] - mf);
  CHECK(double(est::steered_likelihood_field_range_finder_model(b, x, mount, alphas, probs, 3, field)) ==
        Approx(mf + std::log(sf)).epsilon(1e-6));

  // Zero, negative and NaN probabilities are skipped; with none left the result is the stated floor.
  const float bad[3] = {0.0f, -1.0f, __builtin_nanf("")};
  const float l_none = est::steered_beam_range_finder_model(b, x, mount, alphas, bad, 3, caster, beam);
  CHECK(l_none == Approx(90.0f * est::kBeamLogDensityFloor));
  const float one[3] = {0.0f, 0.0f, 1.0f};
  CHECK(est::steered_beam_range_finder_model(b, x, mount, alphas, one, 3, caster, beam) ==
        Approx(float(ll[2])).epsilon(1e-6));
}

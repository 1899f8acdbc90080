#include <catch2/catch.hpp>
#include <cstdio>
#include <string>

#include "sim/learn_beam_model.hpp"
#include "sim/record.hpp"
#include "sim/scenario.hpp"
#include "sim/sensor_stream.hpp"

// EM (Thrun table 6.2) on a recorded log recovers the rangefinder noise the simulator used, where the simulator's
// noise and the beam model agree: the hit spread, the share of random readings and of max readings. (The
// simulator's short readings are uniform on [0, z*], not exponential, so lambda_short is not compared.)
TEST_CASE("learn-beam-model recovers the simulated rangefinder's noise from a recorded log", "[learn_beam_model]") {
  sim::ScenarioConfig sc;
  sc.duration_s = 20.0;
  sc.seed = 3;
  sc.kidnap_at_s = -1.0;
  sc.burst_at_s = -1.0;
  sc.range_noise = {0.05f, 0.05f, 0.03f};  // sigma_hit, p_rand, p_short
  const sim::SimWorld world = sim::load_world(sc);
  const sim::SensorStream stream = sim::generate_stream(sc, world);
  const std::string path = "learn_beam_model_test.lcmlog";
  sim::record_lcm_log(stream, path);

  sim::LearnBeamModelOptions o;
  o.log_path = path;
  const sim::LearnBeamModelResult r = sim::learn_beam_model_from_log(o);
  std::remove(path.c_str());
  const est::BeamModelParams& p = r.learned.params;
  INFO("z_hit " << p.z_hit << " z_short " << p.z_short << " z_max " << p.z_max << " z_rand " << p.z_rand
                << " sigma_hit " << p.sigma_hit);
  CHECK(r.learned.converged);
  CHECK(r.scans_used == 200u);
  CHECK(r.readings_used == 200u * 90u);  // 360 beams, every 4th
  // 18000 readings: sigma within 5 %, random share within 0.01 absolute (its s.e. is ~0.0017).
  CHECK(p.sigma_hit == Approx(0.05).epsilon(0.05));
  CHECK(p.z_rand == Approx(0.05).margin(0.01));
  CHECK(p.z_short == Approx(0.03).margin(0.01));
  CHECK(p.z_hit + p.z_short + p.z_max + p.z_rand == Approx(1.0).margin(1e-4));
}

TEST_CASE("learn-beam-model refuses a log without scans or ground truth", "[learn_beam_model]") {
  sim::LearnBeamModelOptions o;
  o.log_path = "no_such_file.lcmlog";
  CHECK_THROWS(sim::learn_beam_model_from_log(o));
}

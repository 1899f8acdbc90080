// Estimates onto CAN: four frames per estimate sharing one counter; covariance as sigmas and correlations.
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <vector>

#include "hal/can/can_estimate_sink.hpp"
#include "hal/status_word.hpp"

using namespace hal::can;

namespace {
struct Bus final : CanTx {
  std::vector<CanFrame> frames;
  bool accept = true;
  bool send(const CanFrame& f) override {
    if (accept) frames.push_back(f);
    return accept;
  }
};
}  // namespace

TEST_CASE("an estimate becomes pose, sigma, correlation and status frames with one counter", "[can][sink]") {
  Bus bus;
  CanEstimateSink sink(bus);
  hal::Estimate e;
  e.pose = {12.5f, -3.25f, 1.0f};
  // sigma_x = 0.2, sigma_y = 0.5, sigma_theta = 0.1; rho_xy = 0.3, rho_xt = -0.5, rho_yt = 0
  e.covariance << 0.04f, 0.03f, -0.01f,
                  0.03f, 0.25f, 0.0f,
                  -0.01f, 0.0f, 0.01f;
  e.status = hal::status::kCanBusOff | hal::status::kScanTimeout;
  e.rejected_inputs = 70000;
  sink.publish(e);
  sink.publish(e);
  REQUIRE(bus.frames.size() == 8);
  PoseEstimateMsg p;
  PoseSigmaMsg s;
  PoseCorrelationMsg c;
  EstimatorStatusMsg st;
  REQUIRE(decode(bus.frames[0], p) == CodecStatus::ok);
  REQUIRE(decode(bus.frames[1], s) == CodecStatus::ok);
  REQUIRE(decode(bus.frames[2], c) == CodecStatus::ok);
  REQUIRE(decode(bus.frames[3], st) == CodecStatus::ok);
  CHECK(p.x_m == Approx(12.5).margin(5e-4));
  CHECK(p.y_m == Approx(-3.25).margin(5e-4));
  CHECK(s.sigma_x_m == Approx(0.2).margin(5e-4));
  CHECK(s.sigma_y_m == Approx(0.5).margin(5e-4));
  CHECK(s.sigma_theta_rad == Approx(0.1).margin(5e-5));
  CHECK(c.xy == Approx(0.3).margin(1e-4));
  CHECK(c.xtheta == Approx(-0.5).margin(1e-4));
  CHECK(c.ytheta == 0.0f);
  CHECK(st.status_word == (hal::status::kCanBusOff | hal::status::kScanTimeout));
  CHECK(st.rejected_inputs == 65535);  // saturated
  CHECK(p.counter == 0);
  CHECK(st.counter == 0);
  REQUIRE(decode(bus.frames[4], p) == CodecStatus::ok);
  CHECK(p.counter == 1);
}

TEST_CASE("a pose off the bus's range is not sent but the status still is; send failures are counted",
          "[can][sink]") {
  Bus bus;
  CanEstimateSink sink(bus);
  hal::Estimate e;
  e.pose = {5000.0f, 0.0f, 0.0f};
  sink.publish(e);
  e.pose = {std::numeric_limits<float>::quiet_NaN(), 0.0f, 0.0f};
  sink.publish(e);
  CHECK(sink.encode_failures() == 2);
  REQUIRE(bus.frames.size() == 2);
  CHECK(bus.frames[0].id == dbc::kEstimatorStatusId);
  bus.accept = false;
  e.pose = {1.0f, 0.0f, 0.0f};
  sink.publish(e);
  CHECK(sink.send_failures() == 4);
}

TEST_CASE("huge or degenerate covariances saturate instead of failing", "[can][sink]") {
  PoseSigmaMsg s;
  PoseCorrelationMsg c;
  Eigen::Matrix3f cov = Eigen::Matrix3f::Zero();
  cov(0, 0) = 1.0e6f;  // sigma 1000 m
  cov(1, 1) = -1.0f;   // not a variance
  cov(2, 2) = std::numeric_limits<float>::quiet_NaN();
  cov(0, 1) = cov(1, 0) = 5.0f;
  covariance_to_sigma_correlation(cov, s, c);
  CHECK(s.sigma_x_m == Approx(65.535));
  CHECK(s.sigma_y_m == 0.0f);
  CHECK(s.sigma_theta_rad == 0.0f);
  CHECK(c.xy == 0.0f);
  CanFrame f;
  CHECK(encode(s, f) == CodecStatus::ok);
  CHECK(encode(c, f) == CodecStatus::ok);
}

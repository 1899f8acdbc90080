#pragma once
// The estimate sink port: what the loop publishes after each step.
#include <cstdint>

#include "est/eigen.hpp"
#include "est/geometry/pose2.hpp"
#include "hal/time.hpp"

namespace hal {

struct Estimate {
  TimeNs stamp_ns = 0;
  est::Pose2 pose;
  Eigen::Matrix3f covariance = Eigen::Matrix3f::Zero();  // over (x, y, theta): m^2, m rad, rad^2
  std::uint32_t status = 0;                               // hal::status bits
  std::uint32_t rejected_inputs = 0;                      // total inputs rejected since start (saturating)
};

class EstimateSink {
 public:
  virtual void publish(const Estimate& estimate) = 0;

 protected:
  ~EstimateSink() = default;
};

}  // namespace hal

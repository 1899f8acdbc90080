#pragma once
// Publishes each estimate as POSE_ESTIMATE, POSE_SIGMA, POSE_CORRELATION and ESTIMATOR_STATUS, sharing one counter.
#include <cstdint>

#include "hal/can/frame.hpp"
#include "hal/can/estimate_frames.hpp"
#include "hal/estimate.hpp"

namespace hal::can {

// Covariance to the bus representation: sigmas (saturated at the DBC maximum) and correlations (clamped to
// [-1, 1]; 0 where a sigma is 0). A negative variance (never produced by a healthy filter) reads as sigma 0.
void covariance_to_sigma_correlation(const Eigen::Matrix3f& cov, PoseSigmaMsg& sigma, PoseCorrelationMsg& corr);

class CanEstimateSink final : public EstimateSink {
 public:
  explicit CanEstimateSink(CanTx& tx) : tx_(tx) {}

  // A pose outside the POSE_ESTIMATE range (|x|, |y| > 2097 m) or not finite is not sent, and counted.
  void publish(const Estimate& estimate) override;

  std::uint32_t encode_failures() const { return encode_failures_; }
  std::uint32_t send_failures() const { return send_failures_; }

 private:
  void send(const CanFrame& f);

  CanTx& tx_;
  std::uint8_t counter_ = 0;
  std::uint32_t encode_failures_ = 0;
  std::uint32_t send_failures_ = 0;
};

}  // namespace hal::can

// Estimates onto the bus (hal/can/can_estimate_sink.hpp).
#include "hal/can/can_estimate_sink.hpp"

#include "est/math/fmath.hpp"
#include "hal/can/estimate_frames.hpp"

namespace hal::can {

namespace {
float sigma_of(float variance, float max) {
  if (!(variance > 0.0f)) return 0.0f;  // also NaN
  const float s = est::fmath::sqrt(variance);
  return s < max ? s : max;
}
float correlation(float cov, float sa, float sb) {
  if (!(sa > 0.0f) || !(sb > 0.0f) || !est::fmath::isfinite(cov)) return 0.0f;
  const float r = cov / (sa * sb);
  return r > 1.0f ? 1.0f : (r < -1.0f ? -1.0f : r);
}
}  // namespace

void covariance_to_sigma_correlation(const Eigen::Matrix3f& cov, PoseSigmaMsg& sigma, PoseCorrelationMsg& corr) {
  using namespace dbc;
  sigma.sigma_x_m = sigma_of(cov(0, 0), kPoseSigmaSignals[kSigmaX].maximum);
  sigma.sigma_y_m = sigma_of(cov(1, 1), kPoseSigmaSignals[kSigmaY].maximum);
  sigma.sigma_theta_rad = sigma_of(cov(2, 2), kPoseSigmaSignals[kSigmaTheta].maximum);
  // Correlations from the unsaturated sigmas, so that a huge but consistent covariance keeps its shape.
  const float sx = sigma_of(cov(0, 0), 3.0e38f);
  const float sy = sigma_of(cov(1, 1), 3.0e38f);
  const float st = sigma_of(cov(2, 2), 3.0e38f);
  corr.xy = correlation(cov(0, 1), sx, sy);
  corr.xtheta = correlation(cov(0, 2), sx, st);
  corr.ytheta = correlation(cov(1, 2), sy, st);
}

void CanEstimateSink::send(const CanFrame& f) {
  if (!tx_.send(f)) ++send_failures_;
}

void CanEstimateSink::publish(const Estimate& e) {
  const std::uint8_t c = counter_;
  counter_ = static_cast<std::uint8_t>((counter_ + 1u) & 0x0Fu);

  CanFrame pose_frame, sigma_frame, corr_frame, status_frame;
  PoseEstimateMsg pose{e.pose.x, e.pose.y, e.pose.theta, c};
  PoseSigmaMsg sigma;
  PoseCorrelationMsg corr;
  covariance_to_sigma_correlation(e.covariance, sigma, corr);
  sigma.counter = c;
  corr.counter = c;
  EstimatorStatusMsg status;
  status.status_word = e.status;
  status.rejected_inputs = static_cast<std::uint16_t>(e.rejected_inputs > 0xFFFFu ? 0xFFFFu : e.rejected_inputs);
  status.counter = c;

  const bool pose_ok = encode(pose, pose_frame) == CodecStatus::ok && encode(sigma, sigma_frame) == CodecStatus::ok &&
                       encode(corr, corr_frame) == CodecStatus::ok;
  if (pose_ok) {
    send(pose_frame);
    send(sigma_frame);
    send(corr_frame);
  } else {
    ++encode_failures_;
  }
  (void)encode(status, status_frame);  // integers only: cannot fail
  send(status_frame);
}

}  // namespace hal::can

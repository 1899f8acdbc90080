// Estimate frames (hal/can/estimate_frames.hpp), the codec's status names and the message registry
// (hal/can/estimator_dbc.hpp).
#include "hal/can/estimate_frames.hpp"

#include "hal/can/estimator_dbc.hpp"

namespace hal::can {

using namespace dbc;

const char* to_string(CodecStatus s) {
  switch (s) {
    case CodecStatus::ok: return "ok";
    case CodecStatus::wrong_id: return "wrong_id";
    case CodecStatus::wrong_dlc: return "wrong_dlc";
    case CodecStatus::bad_checksum: return "bad_checksum";
    case CodecStatus::not_finite: return "not_finite";
    case CodecStatus::out_of_range: return "out_of_range";
  }
  return "unknown";
}

const MessageSpec* find_message(std::uint32_t id) {
  for (const MessageSpec& m : kMessages)
    if (m.id == id) return &m;
  return nullptr;
}

CodecStatus encode(const PoseEstimateMsg& m, CanFrame& f) {
  FrameWriter w(f, kPoseEstimateId, kPoseEstimateSignals);
  w.physical(kX, m.x_m);
  w.physical(kY, m.y_m);
  w.physical(kTheta, m.theta_rad);
  w.integer(kPoseCounter, counter4(m.counter));
  return w.status();
}

CodecStatus encode(const PoseSigmaMsg& m, CanFrame& f) {
  FrameWriter w(f, kPoseSigmaId, kPoseSigmaSignals);
  w.physical(kSigmaX, m.sigma_x_m);
  w.physical(kSigmaY, m.sigma_y_m);
  w.physical(kSigmaTheta, m.sigma_theta_rad);
  w.integer(kSigmaCounter, counter4(m.counter));
  return w.status();
}

CodecStatus encode(const PoseCorrelationMsg& m, CanFrame& f) {
  FrameWriter w(f, kPoseCorrelationId, kPoseCorrelationSignals);
  w.physical(kCorrXY, m.xy);
  w.physical(kCorrXTheta, m.xtheta);
  w.physical(kCorrYTheta, m.ytheta);
  w.integer(kCorrCounter, counter4(m.counter));
  return w.status();
}

CodecStatus encode(const EstimatorStatusMsg& m, CanFrame& f) {
  FrameWriter w(f, kEstimatorStatusId, kEstimatorStatusSignals);
  w.integer(kStatusWord, m.status_word);
  w.integer(kRejectedInputs, m.rejected_inputs);
  w.integer(kStatusCounter, counter4(m.counter));
  return w.status();
}

CodecStatus decode(const CanFrame& f, PoseEstimateMsg& m) {
  const CodecStatus c = check_frame(f, kPoseEstimateId);
  if (c != CodecStatus::ok) return c;
  m.x_m = decode_physical(f.data, kPoseEstimateSignals[kX]);
  m.y_m = decode_physical(f.data, kPoseEstimateSignals[kY]);
  m.theta_rad = decode_physical(f.data, kPoseEstimateSignals[kTheta]);
  m.counter = raw_u8(f, kPoseEstimateSignals[kPoseCounter]);
  return CodecStatus::ok;
}

CodecStatus decode(const CanFrame& f, PoseSigmaMsg& m) {
  const CodecStatus c = check_frame(f, kPoseSigmaId);
  if (c != CodecStatus::ok) return c;
  m.sigma_x_m = decode_physical(f.data, kPoseSigmaSignals[kSigmaX]);
  m.sigma_y_m = decode_physical(f.data, kPoseSigmaSignals[kSigmaY]);
  m.sigma_theta_rad = decode_physical(f.data, kPoseSigmaSignals[kSigmaTheta]);
  m.counter = raw_u8(f, kPoseSigmaSignals[kSigmaCounter]);
  return CodecStatus::ok;
}

CodecStatus decode(const CanFrame& f, PoseCorrelationMsg& m) {
  const CodecStatus c = check_frame(f, kPoseCorrelationId);
  if (c != CodecStatus::ok) return c;
  m.xy = decode_physical(f.data, kPoseCorrelationSignals[kCorrXY]);
  m.xtheta = decode_physical(f.data, kPoseCorrelationSignals[kCorrXTheta]);
  m.ytheta = decode_physical(f.data, kPoseCorrelationSignals[kCorrYTheta]);
  m.counter = raw_u8(f, kPoseCorrelationSignals[kCorrCounter]);
  return CodecStatus::ok;
}

CodecStatus decode(const CanFrame& f, EstimatorStatusMsg& m) {
  const CodecStatus c = check_frame(f, kEstimatorStatusId);
  if (c != CodecStatus::ok) return c;
  m.status_word = static_cast<std::uint32_t>(extract_raw(f.data, kEstimatorStatusSignals[kStatusWord]));
  m.rejected_inputs = raw_u16(f, kEstimatorStatusSignals[kRejectedInputs]);
  m.counter = raw_u8(f, kEstimatorStatusSignals[kStatusCounter]);
  return CodecStatus::ok;
}

}  // namespace hal::can

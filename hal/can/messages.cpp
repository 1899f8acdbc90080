// Typed messages of estimator.dbc (hal/can/messages.hpp), built on the table-driven signal packer.
#include "hal/can/messages.hpp"

#include "hal/can/crc.hpp"
#include "hal/can/signal.hpp"

namespace hal::can {

namespace {

using namespace dbc;

class Writer {
 public:
  Writer(CanFrame& f, std::uint32_t id, const SignalSpec* signals) : f_(f), signals_(signals) {
    f_ = CanFrame{};
    f_.id = id;
    f_.dlc = 8;
  }
  void physical(std::size_t i, float v) { note(encode_physical(f_.data, signals_[i], v)); }
  void integer(std::size_t i, std::int64_t v) { note(encode_integer(f_.data, signals_[i], v)); }
  CodecStatus status() const { return status_; }

 private:
  void note(EncodeStatus e) {
    if (status_ != CodecStatus::ok) return;
    if (e == EncodeStatus::not_finite) status_ = CodecStatus::not_finite;
    if (e == EncodeStatus::out_of_range) status_ = CodecStatus::out_of_range;
  }
  CanFrame& f_;
  const SignalSpec* signals_;
  CodecStatus status_ = CodecStatus::ok;
};

CodecStatus check_frame(const CanFrame& f, std::uint32_t id) {
  if (f.id != id) return CodecStatus::wrong_id;
  if (f.dlc != 8) return CodecStatus::wrong_dlc;
  return CodecStatus::ok;
}

std::uint8_t u8(const CanFrame& f, const SignalSpec& s) { return static_cast<std::uint8_t>(extract_raw(f.data, s)); }
std::uint16_t u16(const CanFrame& f, const SignalSpec& s) {
  return static_cast<std::uint16_t>(extract_raw(f.data, s));
}
std::int64_t counter4(std::uint8_t c) { return c & 0x0F; }

}  // namespace

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

std::uint16_t range_to_raw_mm(float range_m) {
  if (range_m != range_m || range_m < 0.0f) return 0;
  if (range_m >= 65.535f) return kNoReturnRaw;
  return static_cast<std::uint16_t>(static_cast<std::uint32_t>(range_m * 1000.0f + 0.5f));
}

float range_from_raw_mm(std::uint16_t raw) {
  if (raw == kNoReturnRaw) return __builtin_inff();
  return static_cast<float>(raw) * kScanDataSignals[kRange0].factor;
}

// ---- encode -----------------------------------------------------------------------------------------------------

CodecStatus encode(const WheelTicksMsg& m, CanFrame& f) {
  Writer w(f, kWheelTicksId, kWheelTicksSignals);
  w.integer(kTicksLeft, m.ticks_left);
  w.integer(kTicksRight, m.ticks_right);
  w.integer(kWheelCounter, counter4(m.counter));
  w.integer(kWheelChecksum, frame_crc8(f.id, f.data));
  return w.status();
}

CodecStatus encode(const SteeringMsg& m, CanFrame& f) {
  Writer w(f, kSteeringId, kSteeringSignals);
  w.physical(kSteeringAngle, m.angle_rad);
  w.integer(kSteeringCounter, counter4(m.counter));
  w.integer(kSteeringChecksum, frame_crc8(f.id, f.data));
  return w.status();
}

CodecStatus encode(const ScanHeaderMsg& m, CanFrame& f) {
  Writer w(f, kScanHeaderId, kScanHeaderSignals);
  w.integer(kHeaderScanId, m.scan_id);
  w.integer(kRangeCount, m.range_count);
  w.integer(kScanCrc, m.scan_crc);
  w.physical(kScanTime, m.scan_time_s);
  w.physical(kRangeMax, m.range_max_m);
  return w.status();
}

CodecStatus encode(const ScanInfoMsg& m, CanFrame& f) {
  Writer w(f, kScanInfoId, kScanInfoSignals);
  w.integer(kInfoScanId, m.scan_id);
  w.physical(kRangeMin, m.range_min_m);
  w.physical(kAngleMin, m.angle_min_rad);
  w.physical(kAngleIncrement, m.angle_increment_rad);
  return w.status();
}

CodecStatus encode(const ScanDataMsg& m, CanFrame& f) {
  Writer w(f, kScanDataId, kScanDataSignals);
  w.integer(kDataScanId, m.scan_id);
  w.integer(kSeq, m.seq);
  w.integer(kRange0, m.range_mm[0]);
  w.integer(kRange1, m.range_mm[1]);
  w.integer(kRange2, m.range_mm[2]);
  return w.status();
}

CodecStatus encode(const PoseEstimateMsg& m, CanFrame& f) {
  Writer w(f, kPoseEstimateId, kPoseEstimateSignals);
  w.physical(kX, m.x_m);
  w.physical(kY, m.y_m);
  w.physical(kTheta, m.theta_rad);
  w.integer(kPoseCounter, counter4(m.counter));
  return w.status();
}

CodecStatus encode(const PoseSigmaMsg& m, CanFrame& f) {
  Writer w(f, kPoseSigmaId, kPoseSigmaSignals);
  w.physical(kSigmaX, m.sigma_x_m);
  w.physical(kSigmaY, m.sigma_y_m);
  w.physical(kSigmaTheta, m.sigma_theta_rad);
  w.integer(kSigmaCounter, counter4(m.counter));
  return w.status();
}

CodecStatus encode(const PoseCorrelationMsg& m, CanFrame& f) {
  Writer w(f, kPoseCorrelationId, kPoseCorrelationSignals);
  w.physical(kCorrXY, m.xy);
  w.physical(kCorrXTheta, m.xtheta);
  w.physical(kCorrYTheta, m.ytheta);
  w.integer(kCorrCounter, counter4(m.counter));
  return w.status();
}

CodecStatus encode(const EstimatorStatusMsg& m, CanFrame& f) {
  Writer w(f, kEstimatorStatusId, kEstimatorStatusSignals);
  w.integer(kStatusWord, m.status_word);
  w.integer(kRejectedInputs, m.rejected_inputs);
  w.integer(kStatusCounter, counter4(m.counter));
  return w.status();
}

// ---- decode -----------------------------------------------------------------------------------------------------

CodecStatus decode(const CanFrame& f, WheelTicksMsg& m) {
  const CodecStatus c = check_frame(f, kWheelTicksId);
  if (c != CodecStatus::ok) return c;
  if (u8(f, kWheelTicksSignals[kWheelChecksum]) != frame_crc8(f.id, f.data)) return CodecStatus::bad_checksum;
  m.ticks_left = u16(f, kWheelTicksSignals[kTicksLeft]);
  m.ticks_right = u16(f, kWheelTicksSignals[kTicksRight]);
  m.counter = u8(f, kWheelTicksSignals[kWheelCounter]);
  return CodecStatus::ok;
}

CodecStatus decode(const CanFrame& f, SteeringMsg& m) {
  const CodecStatus c = check_frame(f, kSteeringId);
  if (c != CodecStatus::ok) return c;
  if (u8(f, kSteeringSignals[kSteeringChecksum]) != frame_crc8(f.id, f.data)) return CodecStatus::bad_checksum;
  m.angle_rad = decode_physical(f.data, kSteeringSignals[kSteeringAngle]);
  m.counter = u8(f, kSteeringSignals[kSteeringCounter]);
  return CodecStatus::ok;
}

CodecStatus decode(const CanFrame& f, ScanHeaderMsg& m) {
  const CodecStatus c = check_frame(f, kScanHeaderId);
  if (c != CodecStatus::ok) return c;
  m.scan_id = u8(f, kScanHeaderSignals[kHeaderScanId]);
  m.range_count = u16(f, kScanHeaderSignals[kRangeCount]);
  m.scan_crc = u16(f, kScanHeaderSignals[kScanCrc]);
  m.scan_time_s = decode_physical(f.data, kScanHeaderSignals[kScanTime]);
  m.range_max_m = decode_physical(f.data, kScanHeaderSignals[kRangeMax]);
  return CodecStatus::ok;
}

CodecStatus decode(const CanFrame& f, ScanInfoMsg& m) {
  const CodecStatus c = check_frame(f, kScanInfoId);
  if (c != CodecStatus::ok) return c;
  m.scan_id = u8(f, kScanInfoSignals[kInfoScanId]);
  m.range_min_m = decode_physical(f.data, kScanInfoSignals[kRangeMin]);
  m.angle_min_rad = decode_physical(f.data, kScanInfoSignals[kAngleMin]);
  m.angle_increment_rad = decode_physical(f.data, kScanInfoSignals[kAngleIncrement]);
  return CodecStatus::ok;
}

CodecStatus decode(const CanFrame& f, ScanDataMsg& m) {
  const CodecStatus c = check_frame(f, kScanDataId);
  if (c != CodecStatus::ok) return c;
  m.scan_id = u8(f, kScanDataSignals[kDataScanId]);
  m.seq = u16(f, kScanDataSignals[kSeq]);
  m.range_mm[0] = u16(f, kScanDataSignals[kRange0]);
  m.range_mm[1] = u16(f, kScanDataSignals[kRange1]);
  m.range_mm[2] = u16(f, kScanDataSignals[kRange2]);
  return CodecStatus::ok;
}

CodecStatus decode(const CanFrame& f, PoseEstimateMsg& m) {
  const CodecStatus c = check_frame(f, kPoseEstimateId);
  if (c != CodecStatus::ok) return c;
  m.x_m = decode_physical(f.data, kPoseEstimateSignals[kX]);
  m.y_m = decode_physical(f.data, kPoseEstimateSignals[kY]);
  m.theta_rad = decode_physical(f.data, kPoseEstimateSignals[kTheta]);
  m.counter = u8(f, kPoseEstimateSignals[kPoseCounter]);
  return CodecStatus::ok;
}

CodecStatus decode(const CanFrame& f, PoseSigmaMsg& m) {
  const CodecStatus c = check_frame(f, kPoseSigmaId);
  if (c != CodecStatus::ok) return c;
  m.sigma_x_m = decode_physical(f.data, kPoseSigmaSignals[kSigmaX]);
  m.sigma_y_m = decode_physical(f.data, kPoseSigmaSignals[kSigmaY]);
  m.sigma_theta_rad = decode_physical(f.data, kPoseSigmaSignals[kSigmaTheta]);
  m.counter = u8(f, kPoseSigmaSignals[kSigmaCounter]);
  return CodecStatus::ok;
}

CodecStatus decode(const CanFrame& f, PoseCorrelationMsg& m) {
  const CodecStatus c = check_frame(f, kPoseCorrelationId);
  if (c != CodecStatus::ok) return c;
  m.xy = decode_physical(f.data, kPoseCorrelationSignals[kCorrXY]);
  m.xtheta = decode_physical(f.data, kPoseCorrelationSignals[kCorrXTheta]);
  m.ytheta = decode_physical(f.data, kPoseCorrelationSignals[kCorrYTheta]);
  m.counter = u8(f, kPoseCorrelationSignals[kCorrCounter]);
  return CodecStatus::ok;
}

CodecStatus decode(const CanFrame& f, EstimatorStatusMsg& m) {
  const CodecStatus c = check_frame(f, kEstimatorStatusId);
  if (c != CodecStatus::ok) return c;
  m.status_word = static_cast<std::uint32_t>(extract_raw(f.data, kEstimatorStatusSignals[kStatusWord]));
  m.rejected_inputs = u16(f, kEstimatorStatusSignals[kRejectedInputs]);
  m.counter = u8(f, kEstimatorStatusSignals[kStatusCounter]);
  return CodecStatus::ok;
}

}  // namespace hal::can

#pragma once
// The estimator's outputs on the bus (estimator.dbc): POSE_ESTIMATE, POSE_SIGMA, POSE_CORRELATION and
// ESTIMATOR_STATUS, as structs in SI units with encode and decode (hal/can/can_estimate_sink.hpp sends them).
#include <cstddef>
#include <cstdint>

#include "hal/can/codec.hpp"

namespace hal::can {

namespace dbc {
inline constexpr std::uint32_t kPoseEstimateId = 0x300;
inline constexpr std::uint32_t kPoseSigmaId = 0x301;
inline constexpr std::uint32_t kPoseCorrelationId = 0x302;
inline constexpr std::uint32_t kEstimatorStatusId = 0x310;

enum PoseEstimateSignal : std::size_t { kX, kY, kTheta, kPoseCounter };
inline constexpr SignalSpec kPoseEstimateSignals[] = {
    {"X", 0, 22, LE, true, 0.001f, 0.0f, -2097.152f, 2097.151f, "m"},
    {"Y", 22, 22, LE, true, 0.001f, 0.0f, -2097.152f, 2097.151f, "m"},
    {"Theta", 44, 16, LE, true, 0.0001f, 0.0f, -3.2768f, 3.2767f, "rad"},
    {"Counter", 60, 4, LE, false, 1.0f, 0.0f, 0.0f, 15.0f, ""},
};

enum PoseSigmaSignal : std::size_t { kSigmaX, kSigmaY, kSigmaTheta, kSigmaCounter };
inline constexpr SignalSpec kPoseSigmaSignals[] = {
    {"SigmaX", 0, 16, LE, false, 0.001f, 0.0f, 0.0f, 65.535f, "m"},
    {"SigmaY", 16, 16, LE, false, 0.001f, 0.0f, 0.0f, 65.535f, "m"},
    {"SigmaTheta", 32, 16, LE, false, 0.0001f, 0.0f, 0.0f, 6.5535f, "rad"},
    {"Counter", 48, 4, LE, false, 1.0f, 0.0f, 0.0f, 15.0f, ""},
};

enum PoseCorrelationSignal : std::size_t { kCorrXY, kCorrXTheta, kCorrYTheta, kCorrCounter };
inline constexpr SignalSpec kPoseCorrelationSignals[] = {
    {"CorrXY", 0, 16, LE, true, 0.0001f, 0.0f, -1.0f, 1.0f, ""},
    {"CorrXTheta", 16, 16, LE, true, 0.0001f, 0.0f, -1.0f, 1.0f, ""},
    {"CorrYTheta", 32, 16, LE, true, 0.0001f, 0.0f, -1.0f, 1.0f, ""},
    {"Counter", 48, 4, LE, false, 1.0f, 0.0f, 0.0f, 15.0f, ""},
};

enum EstimatorStatusSignal : std::size_t { kStatusWord, kRejectedInputs, kStatusCounter };
inline constexpr SignalSpec kEstimatorStatusSignals[] = {
    {"StatusWord", 0, 32, LE, false, 1.0f, 0.0f, 0.0f, 4294967295.0f, ""},
    {"RejectedInputs", 32, 16, LE, false, 1.0f, 0.0f, 0.0f, 65535.0f, ""},
    {"Counter", 48, 4, LE, false, 1.0f, 0.0f, 0.0f, 15.0f, ""},
};
}  // namespace dbc

struct PoseEstimateMsg {
  float x_m = 0.0f;
  float y_m = 0.0f;
  float theta_rad = 0.0f;
  std::uint8_t counter = 0;
};

struct PoseSigmaMsg {
  float sigma_x_m = 0.0f;
  float sigma_y_m = 0.0f;
  float sigma_theta_rad = 0.0f;
  std::uint8_t counter = 0;
};

struct PoseCorrelationMsg {
  float xy = 0.0f;
  float xtheta = 0.0f;
  float ytheta = 0.0f;
  std::uint8_t counter = 0;
};

struct EstimatorStatusMsg {
  std::uint32_t status_word = 0;
  std::uint16_t rejected_inputs = 0;
  std::uint8_t counter = 0;
};

CodecStatus encode(const PoseEstimateMsg& m, CanFrame& f);
CodecStatus encode(const PoseSigmaMsg& m, CanFrame& f);
CodecStatus encode(const PoseCorrelationMsg& m, CanFrame& f);
CodecStatus encode(const EstimatorStatusMsg& m, CanFrame& f);

CodecStatus decode(const CanFrame& f, PoseEstimateMsg& m);
CodecStatus decode(const CanFrame& f, PoseSigmaMsg& m);
CodecStatus decode(const CanFrame& f, PoseCorrelationMsg& m);
CodecStatus decode(const CanFrame& f, EstimatorStatusMsg& m);

}  // namespace hal::can

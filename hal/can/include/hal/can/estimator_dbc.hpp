#pragma once
// The codec's copy of hal/can/estimator.dbc: every message of the bus, gathered from the sensors' codecs
// (hal/sensors/<sensor>/can.hpp) and the estimate frames. tests/test_can_dbc.cpp parses the DBC file and requires
// these tables to match it field for field.
//
// Landmark sightings have no frame: a sighting is a variable list of features from a camera or a marker detector,
// which sit on Ethernet rather than on a classic CAN bus; they travel on LCM (hal/sensors/landmarks/lcm.hpp).
#include <cstddef>
#include <cstdint>

#include "hal/can/estimate_frames.hpp"
#include "hal/can/signal_spec.hpp"
#include "hal/sensors/odometry/can.hpp"
#include "hal/sensors/range_scan/can_frames.hpp"
#include "hal/sensors/steering/can.hpp"
#include "hal/sensors/twist/can.hpp"
#include "hal/sensors/wheel_ticks/can.hpp"

namespace hal::can {

namespace dbc {

inline constexpr MessageSpec kMessages[] = {
    {"WHEEL_TICKS", kWheelTicksId, 8, "WHEEL_ENCODERS", kWheelTicksSignals, count_of(kWheelTicksSignals)},
    {"STEERING", kSteeringId, 8, "STEERING_SENSOR", kSteeringSignals, count_of(kSteeringSignals)},
    {"WHEEL_TICKS_EXT", kWheelTicksExtId, 8, "WHEEL_ENCODERS", kWheelTicksExtSignals,
     count_of(kWheelTicksExtSignals)},
    {"TWIST", kTwistId, 8, "BASE_CONTROLLER", kTwistSignals, count_of(kTwistSignals)},
    {"ODOMETRY", kOdometryId, 8, "BASE_CONTROLLER", kOdometrySignals, count_of(kOdometrySignals)},
    {"SCAN_HEADER", kScanHeaderId, 8, "RANGEFINDER", kScanHeaderSignals, count_of(kScanHeaderSignals)},
    {"SCAN_INFO", kScanInfoId, 8, "RANGEFINDER", kScanInfoSignals, count_of(kScanInfoSignals)},
    {"SCAN_DATA", kScanDataId, 8, "RANGEFINDER", kScanDataSignals, count_of(kScanDataSignals)},
    {"POSE_ESTIMATE", kPoseEstimateId, 8, "ESTIMATOR", kPoseEstimateSignals, count_of(kPoseEstimateSignals)},
    {"POSE_SIGMA", kPoseSigmaId, 8, "ESTIMATOR", kPoseSigmaSignals, count_of(kPoseSigmaSignals)},
    {"POSE_CORRELATION", kPoseCorrelationId, 8, "ESTIMATOR", kPoseCorrelationSignals,
     count_of(kPoseCorrelationSignals)},
    {"ESTIMATOR_STATUS", kEstimatorStatusId, 8, "ESTIMATOR", kEstimatorStatusSignals,
     count_of(kEstimatorStatusSignals)},
};

// The ids the estimator receives (its kernel receive filter) and sends.
inline constexpr std::uint32_t kInputIds[] = {kWheelTicksId, kSteeringId, kWheelTicksExtId, kTwistId,
                                              kOdometryId,   kScanHeaderId, kScanInfoId,    kScanDataId};
inline constexpr std::uint32_t kOutputIds[] = {kPoseEstimateId, kPoseSigmaId, kPoseCorrelationId,
                                               kEstimatorStatusId};

}  // namespace dbc

// The message with this id, or nullptr.
const MessageSpec* find_message(std::uint32_t id);

}  // namespace hal::can

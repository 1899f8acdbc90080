#pragma once
// The HAL's sensors, each in its folder hal/sensors/<sensor>/ (sample, validator, CAN codec, LCM conversion), and
// the two lists every port is built from: the raw samples a backend delivers, and the checked samples the gate
// (hal/validated_inputs.hpp) hands on, in the same order. A new sensor is a folder and an entry in both lists.
#include "est/loop/input_kinds.hpp"
#include "hal/sensors/landmarks/validator.hpp"
#include "hal/sensors/odometry/validator.hpp"
#include "hal/sensors/range_scan/validator.hpp"
#include "hal/sensors/steering/validator.hpp"
#include "hal/sensors/twist/validator.hpp"
#include "hal/sensors/wheel_ticks/validator.hpp"

namespace hal {

template <typename... Samples>
struct SampleList {};

using RawSamples =
    SampleList<WheelTicks, SteeringSample, TwistSample, OdometrySample, RangeScanView, LandmarkSightingView>;
using CheckedSamples =
    SampleList<WheelTickDelta, SteeringSample, TwistSample, OdometryDelta, RangeScanView, LandmarkSightingView>;

// The validator of each raw sample and what it yields.
template <typename Raw>
struct Validation;
template <> struct Validation<WheelTicks> { using Validator = WheelTicksValidator; using Checked = WheelTickDelta; };
template <> struct Validation<SteeringSample> { using Validator = SteeringValidator; using Checked = SteeringSample; };
template <> struct Validation<TwistSample> { using Validator = TwistValidator; using Checked = TwistSample; };
template <> struct Validation<OdometrySample> { using Validator = OdometryValidator; using Checked = OdometryDelta; };
template <> struct Validation<RangeScanView> { using Validator = RangeScanValidator; using Checked = RangeScanView; };
template <> struct Validation<LandmarkSightingView> {
  using Validator = LandmarkValidator;
  using Checked = LandmarkSightingView;
};

// The loop's input kind of each checked sample.
template <typename Checked>
struct KindOfChecked;
template <> struct KindOfChecked<WheelTickDelta> { static constexpr auto value = est::loop::InputKind::wheel_ticks; };
template <> struct KindOfChecked<SteeringSample> { static constexpr auto value = est::loop::InputKind::steering; };
template <> struct KindOfChecked<TwistSample> { static constexpr auto value = est::loop::InputKind::twist; };
template <> struct KindOfChecked<OdometryDelta> { static constexpr auto value = est::loop::InputKind::odometry; };
template <> struct KindOfChecked<RangeScanView> { static constexpr auto value = est::loop::InputKind::scan; };
template <> struct KindOfChecked<LandmarkSightingView> { static constexpr auto value = est::loop::InputKind::landmark; };

}  // namespace hal

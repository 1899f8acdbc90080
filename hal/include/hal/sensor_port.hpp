#pragma once
// The input ports. A backend (CAN, LCM, board driver, replay) calls SensorPort with raw decoded samples;
// ValidatedInputs checks them and calls ValidatedSensorPort, which is what the filter loop implements.
#include "hal/landmarks.hpp"
#include "hal/range_scan.hpp"
#include "hal/steering.hpp"
#include "hal/wheel_ticks.hpp"

namespace hal {

class SensorPort {
 public:
  virtual void on_wheel_ticks(const WheelTicks& sample) = 0;
  virtual void on_steering(const SteeringSample& sample) = 0;
  // The view is valid only during the call: copy what you keep.
  virtual void on_range_scan(const RangeScanView& scan) = 0;
  // The features of one sighting; the view is valid only during the call.
  virtual void on_landmarks(const LandmarkSightingView& sighting) = 0;

 protected:
  ~SensorPort() = default;
};

class ValidatedSensorPort {
 public:
  virtual void on_wheel_motion(const WheelTickDelta& delta) = 0;
  virtual void on_steering(const SteeringSample& sample) = 0;
  virtual void on_range_scan(const RangeScanView& scan) = 0;
  virtual void on_landmarks(const LandmarkSightingView& sighting) = 0;

 protected:
  ~ValidatedSensorPort() = default;
};

}  // namespace hal

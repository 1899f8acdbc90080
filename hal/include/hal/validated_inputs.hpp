#pragma once
// The HAL's gate: raw samples from any backend in, checked samples out to the loop, every reject counted.
#include "hal/landmark_validator.hpp"
#include "hal/range_scan_validator.hpp"
#include "hal/sensor_port.hpp"
#include "hal/steering_validator.hpp"
#include "hal/time.hpp"
#include "hal/wheel_ticks_validator.hpp"

namespace hal {

struct InputLimits {
  WheelTicksLimits wheels;
  SteeringLimits steering;
  RangeScanLimits scan;
  LandmarkLimits landmarks;
};

class ValidatedInputs final : public SensorPort {
 public:
  ValidatedInputs(const InputLimits& limits, Clock& clock, ValidatedSensorPort& out)
      : wheels_(limits.wheels),
        steering_(limits.steering),
        scan_(limits.scan),
        landmarks_(limits.landmarks),
        clock_(clock),
        out_(out) {}

  void on_wheel_ticks(const WheelTicks& sample) override;
  void on_steering(const SteeringSample& sample) override;
  void on_range_scan(const RangeScanView& scan) override;
  void on_landmarks(const LandmarkSightingView& sighting) override;

  const WheelTicksValidator& wheels() const { return wheels_; }
  const SteeringValidator& steering() const { return steering_; }
  const RangeScanValidator& scan() const { return scan_; }
  const LandmarkValidator& landmarks() const { return landmarks_; }
  // All kinds together.
  FaultCounters faults() const;

 private:
  WheelTicksValidator wheels_;
  SteeringValidator steering_;
  RangeScanValidator scan_;
  LandmarkValidator landmarks_;
  LandmarkSighting<kMaxLandmarkFeatures> landmark_buffer_;
  Clock& clock_;
  ValidatedSensorPort& out_;
};

}  // namespace hal

#pragma once
// The HAL's gate: raw samples from any backend in, checked samples out to the loop, every reject counted. One
// validator per sensor (hal/samples.hpp), each configured by its part of InputLimits.
#include <cstddef>

#include "hal/fault.hpp"
#include "hal/sensor_port.hpp"
#include "hal/time.hpp"

namespace hal {

struct InputLimits {
  WheelTicksLimits wheels;
  SteeringLimits steering;
  TwistLimits twist;
  OdometryLimits odometry;
  RangeScanLimits scan;
  LandmarkLimits landmarks;

  // The same staleness and skew limits for every sensor.
  void set_timing(const TimingLimits& t) {
    wheels.timing = steering.timing = twist.timing = odometry.timing = scan.timing = landmarks.timing = t;
  }
};

class ValidatedInputs final : public PortImplementation<ValidatedInputs, SensorPort> {
 public:
  ValidatedInputs(const InputLimits& limits, Clock& clock, ValidatedSensorPort& out)
      : wheels_(limits.wheels),
        steering_(limits.steering),
        twist_(limits.twist),
        odometry_(limits.odometry),
        scan_(limits.scan),
        landmarks_(limits.landmarks),
        clock_(clock),
        out_(&out) {}

  template <typename Raw>
  void handle(const Raw& sample) {
    typename Validation<Raw>::Checked checked{};
    if (validator<Raw>().check(sample, clock_.now_ns(), checked) == Fault::none) out_->on(checked);
  }
  void set_output(ValidatedSensorPort& out) { out_ = &out; }

  // The validator of a raw sample type, e.g. validator<WheelTicks>().
  template <typename Raw>
  const typename Validation<Raw>::Validator& validator() const {
    return const_cast<ValidatedInputs*>(this)->validator<Raw>();
  }
  template <typename Raw>
  typename Validation<Raw>::Validator& validator();

  const WheelTicksValidator& wheels() const { return wheels_; }
  const SteeringValidator& steering() const { return steering_; }
  const TwistValidator& twist() const { return twist_; }
  const OdometryValidator& odometry() const { return odometry_; }
  const RangeScanValidator& scan() const { return scan_; }
  const LandmarkValidator& landmarks() const { return landmarks_; }

  // f(name, faults) for every sensor, in the order of hal/samples.hpp.
  template <typename F>
  void for_each_sensor(F&& f) const {
    f(WheelTicksValidator::kName, wheels_.faults());
    f(SteeringValidator::kName, steering_.faults());
    f(TwistValidator::kName, twist_.faults());
    f(OdometryValidator::kName, odometry_.faults());
    f(RangeScanValidator::kName, scan_.faults());
    f(LandmarkValidator::kName, landmarks_.faults());
  }
  // All sensors together.
  FaultCounters faults() const {
    FaultCounters all;
    for_each_sensor([&](const char*, const FaultCounters& c) { all.merge(c); });
    return all;
  }

 private:
  WheelTicksValidator wheels_;
  SteeringValidator steering_;
  TwistValidator twist_;
  OdometryValidator odometry_;
  RangeScanValidator scan_;
  LandmarkValidator landmarks_;
  Clock& clock_;
  ValidatedSensorPort* out_;
};

template <> inline WheelTicksValidator& ValidatedInputs::validator<WheelTicks>() { return wheels_; }
template <> inline SteeringValidator& ValidatedInputs::validator<SteeringSample>() { return steering_; }
template <> inline TwistValidator& ValidatedInputs::validator<TwistSample>() { return twist_; }
template <> inline OdometryValidator& ValidatedInputs::validator<OdometrySample>() { return odometry_; }
template <> inline RangeScanValidator& ValidatedInputs::validator<RangeScanView>() { return scan_; }
template <> inline LandmarkValidator& ValidatedInputs::validator<LandmarkSightingView>() { return landmarks_; }

}  // namespace hal

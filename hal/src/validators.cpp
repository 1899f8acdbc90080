// The HAL validators (hal/*_validator.hpp) and the gate that applies them (hal/validated_inputs.hpp).
#include "hal/landmark_validator.hpp"
#include "hal/range_scan_validator.hpp"
#include "hal/steering_validator.hpp"
#include "hal/validated_inputs.hpp"
#include "hal/wheel_ticks_validator.hpp"

namespace hal {

namespace {
bool finite(float x) { return __builtin_isfinite(x); }
}  // namespace

const char* to_string(Fault f) {
  switch (f) {
    case Fault::none: return "none";
    case Fault::not_finite: return "not_finite";
    case Fault::out_of_range: return "out_of_range";
    case Fault::time_backwards: return "time_backwards";
    case Fault::duplicate: return "duplicate";
    case Fault::stale: return "stale";
    case Fault::from_future: return "from_future";
    case Fault::bad_geometry: return "bad_geometry";
    case Fault::too_few_valid_beams: return "too_few_valid_beams";
    case Fault::kCount: break;
  }
  return "unknown";
}

Fault WheelTicksValidator::check(const WheelTicks& sample, TimeNs now_ns, WheelTickDelta& out) {
  if (sample.wheel_count != limits_.wheel_count || sample.wheel_count > kMaxWheels) return reject(Fault::out_of_range);
  const std::uint32_t mask = counter_mask(limits_.counter_bits);
  for (std::size_t w = 0; w < sample.wheel_count; ++w)
    if (sample.count[w] > mask) return reject(Fault::out_of_range);
  const Fault t = timing_.check(sample.stamp_ns, now_ns);
  if (t != Fault::none) return reject(t);

  out = WheelTickDelta{};
  out.stamp_ns = sample.stamp_ns;
  out.wheel_count = sample.wheel_count;
  if (!timing_.has_last() || sample.stamp_ns - timing_.last_ns() > limits_.max_gap_ns) {
    timing_.accept(sample.stamp_ns);
    last_ = sample;
    return Fault::none;
  }
  const TimeNs dt = sample.stamp_ns - timing_.last_ns();
  for (std::size_t w = 0; w < sample.wheel_count; ++w) {
    const std::int32_t d = counter_delta(sample.count[w], last_.count[w], limits_.counter_bits);
    const std::int64_t magnitude = d < 0 ? -std::int64_t{d} : std::int64_t{d};
    // |d| / dt > max rate, in integers: |d| < 2^31 and 1e9 < 2^30, so the product fits in 63 bits.
    if (magnitude * kNsPerS > std::int64_t{limits_.max_ticks_per_s} * dt) {
      timing_.accept(sample.stamp_ns);
      last_ = sample;
      return reject(Fault::out_of_range);
    }
    out.ticks[w] = d;
  }
  out.dt_ns = dt;
  timing_.accept(sample.stamp_ns);
  last_ = sample;
  return Fault::none;
}

Fault SteeringValidator::check(const SteeringSample& sample, TimeNs now_ns) {
  Fault f = Fault::none;
  if (!finite(sample.angle_rad))
    f = Fault::not_finite;
  else if (sample.angle_rad > limits_.max_angle_rad || sample.angle_rad < -limits_.max_angle_rad)
    f = Fault::out_of_range;
  else
    f = timing_.check(sample.stamp_ns, now_ns);
  if (f != Fault::none) {
    faults_.add(f);
    return f;
  }
  timing_.accept(sample.stamp_ns);
  return Fault::none;
}

bool RangeScanValidator::geometry_ok(const ScanGeometry& g, std::size_t count) const {
  if (!(g.range_min_m >= 0.0f) || !(g.range_max_m > g.range_min_m) || g.range_max_m > limits_.max_range_m) return false;
  if (g.angle_increment_rad == 0.0f) return false;
  if (!(g.scan_time_s >= 0.0f) || g.scan_time_s > limits_.max_scan_time_s) return false;
  if (g.angle_min_rad < -7.0f || g.angle_min_rad > 7.0f) return false;
  // The whole fan must fit in one turn (plus one increment, for sensors that repeat the first beam).
  const float span = g.angle_increment_rad * static_cast<float>(count - 1u);
  const float limit = 6.2831853f + (g.angle_increment_rad < 0.0f ? -g.angle_increment_rad : g.angle_increment_rad);
  return span <= limit && span >= -limit;
}

Fault RangeScanValidator::check(const RangeScanView& scan, TimeNs now_ns) {
  const ScanGeometry& g = scan.geometry;
  if (!finite(g.angle_min_rad) || !finite(g.angle_increment_rad) || !finite(g.range_min_m) ||
      !finite(g.range_max_m) || !finite(g.scan_time_s))
    return reject(Fault::not_finite);
  if (scan.count == 0 || scan.count > limits_.max_beams || scan.ranges == nullptr) return reject(Fault::out_of_range);
  if (!geometry_ok(g, scan.count)) return reject(Fault::bad_geometry);
  const Fault t = timing_.check(scan.stamp_ns, now_ns);
  if (t != Fault::none) return reject(t);

  std::size_t valid = 0;
  for (std::size_t i = 0; i < scan.count; ++i) {
    const float r = scan.ranges[i];
    switch (classify_beam(r, g)) {
      case BeamClass::hit: ++beams_.hits; ++valid; break;
      case BeamClass::max_range: ++beams_.max_range; ++valid; break;
      case BeamClass::unusable:
        if (r != r) ++beams_.not_a_number; else ++beams_.below_min;
        break;
    }
  }
  if (valid < limits_.min_valid_beams) return reject(Fault::too_few_valid_beams);
  timing_.accept(scan.stamp_ns);
  return Fault::none;
}

Fault LandmarkValidator::check_feature(const LandmarkFeature& f) const {
  if (!finite(f.range_m) || !finite(f.bearing_rad) || !finite(f.signature)) return Fault::not_finite;
  if (!(f.range_m > 0.0f) || f.range_m > limits_.max_range_m) return Fault::out_of_range;
  if (f.bearing_rad > 3.14159274f || f.bearing_rad < -3.14159274f) return Fault::out_of_range;
  if (f.id < -1 || f.id > limits_.max_id) return Fault::out_of_range;
  return Fault::none;
}

Fault LandmarkValidator::check(const LandmarkSightingView& sighting, TimeNs now_ns,
                               LandmarkSighting<kMaxLandmarkFeatures>& out) {
  out.count = 0;
  out.stamp_ns = sighting.stamp_ns;
  if (sighting.count == 0 || sighting.count > limits_.max_features || sighting.count > kMaxLandmarkFeatures ||
      sighting.features == nullptr)
    return reject(Fault::out_of_range);
  const Fault t = timing_.check(sighting.stamp_ns, now_ns);
  if (t != Fault::none) return reject(t);
  for (std::size_t i = 0; i < sighting.count; ++i) {
    const Fault f = check_feature(sighting.features[i]);
    if (f == Fault::none)
      out.features[out.count++] = sighting.features[i];
    else
      faults_.add(f);
  }
  if (out.count == 0) return Fault::out_of_range;  // every feature already counted
  features_accepted_ += static_cast<std::uint32_t>(out.count);
  timing_.accept(sighting.stamp_ns);
  return Fault::none;
}

void ValidatedInputs::on_wheel_ticks(const WheelTicks& sample) {
  WheelTickDelta delta;
  if (wheels_.check(sample, clock_.now_ns(), delta) == Fault::none) out_.on_wheel_motion(delta);
}

void ValidatedInputs::on_steering(const SteeringSample& sample) {
  if (steering_.check(sample, clock_.now_ns()) == Fault::none) out_.on_steering(sample);
}

void ValidatedInputs::on_range_scan(const RangeScanView& scan) {
  if (scan_.check(scan, clock_.now_ns()) == Fault::none) out_.on_range_scan(scan);
}

void ValidatedInputs::on_landmarks(const LandmarkSightingView& sighting) {
  if (landmarks_.check(sighting, clock_.now_ns(), landmark_buffer_) == Fault::none)
    out_.on_landmarks(landmark_buffer_.view());
}

FaultCounters ValidatedInputs::faults() const {
  FaultCounters all = wheels_.faults();
  all.merge(steering_.faults());
  all.merge(scan_.faults());
  all.merge(landmarks_.faults());
  return all;
}

}  // namespace hal

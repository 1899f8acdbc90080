// The rangefinder validator (hal/sensors/range_scan/validator.hpp).
#include "hal/sensors/range_scan/validator.hpp"

namespace hal {

namespace {
bool finite(float x) { return __builtin_isfinite(x); }
}  // namespace

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

Fault RangeScanValidator::check(const RangeScanView& scan, TimeNs now_ns, RangeScanView& out) {
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
  out = scan;
  return Fault::none;
}

}  // namespace hal

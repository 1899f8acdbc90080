// Rangefinder scans on LCM (hal/sensors/range_scan/lcm.hpp).
#include "hal/sensors/range_scan/lcm.hpp"

namespace hal::lcm {

LcmReject to_hal(const est_lcm::range_scan_t& m, RangeScanView& out) {
  if (m.num_ranges < 0 || m.ranges_m.size() != static_cast<std::size_t>(m.num_ranges)) return LcmReject::bad_count;
  out.stamp_ns = m.stamp_ns;
  out.geometry = {m.angle_min_rad, m.angle_increment_rad, m.range_min_m, m.range_max_m, m.scan_time_s};
  out.ranges = m.ranges_m.data();
  out.count = m.ranges_m.size();
  return LcmReject::none;
}

est_lcm::range_scan_t to_lcm(const RangeScanView& s) {
  est_lcm::range_scan_t m{};
  m.stamp_ns = s.stamp_ns;
  m.angle_min_rad = s.geometry.angle_min_rad;
  m.angle_increment_rad = s.geometry.angle_increment_rad;
  m.range_min_m = s.geometry.range_min_m;
  m.range_max_m = s.geometry.range_max_m;
  m.scan_time_s = s.geometry.scan_time_s;
  if (s.ranges != nullptr) m.ranges_m.assign(s.ranges, s.ranges + s.count);
  m.num_ranges = static_cast<std::int32_t>(m.ranges_m.size());
  return m;
}

}  // namespace hal::lcm

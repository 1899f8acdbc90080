#pragma once
// Rangefinder scans on LCM: est_lcm::range_scan_t.
#include <cstdint>
#include <est_lcm/range_scan_t.hpp>

#include "hal/lcm/channels.hpp"
#include "hal/lcm/lcm_guard.hpp"
#include "hal/sensors/range_scan/range_scan.hpp"

namespace hal::lcm {

template <> struct LeadingCount<est_lcm::range_scan_t> { static constexpr int bytes = 4; };

// The view points into m.ranges_m: valid while m lives.
LcmReject to_hal(const est_lcm::range_scan_t& m, RangeScanView& out);
est_lcm::range_scan_t to_lcm(const RangeScanView& s);

template <>
struct LcmCodec<RangeScanView> {
  using Message = est_lcm::range_scan_t;
  static constexpr std::string Channels::*channel = &Channels::range_scan;
  struct Storage {};
  static std::int64_t max_count(const InputConfig& c) { return static_cast<std::int64_t>(c.max_ranges); }
  static LcmReject to_hal(const Message& m, const InputConfig&, Storage&, RangeScanView& out) {
    return lcm::to_hal(m, out);
  }
};

}  // namespace hal::lcm

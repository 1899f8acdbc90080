#pragma once
// Checks rangefinder scans: geometry, beam count, timing, and how many beams are usable. Unusable beams do not
// reject a scan (sensors report them routinely); they are counted, and the scan is rejected only when fewer than
// min_valid_beams remain. The filter skips them with classify_beam().
#include <cstddef>
#include <cstdint>

#include "hal/fault.hpp"
#include "hal/sensors/range_scan/range_scan.hpp"
#include "hal/sample_timing.hpp"
#include "hal/sample_validator.hpp"

namespace hal {

struct RangeScanLimits {
  std::size_t max_beams = 1081;
  std::size_t min_valid_beams = 10;  // hits plus max-range readings
  float max_range_m = 100.0f;        // the largest range_max a sensor may declare
  float max_scan_time_s = 1.0f;
  TimingLimits timing;
};

// Per-beam counts over every checked scan (not faults: sensors report unusable beams routinely).
struct BeamCounters {
  std::uint32_t hits = 0;
  std::uint32_t max_range = 0;
  std::uint32_t not_a_number = 0;
  std::uint32_t below_min = 0;
};

class RangeScanValidator : public SampleValidator<RangeScanLimits> {
 public:
  using Limits = RangeScanLimits;
  static constexpr const char* kName = "scan";

  explicit RangeScanValidator(const RangeScanLimits& limits = {}) : SampleValidator(limits) {}

  Fault check(const RangeScanView& scan, TimeNs now_ns, RangeScanView& out);

  const BeamCounters& beams() const { return beams_; }

 private:
  bool geometry_ok(const ScanGeometry& g, std::size_t count) const;

  BeamCounters beams_;
};

}  // namespace hal

#pragma once
// The per-scan half of the beam model of Thrun table 6.1: what a beam's density needs from its reading alone (the
// clamped range, the max-or-rand constant, p_short's numerator z_short lambda e^{-lambda z}), prepared once per scan
// with BeamRangeFinderModel::reading(), so N particles share one exp per beam instead of paying it N times. The
// density from a prepared reading is bit-identical to the model's density(z, z*) (tests/test_beam_readings.cpp).
#include <cstdint>

#include "est/sensor/beam_range_finder_model.hpp"
#include "est/sensor/range_scan.hpp"

namespace est {

// Read-only view: kept beam k's prepared reading, and the model parameters it was prepared with.
struct BeamReadings {
  const BeamRangeFinderModel::Reading* reading = nullptr;
  std::int32_t count = 0;
  BeamModelParams params{};

  // True when prepared from a scan of `beams` beams for a model configured as `model` is now.
  bool matches(std::int32_t beams, const BeamRangeFinderModel& model) const {
    const BeamModelParams& p = model.params();
    return reading != nullptr && count == beams && model.ready() && p.z_hit == params.z_hit &&
           p.z_short == params.z_short && p.z_max == params.z_max && p.z_rand == params.z_rand &&
           p.sigma_hit == params.sigma_hit && p.lambda_short == params.lambda_short &&
           p.range_max == params.range_max && p.max_bin_width == params.max_bin_width;
  }
};

class BeamReadingsBuffer {
 public:
  BeamReadingsBuffer(const BeamReadingsBuffer&) = delete;
  BeamReadingsBuffer& operator=(const BeamReadingsBuffer&) = delete;

  std::int32_t capacity() const { return capacity_; }

  // K exp, once per scan; a max reading is read as range_max, as beam_range_finder_model() does. False (and an empty
  // view) when the scan has more beams than the capacity or the model is not configured.
  bool prepare(const ScanBeams& z, const BeamRangeFinderModel& model) {
    count_ = 0;
    prepared_ = false;
    if (z.count > capacity_ || z.count < 0 || !model.ready()) return false;
    const float zm = model.params().range_max;
    for (std::int32_t k = 0; k < z.count; ++k) readings_[k] = model.reading(z.is_max[k] ? zm : z.range[k]);
    count_ = z.count;
    params_ = model.params();
    prepared_ = true;
    return true;
  }
  BeamReadings view() const { return {prepared_ ? readings_ : nullptr, count_, params_}; }

 protected:
  BeamReadingsBuffer(BeamRangeFinderModel::Reading* readings, std::int32_t capacity)
      : readings_(readings), capacity_(capacity) {}
  ~BeamReadingsBuffer() = default;

 private:
  BeamRangeFinderModel::Reading* readings_;
  std::int32_t capacity_;
  std::int32_t count_ = 0;
  BeamModelParams params_{};
  bool prepared_ = false;
};

template <std::int32_t KMax>
class BeamReadingsStorage final : public BeamReadingsBuffer {
  static_assert(KMax > 0, "capacity must be positive");

 public:
  BeamReadingsStorage() : BeamReadingsBuffer(readings_, KMax) {}

 private:
  BeamRangeFinderModel::Reading readings_[static_cast<std::uint32_t>(KMax)];
};

}  // namespace est

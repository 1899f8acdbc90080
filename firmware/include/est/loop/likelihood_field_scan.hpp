#pragma once
// MCL's correction with the likelihood field (Thrun table 6.3), one of the loop's range models (the others:
// est/loop/beam_scan.hpp, est/loop/steered_scan.hpp). A range model binds a sensor model, its map structures and
// the sensor's mounting to the particle filter's correction:
//   template <std::uint32_t N> CorrectionReport correct(AugmentedMcl<N>&, const ScanBeams&, const ScanContext&) const;
// The per-cell grid (4 bytes a cell, the fast path on a host) is used when one is given, otherwise the 4 KiB
// distance-bucket table (the small-memory path for a board); both give the same bits.
#include <cstdint>

#include "est/filter/augmented_mcl.hpp"
#include "est/geometry/pose2.hpp"
#include "est/sensor/likelihood_field_grid.hpp"
#include "est/sensor/likelihood_field_range_finder_model.hpp"
#include "est/sensor/range_scan.hpp"

namespace est::loop {

// What a range model may need besides the scan: the steering reading at the scan's time (a sensor on the handlebar).
struct ScanContext {
  float steering_rad = 0.0f;
  bool steering_known = false;
};

// The scale of the likelihood field's product for augmented MCL's recovery statistic (est/filter/augmented_mcl.hpp):
// its factors are the beams that are not max readings (table 6.3 skips those), each at most the field's largest term.
inline MeasurementScale likelihood_field_scale(const ScanBeams& beams, const LikelihoodField& field) {
  MeasurementScale scale{0, field.log_term_max()};
  for (std::int32_t k = 0; k < beams.count; ++k) scale.factors += beams.is_max[k] != 0u ? 0 : 1;
  return scale;
}

class LikelihoodFieldScan {
 public:
  // `grid`, if not null, must be tabulated from `field` over the same map; both outlive this.
  explicit LikelihoodFieldScan(const LikelihoodField& field, const Pose2& mount = {},
                               const LikelihoodFieldGrid* grid = nullptr)
      : field_(&field), grid_(grid), mount_(mount) {}

  template <std::uint32_t N>
  CorrectionReport correct(AugmentedMcl<N>& mcl, const ScanBeams& beams, const ScanContext&) const {
    const Pose2 mount = mount_;
    const LikelihoodField& field = *field_;
    const MeasurementScale scale = likelihood_field_scale(beams, field);
    if (grid_ != nullptr && grid_->valid()) {
      const LikelihoodFieldGrid& grid = *grid_;
      return mcl.correct_batch(
          [&](ConstParticleSetView v, float* out) {
            likelihood_field_range_finder_model_batch(beams, v.x, v.y, v.theta, v.count, mount, grid, out);
          },
          scale);
    }
    return mcl.correct([&](const Pose2& x) { return likelihood_field_range_finder_model(beams, x, mount, field); },
                       scale);
  }

  const Pose2& mount() const { return mount_; }

 private:
  const LikelihoodField* field_;
  const LikelihoodFieldGrid* grid_;
  Pose2 mount_;
};

}  // namespace est::loop

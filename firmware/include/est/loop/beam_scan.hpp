#pragma once
// MCL's correction with the beam model of Thrun table 6.1 (est/sensor/beam_range_finder_model.hpp), one of the
// loop's range models (est/loop/likelihood_field_scan.hpp states the concept). Two casters:
//  - BeamScan<Caster>: the expected range z* ray cast exactly per beam and particle (GridRayCaster, or
//    DistanceTransformRayCaster, which gives the same ranges faster): the board's path, memory the map and its
//    distance transform only, cost K casts per particle.
//  - BeamTableScan<KMax>: z* read from a HeadingRangeTable (est/map/heading_range_table.hpp: 2 T bytes per cell,
//    the synthetic office at T = 64 is 14.6 MiB, the Intel map 92 MiB; its error against the exact cast is stated
//    there), with the beams' bearings and the readings' per-scan terms prepared once per scan: the host's path.
//  - BeamConeScan<KMax, Cone>: z* cast exactly by a ConeRayCaster (est/map/cone_ray_caster.hpp: the same floats as
//    GridRayCaster; T bytes per cell, the Intel map at T = 64: 46 MiB) or a PackedConeRayCaster (the same floats,
//    T / 2 bytes per cell), bearings and readings prepared once per scan as the table's.
// Both weigh a particle by the book's product over the beams (in log space).
#include <cstdint>

#include "est/filter/augmented_mcl.hpp"
#include "est/geometry/pose2.hpp"
#include "est/loop/likelihood_field_scan.hpp"
#include "est/map/heading_range_table.hpp"
#include "est/map/cone_ray_caster.hpp"
#include "est/sensor/beam_range_finder_model.hpp"
#include "est/sensor/beam_range_finder_model_cone.hpp"
#include "est/sensor/beam_range_finder_model_table.hpp"
#include "est/sensor/beam_readings.hpp"
#include "est/sensor/range_scan.hpp"

namespace est::loop {

// The scale of the beam model's product for augmented MCL's recovery statistic (est/filter/augmented_mcl.hpp): every
// beam is a factor (table 6.1 weighs max readings too), the origin the mean of the beams' typical log density at a
// correct pose (BeamRangeFinderModel::log_typical: a hit's expectation, not the density's peak, which no scan reaches).
inline MeasurementScale beam_scale(const ScanBeams& beams, const BeamRangeFinderModel& model) {
  if (beams.count <= 0) return {0, 0.0f};
  std::int32_t n_max = 0;
  for (std::int32_t k = 0; k < beams.count; ++k) n_max += beams.is_max[k] != 0u ? 1 : 0;
  const float sum = static_cast<float>(n_max) * model.log_typical(true) +
                    static_cast<float>(beams.count - n_max) * model.log_typical(false);
  return {beams.count, sum / static_cast<float>(beams.count)};
}

template <typename Caster>
class BeamScan {
 public:
  // The caster and the model outlive this.
  BeamScan(const Caster& caster, const BeamRangeFinderModel& model, const Pose2& mount = {})
      : caster_(&caster), model_(&model), mount_(mount) {}

  template <std::uint32_t N>
  CorrectionReport correct(AugmentedMcl<N>& mcl, const ScanBeams& beams, const ScanContext&) {
    const Pose2 mount = mount_;
    const Caster& caster = *caster_;
    const BeamRangeFinderModel& model = *model_;
    return mcl.correct([&](const Pose2& x) { return beam_range_finder_model(beams, x, mount, caster, model); },
                       beam_scale(beams, model));
  }

  const Pose2& mount() const { return mount_; }

 private:
  const Caster* caster_;
  const BeamRangeFinderModel* model_;
  Pose2 mount_;
};

template <std::int32_t KMax>
class BeamTableScan {
 public:
  // The table and the model outlive this.
  BeamTableScan(const HeadingRangeTable& table, const BeamRangeFinderModel& model, const Pose2& mount = {})
      : table_(&table), model_(&model), mount_(mount) {}
  BeamTableScan(const BeamTableScan& o) : table_(o.table_), model_(o.model_), mount_(o.mount_) {}
  BeamTableScan& operator=(const BeamTableScan&) = delete;

  template <std::uint32_t N>
  CorrectionReport correct(AugmentedMcl<N>& mcl, const ScanBeams& beams, const ScanContext&) {
    bearings_.prepare(beams, *table_);
    readings_.prepare(beams, *model_);
    const BeamBearings b = bearings_.view();
    const BeamReadings r = readings_.view();
    const Pose2 mount = mount_;
    const HeadingRangeTable& table = *table_;
    const BeamRangeFinderModel& model = *model_;
    return mcl.correct(
        [&](const Pose2& x) { return beam_range_finder_model(beams, b, r, x, mount, table, model); },
        beam_scale(beams, model));
  }

  const Pose2& mount() const { return mount_; }

 private:
  const HeadingRangeTable* table_;
  const BeamRangeFinderModel* model_;
  Pose2 mount_;
  BeamBearingsStorage<KMax> bearings_;
  BeamReadingsStorage<KMax> readings_;
};

template <std::int32_t KMax, class Cone = ConeRayCaster>
class BeamConeScan {
 public:
  // The caster and the model outlive this.
  BeamConeScan(const Cone& cone, const BeamRangeFinderModel& model, const Pose2& mount = {})
      : cone_(&cone), model_(&model), mount_(mount) {}
  BeamConeScan(const BeamConeScan& o) : cone_(o.cone_), model_(o.model_), mount_(o.mount_) {}
  BeamConeScan& operator=(const BeamConeScan&) = delete;

  template <std::uint32_t N>
  CorrectionReport correct(AugmentedMcl<N>& mcl, const ScanBeams& beams, const ScanContext&) {
    bearings_.prepare(beams, cone_->bins());
    readings_.prepare(beams, *model_);
    const BeamBearings b = bearings_.view();
    const BeamReadings r = readings_.view();
    const Pose2 mount = mount_;
    const Cone& cone = *cone_;
    const BeamRangeFinderModel& model = *model_;
    return mcl.correct(
        [&](const Pose2& x) { return beam_range_finder_model(beams, b, r, x, mount, cone, model); },
        beam_scale(beams, model));
  }

  const Pose2& mount() const { return mount_; }

 private:
  const Cone* cone_;
  const BeamRangeFinderModel* model_;
  Pose2 mount_;
  BeamBearingsStorage<KMax> bearings_;
  BeamReadingsStorage<KMax> readings_;
};

}  // namespace est::loop

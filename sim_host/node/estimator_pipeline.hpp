#pragma once
// The estimator every host program runs, composed once (hal/pipeline.hpp: the HAL gate, the loop port, the
// firmware's filter loop, the estimate sink) around the estimator an EstimatorSpec chooses: one of the six motion
// models, MCL with a range model, the EKF or EKF-SLAM, at the host's capacities. The map models (distance transform,
// likelihood field and its per-cell grid, free space, the beam model and its heading range table) are built here
// from the caller's maps. estimator_node and the simulator both use it; a board states its choice statically
// instead (est/loop/configured_loop.hpp) and composes hal::Pipeline itself. Host only: throws
// std::invalid_argument on a configuration the firmware refuses.
#include <cstdint>
#include <memory>
#include <string>

#include "est/filter/augmented_mcl.hpp"
#include "est/filter/correction_status.hpp"
#include "est/filter/ekf_localization.hpp"
#include "est/loop/ekf_estimator.hpp"
#include "est/loop/ekf_slam_estimator.hpp"
#include "est/loop/input_kinds.hpp"
#include "est/loop/loop_counters.hpp"
#include "est/map/landmark_map.hpp"
#include "hal/estimate.hpp"
#include "hal/loop_port.hpp"
#include "hal/sensor_port.hpp"
#include "hal/validated_inputs.hpp"
#include "node/estimator_spec.hpp"

namespace node {

// The host's capacities (the loop and the filter are statically sized, as on a board).
inline constexpr std::uint32_t kMaxParticles = 20000;
inline constexpr std::int32_t kMaxBeams = 1440;
inline constexpr std::uint32_t kQueueCapacity = 256;
inline constexpr std::uint32_t kScanSlots = 4;
// EKF-SLAM's map (the covariance is (3 + 2 M)^2 floats: 2.6 MB at 400) and its tentative landmarks.
inline constexpr std::int32_t kSlamLandmarks = 400;
inline constexpr std::int32_t kSlamTentative = 256;

class EstimatorPipeline {
 public:
  virtual ~EstimatorPipeline() = default;

  virtual hal::SensorPort& input() = 0;                         // raw samples in (the HAL gate)
  virtual void set_tap(hal::ValidatedSensorPort& tap) = 0;      // checked samples through `tap` to adapter()
  virtual hal::ValidatedSensorPort& adapter() = 0;
  virtual void refresh(std::uint32_t transport_bits, std::uint32_t transport_rejects) = 0;
  virtual void flush() = 0;

  virtual const hal::ValidatedInputs& gate() const = 0;
  virtual const est::loop::LoopCounters& loop_counters() const = 0;
  virtual const hal::LoopPortRejectCounters& port_rejects() const = 0;
  virtual std::uint32_t published() const = 0;
  virtual std::uint32_t nonfinite_estimates() const = 0;
  virtual est::loop::InputKinds inputs() const = 0;  // the kinds the estimator uses
  virtual std::string description() const = 0;      // model, filter, range model, particles

  virtual est::PoseEstimate estimate() const = 0;    // the estimator's, now

  // MCL: the particles and the filter's counters (nullptr and an empty set for the EKF); EKF: its counters.
  virtual est::ConstParticleSetView particles() const = 0;
  virtual const est::MclCounters* mcl_counters() const = 0;
  virtual const est::CorrectionCounters* ekf_counters() const = 0;
  virtual const est::PredictionCounters* ekf_prediction_counters() const = 0;
  // The EKF: its gate's re-openings (0 for the other filters); with --joint-association, where each camera frame's
  // features went (nullptr otherwise).
  virtual std::uint32_t ekf_reopenings() const = 0;
  virtual const est::loop::JointAssociationCounters* joint_counters() const = 0;

  // EKF-SLAM: where each feature went (nullptr for the other filters), and the map.
  virtual const est::loop::SlamAssociationCounters* slam_counters() const = 0;
  virtual int slam_landmarks() const = 0;
  virtual int slam_tentative_landmarks() const = 0;
  virtual est::Landmark slam_landmark(int k) const = 0;  // position and the mean signature of its sightings
};

// `sample_clock`: what the gate judges staleness against; `step_clock` times the steps; both outlive the pipeline,
// as do the maps and the sink.
std::unique_ptr<EstimatorPipeline> make_estimator_pipeline(const EstimatorSpec& spec, const EstimatorMaps& maps,
                                                           hal::Clock& sample_clock, hal::Clock& step_clock,
                                                           hal::EstimateSink& sink);

}  // namespace node

#pragma once
// The estimator pipeline's implementation (node/estimator_pipeline.hpp), a template over the model, the filter and
// the range model; instantiated once per motion model (node/pipeline_<model>.cpp, so they compile in parallel).
// Private to node/.
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "est/filter/free_space_sampler.hpp"
#include "est/loop/beam_scan.hpp"
#include "est/loop/configured_loop.hpp"
#include "est/loop/likelihood_field_scan.hpp"
#include "est/loop/steered_scan.hpp"
#include "est/map/heading_range_table.hpp"
#include "est/map/ray_casting.hpp"
#include "est/sensor/likelihood_field_grid.hpp"
#include "hal/pipeline.hpp"
#include "node/estimator_pipeline.hpp"

namespace node::detail {

// Heap-backed owners of the firmware's runtime-capacity buffers: on the host the map decides their size.
struct FieldCells {
  std::vector<std::uint16_t> cells;
};
class HeapFieldGrid : private FieldCells, public est::LikelihoodFieldGridBuffer {
 public:
  HeapFieldGrid(std::int32_t w, std::int32_t h)
      : FieldCells{std::vector<std::uint16_t>(est::LikelihoodFieldGridBuffer::cells_for(w, h))},
        LikelihoodFieldGridBuffer(cells.data(), w, h) {}
};
struct TableUnits {
  std::vector<std::uint16_t> units;
};
class HeapHeadingTable : private TableUnits, public est::HeadingRangeTableBuffer {
 public:
  explicit HeapHeadingTable(std::size_t entries)
      : TableUnits{std::vector<std::uint16_t>(entries)},
        HeadingRangeTableBuffer(units.data(), static_cast<std::uint32_t>(entries)) {}
};

// The cone caster's arrays sized from the map (T <= 1024): T bytes per cell for the table, the build's two prefix
// counts, a line of bounds and one byte per cell of scratch.
struct ConeArrays {
  ConeArrays(const est::OccupancyGrid& g, std::int32_t bins)
      : n_t(static_cast<std::size_t>(bins < 8 ? 8 : (bins > 1024 ? 1024 : bins))),
        w(static_cast<std::size_t>(g.width())), h(static_cast<std::size_t>(g.height())),
        f(new float[2u * n_t + (w > h ? w : h)]), entry(new std::uint8_t[n_t * w * h + w * h]),
        prefix(new std::uint16_t[w * (h + 1u) + h * (w + 1u)]) {}
  std::size_t n_t, w, h;
  std::unique_ptr<float[]> f;
  std::unique_ptr<std::uint8_t[]> entry;
  std::unique_ptr<std::uint16_t[]> prefix;
};
class HeapCone : private ConeArrays, public est::ConeRayCasterBuffer {
 public:
  HeapCone(const est::OccupancyGrid& g, std::int32_t bins)
      : ConeArrays(g, bins),
        ConeRayCasterBuffer(f.get(), f.get() + n_t, static_cast<std::int32_t>(n_t), entry.get(), g.width(), g.height(),
                            prefix.get(), prefix.get() + w * (h + 1u), f.get() + 2u * n_t, entry.get() + n_t * w * h) {}
};

// What the range models and recovery precompute from the map; owned by the pipeline.
struct MapModels {
  est::LikelihoodField field;
  std::unique_ptr<HeapFieldGrid> field_grid;
  est::LikelihoodFieldGrid field_grid_view;
  est::FreeSpaceSampler free_space;
  est::BeamRangeFinderModel beam;
  std::unique_ptr<HeapHeadingTable> table;
  est::HeadingRangeTable table_view;
  std::unique_ptr<HeapCone> cone;
  est::ConeRayCaster cone_view;
};
std::unique_ptr<MapModels> build_map_models(const EstimatorSpec& spec, const EstimatorMaps& maps);

template <typename Model>
typename Model::Params motion_params(const MotionSpec& m);
template <typename Model>
typename est::loop::ControlAssembler<Model>::Config control_config(const MotionSpec&) {
  return {};
}
template <> inline est::VelocityParams motion_params<est::VelocityMotionModel>(const MotionSpec& m) { return m.velocity; }
template <> inline est::OdometryParams motion_params<est::OdometryMotionModel>(const MotionSpec& m) { return m.odometry; }
template <> inline est::BicycleParams motion_params<est::BicycleMotionModel>(const MotionSpec& m) { return m.bicycle; }
template <> inline est::DiffDriveParams motion_params<est::DiffDriveMotionModel>(const MotionSpec& m) { return m.diff_drive; }
template <> inline est::OmniParams motion_params<est::OmniMotionModel>(const MotionSpec& m) { return m.omni; }
template <> inline est::HolonomicPoseParams motion_params<est::HolonomicPoseMotionModel>(const MotionSpec& m) {
  return m.holonomic;
}


template <>
inline est::loop::ControlAssembler<est::BicycleMotionModel>::Config control_config<est::BicycleMotionModel>(const MotionSpec& m) {
  return m.bicycle_control;
}
template <>
inline est::loop::ControlAssembler<est::OmniMotionModel>::Config control_config<est::OmniMotionModel>(const MotionSpec& m) {
  return m.omni_control;
}
template <>
inline est::loop::ControlAssembler<est::HolonomicPoseMotionModel>::Config control_config<est::HolonomicPoseMotionModel>(
    const MotionSpec& m) {
  return m.holonomic_control;
}


std::string describe(const EstimatorSpec& spec);

template <typename ScanModel>
ScanModel make_scan_model(const EstimatorSpec& spec, const MapModels& m);
template <>
inline est::loop::LikelihoodFieldScan make_scan_model<est::loop::LikelihoodFieldScan>(const EstimatorSpec& spec,
                                                                                        const MapModels& m) {
  return est::loop::LikelihoodFieldScan(m.field, spec.sensor_mount, &m.field_grid_view);
}
using HostBeamScan = est::loop::BeamTableScan<kMaxBeams>;
template <>
inline HostBeamScan make_scan_model<HostBeamScan>(const EstimatorSpec& spec, const MapModels& m) {
  return HostBeamScan(m.table_view, m.beam, spec.sensor_mount);
}
using HostBeamConeScan = est::loop::BeamConeScan<kMaxBeams>;
template <>
inline HostBeamConeScan make_scan_model<HostBeamConeScan>(const EstimatorSpec& spec, const MapModels& m) {
  return HostBeamConeScan(m.cone_view, m.beam, spec.sensor_mount);
}
using HostSteeredScan = est::loop::SteeredScan<kMaxParticles>;
template <>
inline HostSteeredScan make_scan_model<HostSteeredScan>(const EstimatorSpec& spec, const MapModels& m) {
  return HostSteeredScan(m.field, spec.steered, &m.field_grid_view);
}

template <typename Model, est::loop::Filter F, typename ScanModel>
class PipelineImpl final : public EstimatorPipeline {
 public:
  using Configured = est::loop::ConfiguredLoop<
      est::loop::LoopConfig<Model, F, kMaxParticles, kMaxBeams, kQueueCapacity, kScanSlots, ScanModel,
                            est::loop::kHostJointSightings,  // the EKF with joint association (--joint-association)
                            kSlamLandmarks, kSlamTentative>>;
  using Estimator = typename Configured::Estimator;
  static constexpr bool kMcl = F == est::loop::Filter::mcl;
  static constexpr bool kSlam = F == est::loop::Filter::ekf_slam;

  PipelineImpl(const EstimatorSpec& spec, const EstimatorMaps& maps, hal::Clock& sample_clock, hal::Clock& step_clock,
               hal::EstimateSink& sink)
      : spec_(spec),
        models_(build_map_models(spec, maps)),
        estimator_(construct(spec, maps, *models_)),
        loop_(estimator_, spec.timing),
        pipeline_(loop_, spec.limits, sample_clock, step_clock, sink) {
    if constexpr (kMcl) {
      if (spec.global)
        estimator_.initialize_global(spec.particles);
      else
        estimator_.initialize_at(spec.initial_pose, spec.initial_sigma_xy_m, spec.initial_sigma_theta_rad,
                                 spec.particles);
    } else {
      if (spec.global)
        throw std::invalid_argument("the EKF tracks from an initial pose: global localization needs MCL");
      if (!estimator_.initialize_at(spec.initial_pose, spec.initial_sigma_xy_m, spec.initial_sigma_theta_rad))
        throw std::invalid_argument("EKF: the initial pose and sigmas must be finite and the sigmas positive");
    }
  }

  hal::SensorPort& input() override { return pipeline_.input(); }
  void set_tap(hal::ValidatedSensorPort& tap) override { pipeline_.set_tap(tap); }
  hal::ValidatedSensorPort& adapter() override { return pipeline_.adapter(); }
  void refresh(std::uint32_t bits, std::uint32_t rejects) override { pipeline_.refresh(bits, rejects); }
  void flush() override { pipeline_.flush(); }
  const hal::ValidatedInputs& gate() const override { return pipeline_.gate(); }
  const est::loop::LoopCounters& loop_counters() const override { return loop_.counters(); }
  const hal::LoopPortRejectCounters& port_rejects() const override { return pipeline_.port().rejects(); }
  std::uint32_t published() const override { return pipeline_.port().published(); }
  std::uint32_t nonfinite_estimates() const override { return pipeline_.port().nonfinite_estimates(); }
  est::loop::InputKinds inputs() const override { return loop_.inputs(); }
  std::string description() const override { return describe(spec_); }

  est::PoseEstimate estimate() const override { return estimator_.estimate(); }

  est::ConstParticleSetView particles() const override {
    if constexpr (kMcl) return estimator_.filter().particles();
    else return empty_set();
  }
  const est::MclCounters* mcl_counters() const override {
    if constexpr (kMcl) return &estimator_.filter().counters();
    else return nullptr;
  }
  const est::CorrectionCounters* ekf_counters() const override {
    if constexpr (kMcl) return nullptr;
    else return &estimator_.filter().counters();
  }
  const est::PredictionCounters* ekf_prediction_counters() const override {
    if constexpr (kMcl) return nullptr;
    else return &estimator_.filter().prediction_counters();
  }
  std::uint32_t ekf_reopenings() const override {
    if constexpr (F == est::loop::Filter::ekf) return estimator_.reopenings();
    else return 0;
  }
  const est::loop::JointAssociationCounters* joint_counters() const override {
    if constexpr (F == est::loop::Filter::ekf) return spec_.joint_association ? &estimator_.joint_counters() : nullptr;
    else return nullptr;
  }
  const est::loop::SlamAssociationCounters* slam_counters() const override {
    if constexpr (kSlam) return &estimator_.counters();
    else return nullptr;
  }
  int slam_landmarks() const override {
    if constexpr (kSlam) return estimator_.landmarks();
    else return 0;
  }
  int slam_tentative_landmarks() const override {
    if constexpr (kSlam) return estimator_.tentative_landmarks();
    else return 0;
  }
  est::Landmark slam_landmark(int k) const override {
    if constexpr (kSlam) {
      const Eigen::Vector2f m = estimator_.landmark(k);
      return {m.x(), m.y(), estimator_.landmark_signature(k)};
    } else {
      (void)k;
      return {};
    }
  }

 private:
  static est::ConstParticleSetView empty_set() {
    static float none[1] = {0.0f};
    est::ParticleSetView v{none, none, none, none, 0u, 0u};
    return est::ConstParticleSetView(v);
  }

  static Estimator construct(const EstimatorSpec& s, const EstimatorMaps& maps, const MapModels& m) {
    typename Configured::EstimatorConfig e;
    e.motion = motion_params<Model>(s.motion);
    e.control = control_config<Model>(s.motion);
    if constexpr (kMcl) {
      if (s.particles == 0 || s.particles > kMaxParticles)
        throw std::invalid_argument("particles must be in [1, " + std::to_string(kMaxParticles) + "]");
      e.mcl = s.mcl;
      e.beam_stride = s.beam_stride;
      e.cluster_cell = s.cluster_cell_m;
      if (s.mcl_landmarks) {
        e.landmarks = maps.landmarks;
        e.landmark_noise = s.landmark_noise;
        e.sensor_ids = s.landmark_ids;
      }
      return Estimator(e, s.seed, make_scan_model<ScanModel>(s, m), m.free_space);
    } else if constexpr (kSlam) {
      (void)maps;
      e.noise = s.landmark_noise;
      e.rot_sigma = s.ekf_rot_sigma;
      e.noise_step_s = s.slam_noise_step_s;
      e.max_range_m = s.slam_max_range_m;
      e.gate_accept = s.slam_gate_accept;
      e.gate_new = s.slam_gate_new;
      e.search_radius_m = s.slam_search_radius_m;
      e.confirm_sightings = s.slam_confirm;
      e.candidate_radius_m = s.slam_candidate_radius_m;
      e.candidate_scans = s.slam_candidate_frames;
      e.lost_sigma_m = s.lost_sigma_m;
      if (!(e.gate_accept > 0.0f) || e.gate_new < e.gate_accept || !(e.max_range_m > 0.0f))
        throw std::invalid_argument("EKF-SLAM: the gates must be positive, the new-landmark gate at least the other");
      return Estimator(e);
    } else {
      e.ekf.additive_process_noise(2, 2) = s.ekf_rot_sigma * s.ekf_rot_sigma;
      e.ekf.motion_noise = s.ekf_motion_noise;
      e.reopen_after = s.ekf_reopen_after;
      e.reopen_sigma_xy = s.ekf_reopen_sigma_xy;
      e.reopen_sigma_theta = s.ekf_reopen_sigma_theta;
      e.ekf.ambiguity_nats = s.ambiguity_nats;
      e.joint_association = s.joint_association;
      e.lone_pairing_sigma_m = s.lone_pairing_sigma_m;
      e.noise = s.landmark_noise;
      e.sigma_range_per_m = s.landmark_sigma_range_per_m;
      e.lost_sigma_m = s.lost_sigma_m;
      e.sensor_ids = s.landmark_ids;
      return Estimator(e, maps.landmarks);
    }
  }

  EstimatorSpec spec_;
  std::unique_ptr<MapModels> models_;
  Estimator estimator_;
  typename Configured::Loop loop_;
  hal::Pipeline<Estimator> pipeline_;
};

// The pipeline of one model, by filter and range model.
template <typename Model>
std::unique_ptr<EstimatorPipeline> make_for_model(const EstimatorSpec& s, const EstimatorMaps& maps, hal::Clock& a,
                                                  hal::Clock& b, hal::EstimateSink& sink) {
  using est::loop::Filter;
  if (s.filter == Filter::ekf)
    return std::make_unique<PipelineImpl<Model, Filter::ekf, est::loop::LikelihoodFieldScan>>(s, maps, a, b, sink);
  if (s.filter == Filter::ekf_slam)
    return std::make_unique<PipelineImpl<Model, Filter::ekf_slam, est::loop::LikelihoodFieldScan>>(s, maps, a, b, sink);
  switch (s.range_model) {
    case RangeModel::likelihood_field:
      return std::make_unique<PipelineImpl<Model, Filter::mcl, est::loop::LikelihoodFieldScan>>(s, maps, a, b, sink);
    case RangeModel::beam:
      if (s.beam_cast == BeamCast::cone)
        return std::make_unique<PipelineImpl<Model, Filter::mcl, HostBeamConeScan>>(s, maps, a, b, sink);
      return std::make_unique<PipelineImpl<Model, Filter::mcl, HostBeamScan>>(s, maps, a, b, sink);
    case RangeModel::steered:
      if constexpr (std::is_same_v<Model, est::BicycleMotionModel>)
        return std::make_unique<PipelineImpl<Model, Filter::mcl, HostSteeredScan>>(s, maps, a, b, sink);
      break;
  }
  throw std::invalid_argument(std::string("the steered range model is the bicycle's handlebar: --model bicycle, not ") +
                              to_string(s.model));
}

}  // namespace node::detail

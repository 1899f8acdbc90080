// estimator_node's pipeline (hal/tools/pipeline.hpp).
#include "pipeline.hpp"

#include <stdexcept>
#include <type_traits>

#include "est/filter/free_space_sampler.hpp"
#include "est/loop/configured_loop.hpp"
#include "est/map/distance_transform.hpp"
#include "est/map/occupancy_grid.hpp"
#include "est/sensor/likelihood_field_range_finder_model.hpp"
#include "hal/maps/landmark_file.hpp"
#include "hal/maps/office_map.hpp"
#include "hal/maps/ros_map_loader.hpp"

namespace hal::node {

namespace {

// The map and what the models precompute from it; owned here, read by the estimator for its whole life. MCL uses
// the occupancy grid, the EKF the landmarks.
struct MapModels {
  est::LandmarkMapStorage<kMaxLandmarks> landmarks;
  est::OccupancyGridStorage<kMapMaxSide, kMapMaxSide> grid;
  est::DistanceTransformStorage<kMapMaxSide, kMapMaxSide> edt;
  est::LikelihoodField field;
  est::FreeSpaceSampler free_space;
  std::string description;

  void build(const NodeConfig& c) {
    if (c.filter == est::loop::Filter::ekf) {
      if (c.landmarks == "office") {
        maps::make_office_landmarks(landmarks);
        description = "office landmarks (built-in, 16 posts)";
      } else {
        maps::load_landmark_csv(c.landmarks, landmarks);
        description = c.landmarks + " (" + std::to_string(landmarks.size()) + " landmarks)";
      }
      return;
    }
    if (c.map == "office") {
      maps::make_office_map(grid);
      description = "office (built-in, 20 m x 15 m at 0.05 m)";
    } else {
      const maps::RosMapInfo info = maps::load_ros_map(c.map, grid);
      description = c.map + " (" + std::to_string(grid.width()) + " x " + std::to_string(grid.height()) + " at " +
                    std::to_string(info.resolution) + " m)";
    }
    if (edt.build(grid.grid()) != est::MapStatus::ok) throw std::runtime_error("map: distance transform failed");
    if (field.configure(c.field, grid.grid(), edt.view()) != est::SensorModelStatus::ok)
      throw std::runtime_error("likelihood field: bad parameters (z_hit + z_max + z_rand must be 1, sigma_hit > 0)");
    free_space = est::FreeSpaceSampler(grid.grid(), edt.view(), c.clearance_m);
    if (!free_space.valid()) throw std::runtime_error("map: no usable free space");
  }
};

template <typename Model>
typename Model::Params motion_params(const NodeConfig& c);
template <>
est::DiffDriveMotionModel::Params motion_params<est::DiffDriveMotionModel>(const NodeConfig& c) {
  return c.diff_drive;
}
template <>
est::BicycleMotionModel::Params motion_params<est::BicycleMotionModel>(const NodeConfig& c) {
  return c.bicycle;
}

template <typename Model, est::loop::Filter F>
class ModelPipeline final : public Pipeline {
 public:
  // The firmware's static configuration of each pipeline the node can run: the node's capacities, the model and the
  // filter chosen on its command line (the rates and limits are run-time options on the host).
  using Configured = est::loop::ConfiguredLoop<
      est::loop::LoopConfig<Model, F, kMaxParticles, kMaxBeams, kQueueCapacity, kScanSlots>>;
  using Estimator = typename Configured::Estimator;
  using Port = LoopPort<Estimator, kQueueCapacity, kMaxBeams, kScanSlots>;
  static_assert(std::is_same_v<typename Port::Loop, typename Configured::Loop>, "one loop type");

  ModelPipeline(const NodeConfig& c, std::unique_ptr<MapModels> map, Clock& step_clock, EstimateSink& sink)
      : map_(std::move(map)), estimator_(construct(c, *map_)), loop_(estimator_, c.timing), port_(loop_, step_clock, sink) {
    if constexpr (F == est::loop::Filter::mcl) {
      if (c.global)
        estimator_.initialize_global(c.particles);
      else
        estimator_.initialize_at(c.initial_pose, c.initial_sigma_xy_m, c.initial_sigma_theta_rad, c.particles);
    } else {
      if (!estimator_.initialize_at(c.initial_pose, c.initial_sigma_xy_m, c.initial_sigma_theta_rad))
        throw std::runtime_error("EKF: the initial pose and sigmas must be finite and the sigmas positive");
    }
  }

  ValidatedSensorPort& port() override { return port_; }
  void flush() override { port_.flush(); }
  void set_transport_status(std::uint32_t bits) override { port_.set_transport_status(bits); }
  void set_upstream_rejects(std::uint32_t total) override { port_.set_upstream_rejects(total); }
  const est::loop::LoopCounters& loop_counters() const override { return port_.loop_counters(); }
  const LoopPortRejectCounters& port_rejects() const override { return port_.rejects(); }
  std::uint32_t published() const override { return port_.published(); }
  std::uint32_t nonfinite_estimates() const override { return port_.nonfinite_estimates(); }
  std::string map_description() const override { return map_->description; }
  std::string filter_description() const override {
    if constexpr (F == est::loop::Filter::mcl)
      return "augmented MCL, " + std::to_string(estimator_.filter().particles().count) + " particles";
    else
      return "EKF localization (" + std::to_string(estimator_.filter().counters().accepted) + " features fused, " +
             std::to_string(estimator_.filter().counters().rejected()) + " refused)";
  }

 private:
  static Estimator construct(const NodeConfig& c, const MapModels& m) {
    typename Configured::EstimatorConfig e;
    e.motion = motion_params<Model>(c);
    e.odometry = est::loop::OdometryControl<Model>::config(c.metres_per_tick);
    if constexpr (F == est::loop::Filter::mcl) {
      e.mcl.recovery = c.recovery;
      e.mcl.alpha_slow = c.alpha_slow;
      e.mcl.alpha_fast = c.alpha_fast;
      e.sensor_mount = c.sensor_mount;
      e.beam_stride = c.beam_stride;
      e.cluster_cell = c.cluster_cell_m;
      return Estimator(e, c.seed, m.field, m.free_space);
    } else {
      e.ekf.additive_process_noise(2, 2) = c.ekf_rot_sigma * c.ekf_rot_sigma;
      e.noise = c.landmark_noise;
      e.lost_sigma_m = c.lost_sigma_m;
      return Estimator(e, m.landmarks.view());
    }
  }

  std::unique_ptr<MapModels> map_;
  Estimator estimator_;
  typename Port::Loop loop_;
  Port port_;
};

}  // namespace

std::unique_ptr<Pipeline> make_pipeline(const NodeConfig& c, Clock& step_clock, EstimateSink& sink) {
  auto map = std::make_unique<MapModels>();
  map->build(c);
  using est::loop::Filter;
  if (c.filter == Filter::ekf) {
    if (c.model == RobotModel::bicycle)
      return std::make_unique<ModelPipeline<est::BicycleMotionModel, Filter::ekf>>(c, std::move(map), step_clock, sink);
    return std::make_unique<ModelPipeline<est::DiffDriveMotionModel, Filter::ekf>>(c, std::move(map), step_clock, sink);
  }
  if (c.model == RobotModel::bicycle)
    return std::make_unique<ModelPipeline<est::BicycleMotionModel, Filter::mcl>>(c, std::move(map), step_clock, sink);
  return std::make_unique<ModelPipeline<est::DiffDriveMotionModel, Filter::mcl>>(c, std::move(map), step_clock, sink);
}

}  // namespace hal::node

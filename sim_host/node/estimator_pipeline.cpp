// The estimator pipeline (node/estimator_pipeline.hpp): names, the map models, each model's parameters, and the
// dispatch to the per-model instantiations (node/pipeline_<model>.cpp).
#include "node/estimator_pipeline.hpp"

#include <stdexcept>
#include <string>

#include "node/estimator_pipeline_impl.hpp"

namespace node {

const char* to_string(RobotModel m) {
  switch (m) {
    case RobotModel::velocity: return "velocity";
    case RobotModel::odometry: return "odometry";
    case RobotModel::bicycle: return "bicycle";
    case RobotModel::diff_drive: return "diff-drive";
    case RobotModel::omni: return "omni";
    case RobotModel::holonomic: return "holonomic";
  }
  return "unknown";
}

bool parse(const std::string& s, RobotModel& out) {
  for (RobotModel m : kRobotModels)
    if (s == to_string(m)) {
      out = m;
      return true;
    }
  return false;
}

const char* to_string(RangeModel m) {
  switch (m) {
    case RangeModel::likelihood_field: return "likelihood-field";
    case RangeModel::beam: return "beam";
    case RangeModel::steered: return "steered";
  }
  return "unknown";
}

bool parse(const std::string& s, RangeModel& out) {
  for (RangeModel m : {RangeModel::likelihood_field, RangeModel::beam, RangeModel::steered})
    if (s == to_string(m)) {
      out = m;
      return true;
    }
  return false;
}

const char* to_string(est::loop::Filter f) {
  switch (f) {
    case est::loop::Filter::mcl: return "mcl";
    case est::loop::Filter::ekf: return "ekf";
    case est::loop::Filter::ekf_slam: return "ekf-slam";
  }
  return "unknown";
}

bool parse(const std::string& s, est::loop::Filter& out) {
  if (s == "mcl") out = est::loop::Filter::mcl;
  else if (s == "ekf") out = est::loop::Filter::ekf;
  else if (s == "ekf-slam") out = est::loop::Filter::ekf_slam;
  else return false;
  return true;
}

const char* to_string(BeamCast c) { return c == BeamCast::cone ? "cone" : "table"; }

bool parse(const std::string& s, BeamCast& out) {
  if (s == "table") out = BeamCast::table;
  else if (s == "cone") out = BeamCast::cone;
  else return false;
  return true;
}

namespace detail {

std::unique_ptr<MapModels> build_map_models(const EstimatorSpec& s, const EstimatorMaps& maps) {
  auto m = std::make_unique<MapModels>();
  if (s.filter != est::loop::Filter::mcl) return m;
  if (!maps.grid.valid() || !maps.edt.valid())
    throw std::invalid_argument("MCL needs an occupancy map (and its distance transform)");
  if (m->field.configure(s.field, maps.grid, maps.edt) != est::SensorModelStatus::ok)
    throw std::invalid_argument("likelihood field: bad parameters (z_hit + z_max + z_rand must be 1, sigma_hit > 0)");
  m->field_grid = std::make_unique<HeapFieldGrid>(maps.grid.width(), maps.grid.height());
  if (m->field_grid->build(m->field, maps.grid) != est::MapStatus::ok)
    throw std::invalid_argument("likelihood field: cannot tabulate it over the map");
  m->field_grid_view = m->field_grid->view();
  m->free_space = est::FreeSpaceSampler(maps.grid, maps.edt, s.clearance_m);
  if (!m->free_space.valid()) throw std::invalid_argument("map: no usable free space");
  if (s.range_model == RangeModel::beam) {
    if (m->beam.configure(s.beam) != est::SensorModelStatus::ok)
      throw std::invalid_argument("beam model: bad parameters (the four weights must sum to 1, sigma, lambda > 0)");
    // The cone caster takes one byte per cell and heading, the range table two: a size no host has is refused
    // before it is allocated, with the option that sets it.
    const double mib = static_cast<double>(maps.grid.cell_count()) * static_cast<double>(s.heading_bins) *
                       (s.beam_cast == BeamCast::cone ? 1.0 : 2.0) / 1048576.0;
    if (mib > 4096.0)
      throw std::invalid_argument(std::string("beam model: the ") +
                                  (s.beam_cast == BeamCast::cone ? "cone caster" : "heading range table") + " would take " +
                                  std::to_string(static_cast<long long>(mib)) + " MiB (" +
                                  std::to_string(maps.grid.width()) + " x " + std::to_string(maps.grid.height()) +
                                  " cells, " + std::to_string(s.heading_bins) +
                                  " headings), over 4096: lower --heading-bins or use a coarser map");
    if (s.beam_cast == BeamCast::cone) {
      m->cone = std::make_unique<HeapCone>(maps.grid, s.heading_bins);
      if (m->cone->build(maps.grid, s.heading_bins) != est::ConeRayCasterStatus::ok)
        throw std::invalid_argument("beam model: cannot build the cone caster (bins a power of two in [8, 1024])");
      m->cone_view = m->cone->view();
      return m;
    }
    const std::size_t entries = static_cast<std::size_t>(maps.grid.width()) *
                                static_cast<std::size_t>(maps.grid.height()) * static_cast<std::size_t>(s.heading_bins);
    m->table = std::make_unique<HeapHeadingTable>(entries);
    const est::DistanceTransformRayCaster exact(maps.grid, maps.edt);
    if (m->table->build(maps.grid, exact, s.heading_bins, s.beam.range_max) != est::HeadingRangeTableStatus::ok)
      throw std::invalid_argument("beam model: cannot build the heading range table (bins a power of two in [4, 4096])");
    m->table_view = m->table->view();
  }
  return m;
}

// The configuration, not the count of the moment (which KLD moves): "augmented MCL (20000 particles, KLD from 500)".
std::string describe(const EstimatorSpec& s) {
  std::string d = std::string(to_string(s.model)) + " model, ";
  if (s.filter == est::loop::Filter::ekf) return d + "EKF localization on landmark features";
  if (s.filter == est::loop::Filter::ekf_slam)
    return d + "EKF-SLAM on landmark features (gated maximum likelihood, up to " + std::to_string(kSlamLandmarks) +
           " landmarks)";
  const std::string kld = s.mcl.kld ? ", KLD from " + std::to_string(s.mcl.kld_config.n_min) : "";
  return d + "augmented MCL (" + std::to_string(s.particles) + " particles" + kld + "), " +
         to_string(s.range_model) + " range model";
}

// Per-model instantiations (node/pipeline_<model>.cpp).
extern template std::unique_ptr<EstimatorPipeline> make_for_model<est::VelocityMotionModel>(
    const EstimatorSpec&, const EstimatorMaps&, hal::Clock&, hal::Clock&, hal::EstimateSink&);
extern template std::unique_ptr<EstimatorPipeline> make_for_model<est::OdometryMotionModel>(
    const EstimatorSpec&, const EstimatorMaps&, hal::Clock&, hal::Clock&, hal::EstimateSink&);
extern template std::unique_ptr<EstimatorPipeline> make_for_model<est::BicycleMotionModel>(
    const EstimatorSpec&, const EstimatorMaps&, hal::Clock&, hal::Clock&, hal::EstimateSink&);
extern template std::unique_ptr<EstimatorPipeline> make_for_model<est::DiffDriveMotionModel>(
    const EstimatorSpec&, const EstimatorMaps&, hal::Clock&, hal::Clock&, hal::EstimateSink&);
extern template std::unique_ptr<EstimatorPipeline> make_for_model<est::OmniMotionModel>(
    const EstimatorSpec&, const EstimatorMaps&, hal::Clock&, hal::Clock&, hal::EstimateSink&);
extern template std::unique_ptr<EstimatorPipeline> make_for_model<est::HolonomicPoseMotionModel>(
    const EstimatorSpec&, const EstimatorMaps&, hal::Clock&, hal::Clock&, hal::EstimateSink&);

}  // namespace detail

std::unique_ptr<EstimatorPipeline> make_estimator_pipeline(const EstimatorSpec& s, const EstimatorMaps& maps,
                                                           hal::Clock& sample_clock, hal::Clock& step_clock,
                                                           hal::EstimateSink& sink) {
  using namespace detail;
  switch (s.model) {
    case RobotModel::velocity: return make_for_model<est::VelocityMotionModel>(s, maps, sample_clock, step_clock, sink);
    case RobotModel::odometry: return make_for_model<est::OdometryMotionModel>(s, maps, sample_clock, step_clock, sink);
    case RobotModel::bicycle: return make_for_model<est::BicycleMotionModel>(s, maps, sample_clock, step_clock, sink);
    case RobotModel::diff_drive:
      return make_for_model<est::DiffDriveMotionModel>(s, maps, sample_clock, step_clock, sink);
    case RobotModel::omni: return make_for_model<est::OmniMotionModel>(s, maps, sample_clock, step_clock, sink);
    case RobotModel::holonomic:
      return make_for_model<est::HolonomicPoseMotionModel>(s, maps, sample_clock, step_clock, sink);
  }
  throw std::invalid_argument("unknown robot model");
}

}  // namespace node

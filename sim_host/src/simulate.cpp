// The host simulation run: stream -> hal::ValidatedInputs -> hal::LoopPort -> est::loop::FilterLoop(MclEstimator or
// EkfEstimator, chosen through est::loop::ConfiguredLoop).
#include "sim/simulate.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <type_traits>

#include "est/filter/free_space_sampler.hpp"
#include "est/loop/configured_loop.hpp"
#include "est/motion/bicycle_model.hpp"
#include "est/motion/diff_drive_model.hpp"
#include "est/sensor/likelihood_field_range_finder_model.hpp"
#include "hal/estimate.hpp"
#include "hal/status_word.hpp"
#include "hal/validated_inputs.hpp"

namespace sim {
namespace {

constexpr double kPi = 3.14159265358979323846;
// Capacities, as estimator_node's (hal/tools/node_config.hpp) but room for 1440 beams.
constexpr std::uint32_t kMaxParticles = 20000;
constexpr std::int32_t kMaxBeams = 1440;
constexpr std::uint32_t kQueueCapacity = 256;
constexpr std::uint32_t kScanSlots = 4;
constexpr std::uint32_t kSnapshotPoints = 4000;

float wrap(float a) { return std::remainder(a, 6.28318530717958647692f); }

// Seconds of a span of the run, to the millisecond (every time in the run is on the 10 ms grid or 1 ms latencies).
double span_s(hal::TimeNs ns) { return static_cast<double>(ns / hal::kNsPerMs) / 1000.0; }

// The HAL's clock in the simulation: the arrival time of the sample being delivered.
struct ArrivalClock final : hal::Clock {
  hal::TimeNs now = 0;
  hal::TimeNs now_ns() override { return now; }
};

// Times the loop's steps (overruns, worst step); never affects an estimate.
struct WallClock final : hal::Clock {
  hal::TimeNs now_ns() override {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
  }
};

template <typename Model>
typename Model::Params filter_params(const RobotModels& m);
template <>
est::BicycleParams filter_params<est::BicycleMotionModel>(const RobotModels& m) { return m.bicycle_filter; }
template <>
est::DiffDriveParams filter_params<est::DiffDriveMotionModel>(const RobotModels& m) { return m.diff_filter; }

// Every n-th particle, at most kSnapshotPoints.
template <typename Estimator>
ParticleSnapshot snapshot(const Estimator& estimator, hal::TimeNs t, const std::string& label, const est::Pose2& truth,
                          const est::Pose2& estimate) {
  const est::ConstParticleSetView p = estimator.filter().particles();
  ParticleSnapshot snap;
  snap.t_ns = t;
  snap.label = label;
  snap.total = p.count;
  snap.truth = truth;
  snap.estimate = estimate;
  const std::uint32_t step = std::max<std::uint32_t>(1u, (p.count + kSnapshotPoints - 1u) / kSnapshotPoints);
  for (std::uint32_t i = 0; i < p.count; i += step) snap.particles.push_back({p.x[i], p.y[i], p.theta[i]});
  return snap;
}

// The map models MCL needs (the EKF needs only the world's landmarks).
struct MclMapModels {
  est::LikelihoodField field;
  est::FreeSpaceSampler free_space;
};

template <typename Model, est::loop::Filter F>
void run_model(const ScenarioConfig& sc, const FilterOptions& fo, const SimWorld& world, SimResult& r) {
  // The firmware's static configuration of a run: the model and the filter, estimator_node's capacities with room
  // for 1440 beams, the loop's default rates and limits.
  using Configured =
      est::loop::ConfiguredLoop<est::loop::LoopConfig<Model, F, kMaxParticles, kMaxBeams, kQueueCapacity, kScanSlots>>;
  using Estimator = typename Configured::Estimator;
  using Loop = typename Configured::Loop;
  using Port = hal::LoopPort<Estimator, kQueueCapacity, kMaxBeams, kScanSlots>;
  static_assert(std::is_same_v<typename Port::Loop, Loop>, "one loop type");
  constexpr bool kMcl = F == est::loop::Filter::mcl;
  const SensorStream& s = r.stream;

  typename Configured::EstimatorConfig ec;
  ec.motion = filter_params<Model>(robot_models());
  ec.odometry = est::loop::OdometryControl<Model>::config(static_cast<float>(s.metres_per_tick));
  std::unique_ptr<MclMapModels> maps;
  std::unique_ptr<Estimator> estimator;
  if constexpr (kMcl) {
    // The models of the map, as the node builds them.
    maps = std::make_unique<MclMapModels>();
    est::LikelihoodFieldParams lp;
    lp.z_hit = 0.85f;
    lp.z_max = 0.05f;
    lp.z_rand = 0.10f;
    lp.sigma_hit = 0.2f;
    lp.range_max = static_cast<float>(sc.range_max_m);
    lp.max_distance = 2.0f;
    if (maps->field.configure(lp, world.grid, world.edt) != est::SensorModelStatus::ok)
      throw std::runtime_error("the likelihood field could not be configured for this map");
    maps->free_space = est::FreeSpaceSampler(world.grid, world.edt, fo.clearance_m);
    if (!maps->free_space.valid()) throw std::runtime_error("the map has no valid free space");

    ec.mcl.kld = fo.kld;
    ec.mcl.kld_config.n_min = fo.kld_min;
    ec.mcl.alpha_slow = fo.alpha_slow;
    ec.mcl.alpha_fast = fo.alpha_fast;
    ec.mcl.max_injection_fraction = fo.max_injection;
    ec.sensor_mount = s.mount;
    ec.beam_stride = fo.beam_stride;
    ec.cluster_cell = 1.0f;

    if (fo.particles == 0 || fo.particles > kMaxParticles)
      throw std::invalid_argument("--particles must be in [1, " + std::to_string(kMaxParticles) + "]");
    estimator = std::make_unique<Estimator>(ec, sc.seed, maps->field, maps->free_space);
    if (fo.start == StartKind::global)
      estimator->initialize_global(fo.particles);
    else
      estimator->initialize_at(s.truth.front().pose, 0.2f, 0.1f, fo.particles);
  } else {
    // The filter is told the sensor's own noise; the heading noise added per prediction covers what the odometry
    // model leaves out (the encoders' scale error and slip turn the robot where the model says it drove straight).
    ec.noise = sc.landmark_sensor.noise;
    ec.ekf.additive_process_noise(2, 2) = fo.ekf_rot_sigma_rad * fo.ekf_rot_sigma_rad;
    ec.lost_sigma_m = fo.ekf_lost_sigma_m;
    estimator = std::make_unique<Estimator>(ec, world.landmarks);
    if (!estimator->initialize_at(s.truth.front().pose, fo.ekf_start_sigma_xy_m, fo.ekf_start_sigma_theta_rad))
      throw std::invalid_argument("the EKF's start sigmas must be finite and positive");
  }

  auto loop = std::make_unique<Loop>(*estimator, Configured::kTiming);
  WallClock wall;
  ArrivalClock arrival;

  // Snapshots of the particle cloud at fixed times of the run (MCL).
  std::vector<std::pair<hal::TimeNs, std::string>> snap_at;
  const hal::TimeNs t0 = s.truth.front().t_ns, dt = kSimStepNs;
  if constexpr (kMcl) {
    snap_at.push_back({t0, "first scan"});
    snap_at.push_back({t0 + hal::kNsPerS, "1 s"});
    snap_at.push_back({t0 + 3 * hal::kNsPerS, "3 s"});
    if (s.kidnap_ns >= 0) {
      snap_at.push_back({s.kidnap_ns + 3 * dt, "kidnapped + 0.03 s"});
      snap_at.push_back({s.kidnap_ns + hal::kNsPerS, "kidnapped + 1 s"});
    } else {
      snap_at.push_back({t0 + 10 * hal::kNsPerS, "10 s"});
      snap_at.push_back({(t0 + s.end_ns) / 2, "half-way"});
    }
    snap_at.push_back({s.end_ns - 2 * dt, "end"});
    std::sort(snap_at.begin(), snap_at.end());
  }
  std::size_t next_snap = 0;

  struct Sink final : hal::EstimateSink {
    SimResult* r;
    const Estimator* est;
    std::vector<std::pair<hal::TimeNs, std::string>>* snap_at;
    std::size_t* next_snap;
    void publish(const hal::Estimate& e) override {
      OutputRow row;
      row.t_ns = e.stamp_ns;
      row.truth = r->stream.truth_at(e.stamp_ns).pose;
      row.estimate = e.pose;
      row.position_error_m = std::hypot(e.pose.x - row.truth.x, e.pose.y - row.truth.y);
      row.heading_error_rad = std::fabs(wrap(e.pose.theta - row.truth.theta));
      row.sigma_x_m = std::sqrt(std::max(0.0f, e.covariance(0, 0)));
      row.sigma_y_m = std::sqrt(std::max(0.0f, e.covariance(1, 1)));
      row.sigma_theta_rad = std::sqrt(std::max(0.0f, e.covariance(2, 2)));
      row.cov_xy_m2 = e.covariance(0, 1);
      if constexpr (kMcl) row.particles = est->filter().particles().count;
      row.status = e.status & ~hal::status::kDeadlineOverrun;
      row.rejected_inputs = e.rejected_inputs;
      r->rows.push_back(row);
      if constexpr (kMcl) {
        while (*next_snap < snap_at->size() && e.stamp_ns >= (*snap_at)[*next_snap].first) {
          r->snapshots.push_back(snapshot(*est, e.stamp_ns, (*snap_at)[*next_snap].second, row.truth, row.estimate));
          ++*next_snap;
        }
      }
    }
  } sink;
  sink.r = &r;
  sink.est = estimator.get();
  sink.snap_at = &snap_at;
  sink.next_snap = &next_snap;

  if constexpr (kMcl)  // the initial belief, before any input
    r.snapshots.push_back(snapshot(*estimator, t0, "initial belief", s.truth.front().pose, estimator->estimate().mean));
  Port port(*loop, wall, sink);
  hal::ValidatedInputs inputs(s.limits, arrival, port);
  r.rows.reserve(static_cast<std::size_t>((s.end_ns - t0) / dt) + s.scans.size() + s.sightings.size() + 16);
  for (const StreamEvent& e : s.events) {
    arrival.now = e.arrival_ns;
    switch (e.kind) {
      case StreamKind::wheel_ticks: inputs.on_wheel_ticks(e.ticks); break;
      case StreamKind::steering: inputs.on_steering(e.steering); break;
      case StreamKind::scan: inputs.on_range_scan(s.scans[e.scan].view()); break;
      case StreamKind::landmarks: inputs.on_landmarks(s.sightings[e.sighting].view()); break;
    }
    port.set_upstream_rejects(inputs.faults().total());
  }
  port.flush();

  r.wheel_faults = inputs.wheels().faults();
  r.steering_faults = inputs.steering().faults();
  r.scan_faults = inputs.scan().faults();
  r.landmark_faults = inputs.landmarks().faults();
  r.landmark_features_accepted = inputs.landmarks().features_accepted();
  r.beams = inputs.scan().beams();
  r.loop = loop->counters();
  r.port_rejects = port.rejects();
  if constexpr (kMcl) {
    r.mcl = estimator->filter().counters();
  } else {
    r.ekf = estimator->filter().counters();
    r.ekf_predictions = estimator->filter().prediction_counters();
  }
  r.nonfinite_estimates = port.nonfinite_estimates();
}

// The first row in [from, to) from which the error stays within the bounds for `hold` (or to `to`); rows.size() if
// none. By index: two outputs share a time when a scan is applied right after a prediction.
std::size_t localized_at(const std::vector<OutputRow>& rows, hal::TimeNs from, hal::TimeNs to, const FilterOptions& fo) {
  const float pos = static_cast<float>(fo.converge_pos_m);
  const float head = static_cast<float>(fo.converge_heading_deg * kPi / 180.0);
  const hal::TimeNs hold = static_cast<hal::TimeNs>(fo.hold_s * 1e9);
  std::size_t candidate = rows.size();
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const OutputRow& row = rows[i];
    if (row.t_ns < from || row.t_ns >= to) continue;
    const bool ok = row.position_error_m < pos && row.heading_error_rad < head;
    if (!ok) {
      candidate = rows.size();
      continue;
    }
    if (candidate == rows.size()) candidate = i;
    if (row.t_ns - rows[candidate].t_ns >= hold) return candidate;
  }
  return candidate;  // within the bounds up to the end of the phase (shorter than hold): accepted
}

SimMetrics compute_metrics(const SimResult& r, const FilterOptions& fo) {
  SimMetrics m;
  const SensorStream& s = r.stream;
  const hal::TimeNs t0 = s.truth.front().t_ns;
  std::vector<std::pair<hal::TimeNs, std::string>> starts = {
      {t0, fo.start == StartKind::global ? "global localization" : "tracking"}};
  if (s.kidnap_ns >= 0) starts.push_back({s.kidnap_ns, "kidnap recovery"});
  double sp = 0.0, sh = 0.0, sp_all = 0.0;
  std::size_t n = 0, n_all = 0;
  const float pos = static_cast<float>(fo.converge_pos_m);
  const float head = static_cast<float>(fo.converge_heading_deg * kPi / 180.0);
  hal::TimeNs outside = 0;
  m.max_position_error_m = 0.0;
  m.max_heading_error_deg = 0.0;
  for (std::size_t i = 0; i < starts.size(); ++i) {
    const hal::TimeNs from = starts[i].first;
    const hal::TimeNs to = i + 1 < starts.size() ? starts[i + 1].first : s.end_ns + 1;
    PhaseMetrics ph;
    ph.name = starts[i].second;
    ph.start_s = span_s(from - t0);
    ph.end_s = span_s(std::min(to, s.end_ns) - t0);
    const std::size_t first = localized_at(r.rows, from, to, fo);
    ph.localized = first < r.rows.size();
    if (ph.localized) {
      const hal::TimeNs at = r.rows[first].t_ns;
      ph.time_to_localize_s = span_s(at - from);
      m.localized_time_s += span_s(std::min(to, s.end_ns) - at);
      hal::TimeNs prev = -1;
      for (std::size_t k = first; k < r.rows.size(); ++k) {
        const OutputRow& row = r.rows[k];
        if (row.t_ns >= to) break;
        const double ep = row.position_error_m, eh = row.heading_error_rad;
        sp += ep * ep;
        sh += eh * eh;
        ++n;
        m.max_position_error_m = std::max(m.max_position_error_m, ep);
        m.max_heading_error_deg = std::max(m.max_heading_error_deg, eh * 180.0 / kPi);
        if (prev >= 0 && (row.position_error_m >= pos || row.heading_error_rad >= head)) outside += row.t_ns - prev;
        prev = row.t_ns;
      }
    }
    m.phases.push_back(ph);
  }
  for (const OutputRow& row : r.rows) {
    sp_all += static_cast<double>(row.position_error_m) * static_cast<double>(row.position_error_m);
    ++n_all;
  }
  if (n > 0) {
    m.rmse_position_m = std::sqrt(sp / static_cast<double>(n));
    m.rmse_heading_deg = std::sqrt(sh / static_cast<double>(n)) * 180.0 / kPi;
  } else {
    m.max_position_error_m = -1.0;
    m.max_heading_error_deg = -1.0;
  }
  if (n_all > 0) m.rmse_position_all_m = std::sqrt(sp_all / static_cast<double>(n_all));
  m.outside_bounds_s = span_s(outside);
  return m;
}

}  // namespace

std::map<std::string, int> SimResult::observed_counts() const {
  std::map<std::string, int> out;
  const auto add = [&](const std::string& key, std::uint64_t v) {
    if (v > 0) out[key] += static_cast<int>(v);
  };
  const std::pair<const char*, const hal::FaultCounters*> kinds[] = {{"wheel_ticks", &wheel_faults},
                                                                      {"steering", &steering_faults},
                                                                      {"scan", &scan_faults},
                                                                      {"landmarks", &landmark_faults}};
  for (const auto& [name, c] : kinds)
    for (std::size_t i = 1; i < hal::kFaultCount; ++i)
      add(std::string("hal.") + name + "." + hal::to_string(static_cast<hal::Fault>(i)), c->count[i]);
  add("hal.scan.beams_nan", beams.not_a_number);
  add("hal.scan.beams_below_min", beams.below_min);
  add("loop.too_old", loop.too_old);
  add("loop.queue_full", loop.queue_full);
  // The EKF's refusals of features (the innovation gate, no landmark in reach) are the filter's decisions on inputs the
  // HAL passed, not faults of the stream: they are reported with the EKF's counters, not compared with injections.
  add("loop.rejected", filter == est::loop::Filter::ekf && loop.rejected >= ekf.rejected() ? loop.rejected - ekf.rejected()
                                                                                         : loop.rejected);
  for (std::size_t i = 1; i < static_cast<std::size_t>(hal::LoopPortReject::kCount); ++i)
    add(std::string("port.") + hal::to_string(static_cast<hal::LoopPortReject>(i)), port_rejects.count[i]);
  return out;
}

const char* to_string(est::loop::Filter f) { return f == est::loop::Filter::ekf ? "ekf" : "mcl"; }

SimResult run_simulation(const ScenarioConfig& scenario, const FilterOptions& filter, const SimWorld& world) {
  const auto started = std::chrono::steady_clock::now();
  SimResult r;
  r.filter = filter.filter;
  const bool ekf = filter.filter == est::loop::Filter::ekf;
  if (ekf && world.landmarks.size() == 0)
    throw std::invalid_argument("--filter ekf needs landmarks, and " + world.name +
                                " has none (a ROS map carries no landmarks): use the synthetic office (no --map)");
  if (ekf && filter.start == StartKind::global)
    throw std::invalid_argument("--filter ekf tracks from the true start pose (a Gaussian of sigma 0.2 m, 0.1 rad): "
                                "--start global needs --filter mcl");
  r.stream = generate_stream(scenario, world);
  if (r.stream.truth.empty()) throw std::invalid_argument("the run has no steps");
  expect_loop_inputs(r.stream, !ekf, ekf);
  using est::loop::Filter;
  if (scenario.robot == RobotKind::bicycle) {
    if (ekf)
      run_model<est::BicycleMotionModel, Filter::ekf>(scenario, filter, world, r);
    else
      run_model<est::BicycleMotionModel, Filter::mcl>(scenario, filter, world, r);
  } else {
    if (ekf)
      run_model<est::DiffDriveMotionModel, Filter::ekf>(scenario, filter, world, r);
    else
      run_model<est::DiffDriveMotionModel, Filter::mcl>(scenario, filter, world, r);
  }
  r.metrics = compute_metrics(r, filter);
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return r;
}

}  // namespace sim

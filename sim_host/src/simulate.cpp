// The host simulation run: stream -> the estimator pipeline (node/estimator_pipeline.hpp: hal::ValidatedInputs ->
// hal::LoopPort -> est::loop::FilterLoop with the run's model, filter and range model) -> the metrics.
#include "sim/simulate.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <stdexcept>

#include "hal/estimate.hpp"
#include "hal/status_word.hpp"
#include "node/estimator_pipeline.hpp"
#include "node/pacer.hpp"
#include "node/view_feed.hpp"
#include "sim/angles.hpp"

namespace sim {
namespace {

constexpr std::uint32_t kSnapshotPoints = 4000;

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

// Every n-th particle, at most kSnapshotPoints.
ParticleSnapshot snapshot(const node::EstimatorPipeline& p, hal::TimeNs t, const std::string& label,
                          const est::Pose2& truth, const est::Pose2& estimate) {
  const est::ConstParticleSetView v = p.particles();
  ParticleSnapshot snap;
  snap.t_ns = t;
  snap.label = label;
  snap.total = v.count;
  snap.truth = truth;
  snap.estimate = estimate;
  const std::uint32_t step = std::max<std::uint32_t>(1u, (v.count + kSnapshotPoints - 1u) / kSnapshotPoints);
  for (std::uint32_t i = 0; i < v.count; i += step) snap.particles.push_back({v.x[i], v.y[i], v.theta[i]});
  return snap;
}

void run_stream(const ScenarioConfig& sc, const FilterOptions& fo, const SimWorld& world, SimResult& r,
                Progress* progress, const RunView* watch) {
  const SensorStream& s = r.stream;
  const bool mcl = fo.filter == est::loop::Filter::mcl;
  const node::EstimatorSpec spec = estimator_spec(sc, fo, s);
  node::EstimatorMaps maps;
  maps.grid = world.grid;
  maps.edt = world.edt;
  maps.landmarks = world.landmarks;
  maps.description = world.name;

  // Snapshots of the particle cloud at fixed times of the run (MCL).
  std::vector<std::pair<hal::TimeNs, std::string>> snap_at;
  const hal::TimeNs t0 = s.truth.front().t_ns, dt = kSimStepNs;
  if (mcl) {
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
    SimResult* r = nullptr;
    const node::EstimatorPipeline* pipeline = nullptr;
    bool mcl = false;
    std::vector<std::pair<hal::TimeNs, std::string>>* snap_at = nullptr;
    std::size_t* next_snap = nullptr;
    view::LiveView* view = nullptr;
    void publish(const hal::Estimate& e) override {
      OutputRow row = output_row(r->stream, e);
      if (mcl) {
        row.particles = pipeline->particles().count;
        if (const est::MclCounters* c = pipeline->mcl_counters()) {
          row.drawn_particles = c->drawn_particles;
          row.injected_particles = c->injected_particles;
        }
      }
      r->rows.push_back(row);
      r->estimates.push_back(e);
      if (view != nullptr) {
        view->publish_estimate(node::view_sample(e));
        view->publish_truth(e.stamp_ns, {row.truth.x, row.truth.y, row.truth.theta});
        if (mcl) node::feed_particles(*view, *pipeline, e.stamp_ns);
      }
      if (mcl) {
        // The times this output reaches: one panel, their labels joined (a 20 s run's 10 s is its half-way).
        std::string label;
        while (*next_snap < snap_at->size() && e.stamp_ns >= (*snap_at)[*next_snap].first) {
          label += (label.empty() ? "" : ", ") + (*snap_at)[*next_snap].second;
          ++*next_snap;
        }
        if (!label.empty()) r->snapshots.push_back(snapshot(*pipeline, e.stamp_ns, label, row.truth, row.estimate));
      }
    }
  } sink;
  sink.r = &r;
  sink.mcl = mcl;
  sink.snap_at = &snap_at;
  sink.next_snap = &next_snap;
  view::LiveView* const view = watch != nullptr ? watch->view : nullptr;
  sink.view = view;
  node::Pacer pacer(view != nullptr ? watch->speed : 0.0);  // paced for a viewer by the arrival times

  WallClock wall;
  ArrivalClock arrival;
  const std::unique_ptr<node::EstimatorPipeline> pipeline = node::make_estimator_pipeline(spec, maps, arrival, wall, sink);
  sink.pipeline = pipeline.get();
  if (mcl)  // the initial belief, before any input
    r.snapshots.push_back(snapshot(*pipeline, t0, "initial belief", s.truth.front().pose, pipeline->estimate().mean));
  r.rows.reserve(static_cast<std::size_t>((s.end_ns - t0) / dt) + s.scans.size() + s.sightings.size() + 16);
  hal::SensorPort& in = pipeline->input();
  for (const StreamEvent& e : s.events) {
    arrival.now = e.arrival_ns;
    switch (e.kind) {
      case StreamKind::wheel_ticks: in.on(e.ticks); break;
      case StreamKind::steering: in.on(e.steering); break;
      case StreamKind::twist: in.on(e.twist); break;
      case StreamKind::odometry: in.on(e.odometry); break;
      case StreamKind::scan: in.on(s.scans[e.scan].view()); break;
      case StreamKind::landmarks: in.on(s.sightings[e.sighting].view()); break;
    }
    pipeline->refresh(0, 0);
    if (progress != nullptr) progress->update(static_cast<double>(e.arrival_ns - t0) * 1e-9);
    pacer.at(e.arrival_ns);
  }
  pipeline->flush();

  pipeline->gate().for_each_sensor([&](const char* name, const hal::FaultCounters& f) { r.sensor_faults[name] = f; });
  r.landmark_features_accepted = pipeline->gate().landmarks().features_accepted();
  r.beams = pipeline->gate().scan().beams();
  r.loop = pipeline->loop_counters();
  r.port_rejects = pipeline->port_rejects();
  if (const est::MclCounters* m = pipeline->mcl_counters()) r.mcl = *m;
  if (const est::CorrectionCounters* c = pipeline->ekf_counters()) r.ekf = *c;
  if (const est::PredictionCounters* p = pipeline->ekf_prediction_counters()) r.ekf_predictions = *p;
  r.nonfinite_estimates = pipeline->nonfinite_estimates();
  r.description = pipeline->description();
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

}  // namespace

OutputRow output_row(const SensorStream& s, const hal::Estimate& e) {
  OutputRow row;
  row.t_ns = e.stamp_ns;
  row.truth = s.truth_at(e.stamp_ns).pose;
  row.estimate = e.pose;
  row.position_error_m = std::hypot(e.pose.x - row.truth.x, e.pose.y - row.truth.y);
  row.heading_error_rad = std::fabs(wrap_angle(e.pose.theta - row.truth.theta));
  row.sigma_x_m = std::sqrt(std::max(0.0f, e.covariance(0, 0)));
  row.sigma_y_m = std::sqrt(std::max(0.0f, e.covariance(1, 1)));
  row.sigma_theta_rad = std::sqrt(std::max(0.0f, e.covariance(2, 2)));
  row.cov_xy_m2 = e.covariance(0, 1);
  row.status = e.status & ~hal::status::kDeadlineOverrun;
  row.rejected_inputs = e.rejected_inputs;
  return row;
}

SimMetrics compute_metrics(const SensorStream& s, const std::vector<OutputRow>& rows, const FilterOptions& fo) {
  SimMetrics m;
  const hal::TimeNs t0 = s.truth.front().t_ns;
  std::vector<std::pair<hal::TimeNs, std::string>> starts = {
      {t0, fo.start == StartKind::global ? "global localization"
           : fo.start == StartKind::wrong ? "wrong start"
                                          : "tracking"}};
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
    const bool kidnap = s.kidnap_ns >= 0 && from == s.kidnap_ns;
    PhaseMetrics ph;
    ph.name = starts[i].second;
    ph.start_s = span_s(from - t0);
    ph.end_s = span_s(std::min(to, s.end_ns) - t0);
    // A global or wrong start is lost from the start, a tracking start never; a kidnapping from the first output off
    // by more than the bounds (the recovery is timed from there).
    hal::TimeNs lost = !kidnap && fo.start != StartKind::tracking ? from : -1;
    if (kidnap) {
      for (const OutputRow& row : rows) {
        if (row.t_ns < from || row.t_ns >= to) continue;
        if (row.position_error_m >= pos || row.heading_error_rad >= head) {
          lost = row.t_ns;
          break;
        }
      }
    }
    ph.lost_at_s = lost >= 0 ? span_s(lost - t0) : -1.0;
    const hal::TimeNs search = kidnap ? lost : from;  // a kidnapping never lost is never recovered
    const std::size_t first = search >= 0 ? localized_at(rows, search, to, fo) : rows.size();
    ph.localized = first < rows.size();
    if (ph.localized) {
      const hal::TimeNs at = rows[first].t_ns;
      ph.localized_at_s = span_s(at - t0);
      ph.time_to_localize_s = span_s(at - search);
      m.localized_time_s += span_s(std::min(to, s.end_ns) - at);
      hal::TimeNs prev = -1;
      // The filter's counters before the localized part: those of the output before it.
      const std::uint32_t drawn0 = first > 0 ? rows[first - 1].drawn_particles : 0u;
      const std::uint32_t injected0 = first > 0 ? rows[first - 1].injected_particles : 0u;
      std::uint32_t drawn1 = drawn0, injected1 = injected0;
      double particles_sum = 0.0;
      std::size_t rows_in = 0;
      for (std::size_t k = first; k < rows.size(); ++k) {
        const OutputRow& row = rows[k];
        if (row.t_ns >= to) break;
        const double ep = row.position_error_m, eh = row.heading_error_rad;
        sp += ep * ep;
        sh += eh * eh;
        ++n;
        m.max_position_error_m = std::max(m.max_position_error_m, ep);
        m.max_heading_error_deg = std::max(m.max_heading_error_deg, eh * 180.0 / kPi);
        if (prev >= 0 && (row.position_error_m >= pos || row.heading_error_rad >= head)) outside += row.t_ns - prev;
        prev = row.t_ns;
        drawn1 = row.drawn_particles;
        injected1 = row.injected_particles;
        particles_sum += row.particles;
        ph.particles_max = std::max(ph.particles_max, row.particles);
        ++rows_in;
      }
      if (fo.filter == est::loop::Filter::mcl && rows_in > 0) {
        ph.drawn_particles = drawn1 - drawn0;  // unsigned: right across a wrap of the counters
        ph.injected_particles = injected1 - injected0;
        ph.injected_share = ph.drawn_particles > 0 ? static_cast<double>(ph.injected_particles) /
                                                         static_cast<double>(ph.drawn_particles)
                                                   : 0.0;
        ph.particles_mean = particles_sum / static_cast<double>(rows_in);
      }
    }
    m.phases.push_back(ph);
  }
  for (const OutputRow& row : rows) {
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

est::Pose2 wrong_start_pose(const SensorStream& s) {
  // The route's pose half the run later, or the first after it at least 3 m from the start (the farthest if none):
  // a pose in free space, heading along the route, where the robot is not.
  const est::Pose2 start = s.truth.front().pose;
  const auto dist = [&](std::size_t i) { return std::hypot(s.truth[i].pose.x - start.x, s.truth[i].pose.y - start.y); };
  for (std::size_t i = s.truth.size() / 2; i < s.truth.size(); ++i)
    if (dist(i) >= 3.0f) return s.truth[i].pose;
  std::size_t far = 0;
  for (std::size_t i = 1; i < s.truth.size(); ++i)
    if (dist(i) > dist(far)) far = i;
  return s.truth[far].pose;
}

// The estimator of a run, as estimator_node would be configured for this robot (sim_host record writes the same
// options for a replay).
node::EstimatorSpec estimator_spec(const ScenarioConfig& sc, const FilterOptions& fo, const SensorStream& s) {
  node::EstimatorSpec e;
  e.model = sc.robot;
  e.filter = fo.filter;
  e.range_model = fo.range_model;
  e.beam_cast = fo.beam_cast;
  e.motion = robot_models().filter;
  if (!fo.omni_noise.empty()) {
    if (fo.omni_noise.size() != 9) throw std::invalid_argument("the omni model's noise is a1..a9: nine numbers");
    std::copy(fo.omni_noise.begin(), fo.omni_noise.end(), e.motion.omni.alpha);
  }
  e.motion.bicycle_control.metres_per_tick = static_cast<float>(s.metres_per_tick);
  e.motion.bicycle_control.steering_fitted = sc.steering_sensor;
  e.motion.bicycle_control.unknown_steer_sigma = fo.unknown_steer_sigma_rad;
  e.sensor_mount = s.mount;
  e.steered.mount = sc.handlebar_mount;
  e.steered.steer_max = e.motion.bicycle.steer_max;
  e.steered.positions = fo.handle_positions;
  e.steered.reading_sigma = fo.handle_reading_sigma_rad;
  e.steered.floor = fo.handle_reading_floor;
  e.field = {0.85f, 0.05f, 0.10f, 0.2f, static_cast<float>(sc.range_max_m), 2.0f};
  e.beam.range_max = static_cast<float>(sc.range_max_m);
  e.beam_stride = fo.beam_stride;
  e.mcl.kld = fo.kld;
  e.mcl.kld_config.n_min = fo.kld_min;
  e.mcl.alpha_slow = fo.alpha_slow;
  e.mcl.alpha_fast = fo.alpha_fast;
  e.mcl.max_injection_fraction = fo.max_injection;
  e.particles = fo.particles;
  e.seed = sc.seed;
  e.clearance_m = fo.clearance_m;
  e.cluster_cell_m = 1.0f;
  e.global = fo.filter == est::loop::Filter::mcl && fo.start == StartKind::global;
  e.initial_pose = fo.start == StartKind::wrong ? wrong_start_pose(s) : s.truth.front().pose;
  const bool ekf = fo.filter == est::loop::Filter::ekf;
  e.initial_sigma_xy_m = ekf ? fo.ekf_start_sigma_xy_m : 0.2f;
  e.initial_sigma_theta_rad = ekf ? fo.ekf_start_sigma_theta_rad : 0.1f;
  // The filter is told the sensor's own noise; the heading noise added per prediction covers what the motion model
  // leaves out (the encoders' scale error and slip turn the robot where the model says it drove straight).
  e.landmark_noise = sc.landmark_sensor.noise;
  e.ekf_rot_sigma = fo.ekf_rot_sigma_rad;
  e.lost_sigma_m = fo.ekf_lost_sigma_m;
  e.limits = s.limits;
  return e;
}

std::map<std::string, int> SimResult::observed_counts() const {
  std::map<std::string, int> out;
  const auto add = [&](const std::string& key, std::uint64_t v) {
    if (v > 0) out[key] += static_cast<int>(v);
  };
  for (const auto& [name, c] : sensor_faults)
    for (std::size_t i = 1; i < hal::kFaultCount; ++i)
      add(std::string("hal.") + name + "." + hal::to_string(static_cast<hal::Fault>(i)), c.count[i]);
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

SimResult run_simulation(const ScenarioConfig& scenario, const FilterOptions& filter, const SimWorld& world,
                         Progress* progress, const RunView* watch) {
  const auto started = std::chrono::steady_clock::now();
  SimResult r;
  r.filter = filter.filter;
  const bool ekf = filter.filter == est::loop::Filter::ekf;
  if (ekf && world.landmarks.size() == 0)
    throw std::invalid_argument("--filter ekf needs landmarks, and " + world.name +
                                " has none (a ROS map carries no landmarks): use the synthetic office (no --map) or --landmarks FILE");
  if (ekf && filter.start == StartKind::global)
    throw std::invalid_argument("--filter ekf tracks from the true start pose (a Gaussian of sigma 0.2 m, 0.1 rad): "
                                "--start global needs --filter mcl");
  // No silent mismatch between the robot's sensors and the filter's models (issue 37).
  if (!ekf && filter.range_model == node::RangeModel::steered && !scenario.handlebar)
    throw std::invalid_argument("--sensor-model steered is for a rangefinder on the handlebar, and this robot's is "
                                "fixed on the frame: add --handlebar (rangefinder.mount = \"handlebar\"), or use "
                                "--sensor-model likelihood-field or beam");
  if (!ekf && scenario.handlebar && filter.range_model != node::RangeModel::steered)
    throw std::invalid_argument("the rangefinder is on the handlebar and turns with it: a fixed-frame range model "
                                "would take every turn of the handle for a turn of the robot; use --sensor-model "
                                "steered (filter.sensor_model = \"steered\")");
  r.stream = generate_stream(scenario, world);
  if (r.stream.truth.empty()) throw std::invalid_argument("the run has no steps");
  expect_loop_inputs(r.stream, !ekf, ekf);
  run_stream(scenario, filter, world, r, progress, watch);
  r.metrics = compute_metrics(r.stream, r.rows, filter);
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return r;
}

}  // namespace sim

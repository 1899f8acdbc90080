#pragma once
// The host simulation: a scenario's sensor stream goes through the same pipeline estimator_node runs
// (node/estimator_pipeline.hpp: the HAL gate, the loop port, the firmware's filter loop with MCL on the scans or the
// EKF on the landmark sightings, any of the six motion models), in process; every estimate is compared with the
// ground truth. Metrics: accuracy once localized, time to converge from a global start and to recover from the
// kidnapping, and every rejected input by reason next to the faults that were injected. Host only (may throw).
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "est/filter/augmented_mcl.hpp"
#include "est/filter/correction_status.hpp"
#include "est/filter/ekf_localization.hpp"
#include "est/geometry/pose2.hpp"
#include "est/loop/configured_loop.hpp"
#include "est/loop/loop_counters.hpp"
#include "hal/fault.hpp"
#include "hal/loop_port.hpp"
#include "hal/sensors/range_scan/validator.hpp"
#include "node/estimator_spec.hpp"
#include "sim/progress.hpp"
#include "sim/scenario.hpp"
#include "sim/sensor_stream.hpp"
#include "view/live_view.hpp"

namespace sim {

struct FilterOptions {
  // mcl: augmented MCL on the scans (MclEstimator). ekf: EKF localization on the landmark sightings (EkfEstimator,
  // Thrun tables 7.2/7.3), tracking from a Gaussian at the true start; it needs a world with landmarks.
  est::loop::Filter filter = est::loop::Filter::mcl;
  node::RangeModel range_model = node::RangeModel::likelihood_field;  // MCL's
  node::BeamCast beam_cast = node::BeamCast::table;  // the beam model's z*: heading table, or the exact cone caster
  StartKind start = StartKind::global;
  // The steered range model (a rangefinder on the handlebar): the handle positions (0: the steering reading taken as
  // exact), how far the filter trusts the reading, and the steering noise while no steering is known.
  std::int32_t handle_positions = 6;
  float handle_reading_sigma_rad = 0.05f;
  float handle_reading_floor = 0.05f;  // the least p(alpha_m | reading): how often the reading names a wrong position
  float unknown_steer_sigma_rad = 0.3f;
  // The omni model's noise a1..a9 the filter is told, per 10 ms prediction; empty: estimator_node's default
  // (node/estimator_spec.hpp MotionSpec).
  std::vector<float> omni_noise;
  std::uint32_t particles = 20000;  // initial count (and the capacity's share when KLD adapts it)
  bool kld = true;
  std::uint32_t kld_min = 500;
  std::int32_t beam_stride = 6;     // every 6th beam of 360: 60 per scan
  float clearance_m = 0.2f;         // free-space poses this far from walls (global start, injection)
  // Augmented MCL's averages of the per-beam fit (Thrun table 8.3, est/filter/augmented_mcl.hpp), per scan. The slow
  // one forgets the perfect-fit start in ~20 s: at 0.02 (5 s) it learned a look-alike's fit before the search found
  // the robot (one of 40 seeded demo runs took 11.9 s to localize).
  float alpha_slow = 0.005f;
  float alpha_fast = 0.3f;
  float max_injection = 0.5f;       // at most this share of a resampled set is injected
  // EKF: the start's standard deviations (around the true start pose), the heading noise added to every prediction
  // (what the odometry models leave out: slip, the encoders' scale error), and the position sigma beyond which the
  // belief is reported degenerate.
  float ekf_start_sigma_xy_m = 0.2f;
  float ekf_start_sigma_theta_rad = 0.1f;
  float ekf_rot_sigma_rad = 0.002f;
  float ekf_lost_sigma_m = 5.0f;
  // "Localized": position within converge_pos_m and heading within converge_heading_deg for hold_s.
  double converge_pos_m = 0.5;
  double converge_heading_deg = 10.0;
  double hold_s = 2.0;
};

// One estimate of the loop with the truth at its time.
struct OutputRow {
  hal::TimeNs t_ns = 0;
  est::Pose2 truth, estimate;
  float position_error_m = 0.0f;
  float heading_error_rad = 0.0f;
  float sigma_x_m = 0.0f, sigma_y_m = 0.0f, sigma_theta_rad = 0.0f;
  float cov_xy_m2 = 0.0f;      // the position covariance's off-diagonal (the 2-sigma ellipse of the plots)
  std::uint32_t particles = 0; // 0 for the EKF
  // MCL: the filter's counters after this output (cumulative): samples drawn at resamplings, of which injected.
  std::uint32_t drawn_particles = 0, injected_particles = 0;
  std::uint32_t status = 0;  // hal::status bits, without kDeadlineOverrun (wall-clock dependent)
  std::uint32_t rejected_inputs = 0;
};

struct ParticleSnapshot {
  hal::TimeNs t_ns = 0;
  std::string label;
  std::vector<est::Pose2> particles;  // at most 4000 (every n-th)
  std::uint32_t total = 0;
  est::Pose2 truth, estimate;
};

// A phase of the run: from the start or the kidnapping to the next event or the end. Times in s from the run start
// unless named "time_to".
struct PhaseMetrics {
  std::string name;  // "global localization", "tracking", "kidnap recovery"
  double start_s = 0.0, end_s = 0.0;
  // When the estimate was first outside the bounds in the phase: the phase start for a global start; for a
  // kidnapping the first output after it that is off by more than the bounds; -1 when the estimate never left them
  // (a kidnapping that did not really lose the filter: the phase then counts as not recovered).
  double lost_at_s = -1.0;
  bool localized = false;
  double localized_at_s = -1.0;      // from here the estimate stays within the bounds for the hold time
  double time_to_localize_s = -1.0;  // from lost_at_s (tracking: from the start); -1 when never
  // Over the phase's localized part (MCL; -1 when not localized or for the EKF): injected / drawn particles at the
  // resamplings, and the particle count of the outputs.
  double injected_share = -1.0;
  std::uint64_t injected_particles = 0, drawn_particles = 0;
  double particles_mean = -1.0;
  std::uint32_t particles_max = 0;
};

struct SimMetrics {
  std::vector<PhaseMetrics> phases;
  // Over the localized part of every phase.
  double rmse_position_m = -1.0, rmse_heading_deg = -1.0;
  double max_position_error_m = -1.0, max_heading_error_deg = -1.0;
  double localized_time_s = 0.0;
  double outside_bounds_s = 0.0;  // localized time spent outside the bounds after all (transients)
  // Over every output.
  double rmse_position_all_m = -1.0;
};

struct SimResult {
  est::loop::Filter filter = est::loop::Filter::mcl;
  SensorStream stream;
  std::vector<OutputRow> rows;
  std::vector<hal::Estimate> estimates;  // the loop's outputs as published (a row each)
  std::vector<ParticleSnapshot> snapshots;
  std::map<std::string, hal::FaultCounters> sensor_faults;  // by the HAL's sensor names (wheel_ticks, ...)
  std::uint32_t landmark_features_accepted = 0;  // by the HAL
  hal::BeamCounters beams;
  est::loop::LoopCounters loop;
  hal::LoopPortRejectCounters port_rejects;
  est::MclCounters mcl;                   // MCL runs
  est::CorrectionCounters ekf;            // EKF runs: features fused or refused, by reason
  est::PredictionCounters ekf_predictions;
  std::uint32_t nonfinite_estimates = 0;
  std::string description;                // the estimator, as estimator_node describes it
  SimMetrics metrics;
  double wall_s = 0.0;

  // Reject counters by the names InjectedFault::expected uses (hal.<stream>.<reason> with stream a HAL sensor name:
  // wheel_ticks, steering, twist, odometry, scan, landmarks; hal.scan.beams_nan,
  // loop.too_old, loop.queue_full, loop.rejected, port.<reason>); zeros left out. An EKF's refused features are not
  // in loop.rejected here (see SimResult::ekf).
  std::map<std::string, int> observed_counts() const;
};

// The pose a wrong start (StartKind::wrong) believes the robot at, confidently: the route's pose half the run later,
// or the first after it at least 3 m from the true start (the farthest pose of the route if none is).
est::Pose2 wrong_start_pose(const SensorStream& stream);

// The estimator of a run, as estimator_node is configured for this robot (record writes the same as options).
node::EstimatorSpec estimator_spec(const ScenarioConfig& scenario, const FilterOptions& filter,
                                   const SensorStream& stream);

// An estimate with the truth at its time.
OutputRow output_row(const SensorStream& stream, const hal::Estimate& estimate);
// The metrics of a run's estimates against its stream's truth (the phases from the start kind and the kidnapping).
// Rows without MCL's particle counts (a live node's estimates) give the particle figures as zeros.
SimMetrics compute_metrics(const SensorStream& stream, const std::vector<OutputRow>& rows, const FilterOptions& filter);

// A run watched in the live view (view/live_view.hpp; the caller gives it the world's map): every estimate with the
// truth at its time, and MCL's particles at the view's rate; the stream paced at `speed` times real time (0: as fast
// as it goes). The outputs are the same bits as an unwatched run's.
struct RunView {
  view::LiveView* view = nullptr;
  double speed = 1.0;
};

// Throws std::invalid_argument on a bad configuration, e.g. the EKF with a global start or in a world without
// landmarks. `progress` (optional) is told the simulated time (s from the start) as the stream is consumed.
SimResult run_simulation(const ScenarioConfig& scenario, const FilterOptions& filter, const SimWorld& world,
                         Progress* progress = nullptr, const RunView* watch = nullptr);

using node::to_string;  // of est::loop::Filter

// The files of a run in `dir` (created): trajectory.csv, faults.csv, metrics.json and, with plots, trajectory.png,
// errors.png, particles.png (gnuplot scripts and their data beside them). Returns the paths written.
std::vector<std::string> write_simulation_outputs(const SimResult& result, const ScenarioConfig& scenario,
                                                  const FilterOptions& filter, const SimWorld& world,
                                                  const std::string& dir, bool plots);

// The metrics JSON as text (what metrics.json holds).
std::string metrics_json(const SimResult& result, const ScenarioConfig& scenario, const FilterOptions& filter,
                         const SimWorld& world);

}  // namespace sim

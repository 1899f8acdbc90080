#pragma once
// sim_host eval tricycle: calibrates the front-steered model on the tricycle set (data/tricycle.hpp) by least
// squares against the tracked sensor pose, and reports the odometry error before (the header's initial guesses) and
// after, on a held-out part of the log.
//
// The model is the book's bicycle referenced at the front wheel (est/motion/bicycle_model.hpp): the front wheel is
// both steered and driven, so its travel s (the traction encoder) and angle a (the steering encoder) are the
// bicycle's controls as they are, with frame length l = axis_length; base_link is the rear axle's middle, l behind
// the front wheel, and the sensor sits at (laser_x, laser_y, laser_theta) in base_link.
// The fit (Levenberg-Marquardt, Eigen, numerical Jacobian) minimizes the sensor's relative motion over windows of
// `window` records (about 1 s) against the tracker's relative motion over the same records: relative motions keep the
// residuals independent of the drift that a whole dead-reckoned trajectory accumulates, and they see the sensor's
// pose on the robot (the turns move an offset sensor sideways). The odometry error is the dead-reckoned sensor
// trajectory (through the firmware's predict_motion_bicycle, floats) from the tracker's pose at the part's start
// against the tracker, and the error of the windows' relative motions. Host only.
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "data/eval_report.hpp"
#include "data/tricycle.hpp"

namespace sim::data {

struct TricycleEvalOptions {
  std::string out_dir = "eval-tricycle";
  double fit_fraction = 2.0 / 3.0;  // the first part of the records fits; the rest is held out
  double max_seconds = 0.0;         // > 0: the first seconds only (both parts within them)
  int window = 25;                  // records per relative-motion residual (25 Hz: 1 s)
  int max_iterations = 100;
  bool plots = true;
  bool quiet = false;
};

struct OdometryError {
  TrajectoryError trajectory;        // dead-reckoned from the part's first tracked pose
  double window_rmse_xy_m = 0.0;     // relative motion over `window` records against the tracker's
  double window_rmse_theta_rad = 0.0;
  std::uint64_t windows = 0;
};

struct TricycleEval {
  TricycleImport import;
  std::string log_path;
  // The whole log imported with the calibrated steering and replayed through estimator_node's pipeline (lockstep,
  // the bicycle's predictions only: nothing corrects it), against the tracker, and the RMSE between that replay and
  // tricycle_odometry over the same records (the loop's 100 Hz predictions against one step per record).
  TrajectoryError node_after;
  double node_vs_direct_rmse_m = 0.0;
  std::string node_log_path;
  TricycleParams before, after;
  std::size_t fit_records = 0, held_out_records = 0;
  double split_t_s = 0.0;  // the held-out part starts here
  OdometryError fit_before, fit_after, held_before, held_after;
  double cost_before = 0.0, cost_after = 0.0;  // the fit's sum of squared residuals
  int iterations = 0;
  double run_time_s = 0.0;
};

TricycleEval eval_tricycle(const std::string& file, const TricycleEvalOptions& options);
nlohmann::json to_json(const TricycleEval& e);

// The sensor's trajectory dead-reckoned over records [from, to) from the tracked pose at `from`, through the
// firmware's bicycle model (est::predict_motion_bicycle) with the parameters p.
Trajectory tricycle_odometry(const std::vector<TricycleRecord>& records, const TricycleParams& p,
                             const TricycleHeader& h, std::size_t from, std::size_t to);
// The front wheel's pose (the bicycle's reference point) under a tracked sensor pose.
TimedPose tricycle_front_wheel(const TimedPose& sensor, const TricycleParams& p);

// The replay a user makes of an imported log (`sim_host import tricycle --calibration ...`, then estimator_node
// --replay): node::Node with the bicycle at the front wheel (frame length axis_length, metres per tick
// ktraction / traction_max, one 32-bit traction counter), tracking from the front wheel's pose under the tracker's
// first pose, no landmarks; returns the sensor's trajectory.
Trajectory tricycle_node_odometry(const std::string& log, const std::vector<TricycleRecord>& records,
                                  const TricycleParams& p, const TricycleHeader& h, const std::string& out_log);
OdometryError tricycle_odometry_error(const std::vector<TricycleRecord>& records, const TricycleParams& p,
                                      const TricycleHeader& h, std::size_t from, std::size_t to, int window);

}  // namespace sim::data

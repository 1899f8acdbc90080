#pragma once
// What every evaluation on real data shares: trajectories and their errors against a reference (interpolated in
// time), progress on a terminal for long runs (sim/progress.hpp), the printed table and the JSON file. Host only.
#include <cstdint>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "sim/progress.hpp"  // Progress, shared with the simulator

namespace sim::data {

struct TimedPose {
  std::int64_t t_ns = 0;
  double x = 0.0, y = 0.0, theta = 0.0;
};
using Trajectory = std::vector<TimedPose>;  // ordered by time

double wrap_angle(double a);  // to [-pi, pi]

// The reference pose at t by linear interpolation (headings along the shorter arc); false outside the reference's
// span or across a gap longer than max_gap_ns.
bool interpolate(const Trajectory& reference, std::int64_t t_ns, std::int64_t max_gap_ns, TimedPose& out);

struct TrajectoryError {
  double rmse_xy_m = 0.0;       // sqrt(mean(dx^2 + dy^2))
  double rmse_theta_rad = 0.0;  // sqrt(mean(wrapped dtheta^2))
  double max_xy_m = 0.0;
  double final_xy_m = 0.0;
  std::uint64_t n = 0;          // estimates compared (those with a reference within the gap)
};
// The estimate against the reference at the estimate's times, from `from_ns` on.
TrajectoryError trajectory_error(const Trajectory& estimate, const Trajectory& reference, std::int64_t max_gap_ns,
                                 std::int64_t from_ns = INT64_MIN);
// The estimates estimator_node wrote to an LCM log (EST_POSE, pose_estimate_t), in the log's order; throws
// std::runtime_error for a log that cannot be read.
Trajectory read_pose_estimates(const std::string& log_path);

// Per-time errors for the plots: t (s from t0), position error (m), heading error (rad).
struct ErrorSample {
  double t_s = 0.0, xy_m = 0.0, theta_rad = 0.0;
};
std::vector<ErrorSample> error_series(const Trajectory& estimate, const Trajectory& reference,
                                      std::int64_t max_gap_ns, std::int64_t t0_ns);

// A table on stdout: a header row and right-aligned rows, column widths from the contents.
void print_table(std::FILE* f, const std::vector<std::string>& header,
                 const std::vector<std::vector<std::string>>& rows);
std::string fixed(double v, int decimals);

// Writes `j` (indented) to `path`; throws std::runtime_error if it cannot.
void write_json(const std::string& path, const nlohmann::json& j);

double wall_seconds();  // a monotonic clock for the run times the reports state

}  // namespace sim::data

#pragma once
// `sim_host plot LOG...`: the plots of any LCM log the project writes or imports, from the log alone: the estimates
// (EST_POSE, pose_estimate_t) against the ground truth (EST_GROUND_TRUTH, ground_truth_t), paired by the channel's
// suffix (EST_POSE_3 with EST_GROUND_TRUTH_3). A run's log (sim_host run), a recording, an imported dataset (its
// ground truth alone), or estimator_node's output given beside the log it replayed. Host only (throws).
#include <string>
#include <vector>

#include "data/eval_report.hpp"

namespace CLI {
class App;
}

namespace sim::data {

struct LogSeries {
  std::string suffix;  // "" or "_<n>"
  Trajectory truth;
  Trajectory estimate;
  TrajectoryError error;  // the estimate against the truth (n = 0 when either is missing)
};

// Every EST_POSE<suffix> and EST_GROUND_TRUTH<suffix> of the logs, by suffix; throws std::runtime_error naming the
// file for a log that cannot be read, holds no LCM event, or has a message that does not decode.
std::vector<LogSeries> read_log_series(const std::vector<std::string>& logs);

// In `dir`: <suffix>.csv per series (t, truth and estimate, errors) and trajectories.png, errors.png. Returns the
// PNGs written.
std::vector<std::string> write_log_plots(const std::vector<LogSeries>& series, const std::string& dir);

void add_plot_command(CLI::App& app);

}  // namespace sim::data

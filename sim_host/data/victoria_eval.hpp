#pragma once
// sim_host eval victoria: EKF-SLAM of the car (the bicycle at its front axle, data/victoria.hpp) on the tree
// detections with unknown correspondence, against GPS, both through estimator_node's replay of the imported log
// (lockstep, in process: the path a user's replay takes):
//   dead-reckoning   the bicycle's mean over the speed and steering, from the start pose (the EKF with no landmark
//                    input: the trees are not its input), checked against the same mean integrated directly
//   ekf-slam         estimator_node --filter ekf-slam (est/loop/ekf_slam_estimator.hpp: plain EKF-SLAM, table 10.1,
//                    and gated maximum-likelihood association, the correspondence test of table 10.2 done by maximum
//                    likelihood): each tree detection goes to the landmark of smallest Mahalanobis distance if that
//                    is under gate_accept, makes a new landmark if even the smallest is above gate_new, and is
//                    discarded in between; a new landmark is tentative until another scan sees it again
//                    (confirm_sightings). The map and the counters: the node's last slam_map_t.
// The start pose is the only alignment: its position puts the laser (the GPS antenna, car.bmp) at the mean of the
// GPS fixes before the car first moves, its heading turns the dead-reckoned laser's displacement over the first
// `heading_from_m` metres onto the GPS displacement over the same time. The trajectory compared is the laser's
// (the antenna's), at every GPS fix; GPS has jumps and dropouts (info.txt) and is counted as it is. Host only.
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "data/eval_report.hpp"
#include "data/victoria.hpp"

namespace sim::data {

// The noise the filter assumes, per 25 ms (the speed samples' period; shorter steps get proportionally less).
struct VictoriaNoise {
  float speed_var_per_speed = 0.02f;  // the bicycle's k: Var(v) = k |v| per step, m/s
  float steer_sigma = 0.03f;          // rad per step
  float heading_sigma = 0.002f;       // rad per prediction (not scaled), added to the heading: slip unmodelled
  float sigma_range = 0.5f;           // m
  float sigma_bearing = 0.05f;        // rad
};

struct VictoriaEvalOptions {
  VictoriaNoise noise;
  VictoriaGeometry geometry;
  std::string out_dir = "eval-victoria";
  double max_seconds = 0.0;        // > 0: the first seconds only
  double max_range_m = 30.0;       // detections farther away are not used (they are the least accurate)
  float gate_accept = 9.21f;       // chi^2 with 2 dof at 0.99: associate under it
  float gate_new = 30.0f;          // a new landmark above it; in between the detection is discarded
  double heading_from_m = 20.0;    // the start heading from the first metres of travel
  int confirm_sightings = 2;       // a new landmark needs this many sightings in different scans (1: at once)
  float candidate_radius_m = 1.0f; // a tentative landmark's sightings agree within this
  int candidate_scans = 10;        // a tentative landmark unseen for this many scans is forgotten
  bool plots = true;
  bool quiet = false;
};

struct VictoriaRun {
  std::string name;
  TrajectoryError gps;   // the laser's position against the GPS fixes (xy only; a fix has no heading)
  double gps_median_m = 0.0, gps_p95_m = 0.0;  // of the same errors: robust to the GPS's jumps
  double run_time_s = 0.0;
  int landmarks = 0;
  std::uint64_t associated = 0, created = 0, discarded = 0, out_of_range = 0;
  std::uint64_t refused = 0;         // confirmed new landmarks the filter refused: its capacity, or the insertion
  std::uint64_t update_refused = 0;  // associated detections whose update the filter refused (its gate, not PD)
  std::uint64_t tentative_full = 0, bad_input = 0;
  std::uint64_t tentative = 0;  // detections held for a tentative landmark
  std::uint64_t forgotten = 0;  // tentative landmarks never confirmed
};

struct VictoriaEval {
  VictoriaImport import;
  std::string log_path;
  TimedPose start;  // the front axle's start pose
  std::vector<VictoriaRun> runs;
  double node_vs_direct_rmse_m = 0.0;  // dead reckoning: estimator_node's replay against the direct integration
  int capacity = 0;  // the node's EKF-SLAM landmark capacity (node::kSlamLandmarks)
};

VictoriaEval eval_victoria(const std::string& dir, const VictoriaEvalOptions& options);
nlohmann::json to_json(const VictoriaEval& e);

}  // namespace sim::data

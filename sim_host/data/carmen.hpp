#pragma once
// CARMEN logs (carmen.sourceforge.net logger format; the Radish / Freiburg SLAM-corrected logs, gzipped or not):
// ODOM, FLASER and ROBOTLASER1 lines. In these GMapping output logs every scan carries the SLAM-corrected pose, and
// the ODOM stream is rewritten: right after each scan an ODOM line stamped 0 holds the corrected pose, and the
// following ODOM poses are that pose composed with the raw wheel odometry. So the motion between consecutive ODOM
// lines, except the jump into each stamp-0 line, is the raw odometry: the importer chains those increments into one
// drifting odometry pose (Thrun table 5.6's x_bar), and takes the corrected poses as the reference.
//
// The import writes one LCM log on the estimator's default channels (data/channels.hpp):
//   EST_ODOMETRY    odometry_t: the raw odometry pose, from the first scan on
//   EST_RANGE_SCAN  range_scan_t: each scan (FLASER: beam i at -pi/2 + i pi/n for n = 180/360, pi/(n-1) for 181/361)
//   EST_REFERENCE   ground_truth_t: the corrected pose at each scan (a SLAM solution, not measured truth)
// Stamps are the log's seconds. Corrections of the data, each counted and said in the summary: ODOM stamps that go
// backwards or lie outside their scans' interval (garbage such as 1e-42 in the intel log) are re-timed between
// their neighbours in line order; gaps longer than max_odometry_gap_s are bridged with interpolated poses (the HAL
// starts afresh after 0.5 s without odometry, and would lose the motion); readings at the log's largest value
// (81.83 m intel, 50 m aces, 81.91 m fr079: the laser's "no return") become max-range readings. Host only.
#include <cstdint>
#include <string>
#include <vector>

#include "data/eval_report.hpp"
#include "data/import_report.hpp"
#include "est/geometry/pose2.hpp"
#include "hal/sensors/range_scan/range_scan.hpp"

namespace sim::data {

// The HAL's scan geometry (readings at or beyond range_max_m are max-range, "no return"; scan_time_s unused).
using CarmenScanGeometry = hal::ScanGeometry;

struct CarmenScan {
  std::int64_t t_ns = 0;
  TimedPose reference;  // the corrected pose of the robot
  CarmenScanGeometry geometry;
  std::vector<float> ranges;
  std::uint64_t line = 0;  // in the CARMEN file
};

struct CarmenOdometry {
  std::int64_t t_ns = 0;
  double x = 0.0, y = 0.0, theta = 0.0;  // the raw odometry pose (chained increments)
};

// A whole log in memory, as parsed.
struct CarmenData {
  std::string path;
  std::vector<CarmenScan> scans;
  std::vector<CarmenOdometry> odometry;  // from the first scan's stamp on
  est::Pose2 mount{};                    // the laser on the robot (PARAM robot_frontlaser_offset, ROBOTLASER1)
};

struct CarmenImportOptions {
  std::size_t first_scan = 0;       // the slice: scans [first_scan, first_scan + max_scans)
  std::size_t max_scans = 0;        // 0: all
  double max_seconds = 0.0;         // > 0: only scans within this many seconds of the slice's first
  double max_odometry_gap_s = 0.25; // longer gaps between odometry poses are bridged by interpolation
  double no_return_m = 0.0;         // 0: the largest reading in the log; readings >= it are max-range
  double range_min_m = 0.02;
};

struct CarmenImport {
  std::string site;                  // "intel", "aces", ... from the file name
  std::size_t scans = 0;             // written
  std::size_t odometry = 0;          // poses written
  std::size_t beams = 0;             // of the first scan
  CarmenScanGeometry geometry;       // of the first scan
  est::Pose2 mount{};
  double t_first_s = 0.0, t_last_s = 0.0;
  std::uint64_t events = 0;
};

// Parses a CARMEN file (malformed lines reported with their line numbers, skipped or refused as `report` says;
// corrections counted there). Throws std::runtime_error when the file cannot be read or holds no scan.
CarmenData parse_carmen(const std::string& path, const CarmenImportOptions& options, ImportReport& report);
// Writes the slice of `data` that `options` selects to an LCM log.
CarmenImport write_carmen_log(const CarmenData& data, const std::string& out_log, const CarmenImportOptions& options,
                              ImportReport& report);
// Both: `sim_host import carmen`.
CarmenImport import_carmen(const std::string& path, const std::string& out_log, const CarmenImportOptions& options,
                           ImportReport& report);

// An imported log read back.
struct CarmenLog {
  Trajectory reference;          // at the scans' stamps
  Trajectory odometry;           // the raw odometry poses
  std::vector<CarmenScan> scans; // reference filled from EST_REFERENCE at the same stamp
};
CarmenLog read_carmen_log(const std::string& lcmlog);

// ---------------------------------------------------------------------------------------------------------------
// Occupancy grid mapping with known poses (Thrun table 9.1, the inverse range sensor model of table 9.2), host
// side: the geometry from the scans, the firmware's est/map/occupancy_grid_mapping.hpp for the update, the result
// written as a map_server PGM + YAML (trinary: occupied >= 0.65, free <= 0.196).
struct CarmenMapOptions {
  double resolution_m = 0.05;
  double max_range_m = 30.0;  // hits beyond are not mapped (and free space only up to here)
  double margin_m = 2.0;
};
struct CarmenMap {
  std::string yaml, pgm;
  int width = 0, height = 0;
  double resolution_m = 0.0, origin_x = 0.0, origin_y = 0.0;
  std::uint64_t occupied = 0, free = 0, unknown = 0;  // cells
  double endpoints_on_walls = 0.0;  // share of hit end points (at the reference poses) on or next to occupied cells
  double build_s = 0.0;
};
CarmenMap build_carmen_map(const std::vector<CarmenScan>& scans, const est::Pose2& mount, const std::string& stem,
                           const CarmenMapOptions& options);

// ---------------------------------------------------------------------------------------------------------------
// sim_host eval carmen: the map from the corrected poses, then MCL (odometry model, likelihood field) through
// estimator_node's pipeline on the raw odometry and the scans, against the corrected poses:
//   dead-reckoning   the raw odometry from the first corrected pose (the baseline)
//   mcl-tracking     MCL from the first corrected pose (plain MCL unless tracking_recovery: augmented MCL's
//                    random particles, meant for a lost robot, can pull a tracked estimate into a look-alike corridor)
//   mcl-global       MCL from a uniform belief, at `global_starts` start times; localized at the first scan from
//                    which the estimate is within global_success_m and global_success_rad of the reference at every
//                    scan of the next global_hold_s seconds and at global_kept_fraction of the scans to the end of
//                    the run (a few close scans in a dense log, or a find lost again, is no success); time to
//                    localize: log time from the start to that scan
// and the beam model's parameters learned by EM (table 6.2) from the scans at the corrected poses on the map.
struct CarmenEvalOptions {
  std::string out_dir = "eval-carmen";
  CarmenImportOptions import;       // the slice evaluated (and mapped)
  CarmenMapOptions map;
  std::uint32_t particles = 1000;   // tracking
  std::uint64_t seed = 1;
  std::int32_t beam_stride = 2;
  double predict_hz = 10.0;
  float odometry_noise[4] = {0.1f, 0.1f, 0.1f, 0.01f};  // a1..a4 of table 5.6 per prediction (variances)
  // Below this translation per prediction the odometry model takes the motion as a rotation. Backing up no longer
  // needs it (the model reads it as trans < 0); freiburg-079 does: its odometry point lies 0.04 m from the axis the
  // robot turns about (sideways chord / turn, median of 128 turns on the spot), so such a turn reads as a ~5 mm
  // sideways chord, |rot1| = pi/2 in either direction, with a1 (pi/2)^2 of noise. Seeds 1-5: freiburg-079 tracks
  // (0.16 m) at 0.01 and 0.03, and is lost (RMSE > 0.45 m) in 3-5 of 5 at 0.005 and below; intel is lost in 5 of 5
  // at 0.005 and 0.03, and tracks (0.07 m) in 3-4 of 5 at 0.001 and 1e-4 (the firmware's default): pass
  // --min-translation 1e-4 there.
  double min_translation_m = 0.03;
  float sigma_hit_m = 0.1f;         // the likelihood field's
  float z_rand = 0.05f;             // the likelihood field's (z_max 0.05, z_hit the rest)
  // Augmented MCL's recovery (est::MclConfig), for the global runs (and tracking with tracking_recovery).
  float max_injection_fraction = 0.5f;
  float recovery_lost_deficit = 1.0f;
  float recovery_dead_band = 0.15f;
  std::uint32_t recovery_patience = 10u;
  bool tracking = true;
  bool tracking_recovery = false;   // tracking with augmented MCL's random particles (table 8.3) or plain MCL
  int global_starts = 20;           // 0: no global localization; spread evenly over the slice
  std::uint32_t global_particles = 10000;
  double global_seconds = 150.0;    // log time each global run gets
  double global_success_m = 0.5;
  double global_success_rad = 0.3;
  double global_hold_s = 10.0;
  double global_kept_fraction = 0.9;
  bool mrpt_export = false;         // each global run's slice as a CARMEN log for MRPT, and its corrected poses
  bool learn_beam_model = true;
  std::int32_t em_beam_stride = 4;
  bool plots = true;
  bool quiet = false;
};

struct CarmenMethodResult {
  std::string name;
  TrajectoryError error;  // at the scans' stamps
  double run_time_s = 0.0;
  std::uint32_t rejects = 0;  // inputs the node rejected
};

struct CarmenGlobalRun {
  double start_s = 0.0;       // log time of the first scan
  std::size_t start_scan = 0;  // its index among the log's scans
  std::uint32_t injected_particles = 0;  // augmented MCL's random particles over the run
  bool localized = false;
  double time_to_localize_s = 0.0;
  double kept_fraction = 0.0;  // of the scans from the localization on, those within the success bounds
  TrajectoryError after;      // from the localization on
  double run_time_s = 0.0;
};

struct CarmenBeamModel {
  bool learned = false;
  float z_hit = 0, z_short = 0, z_max = 0, z_rand = 0, sigma_hit = 0, lambda_short = 0, range_max = 0;
  double log_likelihood_initial = 0.0, log_likelihood_final = 0.0;  // per reading
  int iterations = 0;
  bool converged = false;
  std::uint64_t readings = 0;
  double run_time_s = 0.0;
};

struct CarmenEval {
  CarmenImport import;
  ImportReport report;
  CarmenMap map;
  std::vector<CarmenMethodResult> methods;
  std::vector<CarmenGlobalRun> global;
  double global_success_rate = 0.0;
  double global_mean_time_s = 0.0;  // over the successful runs
  double global_max_time_s = 0.0;   // over the successful runs
  std::uint32_t global_particles = 0;
  double global_seconds = 0.0;      // log time each global run gets
  CarmenBeamModel beam;
  std::string log_path;
  double duration_s = 0.0;          // log time of the slice
};

CarmenEval eval_carmen(const std::string& path, const CarmenEvalOptions& options);
// mcl-global's success criterion for one run: the estimates against the reference at its scans.
CarmenGlobalRun judge_global_localization(const Trajectory& estimates, const Trajectory& reference,
                                          const CarmenEvalOptions& options);
nlohmann::json to_json(const CarmenEval& e);

}  // namespace sim::data

// `sim_host import FORMAT`: each format's subcommand and the --on-error option they share (data/formats.hpp). The
// importers themselves (data/<format>.cpp) know no command line: the fuzzers link them without CLI11.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "data/carmen.hpp"
#include "data/eval_report.hpp"
#include "data/formats.hpp"
#include "data/import_report.hpp"
#include "data/mrclam.hpp"
#include "data/tricycle.hpp"
#include "data/tricycle_eval.hpp"
#include "data/victoria.hpp"

namespace sim::data {

namespace {

// --on-error skip|refuse (default skip), the same on every importer.
CLI::Option* add_on_error_option(CLI::App& cmd, OnError& out) {
  return cmd
      .add_option_function<std::string>(
          "--on-error",
          [&out](const std::string& s) {
            if (!parse(s, out)) throw CLI::ValidationError("--on-error", "expected skip or refuse");
          },
          "a malformed line: skip it (reported with its file and line, counted in the summary) or refuse the import")
      ->default_str("skip");
}

}  // namespace

void add_mrclam_import(CLI::App& import) {
  CLI::App* cmd = import.add_subcommand(
      "mrclam", "UTIAS MRCLAM (raw/ or sampled-50hz/ layout, any of its nine datasets): every robot's (v, w), its "
                "landmark and robot sightings with identities, Vicon ground truth on EST_GROUND_TRUTH_<robot>");
  auto dir = std::make_shared<std::string>();
  auto out = std::make_shared<std::string>();
  auto opts = std::make_shared<MrclamImportOptions>();
  auto on_error = std::make_shared<OnError>(OnError::skip);
  auto keep = std::make_shared<bool>(false);
  cmd->add_option("DIR", *dir, "the dataset's folder, e.g. MRCLAM_Dataset1")->required()->check(CLI::ExistingDirectory);
  cmd->add_option("--out", *out, "the LCM log to write (the landmark file and arena map go beside it)")->required();
  cmd->add_option("--robots", opts->robots, "subjects to import")->capture_default_str()->delimiter(',');
  cmd->add_option("--seconds", opts->max_seconds, "only the first seconds (0: all)")->capture_default_str();
  cmd->add_flag("--keep-landmark-file", *keep, "import Dataset 1's landmark file as it is (subjects 11, 17 swapped)");
  add_on_error_option(*cmd, *on_error);
  cmd->callback([=] {
    opts->fix_landmarks = !*keep;
    ImportReport report(*on_error);
    const MrclamImport r = import_mrclam(*dir, *out, *opts, report);
    report.print_summary(stdout, "import mrclam: " + *dir + " (" + (r.sampled ? "sampled-50hz" : "raw") +
                                     " layout, dataset " + std::to_string(r.dataset) + ") -> " + *out);
    std::printf("  %llu events over %.1f s%s; landmarks: %s; arena map: %s\n",
                static_cast<unsigned long long>(r.events), r.duration_s,
                r.sampled ? "" : (", t = 0 at Unix time " + fixed(r.t0_unix_s, 3)).c_str(), r.landmarks_csv.c_str(),
                r.arena_yaml.c_str());
    const int s = opts->robots.front();
    const std::string pose = r.has_ground_truth ? fixed(r.start[s][0], 4) + "," + fixed(r.start[s][1], 4) + "," +
                                                      fixed(r.start[s][2], 4)
                                                : std::string("X,Y,THETA");
    std::printf("  replay robot %d: estimator_node --replay %s --model velocity --filter ekf --landmarks %s "
                "--ch-twist EST_TWIST_%d --ch-landmarks EST_LANDMARKS_%d --initial-pose %s --out est%d.lcmlog\n",
                s, out->c_str(), r.landmarks_csv.c_str(), s, s, pose.c_str(), s);
  });
}

void add_victoria_import(CLI::App& import) {
  CLI::App* cmd = import.add_subcommand(
      "victoria", "Victoria Park (ACFR): the car as the bicycle at its front axle: the front axle's travel on "
                  "EST_WHEEL_TICKS (from the rear left wheel's encoder), the steering on EST_STEERING, the tree "
                  "detections (range, bearing from the front axle, diameter as signature, id -1) on EST_LANDMARKS, "
                  "GPS on EST_GPS");
  auto dir = std::make_shared<std::string>();
  auto out = std::make_shared<std::string>();
  auto opts = std::make_shared<VictoriaImportOptions>();
  auto on_error = std::make_shared<OnError>(OnError::skip);
  cmd->add_option("DIR", *dir, "the dataset's folder (victoria-park/ or its acfr-text-rfsslam/)")
      ->required()->check(CLI::ExistingDirectory);
  cmd->add_option("--out", *out, "the LCM log to write")->required();
  cmd->add_option("--seconds", opts->max_seconds, "only the first seconds (0: all)")->capture_default_str();
  cmd->add_option("--metres-per-tick", opts->metres_per_tick, "the travel counter's resolution (m)")
      ->capture_default_str();
  add_on_error_option(*cmd, *on_error);
  cmd->callback([=] {
    ImportReport report(*on_error);
    const VictoriaImport r = import_victoria(*dir, *out, *opts, report);
    report.print_summary(stdout, "import victoria: " + r.folder + " -> " + *out);
    std::printf("  %llu events over %.1f s\n", static_cast<unsigned long long>(r.events), r.duration_s);
    std::printf("  replay (dead reckoning; the pose is the front axle's middle): estimator_node --replay %s --model "
                "bicycle --filter ekf --frame-length %.2f --metres-per-tick %g --wheel-count 1 --wheel-counter-bits 32 "
                "--steer-max 0.8 --max-steer 0.8 --ch-landmarks EST_LANDMARKS_NOT_READ --initial-pose X,Y,THETA "
                "--out est.lcmlog (sim_host eval victoria finds the start pose from GPS)\n", out->c_str(),
                opts->geometry.wheelbase, opts->metres_per_tick);
    std::printf("  replay (EKF-SLAM on the trees, as sim_host eval victoria runs it): estimator_node --replay %s "
                "--model bicycle --filter ekf-slam --frame-length %.2f --metres-per-tick %g --wheel-count 1 "
                "--wheel-counter-bits 32 --steer-max 0.8 --max-steer 0.8 --steer-sigma 0.03 --speed-var-per-speed "
                "0.02 --bicycle-rot-sigma 0 --slam-noise-step 0.025 --predict-hz 40 --ekf-rot-sigma 0.002 "
                "--landmark-sigma-range 0.5 --landmark-sigma-bearing 0.05 --landmark-max-range 100 --lost-sigma 1000 "
                "--initial-pose X,Y,THETA --initial-sigma 0.01,0.01 --out est.lcmlog\n",
                out->c_str(), opts->geometry.wheelbase, opts->metres_per_tick);
  });
}

void add_carmen_import(CLI::App& import) {
  CLI::App* cmd = import.add_subcommand(
      "carmen", "CARMEN logs (ODOM, FLASER, ROBOTLASER1; gzipped or not), e.g. the Radish / Freiburg SLAM-corrected "
                "logs: the raw odometry pose on EST_ODOMETRY, the scans on EST_RANGE_SCAN, the corrected poses on "
                "EST_REFERENCE");
  auto in = std::make_shared<std::string>();
  auto out = std::make_shared<std::string>();
  auto opts = std::make_shared<CarmenImportOptions>();
  auto on_error = std::make_shared<OnError>(OnError::skip);
  cmd->add_option("LOG", *in, "a CARMEN log (.log, .clf, .gz)")->required()->check(CLI::ExistingFile);
  cmd->add_option("--out", *out, "the LCM log to write")->required();
  cmd->add_option("--first-scan", opts->first_scan, "the slice starts at this scan (0-based)")->capture_default_str();
  cmd->add_option("--max-scans", opts->max_scans, "at most this many scans (0: all)")->capture_default_str();
  cmd->add_option("--seconds", opts->max_seconds, "only scans within this many seconds of the first (0: all)")
      ->capture_default_str();
  cmd->add_option("--no-return", opts->no_return_m, "readings at or beyond this are max-range (0: the log's largest)")
      ->capture_default_str();
  cmd->add_option("--max-odometry-gap", opts->max_odometry_gap_s, "longer odometry pauses are bridged (s)")
      ->capture_default_str();
  add_on_error_option(*cmd, *on_error);
  cmd->callback([=] {
    ImportReport report(*on_error);
    const CarmenImport r = import_carmen(*in, *out, *opts, report);
    report.print_summary(stdout, "import carmen: " + *in + " -> " + *out);
    std::printf("  site %s: %zu scans of %zu beams (%.4f rad apart from %.4f rad, max range %.2f m), %zu odometry "
                "poses, %.1f .. %.1f s\n",
                r.site.c_str(), r.scans, r.beams, static_cast<double>(r.geometry.angle_increment_rad),
                static_cast<double>(r.geometry.angle_min_rad), static_cast<double>(r.geometry.range_max_m), r.odometry,
                r.t_first_s, r.t_last_s);
    std::printf("  replay: estimator_node --replay %s --model odometry --sensor-mount %.3f,%.3f,%.3f --range-max %.2f "
                "--map MAP.yaml ...\n",
                out->c_str(), static_cast<double>(r.mount.x), static_cast<double>(r.mount.y),
                static_cast<double>(r.mount.theta), static_cast<double>(r.geometry.range_max_m));
  });
}

void add_tricycle_import(CLI::App& import) {
  CLI::App* cmd = import.add_subcommand(
      "tricycle", "The front-tractor tricycle calibration set (Sapienza): traction ticks (uint32, wrapping) on "
                  "EST_WHEEL_TICKS, the steering on EST_STEERING (angle) and EST_STEERING_TICKS (raw), the tracked "
                  "sensor pose on EST_GROUND_TRUTH");
  auto file = std::make_shared<std::string>();
  auto out = std::make_shared<std::string>();
  auto opts = std::make_shared<TricycleImportOptions>();
  auto on_error = std::make_shared<OnError>(OnError::skip);
  auto cal = std::make_shared<std::vector<double>>();
  cmd->add_option("FILE", *file, "the dataset's dataset.txt")->required()->check(CLI::ExistingFile);
  cmd->add_option("--out", *out, "the LCM log to write")->required();
  cmd->add_option("--seconds", opts->max_seconds, "only the first seconds (0: all)")->capture_default_str();
  cmd->add_option("--steering", *cal, "KSTEER,OFFSET: the steering calibration of EST_STEERING (default: the "
                                      "header's initial guesses)")->delimiter(',')->expected(2);
  add_on_error_option(*cmd, *on_error);
  cmd->callback([=] {
    if (!cal->empty()) {
      opts->calibrated = true;
      opts->params.ksteer = (*cal)[0];
      opts->params.steer_offset = (*cal)[1];
    }
    ImportReport report(*on_error);
    const TricycleImport r = import_tricycle(*file, *out, *opts, report);
    report.print_summary(stdout, "import tricycle: " + *file + " -> " + *out);
    const TricycleParams& g = r.header.guess;
    std::printf("  %llu records over %.1f s, t = 0 at Unix time %.6f; traction counter wrapped %llu times\n",
                static_cast<unsigned long long>(r.records), r.duration_s, r.t0_unix_s,
                static_cast<unsigned long long>(r.traction_wraps));
    std::printf("  header: Ksteer %g, Ktraction %g, axis_length %g, steer_offset %g, encoders %lld / %lld, laser "
                "(%g, %g, %g)\n", g.ksteer, g.ktraction, g.axis_length, g.steer_offset,
                static_cast<long long>(r.header.steer_max), static_cast<long long>(r.header.traction_max),
                g.laser_x, g.laser_y, g.laser_theta);
    const TricycleParams& s = opts->calibrated ? opts->params : g;
    std::printf("  EST_STEERING: a = %g * 2 pi * ticks / %lld + %g rad; the bicycle's --metres-per-tick is "
                "Ktraction / %lld\n", s.ksteer, static_cast<long long>(r.header.steer_max), s.steer_offset,
                static_cast<long long>(r.header.traction_max));
    const std::vector<TricycleRecord> records = read_tricycle_log(*out);
    if (!records.empty()) {
      const TimedPose f = tricycle_front_wheel(records.front().tracker, s);
      std::printf("  replay (odometry only, the front wheel): estimator_node --replay %s --model bicycle --filter ekf "
                  "--frame-length %g --metres-per-tick %.9g --wheel-count 1 --wheel-counter-bits 32 "
                  "--max-ticks-per-s 1000000 --steer-max 1.55 --max-steer 1.55 --initial-pose %.4f,%.4f,%.4f "
                  "--out est.lcmlog\n", out->c_str(), s.axis_length,
                  s.ktraction / static_cast<double>(r.header.traction_max), f.x, f.y, f.theta);
    }
  });
}

}  // namespace sim::data

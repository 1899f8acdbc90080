// estimator_node's options (hal/tools/node_config.hpp).
#include "node_config.hpp"

#include <cmath>
#include <map>
#include <string>
#include <vector>

namespace hal::node {

namespace {

std::string trimmed(double v) {
  std::string s = std::to_string(v);
  while (!s.empty() && s.back() == '0') s.pop_back();
  if (!s.empty() && s.back() == '.') s.pop_back();
  return s;
}

// Durations are given in milliseconds on the command line and kept in nanoseconds.
void add_ms(CLI::App& app, const std::string& name, TimeNs& target, const std::string& help, const char* group) {
  app.add_option_function<double>(
         name, [&target](double ms) { target = static_cast<TimeNs>(std::llround(ms * 1.0e6)); }, help + " (ms)")
      ->default_str(trimmed(static_cast<double>(target) / 1.0e6))
      ->check(CLI::NonNegativeNumber)
      ->group(group);
}

// "x,y,theta" as a pose.
void add_pose(CLI::App& app, const std::string& name, est::Pose2& target, bool* given, const std::string& help,
              const char* group) {
  app.add_option_function<std::vector<float>>(
         name,
         [&target, given](const std::vector<float>& v) {
           target = {v[0], v[1], v[2]};
           if (given != nullptr) *given = true;
         },
         help)
      ->delimiter(',')
      ->expected(3)
      ->group(group);
}

}  // namespace

void add_options(CLI::App& app, NodeConfig& c) {
  app.get_formatter()->column_width(34);

  const char* io = "Inputs and outputs";
  app.add_option("--can", c.can_interface,
                 "SocketCAN interface to read sensor frames from (hal/can/estimator.dbc: WHEEL_TICKS, STEERING, "
                 "SCAN_*); inputs are stamped with the kernel's receive time")
      ->group(io);
  app.add_option("--lcm", c.lcm_url,
                 "LCM URL to read sensor messages from (est_lcm encoder_ticks_t, steering_t, range_scan_t, "
                 "landmark_sighting_t; stamped "
                 "by the sender, same monotonic clock as this host) and to publish on")
      ->group(io);
  app.add_option("--lcm-out", c.lcm_out_url,
                 "LCM URL for the outputs (pose_estimate_t, status_t); default: --lcm's URL, else LCM's default "
                 "(udpm://239.255.76.67:7667?ttl=0 or $LCM_DEFAULT_URL)")
      ->group(io);
  app.add_flag("--can-out", c.can_out,
               "also send each estimate on the --can interface (POSE_ESTIMATE, POSE_SIGMA, POSE_CORRELATION, "
               "ESTIMATOR_STATUS)")
      ->group(io);
  app.add_option("--replay", c.replay_path,
                 "lockstep replay: run this LCM log (lcm-logger format) through the loop as fast as possible and "
                 "exit; each input is stamped with its message's stamp_ns (the log's receive times are ignored), so "
                 "the same log gives the same --out log, bit for bit")
      ->group(io)->check(CLI::ExistingFile);
  app.add_option("--out", c.out_path,
                 "write the estimates (and status) to this LCM log; required with --replay; event times are the "
                 "estimates' stamps")
      ->group(io);
  app.add_option("--record-inputs", c.record_path,
                 "write every input handed to the filter loop, in that order and with the stamp the loop used, to "
                 "this LCM log (replayable with --replay --wheel-counter-bits 32)")
      ->group(io);
  app.add_option("--ch-wheel-ticks", c.channels.wheel_ticks, "LCM channel: encoder ticks in")->capture_default_str()->group(io);
  app.add_option("--ch-steering", c.channels.steering, "LCM channel: steering in")->capture_default_str()->group(io);
  app.add_option("--ch-scan", c.channels.range_scan, "LCM channel: range scans in")->capture_default_str()->group(io);
  app.add_option("--ch-landmarks", c.channels.landmarks, "LCM channel: landmark sightings in (landmark_sighting_t)")->capture_default_str()->group(io);
  app.add_option("--ch-pose", c.channels.pose, "LCM channel: pose estimates out")->capture_default_str()->group(io);
  app.add_option("--ch-status", c.channels.status, "LCM channel: status out")->capture_default_str()->group(io);
  app.add_option("--status-hz", c.status_hz, "status_t rate, in input time (0: only at the end)")
      ->capture_default_str()->check(CLI::NonNegativeNumber)->group(io);
  app.add_option("--duration", c.duration_s, "live: stop after this many seconds (0: run until SIGINT/SIGTERM)")
      ->capture_default_str()->check(CLI::NonNegativeNumber)->group(io);
  app.add_flag("--quiet", c.quiet, "no summary on stderr at the end")->group(io);

  const char* robot = "Robot";
  app.add_option_function<std::string>(
         "--model",
         [&c](const std::string& m) { c.model = m == "bicycle" ? RobotModel::bicycle : RobotModel::diff_drive; },
         "motion model: diff-drive (wheels 0 and 1 are the left and right encoders) or bicycle (wheel 0 is the front "
         "wheel's traction encoder, plus steering)")
      ->check(CLI::IsMember({"diff-drive", "bicycle"}))->default_str("diff-drive")->group(robot);
  app.add_option("--wheel-radius", c.diff_drive.wheel_radius, "diff-drive: wheel radius (m)")->capture_default_str()->group(robot);
  app.add_option("--track-width", c.diff_drive.track_width, "diff-drive: distance between the wheels (m)")->capture_default_str()->group(robot);
  app.add_option("--ticks-per-rev", c.diff_drive.ticks_per_rev, "diff-drive: encoder ticks per wheel revolution")->capture_default_str()->group(robot);
  app.add_option("--travel-sigma-per-m", c.diff_drive.travel_sigma_per_m, "diff-drive: wheel travel noise per metre travelled")->capture_default_str()->group(robot);
  app.add_option("--travel-sigma-floor", c.diff_drive.travel_sigma_floor, "diff-drive: wheel travel noise floor (m)")->capture_default_str()->group(robot);
  app.add_option("--rot-sigma", c.diff_drive.final_rot_sigma, "diff-drive: final rotation noise (rad)")->capture_default_str()->group(robot);
  app.add_option("--frame-length", c.bicycle.frame_length, "bicycle: rear to front wheel (m)")->capture_default_str()->group(robot);
  app.add_option("--steer-max", c.bicycle.steer_max, "bicycle: steering stop (rad)")->capture_default_str()->group(robot);
  app.add_option("--steer-sigma", c.bicycle.steer_sigma, "bicycle: steering noise (rad)")->capture_default_str()->group(robot);
  app.add_option("--speed-var-per-speed", c.bicycle.speed_var_per_speed, "bicycle: speed variance per speed (m/s)")->capture_default_str()->group(robot);
  app.add_option("--bicycle-rot-sigma", c.bicycle.final_rot_sigma, "bicycle: final rotation noise (rad)")->capture_default_str()->group(robot);
  app.add_option("--metres-per-tick", c.metres_per_tick, "bicycle: front wheel travel per encoder tick (m)")->capture_default_str()->group(robot);
  add_pose(app, "--sensor-mount", c.sensor_mount, nullptr, "rangefinder pose on the robot: x,y,theta (m, m, rad); default 0,0,0", robot);

  const char* map = "Map and initial belief";
  app.add_option("--map", c.map,
                 "'office' (the built-in synthetic office, 20 m x 15 m) or a ROS map_server YAML file (PGM image, "
                 "trinary/scale/raw, at most 2048 x 2048 cells)")
      ->capture_default_str()->group(map);
  app.add_option("--clearance", c.clearance_m, "free-space draws keep this far from obstacles (m)")->capture_default_str()->group(map);
  add_pose(app, "--initial-pose", c.initial_pose, &c.initial_pose_given, "tracking: initial pose x,y,theta (m, m, rad)", map);
  app.add_option_function<std::vector<float>>(
         "--initial-sigma",
         [&c](const std::vector<float>& v) {
           c.initial_sigma_xy_m = v[0];
           c.initial_sigma_theta_rad = v[1];
         },
         "tracking: initial spread sigma_xy,sigma_theta (m, rad)")
      ->delimiter(',')->expected(2)->default_str("0.2,0.1")->group(map);
  app.add_flag("--global", c.global, "global localization: particles uniform over the free space")->group(map);

  const char* ekf = "Filter: EKF localization on landmark sightings (--filter ekf)";
  app.add_option_function<std::string>(
         "--filter",
         [&c](const std::string& f) { c.filter = f == "ekf" ? est::loop::Filter::ekf : est::loop::Filter::mcl; },
         "mcl: augmented Monte Carlo localization on range scans and the occupancy map (tracking or global); ekf: "
         "EKF localization on landmark sightings (range, bearing, signature; known or unknown correspondence) and "
         "a landmark map (tracking from --initial-pose; scans are counted as unused)")
      ->check(CLI::IsMember({"mcl", "ekf"}))->default_str("mcl")->group(ekf);
  app.add_option("--landmarks", c.landmarks,
                 "landmark map: 'office' (the built-in office's 16 posts, signatures 1..16) or a CSV file of "
                 "x,y,signature lines (m; '#' comments); a sighting's id is the line index from 0")
      ->capture_default_str()->group(ekf);
  app.add_option("--landmark-sigma-range", c.landmark_noise.sigma_range, "landmark sensor: range noise (m)")->capture_default_str()->check(CLI::PositiveNumber)->group(ekf);
  app.add_option("--landmark-sigma-bearing", c.landmark_noise.sigma_bearing, "landmark sensor: bearing noise (rad)")->capture_default_str()->check(CLI::PositiveNumber)->group(ekf);
  app.add_option("--landmark-sigma-signature", c.landmark_noise.sigma_signature,
                 "landmark sensor: signature noise; > 0 makes signatures part of the association (0: not used)")
      ->capture_default_str()->check(CLI::NonNegativeNumber)->group(ekf);
  app.add_option("--landmark-max-range", c.limits.landmarks.max_range_m, "landmark features beyond this are rejected (m)")->capture_default_str()->check(CLI::PositiveNumber)->group(ekf);
  app.add_option("--ekf-rot-sigma", c.ekf_rot_sigma, "heading noise added to every EKF prediction (rad)")->capture_default_str()->check(CLI::NonNegativeNumber)->group(ekf);
  app.add_option("--lost-sigma", c.lost_sigma_m, "EKF: position sigma above which the estimate is flagged degenerate (m)")->capture_default_str()->check(CLI::PositiveNumber)->group(ekf);

  const char* filter = "Filter: augmented MCL, likelihood field (--filter mcl)";
  app.add_option("--particles", c.particles, "particle count (at most 20000)")
      ->capture_default_str()->check(CLI::Range(1u, kMaxParticles))->group(filter);
  app.add_option("--seed", c.seed, "random seed (the run is a function of the seed and the inputs)")->capture_default_str()->group(filter);
  app.add_option("--beam-stride", c.beam_stride, "use every n-th beam of a scan")
      ->capture_default_str()->check(CLI::Range(1, 1000))->group(filter);
  app.add_option("--z-hit", c.field.z_hit, "likelihood field: weight of the hit term")->capture_default_str()->group(filter);
  app.add_option("--z-max", c.field.z_max, "likelihood field: weight of max-range readings")->capture_default_str()->group(filter);
  app.add_option("--z-rand", c.field.z_rand, "likelihood field: weight of random readings")->capture_default_str()->group(filter);
  app.add_option("--sigma-hit", c.field.sigma_hit, "likelihood field: hit spread (m)")->capture_default_str()->group(filter);
  app.add_option("--range-max", c.field.range_max, "likelihood field: the sensor's maximum range (m)")->capture_default_str()->group(filter);
  app.add_option("--max-distance", c.field.max_distance, "likelihood field: distances capped here (m)")->capture_default_str()->group(filter);
  app.add_option("--alpha-slow", c.alpha_slow, "augmented MCL: slow average rate")->capture_default_str()->group(filter);
  app.add_option("--alpha-fast", c.alpha_fast, "augmented MCL: fast average rate")->capture_default_str()->group(filter);
  app.add_option("--cluster-cell", c.cluster_cell_m, "grid of the strongest-cluster estimate (m)")->capture_default_str()->group(filter);
  app.add_flag("!--no-recovery", c.recovery, "no random particles (plain MCL)")->group(filter);

  const char* loop = "Loop rates and input limits";
  app.add_option_function<double>(
         "--predict-hz",
         [&c](double hz) { c.timing.predict_period_ns = static_cast<TimeNs>(std::llround(1.0e9 / hz)); },
         "prediction rate, in input time")
      ->default_str("100")->check(CLI::Range(1.0, 10000.0))->group(loop);
  add_ms(app, "--reorder-window", c.timing.reorder_window_ns, "inputs this late are still applied in stamp order", loop);
  add_ms(app, "--encoder-timeout", c.timing.encoder_timeout_ns, "encoders stale after", loop);
  add_ms(app, "--steering-timeout", c.timing.steering_timeout_ns, "steering stale after", loop);
  add_ms(app, "--scan-timeout", c.timing.scan_timeout_ns, "scans stale after", loop);
  add_ms(app, "--landmark-timeout", c.timing.landmark_timeout_ns, "landmark sightings stale after (EKF)", loop);
  add_ms(app, "--step-deadline", c.timing.step_deadline_ns, "budget of one predict or correct step (live; replay does not time)", loop);
  add_ms(app, "--max-age", c.limits.wheels.timing.max_age_ns, "live: inputs older than this on arrival are stale", loop);
  add_ms(app, "--max-future", c.limits.wheels.timing.max_future_ns, "live: inputs stamped further ahead of the clock are rejected", loop);
  app.add_option("--max-steer", c.limits.steering.max_angle_rad, "steering samples beyond this are rejected (rad)")->capture_default_str()->group(loop);
  app.add_option("--max-ticks-per-s", c.limits.wheels.max_ticks_per_s, "encoder rate limit (ticks/s)")->capture_default_str()->group(loop);
  app.add_option("--min-valid-beams", c.limits.scan.min_valid_beams, "scans with fewer usable beams are rejected")->capture_default_str()->group(loop);
  app.add_option("--wheel-counter-bits", c.lcm_wheel_counter_bits,
                 "width of the encoder counters in LCM messages (CAN frames carry 16)")
      ->capture_default_str()->check(CLI::Range(1u, 32u))->group(loop);
}

void finish_options(const CLI::App& app, NodeConfig& c) {
  c.limits.steering.timing = c.limits.wheels.timing;
  c.limits.scan.timing = c.limits.wheels.timing;
  c.limits.landmarks.timing = c.limits.wheels.timing;
  c.limits.landmarks.max_id = kMaxLandmarks - 1;
  c.limits.scan.max_beams = static_cast<std::size_t>(kMaxBeams);
  c.lcm_input = app.count("--lcm") > 0;
  if (c.replay_path.empty() && c.can_interface.empty() && !c.lcm_input)
    throw CLI::ValidationError("inputs", "give --can IFACE, --lcm URL, or --replay LOG");
  if (!c.replay_path.empty() && (!c.can_interface.empty() || c.lcm_input))
    throw CLI::ValidationError("--replay", "replays alone: no --can or --lcm with it");
  if (!c.replay_path.empty() && c.out_path.empty()) throw CLI::ValidationError("--replay", "needs --out OUT.lcmlog");
  if (c.can_out && c.can_interface.empty()) throw CLI::ValidationError("--can-out", "needs --can IFACE");
  if (c.global == c.initial_pose_given)
    throw CLI::ValidationError("initial belief", "give exactly one of --initial-pose x,y,theta and --global");
  if (c.filter == est::loop::Filter::ekf && c.global)
    throw CLI::ValidationError("--global", "global localization needs --filter mcl (the EKF tracks from --initial-pose)");
  if (c.lcm_out_url.empty()) c.lcm_out_url = c.lcm_url;
}

}  // namespace hal::node

// estimator_node's options (node/node_config.hpp).
#include "node/node_config.hpp"

#include "node/estimator_pipeline.hpp"
#include "node/view_feed.hpp"

#include <CLI/CLI.hpp>
#include <cmath>
#include <map>
#include <string>
#include <vector>

namespace node {

using hal::TimeNs;

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

// A comma-separated list of exactly n floats into out[0..n).
void add_floats(CLI::App& app, const std::string& name, float* out, std::size_t n, const std::string& help,
                const char* group) {
  std::string def;
  for (std::size_t i = 0; i < n; ++i) def += (i ? "," : "") + trimmed(static_cast<double>(out[i]));
  app.add_option_function<std::vector<float>>(
         name, [out, n](const std::vector<float>& v) { for (std::size_t i = 0; i < n; ++i) out[i] = v[i]; }, help)
      ->delimiter(',')->expected(static_cast<int>(n))->default_str(def)->group(group);
}

template <typename Enum>
void add_choice(CLI::App& app, const std::string& name, Enum& target, std::vector<std::string> names,
                const std::string& help, const char* group) {
  const std::string def = to_string(target);
  app.add_option_function<std::string>(
         name, [&target](const std::string& v) { parse(v, target); }, help)
      ->check(CLI::IsMember(names))->default_str(def)->group(group);
}

}  // namespace

void add_options(CLI::App& app, NodeConfig& c) {
  app.get_formatter()->column_width(34);
  EstimatorSpec& e = c.spec;
  MotionSpec& m = e.motion;

  const char* io = "Inputs and outputs";
  app.add_option("--can", c.can_interface,
                 "SocketCAN interface to read sensor frames from (hal/can/estimator.dbc: WHEEL_TICKS, "
                 "WHEEL_TICKS_EXT, STEERING, TWIST, ODOMETRY, SCAN_*); inputs are stamped with the kernel's receive "
                 "time")
      ->group(io);
  app.add_option("--can-rcvbuf", c.can_receive_buffer_bytes,
                 "the CAN socket's receive queue, bytes (~1 KB a frame; a 360-beam scan is 122 frames), so that a "
                 "slow step does not cost frames (counted as rx_dropped); 0: the kernel's default")
      ->capture_default_str()->check(CLI::NonNegativeNumber)->group(io);
  app.add_option("--lcm", c.lcm_url,
                 "LCM URL to read sensor messages from (est_lcm encoder_ticks_t, steering_t, twist_t, odometry_t, "
                 "range_scan_t, landmark_sighting_t; stamped by the sender, see --stamps) and to publish on")
      ->group(io);
  app.add_option_function<std::string>(
         "--stamps", [&c](const std::string& v) { c.align_stamps = v == "align"; },
         "live LCM inputs: align (the sender's stamps mapped onto this node's clock by one offset measured at the "
         "first message, as when lcm-logplayer plays a log at 1x; stamps already on this clock are kept; estimates "
         "out in the sender's time, as --replay gives them, unless --can inputs share the node clock) or sender "
         "(judged against this node's clock as sent)")
      ->check(CLI::IsMember({"align", "sender"}))->default_str("align")->group(io);
  app.add_option("--live-speed", c.live_speed,
                 "live LCM inputs played at this many times real time (lcm-logplayer --speed S): the node's clock "
                 "runs S times faster than the wall clock, so the HAL's staleness checks, the stamp alignment and the "
                 "loop's deadlines hold in the stream's time; what the node cannot keep up with is dropped and counted")
      ->check(CLI::Range(0.01, 1000.0))->default_val(1.0)->group(io);
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
  app.add_option("--replay-can", c.replay_can_path,
                 "lockstep replay of a candump log (candump -l format) of estimator.dbc frames, each stamped with "
                 "its line's receive time, as the board image replays it")
      ->group(io)->check(CLI::ExistingFile);
  app.add_option("--out", c.out_path,
                 "write the estimates (and status) to this LCM log; event times are the estimates' stamps")
      ->group(io);
  app.add_option("--out-can", c.out_can_path,
                 "write the estimate frames (POSE_ESTIMATE, POSE_SIGMA, POSE_CORRELATION, ESTIMATOR_STATUS) to this "
                 "candump log, stamped with the estimates' stamps")
      ->group(io);
  app.add_option("--record-inputs", c.record_path,
                 "write every input handed to the filter loop, in that order and with the stamp the loop used (in the "
                 "sender's time when --stamps align moved it, as the estimates), to this LCM log (replayable with "
                 "--replay --wheel-counter-bits 32)")
      ->group(io);
  app.add_option("--ch-wheel-ticks", c.channels.wheel_ticks, "LCM channel: encoder ticks in")->capture_default_str()->group(io);
  app.add_option("--ch-steering", c.channels.steering, "LCM channel: steering in")->capture_default_str()->group(io);
  app.add_option("--ch-twist", c.channels.twist, "LCM channel: twists in (twist_t)")->capture_default_str()->group(io);
  app.add_option("--ch-odometry", c.channels.odometry, "LCM channel: odometry poses in (odometry_t)")->capture_default_str()->group(io);
  app.add_option("--ch-scan", c.channels.range_scan, "LCM channel: range scans in")->capture_default_str()->group(io);
  app.add_option("--ch-landmarks", c.channels.landmarks, "LCM channel: landmark sightings in (landmark_sighting_t)")->capture_default_str()->group(io);
  app.add_option("--ch-pose", c.channels.pose, "LCM channel: pose estimates out")->capture_default_str()->group(io);
  app.add_option("--ch-status", c.channels.status, "LCM channel: status out")->capture_default_str()->group(io);
  app.add_option("--ch-slam-map", c.channels.slam_map, "LCM channel: EKF-SLAM's map and association counters out (slam_map_t)")->capture_default_str()->group(io);
  app.add_option("--status-hz", c.status_hz, "status_t rate, in input time (0: only at the end)")
      ->capture_default_str()->check(CLI::NonNegativeNumber)->group(io);
  app.add_option("--duration", c.duration_s, "live: stop after this many seconds (0: run until SIGINT/SIGTERM)")
      ->capture_default_str()->check(CLI::NonNegativeNumber)->group(io);
  app.add_flag("--quiet", c.quiet, "no summary on stderr at the end")->group(io);

  add_view_options(app, c.view_port, c.view_wait, c.replay_speed,
                   "the map, truth, particles, estimate with its 2-sigma ellipse, status");

  const char* robot = "Robot: the motion model and its inputs";
  add_choice(app, "--model", e.model, {"velocity", "odometry", "bicycle", "diff-drive", "omni", "holonomic"},
             "motion model: velocity (twist v, w), odometry (odometry poses, Thrun table 5.6), bicycle (wheel 0 "
             "the front wheel's traction encoder, plus steering), diff-drive (wheels 0 and 1 left and right), omni "
             "(twist v1, v2, w, or 3-4 wheel encoders: --omni-wheels), holonomic (twist u_x, u_y; never turns)",
             robot);
  app.add_option("--wheel-radius", m.diff_drive.wheel_radius, "diff-drive: wheel radius (m)")->capture_default_str()->group(robot);
  app.add_option("--track-width", m.diff_drive.track_width, "diff-drive: distance between the wheels (m)")->capture_default_str()->group(robot);
  app.add_option("--ticks-per-rev", m.diff_drive.ticks_per_rev, "diff-drive: encoder ticks per wheel revolution")->capture_default_str()->group(robot);
  app.add_option("--travel-sigma-per-m", m.diff_drive.travel_sigma_per_m, "diff-drive: wheel travel noise per metre travelled")->capture_default_str()->group(robot);
  app.add_option("--travel-sigma-floor", m.diff_drive.travel_sigma_floor, "diff-drive: wheel travel noise floor (m)")->capture_default_str()->group(robot);
  app.add_option("--rot-sigma", m.diff_drive.final_rot_sigma, "diff-drive: final rotation noise (rad)")->capture_default_str()->group(robot);
  app.add_option("--frame-length", m.bicycle.frame_length, "bicycle: rear to front wheel (m)")->capture_default_str()->group(robot);
  app.add_option("--steer-max", m.bicycle.steer_max, "bicycle: steering stop (rad)")->capture_default_str()->group(robot);
  app.add_option("--steer-sigma", m.bicycle.steer_sigma, "bicycle: steering noise (rad)")->capture_default_str()->group(robot);
  app.add_option("--speed-var-per-speed", m.bicycle.speed_var_per_speed, "bicycle: speed variance per speed (m/s)")->capture_default_str()->group(robot);
  app.add_option("--bicycle-rot-sigma", m.bicycle.final_rot_sigma, "bicycle: final rotation noise (rad)")->capture_default_str()->group(robot);
  app.add_option("--metres-per-tick", m.bicycle_control.metres_per_tick, "bicycle: front wheel travel per encoder tick (m)")->capture_default_str()->group(robot);
  app.add_flag("!--no-steering-sensor", m.bicycle_control.steering_fitted,
               "bicycle: no steering sensor is fitted (steering inputs are unused; the prediction takes the "
               "steering as unknown, --unknown-steer-sigma)")->group(robot);
  app.add_option("--unknown-steer-sigma", m.bicycle_control.unknown_steer_sigma,
                 "bicycle: steering noise while the steering is unknown (rad; 0: --steer-sigma)")->capture_default_str()->group(robot);
  add_floats(app, "--velocity-noise", &m.velocity.a1, 6,
             "velocity: a1..a6 of Thrun table 5.3 (variances: v a1 v^2 + a2 w^2, w a3 v^2 + a4 w^2, final turn a5 v^2 "
             "+ a6 w^2) per prediction", robot);
  add_floats(app, "--odometry-noise", &m.odometry.a1, 4,
             "odometry: a1..a4 of Thrun table 5.6 (variances of rot1/rot2, trans) per prediction", robot);
  add_floats(app, "--omni-noise", m.omni.alpha, 9,
             "omni: a1..a9 (std of v1 = a1|v1| + a2|v2| + a3|w|, v2: a4..a6, w: a7..a9) per prediction", robot);
  app.add_option_function<std::string>(
         "--omni-wheels",
         [&m](const std::string& kind) {
           using Source = est::loop::ControlAssembler<est::OmniMotionModel>::Source;
           m.omni_control.source = kind == "twist" ? Source::twist : Source::wheels;
           float rows[4][3] = {};
           const float r = m.omni_control.wheels.metres_per_tick;  // keep the configured resolution
           const float mpt = r > 0.0f ? r : 0.0005f;
           if (kind == "mecanum") {
             est::mecanum_wheel_rows(0.2f, 0.2f, rows);
             est::configure_omni_wheels(m.omni_control.wheels, rows, 4, mpt);
           } else if (kind == "kiwi3" || kind == "kiwi4") {
             const int n = kind == "kiwi3" ? 3 : 4;
             float beta[4];
             for (int i = 0; i < n; ++i) beta[i] = 6.2831853f * static_cast<float>(i) / static_cast<float>(n);
             est::omni_wheel_rows(beta, n, 0.2f, rows);
             est::configure_omni_wheels(m.omni_control.wheels, rows, n, mpt);
           }
         },
         "omni: the control's source: twist (TWIST / twist_t), or the encoders of a base: mecanum (4 wheels, X, "
         "0.2 m half wheelbase and half track), kiwi3 or kiwi4 (omni wheels on a 0.2 m circle); 0.5 mm per tick")
      ->check(CLI::IsMember({"twist", "mecanum", "kiwi3", "kiwi4"}))->default_str("twist")->group(robot);
  app.add_option_function<float>(
         "--holonomic-noise", [&m](float q) { m.holonomic_control.noise_per_s = Eigen::Matrix2f::Identity() * q; },
         "holonomic: displacement noise per axis and second (m^2/s)")
      ->default_str("0")->check(CLI::NonNegativeNumber)->group(robot);
  app.add_option("--holonomic-heading-sigma", m.holonomic_control.heading_sigma_per_sqrt_s,
                 "holonomic: heading drift (rad per sqrt(s); 0: a constant heading)")->capture_default_str()->group(robot);

  const char* sensor = "Rangefinder (MCL)";
  add_choice(app, "--sensor-model", e.range_model, {"likelihood-field", "beam", "steered"},
             "likelihood-field (Thrun table 6.3); beam (table 6.1, z* from a heading range table, --heading-bins); "
             "steered (a rangefinder on the bicycle's handlebar: the likelihood field marginalized over "
             "--handle-positions handle positions, --handlebar)", sensor);
  add_pose(app, "--sensor-mount", e.sensor_mount, nullptr, "rangefinder pose on the robot: x,y,theta (m, m, rad); default 0,0,0", sensor);
  app.add_option("--z-hit", e.field.z_hit, "likelihood field: weight of the hit term")->capture_default_str()->group(sensor);
  app.add_option("--z-max", e.field.z_max, "likelihood field: weight of max-range readings")->capture_default_str()->group(sensor);
  app.add_option("--z-rand", e.field.z_rand, "likelihood field: weight of random readings")->capture_default_str()->group(sensor);
  app.add_option("--sigma-hit", e.field.sigma_hit, "likelihood field: hit spread (m)")->capture_default_str()->group(sensor);
  app.add_option_function<float>(
         "--range-max", [&e](float r) { e.field.range_max = r; e.beam.range_max = r; },
         "the sensor's maximum range (m)")->default_str(trimmed(static_cast<double>(e.field.range_max)))->group(sensor);
  app.add_option("--max-distance", e.field.max_distance, "likelihood field: distances capped here (m)")->capture_default_str()->group(sensor);
  add_floats(app, "--beam-weights", &e.beam.z_hit, 4, "beam model: z_hit,z_short,z_max,z_rand (sum 1)", sensor);
  app.add_option("--beam-sigma-hit", e.beam.sigma_hit, "beam model: hit spread (m)")->capture_default_str()->group(sensor);
  app.add_option("--beam-lambda-short", e.beam.lambda_short, "beam model: rate of short readings (1/m)")->capture_default_str()->group(sensor);
  app.add_option("--heading-bins", e.heading_bins, "beam model: headings of the range table or cone caster (a power of two)")->capture_default_str()->group(sensor);
  add_choice(app, "--beam-cast", e.beam_cast, {"table", "cone"},
             "beam model: z* from the heading range table (approximate: mean error 0.55 m on the Intel map at 64 "
             "headings) or the cone caster (exact: the exact traversal's ranges, est/map/cone_ray_caster.hpp)", sensor);
  add_floats(app, "--handlebar", &e.steered.mount.pivot_x, 2,
             "steered: the steering axis in the robot frame pivot_x,pivot_y (m)", sensor);
  add_pose(app, "--handlebar-sensor", e.steered.mount.sensor_on_part, nullptr,
           "steered: the sensor's pose on the handlebar x,y,theta (m, m, rad)", sensor);
  app.add_option("--handle-positions", e.steered.positions, "steered: handle positions M across the stops (0: the steering reading taken as exact)")
      ->capture_default_str()->check(CLI::Range(0, 16))->group(sensor);
  app.add_option("--handle-reading-sigma", e.steered.reading_sigma,
                 "steered: how far to trust the steering reading for p(alpha_m | x) (rad)")->capture_default_str()->group(sensor);
  app.add_option("--handle-reading-floor", e.steered.floor,
                 "steered: the least p(alpha_m | reading), how often the reading names a wrong position (lag, bias)")
      ->capture_default_str()->check(CLI::Range(1.0e-6, 0.5))->group(sensor);

  const char* map = "Map and initial belief";
  app.add_option("--map", c.map,
                 "'office' (the simulator's synthetic office, 20 m x 15 m) or a ROS map_server YAML file (PGM image, "
                 "trinary/scale/raw, at most 2048 x 2048 cells)")
      ->capture_default_str()->group(map);
  app.add_option("--clearance", e.clearance_m, "free-space draws keep this far from obstacles (m)")->capture_default_str()->group(map);
  add_pose(app, "--initial-pose", e.initial_pose, nullptr, "tracking: initial pose x,y,theta (m, m, rad)", map);
  app.add_option_function<std::vector<float>>(
         "--initial-sigma",
         [&e](const std::vector<float>& v) {
           e.initial_sigma_xy_m = v[0];
           e.initial_sigma_theta_rad = v[1];
         },
         "tracking: initial spread sigma_xy,sigma_theta (m, rad)")
      ->delimiter(',')->expected(2)->default_str("0.2,0.1")->group(map);
  app.add_flag("--global", e.global, "global localization: particles uniform over the free space")->group(map);

  const char* ekf = "Filter: EKF localization on landmark sightings (--filter ekf)";
  add_choice(app, "--filter", e.filter, {"mcl", "ekf", "ekf-slam"},
             "mcl: augmented Monte Carlo localization on range scans and the occupancy map (tracking or global); "
             "ekf: EKF localization on landmark sightings (range, bearing, signature; known or unknown "
             "correspondence) and a landmark map (tracking from --initial-pose; scans are counted as unused); "
             "ekf-slam: EKF-SLAM on landmark sightings without a map (their ids ignored: gated maximum likelihood, "
             "tentative landmarks; --slam-* options; tracking from --initial-pose, the map's frame); coop-ekf: "
             "one robot's node of a cooperative EKF-SLAM team (its own options: --filter coop-ekf --help)",
             ekf);
  app.add_option("--landmarks", c.landmarks,
                 "landmark map: 'office' (the simulator's office, 16 posts, signatures 1..16) or a CSV file of "
                 "x,y,signature lines (m; '#' comments); a sighting's id is the line index from 0")
      ->capture_default_str()->group(ekf);
  app.add_option("--landmark-sigma-range", e.landmark_noise.sigma_range, "landmark sensor: range noise (m)")->capture_default_str()->check(CLI::PositiveNumber)->group(ekf);
  app.add_option("--landmark-sigma-range-per-m", e.landmark_sigma_range_per_m,
                 "EKF: the range noise grows with the range, as a camera's: sigma_range + this * range (m per m)")
      ->capture_default_str()->check(CLI::NonNegativeNumber)->group(ekf);
  app.add_option("--landmark-sigma-bearing", e.landmark_noise.sigma_bearing, "landmark sensor: bearing noise (rad)")->capture_default_str()->check(CLI::PositiveNumber)->group(ekf);
  app.add_option("--landmark-sigma-signature", e.landmark_noise.sigma_signature,
                 "landmark sensor: signature noise; > 0 makes signatures part of the association (0: not used)")
      ->capture_default_str()->check(CLI::NonNegativeNumber)->group(ekf);
  app.add_option("--landmark-max-range", e.limits.landmarks.max_range_m, "landmark features beyond this are rejected (m)")->capture_default_str()->check(CLI::PositiveNumber)->group(ekf);
  app.add_option_function<std::string>(
         "--landmark-association",
         [&e](const std::string& v) {
           if (v != "sensor" && v != "ml") throw CLI::ValidationError("--landmark-association", "sensor or ml");
           e.landmark_ids = v == "sensor";
         },
         "sensor: a feature's id from the sensor where it gives one (table 7.2), else maximum likelihood (table 7.3); "
         "ml: maximum likelihood for every feature, the sensor's ids ignored")
      ->default_str("sensor")->group(ekf);
  app.add_option("--ambiguity-nats", e.ambiguity_nats,
                 "EKF with maximum likelihood association: refuse a feature whose second-best landmark is within "
                 "this log likelihood of the best (0: take the best whatever the margin)")
      ->capture_default_str()->check(CLI::NonNegativeNumber)->group(ekf);
  app.add_flag("--joint-association", e.joint_association,
               "EKF: features without an id are associated per camera frame (the features sharing a stamp) by joint "
               "compatibility branch and bound instead of one at a time by maximum likelihood")->group(ekf);
  app.add_option("--lone-pairing-sigma", e.lone_pairing_sigma_m,
                 "EKF with --joint-association: a frame that pairs a single feature, with another landmark also in its "
                 "gate, is not fused while the position's deviation is above this (m; 0: always fused)")
      ->capture_default_str()->check(CLI::NonNegativeNumber)->group(ekf);
  app.add_flag("--mcl-landmarks", e.mcl_landmarks,
               "MCL also corrects with landmark sightings on --landmarks (table 6.4 per particle)")->group(ekf);
  app.add_option("--ekf-rot-sigma", e.ekf_rot_sigma, "heading noise added to every EKF prediction (rad)")->capture_default_str()->check(CLI::NonNegativeNumber)->group(ekf);
  app.add_option("--ekf-heading-noise-per-rad", e.ekf_motion_noise.heading_per_rad,
                 "EKF: heading variance added per radian turned (rad^2 / rad), a random walk over the turns")
      ->capture_default_str()->check(CLI::NonNegativeNumber)->group(ekf);
  app.add_option("--ekf-heading-noise-per-m", e.ekf_motion_noise.heading_per_m,
                 "EKF: heading variance added per metre driven (rad^2 / m)")->capture_default_str()->check(CLI::NonNegativeNumber)->group(ekf);
  app.add_option("--ekf-along-noise-per-m", e.ekf_motion_noise.along_per_m,
                 "EKF: along-track position variance added per metre driven (m^2 / m)")->capture_default_str()->check(CLI::NonNegativeNumber)->group(ekf);
  app.add_option("--ekf-cross-noise-per-m", e.ekf_motion_noise.cross_per_m,
                 "EKF: cross-track position variance added per metre driven (m^2 / m)")->capture_default_str()->check(CLI::NonNegativeNumber)->group(ekf);
  app.add_option("--ekf-reopen-after", e.ekf_reopen_after,
                 "EKF: after this many consecutive gate refusals of known-correspondence features the covariance is "
                 "widened by --ekf-reopen-sigma-xy/-theta and the feature fused again (0: never)")->capture_default_str()->group(ekf);
  app.add_option("--ekf-reopen-sigma-xy", e.ekf_reopen_sigma_xy, "EKF: position deviation added when the gate re-opens (m; 0: the heading's alone)")->capture_default_str()->check(CLI::NonNegativeNumber)->group(ekf);
  app.add_option("--ekf-reopen-sigma-theta", e.ekf_reopen_sigma_theta, "EKF: heading deviation added when the gate re-opens (rad)")->capture_default_str()->check(CLI::PositiveNumber)->group(ekf);
  app.add_option("--lost-sigma", e.lost_sigma_m, "EKF: position sigma above which the estimate is flagged degenerate (m)")->capture_default_str()->check(CLI::PositiveNumber)->group(ekf);

  const char* slam = "Filter: EKF-SLAM (--filter ekf-slam; also --landmark-sigma-*, --ekf-rot-sigma, --lost-sigma)";
  app.add_option("--slam-gate-accept", e.slam_gate_accept,
                 "a feature is fused with the most likely landmark under this Mahalanobis distance^2")
      ->capture_default_str()->check(CLI::PositiveNumber)->group(slam);
  app.add_option("--slam-gate-new", e.slam_gate_new,
                 "a feature starts a new landmark above this Mahalanobis distance^2 to every landmark (discarded "
                 "between the gates)")->capture_default_str()->check(CLI::PositiveNumber)->group(slam);
  app.add_option("--slam-max-range", e.slam_max_range_m, "features farther away are not used (m)")
      ->capture_default_str()->check(CLI::PositiveNumber)->group(slam);
  app.add_option("--slam-search-radius", e.slam_search_radius_m,
                 "landmarks farther than this from where a feature puts it are not candidates (m)")
      ->capture_default_str()->check(CLI::PositiveNumber)->group(slam);
  app.add_option("--slam-confirm", e.slam_confirm,
                 "sightings in different frames before a new landmark enters the map (1: at once)")
      ->capture_default_str()->check(CLI::Range(1, 100))->group(slam);
  app.add_option("--slam-candidate-radius", e.slam_candidate_radius_m,
                 "a tentative landmark's sightings agree within this (m)")
      ->capture_default_str()->check(CLI::PositiveNumber)->group(slam);
  app.add_option("--slam-candidate-frames", e.slam_candidate_frames,
                 "a tentative landmark unseen for this many frames is forgotten")
      ->capture_default_str()->check(CLI::Range(1u, 1000000u))->group(slam);
  app.add_option("--slam-noise-step", e.slam_noise_step_s,
                 "bicycle: its per-step noise (--steer-sigma, --speed-var-per-speed, --bicycle-rot-sigma) is for steps "
                 "this long, scaled to each prediction as a white noise (s; 0: per prediction as given)")
      ->capture_default_str()->check(CLI::NonNegativeNumber)->group(slam);

  const char* filter = "Filter: augmented MCL (--filter mcl)";
  app.add_option("--particles", e.particles, "particle count (at most 20000)")
      ->capture_default_str()->check(CLI::Range(1u, kMaxParticles))->group(filter);
  app.add_option("--seed", e.seed, "random seed (the run is a function of the seed and the inputs)")->capture_default_str()->group(filter);
  app.add_option("--beam-stride", e.beam_stride, "use every n-th beam of a scan")
      ->capture_default_str()->check(CLI::Range(1, 1000))->group(filter);
  app.add_option("--alpha-slow", e.mcl.alpha_slow, "augmented MCL: slow average rate")->capture_default_str()->group(filter);
  app.add_option("--alpha-fast", e.mcl.alpha_fast, "augmented MCL: fast average rate")->capture_default_str()->group(filter);
  app.add_option("--max-injection", e.mcl.max_injection_fraction, "augmented MCL: at most this share injected")->capture_default_str()->group(filter);
  app.add_flag("--kld", e.mcl.kld, "adapt the particle count by KLD sampling (up to --particles' capacity)")->group(filter);
  app.add_option("--kld-min", e.mcl.kld_config.n_min, "KLD sampling: the fewest particles")->capture_default_str()->group(filter);
  app.add_option("--cluster-cell", e.cluster_cell_m, "grid of the strongest-cluster estimate (m)")->capture_default_str()->group(filter);
  app.add_flag("!--no-recovery", e.mcl.recovery, "no random particles (plain MCL)")->group(filter);

  const char* loop = "Loop rates and input limits";
  app.add_option_function<double>(
         "--predict-hz",
         [&e](double hz) { e.timing.predict_period_ns = static_cast<TimeNs>(std::llround(1.0e9 / hz)); },
         "prediction rate, in input time")
      ->default_str("100")->check(CLI::Range(1.0, 10000.0))->group(loop);
  add_ms(app, "--reorder-window", e.timing.reorder_window_ns, "inputs this late are still applied in stamp order", loop);
  using est::loop::InputKind;
  add_ms(app, "--encoder-timeout", e.timing.staleness[InputKind::wheel_ticks], "encoders stale after", loop);
  add_ms(app, "--steering-timeout", e.timing.staleness[InputKind::steering], "steering stale after", loop);
  add_ms(app, "--twist-timeout", e.timing.staleness[InputKind::twist], "twists stale after", loop);
  add_ms(app, "--odometry-timeout", e.timing.staleness[InputKind::odometry], "odometry stale after", loop);
  add_ms(app, "--scan-timeout", e.timing.staleness[InputKind::scan], "scans stale after", loop);
  add_ms(app, "--landmark-timeout", e.timing.staleness[InputKind::landmark], "landmark sightings stale after (EKF)", loop);
  add_ms(app, "--step-deadline", e.timing.step_deadline_ns, "budget of one predict or correct step (live; replay does not time)", loop);
  add_ms(app, "--max-age", e.limits.wheels.timing.max_age_ns, "live: inputs older than this on arrival are stale", loop);
  add_ms(app, "--max-future", e.limits.wheels.timing.max_future_ns, "live: inputs stamped further ahead of the clock are rejected", loop);
  app.add_option("--max-steer", e.limits.steering.max_angle_rad, "steering samples beyond this are rejected (rad)")->capture_default_str()->group(loop);
  app.add_option("--wheel-count", e.limits.wheels.wheel_count, "encoders per sample (2 for a diff drive or a bicycle, 3-4 for an omni base)")->capture_default_str()->group(loop);
  app.add_option("--max-ticks-per-s", e.limits.wheels.max_ticks_per_s, "encoder rate limit (ticks/s)")->capture_default_str()->group(loop);
  app.add_option("--max-speed", e.limits.twist.max_speed_mps, "twists and odometry faster than this are rejected (m/s)")->capture_default_str()->group(loop);
  app.add_option("--max-turn-rate", e.limits.twist.max_turn_rate_rps, "twists and odometry turning faster are rejected (rad/s)")->capture_default_str()->group(loop);
  app.add_option("--min-valid-beams", e.limits.scan.min_valid_beams, "scans with fewer usable beams are rejected")->capture_default_str()->group(loop);
  app.add_option("--wheel-counter-bits", c.lcm_wheel_counter_bits,
                 "width of the encoder counters in LCM messages (CAN frames carry 16)")
      ->capture_default_str()->check(CLI::Range(1u, 32u))->group(loop);
}

void finish_options(const CLI::App& app, NodeConfig& c) {
  EstimatorSpec& e = c.spec;
  e.limits.set_timing(e.limits.wheels.timing);
  e.limits.odometry.max_speed_mps = e.limits.twist.max_speed_mps;
  e.limits.odometry.max_turn_rate_rps = e.limits.twist.max_turn_rate_rps;
  e.limits.landmarks.max_id = kMaxLandmarks - 1;
  e.limits.scan.max_beams = static_cast<std::size_t>(kMaxBeams);
  e.steered.steer_max = e.motion.bicycle.steer_max;
  e.beam.range_max = e.field.range_max;
  c.lcm_input = app.count("--lcm") > 0;
  const bool pose_given = app.count("--initial-pose") > 0;
  const bool replay_lcm = !c.replay_path.empty(), replay_can = !c.replay_can_path.empty();
  if (!c.replay() && c.can_interface.empty() && !c.lcm_input)
    throw CLI::ValidationError("inputs", "give --can IFACE, --lcm URL, --replay LOG or --replay-can CANDUMP");
  if (replay_lcm && replay_can) throw CLI::ValidationError("--replay", "one replay at a time: --replay or --replay-can");
  if (c.replay() && (!c.can_interface.empty() || c.lcm_input))
    throw CLI::ValidationError("--replay", "replays alone: no --can or --lcm with it");
  if (c.replay() && c.out_path.empty() && c.out_can_path.empty() && c.view_port == 0)
    throw CLI::ValidationError("--replay", "needs --out OUT.lcmlog, --out-can OUT.candump or --view PORT");
  if (c.view_wait && (c.view_port == 0 || !c.replay()))
    throw CLI::ValidationError("--view-wait", "needs --view PORT and a replay");
  if (app.count("--replay-speed") > 0 && !c.replay()) throw CLI::ValidationError("--replay-speed", "needs a replay");
  c.replay_speed = replay_speed_default(c.replay_speed, c.view_port);
  if (c.can_out && c.can_interface.empty()) throw CLI::ValidationError("--can-out", "needs --can IFACE");
  if (app.count("--stamps") > 0 && !c.lcm_input) throw CLI::ValidationError("--stamps", "needs --lcm URL (live)");
  if (app.count("--live-speed") > 0 && (!c.lcm_input || !c.can_interface.empty()))
    throw CLI::ValidationError("--live-speed", "needs --lcm URL and no --can (CAN frames carry the kernel's real time)");
  if (e.global == pose_given)
    throw CLI::ValidationError("initial belief", "give exactly one of --initial-pose x,y,theta and --global");
  if (e.filter != est::loop::Filter::mcl && e.global)
    throw CLI::ValidationError("--global", "global localization needs --filter mcl (the EKF tracks from --initial-pose)");
  if (e.filter == est::loop::Filter::ekf_slam && e.slam_gate_new < e.slam_gate_accept)
    throw CLI::ValidationError("--slam-gate-new", "at least --slam-gate-accept");
  if (e.range_model == RangeModel::steered && e.model != RobotModel::bicycle)
    throw CLI::ValidationError("--sensor-model", "steered: the handlebar is the bicycle's (--model bicycle)");
  // A rangefinder on the handlebar read by a fixed-frame model takes every turn of the handle for a turn of the robot.
  if ((app.count("--handlebar") > 0 || app.count("--handlebar-sensor") > 0) && e.range_model != RangeModel::steered)
    throw CLI::ValidationError("--handlebar", "mounts the rangefinder on the handlebar: it needs --sensor-model steered");
  if (e.model == RobotModel::omni &&
      e.motion.omni_control.source == est::loop::ControlAssembler<est::OmniMotionModel>::Source::wheels &&
      app.count("--wheel-count") == 0)
    e.limits.wheels.wheel_count = e.motion.omni_control.wheels.count;
  if (c.lcm_out_url.empty()) c.lcm_out_url = c.lcm_url;
}

namespace {
std::string f(float v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.9g", static_cast<double>(v));
  return b;
}
std::string list(const float* v, int n) {
  std::string s;
  for (int i = 0; i < n; ++i) s += (i ? "," : "") + f(v[i]);
  return s;
}
std::string pose(const est::Pose2& p) { return f(p.x) + "," + f(p.y) + "," + f(p.theta); }
}  // namespace

std::string command_line(const EstimatorSpec& e, const std::string& map, const std::string& landmarks) {
  const MotionSpec& m = e.motion;
  std::string o = std::string("--model ") + to_string(e.model) + " --filter " + to_string(e.filter);
  switch (e.model) {
    case RobotModel::velocity: o += " --velocity-noise " + list(&m.velocity.a1, 6); break;
    case RobotModel::odometry: o += " --odometry-noise " + list(&m.odometry.a1, 4); break;
    case RobotModel::bicycle:
      o += " --frame-length " + f(m.bicycle.frame_length) + " --steer-max " + f(m.bicycle.steer_max) +
           " --steer-sigma " + f(m.bicycle.steer_sigma) + " --speed-var-per-speed " + f(m.bicycle.speed_var_per_speed) +
           " --bicycle-rot-sigma " + f(m.bicycle.final_rot_sigma) + " --metres-per-tick " +
           f(m.bicycle_control.metres_per_tick) + " --unknown-steer-sigma " + f(m.bicycle_control.unknown_steer_sigma);
      if (!m.bicycle_control.steering_fitted) o += " --no-steering-sensor";
      break;
    case RobotModel::diff_drive:
      o += " --wheel-radius " + f(m.diff_drive.wheel_radius) + " --track-width " + f(m.diff_drive.track_width) +
           " --ticks-per-rev " + std::to_string(m.diff_drive.ticks_per_rev) + " --travel-sigma-per-m " +
           f(m.diff_drive.travel_sigma_per_m) + " --travel-sigma-floor " + f(m.diff_drive.travel_sigma_floor) +
           " --rot-sigma " + f(m.diff_drive.final_rot_sigma);
      break;
    case RobotModel::omni:
      o += " --omni-noise " + list(m.omni.alpha, 9);
      if (m.omni_control.source == est::loop::ControlAssembler<est::OmniMotionModel>::Source::wheels)
        o += " --omni-wheels mecanum";  // the simulator's base (node_config.cpp: 0.2 m, 0.5 mm per tick)
      break;
    case RobotModel::holonomic:
      o += " --holonomic-noise " + f(m.holonomic_control.noise_per_s(0, 0)) + " --holonomic-heading-sigma " +
           f(m.holonomic_control.heading_sigma_per_sqrt_s);
      break;
  }
  o += " --wheel-count " + std::to_string(e.limits.wheels.wheel_count) + " --max-ticks-per-s " +
       std::to_string(e.limits.wheels.max_ticks_per_s) + " --max-steer " + f(e.limits.steering.max_angle_rad) +
       " --max-speed " + f(e.limits.twist.max_speed_mps) + " --max-turn-rate " + f(e.limits.twist.max_turn_rate_rps);
  if (e.filter == est::loop::Filter::ekf_slam) {
    o += " --landmark-sigma-range " + f(e.landmark_noise.sigma_range) + " --landmark-sigma-bearing " +
         f(e.landmark_noise.sigma_bearing) + " --landmark-max-range " + f(e.limits.landmarks.max_range_m) +
         " --slam-gate-accept " + f(e.slam_gate_accept) + " --slam-gate-new " + f(e.slam_gate_new) +
         " --slam-max-range " + f(e.slam_max_range_m) + " --slam-search-radius " + f(e.slam_search_radius_m) +
         " --slam-confirm " + std::to_string(e.slam_confirm) + " --slam-candidate-radius " +
         f(e.slam_candidate_radius_m) + " --slam-candidate-frames " + std::to_string(e.slam_candidate_frames) +
         " --slam-noise-step " + f(e.slam_noise_step_s);
  } else if (e.filter == est::loop::Filter::ekf || e.mcl_landmarks) {
    o += " --landmarks " + landmarks + " --landmark-sigma-range " + f(e.landmark_noise.sigma_range) +
         " --landmark-sigma-bearing " + f(e.landmark_noise.sigma_bearing) + " --landmark-sigma-signature " +
         f(e.landmark_noise.sigma_signature) + " --landmark-max-range " + f(e.limits.landmarks.max_range_m);
    if (!e.landmark_ids) o += " --landmark-association ml";
  } else {
    // The HAL's gate judges landmark sightings whatever the filter does with them (MCL drops them): its reach too.
    o += " --landmark-max-range " + f(e.limits.landmarks.max_range_m);
  }
  if (e.filter == est::loop::Filter::ekf && e.ambiguity_nats > 0.0f) o += " --ambiguity-nats " + f(e.ambiguity_nats);
  if (e.filter == est::loop::Filter::ekf && e.joint_association) o += " --joint-association";
  if (e.filter == est::loop::Filter::ekf && e.joint_association && e.lone_pairing_sigma_m > 0.0f)
    o += " --lone-pairing-sigma " + f(e.lone_pairing_sigma_m);
  if (e.filter == est::loop::Filter::ekf && e.landmark_sigma_range_per_m > 0.0f)
    o += " --landmark-sigma-range-per-m " + f(e.landmark_sigma_range_per_m);
  if (e.filter == est::loop::Filter::ekf || e.filter == est::loop::Filter::ekf_slam) {
    o += " --ekf-rot-sigma " + f(e.ekf_rot_sigma) + " --lost-sigma " + f(e.lost_sigma_m);
    const est::MotionProportionalNoise& q = e.ekf_motion_noise;
    if (q.heading_per_rad > 0.0f) o += " --ekf-heading-noise-per-rad " + f(q.heading_per_rad);
    if (q.heading_per_m > 0.0f) o += " --ekf-heading-noise-per-m " + f(q.heading_per_m);
    if (q.along_per_m > 0.0f) o += " --ekf-along-noise-per-m " + f(q.along_per_m);
    if (q.cross_per_m > 0.0f) o += " --ekf-cross-noise-per-m " + f(q.cross_per_m);
    if (e.ekf_reopen_after > 0)
      o += " --ekf-reopen-after " + std::to_string(e.ekf_reopen_after) + " --ekf-reopen-sigma-xy " +
           f(e.ekf_reopen_sigma_xy) + " --ekf-reopen-sigma-theta " + f(e.ekf_reopen_sigma_theta);
  } else {
    if (e.mcl_landmarks) o += " --mcl-landmarks";
    o += " --map " + map + " --sensor-model " + to_string(e.range_model) + " --sensor-mount " + pose(e.sensor_mount) +
         " --range-max " + f(e.field.range_max) + " --z-hit " + f(e.field.z_hit) + " --z-max " + f(e.field.z_max) +
         " --z-rand " + f(e.field.z_rand) + " --sigma-hit " + f(e.field.sigma_hit) + " --max-distance " +
         f(e.field.max_distance) + " --particles " + std::to_string(e.particles) + " --seed " +
         std::to_string(e.seed) + " --beam-stride " + std::to_string(e.beam_stride) + " --alpha-slow " +
         f(e.mcl.alpha_slow) + " --alpha-fast " + f(e.mcl.alpha_fast) + " --max-injection " +
         f(e.mcl.max_injection_fraction) + " --clearance " + f(e.clearance_m) + " --cluster-cell " +
         f(e.cluster_cell_m) + " --kld-min " + std::to_string(e.mcl.kld_config.n_min);
    if (e.mcl.kld) o += " --kld";
    if (!e.mcl.recovery) o += " --no-recovery";
    if (e.range_model == RangeModel::beam)
      o += " --beam-cast " + std::string(to_string(e.beam_cast)) + " --heading-bins " + std::to_string(e.heading_bins);
    if (e.range_model == RangeModel::steered)
      o += " --handlebar " + f(e.steered.mount.pivot_x) + "," + f(e.steered.mount.pivot_y) + " --handlebar-sensor " +
           pose(e.steered.mount.sensor_on_part) + " --handle-positions " + std::to_string(e.steered.positions) +
           " --handle-reading-sigma " + f(e.steered.reading_sigma) + " --handle-reading-floor " + f(e.steered.floor);
  }
  if (e.global)
    o += " --global";
  else
    o += " --initial-pose " + pose(e.initial_pose) + " --initial-sigma " + f(e.initial_sigma_xy_m) + "," +
         f(e.initial_sigma_theta_rad);
  return o;
}

}  // namespace node

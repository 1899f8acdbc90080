// The simulate and record subcommands: one scenario (world, robot, sensors, faults), run in process through the HAL
// and the firmware's filter loop, or written to an LCM log.
#include <CLI/CLI.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>

#include "sim/commands.hpp"
#include "sim/record.hpp"
#include "sim/scenario.hpp"
#include "sim/scenario_file.hpp"
#include "sim/scenario_run.hpp"
#include "sim/simulate.hpp"
#include "team/team_scenarios.hpp"

namespace sim {
namespace {

struct ScenarioOptions {
  ScenarioConfig config;
  std::string robot = "bicycle";
  std::string route;
  std::string plan = "default";
  std::vector<std::string> fault_overrides;
  double range_sigma = 0.02, p_rand = 0.01, p_short = 0.01;
  std::string landmark_ids = "known";
};

std::string fault_help() {
  std::ostringstream s;
  s << "Fault classes for --fault KEY=COUNT (and the counter that must show each one):\n";
  for (const FaultClassInfo& f : fault_catalogue())
    s << "  " << f.key << std::string(f.key.size() < 27 ? 27 - f.key.size() : 1, ' ') << f.what << "  [" << f.expected
      << "]\n";
  s << "Events: --kidnap-at (the robot is carried 3 or more route segments ahead, at least 3 m where the route\n"
       "allows), --burst-at/--burst-ms (every stream silent: a bus outage), --slip-events (the encoders count --slip-factor more for --slip-duration).\n"
       "The landmark classes need a world with landmarks (the synthetic office's 16 posts; a ROS map has none).\n";
  return s.str();
}

void add_scenario_options(CLI::App* c, ScenarioOptions& o) {
  ScenarioConfig& s = o.config;
  c->add_option("--map", s.map_yaml, "ROS map_server YAML (default: the synthetic office, 20 m x 15 m)");
  c->add_option("--landmarks", s.landmarks_csv,
                "landmarks with signatures, 'x,y,signature' per line (m), in place of the world's own (the office's 16 "
                "posts; a ROS map has none)");
  c->add_option("--route", o.route,
                "waypoints 'x,y;x,y;...' in the map frame, visited in a loop (required with --map; default: the "
                "office's 24.7 m route); 'x,y,speed' drives the segment from that waypoint at speed m/s");
  c->add_option("--robot", o.robot,
                "the robot, one per motion model: bicycle (front-wheel referenced, traction encoder + steering), "
                "diff-drive (two wheel encoders), velocity (a unicycle sending its commanded twist v, w), odometry (a "
                "diff-drive base sending the pose it integrates), omni (a mecanum base moving sideways, four wheel "
                "encoders), holonomic (x and y driven independently, never turning, sending its twist u_x, u_y)")
      ->check(CLI::IsMember({"bicycle", "diff-drive", "velocity", "odometry", "omni", "holonomic"}))
      ->capture_default_str();
  c->add_option("--duration", s.duration_s, "simulated time, s")->capture_default_str();
  c->add_option("--speed", s.speed_mps, "cruise speed, m/s")->capture_default_str();
  c->add_option("--start-segment", s.start_segment, "the run starts at the beginning of this route segment")
      ->capture_default_str();
  c->add_option("--seed", s.seed, "seed of every random draw (same seed: identical outputs)")->capture_default_str();
  c->add_option("--encoder-hz", s.encoder_hz, "encoder sample rate (divides 100)")->capture_default_str();
  c->add_option("--steering-hz", s.steering_hz, "steering sample rate (bicycle)")->capture_default_str();
  c->add_option("--twist-hz", s.twist_hz, "twist rate (velocity and holonomic robots)")->capture_default_str();
  c->add_option("--odometry-hz", s.odometry_hz, "odometry pose rate (odometry base)")->capture_default_str();
  c->add_option("--scan-hz", s.scan_hz, "rangefinder scan rate")->capture_default_str();
  c->add_option("--beams", s.beams, "beams per scan")->capture_default_str();
  c->add_option("--fov-deg", s.fov_deg, "field of view, deg (360: a full turn, beams at 360/beams deg)")
      ->capture_default_str();
  c->add_option("--range-max", s.range_max_m, "maximum range, m (no return reads range_max)")->capture_default_str();
  c->add_option("--range-sigma", o.range_sigma, "beam model: sigma of a hit, m")->capture_default_str();
  c->add_option("--p-rand", o.p_rand, "beam model: probability of a random reading")->capture_default_str();
  c->add_option("--p-short", o.p_short, "beam model: probability of a short reading (unmapped obstacle)")
      ->capture_default_str();
  c->add_option("--encoder-scale-error", s.encoder_scale_error, "relative error of the counted wheel travel")
      ->capture_default_str();
  c->add_option("--encoder-noise", s.encoder_noise, "relative noise of each step's counted travel")
      ->capture_default_str();
  c->add_option("--slip-events", s.slip_events, "wheel-spin episodes")->capture_default_str();
  c->add_option("--slip-duration", s.slip_duration_s, "length of each, s")->capture_default_str();
  c->add_option("--slip-factor", s.slip_factor, "extra travel counted while slipping")->capture_default_str();
  c->add_option("--steering-sigma-deg", s.steering_sigma_deg, "steering sensor noise, deg")->capture_default_str();
  c->add_option("--steering-bias-deg", s.steering_bias_deg, "steering sensor bias, deg")->capture_default_str();
  c->add_option_function<std::string>(
       "--steering-sensor", [&s](const std::string& v) { s.steering_sensor = v == "present"; },
       "bicycle: present, or absent (no steering stream; the filter takes the steering as unknown)")
      ->check(CLI::IsMember({"present", "absent"}))->default_str("present");
  c->add_option("--handle-detents", s.handle_detents,
                "bicycle: the handlebar has this many positions from stop to stop and the steering snaps to the "
                "nearest (the exercise's handlebar; 0: continuous)")->capture_default_str();
  c->add_flag("--handlebar", s.handlebar,
              "bicycle: the rangefinder sits on the handlebar (0.15 m ahead of the steering axis at the front wheel), "
              "so its pose follows the true steering angle");
  c->add_option("--landmark-hz", s.landmark_hz,
                "landmark sensor rate (divides 100); sightings of the world's landmarks in range, field of view and "
                "line of sight (the office's 16 posts; a ROS map has none)")
      ->capture_default_str();
  c->add_option("--landmark-range-sigma", s.landmark_sensor.noise.sigma_range, "landmark sensor: range noise, m")
      ->capture_default_str();
  c->add_option("--landmark-bearing-sigma", s.landmark_sensor.noise.sigma_bearing, "landmark sensor: bearing noise, rad")
      ->capture_default_str();
  c->add_option("--landmark-signature-sigma", s.landmark_sensor.noise.sigma_signature,
                "landmark sensor: signature noise (the office's signatures are 1..16)")
      ->capture_default_str();
  c->add_option("--landmark-max-range", s.landmark_sensor.max_range, "landmark sensor: reach, m")->capture_default_str();
  c->add_option("--landmark-ids", o.landmark_ids,
                "known: each feature carries its landmark's map index (coded markers); unknown: id -1, the EKF "
                "associates by maximum likelihood with the signature (Thrun table 7.3)")
      ->check(CLI::IsMember({"known", "unknown"}))
      ->capture_default_str();
  c->add_option("--faults", o.plan,
                "fault plan: default (58 faults for the bicycle, 41 for the diff drive, over 60 s, and 13 in the "
                "landmark sightings when the world has landmarks) or none")
      ->check(CLI::IsMember({"default", "none"}))
      ->capture_default_str();
  c->add_option("--fault", o.fault_overrides, "KEY=COUNT: set one fault class's count (repeatable; see below)");
  c->add_option("--kidnap-at", s.kidnap_at_s,
                "kidnapping time, s (negative: none). With --filter ekf the default is none: the EKF tracks one "
                "Gaussian and cannot recover (given explicitly, the run reports the kidnap phase as not recovered)")
      ->capture_default_str();
  c->add_option("--burst-at", s.burst_at_s, "bus outage time, s (negative: none)")->capture_default_str();
  c->add_option("--burst-ms", s.burst_ms, "bus outage length, ms")->capture_default_str();
  c->footer(fault_help());
}

std::vector<est::sim::Waypoint> parse_route(const std::string& text) {
  std::vector<est::sim::Waypoint> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ';')) {
    if (item.find_first_not_of(" \t") == std::string::npos) continue;
    double x = 0.0, y = 0.0, speed = 0.0;
    char comma = 0, extra = 0;
    std::istringstream is(item);
    bool ok = static_cast<bool>(is >> x >> comma >> y) && comma == ',' && std::isfinite(x) && std::isfinite(y);
    if (ok && (is >> extra)) ok = extra == ',' && (is >> speed) && speed > 0.0 && speed <= 3.0 && !(is >> extra);
    if (!ok) throw CLI::ValidationError("--route", "expected 'x,y[,speed];x,y[,speed];...' (speed in (0, 3] m/s), got '" + item + "'");
    out.push_back({static_cast<float>(x), static_cast<float>(y), static_cast<float>(speed)});
  }
  if (out.size() < 2) throw CLI::ValidationError("--route", "needs at least two waypoints");
  return out;
}

ScenarioConfig finish_scenario(ScenarioOptions& o) {
  ScenarioConfig s = o.config;
  if (!parse(o.robot, s.robot)) throw CLI::ValidationError("--robot", "unknown robot '" + o.robot + "'");
  if (s.handlebar && s.robot != RobotKind::bicycle)
    throw CLI::ValidationError("--handlebar", "the handlebar is the bicycle's (--robot bicycle)");
  if (!o.route.empty()) s.route = parse_route(o.route);
  s.range_noise = {static_cast<float>(o.range_sigma), static_cast<float>(o.p_rand), static_cast<float>(o.p_short)};
  if (!(o.range_sigma > 0.0) || o.p_rand < 0.0 || o.p_short < 0.0 || o.p_rand + o.p_short > 1.0)
    throw CLI::ValidationError("--range-sigma/--p-rand/--p-short", "sigma > 0, probabilities >= 0 summing to <= 1");
  s.landmark_ids_known = o.landmark_ids == "known";
  s.faults = o.plan == "default" ? default_fault_counts(s.robot, has_landmarks(s), s.steering_sensor) : FaultCounts{};
  for (const std::string& f : o.fault_overrides) {
    const std::size_t eq = f.find('=');
    if (eq == std::string::npos) throw CLI::ValidationError("--fault", "expected KEY=COUNT, got '" + f + "'");
    try {
      s.faults[f.substr(0, eq)] = std::stoi(f.substr(eq + 1));
    } catch (const std::exception&) {
      throw CLI::ValidationError("--fault", "expected KEY=COUNT, got '" + f + "'");
    }
  }
  return s;
}

}  // namespace

void add_simulate_command(CLI::App& app) {
  auto opts = std::make_shared<ScenarioOptions>();
  auto filter = std::make_shared<FilterOptions>();
  auto out = std::make_shared<std::string>();
  auto start = std::make_shared<std::string>();
  auto filter_kind = std::make_shared<std::string>("mcl");
  auto no_plots = std::make_shared<bool>(false);
  auto no_kld = std::make_shared<bool>(false);
  auto scenario = std::make_shared<std::string>();
  auto quiet = std::make_shared<bool>(false);
  CLI::App* c = app.add_subcommand(
      "simulate",
      "Host simulation end to end: a robot drives a route in a world; encoder, steering and 2D rangefinder streams "
      "with noise and injected faults go through the HAL gate (hal::ValidatedInputs) and the firmware's filter loop "
      "(est::loop::FilterLoop + MclEstimator on the scans, or EkfEstimator on landmark sightings with --filter ekf) in "
      "process. Writes OUT/trajectory.csv (truth and estimate per output), OUT/faults.csv, OUT/metrics.json (RMSE, "
      "time to converge and to recover, rejects by reason vs injected faults, loop counters) and OUT/trajectory.png, "
      "errors.png, particles.png (MCL; the EKF draws its 2-sigma ellipses on trajectory.png). Same seed: identical "
      "CSV. The same runner as `sim_host run FILE` (a scenario file holds every option below: "
      "sim_host/scenarios/example.toml).");
  c->add_option("--out", *out, "output directory (created)")->required();
  add_scenario_options(c, *opts);
  c->add_option("--filter", *filter_kind,
                "mcl: augmented MCL on the range scans; ekf: EKF localization on the landmark sightings (tracking "
                "from the true start, sigmas 0.2 m and 0.1 rad; needs a world with landmarks)")
      ->check(CLI::IsMember({"mcl", "ekf"}))
      ->capture_default_str();
  c->add_option("--start", *start,
                "global (uniform over the free space; MCL only), tracking (around the true start) or wrong (the "
                "same confident Gaussian around a pose the robot is not at, the route's pose at least 3 m away half the "
                "run later; MCL only); default: global for MCL, tracking for the EKF")
      ->check(CLI::IsMember({"global", "tracking", "wrong"}));
  c->add_option("--particles", filter->particles, "initial particles (at most 20000)")->capture_default_str();
  c->add_option_function<std::string>(
       "--sensor-model", [filter](const std::string& v) { node::parse(v, filter->range_model); },
       "MCL's range model: likelihood-field (Thrun table 6.3), beam (table 6.1, z* from a heading range table), or "
       "steered (the bicycle's handlebar rangefinder, marginalized over --handle-positions; with --handlebar)")
      ->check(CLI::IsMember({"likelihood-field", "beam", "steered"}))->default_str("likelihood-field");
  c->add_option_function<std::string>(
       "--beam-cast", [filter](const std::string& v) { node::parse(v, filter->beam_cast); },
       "beam model: z* from the heading range table (approximate) or the cone caster (exact, "
       "est/map/cone_ray_caster.hpp)")
      ->check(CLI::IsMember({"table", "cone"}))->default_str("table");
  c->add_option("--handle-positions", filter->handle_positions,
                "steered: handle positions across the steering stops (0: the steering reading taken as exact)")
      ->capture_default_str()->check(CLI::Range(0, 16));
  c->add_option("--handle-reading-sigma", filter->handle_reading_sigma_rad,
                "steered: how far the filter trusts the steering reading, rad")->capture_default_str();
  c->add_option("--handle-reading-floor", filter->handle_reading_floor,
                "steered: the least probability the reading leaves a handle position (how often it names a wrong one: "
                "lag, bias)")->capture_default_str()->check(CLI::Range(1.0e-6, 0.5));
  c->add_option("--unknown-steer-sigma", filter->unknown_steer_sigma_rad,
                "bicycle without a steering sensor: the steering noise of the prediction, rad")->capture_default_str();
  c->add_flag("--no-kld", *no_kld, "keep the particle count fixed (default: KLD-sampling adapts it)");
  c->add_option("--kld-min", filter->kld_min, "KLD-sampling's minimum count")->capture_default_str();
  c->add_option("--beam-stride", filter->beam_stride, "the filter uses every n-th beam")->capture_default_str();
  c->add_option("--alpha-slow", filter->alpha_slow, "augmented MCL: decay of the slow likelihood average, per scan")
      ->capture_default_str();
  c->add_option("--alpha-fast", filter->alpha_fast, "augmented MCL: decay of the fast likelihood average, per scan")
      ->capture_default_str();
  c->add_option("--max-injection", filter->max_injection, "augmented MCL: largest share of random particles per resampling")
      ->capture_default_str();
  c->add_option("--localized-m", filter->converge_pos_m, "localized: position error below this, m")
      ->capture_default_str();
  c->add_option("--localized-deg", filter->converge_heading_deg, "localized: heading error below this, deg")
      ->capture_default_str();
  c->add_option("--hold", filter->hold_s, "localized: within both bounds for this long, s")->capture_default_str();
  c->add_option("--ekf-rot-sigma", filter->ekf_rot_sigma_rad,
                "EKF: heading noise added to every 10 ms prediction, rad (what the odometry model leaves out)")
      ->capture_default_str();
  c->add_flag("--no-plots", *no_plots, "skip the PNG figures (no gnuplot needed)");
  std::string team_help = "a robot-team scenario instead of the single robot (then --seed, --duration, --out and "
                          "--no-plots apply):";
  for (const team::TeamScenarioInfo& t : team::team_scenarios()) team_help += "\n  " + t.name + ": " + t.what;
  c->add_option("--scenario", *scenario, team_help)->check([](const std::string& v) {
    return team::is_team_scenario(v) ? std::string() : "unknown team scenario '" + v + "'";
  });
  CLI::Option* kidnap_opt = c->get_option("--kidnap-at");
  CLI::Option* duration_opt = c->get_option("--duration");
  c->add_flag("--quiet", *quiet, "no progress line on a terminal");
  c->callback([=]() {
    // The same runner as `sim_host run` (sim/scenario_run.hpp), configured from the options.
    ScenarioFile f;
    f.source = "the command line";
    if (!scenario->empty()) {
      f.runner = ScenarioRunner::team;
      f.team = *scenario;
      f.scenario.seed = opts->config.seed;
      f.team_duration_s = duration_opt->count() > 0 ? opts->config.duration_s : -1.0;
    } else {
      f.scenario = finish_scenario(*opts);
      FilterOptions& fo = f.filter;
      fo = *filter;
      const bool ekf = *filter_kind == "ekf";
      fo.filter = ekf ? est::loop::Filter::ekf : est::loop::Filter::mcl;
      if (ekf && (*start == "global" || *start == "wrong"))
        throw CLI::ValidationError("--start", "the EKF tracks from the true start pose: --start " + *start +
                                                  " needs --filter mcl");
      fo.start = ekf ? StartKind::tracking : StartKind::global;  // the default, when --start is not given
      parse(*start, fo.start);
      if (ekf && kidnap_opt->count() == 0) f.scenario.kidnap_at_s = -1.0;  // an EKF cannot recover: none unless asked
      fo.kld = !*no_kld;
    }
    RunOptions ro;
    ro.out = *out;
    ro.plots = !*no_plots;
    ro.quiet = *quiet;
    run_scenario(f, ro);
  });
}

void add_record_command(CLI::App& app) {
  auto opts = std::make_shared<ScenarioOptions>();
  auto out = std::make_shared<std::string>();
  CLI::App* c = app.add_subcommand(
      "record",
      "The same scenario as simulate (world, robot, sensors, faults) written as an LCM log for estimator_node "
      "--replay and the HIL test: EST_WHEEL_TICKS, EST_STEERING, EST_RANGE_SCAN and EST_GROUND_TRUTH (est_lcm "
      "types), event times = arrival times (us). Also writes FILE.json: message counts, injected faults and the "
      "reject counts a HAL must show on replay.");
  c->add_option("--out", *out, "the .lcmlog file to write")->required();
  add_scenario_options(c, *opts);
  c->callback([=]() {
    const ScenarioConfig sc = finish_scenario(*opts);
    const SimWorld world = load_world(sc);
    const SensorStream s = generate_stream(sc, world);
    const std::filesystem::path parent = std::filesystem::path(*out).parent_path();
    if (!parent.empty()) std::filesystem::create_directories(parent);
    const RecordSummary summary = record_lcm_log(s, *out);
    std::ofstream f(*out + ".json");
    f << record_sidecar_json(s, sc, world, summary, *out);
    if (!f) throw std::runtime_error("cannot write " + *out + ".json");
    std::cout << "record: " << to_string(sc.robot) << " in " << world.name << ", " << sc.duration_s << " s, seed "
              << sc.seed << ": " << summary.events << " events -> " << *out << "\n";
    for (const auto& [channel, n] : summary.messages) std::cout << "  " << channel << ": " << n << "\n";
    std::cout << "  injected faults and expected reject counts: " << *out << ".json\n";
  });
}

}  // namespace sim

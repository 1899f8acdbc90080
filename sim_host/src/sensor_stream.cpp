// The sensor stream of a scenario: truth, raw samples with their noise, injected faults, arrival order.
#include "sim/sensor_stream.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <optional>
#include <set>
#include <stdexcept>

#include "est/loop/filter_loop.hpp"
#include "est/sensor/steered_range_finder.hpp"
#include "est/random/samplers.hpp"
#include "est/random/xoshiro128.hpp"
#include "sim/angles.hpp"
#include "world/landmark_sensor.hpp"
#include "world/robots.hpp"

namespace sim {
namespace {

constexpr hal::TimeNs kMs = hal::kNsPerMs;
constexpr float kSimStepS = 0.01f;
// Nominal delivery latency after the stamp (a scan is stamped at its start and sent after the sweep's processing).
constexpr hal::TimeNs kLatencyWheels = 1 * kMs;
constexpr hal::TimeNs kLatencySteering = 1 * kMs;
constexpr hal::TimeNs kLatencyScan = 12 * kMs;
constexpr hal::TimeNs kLatencyLandmarks = 15 * kMs;  // a camera frame's marker detection
constexpr hal::TimeNs kStaleDelay = 300 * kMs;
constexpr hal::TimeNs kLateDelay = 60 * kMs;
constexpr hal::TimeNs kFutureOffset = 1000 * kMs;
constexpr hal::TimeNs kDuplicateGap = kMs / 5;
constexpr std::uint32_t kCounterStart = 0xffffc000u;  // 16384 ticks before the 32-bit counters wrap
constexpr int kFaultSpacing = 4;                      // samples between two faults of one stream
constexpr float kSteeringSpikeRad = 2.5f;
constexpr float kTwistSpikeMps = 20.0f;
const est::Pose2 kOdometryReset{10.0f, -5.0f, 1.0f};  // the new odometry frame's offset after a reset
constexpr float kNanBeamFraction = 0.1f;
constexpr float kLandmarkSpikeFactor = 3.0f;          // a range_spike feature reads this times the sensor's reach
constexpr float kLandmarkRangeMargin = 1.0f;          // the HAL accepts features this far beyond the reach (noise)

struct StreamSpec {
  StreamKind kind;
  const char* name;
  hal::TimeNs period;
  hal::TimeNs latency;
  int count;
};

using Schedule = std::map<int, std::string>;  // sample index -> fault class

struct Interval {
  hal::TimeNs from, to;
};

// Sample indices for the faults of one stream: at least kFaultSpacing apart, clear of the first and last second and
// of the excluded intervals (the burst), and where `eligible` is given only where it is set, each drawn uniformly
// from the slots still free. Fails only when none is.
Schedule place_faults(const StreamSpec& s, const FaultCounts& counts, const std::vector<Interval>& exclude,
                      est::Rng& rng, const std::vector<char>* eligible = nullptr) {
  Schedule out;
  // Sightings come 5 a second: two apart keeps the sample before a fault clean, which is all their classes need.
  const int spacing = s.kind == StreamKind::landmarks ? 2 : kFaultSpacing;
  const int margin = std::max(spacing, static_cast<int>(hal::kNsPerS / s.period));
  const std::string prefix = std::string(s.name) + ".";
  std::vector<int> free;
  for (const auto& [key, n] : counts) {
    if (key.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string cls = key.substr(prefix.size());
    for (int i = 0; i < n; ++i) {
      free.clear();
      for (int j = margin; j < s.count - margin; ++j) {
        const hal::TimeNs t = kSimStartNs + static_cast<hal::TimeNs>(j) * s.period;
        bool ok = eligible == nullptr || (*eligible)[static_cast<std::size_t>(j)] != 0;
        for (const Interval& x : exclude) ok = ok && !(t >= x.from && t < x.to);
        const auto near = out.lower_bound(j - spacing + 1);
        if (near != out.end() && near->first < j + spacing) ok = false;
        if (ok) free.push_back(j);
      }
      if (free.empty())
        throw std::invalid_argument("cannot place " + std::to_string(n) + " '" + key + "' faults (with the other " +
                                    s.name + " faults) in this run: lengthen --duration or lower the counts");
      out[free[rng.below(static_cast<std::uint32_t>(free.size()))]] = cls;
    }
  }
  return out;
}

// What must count an injected timing fault, from the timing rules of the HAL (hal/sample_timing.hpp) and the loop.
std::string expect_timing(const StreamSpec& s, const std::string& cls, hal::TimeNs delay, hal::TimeNs stamp_shift,
                          const hal::TimingLimits& limits, hal::TimeNs encoder_period) {  // of the motion stream
  const std::string hal_prefix = std::string("hal.") + to_string(s.kind) + ".";
  const hal::TimeNs age = delay - stamp_shift;  // arrival - stamp
  if (age > limits.max_age_ns) return hal_prefix + "stale";
  if (-age > limits.max_future_ns) return hal_prefix + "from_future";
  if (stamp_shift < 0) return hal_prefix + "time_backwards";  // shifted past the previous (clean) sample
  if (delay > s.period + s.latency) return hal_prefix + "time_backwards";  // newer samples of its kind came first
  const hal::TimeNs window = est::loop::LoopTiming{}.reorder_window_ns;
  if (delay <= window) return "-";
  // By its arrival the motion samples stamped up to floor((delay - latency) / period) periods later are in; the loop
  // has applied everything a window older than the newest of them: beyond the sample's stamp (one period to spare).
  if (((delay - kLatencyWheels) / encoder_period) * encoder_period >= window + encoder_period) return "loop.too_old";
  throw std::invalid_argument(s.name + std::string(".") + cls +
                              ": with these sensor rates the delay neither stays within the reorder window nor "
                              "clearly exceeds it; raise --encoder-hz");
}

std::size_t nearest_segment(const est::sim::Route& r, const est::Pose2& p) {
  std::size_t best = 0;
  double best_d = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < r.size(); ++i) {
    const double ax = r[i].x, ay = r[i].y, bx = r[i + 1].x, by = r[i + 1].y;
    const double vx = bx - ax, vy = by - ay, l2 = vx * vx + vy * vy;
    const double px = p.x, py = p.y;
    double f = l2 > 0.0 ? ((px - ax) * vx + (py - ay) * vy) / l2 : 0.0;
    f = std::clamp(f, 0.0, 1.0);
    const double d = std::hypot(ax + f * vx - px, ay + f * vy - py);
    if (d < best_d) {
      best_d = d;
      best = i;
    }
  }
  return best;
}

std::uint32_t counter_value(std::uint32_t offset, double counted) {
  const auto n = static_cast<std::int64_t>(std::floor(counted));
  return static_cast<std::uint32_t>(static_cast<std::uint64_t>(offset) + static_cast<std::uint64_t>(n));
}

}  // namespace

const char* to_string(StreamKind k) {
  switch (k) {
    case StreamKind::wheel_ticks: return "wheel_ticks";
    case StreamKind::steering: return "steering";
    case StreamKind::twist: return "twist";
    case StreamKind::odometry: return "odometry";
    case StreamKind::scan: return "scan";
    case StreamKind::landmarks: return "landmarks";
  }
  return "unknown";
}

RobotModels robot_models() {
  RobotModels m;
  const float deg = static_cast<float>(kPi / 180.0);
  est::sim::RobotTruth& t = m.truth;
  node::MotionSpec& f = m.filter;
  // Bicycle: 0.6 m frame, stop at 60 deg. Truth noise per 10 ms step; the filter is told more (estimator_node's
  // defaults), which also covers the encoder's scale error, noise and slip.
  t.bicycle = {0.6f, 60.0f * deg, 0.01f, 0.0005f, 0.001f, kSimStepS};
  f.bicycle = {0.6f, 60.0f * deg, 0.05f, 0.1f, 0.01f, kSimStepS};
  t.diff_drive = {0.05f, 0.3f, 4096u, 0.02f, 0.0002f, 0.001f};
  f.diff_drive = {0.05f, 0.3f, 4096u, 0.1f, 0.003f, 0.01f};
  // The other models' filter noise is estimator_node's defaults (node/estimator_spec.hpp), which cover the errors
  // below: the velocity robot executes its exact command with this noise (a1..a6 per step); the odometry base
  // integrates its (erring) wheel counts; the omni base's wheels count with the encoders' errors.
  t.velocity = {0.002f, 0.0002f, 0.002f, 0.002f, 0.0001f, 0.0001f, kSimStepS};
  f.velocity.dt = kSimStepS;
  t.omni = {{0.01f, 0.002f, 0.002f, 0.002f, 0.01f, 0.002f, 0.005f, 0.005f, 0.01f}, kSimStepS};
  f.omni.dt = kSimStepS;
  float rows[4][3] = {};
  est::mecanum_wheel_rows(0.2f, 0.2f, rows);
  est::configure_omni_wheels(t.omni_wheels, rows, 4, static_cast<float>(metres_per_tick(RobotKind::omni)));
  f.omni_control.source = est::loop::ControlAssembler<est::OmniMotionModel>::Source::wheels;
  f.omni_control.wheels = t.omni_wheels;
  // Holonomic robot: displacement noise per step (B = dt I, Q per step).
  t.holonomic.point.Q = Eigen::Matrix2f::Identity() * 1.0e-6f;
  f.bicycle_control.metres_per_tick = static_cast<float>(metres_per_tick(RobotKind::bicycle));
  return m;
}

double metres_per_tick(RobotKind r) {
  switch (r) {
    case RobotKind::bicycle: return 0.001;
    case RobotKind::omni: return 0.0005;
    default: return static_cast<double>(est::diff_drive_m_per_tick({0.05f, 0.3f, 4096u, 0.0f, 0.0f, 0.0f}));
  }
}

const TruthSample& SensorStream::truth_at(hal::TimeNs t) const {
  if (truth.empty()) throw std::logic_error("truth_at: empty stream");
  const hal::TimeNs k = (t - kSimStartNs) / kSimStepNs;
  const auto i = static_cast<std::size_t>(std::clamp<hal::TimeNs>(k, 0, static_cast<hal::TimeNs>(truth.size()) - 1));
  return truth[i];
}

std::map<std::string, int> SensorStream::expected_counts() const {
  std::map<std::string, int> out;
  for (const InjectedFault& f : faults) {
    if (f.expected != "-") out[f.expected] += f.amount;
    if (!f.also.empty()) out[f.also] += f.also_amount;
  }
  return out;
}

SensorStream generate_stream(const ScenarioConfig& c, const SimWorld& world) {
  // Configuration checks.
  if (!(c.duration_s > 0.0 && c.duration_s <= 3600.0)) throw std::invalid_argument("--duration must be in (0, 3600] s");
  if (!(c.speed_mps > 0.0 && c.speed_mps <= 3.0)) throw std::invalid_argument("--speed must be in (0, 3] m/s");
  for (int hz : {c.encoder_hz, c.steering_hz, c.twist_hz, c.odometry_hz, c.scan_hz, c.landmark_hz})
    if (hz <= 0 || 100 % hz != 0) throw std::invalid_argument("sensor rates must divide 100 Hz (1, 2, 4, 5, 10, 20, 25, 50, 100)");
  const est::sim::LandmarkSensorSpec& lms = c.landmark_sensor;
  if (!(lms.noise.sigma_range > 0.0f) || !(lms.noise.sigma_bearing > 0.0f) || !(lms.noise.sigma_signature >= 0.0f) ||
      !std::isfinite(lms.noise.sigma_range) || !std::isfinite(lms.noise.sigma_bearing) ||
      !std::isfinite(lms.noise.sigma_signature))
    throw std::invalid_argument("--landmark-range-sigma and --landmark-bearing-sigma must be positive and finite");
  if (!(lms.max_range > 0.0f && lms.max_range <= 100.0f) || !(lms.fov > 0.0f && lms.fov <= 6.2832f))
    throw std::invalid_argument("the landmark sensor's reach must be in (0, 100] m and its field of view in (0, 360] deg");
  if (c.beams < 10 || c.beams > 1440) throw std::invalid_argument("--beams must be in [10, 1440]");
  if (!(c.fov_deg > 0.0 && c.fov_deg <= 360.0)) throw std::invalid_argument("--fov-deg must be in (0, 360]");
  if (!(c.range_max_m > 0.5 && c.range_max_m <= 100.0)) throw std::invalid_argument("--range-max must be in (0.5, 100] m");
  std::set<std::string> known;
  for (const FaultClassInfo& f : fault_catalogue()) known.insert(f.key);
  for (const auto& [key, n] : c.faults) {
    if (!known.count(key)) throw std::invalid_argument("unknown fault class '" + key + "' (sim_host simulate --list-faults)");
    if (n < 0) throw std::invalid_argument("fault count of '" + key + "' is negative");
    if (n > 0 && key.rfind("landmarks.", 0) != 0 && !fault_applies(c.robot, key, c.steering_sensor))
      throw std::invalid_argument("'" + key + "': this robot has no such stream (" + to_string(c.robot) +
                                  (c.steering_sensor ? "" : ", no steering sensor") + ")");
    if (n > 0 && world.landmarks.size() == 0 && key.rfind("landmarks.", 0) == 0)
      throw std::invalid_argument("'" + key + "': this world has no landmarks (a ROS map): no landmark sightings");
  }

  RobotModels models = robot_models();
  models.truth.handle_detents = c.handle_detents;
  if (!c.omni_noise.empty()) {
    if (c.omni_noise.size() != 9) throw std::invalid_argument("the omni base's noise is a1..a9: nine numbers");
    std::copy(c.omni_noise.begin(), c.omni_noise.end(), models.truth.omni.alpha);
  }
  const bool bicycle = c.robot == RobotKind::bicycle;
  const bool odometry_base = has_odometry(c.robot);
  const est::sim::Route* const route = world.route.get();
  const bool scripted = !c.controls.empty();
  if (!scripted && route == nullptr) throw std::invalid_argument("a robot needs a route or a control script");
  if (scripted && !c.start_pose && route == nullptr)
    throw std::invalid_argument("a control script without a route needs its start pose");
  const int steps = static_cast<int>(std::lround(c.duration_s / static_cast<double>(kSimStepS)));
  const int enc_div = 100 / c.encoder_hz, steer_div = 100 / c.steering_hz, scan_div = 100 / c.scan_hz;
  const int twist_div = 100 / c.twist_hz, odom_div = 100 / c.odometry_hz;
  const int mark_div = 100 / c.landmark_hz;

  SensorStream s;
  s.route_waypoints = scripted || route == nullptr ? 0 : route->size();
  s.end_ns = kSimStartNs + static_cast<hal::TimeNs>(steps) * kSimStepNs;
  s.mount = c.handlebar ? est::steered_sensor_mount(c.handlebar_mount, 0.0f) : c.rangefinder_mount;
  s.metres_per_tick = metres_per_tick(c.robot);
  // The fastest the robot is told to drive: its cruise speed or a route segment's, or its script's fastest command
  // (and turn, beyond the controllers' 1.5 rad/s).
  double top_speed = c.speed_mps, top_turn = 1.5;
  if (scripted) {
    top_speed = 0.1;
    for (const est::sim::TimedCommand& u : c.controls) {
      const double a = std::fabs(static_cast<double>(u.u[0])), b = std::fabs(static_cast<double>(u.u[1]));
      const double w = c.robot == RobotKind::omni ? std::fabs(static_cast<double>(u.u[2]))
                       : c.robot == RobotKind::bicycle || c.robot == RobotKind::holonomic ? 0.0 : b;
      top_speed = std::max(top_speed, c.robot == RobotKind::omni || c.robot == RobotKind::holonomic ? a + b : a);
      top_turn = std::max(top_turn, w);
    }
  } else {
    for (std::size_t i = 0; i < route->size(); ++i)
      top_speed = std::max(top_speed, static_cast<double>((*route)[i].speed_mps));
  }
  // The fastest wheel: the bicycle's front wheel at speed; a diff drive turning at top_turn; a mecanum wheel with
  // |v1| + |v2| + (lx + ly) |w| (the omni base turns at up to 1 rad/s on a route).
  const double wheel_speed_max =
      bicycle ? top_speed
      : c.robot == RobotKind::omni
          ? 1.5 * top_speed + 0.4 * std::max(1.0, scripted ? top_turn : 1.0)
          : top_speed + top_turn * 0.5 * static_cast<double>(models.truth.diff_drive.track_width);
  s.limits.wheels.wheel_count = c.robot == RobotKind::omni ? 4 : 2;
  s.limits.wheels.counter_bits = kEncoderCounterBits;
  s.limits.wheels.max_ticks_per_s = static_cast<std::uint32_t>(std::ceil(3.0 * wheel_speed_max / s.metres_per_tick));
  // The stops plus what the sensor may add there: its bias and 4 sigma of its noise (a sensor that reads past the
  // stop is biased, not broken; refused, its last reading would stand for the handle while it sits at the stop).
  s.limits.steering.max_angle_rad =
      models.truth.bicycle.steer_max +
      static_cast<float>((std::fabs(c.steering_bias_deg) + 4.0 * c.steering_sigma_deg) * kPi / 180.0);
  s.limits.twist.max_speed_mps = static_cast<float>(3.0 * top_speed);
  s.limits.twist.max_turn_rate_rps = static_cast<float>(2.0 * top_turn);
  s.limits.odometry.max_speed_mps = static_cast<float>(3.0 * top_speed);
  s.limits.odometry.max_turn_rate_rps = static_cast<float>(2.0 * top_turn);
  s.limits.scan.max_beams = static_cast<std::size_t>(std::max(1081, c.beams));
  s.landmark_count = static_cast<std::size_t>(world.landmarks.size());
  s.limits.landmarks.max_range_m = lms.max_range + kLandmarkRangeMargin;
  s.limits.landmarks.max_id = std::max<std::int32_t>(0, world.landmarks.size() - 1);
  s.limits.set_timing(s.limits.wheels.timing);

  const StreamSpec wheels{StreamKind::wheel_ticks, "wheel_ticks", enc_div * kSimStepNs, kLatencyWheels,
                          has_wheel_ticks(c.robot) ? steps / enc_div : 0};
  const StreamSpec steering{StreamKind::steering, "steering", steer_div * kSimStepNs, kLatencySteering,
                            bicycle && c.steering_sensor ? steps / steer_div : 0};
  const StreamSpec twists{StreamKind::twist, "twist", twist_div * kSimStepNs, kLatencyWheels,
                          has_twist(c.robot) ? steps / twist_div : 0};
  const StreamSpec odometry{StreamKind::odometry, "odometry", odom_div * kSimStepNs, kLatencyWheels,
                            odometry_base ? steps / odom_div : 0};
  const StreamSpec scans{StreamKind::scan, "scan", scan_div * kSimStepNs, kLatencyScan, steps / scan_div};
  const StreamSpec marks{StreamKind::landmarks, "landmarks", mark_div * kSimStepNs, kLatencyLandmarks,
                         world.landmarks.size() > 0 ? steps / mark_div : 0};

  est::Rng truth_rng = est::Rng::stream(c.seed, 1);
  est::Rng range_rng = est::Rng::stream(c.seed, 2);
  est::Rng odo_rng = est::Rng::stream(c.seed, 3);
  est::Rng fault_rng = est::Rng::stream(c.seed, 4);
  est::Rng landmark_rng = est::Rng::stream(c.seed, 5);
  est::Rng landmark_fault_rng = est::Rng::stream(c.seed, 6);

  // Events: the burst (bus outage), slips, the kidnapping.
  std::vector<Interval> burst;
  if (c.burst_at_s >= 0.0 && c.burst_at_s < c.duration_s && c.burst_ms > 0.0) {
    const hal::TimeNs b0 = kSimStartNs + static_cast<hal::TimeNs>(std::llround(c.burst_at_s * 1e9));
    burst.push_back({b0, b0 + static_cast<hal::TimeNs>(std::llround(c.burst_ms * 1e6))});
    s.faults.push_back({b0, "event.burst", "-", 1, "", 0});
  }
  std::vector<Interval> exclude;
  for (const Interval& b : burst) exclude.push_back({b.from - 500 * kMs, b.to + 800 * kMs});
  const Schedule wheel_faults = place_faults(wheels, c.faults, exclude, fault_rng);
  const Schedule steer_faults = place_faults(steering, c.faults, exclude, fault_rng);
  const Schedule scan_faults = place_faults(scans, c.faults, exclude, fault_rng);
  const Schedule twist_faults = place_faults(twists, c.faults, exclude, fault_rng);
  // The period of the robot's motion stream: newer motion samples are what push a late input out of the window.
  const hal::TimeNs motion_period =
      wheels.count > 0 ? wheels.period : twists.count > 0 ? twists.period : odometry.period;
  const Schedule odom_faults = place_faults(odometry, c.faults, exclude, fault_rng);

  std::vector<Interval> slips;
  for (int i = 0; i < c.slip_events && c.duration_s > 4.0; ++i) {
    for (int tries = 0; tries < 200; ++tries) {
      const double at = 2.0 + static_cast<double>(fault_rng.uniform()) * (c.duration_s - 3.0 - c.slip_duration_s);
      const hal::TimeNs a = kSimStartNs + static_cast<hal::TimeNs>(std::llround(at * 1e9));
      const Interval iv{a, a + static_cast<hal::TimeNs>(std::llround(c.slip_duration_s * 1e9))};
      bool clear = true;
      for (const Interval& o : slips) clear = clear && (iv.to + hal::kNsPerS < o.from || o.to + hal::kNsPerS < iv.from);
      if (clear) {
        slips.push_back(iv);
        s.faults.push_back({a, "event.slip", "-", 1, "", 0});
        break;
      }
    }
  }
  const int kidnap_step =
      c.kidnap_at_s >= 0.0 && c.kidnap_at_s < c.duration_s ? static_cast<int>(std::lround(c.kidnap_at_s / static_cast<double>(kSimStepS))) : -1;

  if (scripted && kidnap_step >= 0)
    throw std::invalid_argument("a kidnapping carries the robot onto its route: a robot on a control script has none");
  const est::Pose2 start =
      c.start_pose ? *c.start_pose : route->pose_on_segment(c.start_segment % route->size(), 0.0f);
  const std::optional<est::sim::ControlScript> script =
      scripted ? std::optional<est::sim::ControlScript>(c.controls) : std::nullopt;
  const std::unique_ptr<est::sim::SimRobot> robot =
      scripted ? est::sim::make_robot(c.robot, *script, start, models.truth, kSimStepS, s.metres_per_tick)
               : est::sim::make_robot(c.robot, *route, start, c.start_segment + 1, models.truth,
                                      static_cast<float>(c.speed_mps), kSimStepS, s.metres_per_tick);
  const auto pose = [&]() { return robot->pose(); };

  // The rangefinder.
  const float fov = static_cast<float>(c.fov_deg * kPi / 180.0);
  const bool full_turn = c.fov_deg >= 360.0;
  est::ScanLayout layout;
  layout.angle_min = full_turn ? -static_cast<float>(kPi) : -0.5f * fov;
  layout.angle_increment = full_turn ? fov / static_cast<float>(c.beams) : fov / static_cast<float>(c.beams - 1);
  layout.count = c.beams;
  layout.range_min = 0.05f;
  layout.range_max = static_cast<float>(c.range_max_m);
  hal::ScanGeometry geometry{layout.angle_min, layout.angle_increment, layout.range_min, layout.range_max,
                             1.0f / static_cast<float>(c.scan_hz)};
  std::vector<float> ranges;

  const auto in_any = [](const std::vector<Interval>& v, hal::TimeNs t) {
    for (const Interval& x : v)
      if (t >= x.from && t < x.to) return true;
    return false;
  };
  const hal::TimingLimits& timing = s.limits.wheels.timing;

  // Emits one sample of `spec` (index j, stamp t) with the fault scheduled for it, if any. `make` builds the event
  // for a stamp; `mutate` applies a content fault to it and returns the expected counter and amount.
  std::vector<std::pair<StreamEvent, std::size_t>> events;  // with generation order for a stable sort
  const auto push = [&](StreamEvent e) { events.push_back({e, events.size()}); };
  const auto emit = [&](const StreamSpec& spec, const Schedule& sched, int j, hal::TimeNs t, auto make) {
    const auto it = sched.find(j);
    if (it == sched.end()) {
      StreamEvent e = make(t);
      e.arrival_ns = t + spec.latency;
      push(e);
      return;
    }
    const std::string& cls = it->second;
    const std::string key = std::string(spec.name) + "." + cls;
    const std::string hal_prefix = std::string("hal.") + to_string(spec.kind) + ".";
    InjectedFault f{t, key, "-", 1, "", 0};
    hal::TimeNs delay = spec.latency, shift = 0;
    bool deliver = true;
    if (cls == "dropped") {
      deliver = false;
    } else if (cls == "duplicate") {
      f.expected = hal_prefix + "duplicate";
    } else if (cls == "stale") {
      delay = kStaleDelay;
    } else if (cls == "late") {
      delay = kLateDelay;
    } else if (cls == "reordered") {
      delay = spec.kind == StreamKind::scan ? 18 * kMs : 15 * kMs;
    } else if (cls == "time_backwards") {
      shift = -(3 * spec.period) / 2;
    } else if (cls == "from_future") {
      shift = kFutureOffset;
    } else if (cls == "nan") {
      f.expected = hal_prefix + "not_finite";
    } else if (cls == "spike" || cls == "range_spike") {
      f.expected = hal_prefix + "out_of_range";
    } else if (cls == "counter_jump" || cls == "reset") {
      f.expected = hal_prefix + "out_of_range";
    } else if (cls == "nan_scan") {
      f.expected = hal_prefix + "too_few_valid_beams";
    } else if (cls == "nan_beams") {
      f.expected = hal_prefix + "beams_nan";
    }
    if (cls == "stale" || cls == "late" || cls == "reordered" || cls == "time_backwards" || cls == "from_future")
      f.expected = expect_timing(spec, cls, delay, shift, timing, motion_period);
    if (deliver) {
      StreamEvent e = make(t + shift);
      e.arrival_ns = t + delay;
      if (cls == "nan" && spec.kind == StreamKind::steering) e.steering.angle_rad = std::numeric_limits<float>::quiet_NaN();
      if (cls == "nan" && spec.kind == StreamKind::twist) e.twist.v1_mps = std::numeric_limits<float>::quiet_NaN();
      if (cls == "nan" && spec.kind == StreamKind::odometry) e.odometry.pose.x = std::numeric_limits<float>::quiet_NaN();
      if ((cls == "nan" || cls == "range_spike") && spec.kind == StreamKind::landmarks) {
        // The first feature only: a sighting that is eligible for a fault has another one, which passes.
        s.sightings[e.sighting].features.front().range_m =
            cls == "nan" ? std::numeric_limits<float>::quiet_NaN() : kLandmarkSpikeFactor * lms.max_range;
      }
      if (cls == "spike" && spec.kind == StreamKind::steering) e.steering.angle_rad = kSteeringSpikeRad;
      if (cls == "spike" && spec.kind == StreamKind::twist) e.twist.v1_mps = kTwistSpikeMps;
      if (cls == "nan_scan" || cls == "nan_beams") {
        ScanRecord copy = s.scans[e.scan];
        int n = 0;
        for (float& r : copy.ranges) {
          if (cls == "nan_scan" || fault_rng.uniform() < kNanBeamFraction) {
            r = std::numeric_limits<float>::quiet_NaN();
            ++n;
          }
        }
        if (cls == "nan_beams") f.amount = n;
        if (cls == "nan_scan") {
          f.also = hal_prefix + "beams_nan";  // the validator counts the beams of a scan it then rejects
          f.also_amount = n;
        }
        s.scans.push_back(std::move(copy));
        e.scan = s.scans.size() - 1;
      }
      // The loop takes a sighting as one input per feature: a late one is too old once per feature.
      if (spec.kind == StreamKind::landmarks && f.expected.rfind("loop.", 0) == 0)
        f.amount = static_cast<int>(s.sightings[e.sighting].features.size());
      const int fault_index = static_cast<int>(s.faults.size());
      if (cls == "duplicate") {
        push(e);
        e.arrival_ns += kDuplicateGap;
      }
      e.fault = fault_index;
      push(e);
    }
    s.faults.push_back(f);
  };

  double counted[4] = {0.0, 0.0, 0.0, 0.0};  // ticks, fractional
  std::uint32_t offset[4] = {kCounterStart, kCounterStart, kCounterStart, kCounterStart};
  const std::uint8_t wheel_count = s.limits.wheels.wheel_count;
  // The odometry base's own integration of its counted wheel travel (its drift is the encoders' errors), and the
  // offset of its odometry frame after a reset.
  double odom_x = 0.0, odom_y = 0.0, odom_theta = 0.0;
  est::Pose2 odom_frame{};
  const double half_track_inv = 1.0 / static_cast<double>(models.truth.diff_drive.track_width);
  s.truth.reserve(static_cast<std::size_t>(steps));
  float steer_true = 0.0f;  // the handlebar's angle over the last step
  for (int k = 0; k < steps; ++k) {
    const hal::TimeNs t = kSimStartNs + static_cast<hal::TimeNs>(k) * kSimStepNs;
    if (k == kidnap_step) {
      // Onto the route 3 or more segments ahead, 30 % into the segment: the first such pose at least
      // kKidnapMinDistanceM away (far beyond the localized bound, so the filter must lose and regain its estimate),
      // else the farthest of them.
      const est::Pose2 from = pose();
      const std::size_t here = nearest_segment(*route, from);
      std::size_t seg = here + 3;
      double best = -1.0;
      for (std::size_t ahead = 3; ahead < 3 + route->size(); ++ahead) {
        const est::Pose2 q = route->pose_on_segment((here + ahead) % route->size(), 0.3f);
        const double d = std::hypot(static_cast<double>(q.x - from.x), static_cast<double>(q.y - from.y));
        if (d > best) {
          best = d;
          seg = here + ahead;
        }
        if (d >= kKidnapMinDistanceM) break;
      }
      const est::Pose2 to = route->pose_on_segment(seg % route->size(), 0.3f);
      s.kidnap_distance_m = best;
      robot->teleport(to, seg + 1);
      s.kidnap_ns = t;
      s.faults.push_back({t, "event.kidnap", "-", 1, "", 0});
    }
    const est::Pose2 p = pose();
    std::int32_t cx = 0, cy = 0;
    if (!world.grid.world_to_cell(p.x, p.y, cx, cy) || world.grid.classify(cx, cy) == est::CellClass::occupied) {
      char where[160];
      std::snprintf(where, sizeof where, "the robot left the free space at (%.2f, %.2f) m, %.2f s into the run",
                    static_cast<double>(p.x), static_cast<double>(p.y), static_cast<double>(k) * 0.01);
      throw std::invalid_argument(std::string(where) + (scripted ? ": the control script drives it into an obstacle or off the map"
                                                                  : ": the route crosses an obstacle or leaves the map (--route)"));
    }
    s.truth.push_back({t, p, 0.0f, 0.0f});
    const bool silent = in_any(burst, t);

    // Encoders: the counters through the previous step.
    if (wheels.count > 0 && k % enc_div == 0 && !silent) {
      const int j = k / enc_div;
      const auto it = wheel_faults.find(j);
      if (it != wheel_faults.end() && it->second == "counter_jump") {
        // An encoder reset: the counters continue from garbage, far from where they were.
        for (std::uint8_t w = 0; w < wheel_count; ++w) {
          std::uint32_t jump = 0;
          do jump = fault_rng.next(); while (jump < (1u << 24) || jump > 0u - (1u << 24));
          offset[w] += jump;
        }
      }
      emit(wheels, wheel_faults, j, t, [&](hal::TimeNs stamp) {
        StreamEvent e;
        e.kind = StreamKind::wheel_ticks;
        e.ticks.stamp_ns = stamp;
        e.ticks.wheel_count = wheel_count;
        for (std::uint8_t w = 0; w < wheel_count; ++w) e.ticks.count[w] = counter_value(offset[w], counted[w]);
        return e;
      });
    }

    // Odometry: the base's integrated pose through the previous step, in its own frame.
    if (odometry.count > 0 && k % odom_div == 0 && !silent) {
      const int j = k / odom_div;
      const auto it = odom_faults.find(j);
      if (it != odom_faults.end() && it->second == "reset") odom_frame = est::compose(odom_frame, kOdometryReset);
      const est::Pose2 integrated{static_cast<float>(odom_x), static_cast<float>(odom_y),
                                  static_cast<float>(std::remainder(odom_theta, 2.0 * kPi))};
      const est::Pose2 reported = est::compose(odom_frame, integrated);
      emit(odometry, odom_faults, j, t, [&](hal::TimeNs stamp) {
        StreamEvent e;
        e.kind = StreamKind::odometry;
        e.odometry.stamp_ns = stamp;
        e.odometry.pose = reported;
        return e;
      });
    }

    // The command of this step moves the truth; the encoders count the wheels' turning (with their errors).
    const bool slipping = in_any(slips, t);
    const auto count_factor = [&]() {
      return 1.0 + c.encoder_scale_error + (slipping ? c.slip_factor : 0.0) +
             static_cast<double>(est::sample_normal(odo_rng, static_cast<float>(c.encoder_noise)));
    };
    const est::sim::RobotStep step = robot->step(truth_rng);
    double counted_step[4] = {0.0, 0.0, 0.0, 0.0};
    for (std::uint8_t w = 0; w < step.wheels && w < 4; ++w) {
      counted_step[w] = step.travel_ticks[w] * count_factor();
      counted[w] += counted_step[w];
    }
    if (odometry_base) {  // the exact arc of the counted travel (double: the base's own arithmetic)
      const double l = counted_step[0] * s.metres_per_tick, r = counted_step[1] * s.metres_per_tick;
      const double sd = 0.5 * (l + r), h = 0.5 * (r - l) * half_track_inv;
      const double chord = std::fabs(h) < 1e-9 ? sd : sd * std::sin(h) / h;
      odom_x += chord * std::cos(odom_theta + h);
      odom_y += chord * std::sin(odom_theta + h);
      odom_theta += 2.0 * h;
    }
    steer_true = step.steer_rad;
    const float steer_cmd = step.steer_rad;
    const est::Pose2 next = pose();
    s.truth.back().v_mps = std::hypot(next.x - p.x, next.y - p.y) / kSimStepS;
    s.truth.back().omega_rps = wrap_angle(next.theta - p.theta) / kSimStepS;

    // Twist: the command of this step, held until the next sample.
    if (twists.count > 0 && k % twist_div == 0 && !silent) {
      emit(twists, twist_faults, k / twist_div, t, [&](hal::TimeNs stamp) {
        StreamEvent e;
        e.kind = StreamKind::twist;
        e.twist = {stamp, step.v1_mps, step.v2_mps, step.w_rps};
        return e;
      });
    }

    // Steering: the wheel angle held over this step, with the sensor's bias and noise.
    if (bicycle && k % steer_div == 0) {
      const float measured = steer_cmd + static_cast<float>(c.steering_bias_deg * kPi / 180.0) +
                             est::sample_normal(odo_rng, static_cast<float>(c.steering_sigma_deg * kPi / 180.0));
      if (!silent && steering.count > 0)
        emit(steering, steer_faults, k / steer_div, t, [&](hal::TimeNs stamp) {
          StreamEvent e;
          e.kind = StreamKind::steering;
          e.steering = {stamp, measured};
          return e;
        });
    }

    // The scan from this step's pose (always drawn, so the noise does not depend on the fault plan).
    if (k % scan_div == 0) {
      // On the handlebar the sensor turns with the steering (its angle over the step that starts here).
      const est::Pose2 mount = c.handlebar ? est::steered_sensor_mount(c.handlebar_mount, steer_true) : s.mount;
      est::sim::simulate_scan(world.grid, p, mount, layout, c.range_noise, range_rng, ranges);
      if (!silent) {
        emit(scans, scan_faults, k / scan_div, t, [&](hal::TimeNs stamp) {
          ScanRecord r;
          r.stamp_ns = stamp;
          r.geometry = geometry;
          r.ranges = ranges;
          s.scans.push_back(std::move(r));
          StreamEvent e;
          e.kind = StreamKind::scan;
          e.scan = s.scans.size() - 1;
          return e;
        });
      }
    }
  }

  // Landmark sightings from the truth of every sample time (after the kidnapping's teleport, silent in the outage),
  // each drawn whether or not it is delivered, from its own generators so the other streams' draws do not move.
  if (marks.count > 0) {
    std::vector<std::vector<hal::LandmarkFeature>> seen(static_cast<std::size_t>(marks.count));
    std::vector<est::sim::Sighting> sighted;
    for (int j = 0; j < marks.count; ++j) {
      const std::size_t k = static_cast<std::size_t>(j) * static_cast<std::size_t>(mark_div);
      est::sim::simulate_landmarks(world.grid, world.landmarks, s.truth[k].pose, lms, landmark_rng, sighted);
      for (const est::sim::Sighting& x : sighted)
        seen[static_cast<std::size_t>(j)].push_back(
            {x.f.range, x.f.bearing, x.f.signature, c.landmark_ids_known ? x.c : std::int32_t{-1}});
    }
    // A fault goes to a sighting of two or more features (a content fault leaves one that passes) whose predecessor
    // was delivered (so the HAL's timing checks compare with the sample one period before).
    std::vector<char> eligible(static_cast<std::size_t>(marks.count), 0);
    const auto delivered = [&](int j) {
      return !seen[static_cast<std::size_t>(j)].empty() &&
             !in_any(burst, kSimStartNs + static_cast<hal::TimeNs>(j) * marks.period);
    };
    for (int j = 1; j < marks.count; ++j)
      eligible[static_cast<std::size_t>(j)] = delivered(j) && delivered(j - 1) && seen[static_cast<std::size_t>(j)].size() >= 2u;
    const Schedule mark_faults = place_faults(marks, c.faults, exclude, landmark_fault_rng, &eligible);
    for (int j = 0; j < marks.count; ++j) {
      if (!delivered(j)) continue;  // a sensor that sees nothing sends nothing
      const hal::TimeNs t = kSimStartNs + static_cast<hal::TimeNs>(j) * marks.period;
      emit(marks, mark_faults, j, t, [&](hal::TimeNs stamp) {
        SightingRecord r;
        r.stamp_ns = stamp;
        r.features = seen[static_cast<std::size_t>(j)];
        s.sightings.push_back(std::move(r));
        StreamEvent e;
        e.kind = StreamKind::landmarks;
        e.sighting = s.sightings.size() - 1;
        return e;
      });
    }
  }

  std::stable_sort(events.begin(), events.end(), [](const auto& a, const auto& b) {
    return a.first.arrival_ns != b.first.arrival_ns ? a.first.arrival_ns < b.first.arrival_ns : a.second < b.second;
  });
  s.events.reserve(events.size());
  for (auto& e : events) s.events.push_back(e.first);
  return s;
}

void expect_loop_inputs(SensorStream& stream, bool uses_scans, bool uses_landmarks) {
  for (InjectedFault& f : stream.faults) {
    if (f.expected.rfind("loop.", 0) != 0) continue;
    if ((!uses_scans && f.key.rfind("scan.", 0) == 0) || (!uses_landmarks && f.key.rfind("landmarks.", 0) == 0))
      f.expected = "-";
  }
}

}  // namespace sim

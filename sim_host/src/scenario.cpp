// Scenario pieces shared by simulate and record: the fault catalogue, the default plan, the world.
#include "sim/scenario.hpp"

#include <memory>
#include <stdexcept>

#include "est/map/distance_transform.hpp"
#include "est/map/occupancy_grid.hpp"
#include "hal/maps/landmark_file.hpp"
#include "maps/ros_map_loader.hpp"
#include "world/office_world.hpp"

namespace sim {

bool has_wheel_ticks(RobotKind r) {
  return r == RobotKind::bicycle || r == RobotKind::diff_drive || r == RobotKind::omni;
}
bool has_twist(RobotKind r) { return r == RobotKind::velocity || r == RobotKind::holonomic; }
bool has_odometry(RobotKind r) { return r == RobotKind::odometry; }

bool fault_applies(RobotKind r, const std::string& key, bool steering_sensor, bool landmarks) {
  const auto stream = [&](const char* p) { return key.rfind(p, 0) == 0; };
  if (stream("steering.")) return r == RobotKind::bicycle && steering_sensor;
  if (stream("wheel_ticks.")) return has_wheel_ticks(r);
  if (stream("twist.")) return has_twist(r);
  if (stream("odometry.")) return has_odometry(r);
  if (stream("landmarks.")) return landmarks;
  return true;
}

const std::vector<FaultClassInfo>& fault_catalogue() {
  static const std::vector<FaultClassInfo> c = {
      {"wheel_ticks.dropped", "the sample is lost on the bus", "-"},
      {"wheel_ticks.duplicate", "the sample is delivered twice", "hal.wheel_ticks.duplicate"},
      {"wheel_ticks.stale", "delivered 300 ms after its stamp", "hal.wheel_ticks.stale"},
      {"wheel_ticks.late", "delivered 60 ms late, after newer samples of its kind", "hal.wheel_ticks.time_backwards"},
      {"wheel_ticks.time_backwards", "stamped 1.5 periods before the previous sample", "hal.wheel_ticks.time_backwards"},
      {"wheel_ticks.from_future", "stamped 1 s ahead of the clock", "hal.wheel_ticks.from_future"},
      {"wheel_ticks.counter_jump", "the counters restart from garbage (encoder reset)", "hal.wheel_ticks.out_of_range"},
      {"steering.dropped", "the sample is lost on the bus", "-"},
      {"steering.duplicate", "the sample is delivered twice", "hal.steering.duplicate"},
      {"steering.stale", "delivered 300 ms after its stamp", "hal.steering.stale"},
      {"steering.late", "delivered 60 ms late, after newer samples of its kind", "hal.steering.time_backwards"},
      {"steering.reordered", "delivered 15 ms late: after newer encoder samples, within the reorder window", "-"},
      {"steering.time_backwards", "stamped 1.5 periods before the previous sample", "hal.steering.time_backwards"},
      {"steering.from_future", "stamped 1 s ahead of the clock", "hal.steering.from_future"},
      {"steering.nan", "the angle is NaN", "hal.steering.not_finite"},
      {"steering.spike", "the angle reads 2.5 rad, beyond the mechanical stop", "hal.steering.out_of_range"},
      {"twist.dropped", "the sample is lost on the bus (the previous twist holds)", "-"},
      {"twist.duplicate", "the sample is delivered twice", "hal.twist.duplicate"},
      {"twist.stale", "delivered 300 ms after its stamp", "hal.twist.stale"},
      {"twist.late", "delivered 60 ms late, after newer samples of its kind", "hal.twist.time_backwards"},
      {"twist.time_backwards", "stamped 1.5 periods before the previous sample", "hal.twist.time_backwards"},
      {"twist.from_future", "stamped 1 s ahead of the clock", "hal.twist.from_future"},
      {"twist.nan", "the forward speed is NaN", "hal.twist.not_finite"},
      {"twist.spike", "the forward speed reads 20 m/s, beyond the base's limit", "hal.twist.out_of_range"},
      {"odometry.dropped", "the pose is lost on the bus (the next increment spans both intervals)", "-"},
      {"odometry.duplicate", "the sample is delivered twice", "hal.odometry.duplicate"},
      {"odometry.stale", "delivered 300 ms after its stamp", "hal.odometry.stale"},
      {"odometry.late", "delivered 60 ms late, after newer samples of its kind", "hal.odometry.time_backwards"},
      {"odometry.time_backwards", "stamped 1.5 periods before the previous sample", "hal.odometry.time_backwards"},
      {"odometry.from_future", "stamped 1 s ahead of the clock", "hal.odometry.from_future"},
      {"odometry.nan", "the pose's x is NaN", "hal.odometry.not_finite"},
      {"odometry.reset", "the base's odometry frame restarts elsewhere (every later pose offset by 10 m, 1 rad)",
       "hal.odometry.out_of_range"},
      {"scan.dropped", "the scan is lost", "-"},
      {"scan.duplicate", "the scan is delivered twice", "hal.scan.duplicate"},
      {"scan.stale", "delivered 300 ms after its stamp", "hal.scan.stale"},
      {"scan.late", "delivered 60 ms late: beyond the loop's 20 ms reorder window", "loop.too_old"},
      {"scan.reordered", "delivered 18 ms late: after newer encoder samples, within the reorder window", "-"},
      {"scan.time_backwards", "stamped 1.5 periods before the previous scan", "hal.scan.time_backwards"},
      {"scan.from_future", "stamped 1 s ahead of the clock", "hal.scan.from_future"},
      {"scan.nan_scan", "every reading is NaN", "hal.scan.too_few_valid_beams"},
      {"scan.nan_beams", "10 % of the readings are NaN (the scan stays usable)", "hal.scan.beams_nan"},
      {"landmarks.dropped", "the sighting is lost", "-"},
      {"landmarks.duplicate", "the sighting is delivered twice", "hal.landmarks.duplicate"},
      {"landmarks.stale", "delivered 300 ms after its stamp", "hal.landmarks.stale"},
      {"landmarks.late", "delivered 60 ms late: beyond the loop's reorder window (EKF; MCL drops sightings)",
       "loop.too_old"},
      {"landmarks.from_future", "stamped 1 s ahead of the clock", "hal.landmarks.from_future"},
      {"landmarks.nan", "one feature's range is NaN (the others pass)", "hal.landmarks.not_finite"},
      {"landmarks.range_spike", "one feature reads 3x the sensor's reach (the others pass)",
       "hal.landmarks.out_of_range"},
  };
  return c;
}

FaultCounts default_fault_counts(RobotKind robot, bool landmarks, bool steering_sensor) {
  FaultCounts f = {
      {"scan.dropped", 5},        {"scan.duplicate", 2},        {"scan.stale", 2},
      {"scan.late", 3},           {"scan.reordered", 3},        {"scan.time_backwards", 2},
      {"scan.from_future", 1},    {"scan.nan_scan", 2},         {"scan.nan_beams", 5},
  };
  if (has_wheel_ticks(robot)) {
    const FaultCounts w = {{"wheel_ticks.dropped", 5}, {"wheel_ticks.duplicate", 3}, {"wheel_ticks.stale", 2},
                           {"wheel_ticks.late", 2},    {"wheel_ticks.time_backwards", 2},
                           {"wheel_ticks.from_future", 1}, {"wheel_ticks.counter_jump", 1}};
    f.insert(w.begin(), w.end());
  }
  if (has_twist(robot)) {
    const FaultCounts t = {{"twist.dropped", 4}, {"twist.duplicate", 2},      {"twist.stale", 2},
                           {"twist.late", 2},    {"twist.time_backwards", 2}, {"twist.from_future", 1},
                           {"twist.nan", 2},     {"twist.spike", 2}};
    f.insert(t.begin(), t.end());
  }
  if (has_odometry(robot)) {
    const FaultCounts o = {{"odometry.dropped", 4}, {"odometry.duplicate", 2},      {"odometry.stale", 2},
                           {"odometry.late", 2},    {"odometry.time_backwards", 2}, {"odometry.from_future", 1},
                           {"odometry.nan", 2},     {"odometry.reset", 1}};
    f.insert(o.begin(), o.end());
  }
  if (robot == RobotKind::bicycle && steering_sensor) {
    const FaultCounts s = {{"steering.dropped", 3},  {"steering.duplicate", 2},      {"steering.stale", 1},
                           {"steering.late", 1},     {"steering.reordered", 2},      {"steering.time_backwards", 2},
                           {"steering.from_future", 1}, {"steering.nan", 3},         {"steering.spike", 2}};
    f.insert(s.begin(), s.end());
  }
  if (landmarks) {
    const FaultCounts l = {{"landmarks.dropped", 3},        {"landmarks.duplicate", 2}, {"landmarks.stale", 2},
                           {"landmarks.late", 1},           {"landmarks.from_future", 1},
                           {"landmarks.nan", 2},            {"landmarks.range_spike", 2}};
    f.insert(l.begin(), l.end());
  }
  return f;
}

namespace {

// The largest map a run loads (4 MB of grid, 8 MB of transform), and the most landmarks (estimator_node's).
constexpr std::int32_t kMaxSide = 2048;
constexpr std::int32_t kMaxLandmarks = 1024;

struct LoadedMap {
  est::OccupancyGridStorage<kMaxSide, kMaxSide> grid;
  est::DistanceTransformStorage<kMaxSide, kMaxSide> edt;
};

// The grid, its transform and the route: the office (with its landmarks) or a ROS map (none).
SimWorld load_grid_world(const ScenarioConfig& config) {
  SimWorld w;
  if (config.map_yaml.empty()) {
    const est::sim::OfficeWorld& office = est::sim::office_world();
    w.name = "office";
    w.grid = office.grid();
    w.edt = office.edt();
    w.landmarks = office.landmarks();
    w.route = std::make_unique<est::sim::Route>(config.route.empty() ? office.route : est::sim::Route(config.route));
    return w;
  }
  if (config.controls.empty() && config.route.size() < 2)
    throw std::invalid_argument("--route is required with --map (at least two waypoints x,y in the map frame)");
  if (!config.controls.empty() && config.route.empty() && !config.start_pose)
    throw std::invalid_argument("a control script in a map_server map needs its start pose (no route to start on)");
  auto m = std::make_shared<LoadedMap>();
  est::sim::load_ros_map(config.map_yaml, m->grid);
  if (m->edt.build(m->grid.grid()) != est::MapStatus::ok)
    throw std::runtime_error(config.map_yaml + ": the distance transform could not be built");
  w.name = config.map_yaml;
  w.grid = m->grid.grid();
  w.edt = m->edt.view();
  w.storage = m;
  if (!config.route.empty()) w.route = std::make_unique<est::sim::Route>(config.route);
  return w;
}

}  // namespace

bool has_landmarks(const ScenarioConfig& config) { return config.map_yaml.empty() || !config.landmarks_csv.empty(); }

const char* to_string(StartKind k) {
  switch (k) {
    case StartKind::global: return "global";
    case StartKind::tracking: return "tracking";
    case StartKind::wrong: return "wrong";
  }
  return "?";
}

bool parse(const std::string& s, StartKind& out) {
  for (const StartKind k : {StartKind::global, StartKind::tracking, StartKind::wrong})
    if (s == to_string(k)) {
      out = k;
      return true;
    }
  return false;
}

SimWorld load_world(const ScenarioConfig& config) {
  SimWorld w = load_grid_world(config);
  if (!config.landmarks_csv.empty()) {
    auto lm = std::make_shared<est::LandmarkMapStorage<kMaxLandmarks>>();
    hal::maps::load_landmark_csv(config.landmarks_csv, *lm);
    w.landmarks = lm->view();
    w.landmark_storage = lm;
  }
  return w;
}

}  // namespace sim

#pragma once
// A host simulation scenario: the world (the synthetic office or a ROS map), the robot and its route, the sensors
// with their noise, and the faults injected into their streams. `simulate` and `record` share it, so a recorded log
// carries exactly the stream an in-process run consumes. Host only (may throw).
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "est/geometry/pose2.hpp"
#include "est/map/distance_transform.hpp"
#include "est/map/landmark_map.hpp"
#include "est/map/occupancy_grid.hpp"
#include "est/sensor/steered_range_finder.hpp"
#include "node/estimator_spec.hpp"
#include "world/control_script.hpp"
#include "world/landmark_sensor.hpp"
#include "world/range_sensor.hpp"
#include "world/robots.hpp"
#include "world/route.hpp"

namespace sim {

// One robot per motion model (sim_host/world/robots.hpp); the names are estimator_node's --model names.
using RobotKind = est::sim::RobotKind;
inline constexpr RobotKind kRobots[] = {RobotKind::bicycle,  RobotKind::diff_drive, RobotKind::velocity,
                                        RobotKind::odometry, RobotKind::omni,       RobotKind::holonomic};
// global: uniform over the free space; tracking: a Gaussian around the true start; wrong: the same Gaussian around a
// pose the robot is not at (wrong_start_pose()), a confident wrong belief the filter must notice and leave (MCL).
enum class StartKind { global, tracking, wrong };
const char* to_string(StartKind k);                   // "global", "tracking", "wrong"
bool parse(const std::string& s, StartKind& out);  // the same names; false (out untouched) for any other

// Injected faults by stream and class, e.g. {"scan.stale", 2}. Keys: <stream>.<class> with stream in wheel_ticks,
// steering, twist, odometry, scan, landmarks; fault_catalogue() lists every key with what it does and how the HAL or
// the loop must count it.
using FaultCounts = std::map<std::string, int>;

struct FaultClassInfo {
  std::string key;
  std::string what;      // what is done to the sample
  std::string expected;  // the counter that must move by one per injection ("-" when none must)
};
const std::vector<FaultClassInfo>& fault_catalogue();
// The plan of the default 60 s scenario, ~1 fault per second in each of the robot's streams: 58 for the bicycle (41
// without a steering sensor), and 13 more in the landmark sightings when the world has landmarks. (No
// landmarks.time_backwards: at the sensor's rates a stamp before the previous sighting's is already older than the
// HAL's staleness limit.)
FaultCounts default_fault_counts(RobotKind robot, bool landmarks = true, bool steering_sensor = true);

// The streams a robot has: encoders (bicycle, diff drive, omni base), steering (the bicycle, when fitted), twist
// (the velocity and holonomic robots' commands), odometry (the odometry base's integrated pose).
bool has_wheel_ticks(RobotKind r);
bool has_twist(RobotKind r);
bool has_odometry(RobotKind r);
// Whether fault class `key` (<stream>.<class>) can be injected into this robot's streams.
bool fault_applies(RobotKind r, const std::string& key, bool steering_sensor = true, bool landmarks = true);

struct ScenarioConfig {
  // World.
  std::string map_yaml;                 // empty: the synthetic office (sim_host/maps/office_map.hpp)
  std::vector<est::sim::Waypoint> route;  // empty: the world's own route (required with map_yaml)
  // Landmarks with signatures, "x,y,signature" per line (hal/maps/landmark_file.hpp), in place of the world's own;
  // empty: the world's (the office's 16 posts; none in a ROS map).
  std::string landmarks_csv;
  // Robot.
  RobotKind robot = RobotKind::bicycle;
  double speed_mps = 0.8;
  double duration_s = 60.0;
  std::size_t start_segment = 0;        // the run starts at the beginning of this route segment
  // A control script in place of the route (world/control_script.hpp): timed commands in the model's own terms,
  // each held until the next. Empty: the robot follows the route.
  std::vector<est::sim::TimedCommand> controls;
  // The start pose (m, m, rad); unset: the beginning of route segment start_segment (required with a script in a
  // map_server map, which then has no route).
  std::optional<est::Pose2> start_pose;
  // The omni base's true noise a1..a9 per 10 ms step (est::OmniParams::alpha); empty: the simulator's
  // (robot_models() in sim/sensor_stream.hpp).
  std::vector<float> omni_noise;
  std::uint64_t seed = 1;
  // Sensors (rates in Hz; they must divide the 100 Hz simulation step).
  int encoder_hz = 100;
  int steering_hz = 50;
  int twist_hz = 50;
  int odometry_hz = 50;
  int scan_hz = 10;
  int beams = 360;
  double fov_deg = 360.0;
  double range_max_m = 12.0;
  est::sim::RangeNoise range_noise{0.02f, 0.01f, 0.01f};
  double encoder_scale_error = 0.01;    // the odometry counts 1 % more than the wheel turns (radius error)
  double encoder_noise = 0.02;          // relative noise of each step's counted travel
  int slip_events = 2;                  // wheel-spin episodes: the encoder counts slip_factor more
  double slip_duration_s = 0.5;
  double slip_factor = 0.3;
  double steering_sigma_deg = 0.5;
  double steering_bias_deg = 0.5;
  bool steering_sensor = true;          // false: the bicycle has no steering sensor (no steering stream)
  // The rangefinder on the bicycle's handlebar: its pose follows the true steering angle (the steering axis at the
  // front wheel, the sensor 0.15 m ahead of it on the bar); otherwise fixed at the robot's reference point.
  bool handlebar = false;
  est::SteeredMount handlebar_mount{0.0f, 0.0f, {0.15f, 0.0f, 0.0f}};
  est::Pose2 rangefinder_mount{};       // otherwise: its pose in the robot frame (m, m, rad)
  std::int32_t handle_detents = 0;      // the handlebar's positions from stop to stop (0: continuous)
  // Landmark sensor (the world's landmark map; none in a ROS map): sightings at landmark_hz, each feature with its
  // map index (landmark_ids_known) or -1 (the filter associates by maximum likelihood, with the signature).
  int landmark_hz = 5;
  est::sim::LandmarkSensorSpec landmark_sensor{};
  bool landmark_ids_known = true;
  // Faults.
  FaultCounts faults;                   // empty: none
  double kidnap_at_s = 30.0;            // < 0: no kidnapping
  double burst_at_s = 45.0;             // a bus outage: every stream silent for burst_ms; < 0: none
  double burst_ms = 400.0;
};

// The world of a run: grid, distance transform, landmarks and route, owned here.
struct SimWorld {
  std::string name;
  std::shared_ptr<void> storage;  // the grid and transform of a loaded map (the office's are static)
  std::shared_ptr<void> landmark_storage;  // the landmarks of a landmark file
  est::OccupancyGrid grid;
  est::DistanceTransform edt;
  est::LandmarkMap landmarks;     // the office's 16 posts; empty in a ROS map
  // The office's (with a control script too: its start pose) or the file's; null: a control script in a map_server
  // map.
  std::unique_ptr<est::sim::Route> route;
};
// Whether the world of a run has landmarks: the office's, or a landmark file's.
bool has_landmarks(const ScenarioConfig& config);
// The office (shared, built once) or the ROS map of the config, and the landmark file's landmarks; throws on a bad
// map, landmark file or route.
SimWorld load_world(const ScenarioConfig& config);

using node::parse;      // RobotKind by estimator_node's --model names
using node::to_string;

}  // namespace sim

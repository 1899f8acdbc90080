#pragma once
// The channels of an imported log. A single-robot dataset uses the estimator's own channels (hal/lcm/channels.hpp:
// EST_TWIST, EST_ODOMETRY, EST_WHEEL_TICKS, EST_STEERING, EST_RANGE_SCAN, EST_LANDMARKS), so estimator_node --replay
// reads it with its defaults; the reference goes on its own channel, never one the estimator reads. A team dataset
// (MRCLAM) has one set per robot, suffixed with the robot's id: EST_TWIST_3, EST_LANDMARKS_3, ...
#include <string>

namespace sim::data {

inline const char* const kGroundTruthChannel = "EST_GROUND_TRUTH";  // ground_truth_t: Vicon, a tracked pose
inline const char* const kReferenceChannel = "EST_REFERENCE";       // ground_truth_t: SLAM-corrected poses
inline const char* const kGpsChannel = "EST_GPS";                   // ground_truth_t: a GPS fix (theta NaN)
inline const char* const kRobotSightingsChannel = "EST_ROBOT_SIGHTINGS";  // landmark_sighting_t, id = robot id

inline std::string robot_channel(const std::string& base, int robot_id) {
  return base + "_" + std::to_string(robot_id);
}

}  // namespace sim::data

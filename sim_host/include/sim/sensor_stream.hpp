#pragma once
// The sensor stream of a scenario, as a robot's buses would deliver it: raw HAL samples (encoder counters that
// wrap, steering angles, range scans, landmark sightings), each stamped by the robot's clock and delivered at an arrival time, with the
// scenario's faults injected, plus the ground truth at every 10 ms simulation step. Generated up front and
// deterministically from the seed; consumed by `simulate` (through the HAL into the filter loop) and by `record`
// (into an LCM log).
//
// Timing: the simulation steps at 10 ms from t0 = 1 s. A sample's stamp is the step's time; it arrives after its
// nominal latency (encoders and steering 1 ms, scans 12 ms, landmark sightings 15 ms: within the loop's 20 ms
// reorder window).
//
// Random draws: each source has its own generator stream of the seed (truth 1, scans 2, odometry 3, faults 4,
// landmark sightings 5, landmark faults 6), so adding or changing one stream never moves another's draws.
//
// Per robot (sim_host/world/robots.hpp): the bicycle sends its front (traction) and rear wheel counters and its
// steering angle; the diff drive its two wheel counters; the omni base its four mecanum wheel counters; the
// velocity and holonomic robots their commanded twist; the odometry base the pose it integrates from its (erring)
// wheel counts. Every robot's rangefinder and landmark sensor are the same.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "est/geometry/pose2.hpp"
#include "hal/samples.hpp"
#include "hal/time.hpp"
#include "hal/validated_inputs.hpp"
#include "node/estimator_spec.hpp"
#include "sim/scenario.hpp"
#include "world/robots.hpp"

namespace sim {

inline constexpr hal::TimeNs kSimStepNs = 10 * hal::kNsPerMs;
inline constexpr hal::TimeNs kSimStartNs = hal::kNsPerS;
inline constexpr unsigned kEncoderCounterBits = 32;  // as est_lcm::encoder_ticks_t and the LCM backend's default

enum class StreamKind : std::uint8_t { wheel_ticks, steering, twist, odometry, scan, landmarks };
const char* to_string(StreamKind k);

struct StreamEvent {
  hal::TimeNs arrival_ns = 0;
  StreamKind kind = StreamKind::wheel_ticks;
  hal::WheelTicks ticks;
  hal::SteeringSample steering;
  hal::TwistSample twist;
  hal::OdometrySample odometry;
  std::size_t scan = 0;  // index into SensorStream::scans
  std::size_t sighting = 0;  // index into SensorStream::sightings
  int fault = -1;        // index into SensorStream::faults when this delivery carries an injected fault
};

struct ScanRecord {
  hal::TimeNs stamp_ns = 0;
  hal::ScanGeometry geometry;
  std::vector<float> ranges;
  hal::RangeScanView view() const { return {stamp_ns, geometry, ranges.data(), ranges.size()}; }
};

// A landmark sighting as the sensor sends it (never empty: a sensor that sees nothing sends nothing).
struct SightingRecord {
  hal::TimeNs stamp_ns = 0;
  std::vector<hal::LandmarkFeature> features;
  hal::LandmarkSightingView view() const { return {stamp_ns, features.data(), features.size()}; }
};

struct TruthSample {
  hal::TimeNs t_ns = 0;
  est::Pose2 pose;      // the robot's reference point (front wheel of the bicycle, axle midpoint of the diff drive)
  float v_mps = 0.0f;   // of the reference point, over the step that starts here
  float omega_rps = 0.0f;
};

// One injected fault (or event): where, what, and which counter must show it.
struct InjectedFault {
  hal::TimeNs t_ns = 0;   // stamp of the affected sample (start of a burst or slip)
  std::string key;        // <stream>.<class>, or "event.kidnap", "event.burst", "event.slip"
  std::string expected;   // e.g. "hal.scan.stale", "loop.too_old", "-"
  int amount = 1;         // what that counter must move by (beams for scan.nan_beams)
  std::string also;       // a second counter that must move (a NaN scan's beams), empty when none
  int also_amount = 0;
};

// The kidnapping carries the robot at least this far when the route allows (six times the localized bound).
inline constexpr double kKidnapMinDistanceM = 3.0;

struct SensorStream {
  std::vector<StreamEvent> events;  // in arrival order (ties: generation order)
  std::vector<ScanRecord> scans;
  std::vector<SightingRecord> sightings;
  std::vector<TruthSample> truth;   // every 10 ms step, t = kSimStartNs + k * kSimStepNs
  std::vector<InjectedFault> faults;
  hal::InputLimits limits;          // what the HAL gate of this robot is configured with
  hal::TimeNs kidnap_ns = -1;       // -1: none
  double kidnap_distance_m = 0.0;   // how far the kidnapping carried the robot (>= kKidnapMinDistanceM when it can)
  hal::TimeNs end_ns = 0;
  est::Pose2 mount;                 // rangefinder in the robot frame (on the handlebar: at steering 0)
  double metres_per_tick = 0.0;     // encoder resolution (the bicycle's traction wheel / each wheel of the others)
  std::size_t route_waypoints = 0;
  std::size_t landmark_count = 0;   // landmarks in the world's map (0: no landmark sensor)

  const TruthSample& truth_at(hal::TimeNs t) const;  // the step at or before t (clamped to the run)
  // Expected counts by counter name (sums of InjectedFault::amount; "-" left out).
  std::map<std::string, int> expected_counts() const;
};

// Robot parameters of the scenarios: the truth's noise, and what the filter is told (larger), for every model.
struct RobotModels {
  est::sim::RobotTruth truth;
  node::MotionSpec filter;
};
RobotModels robot_models();
// The encoder resolution of each robot that has encoders (m per tick).
double metres_per_tick(RobotKind r);

// Throws std::invalid_argument on a bad configuration (rates, unknown fault keys, faults that do not fit the run).
// The expectations assume a loop that consumes scans and landmark sightings; see expect_loop_inputs.
SensorStream generate_stream(const ScenarioConfig& config, const SimWorld& world);

// A filter loop drops the inputs its estimator does not use when they are pushed (counted as unused, before any
// ordering check): a late scan under the EKF, or a late sighting under MCL, then moves no counter.
void expect_loop_inputs(SensorStream& stream, bool uses_scans, bool uses_landmarks);

}  // namespace sim
